//! `run`, `queue` and `status` through the real binary on real study files (issue 3): a complete
//! dataset, `kill -9` then `--resume` gives the same dataset, locks, refusal to overwrite,
//! several studies, shards, the queue, the audit.

use std::path::{Path, PathBuf};
use std::process::{Command as StdCommand, Stdio};
use std::time::{Duration, Instant};

use crate::common;

use assert_cmd::Command;
use common::{study_text, write_study};
use impactsweep::store;
use predicates::prelude::*;

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// Part files by name with their bytes.
fn parts(dir: &Path) -> Vec<(String, Vec<u8>)> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().to_string(),
                std::fs::read(p).unwrap(),
            )
        })
        .collect()
}

#[test]
fn run_writes_a_complete_dataset_with_a_summary_line() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "small", 5, 2);
    let out = tmp.path().join("out");
    let run = bin()
        .args(["run", s.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .assert()
        .success()
        .stderr(
            predicate::str::contains("small: 60 runs (ok ")
                .and(predicate::str::contains("runs/s"))
                .and(predicate::str::contains("8 chunks written")),
        )
        .get_output()
        .clone();
    // stderr is not a terminal here: no progress bar, just the summary line.
    assert_eq!(String::from_utf8_lossy(&run.stderr).lines().count(), 1);
    let dir = out.join("small");
    assert_eq!(
        std::fs::read_to_string(dir.join("study.toml")).unwrap(),
        study_text("small", 5, 2)
    );
    assert_eq!(store::part_files(&dir).unwrap().len(), 8);
    let m = store::read_manifest(&dir).unwrap().unwrap();
    assert_eq!((m.n_runs, m.runs_done, m.chunks_done), (60, 60, 8));
    assert!(!dir.join(".lock").exists(), "the lock is released");
    bin()
        .args(["status", dir.to_str().unwrap()])
        .assert()
        .success()
        .stdout(
            predicate::str::contains("chunks 8/8 done, runs 60/60 done")
                .and(predicate::str::contains("complete")),
        );
}

#[test]
fn quiet_prints_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "q", 3, 100);
    bin()
        .args(["run", s.to_str().unwrap(), "--quiet", "--out"])
        .arg(tmp.path().join("out"))
        .assert()
        .success()
        .stdout("")
        .stderr("");
}

#[test]
fn the_bundled_quick_study_runs() {
    let quick = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/quick.toml");
    let tmp = tempfile::tempdir().unwrap();
    bin()
        .arg("run")
        .arg(&quick)
        .args(["--quiet", "--out"])
        .arg(tmp.path())
        .assert()
        .success();
    let m = store::read_manifest(&tmp.path().join("quick"))
        .unwrap()
        .unwrap();
    assert_eq!(m.runs_done, m.n_runs);
    assert!(m.n_runs > 0);
}

#[test]
fn an_existing_output_is_refused_without_resume_and_left_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "twice", 3, 1);
    let out = tmp.path().join("out");
    bin()
        .args(["run", "--quiet", s.to_str().unwrap(), "--out"])
        .arg(&out)
        .assert()
        .success();
    let dir = out.join("twice");
    let before = parts(&dir);
    let manifest = std::fs::read(dir.join("manifest.json")).unwrap();
    bin()
        .args(["run", s.to_str().unwrap(), "--out"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(
            predicate::str::contains(dir.display().to_string())
                .and(predicate::str::contains("not empty"))
                .and(predicate::str::contains("--resume")),
        );
    assert_eq!(parts(&dir), before);
    assert_eq!(std::fs::read(dir.join("manifest.json")).unwrap(), manifest);
    // A directory with anything in it counts.
    let other = tmp.path().join("other");
    std::fs::create_dir_all(other.join("twice")).unwrap();
    std::fs::write(other.join("twice/notes.txt"), "mine").unwrap();
    bin()
        .args(["run", s.to_str().unwrap(), "--out"])
        .arg(&other)
        .assert()
        .code(2);
    assert_eq!(
        std::fs::read_to_string(other.join("twice/notes.txt")).unwrap(),
        "mine"
    );
}

#[test]
fn a_live_writer_lock_refuses_and_a_dead_one_does_not_block_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "locked", 3, 1);
    let out = tmp.path().join("out");
    let dir = out.join("locked");
    std::fs::create_dir_all(&dir).unwrap();
    // A live process holds the lock.
    let mut holder = StdCommand::new("sleep").arg("60").spawn().unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let lock = dir.join(".lock");
    std::fs::write(&lock, format!("{} {}\n", holder.id(), host.trim())).unwrap();
    bin()
        .args(["run", s.to_str().unwrap(), "--resume", "--out"])
        .arg(&out)
        .assert()
        .code(1)
        .stderr(
            predicate::str::contains(lock.display().to_string())
                .and(predicate::str::contains(format!("PID {}", holder.id()))),
        );
    bin()
        .args(["status", dir.to_str().unwrap()])
        .assert()
        .failure();
    // The holder dies: its lock no longer blocks --resume.
    holder.kill().unwrap();
    holder.wait().unwrap();
    bin()
        .args(["run", s.to_str().unwrap(), "--resume", "--quiet", "--out"])
        .arg(&out)
        .assert()
        .success();
    assert!(!lock.exists());
    assert_eq!(store::part_files(&dir).unwrap().len(), 9);
}

