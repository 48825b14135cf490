//! Issue 67 item 8, record suites: `[scene] records = [...]` or a folder. Realization `c` of a
//! design is record `c`, run at its own sample interval and length, scaled to the stripe and
//! searched for its capacity: the same bits as a one-record study of that file. The records are
//! copied into the run directory (`records/`), so the run directory reduces where the suite is
//! gone; the capacities table names each record; the rows are the same bits on 1 or 2 threads,
//! another chunk size and after a resume. (The bad suites' messages: `random_study_errors.rs`.)

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::sim::random::RealizationRecord;
use impactsweep::store::{self, RunRow};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// Three records of the bundled suite at three sample intervals: 0.01, 0.02 and 0.005 s.
const RECORDS: [&str; 3] = ["syn-01.csv", "syn-03.csv", "syn-04.csv"];

const STUDY: &str = "[study]\nname = \"NAME\"\nseed = 8\n[system]\nM = 1.0\nK = 246.7\n\
C = 0.628\ne = 0.6\nd = 0.02\n[scene]\nkind = \"record\"\nLOAD\nyield_coefficient = 0.25\n\
intensity = \"sa\"\ndesign_intensity = 0.2\n[sweep]\nm = [0.0, 0.1]\nim = [0.2, 0.3]\n\
[hazard]\nk0 = 3.72e-4\nk = 2.5\n";

/// A study `name` in `dir` with `load` (its `record` or `records` line).
fn study(dir: &Path, name: &str, load: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, STUDY.replace("NAME", name).replace("LOAD", load)).unwrap();
    path
}

/// The suite's files copied into `dir/suite`.
fn suite(dir: &Path) {
    std::fs::create_dir_all(dir.join("suite")).unwrap();
    for r in RECORDS {
        std::fs::copy(
            Path::new("configs/records/suite").join(r),
            dir.join("suite").join(r),
        )
        .unwrap();
    }
}

fn rows(dir: &Path) -> Vec<RunRow<RealizationRecord>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<RealizationRecord>(p).unwrap())
        .collect()
}

/// A row's record as bits (NaN-safe).
fn bits(r: &RealizationRecord) -> String {
    format!("{r:?}")
}

#[test]
fn issue_67_each_record_of_a_suite_runs_as_its_own_record_study() {
    let tmp = tempfile::tempdir().unwrap();
    suite(tmp.path());
    let listed = format!(
        "records = [{}]",
        RECORDS
            .iter()
            .map(|r| format!("\"suite/{r}\""))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let by_list = common::run_study_file(
        &study(tmp.path(), "list", &listed),
        &tmp.path().join("out"),
        "list",
    );
    let by_folder = common::run_study_file(
        &study(tmp.path(), "folder", "records = \"suite\""),
        &tmp.path().join("out"),
        "folder",
    );
    let suite_rows = rows(&by_list);
    // 2 designs x 2 stripes x 3 records.
    assert_eq!(suite_rows.len(), 12);
    assert_eq!(
        suite_rows
            .iter()
            .map(|r| bits(&r.record))
            .collect::<Vec<_>>(),
        rows(&by_folder)
            .iter()
            .map(|r| bits(&r.record))
            .collect::<Vec<_>>(),
        "a folder is its files by name"
    );
    for (c, r) in RECORDS.iter().enumerate() {
        let name = format!("one{c}");
        let one = common::run_study_file(
            &study(tmp.path(), &name, &format!("record = \"suite/{r}\"")),
            &tmp.path().join("out"),
            &name,
        );
        let one_rows = rows(&one);
        assert_eq!(one_rows.len(), 4);
        for o in &one_rows {
            let s = suite_rows
                .iter()
                .find(|s| s.point == o.point && s.case == c as u32)
                .unwrap();
            assert_eq!(
                bits(&s.record),
                bits(&o.record),
                "record {r}, point {}",
                o.point
            );
        }
        // Each record's own length: its samples at its own dt.
        let samples = std::fs::read_to_string(tmp.path().join("suite").join(r))
            .unwrap()
            .lines()
            .filter(|l| l.starts_with(|ch: char| ch.is_ascii_digit()))
            .count() as u64;
        assert!(one_rows.iter().all(|o| o.record.record.samples <= samples));
    }
    assert!(suite_rows.iter().any(|r| r.record.capacity.is_some()));
    // The run directory holds the records: it reduces with the suite gone.
    std::fs::remove_dir_all(tmp.path().join("suite")).unwrap();
    for r in RECORDS {
        assert!(by_list.join("records").join(r).exists());
    }
    bin().arg("reduce").arg(&by_list).assert().success();
    bin().arg("reduce").arg(&by_folder).assert().success();
    let caps = std::fs::read_to_string(by_folder.join("capacities.csv")).unwrap();
    let mut lines = caps.lines();
    let header = common::csv_cells(lines.next().unwrap());
    let at = header
        .iter()
        .position(|h| h == "record")
        .expect("a record column");
    let case = header.iter().position(|h| h == "case").unwrap();
    let mut n = 0;
    for l in lines {
        let cells = common::csv_cells(l);
        let c: usize = cells[case].parse().unwrap();
        assert_eq!(cells[at], RECORDS[c]);
        n += 1;
    }
    assert_eq!(n, 6, "2 designs x 3 records at the design stripe");
    let report = std::fs::read_to_string(by_folder.join("report.md")).unwrap();
    assert!(report.contains(
        "a suite of 3 records of ground acceleration (syn-01.csv, syn-03.csv, syn-04.csv)"
    ));
}

#[test]
fn issue_67_a_suite_is_the_same_bits_on_any_thread_count_chunk_and_resume() {
    let tmp = tempfile::tempdir().unwrap();
    suite(tmp.path());
    let path = study(tmp.path(), "det", "records = \"suite\"");
    let run = |out: &str, threads: &str, extra: &[&str]| -> PathBuf {
        let out = tmp.path().join(out);
        bin()
            .arg("run")
            .arg(&path)
            .args([
                "--out",
                out.to_str().unwrap(),
                "--quiet",
                "--threads",
                threads,
            ])
            .args(extra)
            .assert()
            .success();
        out.join("det")
    };
    let one = run("one", "1", &["--chunk-points", "1"]);
    let two = run("two", "2", &["--chunk-points", "1"]);
    assert!(common::dataset(&one) == common::dataset(&two));
    let whole = run("whole", "2", &[]);
    assert_eq!(rows(&whole), rows(&one));
    let s = Study::load(&path).unwrap();
    let resumed = tmp.path().join("resumed");
    let first = sweep::run_study(
        &s,
        &resumed,
        &SweepOptions {
            threads: Some(1),
            chunk_points: Some(1),
            stop_after: Some(1),
            ..SweepOptions::default()
        },
    )
    .unwrap();
    assert_eq!(first.chunks_written, 1);
    bin()
        .arg("run")
        .arg(&path)
        .args(["--out", resumed.to_str().unwrap(), "--quiet", "--resume"])
        .assert()
        .success();
    assert_eq!(rows(&resumed.join("det")), rows(&one));
}
