//! Issue 4's acceptance: `scripts/reproduce_paper.sh` regenerates `results/afsharfard2013/` and
//! the committed files match what it writes, byte for byte (the pipeline writes no timestamps).
//! The script runs here with this test build's binary into a temporary directory.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

fn files(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect()
}

#[test]
fn reproduce_paper_regenerates_the_committed_results() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let committed = root.join("results/afsharfard2013");
    let tmp = tempfile::tempdir().unwrap();
    let dest = tmp.path().join("afsharfard2013");
    let out = Command::new("bash")
        .arg(root.join("scripts/reproduce_paper.sh"))
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
        "reproduce_paper.sh failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(files(&committed), files(&dest), "the set of files differs");
    let mut differ = vec![];
    for name in files(&committed) {
        let a = std::fs::read(committed.join(&name)).unwrap();
        let b = std::fs::read(dest.join(&name)).unwrap();
        if a != b {
            differ.push(name);
        }
    }
    assert!(
        differ.is_empty(),
        "regenerated files differ from the committed ones: {differ:?} \
         (re-run scripts/reproduce_paper.sh and commit, if the change is intended)"
    );
}