/// 500 values of e x 3 of m = 1500 design points x 4 cases = 6000 runs in 500 chunks on one
/// thread (each part file is synced before its rename): long enough to be stopped in the
/// middle. Starts `run` into `tmp/<out>` and returns the study, the run directory and the
/// child once two part files exist.
fn start_big_run(tmp: &Path, out: &str) -> (PathBuf, PathBuf, std::process::Child) {
    let s = write_study(tmp, "big", 500, 3);
    let out = tmp.join(out);
    let dir = out.join("big");
    let exe = assert_cmd::cargo::cargo_bin("impactsweep");
    let mut child = StdCommand::new(&exe)
        .args([
            "run",
            s.to_str().unwrap(),
            "--quiet",
            "--threads",
            "1",
            "--out",
        ])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while store::part_files(&dir).map(|p| p.len()).unwrap_or(0) < 2 {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it could be stopped"
        );
        assert!(start.elapsed() < Duration::from_secs(120), "no part file");
        std::thread::sleep(Duration::from_millis(5));
    }
    (s, dir, child)
}

/// Runs the study uninterrupted into `tmp/clean` and returns its run directory.
fn clean_run(tmp: &Path, study: &Path) -> PathBuf {
    let clean = tmp.join("clean");
    bin()
        .args(["run", study.to_str().unwrap(), "--quiet", "--out"])
        .arg(&clean)
        .assert()
        .success();
    clean.join("big")
}

/// An interrupt (SIGTERM, as Slurm sends; Ctrl-C sends SIGINT to the same handler) finishes
/// the chunk in hand, releases the lock and exits with status 130 and a resume hint; `--resume`
/// then completes the dataset exactly as an uninterrupted run writes it.
#[test]
fn sigterm_stops_cleanly_and_resume_completes_the_dataset() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, dir, child) = start_big_run(tmp.path(), "stopped");
    // SAFETY: kill(2) on our own child's PID with a valid signal number.
    let rc = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    assert_eq!(rc, 0);
    let done = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted:") && err.contains("--resume"),
        "{err}"
    );
    assert!(!dir.join(".lock").exists(), "the lock is released");
    let parts_now = store::part_files(&dir).unwrap().len();
    assert!(parts_now < 500, "the run finished before the signal");
    bin()
        .args(["run", s.to_str().unwrap(), "--resume", "--quiet", "--out"])
        .arg(dir.parent().unwrap())
        .assert()
        .success();
    assert!(
        parts(&dir) == parts(&clean_run(tmp.path(), &s)),
        "part files differ"
    );
}

/// The acceptance test: `kill -9` during a run, then `--resume`, gives the same dataset as an
/// uninterrupted run, byte for byte.
#[test]
fn kill_9_then_resume_gives_the_uninterrupted_dataset() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, dir, mut child) = start_big_run(tmp.path(), "killed");
    let killed = dir.parent().unwrap().to_path_buf();
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let done = store::part_files(&dir).unwrap().len();
    assert!(
        done < 500,
        "the run finished before the kill ({done} parts); make the study bigger"
    );
    assert!(dir.join(".lock").exists(), "a killed run leaves its lock");

    bin()
        .args(["status", dir.to_str().unwrap()])
        .assert()
        .success()
        .stdout(predicate::str::contains("missing chunks:").and(predicate::str::contains("stale")));
    bin()
        .args(["run", s.to_str().unwrap(), "--resume", "--quiet", "--out"])
        .arg(&killed)
        .assert()
        .success();

    let clean = clean_run(tmp.path(), &s);
    let a = parts(&dir);
    assert_eq!(a.len(), 500);
    assert!(a == parts(&clean), "part files differ");
    let ma = store::read_manifest(&dir).unwrap().unwrap();
    let mb = store::read_manifest(&clean).unwrap().unwrap();
    assert_eq!(ma.chunks, mb.chunks);
    assert_eq!(ma.outcomes, mb.outcomes);
    assert!(
        std::fs::read_dir(dir.join("points")).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .ends_with(".tmp")),
        "no temp file left"
    );
}

