//! Issue 4's acceptance: `scripts/reproduce_paper.sh` regenerates `results/afsharfard2013/` and
//! the committed files match what it writes, byte for byte (the pipeline writes no timestamps).
//! Issue 10's: `scripts/design_space.sh` regenerates `results/design-space/` (the three-axis
//! showcase) the same way. The scripts run here with this test build's binary into a temporary
//! directory.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

fn files(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect()
}

/// Runs `script` with `DEST` in a temporary directory and compares what it writes with the
/// committed `results/<name>/`, file by file and byte for byte.
fn regenerates(script: &str, name: &str) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let committed = root.join("results").join(name);
    let tmp = tempfile::tempdir().unwrap();
    let dest = tmp.path().join(name);
    let out = Command::new("bash")
        .arg(root.join("scripts").join(script))
        .arg(tmp.path().join("work"))
        .env("DEST", &dest)
        .env(
            "IMPACTSWEEP_BIN",
            assert_cmd::cargo::cargo_bin("impactsweep"),
        )
        .current_dir(root)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{script} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(files(&committed), files(&dest), "the set of files differs");
    let mut differ = vec![];
    for file in files(&committed) {
        let a = std::fs::read(committed.join(&file)).unwrap();
        let b = std::fs::read(dest.join(&file)).unwrap();
        if a != b {
            differ.push(file);
        }
    }
    assert!(
        differ.is_empty(),
        "regenerated files differ from the committed ones: {differ:?} \
         (re-run scripts/{script} and commit, if the change is intended)"
    );
}

#[test]
fn reproduce_paper_regenerates_the_committed_results() {
    regenerates("reproduce_paper.sh", "afsharfard2013");
}

/// Issue 10: the three-axis showcase.
#[test]
fn design_space_regenerates_the_committed_showcase() {
    regenerates("design_space.sh", "design-space");
}

/// Issue 12: `scripts/frequency_response.sh` regenerates `results/frequency-response/` (a
/// harmonic study over r, m and d) the same way.
#[test]
fn frequency_response_regenerates_the_committed_showcase() {
    regenerates("frequency_response.sh", "frequency-response");
}
