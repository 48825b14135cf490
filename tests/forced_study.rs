//! Harmonic studies (issue 12, item 3): `[scene] kind = "harmonic"` with `F0` and `omega` or
//! `r`, the frequency and the force as sweepable axes, the forced outputs in the records, noise
//! and the perturbation cases as in free decay, the frequency axis innermost so that chunks hold
//! whole frequency-response curves, and records bit-identical whatever the threads, chunks,
//! shards or interruptions.

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::model::System;
use impactsweep::sim::{Drive, Harmonic, HarmonicRecord, NoProbe, NoiseSettings, Request, Scene};
use impactsweep::sim::{SolverSettings, noise::NoiseStream, simulate_harmonic};
use impactsweep::store::{self, RunRow, TableKind, schema};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};
use predicates::prelude::*;

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// Seven frequency ratios around resonance (given first in the file: the study moves the
/// frequency axis last), two inner masses (none, and Table I's), four cases: the ideal one, a
/// heavier inner mass, a noisy one, a noisy smaller clearance.
fn study_text(name: &str) -> String {
    format!(
        r#"[study]
name = "{name}"
seed = 5

[system]
v0 = 0.0

[scene]
kind = "harmonic"
F0 = 0.3
n_trans_max = 600
life_max_periods = 2000
n_meas = 10

[sweep]
r = {{ start = 0.85, stop = 1.15, num = 7 }}
m = [0.0, 0.02]

[noise]
power = 1e-12
sample_time = 1e-3

[perturb]
cases = [
  {{ dm = 0.002 }},
  {{ noise_seed = 1 }},
  {{ dd = -0.002, noise_seed = 2 }},
]
"#
    )
}

fn write_study(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, study_text(name)).unwrap();
    path
}

fn load(dir: &Path, name: &str) -> Study {
    Study::load(&write_study(dir, name)).unwrap()
}

fn read_all(dir: &Path) -> Vec<RunRow<HarmonicRecord>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<HarmonicRecord>(p).unwrap())
        .collect()
}

/// Every stored column of every row as bits.
fn bits(rows: &[RunRow<HarmonicRecord>]) -> Vec<Vec<u64>> {
    rows.iter()
        .map(|r| {
            let c = &r.record;
            let mut v = vec![
                r.point_id,
                u64::from(r.case),
                r.dm.to_bits(),
                r.dd.to_bits(),
                c.outcome as u64,
                u64::from(c.period),
                c.n_trans,
                u64::from(c.converged),
                c.n_meas,
                c.impacts,
                c.sticks,
                c.steps,
            ];
            for x in [
                c.F0,
                c.omega,
                c.r,
                c.amplitude,
                c.impacts_per_period,
                c.amplitude_linear,
                c.attenuation,
                c.energy_force,
                c.energy_viscous,
                c.energy_impact,
                c.t_stop,
            ] {
                v.push(x.to_bits());
            }
            for k in impactsweep::model::SYSTEM_KEYS {
                v.push(r.system.get(k).unwrap().to_bits());
            }
            v
        })
        .collect()
}

fn part_bytes(dir: &Path) -> Vec<Vec<u8>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .collect()
}