#[test]
fn several_studies_run_one_after_another() {
    let tmp = tempfile::tempdir().unwrap();
    let a = write_study(tmp.path(), "first", 3, 2);
    let b = write_study(tmp.path(), "second", 4, 2);
    let out = tmp.path().join("out");
    bin()
        .args(["run", a.to_str().unwrap(), b.to_str().unwrap(), "--out"])
        .arg(&out)
        .assert()
        .success()
        .stderr(
            predicate::str::contains("first: 36 runs")
                .and(predicate::str::contains("second: 48 runs")),
        );
}

#[test]
fn shards_share_a_directory_and_match_an_unsharded_run() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "sh", 7, 2);
    let out = tmp.path().join("sharded");
    for i in 0..3 {
        bin()
            .args(["run", s.to_str().unwrap(), "--quiet", "--shard"])
            .arg(format!("{i}/3"))
            .arg("--out")
            .arg(&out)
            .assert()
            .success();
        if i == 0 {
            bin()
                .args(["status", out.join("sh").to_str().unwrap()])
                .assert()
                .success()
                .stdout(
                    predicate::str::contains("missing chunks: 1-2, 4-5, 7-8, 10")
                        .and(predicate::str::contains("shard 0/3: chunks 4/4 done")),
                );
        }
    }
    // The same shard twice without --resume is refused.
    bin()
        .args(["run", s.to_str().unwrap(), "--shard", "1/3", "--out"])
        .arg(&out)
        .assert()
        .code(2);
    let whole = tmp.path().join("whole");
    bin()
        .args(["run", s.to_str().unwrap(), "--quiet", "--out"])
        .arg(&whole)
        .assert()
        .success();
    assert!(parts(&out.join("sh")) == parts(&whole.join("sh")));
    let m = store::read_manifest(&out.join("sh")).unwrap().unwrap();
    assert_eq!(m.runs_done, 84);
    assert_eq!(m.shards, vec!["0/3", "1/3", "2/3"]);
}

/// Slurm array tasks: every shard starts at once in the same directory, without --resume.
#[test]
fn concurrent_shards_build_one_dataset_and_one_manifest() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "conc", 30, 1);
    let out = tmp.path().join("out");
    let exe = assert_cmd::cargo::cargo_bin("impactsweep");
    let children: Vec<_> = (0..3)
        .map(|i| {
            StdCommand::new(&exe)
                .args(["run", s.to_str().unwrap(), "--quiet", "--threads", "1"])
                .arg("--shard")
                .arg(format!("{i}/3"))
                .arg("--out")
                .arg(&out)
                .spawn()
                .unwrap()
        })
        .collect();
    for mut c in children {
        assert!(c.wait().unwrap().success());
    }
    let whole = tmp.path().join("whole");
    bin()
        .args(["run", s.to_str().unwrap(), "--quiet", "--out"])
        .arg(&whole)
        .assert()
        .success();
    assert!(parts(&out.join("conc")) == parts(&whole.join("conc")));
    let m = store::read_manifest(&out.join("conc")).unwrap().unwrap();
    let w = store::read_manifest(&whole.join("conc")).unwrap().unwrap();
    assert_eq!(
        m.chunks_done, 90,
        "no shard lost another's manifest entries"
    );
    assert_eq!(m.chunks, w.chunks);
    assert_eq!(m.shards, vec!["0/3", "1/3", "2/3"]);
}

