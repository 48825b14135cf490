//! Several damper units (model.md §14, issue 68): checks that can fail.
//!
//! * `N` identical units started together are one unit of the same total mass (each unit
//!   `m / N`, the single unit `m`), in free decay (every solver, with rebounds, chatter and
//!   sticking) and in the harmonic scene, to `1e-12`: the simultaneous impact law makes that an
//!   identity, where impacts taken one after another would break it.
//! * Momentum `M v + sum m_i w_i` is conserved at every impact, to rounding.
//! * Per-unit impact counts add up, and every unit's clearance is the one `d_spread` gives.

use crate::common;
use impactsweep::model::System;
use impactsweep::sim::harmonic::{Drive, Harmonic};
use impactsweep::sim::{
    NoProbe, Probe, Record, Request, SolverKind, SolverSettings, State, Wall, simulate,
    simulate_harmonic,
};

fn close(a: f64, b: f64, scale: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol * scale.max(a.abs()).max(b.abs()) || (a.is_nan() && b.is_nan()),
        "{what}: {a:e} vs {b:e} (diff {:e})",
        (a - b).abs()
    );
}

fn same_free(one: &Record, several: &Record, tol: f64, what: &str) {
    assert_eq!(one.outcome, several.outcome, "{what}: outcome");
    if !what.contains("e = 0 ") {
        // With e = 0 a unit leaving its wall at zero relative speed may be caught again at the
        // same instant by rounding, an impact of no impulse: counts differ by those, the
        // motion does not.
        assert_eq!(one.impacts, several.impacts, "{what}: impacts");
    }
    assert_eq!(one.sticks, several.sticks, "{what}: sticks");
    let x = one.x1.abs();
    for (a, b, name) in [
        (one.x1, several.x1, "x1"),
        (one.x2, several.x2, "x2"),
        (one.xmax, several.xmax, "xmax"),
    ] {
        close(a, b, x, tol, &format!("{what}: {name}"));
    }
    for (a, b, name) in [
        (one.t1, several.t1, "t1"),
        (one.t2, several.t2, "t2"),
        (one.t_stop, several.t_stop, "t_stop"),
    ] {
        // Undamped rebounds amplify the last bits: to 1e-11 by the fourth peak.
        close(a, b, one.t_stop, 10.0 * tol, &format!("{what}: {name}"));
    }
    close(one.di, several.di, 0.0, 100.0 * tol, &format!("{what}: di"));
    let e = one.energy_impact + one.energy_viscous;
    close(
        one.energy_impact,
        several.energy_impact,
        e,
        tol,
        &format!("{what}: energy_impact"),
    );
    close(
        one.energy_viscous,
        several.energy_viscous,
        e,
        tol,
        &format!("{what}: energy_viscous"),
    );
}

fn settings(kind: SolverKind) -> SolverSettings {
    SolverSettings {
        kind,
        ..SolverSettings::default()
    }
}

#[test]
fn identical_units_in_step_are_one_unit_in_free_decay() {
    let req = Request {
        peaks: 4,
        ..Request::default()
    };
    let mut cases = 0;
    let mut sticking = 0;
    for kind in [SolverKind::Exact, SolverKind::Dopri5, SolverKind::Rk4] {
        for n in [2.0, 3.0, 5.0, 8.0] {
            for e in [0.95, 0.8, 0.5, 0.2, 0.0] {
                for (d, m, c) in [(0.01, 0.02, 0.1), (0.004, 0.03, 0.0), (0.03, 0.01, 2.0)] {
                    if kind != SolverKind::Exact && (n > 3.0 || e < 0.5) {
                        continue;
                    }
                    let one = System {
                        e,
                        d,
                        m,
                        C: c,
                        ..System::TABLE_I
                    };
                    let several = System { units: n, ..one };
                    several.validate().unwrap();
                    let s = settings(kind);
                    let a = simulate(&one, &s, &req, None, &mut NoProbe);
                    let b = simulate(&several, &s, &req, None, &mut NoProbe);
                    let what = format!("{kind:?} N = {n} e = {e} d = {d} m = {m} C = {c}");
                    // The step-size control of the integrators reacts to rounding: 1e-8 there.
                    let tol = if kind == SolverKind::Exact {
                        1e-12
                    } else {
                        1e-8
                    };
                    same_free(&a, &b, tol, &what);
                    assert_eq!(b.unit_impacts.len(), n as usize, "{what}");
                    for &k in &b.unit_impacts {
                        assert_eq!(k, b.impacts, "{what}: every unit hits at every impact");
                    }
                    assert!(b.steps <= (n as u64 + 1) * a.steps, "{what}: steps");
                    cases += 1;
                    sticking += usize::from(a.sticks > 0);
                }
            }
        }
    }
    assert!(cases >= 60, "{cases}");
    assert!(sticking >= 5, "the cases must include sticking: {sticking}");
}

