//! The integrating solvers (`rk4`, `dopri5`) against `exact` (issue 5, item 5): measured order,
//! tolerance, impact counts and the extremes table. No test here is timed: every run is bounded
//! by the step and impact caps, and an exhausted cap is a named outcome the tests inspect.

use impactsweep::model::System;
use impactsweep::sim::{
    NoProbe, Outcome, Probe, Record, Request, SolverKind, SolverSettings, State, Wall, simulate,
};

fn run(sys: &System, s: &SolverSettings) -> Record {
    simulate(sys, s, &Request::default(), None, &mut NoProbe)
}

fn exact(sys: &System) -> Record {
    run(
        sys,
        &SolverSettings {
            tol: 1e-15,
            ..SolverSettings::default()
        },
    )
}

fn rk4(h: f64) -> SolverSettings {
    SolverSettings {
        kind: SolverKind::Rk4,
        h,
        tol: 1e-15,
        ..SolverSettings::default()
    }
}

fn dopri5(rtol: f64, atol: f64) -> SolverSettings {
    SolverSettings {
        kind: SolverKind::Dopri5,
        rtol,
        atol,
        tol: 1e-15,
        ..SolverSettings::default()
    }
}

/// Relative errors of the observables the tradeoff reports, in one number: the largest of the
/// errors in X1, X2, t1, t2.
fn error(got: &Record, truth: &Record) -> f64 {
    assert_eq!(got.outcome, truth.outcome);
    [
        (got.x1, truth.x1),
        (got.x2, truth.x2),
        (got.t1, truth.t1),
        (got.t2, truth.t2),
    ]
    .iter()
    .map(|(a, b)| ((a - b) / b).abs())
    .fold(0.0, f64::max)
}

/// log2 of successive error ratios when h halves.
fn orders(sys: &System, divs: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let truth = exact(sys);
    let errs: Vec<f64> = divs
        .iter()
        .map(|n| error(&run(sys, &rk4(sys.period() / n)), &truth))
        .collect();
    let orders = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    (errs, orders)
}

#[test]
fn rk4_is_fourth_order_without_impacts() {
    // A clearance far wider than the motion: no impact, the smooth linear oscillator.
    let sys = System {
        d: 1e3,
        ..System::TABLE_I
    };
    let (errs, orders) = orders(&sys, &[50.0, 100.0, 200.0, 400.0]);
    assert!(
        errs[0] > 1e-9,
        "the coarsest step must show an error: {errs:?}"
    );
    for p in &orders {
        assert!(
            (3.5..=4.5).contains(p),
            "orders {orders:?}, errors {errs:?}"
        );
    }
}

#[test]
fn rk4_converges_with_impacts() {
    // Table I at e = 0.9: 14 impacts before the second peak; the same impacts at every step.
    let sys = System::TABLE_I;
    let truth = exact(&sys);
    for n in [100.0, 200.0, 400.0, 800.0] {
        assert_eq!(run(&sys, &rk4(sys.period() / n)).impacts, truth.impacts);
    }
    let (errs, orders) = orders(&sys, &[100.0, 200.0, 400.0, 800.0]);
    // Each impact restarts the step grid, so the order shows only on average; it must still be
    // clearly fourth-ish and the error must fall by three orders of magnitude over the ladder.
    let mean = orders.iter().sum::<f64>() / orders.len() as f64;
    assert!(mean > 3.3, "orders {orders:?}, errors {errs:?}");
    assert!(errs[3] < errs[0] * 1e-3, "errors {errs:?}");
}

#[test]
fn dopri5_meets_its_tolerance_on_the_linear_oscillator() {
    let sys = System {
        d: 1e3,
        ..System::TABLE_I
    };
    let truth = exact(&sys);
    let amp = sys.v0 / sys.omega();
    for rtol in [1e-5, 1e-7, 1e-9, 1e-11] {
        let got = run(&sys, &dopri5(rtol, rtol * amp));
        let err = error(&got, &truth);
        // Local error per step is held under rtol; over the ~30-400 steps of two periods the
        // global error stays within a small multiple of it.
        assert!(err <= 10.0 * rtol, "rtol {rtol}: error {err:e}");
        assert!(
            err > 1e-4 * rtol,
            "rtol {rtol}: suspiciously exact ({err:e})"
        );
    }
}