#[test]
fn issue_12_a_harmonic_study_records_the_forced_outputs_of_every_run() {
    let tmp = tempfile::tempdir().unwrap();
    let study = write_study(tmp.path(), "fr");
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "fr");
    let part = store::part_path(&dir, 0);
    let meta = store::part_metadata(&part).unwrap();
    assert_eq!(meta[schema::META_TABLE], "forced_points");
    let rows = read_all(&dir);
    assert_eq!(rows.len(), 2 * 7 * 4);

    let r_values: Vec<f64> = (0..7)
        .map(|i| [0.85, 0.9, 0.95, 1.0, 1.05, 1.1, 1.15][i])
        .collect();
    let noise = NoiseSettings {
        power: 1e-12,
        sample_time: 1e-3,
    };
    for row in &rows {
        // The frequency varies fastest: point = m index * 7 + r index.
        let (mi, ri) = (row.point / 7, (row.point % 7) as usize);
        assert_eq!(row.point_id, row.point * 4 + u64::from(row.case));
        let case = [
            (0.0, 0.0, None),
            (0.002, 0.0, None),
            (0.0, 0.0, Some(1)),
            (0.0, -0.002, Some(2)),
        ][row.case as usize];
        let sys = System {
            v0: 0.0,
            m: [0.0, 0.02][mi as usize] + case.0,
            d: 0.01 + case.1,
            ..System::TABLE_I
        };
        assert_eq!(row.system, sys, "run {}", row.point_id);
        assert_eq!(row.record.r.to_bits(), r_values[ri].to_bits());
        assert_eq!(row.record.F0, 0.3);
        // The same run, simulated here from its inputs alone.
        let h = Harmonic {
            F0: 0.3,
            drive: Drive::Ratio(r_values[ri]),
            n_trans_max: 600,
            n_meas: 10,
            ..Harmonic::default()
        };
        let want = match case.2 {
            Some(seed) => {
                let mut stream = NoiseStream::new(5, seed, row.point);
                simulate_harmonic(
                    &sys,
                    &SolverSettings::default(),
                    &Request::default(),
                    &h,
                    Some((&noise, &mut stream)),
                    &mut NoProbe,
                )
            }
            None => simulate_harmonic(
                &sys,
                &SolverSettings::default(),
                &Request::default(),
                &h,
                None,
                &mut NoProbe,
            ),
        };
        let stored = RunRow {
            record: want.clone(),
            ..row.clone()
        };
        assert_eq!(
            bits(std::slice::from_ref(row)),
            bits(std::slice::from_ref(&stored)),
            "run {}",
            row.point_id
        );
        assert_eq!(row.record.n_meas, 10);
        assert_eq!(row.record.outcome.name(), "ok", "run {}", row.point_id);
        // Without the inner mass the primary system is linear: its amplitude is the linear one.
        if mi == 0 && case.2.is_none() && case.0 == 0.0 {
            let rel = (row.record.amplitude / row.record.amplitude_linear - 1.0).abs();
            assert!(rel < 1e-9, "run {}: {rel:e}", row.point_id);
            assert_eq!(row.record.impacts, 0);
        }
    }
    // The damper helps at resonance (ideal case, m = 0.02, r = 1): Masri's regime.
    let at_resonance = rows
        .iter()
        .find(|r| r.point == 7 + 3 && r.case == 0)
        .unwrap();
    assert!(at_resonance.record.attenuation < 0.1, "{at_resonance:?}");
    assert_eq!(at_resonance.record.period, 1);
    // Noise is drawn only in the noisy cases, and moves the measured amplitude, not the motion:
    // on periodic orbits the noisy run has the same impacts per period. (The samples split the
    // motion into more pieces, so a chaotic orbit drifts apart at rounding level.)
    let ideal: Vec<&RunRow<HarmonicRecord>> = rows.iter().filter(|r| r.case == 0).collect();
    let noisy: Vec<&RunRow<HarmonicRecord>> = rows.iter().filter(|r| r.case == 2).collect();
    for (a, b) in ideal.iter().zip(&noisy) {
        assert_ne!(a.record.amplitude, b.record.amplitude, "point {}", a.point);
        if a.record.period > 0 {
            assert_eq!(
                a.record.impacts_per_period, b.record.impacts_per_period,
                "point {}",
                a.point
            );
        }
    }
    // Every field carries its unit.
    let builder = store::open(&part).unwrap();
    for field in builder.schema().fields() {
        assert_eq!(
            field.metadata().get(schema::FIELD_UNIT).map(String::as_str),
            schema::unit(TableKind::HarmonicPoints, field.name()),
            "{}",
            field.name()
        );
    }
}