#[test]
fn identical_units_in_step_are_one_unit_in_the_harmonic_scene() {
    let req = Request::default();
    let s = SolverSettings::default();
    let (mut compared, mut sticking) = (0, 0);
    for r in [0.7, 0.95, 1.0, 1.1, 1.6] {
        for (n, e) in [(2.0, 0.8), (4.0, 0.6), (3.0, 0.3), (3.0, 0.0)] {
            let one = System {
                e,
                ..System::TABLE_I
            };
            let several = System { units: n, ..one };
            let scene = Harmonic {
                F0: 0.5,
                drive: Drive::Ratio(r),
                n_meas: 8,
                starts: 1,
                ..Harmonic::default()
            };
            scene.validate(&one).unwrap();
            let a = simulate_harmonic(&one, &s, &req, &scene, None, &mut NoProbe);
            let b = simulate_harmonic(&several, &s, &req, &scene, None, &mut NoProbe);
            let what = format!("r = {r} N = {n} e = {e}");
            assert_eq!(a.outcome, b.outcome, "{what}");
            if a.n_trans >= scene.n_trans_max {
                // No steady state within the transient's cap: after 2,000 periods of a motion
                // that does not settle, rounding has grown to the size of the motion.
                continue;
            }
            compared += 1;
            sticking += usize::from(a.sticks > 0);
            // The steady state: the transient's end is decided by a convergence test at
            // `trans_tol = 1e-10`, which rounding may pass a few periods earlier or later, so
            // the counts over the whole run are not compared; the orbit is.
            assert_eq!(a.period, b.period, "{what}: period");
            assert_eq!(
                a.impacts_per_period, b.impacts_per_period,
                "{what}: impacts a period"
            );
            close(
                a.amplitude,
                b.amplitude,
                0.0,
                1e-9,
                &format!("{what}: amplitude"),
            );
        }
    }
    assert!(compared >= 10, "{compared} cases settled");
    assert!(sticking >= 2, "{sticking} cases stick");
}

/// Momentum of the main mass and the units that hit, before and after each impact; the other
/// units keep their velocities, so this is the whole momentum's jump.
#[derive(Default)]
struct Momentum {
    m: Vec<f64>,
    big_m: f64,
    /// (t, before, after) summed over the units of one impact instant.
    events: Vec<(f64, f64, f64, f64)>,
    worst: f64,
    hits: Vec<u64>,
}

impl Momentum {
    fn flush(&mut self) {
        for &(_, before, after, scale) in &self.events {
            self.worst = self.worst.max((after - before).abs() / scale);
        }
        self.events.clear();
    }
}

impl Probe for Momentum {
    fn impact_of(&mut self, t: f64, unit: usize, _wall: Wall, before: &State, after: &State) {
        self.hits[unit] += 1;
        let mi = self.m[unit];
        match self.events.last_mut() {
            Some(last) if last.0 == t => {
                last.1 += mi * before.w;
                last.2 += mi * after.w;
                last.3 += (mi * before.w).abs();
            }
            _ => {
                self.flush();
                self.events.push((
                    t,
                    self.big_m * before.v + mi * before.w,
                    self.big_m * after.v + mi * after.w,
                    (self.big_m * before.v).abs() + (mi * before.w).abs(),
                ));
            }
        }
    }
}

#[test]
fn momentum_is_conserved_at_every_impact_of_different_units() {
    let req = Request {
        t_end: Some(2.0),
        ..Request::default()
    };
    let mut total = 0;
    for (n, spread, e) in [(3.0, 0.4, 0.9), (5.0, 0.3, 0.9), (8.0, 0.5, 0.95)] {
        let sys = System {
            units: n,
            d_spread: spread,
            e,
            ..System::TABLE_I
        };
        sys.validate().unwrap();
        let units = sys.unit_list();
        let mut probe = Momentum {
            m: units.iter().map(|u| u.m).collect(),
            big_m: sys.M,
            hits: vec![0; units.len()],
            ..Momentum::default()
        };
        let rec = simulate(&sys, &SolverSettings::default(), &req, None, &mut probe);
        probe.flush();
        // Sticking carries units with the main mass; these cases rebound only.
        assert_eq!(rec.sticks, 0, "N = {n}");
        assert!(
            probe.worst < 1e-14,
            "N = {n}: momentum jump {:e}",
            probe.worst
        );
        assert_eq!(probe.hits, rec.unit_impacts, "N = {n}");
        assert!(rec.impacts > 10, "N = {n}: {}", rec.impacts);
        // Different clearances engage at different times.
        assert_eq!(rec.unit_impacts.iter().sum::<u64>(), rec.impacts, "N = {n}");
        assert!(
            rec.unit_impacts.iter().any(|&k| k != rec.unit_impacts[0]),
            "N = {n}: {:?}",
            rec.unit_impacts
        );
        total += rec.impacts;
    }
    assert!(total > 100, "{total}");
}