#[test]
fn every_solver_agrees_with_exact_on_impacts_at_its_finest_setting() {
    let truth = exact(&System::TABLE_I);
    assert_eq!(truth.impacts, 14);
    let period = System::TABLE_I.period();
    let amp = System::TABLE_I.v0 / System::TABLE_I.omega();
    for s in [
        SolverSettings::default(),
        rk4(period / 6400.0),
        dopri5(1e-11, 1e-11 * amp),
    ] {
        let got = run(&System::TABLE_I, &s);
        assert_eq!(got.outcome, Outcome::Ok, "{:?}", s.kind);
        assert_eq!(got.impacts, truth.impacts, "{:?}", s.kind);
        assert_eq!(got.sticks, truth.sticks, "{:?}", s.kind);
        assert!(
            error(&got, &truth) < 1e-9,
            "{:?}: {}",
            s.kind,
            error(&got, &truth)
        );
    }
}

#[test]
fn every_solver_agrees_on_impacts_over_the_paper_sweep() {
    // The whole e = 0.45..0.95 set, chatter and sticking included.
    let period = System::TABLE_I.period();
    let amp = System::TABLE_I.v0 / System::TABLE_I.omega();
    for i in 0..=50 {
        let sys = System {
            e: 0.45 + 0.01 * i as f64,
            ..System::TABLE_I
        };
        let truth = exact(&sys);
        for s in [rk4(period / 1600.0), dopri5(1e-10, 1e-10 * amp)] {
            let got = run(&sys, &s);
            assert_eq!(
                (got.outcome, got.impacts, got.sticks),
                (truth.outcome, truth.impacts, truth.sticks),
                "e = {}, {:?}",
                sys.e,
                s.kind
            );
        }
    }
}

/// The extremes table of the simulator issue, as variations of Table I.
fn extremes() -> Vec<(&'static str, System)> {
    let t = System::TABLE_I;
    let crit = 2.0 * (t.K * t.M).sqrt();
    vec![
        ("e = 0", System { e: 0.0, ..t }),
        ("e = 1e-9", System { e: 1e-9, ..t }),
        ("e = 0.45 (Table I chatter)", System { e: 0.45, ..t }),
        ("e = 1", System { e: 1.0, ..t }),
        ("d = 1e-9", System { d: 1e-9, ..t }),
        ("d = 1e3", System { d: 1e3, ..t }),
        ("m/M = 1e-9", System { m: 1e-9 * t.M, ..t }),
        (
            "m/M = 100",
            System {
                m: 100.0 * t.M,
                ..t
            },
        ),
        ("C = 0", System { C: 0.0, ..t }),
        (
            "C = crit (1 - 1e-12)",
            System {
                C: crit * (1.0 - 1e-12),
                ..t
            },
        ),
        (
            "C = crit (1 + 1e-12)",
            System {
                C: crit * (1.0 + 1e-12),
                ..t
            },
        ),
        (
            "C = 50 crit",
            System {
                C: 50.0 * crit,
                ..t
            },
        ),
        ("v0 = 0", System { v0: 0.0, ..t }),
        // Amplitude exactly d/2: the left wall is touched at the first peak.
        ("grazing", near_grazing(1.0)),
    ]
}

/// Undamped, inner mass at rest in the middle of the cavity: the left wall is reached when
/// `x = d/2`, and the amplitude is `v0 / omega`.
fn near_grazing(amplitude_over_half_d: f64) -> System {
    let t = System::TABLE_I;
    System {
        C: 0.0,
        v0: t.omega() * 0.5 * t.d * amplitude_over_half_d,
        ..t
    }
}

