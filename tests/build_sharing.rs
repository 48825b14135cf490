//! The Python extension's test build reuses the main crate's (scripts/test.sh; BENCHMARKS.md,
//! "CI time") only while Cargo resolves every dependency the two share to the same features.
//! `cargo test` unifies the main crate's dev-dependencies into them, so `python/Cargo.toml`
//! mirrors those dev-dependencies, optional, behind its feature `share-test-build`. A
//! dev-dependency added or changed here and not there would not fail any build: the extension
//! would silently compile the world again (minutes of CI). This test says so instead.

use std::path::Path;

fn manifest(path: &Path) -> toml::Table {
    let text = std::fs::read_to_string(path).unwrap();
    text.parse::<toml::Table>().unwrap()
}

/// A dependency's version, default features and features, whatever form it is written in.
fn spec(v: &toml::Value) -> (String, bool, Vec<String>) {
    match v {
        toml::Value::String(s) => (s.clone(), true, vec![]),
        toml::Value::Table(t) => {
            let version = t["version"].as_str().unwrap().to_string();
            let default = t
                .get("default-features")
                .and_then(|d| d.as_bool())
                .unwrap_or(true);
            let mut features: Vec<String> = t
                .get("features")
                .and_then(|f| f.as_array())
                .map(|a| a.iter().map(|f| f.as_str().unwrap().to_string()).collect())
                .unwrap_or_default();
            features.sort();
            (version, default, features)
        }
        _ => panic!("a dependency is a string or a table: {v}"),
    }
}

#[test]
fn the_extension_mirrors_every_dev_dependency_of_the_main_crate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let main = manifest(&root.join("Cargo.toml"));
    let py = manifest(&root.join("python/Cargo.toml"));
    let dev = main["dev-dependencies"].as_table().unwrap();
    let deps = py["dependencies"].as_table().unwrap();
    let share: Vec<&str> = py["features"]["share-test-build"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(!dev.is_empty());
    for (name, want) in dev {
        let got = deps.get(name).unwrap_or_else(|| {
            panic!("python/Cargo.toml does not mirror the dev-dependency {name}")
        });
        assert_eq!(
            spec(got),
            spec(want),
            "python/Cargo.toml mirrors {name} with another version or other features"
        );
        assert_eq!(got.get("optional").and_then(|o| o.as_bool()), Some(true));
        assert!(
            share.contains(&format!("dep:{name}").as_str()),
            "share-test-build does not turn on {name}"
        );
    }
    assert_eq!(
        share.len(),
        dev.len(),
        "share-test-build turns on more than the mirror"
    );
}

/// The main crate names `syn` with the features pyo3's macros ask of it (a build-dependency it
/// never builds), and `arrow-array` with `ffi`, the feature the extension's pyarrow bridge
/// (`arrow-pyarrow`) asks of it; an arrow crate the extension names itself has the main crate's
/// features: the two other conditions of the shared build.
#[test]
fn syn_and_arrow_resolve_alike_in_both_builds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let main = manifest(&root.join("Cargo.toml"));
    let py = manifest(&root.join("python/Cargo.toml"));
    let syn = spec(&main["build-dependencies"]["syn"]);
    for f in ["extra-traits", "visit-mut"] {
        assert!(syn.2.contains(&f.to_string()), "syn without {f}");
    }
    let array = spec(&main["dependencies"]["arrow-array"]);
    assert!(
        array.2.contains(&"ffi".to_string()),
        "arrow-array without ffi"
    );
    assert!(py["dependencies"].get("arrow-pyarrow").is_some());
    for (name, got) in py["dependencies"].as_table().unwrap() {
        if name.starts_with("arrow") && name != "arrow-pyarrow" {
            let want = main["dependencies"]
                .get(name)
                .unwrap_or_else(|| panic!("the extension names {name}, the main crate does not"));
            assert_eq!(
                spec(got),
                spec(want),
                "{name} differs between the two builds"
            );
        }
    }
}