#[test]
fn clearances_spread_evenly_and_bad_units_are_named() {
    let sys = System {
        units: 5.0,
        d_spread: 0.5,
        ..System::TABLE_I
    };
    let d: Vec<f64> = sys.unit_list().iter().map(|u| u.d).collect();
    let want = [0.005, 0.0075, 0.01, 0.0125, 0.015];
    for (a, b) in d.iter().zip(want) {
        close(*a, b, 0.0, 1e-15, "d_i");
    }
    let m: f64 = sys.unit_list().iter().map(|u| u.m).sum();
    close(m, sys.m, 0.0, 1e-15, "total m");
    for (units, spread, y0, want) in [
        (
            0.0,
            0.0,
            0.0,
            "units = 0: the number of units must be a whole number in [1, 64]",
        ),
        (
            2.5,
            0.0,
            0.0,
            "units = 2.5: the number of units must be a whole number in [1, 64]",
        ),
        (
            -3.0,
            0.0,
            0.0,
            "units = -3: the number of units must be a whole number in [1, 64]",
        ),
        (
            65.0,
            0.0,
            0.0,
            "units = 65: the number of units must be a whole number in [1, 64]",
        ),
        (
            2.0,
            1.0,
            0.0,
            "d_spread = 1: the clearance spread must be in [0, 1)",
        ),
        (
            3.0,
            0.5,
            0.003,
            "y0 = 0.003: every unit must start inside its cavity: |y0 - x0| = 0.003 exceeds the smallest unit's d/2 = 0.0025 (d_spread = 0.5)",
        ),
    ] {
        let s = System {
            units,
            d_spread: spread,
            y0,
            ..System::TABLE_I
        };
        assert_eq!(s.validate().unwrap_err().to_string(), want);
    }
}

/// Every impact as the Rust run found it, with every unit's state after it (tracked along the
/// units' straight lines between impacts: these cases neither stick nor accelerate the units).
/// One impact instant: (t, x, v, units hit in order with their wall, each unit's (y, w) after).
type ImpactRow = (f64, f64, f64, Vec<(usize, Wall)>, Vec<(f64, f64)>);

#[derive(Default)]
struct Impacts {
    rows: Vec<ImpactRow>,
    /// Each unit's last known (t, y, w).
    lines: Vec<(f64, f64, f64)>,
}

impl Probe for Impacts {
    fn impact_of(&mut self, t: f64, unit: usize, wall: Wall, _before: &State, after: &State) {
        self.lines[unit] = (t, after.y, after.w);
        let now: Vec<(f64, f64)> = self
            .lines
            .iter()
            .map(|&(t0, y, w)| (y + w * (t - t0), w))
            .collect();
        match self.rows.last_mut() {
            Some(row) if row.0 == t => {
                row.3.push((unit, wall));
                row.4 = now;
            }
            _ => self
                .rows
                .push((t, after.x, after.v, vec![(unit, wall)], now)),
        }
    }
}

