//! Issue 25: the layering the code promises. The Python binding (`python/src`) imports nothing
//! from the command line's layer (`impactsweep::app`), and within `src/app/` and `src/study/` no
//! module imports one that imports it back (directly or through others): each folder's modules
//! form a graph without cycles. A module's imports are read from its source: `super::NAME`,
//! `crate::app::NAME` or `crate::study::NAME` naming a sibling file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The sibling modules each `.rs` file of `dir` (other than `mod.rs`) refers to.
fn graph(dir: &Path, folder: &str) -> BTreeMap<String, BTreeSet<String>> {
    let names: BTreeSet<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            let stem = p.file_stem()?.to_str()?.to_string();
            (p.extension()? == "rs" && stem != "mod").then_some(stem)
        })
        .collect();
    let mut g = BTreeMap::new();
    for n in &names {
        let text = std::fs::read_to_string(dir.join(format!("{n}.rs"))).unwrap();
        // Only the code before the unit tests: a test may use anything.
        let code = text.split("#[cfg(test)]").next().unwrap_or("");
        let mut uses = BTreeSet::new();
        for other in names.iter().filter(|o| *o != n) {
            let refs = [
                format!("super::{other}::"),
                format!("super::{other}}}"),
                format!("super::{other};"),
                format!("super::{{{other}"),
                format!("crate::{folder}::{other}::"),
                format!("crate::{folder}::{other};"),
            ];
            if refs.iter().any(|r| code.contains(r.as_str())) {
                uses.insert(other.clone());
            }
        }
        g.insert(n.clone(), uses);
    }
    g
}

/// A cycle of `g`, if there is one.
fn cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == n) {
            let mut c = path[i..].to_vec();
            c.push(n.to_string());
            return Some(c);
        }
        if done.contains(n) {
            return None;
        }
        path.push(n.to_string());
        for m in &g[n] {
            if let Some(c) = visit(m, g, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(n.to_string());
        None
    }
    let mut done = BTreeSet::new();
    g.keys()
        .find_map(|n| visit(n, g, &mut Vec::new(), &mut done))
}

#[test]
fn issue_25_the_python_binding_imports_nothing_from_the_command_line() {
    for e in std::fs::read_dir(root().join("python/src")).unwrap() {
        let p = e.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(
            !text.contains("impactsweep::app"),
            "{} imports the command line's layer (impactsweep::app); use impactsweep::api",
            p.display()
        );
    }
}

#[test]
fn issue_25_no_import_circles_in_app_and_study() {
    for folder in ["app", "study"] {
        let g = graph(&root().join("src").join(folder), folder);
        assert!(g.len() >= 5, "{folder}: {g:?}");
        if let Some(c) = cycle(&g) {
            panic!("src/{folder}: an import circle: {}", c.join(" -> "));
        }
    }
}
