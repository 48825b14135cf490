//! The sweep engine's records are bit-identical for any thread count, chunk size, shard split and
//! interruption (issue 3). Library level: the studies are built in Rust, so these tests do not
//! depend on the study-file parser.

use std::path::Path;

use crate::common;

use common::{dead_pid, study};
use impactsweep::plan::Plan;
use impactsweep::sim::{NoProbe, SolverKind, SolverSettings, simulate};
use impactsweep::store::{self, RunRow};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};

fn opts() -> SweepOptions {
    SweepOptions::default()
}

/// Every column of every row as bits, in file order.
fn bits(rows: &[RunRow]) -> Vec<Vec<u64>> {
    rows.iter()
        .map(|r| {
            let mut v = vec![
                r.point_id,
                r.point,
                u64::from(r.case),
                u64::from(r.ideal),
                r.dm.to_bits(),
                r.dd.to_bits(),
                r.noise_seed.map_or(u64::MAX, |s| s ^ 0x5a5a),
                u64::from(r.noise_seed.is_some()),
                r.tol.to_bits(),
                r.solver.len() as u64,
                r.record.outcome as u64,
                r.record.impacts,
                r.record.sticks,
                r.record.steps,
            ];
            for k in impactsweep::model::SYSTEM_KEYS {
                v.push(r.system.get(k).unwrap().to_bits());
            }
            let rec = &r.record;
            for x in [
                rec.x1,
                rec.t1,
                rec.x2,
                rec.t2,
                rec.xmax,
                rec.di,
                rec.energy_impact,
                rec.energy_viscous,
                rec.t_stop,
            ] {
                v.push(x.to_bits());
            }
            v
        })
        .collect()
}

/// All rows of a run directory, in chunk order.
fn read_all(dir: &Path) -> Vec<RunRow> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_part(p).unwrap())
        .collect()
}