/// The independent reference (`tests/oracle/units.py`, written apart from the simulator: closed
/// form between impacts, impacts by dense sampling and Brent's method) restarted from the Rust
/// state after each impact predicts the next impact: the same instant to `1e-9` s, the same
/// units at the same walls, and the same velocities after it to `1e-9` relative. Restarting
/// at every impact compares the event map itself; a whole run cannot be compared to `1e-9`,
/// as impacts amplify the last bits by about `4e8` a second (the oracle's own measurement).
#[test]
fn an_independent_reference_agrees_on_every_impact_of_different_units() {
    use serde_json::{Value, json};
    let cases = [
        (
            System {
                units: 3.0,
                d_spread: 0.25,
                e: 0.85,
                ..System::TABLE_I
            },
            None,
        ),
        (
            System {
                units: 4.0,
                d_spread: 0.6,
                e: 0.7,
                m: 0.03,
                ..System::TABLE_I
            },
            None,
        ),
        (
            System {
                units: 3.0,
                d_spread: 0.4,
                e: 0.9,
                v0: 0.0,
                ..System::TABLE_I
            },
            Some((0.5, 0.9)),
        ),
    ];
    let mut compared = 0;
    for (sys, forcing) in cases {
        sys.validate().unwrap();
        let units = sys.unit_list();
        let mut probe = Impacts {
            lines: units.iter().map(|u| (0.0, u.y0, u.w0)).collect(),
            ..Impacts::default()
        };
        let load = match forcing {
            None => {
                let req = Request {
                    t_end: Some(0.6),
                    ..Request::default()
                };
                let rec = simulate(&sys, &SolverSettings::default(), &req, None, &mut probe);
                assert_eq!(rec.sticks, 0);
                Value::Null
            }
            Some((f0, r)) => {
                let scene = Harmonic {
                    F0: f0,
                    drive: Drive::Ratio(r),
                    n_trans: Some(4),
                    n_meas: 4,
                    starts: 1,
                    ..Harmonic::default()
                };
                let req = Request::default();
                let rec = simulate_harmonic(
                    &sys,
                    &SolverSettings::default(),
                    &req,
                    &scene,
                    None,
                    &mut probe,
                );
                assert_eq!(rec.sticks, 0);
                json!({"kind": "harmonic", "F0": f0, "omega": scene.omega(&sys)})
            }
        };
        let rows = &probe.rows;
        assert!(rows.len() > 20, "{} impacts", rows.len());
        let unit_json = |state: &[(f64, f64)]| -> Vec<Value> {
            units
                .iter()
                .zip(state)
                .map(|(u, (y, w))| json!({"m": u.m, "d": u.d, "e": u.e, "y0": y, "w0": w}))
                .collect()
        };
        let specs: Vec<Value> = rows
            .windows(2)
            .map(|pair| {
                let (t, x, v, _, state) = &pair[0];
                json!({"M": sys.M, "K": sys.K, "C": sys.C, "x0": x, "v0": v, "t0": t,
                       "units": unit_json(state), "load": load,
                       "t_end": pair[1].0 + 0.05, "max_impacts": units.len()})
            })
            .collect();
        let out = std::process::Command::new(common::python())
            .arg(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/tests/oracle/units.py"
            ))
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .and_then(|mut child| {
                use std::io::Write;
                child
                    .stdin
                    .take()
                    .unwrap()
                    .write_all(serde_json::to_string(&specs).unwrap().as_bytes())?;
                child.wait_with_output()
            })
            .expect("the oracle runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let results: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
        for (k, (pair, res)) in rows.windows(2).zip(&results).enumerate() {
            let next = &pair[1];
            let hits: Vec<&Value> = res["impacts"].as_array().unwrap().iter().collect();
            let first = hits.first().unwrap_or_else(|| panic!("impact {k}: {res}"));
            let t = first["t"].as_f64().unwrap();
            let what = format!("{:?} impact {}", forcing, k + 1);
            assert!((t - next.0).abs() < 1e-9, "{what}: t {t} vs {}", next.0);
            let same: Vec<(usize, Wall)> = hits
                .iter()
                .filter(|h| h["t"].as_f64() == Some(t))
                .map(|h| {
                    let wall = if h["wall"] == "right" {
                        Wall::Right
                    } else {
                        Wall::Left
                    };
                    (h["unit"].as_u64().unwrap() as usize, wall)
                })
                .collect();
            assert_eq!(same, next.3, "{what}: units and walls");
            let at_t: Vec<&&Value> = hits.iter().filter(|h| h["t"].as_f64() == Some(t)).collect();
            let v_after = at_t.last().unwrap()["v_after"].as_f64().unwrap();
            close(v_after, next.2, 0.0, 1e-9, &format!("{what}: v after"));
            for h in hits.iter().filter(|h| h["t"].as_f64() == Some(t)) {
                let i = h["unit"].as_u64().unwrap() as usize;
                let w = h["w_after"].as_f64().unwrap();
                close(
                    w,
                    next.4[i].1,
                    next.2.abs(),
                    1e-9,
                    &format!("{what}: w{i} after"),
                );
            }
            compared += 1;
        }
    }
    assert!(compared > 100, "{compared} impacts compared");
}

