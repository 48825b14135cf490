//! The forced (harmonic) scene (issue 12): linear limits, the energy balance on periodic orbits,
//! an independent integrator (SciPy), chatter/sticking at low frequency ratios and grazing
//! orbits, resonance refusal, noise and determinism. Every run is bounded by the solver's caps
//! (never by a timer) and ends with a named outcome.

use crate::common;

use std::path::Path;

use common::python;

use impactsweep::model::System;
use impactsweep::sim::noise::NoiseStream;
use impactsweep::sim::{
    Drive, Harmonic, HarmonicRecord, NoProbe, NoiseSettings, Outcome, Probe, Request,
    SolverSettings, State, Wall, simulate_harmonic,
};
use proptest::prelude::*;

const T1: System = System::TABLE_I;

fn run_with<P: Probe>(sys: &System, h: &Harmonic, probe: &mut P) -> HarmonicRecord {
    h.validate(sys).unwrap();
    simulate_harmonic(
        sys,
        &SolverSettings::default(),
        &Request::default(),
        h,
        None,
        probe,
    )
}

fn run(sys: &System, h: &Harmonic) -> HarmonicRecord {
    run_with(sys, h, &mut NoProbe)
}

fn at_ratio(f0: f64, r: f64) -> Harmonic {
    Harmonic {
        F0: f0,
        drive: Drive::Ratio(r),
        ..Harmonic::default()
    }
}

fn crit() -> f64 {
    2.0 * (T1.K * T1.M).sqrt()
}

/// The linear limit of one case: `amplitude = amplitude_linear` to 1e-9 relative.
fn linear_case(sys: &System, zeta: f64, r: f64) {
    let sys = System {
        C: zeta * crit(),
        ..*sys
    };
    // Slow transients (zeta = 0.001 at r = 5 decays by e^{-0.00126} per period) need a long cap.
    let h = Harmonic {
        n_trans_max: 200_000,
        ..at_ratio(1.0, r)
    };
    let rec = run(&sys, &h);
    assert_eq!(rec.outcome, Outcome::Ok, "zeta={zeta} r={r}: {rec:?}");
    assert!(rec.converged, "zeta={zeta} r={r}: {rec:?}");
    let rel = (rec.amplitude - rec.amplitude_linear).abs() / rec.amplitude_linear;
    assert!(
        rel <= 1e-9,
        "zeta={zeta} r={r} m={} d={}: amplitude {} vs linear {} ({rel:e})",
        sys.m,
        sys.d,
        rec.amplitude,
        rec.amplitude_linear
    );
    assert_eq!(rec.period, 1, "zeta={zeta} r={r}");
    // The textbook formula, independently of the record's own.
    let xst = 1.0 / sys.K;
    let lin = xst / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
    assert!((rec.amplitude_linear - lin).abs() <= 1e-14 * lin);
}

const ZETAS: [f64; 7] = [0.001, 0.01, 0.1, 0.5, 1.0, 1.5, 2.0];
const RATIOS: [f64; 9] = [0.1, 0.3, 0.7, 0.95, 1.0, 1.05, 1.5, 2.5, 5.0];

#[test]
fn no_inner_mass_gives_the_linear_amplitude_over_the_grid() {
    for zeta in ZETAS {
        for r in RATIOS {
            linear_case(&System { m: 0.0, ..T1 }, zeta, r);
        }
    }
}