#[test]
fn issue_12_harmonic_records_are_bit_identical_across_threads_chunks_shards_and_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let s = load(tmp.path(), "det");
    assert_eq!(s.axes.last().unwrap().key, "r");
    assert_eq!(s.curve_points(), 7);
    let run = |out: &str, o: SweepOptions| {
        sweep::run_study(&s, &tmp.path().join(out), &o).unwrap();
        tmp.path().join(out).join("det")
    };
    let one = run(
        "t1",
        SweepOptions {
            threads: Some(1),
            ..SweepOptions::default()
        },
    );
    let want = bits(&read_all(&one));
    assert_eq!(want.len(), 56);
    let two = run(
        "t2",
        SweepOptions {
            threads: Some(2),
            ..SweepOptions::default()
        },
    );
    assert_eq!(part_bytes(&two), part_bytes(&one));
    // One curve per chunk, sharded in two.
    for i in 0..2 {
        run(
            "shards",
            SweepOptions {
                shard: (i, 2),
                chunk_points: Some(7),
                ..SweepOptions::default()
            },
        );
    }
    let sharded = tmp.path().join("shards").join("det");
    assert_eq!(store::part_files(&sharded).unwrap().len(), 2);
    assert_eq!(bits(&read_all(&sharded)), want);
    // Interrupted after the first chunk, then resumed.
    let o = SweepOptions {
        chunk_points: Some(7),
        stop_after: Some(1),
        ..SweepOptions::default()
    };
    let resumed = run("resume", o);
    assert_eq!(store::part_files(&resumed).unwrap().len(), 1);
    run(
        "resume",
        SweepOptions {
            resume: true,
            ..SweepOptions::default()
        },
    );
    assert_eq!(part_bytes(&resumed), part_bytes(&sharded));
    assert!(sweep::status(&resumed).unwrap().complete());
}

#[test]
fn issue_12_a_chunk_size_that_cuts_a_curve_and_the_audit_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let study = write_study(tmp.path(), "cut");
    let out = tmp.path().join("out");
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--chunk-points", "5"])
        .assert()
        .code(2)
        .stderr(predicate::eq(
            "error: --chunk-points 5: must be a multiple of the 7 values of the frequency axis \
             [sweep].r, so that every chunk holds whole frequency-response curves\n",
        ));
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--audit", "2"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--audit 2: the accuracy audit"));
    assert!(!out.join("cut").exists());
}

#[test]
fn issue_12_plan_describes_the_scene_and_a_free_decay_reader_refuses_forced_parts() {
    let tmp = tempfile::tempdir().unwrap();
    let study = write_study(tmp.path(), "planned");
    bin().arg("plan").arg(&study).assert().success().stdout(
        predicate::str::contains("axes:           m = 0 .. 0.02 (2 values)\n")
            .and(predicate::str::contains(
                "                r = 0.85 .. 1.15 (7 values)\n",
            ))
            .and(predicate::str::contains(
                "scene:          harmonic: F0 cos(omega t) on the main mass; F0 = 0.3 N, r \
                     swept (each curve: 7 values)\n",
            ))
            .and(predicate::str::contains(
                "each run:       transient until the Poincare section converges (trans_tol \
                     1e-10), at most 600 forcing periods, then 10 periods measured",
            )),
    );
    let s = load(tmp.path(), "parts");
    sweep::run_study(&s, tmp.path(), &SweepOptions::default()).unwrap();
    let part = store::part_path(&tmp.path().join("parts"), 0);
    let e = store::read_part(&part).unwrap_err().to_string();
    assert!(
        e.ends_with("holds the forced_points table, not points (a part of another scene's study; see docs/schema.md)"),
        "{e}"
    );
    assert!(matches!(s.scene, Scene::Harmonic(_)));
}