/// The part files' bytes, by name.
fn part_bytes(dir: &Path) -> Vec<(String, Vec<u8>)> {
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

fn run(s: &Study, out: &Path, o: SweepOptions) -> sweep::SweepSummary {
    sweep::run_study(s, out, &o).unwrap()
}

#[test]
fn every_column_is_bit_identical_across_threads_chunks_and_shards() {
    let s = study("det", 13);
    let tmp = tempfile::tempdir().unwrap();
    let out = |n: &str| tmp.path().join(n);

    let one = run(
        &s,
        &out("t1"),
        SweepOptions {
            threads: Some(1),
            ..opts()
        },
    );
    assert_eq!(one.runs, 13 * 3 * 4);
    assert_eq!(one.chunks_written, 3);
    let reference = read_all(&out("t1").join("det"));
    let want = bits(&reference);
    assert_eq!(want.len(), 156);
    // point_id order, every id once.
    let ids: Vec<u64> = reference.iter().map(|r| r.point_id).collect();
    assert_eq!(ids, (0..156).collect::<Vec<_>>());

    run(
        &s,
        &out("t2"),
        SweepOptions {
            threads: Some(2),
            ..opts()
        },
    );
    assert_eq!(bits(&read_all(&out("t2").join("det"))), want);
    assert_eq!(
        part_bytes(&out("t2").join("det")),
        part_bytes(&out("t1").join("det"))
    );

    for cp in [1, 7] {
        let o = out(&format!("cp{cp}"));
        let sum = run(
            &s,
            &o,
            SweepOptions {
                chunk_points: Some(cp),
                threads: Some(2),
                ..opts()
            },
        );
        assert_eq!(sum.chunks_written, 39u64.div_ceil(cp));
        assert_eq!(bits(&read_all(&o.join("det"))), want, "chunk_points {cp}");
    }

    for n in [2, 3] {
        let o = out(&format!("shards{n}"));
        for i in 0..n {
            let sum = run(
                &s,
                &o,
                SweepOptions {
                    shard: (i, n),
                    chunk_points: Some(4),
                    ..opts()
                },
            );
            assert_eq!(
                sum.chunks_written,
                (i..10).step_by(n as usize).count() as u64
            );
        }
        let dir = o.join("det");
        assert_eq!(bits(&read_all(&dir)), want, "{n} shards");
        let st = sweep::status(&dir).unwrap();
        assert!(st.complete());
        assert_eq!(st.manifest.chunks_done, 10);
        assert_eq!(st.manifest.runs_done, 156);
        assert_eq!(st.manifest.shards.len(), n as usize);
    }
}

#[test]
fn noise_is_applied_only_to_noisy_cases_and_depends_on_the_seed() {
    let s = study("noise", 3);
    let tmp = tempfile::tempdir().unwrap();
    run(&s, tmp.path(), opts());
    let rows = read_all(&tmp.path().join("noise"));
    let mut clean = s.clone();
    clean.noise = None;
    clean.name = "clean".into();
    run(&clean, tmp.path(), opts());
    let clean_rows = read_all(&tmp.path().join("clean"));
    for (a, b) in rows.iter().zip(&clean_rows) {
        if a.noise_seed.is_some() {
            assert_ne!(a.record.xmax, b.record.xmax, "noise changes xmax");
        } else {
            assert_eq!(a.record.xmax.to_bits(), b.record.xmax.to_bits());
        }
    }
    // Both noisy cases of one point differ (different seeds).
    assert_ne!(rows[2].record.xmax, rows[3].record.xmax);
    // The noise seed is stored as given (null where the case has none).
    assert!(rows.iter().all(|r| r.noise_seed.is_some() == (r.case >= 2)));
    // Without [noise], a case with a noise seed but no perturbation is the ideal run, bit for
    // bit: no noise is drawn.
    for p in clean_rows.chunks(4) {
        assert_eq!(p[2].record.xmax.to_bits(), p[0].record.xmax.to_bits());
        assert_eq!(p[2].record.di.to_bits(), p[0].record.di.to_bits());
    }
}

#[test]
fn an_interrupted_run_resumes_to_identical_part_files() {
    let s = study("resume", 13);
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    run(
        &s,
        &full,
        SweepOptions {
            chunk_points: Some(2),
            ..opts()
        },
    );

    let part = tmp.path().join("part");
    let first = run(
        &s,
        &part,
        SweepOptions {
            chunk_points: Some(2),
            stop_after: Some(8),
            ..opts()
        },
    );
    assert_eq!(first.chunks_written, 8);
    assert_eq!(first.chunks_left, 12);
    let dir = part.join("resume");
    // What a crash leaves: a stale lock of a dead process, a half-written temp file, a part
    // the manifest does not list yet (written, then killed before the manifest update), and a
    // truncated part.
    let dead = dead_pid();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    std::fs::write(dir.join(".lock"), format!("{dead} {}", host.trim())).unwrap();
    std::fs::write(store::tmp_path(&store::part_path(&dir, 9)), b"half a file").unwrap();
    std::fs::copy(
        store::part_path(&full.join("resume"), 8),
        store::part_path(&dir, 8),
    )
    .unwrap();
    let p3 = store::part_path(&dir, 3);
    let bytes = std::fs::read(&p3).unwrap();
    std::fs::write(&p3, &bytes[..bytes.len() / 2]).unwrap();

    // Without --resume: refused, nothing touched.
    let err = sweep::run_study(&s, &part, &opts()).unwrap_err();
    assert!(format!("{err:#}").contains("pass --resume"), "{err:#}");
    assert_eq!(impactsweep::error::exit_code(&err), 2);

    let second = run(
        &s,
        &part,
        SweepOptions {
            resume: true,
            ..opts()
        },
    );
    // Chunks 0-2, 4-7 kept, 8 adopted; 3 redone (truncated), 9-19 run.
    assert_eq!(second.chunks_kept, 8);
    assert_eq!(second.chunks_written, 12);
    assert!(!store::tmp_path(&store::part_path(&dir, 9)).exists());
    assert!(!dir.join(".lock").exists());
    assert_eq!(part_bytes(&dir), part_bytes(&full.join("resume")));
    let m = store::read_manifest(&dir).unwrap().unwrap();
    let mf = store::read_manifest(&full.join("resume")).unwrap().unwrap();
    assert_eq!(m.chunks, mf.chunks);
    assert_eq!(m.runs_done, 156);
    // Every checksum in the manifest is the file's.
    for c in &m.chunks {
        let sum = store::checksum_file(&store::part_path(&dir, c.chunk)).unwrap();
        assert_eq!(c.checksum, format!("{sum:016x}"));
    }

    // Resuming a finished run does nothing.
    let third = run(
        &s,
        &part,
        SweepOptions {
            resume: true,
            ..opts()
        },
    );
    assert_eq!((third.chunks_written, third.chunks_kept), (0, 20));
}

#[test]
fn a_live_lock_refuses_a_second_writer_and_names_the_pid() {
    let s = study("locked", 3);
    let tmp = tempfile::tempdir().unwrap();
    run(
        &s,
        tmp.path(),
        SweepOptions {
            stop_after: Some(0),
            ..opts()
        },
    );
    let dir = tmp.path().join("locked");
    // A live process holds the lock: this test process itself.
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let me = std::process::id();
    std::fs::write(dir.join(".lock"), format!("{me} {}", host.trim())).unwrap();
    let err = sweep::run_study(
        &s,
        tmp.path(),
        &SweepOptions {
            resume: true,
            ..opts()
        },
    )
    .unwrap_err();
    let msg = format!("{err:#}");
    assert!(
        msg.contains(&dir.join(".lock").display().to_string()),
        "{msg}"
    );
    assert!(msg.contains(&format!("PID {me}")), "{msg}");
    assert!(store::part_files(&dir).unwrap().is_empty());
    // A sibling shard has its own lock and is not blocked.
    let sum = run(
        &s,
        tmp.path(),
        SweepOptions {
            resume: true,
            shard: (1, 2),
            ..opts()
        },
    );
    assert_eq!(sum.chunks_written, 0, "one chunk, owned by shard 0/2");
}

#[test]
fn a_different_study_in_the_directory_is_refused() {
    let s = study("same", 3);
    let tmp = tempfile::tempdir().unwrap();
    run(&s, tmp.path(), opts());
    let mut other = s.clone();
    other.source.push_str("# edited\n");
    let err = sweep::run_study(
        &other,
        tmp.path(),
        &SweepOptions {
            resume: true,
            ..opts()
        },
    )
    .unwrap_err();
    assert!(format!("{err:#}").contains("holds a different study"));
    assert_eq!(impactsweep::error::exit_code(&err), 2);
}

#[test]
fn the_audit_is_deterministic_and_measures_the_solver() {
    let mut s = study("audit", 13);
    s.run.audit = 5;
    let tmp = tempfile::tempdir().unwrap();
    let sum = run(&s, tmp.path(), opts());
    let a = sum.audit.expect("audit ran");
    assert_eq!(a.points.len(), 5);
    assert_eq!(a.points, sweep::audit_points(2013, 39, 5));
    assert!(a.points.windows(2).all(|w| w[0] < w[1]));
    assert_eq!(a.solver, "exact");
    assert_eq!(a.xmax.n, 5);
    // exact at tol 1e-12 against exact at 1e-14: tiny but measured, and no outcome changes.
    assert!(
        a.xmax.max < 1e-9 && a.t1.max < 1e-9 && a.di.max < 1e-6,
        "{a:?}"
    );
    assert_eq!((a.outcome_changed, a.impacts_changed), (0, 0));
    let m = store::read_manifest(&tmp.path().join("audit"))
        .unwrap()
        .unwrap();
    assert_eq!(m.audit, Some(a.clone()));

    // A loose tolerance shows up as a larger error.
    let mut loose = s.clone();
    loose.name = "loose".into();
    loose.solver.tol = 1e-4;
    let b = run(&loose, tmp.path(), opts()).audit.unwrap();
    assert!(b.t1.max > a.t1.max, "{b:?} vs {a:?}");
    assert!(b.t1.max > 1e-9, "{b:?}");

    // A cheap solver (issue 5): RK4 with a coarse step is measurably off, by the amount the
    // simulator itself gives for those points.
    let mut cheap = s.clone();
    cheap.name = "cheap".into();
    cheap.solver.kind = SolverKind::Rk4;
    cheap.solver.h = 2e-3;
    let c = run(&cheap, tmp.path(), opts()).audit.unwrap();
    assert_eq!(c.solver, "rk4");
    assert_eq!(c.points, a.points);
    let plan = Plan::new(&cheap);
    let exact = SolverSettings {
        kind: SolverKind::Exact,
        tol: impactsweep::accuracy::REFERENCE_TOL,
        ..cheap.solver
    };
    let mut want_max: f64 = 0.0;
    for &p in &c.points {
        let run = plan.run(p, 0);
        let got = simulate(
            &run.system,
            &cheap.solver,
            &cheap.request,
            None,
            &mut NoProbe,
        );
        let reference = simulate(&run.system, &exact, &cheap.request, None, &mut NoProbe);
        want_max = want_max.max((got.xmax - reference.xmax).abs() / reference.xmax.abs());
    }
    assert_eq!(c.xmax.max.to_bits(), want_max.to_bits());
    assert!(c.xmax.max > 1e-8 && c.xmax.max < 0.1, "{c:?}");
    assert!(c.di.max > 0.0 && c.di.n == 5, "{c:?}");
    let m = store::read_manifest(&tmp.path().join("cheap"))
        .unwrap()
        .unwrap();
    assert_eq!(m.audit, Some(c));
}

#[test]
fn manifest_records_sizes_and_outcomes() {
    let s = study("manifest", 5);
    let tmp = tempfile::tempdir().unwrap();
    let sum = run(&s, tmp.path(), opts());
    let dir = tmp.path().join("manifest");
    let m = store::read_manifest(&dir).unwrap().unwrap();
    assert_eq!(
        (m.n_points, m.n_cases, m.n_runs, m.n_chunks, m.chunk_points),
        (15, 4, 60, 1, 16)
    );
    assert_eq!(m.outcomes, sum.outcomes);
    assert_eq!(m.outcomes.values().sum::<u64>(), 60);
    assert_eq!(
        std::fs::read_to_string(dir.join("study.toml")).unwrap(),
        s.source
    );
    let meta = store::part_metadata(&store::part_path(&dir, 0)).unwrap();
    assert_eq!(meta[store::META_STUDY], s.source);
    assert!(sweep::ranges(&[0, 1, 2, 3, 7, 9, 10]) == "0-3, 7, 9-10");
}

/// Whether this processor has the FMA and AVX2 that make glibc pick its FMA code for `exp`,
/// `sin` and `cos` (so that `GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA` selects another code).
fn glibc_has_two_codes() -> bool {
    let Ok(cpu) = std::fs::read_to_string("/proc/cpuinfo") else {
        return false;
    };
    let flags = cpu.lines().find(|l| l.starts_with("flags")).unwrap_or("");
    let has = |f: &str| flags.split_whitespace().any(|w| w == f);
    cfg!(all(
        target_os = "linux",
        target_arch = "x86_64",
        target_env = "gnu"
    )) && has("fma")
        && has("avx2")
}

/// A dataset's records are one math library's bits (src/sim/math.rs): glibc's two codes for
/// `exp`, `sin`, `cos` (picked by the processor) give other part files for the same study
/// (`configs/paper.toml`), and a shard or a resume with the other code is refused, naming both
/// fingerprints, without writing anything; the same code goes on.
#[test]
fn a_shard_with_another_math_library_is_refused_and_would_have_written_other_bits() {
    if !glibc_has_two_codes() {
        eprintln!(
            "skipped: no x86-64 glibc with FMA and AVX2 here, so no second math code to test"
        );
        return;
    }
    let other = ("GLIBC_TUNABLES", "glibc.cpu.hwcaps=-AVX2,-FMA");
    let tmp = tempfile::tempdir().unwrap();
    let paper = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/paper.toml");
    let run = |out: &str, env: Option<(&str, &str)>, args: &[&str]| {
        let mut c = assert_cmd::Command::cargo_bin("impactsweep").unwrap();
        c.arg("run")
            .arg(&paper)
            .arg("--out")
            .arg(tmp.path().join(out));
        c.args(args).arg("--quiet");
        if let Some((k, v)) = env {
            c.env(k, v);
        }
        c.output().unwrap()
    };
    // The same study by the two codes: other bits.
    assert!(run("a", None, &[]).status.success());
    assert!(run("b", Some(other), &[]).status.success());
    let (a, b) = (
        part_bytes(&tmp.path().join("a/paper")),
        part_bytes(&tmp.path().join("b/paper")),
    );
    assert_eq!(a.len(), b.len());
    assert!(
        a != b,
        "glibc's two codes wrote the same part files: the fingerprint guards nothing here"
    );
    // Shard 1/2 by one code, then shard 0/2 and a resume by the other: refused.
    assert!(run("s", None, &["--shard", "1/2"]).status.success());
    let dir = tmp.path().join("s/paper");
    let before = part_bytes(&dir);
    let manifest = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    for args in [&["--shard", "0/2"][..], &["--resume"][..]] {
        let out = run("s", Some(other), args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("math library that rounds differently") && err.contains("fingerprint"),
            "{args:?}: {err}"
        );
        assert_eq!(
            part_bytes(&dir),
            before,
            "{args:?}: a part file was written"
        );
        assert_eq!(
            std::fs::read_to_string(dir.join("manifest.json")).unwrap(),
            manifest,
            "{args:?}"
        );
    }
    // The same code finishes it, to the bits of the whole run.
    assert!(run("s", None, &["--shard", "0/2"]).status.success());
    assert_eq!(part_bytes(&dir), a);
}

/// The analysis shards of a harmonic study (`reduce --shard I/N`) record their math library's
/// fingerprint, and the final `reduce` refuses a set computed by two (naming the shards and
/// both fingerprints), then merges it once the odd shard is run again by the same library.
#[test]
fn analysis_shards_of_two_math_libraries_are_not_merged() {
    if !glibc_has_two_codes() {
        eprintln!(
            "skipped: no x86-64 glibc with FMA and AVX2 here, so no second math code to test"
        );
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("att.toml");
    std::fs::write(&study, common::census_study_text("att")).unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "att");
    let reduce = |args: &[&str], other: bool| {
        let mut c = assert_cmd::Command::cargo_bin("impactsweep").unwrap();
        c.arg("reduce").arg(&dir).args(args);
        if other {
            c.env("GLIBC_TUNABLES", "glibc.cpu.hwcaps=-AVX2,-FMA");
        }
        c.output().unwrap()
    };
    assert!(reduce(&["--shard", "0/2"], false).status.success());
    assert!(reduce(&["--shard", "1/2"], true).status.success());
    let out = reduce(&[], false);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("math libraries that round differently")
            && err.contains("shard 0/2 ")
            && err.contains("shard 1/2 "),
        "{err}"
    );
    assert!(!dir.join("report.md").exists(), "a report was written");
    assert!(reduce(&["--shard", "1/2"], false).status.success());
    assert!(reduce(&[], false).status.success());
    assert!(dir.join("report.md").exists());
}