#[test]
fn an_unreachable_clearance_gives_the_linear_amplitude_over_the_grid() {
    for zeta in ZETAS {
        for r in RATIOS {
            // Steady amplitude at most X_st / (2 zeta) = 1.25 m at zeta = 0.001; transient 3 cm.
            let sys = System { d: 10.0, ..T1 };
            linear_case(&sys, zeta, r);
            let rec = run(
                &System {
                    C: zeta * crit(),
                    ..sys
                },
                &Harmonic {
                    n_trans_max: 200_000,
                    ..at_ratio(1.0, r)
                },
            );
            assert_eq!(rec.impacts, 0, "zeta={zeta} r={r}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]
    #[test]
    fn linear_limit_holds_for_random_damping_and_ratio(
        lz in (0.001f64).log10()..(2.0f64).log10(),
        lr in (0.1f64).log10()..(5.0f64).log10(),
        no_mass in any::<bool>(),
    ) {
        let sys = if no_mass { System { m: 0.0, ..T1 } } else { System { d: 10.0, ..T1 } };
        linear_case(&sys, 10f64.powf(lz), 10f64.powf(lr));
    }
}

/// Periodic orbits of the Table I system (found with `examples/forced_scan.rs`).
const PERIODIC: [(f64, f64, f64); 5] = [
    // (F0, r, d)
    (0.3, 0.98, 0.01),
    (0.3, 0.96, 0.01),
    (1.0, 0.8, 0.01),
    (1.0, 1.08, 0.01),
    (1.0, 1.2, 0.01),
];

#[test]
fn on_periodic_orbits_the_work_of_the_force_equals_the_losses() {
    for (f0, r, d) in PERIODIC {
        let sys = System { d, ..T1 };
        // 24 periods: a multiple of every period up to 4, 6 and 8.
        let h = Harmonic {
            n_meas: 24,
            ..at_ratio(f0, r)
        };
        let rec = run(&sys, &h);
        assert_eq!(rec.outcome, Outcome::Ok);
        assert!(rec.period >= 1 && 24 % rec.period == 0, "{rec:?}");
        assert!(rec.impacts_per_period >= 1.0, "{rec:?}");
        let losses = rec.energy_viscous + rec.energy_impact;
        let rel = (rec.energy_force - losses).abs() / rec.energy_force;
        assert!(
            rel <= 1e-9,
            "F0={f0} r={r}: work {} vs losses {} ({rel:e})",
            rec.energy_force,
            losses
        );
        assert!(rec.energy_impact > 0.0 && rec.energy_viscous > 0.0);
    }
}

/// Energy after every event, to check the balance over a window that is not periodic too.
#[derive(Default)]
struct Energies(Vec<(f64, f64)>);
impl Probe for Energies {
    fn energy(&mut self, t: f64, e: f64) {
        self.0.push((t, e));
    }
}

#[test]
fn the_energy_balance_closes_on_a_chaotic_window() {
    // r = 1.0 with F0 = 1 is not periodic: the balance then includes the change of energy.
    let h = Harmonic {
        n_trans: Some(50),
        n_meas: 10,
        ..at_ratio(1.0, 1.0)
    };
    let mut p = Energies::default();
    let rec = run_with(&T1, &h, &mut p);
    assert_eq!(rec.outcome, Outcome::Ok);
    let tf = std::f64::consts::TAU / rec.omega;
    let at = |t: f64| {
        p.0.iter()
            .rev()
            .find(|(ti, _)| (ti - t).abs() <= 1e-9 * t)
            .map(|(_, e)| *e)
            .unwrap()
    };
    let (e0, e1) = (at(50.0 * tf), at(60.0 * tf));
    let balance = rec.energy_force - rec.energy_viscous - rec.energy_impact - (e1 - e0);
    assert!(
        balance.abs() <= 1e-10 * rec.energy_force,
        "balance {balance:e} of {}",
        rec.energy_force
    );
}

fn scipy(args: &[String]) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/peer_scipy_forced.py");
    let out = std::process::Command::new(python())
        .arg(script)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The period-1 orbit with two impacts per period of the Table I system at F0 = 0.3 N,
/// r = 0.98 (found by `examples/forced_scan.rs` over F0 in {0.1, 0.3, 1} and r in [0.8, 1.2]:
/// at F0 = 0.3 the runs at r = 0.96 and 0.98 converge to period 1 with exactly 2 impacts per
/// period, one on each wall; r = 0.98 has no sticking) agrees with SciPy's DOP853 with wall
/// events and a restart at each impact, from the same initial state over the same 1500 + 20
/// periods. Before the orbit attracts it the transient is chaotic (the two drift apart after
/// ~10 periods), so the test compares orbits, not transients.
#[test]
fn period_one_orbit_with_two_impacts_agrees_with_scipy() {
    let h = Harmonic {
        n_trans: Some(1500),
        n_meas: 20,
        ..at_ratio(0.3, 0.98)
    };
    let rec = run(&T1, &h);
    assert_eq!(rec.outcome, Outcome::Ok);
    assert_eq!(rec.period, 1, "{rec:?}");
    assert_eq!(rec.impacts_per_period, 2.0, "{rec:?}");
    let args: Vec<String> = [
        "--F0",
        "0.3",
        "--r",
        "0.98",
        "--n-trans",
        "1500",
        "--n-meas",
        "20",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let py = scipy(&args);
    assert_eq!(py["outcome"], "ok");
    let amp = py["amplitude"].as_f64().unwrap();
    let rel = (amp - rec.amplitude).abs() / rec.amplitude;
    assert!(rel <= 1e-7, "SciPy {amp} vs {} ({rel:e})", rec.amplitude);
    assert_eq!(py["impacts_per_period"].as_f64().unwrap(), 2.0);
    // The same orbit seen from its own end state: SciPy over 20 periods from where the exact
    // run ended repeats it (the Poincaré section returns after one period).
    let e = rec.end;
    let args: Vec<String> = [
        ("--F0", 0.3),
        ("--r", 0.98),
        ("--x0", e.x),
        ("--v0", e.v),
        ("--y0", e.y),
        ("--w0", e.w),
    ]
    .iter()
    // `--x0=-1e-4`: argparse would take a separate `-1e-4` for an option.
    .map(|(k, v)| format!("{k}={v:e}"))
    .chain(["--n-trans", "0", "--n-meas", "20"].map(String::from))
    .collect();
    let py = scipy(&args);
    let amp = py["amplitude"].as_f64().unwrap();
    assert!((amp - rec.amplitude).abs() <= 1e-7 * rec.amplitude, "{amp}");
    let sections = py["sections"].as_array().unwrap();
    let first: Vec<f64> = sections[0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    for s in sections {
        let s: Vec<f64> = s
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert!((s[0] - first[0]).abs() <= 1e-7 * rec.amplitude, "{s:?}");
    }
}

/// Counts sticking phases and checks the inner mass stays in the cavity.
#[derive(Default)]
struct Watch {
    half_d: f64,
    worst: f64,
    sticks: u64,
    impacts: Vec<(f64, Wall, State)>,
}
impl Probe for Watch {
    fn impact(&mut self, t: f64, w: Wall, before: &State, _after: &State) {
        self.worst = self.worst.max((before.y - before.x).abs() / self.half_d);
        self.impacts.push((t, w, *before));
    }
    fn stick(&mut self, _t: f64, _w: Wall, _s: &State) {
        self.sticks += 1;
    }
    fn sample(&mut self, _t: f64, s: &State) {
        self.worst = self.worst.max((s.y - s.x).abs() / self.half_d);
    }
}

#[test]
fn low_frequency_ratios_chatter_stick_and_finish() {
    // The inner mass rides a wall while the slow force pushes the pair, separates when the
    // contact would have to pull, chatters against the other wall and sticks again.
    for (r, e) in [
        (0.05, 0.45),
        (0.1, 0.45),
        (0.2, 0.7),
        (0.1, 0.0),
        (0.3, 0.9),
    ] {
        let sys = System { e, d: 0.002, ..T1 };
        let h = Harmonic {
            n_meas: 8,
            ..at_ratio(1.0, r)
        };
        let mut w = Watch {
            half_d: sys.d / 2.0,
            ..Watch::default()
        };
        let req = Request {
            trace_dt: Some(1e-3),
            ..Request::default()
        };
        let rec = simulate_harmonic(&sys, &SolverSettings::default(), &req, &h, None, &mut w);
        assert_eq!(rec.outcome, Outcome::Ok, "r={r} e={e}: {rec:?}");
        assert!(rec.sticks >= 1, "r={r} e={e}: {rec:?}");
        assert_eq!(rec.sticks, w.sticks);
        assert!(w.worst <= 1.0 + 1e-9, "r={r} e={e}: |z| = {} d/2", w.worst);
        // Bounded work, not time: at most a few hundred steps per natural period simulated
        // (a forcing period at r = 0.05 holds 20 of them, each with its chatter sequences).
        let natural = rec.t_stop / sys.period();
        assert!(
            rec.steps as f64 <= 300.0 * natural + 10_000.0,
            "r={r} e={e}: {} steps over {natural} natural periods",
            rec.steps
        );
        assert!(rec.amplitude.is_finite() && rec.amplitude > 0.0);
    }
}

/// Table I's linear steady orbit at `F0`, `r`: `x = P cos(omega t) + Q sin(omega t)`, as
/// `[P, Q, omega, A, t]` with its amplitude `A` and the time `t` of its first maximum.
fn linear_steady(f0: f64, r: f64) -> [f64; 5] {
    let w = r * T1.omega();
    let (re, im) = (T1.K - T1.M * w * w, T1.C * w);
    let dd = re * re + im * im;
    let (p, q) = (f0 * re / dd, f0 * im / dd);
    [p, q, w, p.hypot(q), q.atan2(p) / w]
}

/// The main mass on [`linear_steady`]'s orbit (the free part zero, so it moves on it exactly),
/// in a cavity of clearance `d` with the inner mass at rest `eps` beyond where the left wall
/// reaches it at the first maximum of `x`: the run over 20 + 20 periods and the impacts it made.
fn at_the_left_walls_reach(f0: f64, r: f64, d: f64, eps: f64) -> (HarmonicRecord, Watch) {
    let [p, q, w, a, _] = linear_steady(f0, r);
    let sys = System {
        x0: p,
        v0: q * w,
        y0: a - d / 2.0 + eps,
        w0: 0.0,
        d,
        ..T1
    };
    let mut watch = Watch {
        half_d: d / 2.0,
        ..Watch::default()
    };
    let h = Harmonic {
        n_trans: Some(20),
        n_meas: 20,
        ..at_ratio(f0, r)
    };
    let rec = run_with(&sys, &h, &mut watch);
    (rec, watch)
}

/// An orbit that only touches a wall: the main mass on the linear steady orbit
/// `x = P cos(omega t) + Q sin(omega t)` of amplitude `A`, the inner mass at rest at
/// `y0 = A - d/2`, so `z = y0 - x >= -d/2` with equality, at zero relative velocity, exactly at
/// the first maximum of `x`.
#[test]
fn a_grazing_orbit_is_found_and_ends_with_a_named_outcome() {
    let (f0, r) = (1.0, 0.5);
    let [_, _, w, a, t_max] = linear_steady(f0, r);
    let (rec, watch) = at_the_left_walls_reach(f0, r, 0.01, 0.0);
    assert!(Outcome::ALL.contains(&rec.outcome));
    assert_eq!(rec.outcome, Outcome::Ok);
    let (t, wall, before) = watch
        .impacts
        .first()
        .expect("the grazing contact was missed");
    assert_eq!(*wall, Wall::Left);
    assert!(
        (t - t_max).abs() <= 1e-6 / w,
        "contact at {t}, maximum at {t_max}"
    );
    assert!(
        (before.v - before.w).abs() <= 1e-6 * a * w,
        "not grazing: {before:?}"
    );
    assert!(rec.steps <= 100_000, "{} steps", rec.steps);
}

/// Near-grazing contacts on both sides of the tangency. The main mass starts on its steady
/// state (the free part is zero, so it moves as `x = A cos(omega t - phi)` exactly) and the inner
/// mass rests where the left wall reaches it at the first maximum, moved by `eps`: `eps < 0`
/// puts it inside the wall's reach (a contact must come, before the maximum), `eps > 0` just
/// beyond it (no contact ever: the right wall cannot reach it either, `2 A < d`). Offsets from
/// `1e-13 A` to `1e-6 A` on each side (below about `1e-15 A` the gap is the rounding of `x`
/// itself), at three forces and three frequency ratios: a finder that steps over a shallow
/// crossing, or reports a contact that cannot happen, fails here.
#[test]
fn near_grazing_contacts_are_found_on_one_side_and_absent_on_the_other() {
    let d = 0.01;
    let mut cases = 0;
    for f0 in [1.0, 0.3, 0.1] {
        for r in [0.5, 0.8, 1.2] {
            let [_, _, _, a, t_max] = linear_steady(f0, r);
            if 2.0 * a >= d {
                continue;
            }
            for k in 6..=13 {
                for side in [-1.0, 1.0] {
                    let eps = side * a * 10f64.powi(-k);
                    let (rec, watch) = at_the_left_walls_reach(f0, r, d, eps);
                    let case = format!("F0 = {f0}, r = {r}, eps = {eps:e}");
                    assert_eq!(rec.outcome, Outcome::Ok, "{case}");
                    assert!(rec.steps <= 100_000, "{case}: {} steps", rec.steps);
                    let first = watch.impacts.first();
                    if side < 0.0 {
                        let (t, wall, _) =
                            first.unwrap_or_else(|| panic!("{case}: contact missed"));
                        assert_eq!(*wall, Wall::Left, "{case}");
                        assert!(
                            *t <= t_max + 1e-9,
                            "{case}: contact at {t}, maximum {t_max}"
                        );
                    } else {
                        assert!(
                            first.is_none(),
                            "{case}: a contact that cannot be: {first:?}"
                        );
                    }
                    cases += 1;
                }
            }
        }
    }
    assert!(cases >= 80, "{cases} cases");
}

#[test]
fn resonance_without_damping_is_refused_with_the_range() {
    let sys = System { C: 0.0, ..T1 };
    let err = at_ratio(1.0, 1.0).validate(&sys).unwrap_err().to_string();
    assert!(
        err.starts_with("r = 1: resonance without damping: |K - M omega^2 + i C omega| = "),
        "{err}"
    );
    assert!(err.ends_with("move r or give C > 0"), "{err}");
    // The stuck pair's resonance too.
    let r_pair = (T1.M / (T1.M + T1.m)).sqrt();
    let err = at_ratio(1.0, r_pair)
        .validate(&sys)
        .unwrap_err()
        .to_string();
    assert!(err.contains("|K - (M + m) omega^2 + i C omega|"), "{err}");
    // Any damping, or a ratio off resonance, is accepted.
    at_ratio(1.0, 1.0).validate(&T1).unwrap();
    at_ratio(1.0, 1.001).validate(&sys).unwrap();
}

#[test]
fn same_input_same_bits_and_noise_is_seeded() {
    let h = at_ratio(0.3, 0.98);
    let a = run(&T1, &h);
    let b = run(&T1, &h);
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
    let ns = NoiseSettings {
        power: 5e-12,
        sample_time: 1e-4,
    };
    let noisy = |seed: u64| {
        let mut stream = NoiseStream::new(2013, seed, 0);
        simulate_harmonic(
            &T1,
            &SolverSettings::default(),
            &Request::default(),
            &h,
            Some((&ns, &mut stream)),
            &mut NoProbe,
        )
    };
    let (n1, n1b, n2) = (noisy(1), noisy(1), noisy(2));
    assert_eq!(n1.amplitude.to_bits(), n1b.amplitude.to_bits());
    assert_ne!(n1.amplitude.to_bits(), n2.amplitude.to_bits());
    // The noise (sd sqrt(P / Ts) = 2.2e-4 m here, like the orbit itself) moves the sampled
    // maximum by a few standard deviations at most, and the motion underneath is unchanged.
    let sd = (ns.power / ns.sample_time).sqrt();
    assert!((n1.amplitude - a.amplitude).abs() <= 6.0 * sd, "{n1:?}");
    assert_eq!(n1.impacts, a.impacts);
    assert_eq!(n1.period, a.period);
}

fn forced_case() -> impl Strategy<Value = (System, Harmonic)> {
    (
        -1.0..1.0f64,                                       // log10 M
        prop_oneof![Just(f64::NEG_INFINITY), -3.0..0.5f64], // log10 m/M (or no damper)
        1.0..4.0f64,                                        // log10 K
        prop_oneof![Just(0.0), 0.0..2.0f64],                // zeta
        -2.0..1.0f64,                                       // log10 d / X_st
        0.0..=1.0f64,                                       // e
        -1.0..0.7f64,                                       // log10 r
        -1.0..1.0f64,                                       // v0 (m/s)
    )
        .prop_map(|(lm, lr, lk, zeta, ld, e, lrat, v0)| {
            let big_m = 10f64.powf(lm);
            let k = 10f64.powf(lk);
            let sys = System {
                M: big_m,
                m: big_m * 10f64.powf(lr),
                K: k,
                C: 2.0 * zeta * (k * big_m).sqrt(),
                d: 10f64.powf(ld) / k,
                e,
                x0: 0.0,
                v0,
                y0: 0.0,
                w0: 0.0,
                units: 1.0,
                d_spread: 0.0,
                table: None,
            };
            let h = Harmonic {
                n_trans: Some(30),
                n_meas: 5,
                ..at_ratio(1.0, 10f64.powf(lrat))
            };
            (sys, h)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// Wide random systems and forcing: a named outcome, finite observables when `ok`, the inner
    /// mass never through a wall (a missed impact would let it through), the sticking count
    /// the probe saw, and the same bits twice.
    #[test]
    fn any_forced_run_ends_named_inside_the_cavity((sys, h) in forced_case()) {
        prop_assume!(h.validate(&sys).is_ok());
        let mut w = Watch { half_d: sys.d / 2.0, ..Watch::default() };
        let req = Request { trace_dt: Some(sys.period() / 50.0), ..Request::default() };
        let rec = simulate_harmonic(&sys, &SolverSettings::default(), &req, &h, None, &mut w);
        prop_assert!(Outcome::ALL.contains(&rec.outcome));
        prop_assert!(w.worst <= 1.0 + 1e-9, "|z| reached {} d/2: {rec:?}", w.worst);
        prop_assert_eq!(rec.sticks, w.sticks);
        if rec.outcome == Outcome::Ok {
            prop_assert!(rec.amplitude.is_finite() && rec.amplitude >= 0.0, "{rec:?}");
            prop_assert!(rec.impacts_per_period.is_finite() && rec.period <= 8);
            prop_assert!(rec.energy_force.is_finite() && rec.energy_viscous >= 0.0);
            prop_assert!(rec.energy_impact >= -1e-12 * rec.energy_force.abs().max(1e-300));
        }
        let settings = SolverSettings::default();
        let again = simulate_harmonic(&sys, &settings, &req, &h, None, &mut NoProbe);
        prop_assert_eq!(format!("{rec:?}"), format!("{again:?}"));
    }
}

/// Trace samples as `(t, x)`.
#[derive(Default)]
struct Samples(Vec<(f64, f64)>);
impl Probe for Samples {
    fn sample(&mut self, t: f64, s: &State) {
        self.0.push((t, s.x));
    }
    fn impact(&mut self, t: f64, _w: Wall, before: &State, _after: &State) {
        self.0.push((t, before.x));
    }
}

/// `amplitude` is the exact `max |x|` of the window: never below a dense trace's largest sample
/// (impacts included), and above it by no more than the trace's step can hide.
#[test]
fn amplitude_is_the_maximum_of_a_dense_trace_over_the_window() {
    for (f0, r) in [(1.0, 0.8), (1.0, 1.0), (0.3, 0.98), (1.0, 0.3)] {
        let h = Harmonic {
            n_trans: Some(40),
            n_meas: 5,
            ..at_ratio(f0, r)
        };
        let tf = std::f64::consts::TAU / (r * T1.omega());
        let dt = tf / 20_000.0;
        let req = Request {
            trace_dt: Some(dt),
            ..Request::default()
        };
        let mut p = Samples::default();
        let rec = simulate_harmonic(&T1, &SolverSettings::default(), &req, &h, None, &mut p);
        assert_eq!(rec.outcome, Outcome::Ok);
        let (a, b) = (40.0 * tf, 45.0 * tf);
        let sampled =
            p.0.iter()
                .filter(|(t, _)| *t >= a * (1.0 + 1e-12) && *t <= b * (1.0 - 1e-12))
                .map(|(_, x)| x.abs())
                .fold(0.0, f64::max);
        assert!(
            rec.amplitude >= sampled * (1.0 - 1e-14),
            "F0={f0} r={r}: {} below the sampled {sampled}",
            rec.amplitude
        );
        // Impact kinks are rows of the trace, so the maximum the samples can miss is a smooth
        // top, below the nearest sample by at most |x''| dt^2 / 2 (|x''| a few A Omega^2).
        let omega = (r * T1.omega()).max(T1.omega());
        let slack = 4.0 * rec.amplitude * (omega * dt).powi(2);
        assert!(
            rec.amplitude - sampled <= slack,
            "F0={f0} r={r}: {} vs sampled {sampled}",
            rec.amplitude
        );
    }
}

/// Issue 22, item 5: a long window gives an amplitude. At the showcase's chaotic point (m = 20 g,
/// d = 20 mm, r = 1.01) a window of 200,000 forcing periods (about 216,000 impacts) ends `ok`:
/// the harmonic scene's caps on impacts and steps scale with the periods the run may take.
#[test]
fn issue_22_a_window_of_200000_periods_gives_an_amplitude() {
    let sys = System {
        m: 0.02,
        d: 0.02,
        e: 0.9,
        C: 0.1,
        x0: 0.0,
        v0: 0.0,
        ..System::TABLE_I
    };
    let scene = Harmonic {
        F0: 0.1,
        drive: Drive::Ratio(1.01),
        n_meas: 200_000,
        ..Harmonic::default()
    };
    let rec = simulate_harmonic(
        &sys,
        &SolverSettings::default(),
        &Request::default(),
        &scene,
        None,
        &mut NoProbe,
    );
    assert_eq!(rec.outcome, Outcome::Ok, "{rec:?}");
    assert!(
        rec.impacts > SolverSettings::default().max_impacts,
        "{}",
        rec.impacts
    );
    // The issue's brute force: 0.95 cm over 200,000 periods.
    assert!(
        (0.0085..0.0100).contains(&rec.amplitude),
        "{}",
        rec.amplitude
    );
}
