//! Issue 10: reports waiting in the morning. `queue --reduce` (and `run --reduce`) reduce each
//! study as soon as its sweep ends, a failed reduce is reported without stopping the queue,
//! `status` on the output root lists every study with its state and report, and a study run with
//! `--allow-large` can be reduced.

use std::path::Path;

use assert_cmd::Command;
use predicates::prelude::*;

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// configs/quick.toml under another name (6 points x 4 cases).
fn quick(dir: &Path, name: &str) {
    let text = std::fs::read_to_string("configs/quick.toml")
        .unwrap()
        .replace("name = \"quick\"", &format!("name = \"{name}\""));
    assert!(text.contains(&format!("name = \"{name}\"")));
    std::fs::write(dir.join(format!("{name}.toml")), text).unwrap();
}

#[test]
fn issue_10_queue_reduce_leaves_reports_and_goes_on_after_a_failed_reduce() {
    let tmp = tempfile::tempdir().unwrap();
    let studies = tmp.path().join("studies");
    std::fs::create_dir(&studies).unwrap();
    quick(&studies, "a");
    quick(&studies, "b");
    let out = tmp.path().join("out");
    // Study a's reduce will fail: a directory sits where its summary goes.
    std::fs::create_dir_all(out.join("a/summary.parquet")).unwrap();
    bin()
        .arg("queue")
        .arg(&studies)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--reduce"])
        .assert()
        .code(1)
        .stderr(
            predicate::str::contains("error: a: reduce failed")
                .and(predicate::str::contains("b: reduced 6 design points"))
                .and(predicate::str::contains("reduce failed for 1 study: a")),
        );
    assert!(out.join("b/report.md").exists());
    assert!(!out.join("a/report.md").exists());
    // status on the output root: both sweeps complete, one report.
    bin().arg("status").arg(&out).assert().success().stdout(
        predicate::str::contains("2 studies")
            .and(predicate::str::contains(
                "a: complete, 24 runs; report: not reduced",
            ))
            .and(predicate::str::contains("b: complete, 24 runs; report: "))
            .and(predicate::str::contains("b/report.md")),
    );
    // Once the cause is gone, the queue skips the finished sweeps and reduces the one left.
    std::fs::remove_dir(out.join("a/summary.parquet")).unwrap();
    bin()
        .arg("queue")
        .arg(&studies)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--reduce"])
        .assert()
        .success()
        .stderr(predicate::str::contains("a: reduced 6 design points"));
    assert!(out.join("a/report.md").exists());
}

#[test]
fn issue_10_a_study_run_with_allow_large_is_reduced() {
    let tmp = tempfile::tempdir().unwrap();
    // 2,500,001 values of e x 4 cases: over the size guard of 10^7 runs. One shard of 2,501
    // runs one chunk of 1,000 points.
    let text = std::fs::read_to_string("configs/quick.toml")
        .unwrap()
        .replace("name = \"quick\"", "name = \"large\"")
        .replace(
            "e = { start = 0.5, stop = 0.9, num = 6 }",
            "e = { start = 0.5, stop = 0.9, num = 2500001 }",
        )
        .replace("chunk_points = 2", "chunk_points = 1000");
    assert!(text.contains("num = 2500001") && text.contains("chunk_points = 1000"));
    let study = tmp.path().join("large.toml");
    std::fs::write(&study, text).unwrap();
    let out = tmp.path().join("out");
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--allow-large", "--shard", "0/2501", "--reduce"])
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "large: not reduced: 2500 of 2501 chunks missing",
        ));
    bin()
        .arg("reduce")
        .arg(out.join("large"))
        .assert()
        .success()
        .stdout(predicate::str::contains("reduced 1000 design points"));
    let md = std::fs::read_to_string(out.join("large/report.md")).unwrap();
    assert!(
        md.contains("1,000 of 2,500,001 design points reduced"),
        "{md}"
    );
}