/// Records the time of the first impact.
#[derive(Default)]
struct FirstImpact(Option<f64>);

impl Probe for FirstImpact {
    fn impact(&mut self, t: f64, _wall: Wall, _before: &State, _after: &State) {
        self.0.get_or_insert(t);
    }
}

fn first_impact(sys: &System, s: &SolverSettings) -> (Record, Option<f64>) {
    let mut probe = FirstImpact::default();
    let rec = simulate(sys, s, &Request::default(), None, &mut probe);
    (rec, probe.0)
}

#[test]
fn a_dip_shorter_than_one_step_is_not_missed() {
    // rk4 at its default step (1e-4 s) with the amplitude 1e-6 above d/2: the gap dips 2.5 nm
    // below zero for 2 sqrt(2 * 2.5e-9 / (omega^2 d / 2)) = 3.2e-5 s, a third of a step.
    // dopri5 at its default rtol (steps of about T/20 = 5e-3 s here) with 1e-3 above: a dip of
    // 1.4e-3 s, a quarter of a step. The step's end values alone would usually miss either dip;
    // the interpolant's extremum does not.
    for (kind, margin) in [(SolverKind::Rk4, 1e-6), (SolverKind::Dopri5, 1e-3)] {
        let s = SolverSettings {
            kind,
            ..SolverSettings::default()
        };
        let sys = near_grazing(1.0 + margin);
        let (truth, t_truth) = first_impact(&sys, &SolverSettings::default());
        let (got, t_got) = first_impact(&sys, &s);
        assert!(truth.impacts >= 1);
        assert_eq!(got.impacts, truth.impacts, "{kind:?}");
        let (a, b) = (t_got.unwrap(), t_truth.unwrap());
        assert!(
            (a - b).abs() < 1e-3 * b,
            "{kind:?}: first impact at {a} vs {b}"
        );
        // Just as far below: no contact for anyone.
        let clear = near_grazing(1.0 - margin);
        assert_eq!(run(&clear, &SolverSettings::default()).impacts, 0);
        assert_eq!(run(&clear, &s).impacts, 0, "{kind:?}");
    }
}

#[test]
fn every_solver_passes_the_extremes_table() {
    let caps = SolverSettings {
        max_steps: 2_000_000,
        max_impacts: 100_000,
        ..SolverSettings::default()
    };
    let solvers = [
        SolverSettings { ..caps },
        SolverSettings {
            kind: SolverKind::Rk4,
            ..caps
        },
        SolverSettings {
            kind: SolverKind::Dopri5,
            ..caps
        },
    ];
    for (name, sys) in extremes() {
        sys.validate().unwrap();
        let truth = run(&sys, &caps);
        for s in &solvers {
            let r = run(&sys, s);
            let what = format!("{name}, {:?}: {r:?}", s.kind);
            assert!(Outcome::ALL.contains(&r.outcome), "{what}");
            assert!(r.t_stop.is_finite() && r.t_stop >= 0.0, "{what}");
            assert!(
                r.energy_impact.is_finite() && r.energy_viscous.is_finite(),
                "{what}"
            );
            for (x, t) in &r.peaks {
                assert!(x.is_finite() && t.is_finite(), "{what}");
            }
            if r.outcome == Outcome::Ok {
                for v in [r.x1, r.t1, r.x2, r.t2, r.xmax, r.di] {
                    assert!(v.is_finite(), "{what}");
                }
            }
            // Same named outcome as exact, except where the answer rests on a touch that
            // rounding decides (grazing).
            if name != "grazing" {
                assert_eq!(r.outcome, truth.outcome, "{what}");
            }
        }
    }
}

// ---- the commands -------------------------------------------------------------------------

use assert_cmd::Command;
use predicates::prelude::*;