#[test]
fn queue_skips_finished_resumes_partial_and_starts_new_studies() {
    let tmp = tempfile::tempdir().unwrap();
    let q = tmp.path().join("queue");
    std::fs::create_dir(&q).unwrap();
    let a = write_study(&q, "a", 3, 1);
    let b = write_study(&q, "b", 4, 1);
    write_study(&q, "c", 2, 1);
    std::fs::write(q.join("README.txt"), "not a study").unwrap();
    let out = tmp.path().join("out");
    // a finished, b half done (one shard of two).
    bin()
        .args(["run", a.to_str().unwrap(), "--quiet", "--out"])
        .arg(&out)
        .assert()
        .success();
    bin()
        .args([
            "run",
            b.to_str().unwrap(),
            "--quiet",
            "--shard",
            "0/2",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let a_parts = parts(&out.join("a"));
    let a_mtime = std::fs::metadata(store::part_path(&out.join("a"), 0))
        .unwrap()
        .modified()
        .unwrap();

    bin()
        .args(["queue", q.to_str().unwrap(), "--out"])
        .arg(&out)
        .assert()
        .success()
        .stderr(
            predicate::str::contains("a: finished")
                .and(predicate::str::contains("skipped"))
                .and(predicate::str::contains("b: 24 runs"))
                .and(predicate::str::contains("6 chunks written, 6 kept"))
                .and(predicate::str::contains("c: 24 runs")),
        );
    assert_eq!(parts(&out.join("a")), a_parts);
    assert_eq!(
        std::fs::metadata(store::part_path(&out.join("a"), 0))
            .unwrap()
            .modified()
            .unwrap(),
        a_mtime
    );
    for (name, n) in [("a", 36), ("b", 48), ("c", 24)] {
        let m = store::read_manifest(&out.join(name)).unwrap().unwrap();
        assert_eq!(m.runs_done, n, "{name}");
    }
    // Again: everything is finished.
    bin()
        .args(["queue", q.to_str().unwrap(), "--out"])
        .arg(&out)
        .assert()
        .success()
        .stderr(predicate::str::contains("c: finished"));
}

#[test]
fn audit_records_the_realised_error_in_the_manifest() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "aud", 9, 4);
    bin()
        .args(["run", s.to_str().unwrap(), "--audit", "4", "--out"])
        .arg(tmp.path())
        .assert()
        .success()
        .stderr(predicate::str::contains("audit of 4 points"));
    let text = std::fs::read_to_string(tmp.path().join("aud/manifest.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let audit = &json["audit"];
    assert_eq!(audit["points"].as_array().unwrap().len(), 4);
    assert_eq!(audit["solver"], "exact");
    assert!(audit["di"]["max"].as_f64().unwrap() < 1e-6);
    assert_eq!(audit["outcome_changed"], 0);
    bin()
        .args(["status", tmp.path().join("aud").to_str().unwrap()])
        .assert()
        .success()
        .stdout(predicate::str::contains("audit (4 points"));
}

#[test]
fn bad_run_options_are_input_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let s = write_study(tmp.path(), "opts", 3, 1);
    bin()
        .args(["run", s.to_str().unwrap(), "--threads", "0", "--out"])
        .arg(tmp.path())
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--threads 0"));
    bin()
        .args(["run", s.to_str().unwrap(), "--shard", "2/2"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("expected I/N"));
    bin()
        .args(["status", tmp.path().to_str().unwrap()])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "a run directory (no manifest.json)",
        ));
}

#[test]
fn allow_large_lifts_the_size_guard_for_run() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("huge.toml");
    std::fs::write(
        &path,
        "[study]\nname = \"huge\"\n\n[sweep]\ne = { start = 0.0, stop = 1.0, num = 10001 }\n\
         m = { start = 0.01, stop = 0.03, num = 1001 }\n",
    )
    .unwrap();
    bin()
        .args(["run", path.to_str().unwrap(), "--out"])
        .arg(tmp.path())
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--allow-large"));
    // With the flag the study is accepted; an occupied output directory then stops the run
    // before anything is simulated.
    std::fs::create_dir_all(tmp.path().join("huge")).unwrap();
    std::fs::write(tmp.path().join("huge/keep.txt"), "x").unwrap();
    bin()
        .args(["run", path.to_str().unwrap(), "--allow-large", "--out"])
        .arg(tmp.path())
        .assert()
        .code(2)
        .stderr(predicate::str::contains("not empty"));
}

#[test]
fn every_study_is_checked_before_the_first_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let good = write_study(tmp.path(), "good", 3, 1);
    let bad = tmp.path().join("bad.toml");
    std::fs::write(&bad, "[study]\nname = \"bad\"\n[system]\ne = 1.5\n").unwrap();
    bin()
        .args([
            "run",
            good.to_str().unwrap(),
            bad.to_str().unwrap(),
            "--out",
        ])
        .arg(tmp.path().join("out"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains("bad.toml"));
    assert!(!tmp.path().join("out/good").exists(), "nothing ran");
}

/// Issue 5: a sweep on a cheap solver states how far it may be off.
#[test]
fn audit_of_a_cheap_solver_reports_its_error() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("rk.toml");
    let text = study_text("rk", 9, 4) + "\n[solver]\nkind = \"rk4\"\nh = 2e-3\n";
    std::fs::write(&path, text).unwrap();
    bin()
        .args(["run", path.to_str().unwrap(), "--audit", "5", "--out"])
        .arg(tmp.path())
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "audit of 5 points (rk4 h = 2e-3 against exact): max relative error xmax",
        ));
    let m = store::read_manifest(&tmp.path().join("rk"))
        .unwrap()
        .unwrap();
    let a = m.audit.unwrap();
    assert_eq!((a.solver.as_str(), a.points.len()), ("rk4", 5));
    assert_eq!((a.knob.as_str(), a.knob_value), ("h", 2e-3));
    assert!(a.xmax.max > 1e-8 && a.xmax.max < 0.1, "{a:?}");
    let rows = store::read_part(&store::part_path(&tmp.path().join("rk"), 0)).unwrap();
    assert!(rows.iter().all(|r| r.solver == "rk4"));
    let meta = store::part_metadata(&store::part_path(&tmp.path().join("rk"), 0)).unwrap();
    assert!(meta[store::META_STUDY].contains("kind = \"rk4\""));
}