/// A directory started by a build of another numerics version (`manifest.json`'s `numerics`,
/// here written as another build would) refuses a resume by this one, naming both versions, and
/// nothing is written; `status` says so.
#[test]
fn a_resume_by_a_build_of_other_numerics_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let paper = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/paper.toml");
    let bin = || assert_cmd::Command::cargo_bin("impactsweep").unwrap();
    let out = tmp.path().join("o");
    bin()
        .arg("run")
        .arg(&paper)
        .arg("--out")
        .arg(&out)
        .args(["--shard", "1/2", "--quiet"])
        .assert()
        .success();
    let dir = out.join("paper");
    let path = dir.join("manifest.json");
    let ours = impactsweep::sim::math::NUMERICS;
    let text = std::fs::read_to_string(&path).unwrap();
    let line = format!("\"numerics\": {ours},");
    assert!(text.contains(&line), "{text}");
    let other = text.replace(&line, &format!("\"numerics\": {},", ours + 1));
    std::fs::write(&path, &other).unwrap();
    let before = part_bytes(&dir);
    let res = bin()
        .arg("run")
        .arg(&paper)
        .arg("--out")
        .arg(&out)
        .args(["--resume", "--quiet"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&res.stderr);
    assert_eq!(res.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!(
            "numerics version {} in manifest.json, {ours} here",
            ours + 1
        )),
        "{err}"
    );
    assert_eq!(part_bytes(&dir), before);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), other);
    let status = bin().arg("status").arg(&dir).output().unwrap();
    assert!(
        String::from_utf8_lossy(&status.stdout).contains("a resume by it is refused"),
        "{}",
        String::from_utf8_lossy(&status.stdout)
    );
}