/// A free-decay study sweeps `units` and `d_spread`: its parts carry both columns and read back
/// to the systems that ran, the runs equal `simulate`'s of the same system, and the reduce reads
/// it end to end (a study of one unit has neither column: the golden and schema tests).
#[test]
fn a_study_sweeps_units_and_its_tables_carry_them() {
    use impactsweep::store::{part_files, read_rows};
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("units.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"units\"\nseed = 3\n[system]\ne = 0.7\n[sweep]\nunits = [1, 3, 8]\n\
         d_spread = [0.0, 0.5]\n[perturb]\ndd = [0.001]\n[reliability]\nstrength_mean = 285e6\n\
         strength_sd = 20e6\n",
    )
    .unwrap();
    let run = common::run_study_file(&study, tmp.path(), "units");
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("reduce")
        .arg(&run)
        .assert()
        .success();
    let mut seen = vec![];
    for part in part_files(&run).unwrap() {
        for row in read_rows::<Record>(&part).unwrap() {
            let sys = row.system;
            sys.validate().unwrap();
            let again = simulate(
                &sys,
                &SolverSettings::default(),
                &Request::default(),
                None,
                &mut NoProbe,
            );
            assert_eq!(again.x1.to_bits(), row.record.x1.to_bits(), "{sys:?}");
            assert_eq!(again.impacts, row.record.impacts);
            seen.push((sys.units, sys.d_spread, sys.d));
        }
    }
    assert_eq!(seen.len(), 12);
    for units in [1.0, 3.0, 8.0] {
        for spread in [0.0, 0.5] {
            assert!(
                seen.iter().any(|s| s.0 == units && s.1 == spread),
                "{units} {spread}"
            );
        }
    }
    let report = std::fs::read_to_string(run.join("report.md")).unwrap();
    assert!(report.contains("`units` from 1 to 8"), "{report}");
}

/// The random scene under a Kanai–Tajimi ground motion: `N` identical units in step are one
/// unit of the same mass over the first second, to `1e-12` (beyond it impacts amplify the last
/// bits about a thousandfold a second, as the free scene's do), and spread clearances change the
/// response.
#[test]
fn identical_units_in_step_are_one_unit_under_a_random_ground_motion() {
    use impactsweep::api::realization::RandomSetup;
    let run = |extra: &[&str]| {
        let mut sets: Vec<String> = [
            "scene=random",
            "spectrum=kanai-tajimi",
            "S0=0.05",
            "duration=1",
            "m=0.01",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        sets.extend(extra.iter().map(|s| s.to_string()));
        let setup = RandomSetup::from_sets("random", &sets).unwrap();
        setup.run(None).unwrap().0.record
    };
    let one = run(&[]);
    assert!(one.impacts >= 5, "{}", one.impacts);
    for n in ["2", "3", "8"] {
        let several = run(&[&format!("units={n}")]);
        assert_eq!(several.impacts, one.impacts, "N = {n}");
        close(
            one.amplitude,
            several.amplitude,
            0.0,
            1e-12,
            &format!("N = {n}: amplitude"),
        );
        close(
            one.rms_x,
            several.rms_x,
            0.0,
            1e-12,
            &format!("N = {n}: rms x"),
        );
        close(
            one.energy_impact,
            several.energy_impact,
            0.0,
            1e-11,
            &format!("N = {n}: energy_impact"),
        );
    }
    let spread = run(&["units=3", "d_spread=0.5"]);
    assert_ne!(spread.impacts, one.impacts);
}

/// Regression (found on a seismic study of several units): two units pressed on their right
/// walls while a third impact's impulse moved the main mass off the one stuck there traded
/// impulses of rounding size without end (400,000 impacts in 4e-7 s, the event cap). An impact
/// whose units all close onto the main mass is a plastic joining and keeps the stuck ones.
#[test]
fn units_pressed_on_their_walls_do_not_trade_impulses_without_end() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("s.toml");
    std::fs::write(&study, STUCK_STUDY).unwrap();
    let out = std::process::Command::new(assert_cmd::cargo::cargo_bin("impactsweep"))
        .args(["simulate", "--study"])
        .arg(&study)
        .args(["--point", "30", "--realization", "20"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let row: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(row["record"]["outcome"], "ok", "{row}");
    assert!(row["record"]["impacts"].as_u64().unwrap() < 2_000, "{row}");
}

const STUCK_STUDY: &str = r#"[study]
name = "multi-unit-seismic"
seed = 2026
[system]
M = 1.0
K = 246.7
C = 0.628
e = 0.6
m = 0.1
d = 0.02
[scene]
kind = "random"
input = "base"
spectrum = "clough-penzien"
omega_g = 15.708
zeta_g = 0.6
omega_f = 1.5708
zeta_f = 0.6
S0 = 0.005
duration = 20
envelope = { t1 = 2, t2 = 12, c = 0.3 }
yield_coefficient = 0.25
realizations = 200
intensity = "sa"
design_intensity = 0.2
[sweep]
units = [1, 2, 4, 8]
d_spread = [0.0, 0.5]
im = [0.1, 0.15, 0.2, 0.25, 0.3, 0.4]
"#;