/// A harmonic run directory whose manifest and journals are gone: `--resume` verifies its parts
/// (reading the `forced_points` table) and keeps them, without running them again.
#[test]
fn issue_12_unrecorded_harmonic_parts_are_verified_and_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let study = write_study(tmp.path(), "kept");
    let out = tmp.path().join("out");
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--chunk-points", "7"])
        .assert()
        .success();
    let dir = out.join("kept");
    let before = part_bytes(&dir);
    assert_eq!(before.len(), 2);
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if name == "manifest.json" || name.starts_with("journal") {
            std::fs::remove_file(&path).unwrap();
        }
    }
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--resume", "--chunk-points", "7"])
        .assert()
        .success()
        .stderr(predicate::str::contains("0 chunks written, 2 kept"));
    assert_eq!(part_bytes(&dir), before);
    assert!(sweep::status(&dir).unwrap().complete());
}

/// Every attractors part's rows, in chunk order, as text (every value to its last bit).
fn attractor_rows(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for p in store::part_files(dir).unwrap() {
        let k = store::part_chunk(&p).unwrap();
        let side = store::attractors::attractors_part_path(dir, k);
        for a in store::attractors::read_part(&side).unwrap() {
            out.push(format!("{a:?}"));
        }
    }
    out
}

/// Issue 23: the sweep stores every run's attractors, every case's, beside its points: the same
/// rows for 1 and 2 threads, for one chunk and for seven, sharded in three, and after a
/// `kill -9` and `--resume` the dataset (points, attractors and manifest) of an uninterrupted run.
#[test]
fn issue_23_attractor_tables_are_identical_across_threads_chunks_shards_and_kill_9() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("att.toml");
    std::fs::write(&path, common::census_study_text("att")).unwrap();
    let s = Study::load(&path).unwrap();
    let run = |out: &str, o: SweepOptions| {
        sweep::run_study(&s, &tmp.path().join(out), &o).unwrap();
        tmp.path().join(out).join("att")
    };
    let one = run(
        "t1",
        SweepOptions {
            threads: Some(1),
            ..SweepOptions::default()
        },
    );
    assert_eq!(store::part_files(&one).unwrap().len(), 1);
    let want = attractor_rows(&one);
    // Every run has its attractors, every case's.
    let runs: std::collections::BTreeSet<(u64, u32)> =
        store::attractors::read_part(&store::attractors::attractors_part_path(&one, 0))
            .unwrap()
            .iter()
            .map(|a| (a.run.point, a.run.case))
            .collect();
    assert_eq!(runs.len(), 7 * 4 * 2);
    let seven = run(
        "t2",
        SweepOptions {
            threads: Some(2),
            chunk_points: Some(4),
            ..SweepOptions::default()
        },
    );
    assert_eq!(store::part_files(&seven).unwrap().len(), 7);
    assert_eq!(attractor_rows(&seven), want);
    for i in 0..3 {
        run(
            "shards",
            SweepOptions {
                shard: (i, 3),
                chunk_points: Some(4),
                ..SweepOptions::default()
            },
        );
    }
    let sharded = tmp.path().join("shards").join("att");
    // The same part files (the manifests differ in the shards they name).
    let parts = |dir: &Path| -> Vec<(String, u64)> {
        common::dataset(dir)
            .into_iter()
            .filter(|f| f.0 != "manifest.json")
            .map(|(n, b)| (n, store::Checksum::DEFAULT.of(&b)))
            .collect()
    };
    assert_eq!(parts(&sharded), parts(&seven));
    // kill -9 in the middle of a one-thread run of seven chunks, then --resume.
    let out = tmp.path().join("killed");
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("impactsweep"))
        .arg("run")
        .arg(&path)
        .args(["--quiet", "--threads", "1", "--chunk-points", "4", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let dir = out.join("att");
    let start = std::time::Instant::now();
    while store::part_files(&dir).map_or(0, |p| p.len()) < 2 && child.try_wait().unwrap().is_none()
    {
        assert!(start.elapsed() < std::time::Duration::from_secs(300));
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let running = child.try_wait().unwrap().is_none();
    let _ = child.kill();
    child.wait().unwrap();
    assert!(running, "the run ended before the kill");
    bin()
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--resume"])
        .assert()
        .success();
    assert_eq!(parts(&dir), parts(&seven));
    assert_eq!(
        std::fs::read(dir.join("manifest.json")).unwrap(),
        std::fs::read(seven.join("manifest.json")).unwrap()
    );
}

/// The study `text` (named `name`) run into `dir` with the default options: every attractor row
/// it stored, in chunk order.
fn study_attractors(
    dir: &Path,
    name: &str,
    text: &str,
) -> Vec<impactsweep::orbits::attractors::AttractorRow> {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let s = Study::load(&path).unwrap();
    sweep::run_study(&s, dir, &SweepOptions::default()).unwrap();
    let run = dir.join(name);
    let mut out = Vec::new();
    for p in store::part_files(&run).unwrap() {
        let side = store::attractors::attractors_part_path(&run, store::part_chunk(&p).unwrap());
        out.extend(store::attractors::read_part(&side).unwrap());
    }
    out
}

/// Issue 23: `nonperiodic_peak = "window"` skips the design life and nothing else. The same
/// study with and without it stores the same attractors (every periodic row to its last bit, and
/// every census column of the others); a motion that is not periodic then keeps its window's
/// maximum as its amplitude and has no life estimate, where the default measured one.
#[test]
fn issue_23_window_peaks_store_the_same_attractors_without_the_design_life() {
    let tmp = tempfile::tempdir().unwrap();
    let rows = |name: &str, extra: &str| {
        let text = common::census_study_text(name)
            .replace("starts = 4\n", &format!("starts = 4\n{extra}"));
        study_attractors(tmp.path(), name, &text)
    };
    let life = rows("life", "");
    let window = rows("window", "nonperiodic_peak = \"window\"\n");
    // The design life may also find that a motion was a start still approaching a periodic
    // orbit of its census (`orbits::race`): it is folded into that orbit, so the life study can
    // hold fewer rows, each of which the window study holds (the same point, case and section).
    assert!(life.len() <= window.len());
    let key = |a: &impactsweep::orbits::attractors::AttractorRow| {
        (a.run.point, a.run.case, a.section.map(f64::to_bits))
    };
    let folded: Vec<_> = window
        .iter()
        .filter(|w| !life.iter().any(|l| key(l) == key(w)))
        .collect();
    assert_eq!(life.len() + folded.len(), window.len());
    assert!(folded.iter().all(|w| !w.kind.periodic()), "{folded:?}");
    let window: Vec<_> = window
        .iter()
        .filter(|w| life.iter().any(|l| key(l) == key(w)))
        .collect();
    let mut measured = 0;
    for (l, w) in life.iter().zip(window) {
        assert_eq!((l.run.point, l.run.case), (w.run.point, w.run.case));
        if l.kind.periodic() {
            // Its basin holds the folded starts too.
            let same = |a: &impactsweep::orbits::attractors::AttractorRow| {
                (a.kind, a.amplitude.to_bits(), a.section.map(f64::to_bits))
            };
            assert_eq!(same(l), same(w));
            assert!(l.starts >= w.starts);
            continue;
        }
        let census = |a: &impactsweep::orbits::attractors::AttractorRow| {
            format!(
                "{:?}",
                (
                    a.kind,
                    a.window_amplitude,
                    a.basin_share,
                    a.starts,
                    a.lyapunov,
                    a.section
                )
            )
        };
        assert_eq!(census(l), census(w));
        assert_eq!(w.amplitude.to_bits(), w.window_amplitude.to_bits());
        assert!(w.life_amplitude.is_nan() && w.life_lo.is_nan() && w.life_hi.is_nan());
        assert_eq!(w.measured_periods, 0);
        if l.life_lo.is_finite() {
            measured += 1;
        }
    }
    assert!(
        measured > 0,
        "the study has no motion whose design life was measured"
    );
}

/// Issue 69, item 7: `life_curve = "whole"` measures every frequency of the ideal curve until
/// its value is known (each motion that could carry it settled or at `life_max_periods`), and
/// changes nothing else: a perturbed case's curve, which serves its peak alone, races as with
/// the default (`"decisions"`) and stores the same rows to their last bit. Under the default
/// some motion of the ideal curve stops short of the cap: the rule has work to do here.
#[test]
fn issue_69_the_whole_curve_is_measured_where_asked_and_nothing_else_moves() {
    whole_curve_is_measured_where_asked("");
}

/// As [`issue_69_the_whole_curve_is_measured_where_asked_and_nothing_else_moves`] for two units
/// of different clearances (the same added mass), whose curves race through the same rules.
#[test]
fn issue_69_the_whole_curve_of_two_units_is_measured_where_asked_and_nothing_else_moves() {
    whole_curve_is_measured_where_asked("units = 2\nd_spread = 0.2\n");
}

/// The whole curve's check on the study of four frequencies near resonance, with `units` (the
/// `[system]` keys of several units, or nothing) added to its system.
fn whole_curve_is_measured_where_asked(units: &str) {
    let tmp = tempfile::tempdir().unwrap();
    const CAP: u64 = 8000;
    let rows = |name: &str, extra: &str| {
        let text = format!(
            "[study]\nname = \"{name}\"\nseed = 3\n[system]\nC = 0.1\ne = 0.9\nm = 0.02\n\
             d = 0.02\nx0 = 0.0\nv0 = 0.0\ny0 = 0.0\nw0 = 0.0\n{units}[scene]\nkind = \"harmonic\"\n\
             F0 = 0.1\nstarts = 4\nlife_max_periods = {CAP}\n{extra}[sweep]\n\
             r = [0.94, 0.95, 0.99, 1.0]\n[perturb]\ndm = [0.001]\n[ranking]\nverify_periods = 0\n"
        );
        study_attractors(tmp.path(), name, &text)
    };
    let decisions = rows("decisions", "");
    let whole = rows("whole", "life_curve = \"whole\"\n");
    let perturbed = |rows: &[impactsweep::orbits::attractors::AttractorRow]| {
        rows.iter()
            .filter(|a| a.run.case == 1)
            .map(|a| format!("{a:?}"))
            .collect::<Vec<_>>()
    };
    assert!(!perturbed(&decisions).is_empty());
    assert_eq!(perturbed(&decisions), perturbed(&whole));
    let wandering = |rows: &[impactsweep::orbits::attractors::AttractorRow]| {
        rows.iter()
            .filter(|a| a.run.case == 0 && !a.kind.periodic() && a.life_amplitude.is_finite())
            .cloned()
            .collect::<Vec<_>>()
    };
    let short = wandering(&decisions)
        .iter()
        .filter(|a| a.measured_periods < CAP)
        .count();
    assert!(
        short > 0,
        "every motion reached the cap without the rule: {:?}",
        wandering(&decisions)
            .iter()
            .map(|a| (a.run.point, a.measured_periods, a.life_amplitude))
            .collect::<Vec<_>>()
    );
    // Each frequency's lower end: its largest periodic amplitude and lower end of an interval.
    let ideal: Vec<_> = whole.iter().filter(|a| a.run.case == 0).collect();
    let lower = |point: u64| {
        ideal
            .iter()
            .filter(|a| a.run.point == point)
            .map(|a| {
                if a.kind.periodic() {
                    a.amplitude
                } else {
                    a.life_lo
                }
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let motions = wandering(&whole);
    assert!(!motions.is_empty());
    for a in &motions {
        let settled = 0.5 * (a.life_hi - a.life_lo) <= 0.05 * a.life_amplitude;
        let out_of_it = a.life_hi <= lower(a.run.point);
        assert!(
            a.measured_periods == CAP || settled || out_of_it,
            "r = {}: {} periods, {} [{}, {}]",
            a.run.point,
            a.measured_periods,
            a.life_amplitude,
            a.life_lo,
            a.life_hi
        );
    }
}
