//! Several damper units (model.md §14, issue 68): checks that can fail.
//!
//! * `N` identical units started together are one unit of the same total mass (each unit
//!   `m / N`, the single unit `m`), in free decay (every solver, with rebounds, chatter and
//!   sticking) and in the harmonic scene, to `1e-12`: the simultaneous impact law makes that an
//!   identity, where impacts taken one after another would break it.
//! * Momentum `M v + sum m_i w_i` is conserved at every impact, to rounding.
//! * Per-unit impact counts add up, and every unit's clearance is the one `d_spread` gives.

use crate::common;
use impactsweep::model::{System, Unit};
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
/// units' flights between impacts: straight lines, or under a ground motion `ground` its exact
/// double integral; these cases do not stick).
/// One impact instant: (t, x, v, units hit in order with their wall, each unit's (y, w) after).
type ImpactRow = (f64, f64, f64, Vec<(usize, Wall)>, Vec<(f64, f64)>);

#[derive(Default)]
struct Impacts {
    rows: Vec<ImpactRow>,
    /// Each unit's last known (t, y, w).
    lines: Vec<(f64, f64, f64)>,
    /// The ground acceleration the units fly under, if any.
    ground: Option<Ground>,
}

/// A ground acceleration linear between samples `a[k]` at `k dt` and 0 after the last, as the
/// record scene and the oracle's `ground` load take it.
#[derive(Clone)]
struct Ground {
    dt: f64,
    a: Vec<f64>,
}

impl Ground {
    /// `(y, w)` at `t1` of a unit free at `(y, w)` at `t0` under `y'' = -a_g(t)`: exact on each
    /// piece between samples.
    fn fly(&self, t0: f64, (mut y, mut w): (f64, f64), t1: f64) -> (f64, f64) {
        let mut t = t0;
        while t < t1 {
            let mut k = (t / self.dt).floor() as usize;
            if (k + 1) as f64 * self.dt <= t {
                // t on a sample that t / dt rounded below.
                k += 1;
            }
            let (a0, slope, end) = if k + 1 < self.a.len() {
                let tk = k as f64 * self.dt;
                let slope = (self.a[k + 1] - self.a[k]) / self.dt;
                (
                    self.a[k] + slope * (t - tk),
                    slope,
                    ((k + 1) as f64 * self.dt).min(t1),
                )
            } else {
                (0.0, 0.0, t1)
            };
            let h = end - t;
            y += w * h - (a0 * h * h / 2.0 + slope * h * h * h / 6.0);
            w -= a0 * h + slope * h * h / 2.0;
            t = end;
        }
        (y, w)
    }
}