#[test]
fn simulate_takes_the_solver_and_its_knobs() {
    let out = Command::cargo_bin("impactsweep")
        .unwrap()
        .args([
            "simulate",
            "--json",
            "--set",
            "solver=rk4",
            "--set",
            "h=1e-4",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["solver"]["kind"], "rk4");
    assert_eq!(v["solver"]["h"], 1e-4);
    assert_eq!(v["impacts"], 14);
    let truth = exact(&System::TABLE_I);
    let di = v["di"].as_f64().unwrap();
    assert!(((di - truth.di) / truth.di).abs() < 1e-6, "{di}");

    let out = Command::cargo_bin("impactsweep")
        .unwrap()
        .args(["simulate", "--json", "--set", "solver=dopri5"])
        .args(["--set", "rtol=1e-9", "--set", "atol=1e-12"])
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["solver"]["kind"], "dopri5");
    assert_eq!(v["solver"]["rtol"], 1e-9);
    assert_eq!(v["impacts"], 14);
}

#[test]
fn solver_knobs_out_of_range_are_refused_by_name() {
    for (set, msg) in [
        ("h=0", "--set h = 0: must be in [1e-9, 1]"),
        ("rtol=1", "--set rtol = 1: must be in [1e-14, 0.1]"),
        ("atol=-1", "--set atol = -1: must be in [1e-18, 0.1]"),
        (
            "solver=euler",
            "--set solver=euler: unknown solver; allowed: exact, rk4, dopri5",
        ),
    ] {
        Command::cargo_bin("impactsweep")
            .unwrap()
            .args(["simulate", "--set", set])
            .assert()
            .code(2)
            .stderr(predicate::str::contains(msg));
    }
}