/// A build for the x86-64-v3 level (`.cargo/config.toml`) on a processor without it says so and
/// stops with status 1, instead of dying on an illegal instruction (`sim::math::MISSING_CPU`);
/// on one with it, it runs. The binary runs under QEMU's user-mode emulation of a Nehalem
/// (SSE4.2, no AVX) and of a Haswell (AVX2, FMA, BMI2). A build for the base level runs on
/// both. Skips, loudly, without `qemu-x86_64` (`scripts/test.sh` installs Debian's
/// `qemu-user` as root).
#[test]
#[cfg(target_arch = "x86_64")]
fn an_older_processor_is_told_what_the_build_needs() {
    let qemu = ["/usr/bin/qemu-x86_64", "/usr/local/bin/qemu-x86_64"]
        .into_iter()
        .find(|p| Path::new(p).exists());
    let Some(qemu) = qemu else {
        eprintln!(
            "SKIPPED an_older_processor_is_told_what_the_build_needs: no qemu-x86_64 \
             (Debian's qemu-user)"
        );
        return;
    };
    let run = |cpu: &str| {
        std::process::Command::new(qemu)
            .args(["-cpu", cpu, env!("CARGO_BIN_EXE_impactsweep"), "--version"])
            .output()
            .expect("qemu-x86_64 runs")
    };
    let old = run("Nehalem");
    let stderr = String::from_utf8_lossy(&old.stderr);
    if cfg!(target_feature = "avx2") {
        assert_eq!(old.status.code(), Some(1), "on a Nehalem: {stderr}");
        assert!(
            stderr.contains("uses the x86-64-v3 instructions")
                && stderr.contains("RUSTFLAGS= cargo build --release"),
            "on a Nehalem: {stderr}"
        );
    } else {
        assert!(old.status.success(), "a base build on a Nehalem: {stderr}");
    }
    let new = run("Haswell");
    assert!(
        new.status.success() && String::from_utf8_lossy(&new.stdout).starts_with("impactsweep"),
        "on a Haswell: {}",
        String::from_utf8_lossy(&new.stderr)
    );
}