impl Probe for Impacts {
    fn impact_of(&mut self, t: f64, unit: usize, wall: Wall, _before: &State, after: &State) {
        self.lines[unit] = (t, after.y, after.w);
        let now: Vec<(f64, f64)> = self
            .lines
            .iter()
            .map(|&(t0, y, w)| match &self.ground {
                None => (y + w * (t - t0), w),
                Some(g) => g.fly(t0, (y, w), t),
            })
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
        compared += against_the_oracle(&sys, &probe.rows, &load, &format!("{forcing:?}"));
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

/// Restarts the oracle from the Rust state after each impact of `rows` (a run of `sys` under
/// `load`, the oracle's load spec) and checks that it predicts the next one: the same instant to
/// `1e-9` s, the same units at the same walls and the same velocities after to `1e-9`
/// relative. Returns the impacts compared.
fn against_the_oracle(
    sys: &System,
    rows: &[ImpactRow],
    load: &serde_json::Value,
    case: &str,
) -> usize {
    use serde_json::{Value, json};
    let units = sys.unit_list();
    let mut compared = 0;
    let (mut worst_t, mut worst_v) = (0.0f64, 0.0f64);
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
        let what = format!("{case} impact {}", k + 1);
        assert!((t - next.0).abs() < 1e-9, "{what}: t {t} vs {}", next.0);
        worst_t = worst_t.max((t - next.0).abs());
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
        worst_v = worst_v.max((v_after - next.2).abs() / next.2.abs().max(f64::MIN_POSITIVE));
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
    eprintln!(
        "{case}: {compared} impacts, worst |dt| {worst_t:e} s, worst v after {worst_v:e} relative"
    );
    compared
}

/// Three different units of a `[[system.unit]]` table (model.md §14): each its own mass,
/// clearance, restitution and initial state.
fn three_units(base: System) -> System {
    base.with_units(&[
        Unit {
            m: 0.004,
            d: 0.006,
            e: 0.9,
            y0: 0.001,
            w0: 0.0,
        },
        Unit {
            m: 0.006,
            d: 0.01,
            e: 0.75,
            y0: 0.0,
            w0: 0.1,
        },
        Unit {
            m: 0.01,
            d: 0.014,
            e: 0.6,
            y0: -0.002,
            w0: -0.1,
        },
    ])
}

/// Issue 68: "An independent reference for three different units: free decay, a harmonic
/// transient and a record, to 1e-9, impacts equal." Three units of a table with different `m`,
/// `d`, `e` and starts; the oracle restarted from the Rust state after each impact predicts the
/// next one ([`against_the_oracle`]) in free decay and under a harmonic force.
#[test]
fn three_different_units_agree_with_the_reference_free_and_harmonic() {
    use serde_json::{Value, json};
    let free = three_units(System::TABLE_I);
    free.validate().unwrap();
    let (m, d, e) = (free.m, free.d, free.e);
    assert_eq!((free.unit_count(), m, d), (3, 0.02, 0.014));
    close(
        e,
        (0.004 * 0.9 + 0.006 * 0.75 + 0.01 * 0.6) / 0.02,
        0.0,
        1e-15,
        "e",
    );
    let mut probe = Impacts {
        lines: free.unit_list().iter().map(|u| (0.0, u.y0, u.w0)).collect(),
        ..Impacts::default()
    };
    let req = Request {
        t_end: Some(1.5),
        ..Request::default()
    };
    let rec = simulate(&free, &SolverSettings::default(), &req, None, &mut probe);
    assert_eq!(rec.sticks, 0);
    assert!(
        rec.unit_impacts.iter().all(|&k| k > 10),
        "{:?}",
        rec.unit_impacts
    );
    let n_free = against_the_oracle(&free, &probe.rows, &Value::Null, "free");

    let forced = three_units(System {
        v0: 0.0,
        ..System::TABLE_I
    });
    let scene = Harmonic {
        F0: 0.5,
        drive: Drive::Ratio(0.9),
        n_trans: Some(8),
        n_meas: 4,
        starts: 1,
        ..Harmonic::default()
    };
    scene.validate(&forced).unwrap();
    let mut probe = Impacts {
        lines: forced
            .unit_list()
            .iter()
            .map(|u| (0.0, u.y0, u.w0))
            .collect(),
        ..Impacts::default()
    };
    let rec = simulate_harmonic(
        &forced,
        &SolverSettings::default(),
        &Request::default(),
        &scene,
        None,
        &mut probe,
    );
    assert_eq!(rec.sticks, 0);
    let load = json!({"kind": "harmonic", "F0": 0.5, "omega": scene.omega(&forced)});
    let n_forced = against_the_oracle(&forced, &probe.rows, &load, "harmonic");
    eprintln!("three units: {n_free} impacts in free decay, {n_forced} under a harmonic force");
    assert!(n_free > 100 && n_forced > 100, "{n_free} {n_forced}");
}

/// The same three units in a record study (`[scene] kind = "record"`, a ground acceleration
/// read from a CSV file, `[[system.unit]]` in the study): the oracle's ground load, linear
/// between the record's samples, predicts every impact of the run from the one before.
#[test]
fn three_different_units_agree_with_the_reference_under_a_record() {
    use impactsweep::plan::Plan;
    use impactsweep::sim::Scene;
    use impactsweep::sim::random::{GivenNormals, simulate_random};
    use impactsweep::study::Study;
    let tmp = tempfile::tempdir().unwrap();
    let dt = 0.005;
    let a: Vec<f64> = (0..=600)
        .map(|k| {
            let t = k as f64 * dt;
            // Near the structure's 10 Hz, so that the units rattle without sticking.
            let v = 3.0 * (2.0 * std::f64::consts::PI * 9.3 * t).sin()
                + 2.0 * (2.0 * std::f64::consts::PI * 11.1 * t + 1.0).sin();
            (v * 1e6).round() / 1e6
        })
        .collect();
    let csv: String = std::iter::once("t,a\n".to_string())
        .chain(
            a.iter()
                .enumerate()
                .map(|(k, v)| format!("{},{v}\n", k as f64 * dt)),
        )
        .collect();
    std::fs::write(tmp.path().join("quake.csv"), csv).unwrap();
    let study = tmp.path().join("three.toml");
    std::fs::write(&study, THREE_UNIT_RECORD_STUDY).unwrap();
    let study = Study::load(&study).unwrap();
    let plan = Plan::new(&study);
    let (sys, scene) = plan.point(0);
    let Scene::Random(scene) = scene else {
        panic!("a record study")
    };
    assert_eq!(
        sys,
        three_units(System {
            x0: 0.0,
            v0: 0.0,
            y0: 0.0,
            w0: 0.0,
            ..System::TABLE_I
        })
    );
    assert_eq!(scene.dt, dt);
    let ground = Ground { dt, a };
    let mut probe = Impacts {
        lines: sys.unit_list().iter().map(|u| (0.0, u.y0, u.w0)).collect(),
        ground: Some(ground.clone()),
        ..Impacts::default()
    };
    let rec = simulate_random(
        &sys,
        &study.solver,
        &study.request,
        &scene,
        GivenNormals::new(&[]),
        &mut probe,
    );
    eprintln!(
        "record: {} impacts, {} sticks, {:?}",
        rec.impacts, rec.sticks, rec.outcome
    );
    assert_eq!(rec.sticks, 0);
    let load = serde_json::json!({"kind": "ground", "dt": dt, "a": ground.a});
    let n = against_the_oracle(&sys, &probe.rows, &load, "record");
    eprintln!("three units under a record: {n} impacts");
    assert!(n > 100, "{n} impacts compared");
}

const THREE_UNIT_RECORD_STUDY: &str = r#"[study]
name = "three-units"
[system]
M = 0.1
K = 400
C = 0.1
[[system.unit]]
m = 0.004
d = 0.006
e = 0.9
y0 = 0.001
[[system.unit]]
m = 0.006
d = 0.01
e = 0.75
w0 = 0.1
[[system.unit]]
m = 0.01
d = 0.014
e = 0.6
y0 = -0.002
w0 = -0.1
[scene]
kind = "record"
record = "quake.csv"
"#;

/// A free-decay study of `[[system.unit]]` tables sweeping `C`: its parts carry the `units`
/// column and the tables in their metadata, the rows read back to the systems that ran (with
/// their tables) and equal `simulate`'s runs bit for bit, and the reduce reads it. A table of
/// one unit is the plain system: the same rows, bit for bit, as the study written with
/// `[system]` keys.
#[test]
fn a_study_of_unit_tables_stores_and_reads_back_its_units() {
    use impactsweep::store::{META_UNITS, part_files, part_metadata, read_rows};
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("tables.toml");
    let tables = "[[system.unit]]\nm = 0.004\nd = 0.006\ne = 0.9\ny0 = 0.001\n\
                  [[system.unit]]\nm = 0.006\nd = 0.01\ne = 0.75\nw0 = 0.1\n\
                  [[system.unit]]\nm = 0.01\nd = 0.014\ne = 0.6\ny0 = -0.002\nw0 = -0.1\n";
    std::fs::write(
        &study,
        format!("[study]\nname = \"tables\"\n[sweep]\nC = [0.1, 0.5, 2.0]\n{tables}"),
    )
    .unwrap();
    let run = common::run_study_file(&study, tmp.path(), "tables");
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("reduce")
        .arg(&run)
        .assert()
        .success();
    let want = three_units(System::TABLE_I);
    let mut seen = 0;
    for part in part_files(&run).unwrap() {
        let meta = part_metadata(&part).unwrap();
        assert!(meta.contains_key(META_UNITS), "{meta:?}");
        for row in read_rows::<Record>(&part).unwrap() {
            let sys = row.system;
            sys.validate().unwrap();
            assert_eq!(sys.table, want.table);
            assert_eq!(
                (sys.units, sys.m, sys.d, sys.e),
                (3.0, want.m, want.d, want.e)
            );
            let again = simulate(
                &sys,
                &SolverSettings::default(),
                &Request::default(),
                None,
                &mut NoProbe,
            );
            assert_eq!(again.x1.to_bits(), row.record.x1.to_bits(), "{sys:?}");
            assert_eq!(again.impacts, row.record.impacts);
            seen += 1;
        }
    }
    assert_eq!(seen, 3);

    // One table is the plain system.
    let one = tmp.path().join("one.toml");
    std::fs::write(
        &one,
        "[study]\nname = \"one\"\n[sweep]\nC = [0.1, 0.5]\n\
         [[system.unit]]\nm = 0.01\nd = 0.014\ne = 0.6\ny0 = -0.002\nw0 = -0.1\n",
    )
    .unwrap();
    let plain = tmp.path().join("plain.toml");
    std::fs::write(
        &plain,
        "[study]\nname = \"plain\"\n[system]\nm = 0.01\nd = 0.014\ne = 0.6\ny0 = -0.002\n\
         w0 = -0.1\n[sweep]\nC = [0.1, 0.5]\n",
    )
    .unwrap();
    let a = common::run_study_file(&one, tmp.path(), "one");
    let b = common::run_study_file(&plain, tmp.path(), "plain");
    let rows = |dir: &std::path::Path| -> Vec<_> {
        part_files(dir)
            .unwrap()
            .iter()
            .flat_map(|p| read_rows::<Record>(p).unwrap())
            // Debug text: the same bits print the same, NaN included.
            .map(|r| format!("{:?} {:?}", r.system, r.record))
            .collect()
    };
    let (ra, rb) = (rows(&a), rows(&b));
    assert_eq!(ra.len(), 2);
    assert_eq!(ra, rb);
    for part in part_files(&a).unwrap() {
        let meta = part_metadata(&part).unwrap();
        assert!(!meta.contains_key(META_UNITS));
    }
}

/// A harmonic study of `[[system.unit]]` tables runs and reduces end to end; its report's
/// "Several units" section does not take the table's different units for one unit (their
/// `d_spread` reads 0).
#[test]
fn a_harmonic_study_of_unit_tables_reduces_and_reports_them() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("h.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"h\"\n[system]\nv0 = 0.0\n\
         [[system.unit]]\nm = 0.004\nd = 0.006\ne = 0.9\n\
         [[system.unit]]\nm = 0.006\nd = 0.01\ne = 0.75\n\
         [[system.unit]]\nm = 0.01\nd = 0.014\ne = 0.6\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.5\nstarts = 1\nlife_max_periods = 2000\n\
         [sweep]\nr = { start = 0.8, stop = 1.2, num = 5 }\n\
         [ranking]\nverify_periods = 0\n",
    )
    .unwrap();
    let run = common::run_study_file(&study, tmp.path(), "h");
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("reduce")
        .arg(&run)
        .assert()
        .success();
    let report = std::fs::read_to_string(run.join("report.md")).unwrap();
    assert!(report.contains("## Several units"), "{report}");
    assert!(report.contains("and they are not one unit"), "{report}");
    assert!(!report.contains("one unit in effect"), "{report}");
}