#[test]
fn tradeoff_quick_writes_its_table_chart_and_parquet_and_merges_a_peer() {
    let dir = tempfile::tempdir().unwrap();
    // A peer that reproduces exact's values, with one run stopped by its chatter guard.
    let runs: Vec<serde_json::Value> = (0..=50)
        .map(|i| {
            let sys = System {
                e: 0.45 + 0.01 * i as f64,
                ..System::TABLE_I
            };
            let r = exact(&sys);
            if i == 0 {
                serde_json::json!({"e": sys.e, "outcome": "chatter", "xmax": null, "t1": null,
                                   "di": null, "impacts": 1000})
            } else {
                serde_json::json!({"e": sys.e, "outcome": "ok", "xmax": r.xmax, "t1": r.t1,
                                   "di": r.di, "impacts": r.impacts})
            }
        })
        .collect();
    let peer = serde_json::json!({"tool": "scipy", "version": "test", "methods": [{
        "method": "DOP853", "rtol": 1e-10, "atol": 1e-12, "time_per_run_s": 1e-3,
        "cpu_per_run_s": 1e-3, "reps": 1, "runs": runs}]});
    std::fs::write(dir.path().join("peer_scipy.json"), peer.to_string()).unwrap();
    let out = Command::cargo_bin("impactsweep")
        .unwrap()
        .args(["tradeoff", "--quick", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success(), "{text}");
    for needle in [
        "| exact | tol = 1e-12 |",
        "| rk4 | h = T/800 |",
        "| dopri5 | rtol = 1e-9 |",
        "| scipy-DOP853 | rtol = 1e-10 |",
        "1 (1 unfinished)",
        "Cheapest exact with DI error under 0.1 %",
        "Cheapest rk4 with DI error under 0.1 %",
        "Cheapest dopri5 with DI error under 0.1 %",
    ] {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
    for f in [
        "tradeoff.parquet",
        "tradeoff.md",
        "tradeoff.svg",
        "tradeoff.png",
    ] {
        let meta = std::fs::metadata(dir.path().join(f)).unwrap();
        assert!(meta.len() > 500, "{f}");
    }
    let svg = std::fs::read_to_string(dir.path().join("tradeoff.svg")).unwrap();
    for name in ["exact", "rk4", "dopri5", "scipy-DOP853"] {
        assert!(svg.contains(name), "{name} not in the chart's legend");
    }
}

#[test]
fn quote_measures_a_setting_against_exact() {
    use impactsweep::accuracy::quote;
    let fine = quote(&rk4(System::TABLE_I.period() / 800.0));
    let coarse = quote(&rk4(System::TABLE_I.period() / 50.0));
    assert_eq!(fine.runs, 11);
    assert!(fine.time_per_run > 0.0 && fine.cpu_per_run > 0.0);
    assert!(fine.di_err < 1e-8, "{fine}");
    assert!(coarse.di_err > 100.0 * fine.di_err, "{coarse} vs {fine}");
    assert_eq!(fine.changed_impacts, 0);
}

/// Collects trace samples `(t, x)`.
#[derive(Default)]
struct Samples(Vec<(f64, f64)>);

impl Probe for Samples {
    fn sample(&mut self, t: f64, s: &State) {
        self.0.push((t, s.x));
    }
}

#[test]
fn issue_5_a_maximum_after_an_impact_that_reverses_v_is_found() {
    // At e = 0.80..0.83 the first maximum is followed, inside the same positive half-cycle, by
    // an impact that turns the main mass upward again and a second, higher maximum. Found by the
    // SciPy peer: the driver kept the stale sign of v and never watched the second maximum.
    // X1 must be at least every sampled x of the first positive half-cycle.
    let amp = System::TABLE_I.v0 / System::TABLE_I.omega();
    for e in [0.80, 0.81, 0.82, 0.83] {
        let sys = System {
            e,
            ..System::TABLE_I
        };
        for s in [
            SolverSettings::default(),
            rk4(sys.period() / 1600.0),
            dopri5(1e-10, 1e-10 * amp),
        ] {
            let mut probe = Samples::default();
            let req = Request {
                trace_dt: Some(1e-5),
                ..Request::default()
            };
            let r = simulate(&sys, &s, &req, None, &mut probe);
            let first_zero = probe
                .0
                .iter()
                .find(|(t, x)| *t > 0.0 && *x < 0.0)
                .map(|p| p.0)
                .unwrap();
            let sampled = probe
                .0
                .iter()
                .filter(|(t, _)| *t < first_zero)
                .map(|p| p.1)
                .fold(f64::MIN, f64::max);
            assert!(
                r.x1 >= sampled - 1e-12 && r.x1 - sampled < 1e-6,
                "e = {e}, {:?}: X1 = {} but x reached {sampled}",
                s.kind,
                r.x1
            );
        }
    }
}

#[test]
fn noisy_runs_agree_across_solvers() {
    // With noise the peaks are the largest noisy samples in each positive half-cycle; the
    // samples fall at fixed times k Ts, so every accurate solver sees the same noise at the
    // same instants and must pick the same samples.
    use impactsweep::sim::NoiseSettings;
    use impactsweep::sim::noise::NoiseStream;
    let ns = NoiseSettings {
        power: 5e-12,
        sample_time: 1e-3,
    };
    let period = System::TABLE_I.period();
    let amp = System::TABLE_I.v0 / System::TABLE_I.omega();
    for e in [0.45, 0.9] {
        let sys = System {
            e,
            ..System::TABLE_I
        };
        let noisy = |s: &SolverSettings| {
            let mut stream = NoiseStream::new(7, 3, 0);
            simulate(
                &sys,
                s,
                &Request::default(),
                Some((&ns, &mut stream)),
                &mut NoProbe,
            )
        };
        let truth = noisy(&SolverSettings::default());
        assert_eq!(truth.outcome, Outcome::Ok);
        for s in [rk4(period / 800.0), dopri5(1e-10, 1e-10 * amp)] {
            let got = noisy(&s);
            assert_eq!(got.outcome, truth.outcome, "e = {e}, {:?}", s.kind);
            assert_eq!(got.impacts, truth.impacts, "e = {e}, {:?}", s.kind);
            assert_eq!(got.t1, truth.t1, "e = {e}, {:?}: same sample", s.kind);
            assert!(
                (got.xmax - truth.xmax).abs() < 1e-10,
                "e = {e}, {:?}",
                s.kind
            );
        }
    }
}
