//! The exact simulator against closed forms, invariants and an independent integrator
//! (issue 2, "tests that can fail"), plus the extremes table: one test per row, each bounded by
//! the solver's caps (never by a timer) and required to end with a named outcome.

use impactsweep::model::System;
use impactsweep::sim::{
    NoProbe, Outcome, Probe, Record, Request, SolverSettings, State, Wall, simulate,
};

fn run(sys: &System) -> Record {
    simulate(
        sys,
        &SolverSettings::default(),
        &Request::default(),
        None,
        &mut NoProbe,
    )
}

fn run_with<P: Probe>(sys: &System, req: &Request, probe: &mut P) -> Record {
    simulate(sys, &SolverSettings::default(), req, None, probe)
}

/// First positive peak of the free linear oscillator from x0 = 0, v0 > 0, in closed form:
/// x = (v0 / wd) e^{-a t} sin(wd t), maximal where tan(wd t) = wd / a.
fn linear_first_peak(sys: &System) -> (f64, f64) {
    let a = sys.C / (2.0 * sys.M);
    let wd = (sys.K / sys.M - a * a).sqrt();
    let t = wd.atan2(a) / wd;
    (sys.v0 / wd * (-a * t).exp() * (wd * t).sin(), t)
}

#[test]
fn no_damper_gives_the_linear_oscillator_peak() {
    let sys = System {
        m: 0.0,
        ..System::TABLE_I
    };
    let rec = run(&sys);
    assert_eq!(rec.outcome, Outcome::Ok);
    let (x, t) = linear_first_peak(&sys);
    assert!((rec.x1 - x).abs() <= 1e-12 * x, "{} vs {x}", rec.x1);
    assert!((rec.t1 - t).abs() <= 1e-9 * t, "{} vs {t}", rec.t1);
    assert_eq!(rec.energy_impact, 0.0);
}

#[test]
fn unreachable_clearance_gives_the_linear_oscillator_peak() {
    let sys = System {
        d: 1.0,
        ..System::TABLE_I
    };
    let rec = run(&sys);
    assert_eq!(rec.outcome, Outcome::Ok);
    assert_eq!(rec.impacts, 0);
    let (x, _) = linear_first_peak(&sys);
    assert!((rec.x1 - x).abs() <= 1e-12 * x);
    // The second peak is one damped period later, smaller by exp(-a Td).
    let a = sys.C / (2.0 * sys.M);
    let td = std::f64::consts::TAU / (sys.K / sys.M - a * a).sqrt();
    assert!((rec.x2 - x * (-a * td).exp()).abs() <= 1e-12 * x);
    assert!((rec.t2 - rec.t1 - td).abs() <= 1e-9 * td);
}

/// Records every event's energy and checks momentum at every impact.
#[derive(Default)]
struct Audit {
    sys: Option<System>,
    energies: Vec<f64>,
    impacts: Vec<(f64, Wall, State, State)>,
    worst_momentum: f64,
}

impl Probe for Audit {
    fn impact(&mut self, t: f64, wall: Wall, before: &State, after: &State) {
        let s = self.sys.unwrap();
        let p0 = s.M * before.v + s.m * before.w;
        let p1 = s.M * after.v + s.m * after.w;
        let scale = s.M * before.v.abs() + s.m * before.w.abs();
        if scale > 0.0 {
            self.worst_momentum = self.worst_momentum.max((p1 - p0).abs() / scale);
        }
        self.impacts.push((t, wall, *before, *after));
    }
    fn energy(&mut self, _t: f64, e: f64) {
        self.energies.push(e);
    }
}

#[test]
fn elastic_undamped_impacts_conserve_energy_over_200_impacts() {
    let sys = System {
        e: 1.0,
        C: 0.0,
        ..System::TABLE_I
    };
    let req = Request {
        t_end: Some(1.0),
        ..Request::default()
    };
    let mut audit = Audit {
        sys: Some(sys),
        ..Audit::default()
    };
    let rec = run_with(&sys, &req, &mut audit);
    assert!(rec.impacts >= 200, "only {} impacts", rec.impacts);
    let e0 = sys.energy(sys.x0, sys.v0, sys.w0);
    for e in &audit.energies {
        assert!(
            (e - e0).abs() <= 1e-12 * e0,
            "energy drifted to {e} from {e0}"
        );
    }
    assert!(rec.energy_impact <= 1e-12 * e0);
    assert!(rec.energy_viscous <= 1e-12 * e0);
}

#[test]
fn momentum_is_conserved_at_every_impact() {
    for e in [0.0, 0.45, 0.74, 0.9, 1.0] {
        let sys = System {
            e,
            ..System::TABLE_I
        };
        let mut audit = Audit {
            sys: Some(sys),
            ..Audit::default()
        };
        let rec = run_with(&sys, &Request::default(), &mut audit);
        assert!(rec.impacts > 0);
        assert!(
            audit.worst_momentum <= 1e-15,
            "e={e}: {}",
            audit.worst_momentum
        );
    }
}

#[test]
fn energy_balance_closes() {
    for e in [0.0, 0.45, 0.9] {
        let sys = System {
            e,
            ..System::TABLE_I
        };
        let mut audit = Audit {
            sys: Some(sys),
            ..Audit::default()
        };
        let rec = run_with(&sys, &Request::default(), &mut audit);
        let e0 = sys.energy(sys.x0, sys.v0, sys.w0);
        let last = *audit.energies.last().unwrap();
        let lost = rec.energy_impact + rec.energy_viscous;
        assert!((e0 - last - lost).abs() <= 1e-12 * e0, "e={e}");
        assert!(
            audit
                .energies
                .windows(2)
                .all(|w| w[1] <= w[0] * (1.0 + 1e-14))
        );
    }
}

/// Every trace sample and impact row keeps the inner mass inside the cavity.
#[derive(Default)]
struct Walls {
    half_d: f64,
    worst: f64,
    rows: usize,
}

impl Probe for Walls {
    fn sample(&mut self, _t: f64, s: &State) {
        self.rows += 1;
        self.worst = self.worst.max((s.y - s.x).abs() / self.half_d);
    }
    fn impact(&mut self, t: f64, w: Wall, before: &State, _after: &State) {
        self.sample(t, before);
        let _ = w;
    }
}

#[test]
fn inner_mass_never_leaves_the_cavity() {
    for e in [0.0, 0.45, 0.74, 0.9, 1.0] {
        let sys = System {
            e,
            ..System::TABLE_I
        };
        let req = Request {
            t_end: Some(1.0),
            trace_dt: Some(1e-5),
            ..Request::default()
        };
        let mut w = Walls {
            half_d: sys.d / 2.0,
            ..Walls::default()
        };
        run_with(&sys, &req, &mut w);
        assert!(w.rows > 100_000);
        assert!(
            w.worst <= 1.0 + 1e-12,
            "e={e}: |y-x| reached {} d/2",
            w.worst
        );
    }
}

#[test]
fn table_i_first_peak_and_di_stay_in_the_independent_band() {
    // model.md §7: for the noise-free Table I system, X1 in [2.7, 3.0] cm and DI in
    // [0.01, 0.04] m/s for every e in [0.45, 0.95].
    for i in 0..=50 {
        let e = 0.45 + i as f64 * 0.01;
        let rec = run(&System {
            e,
            ..System::TABLE_I
        });
        assert_eq!(rec.outcome, Outcome::Ok, "e={e}");
        assert!(
            (0.027..=0.030).contains(&rec.x1),
            "e={e}: X1 = {} cm",
            rec.x1 * 100.0
        );
        assert!((0.01..=0.04).contains(&rec.di), "e={e}: DI = {}", rec.di);
        assert_eq!(rec.xmax, rec.x1.max(rec.x2));
    }
}

#[test]
fn first_peak_has_a_kink_near_e_074() {
    // model.md §7: a non-smooth change of the first peak near e = 0.74. X1 rises with e up to
    // there and falls after it, and its second difference there is far above the typical one.
    let x1: Vec<f64> = (0..=50)
        .map(|i| {
            run(&System {
                e: 0.45 + i as f64 * 0.01,
                ..System::TABLE_I
            })
            .x1
        })
        .collect();
    let d2: Vec<f64> = x1
        .windows(3)
        .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs())
        .collect();
    let mut sorted = d2.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let kinks: Vec<f64> = (0..d2.len())
        .filter(|&i| d2[i] > 10.0 * median && x1[i + 1] > x1[i] && x1[i + 1] > x1[i + 2])
        .map(|i| 0.45 + (i + 1) as f64 * 0.01)
        .collect();
    assert!(
        kinks.iter().any(|e| (0.72..=0.77).contains(e)),
        "kinks (local maxima of X1) at {kinks:?}"
    );
}

/// RK4 with step `h` on the free main mass (independent of the closed form).
fn rk4_x(sys: &System, t: f64, h: f64) -> (f64, f64) {
    let f = |x: f64, v: f64| (v, -(sys.C * v + sys.K * x) / sys.M);
    let (mut x, mut v) = (sys.x0, sys.v0);
    let n = (t / h).ceil() as usize;
    let h = t / n as f64;
    for _ in 0..n {
        let (a1, b1) = f(x, v);
        let (a2, b2) = f(x + 0.5 * h * a1, v + 0.5 * h * b1);
        let (a3, b3) = f(x + 0.5 * h * a2, v + 0.5 * h * b2);
        let (a4, b4) = f(x + h * a3, v + h * b3);
        x += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        v += h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4);
    }
    (x, v)
}

#[test]
fn first_impact_time_matches_an_independent_integrator_and_the_gap_function() {
    // Before the first impact the inner mass rests (y = 0) and the gap is d/2 - |x|. Find where
    // the RK4 solution (steps halved until converged) reaches it by bisection, and compare.
    let sys = System::TABLE_I;
    let mut audit = Audit {
        sys: Some(sys),
        ..Audit::default()
    };
    run_with(&sys, &Request::default(), &mut audit);
    let (t_imp, wall, before, _) = audit.impacts[0];
    assert_eq!(
        wall,
        Wall::Left,
        "the main mass moves right first, so z = -x hits -d/2"
    );
    // Gap function at the located time: within tolerance of the wall.
    assert!(((before.y - before.x) + sys.d / 2.0).abs() <= 1e-15);
    let gap = |t: f64, h: f64| sys.d / 2.0 - rk4_x(&sys, t, h).0;
    let (mut lo, mut hi) = (0.0, t_imp * 1.5);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if gap(mid, 1e-6) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    assert!((lo - t_imp).abs() <= 1e-10, "RK4 root {lo} vs {t_imp}");
}

#[test]
fn impacts_sit_on_the_walls() {
    for e in [0.45, 0.9] {
        let sys = System {
            e,
            ..System::TABLE_I
        };
        let mut audit = Audit {
            sys: Some(sys),
            ..Audit::default()
        };
        run_with(&sys, &Request::default(), &mut audit);
        // Located within tol * period: the gap left is at most |relative velocity| times that.
        let tol_t = SolverSettings::default().tol * sys.period();
        for (_, wall, before, _) in &audit.impacts {
            let z = before.y - before.x;
            let bound = 2.0 * (before.w - before.v).abs() * tol_t + 1e-17;
            assert!((z - wall.sign() * sys.d / 2.0).abs() <= bound, "z = {z}");
        }
    }
}

#[test]
fn chatter_at_e_045_sticks_near_0036_s() {
    #[derive(Default)]
    struct Sticks(Vec<f64>);
    impl Probe for Sticks {
        fn stick(&mut self, t: f64, _w: Wall, _s: &State) {
            self.0.push(t);
        }
    }
    let sys = System {
        e: 0.45,
        ..System::TABLE_I
    };
    let mut p = Sticks::default();
    let rec = run_with(&sys, &Request::default(), &mut p);
    assert_eq!(rec.outcome, Outcome::Ok);
    assert!(
        (0.034..=0.037).contains(&p.0[0]),
        "first stick at {}",
        p.0[0]
    );
    assert!(
        rec.impacts < 200,
        "{} impacts: the accumulation was not cut",
        rec.impacts
    );
}

#[test]
fn same_input_same_bits() {
    let sys = System {
        e: 0.74,
        ..System::TABLE_I
    };
    let a = run(&sys);
    let b = run(&sys);
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
    assert_eq!(a.xmax.to_bits(), b.xmax.to_bits());
    assert_eq!(a.di.to_bits(), b.di.to_bits());
}

// ---- The extremes table: one test per row. --------------------------------------------------

fn crit() -> f64 {
    2.0 * (System::TABLE_I.K * System::TABLE_I.M).sqrt()
}

/// Runs a row: a named outcome, and finite observables whenever the outcome is `ok`.
fn extreme(sys: System) -> Record {
    sys.validate().unwrap();
    let rec = run(&sys);
    assert!(Outcome::ALL.contains(&rec.outcome));
    assert!(rec.t_stop.is_finite());
    assert!(rec.energy_impact.is_finite() && rec.energy_viscous.is_finite());
    if rec.outcome == Outcome::Ok {
        for v in [rec.x1, rec.t1, rec.x2, rec.t2, rec.xmax, rec.di] {
            assert!(v.is_finite(), "{rec:?}");
        }
    }
    assert!(rec.steps < 1_000_000, "{} steps", rec.steps);
    rec
}

macro_rules! extreme_row {
    ($name:ident, $sys:expr, $expect:expr) => {
        #[test]
        fn $name() {
            let rec = extreme($sys);
            let expect: &[Outcome] = &$expect;
            assert!(expect.contains(&rec.outcome), "{:?}", rec);
        }
    };
}

const T1: System = System::TABLE_I;
extreme_row!(extreme_e_0, System { e: 0.0, ..T1 }, [Outcome::Ok]);
extreme_row!(extreme_e_1e_9, System { e: 1e-9, ..T1 }, [Outcome::Ok]);
extreme_row!(extreme_e_045, System { e: 0.45, ..T1 }, [Outcome::Ok]);
extreme_row!(extreme_e_1, System { e: 1.0, ..T1 }, [Outcome::Ok]);
extreme_row!(extreme_d_1e_9, System { d: 1e-9, ..T1 }, [Outcome::Ok]);
extreme_row!(extreme_d_1e3, System { d: 1e3, ..T1 }, [Outcome::Ok]);
extreme_row!(
    extreme_mass_ratio_1e_9,
    System { m: 1e-10, ..T1 },
    [Outcome::Ok]
);
extreme_row!(
    extreme_mass_ratio_100,
    System { m: 10.0, ..T1 },
    [Outcome::Ok]
);
extreme_row!(extreme_c_0, System { C: 0.0, ..T1 }, [Outcome::Ok]);

#[test]
fn extreme_c_just_below_critical() {
    // Near critical damping there is no second positive half-cycle within the horizon unless
    // the impacts make one; either way the outcome is named and observables finite.
    let rec = extreme(System {
        C: crit() * (1.0 - 1e-12),
        ..T1
    });
    assert!(rec.x1.is_finite());
}

#[test]
fn extreme_c_just_above_critical() {
    let below = extreme(System {
        C: crit() * (1.0 - 1e-12),
        ..T1
    });
    let above = extreme(System {
        C: crit() * (1.0 + 1e-12),
        ..T1
    });
    // Continuity across critical damping: the first peak agrees to near machine precision.
    assert!(
        (below.x1 - above.x1).abs() <= 1e-9 * below.x1,
        "{below:?} {above:?}"
    );
}

extreme_row!(
    extreme_c_50_critical,
    System {
        C: 50.0 * 2.0 * 6.324555320336759,
        ..T1
    },
    [Outcome::NoSecondPeak, Outcome::Ok]
);
extreme_row!(
    extreme_v0_0,
    System { v0: 0.0, ..T1 },
    [Outcome::NoSecondPeak]
);

#[test]
fn extreme_grazing_contact_is_detected() {
    // Undamped main mass x = A sin(w t); inner mass at rest at y0 = A - d/2, so
    // z = y0 - A sin(w t) >= -d/2 with equality (zero relative velocity) exactly at t = T/4.
    let (a, d) = (0.008, 0.01);
    let w = (T1.K / T1.M).sqrt();
    let sys = System {
        C: 0.0,
        x0: 0.0,
        v0: a * w,
        y0: a - d / 2.0,
        w0: 0.0,
        d,
        ..T1
    };
    let mut audit = Audit {
        sys: Some(sys),
        ..Audit::default()
    };
    let req = Request {
        t_end: Some(0.3 * sys.period()),
        ..Request::default()
    };
    let rec = run_with(&sys, &req, &mut audit);
    assert!(Outcome::ALL.contains(&rec.outcome));
    let (t, wall, before, _) = audit
        .impacts
        .first()
        .expect("the grazing contact was missed");
    assert_eq!(*wall, Wall::Left);
    assert!(
        (t - sys.period() / 4.0).abs() <= 1e-6 * sys.period(),
        "t = {t}"
    );
    assert!(
        (before.w - before.v).abs() <= 1e-6 * a * w,
        "not a grazing contact"
    );
}

#[test]
fn extreme_table_i_e_045_chatters_and_finishes() {
    let rec = extreme(System { e: 0.45, ..T1 });
    assert_eq!(rec.outcome, Outcome::Ok);
    assert!(rec.sticks >= 1);
}

/// Regression (found while building issue 2): an impact that reverses the main mass after a
/// maximum starts a new rise; the driver must look for the next maximum. The peaks must equal
/// the maxima of a dense trace over each positive half-cycle, for every e of the paper's sweep.
#[test]
fn peaks_equal_the_maxima_of_a_dense_trace() {
    #[derive(Default)]
    struct Dense(Vec<(f64, f64)>);
    impl Probe for Dense {
        fn sample(&mut self, t: f64, s: &State) {
            self.0.push((t, s.x));
        }
    }
    for i in 0..=50 {
        let e = 0.45 + i as f64 * 0.01;
        let sys = System {
            e,
            ..System::TABLE_I
        };
        let mut dense = Dense::default();
        let req = Request {
            trace_dt: Some(2e-6),
            ..Request::default()
        };
        let rec = run_with(&sys, &req, &mut dense);
        // Split the trace into positive half-cycles and take each one's maximum.
        let mut maxima = vec![];
        let mut cur: Option<f64> = None;
        for &(_, x) in &dense.0 {
            if x > 0.0 {
                cur = Some(cur.map_or(x, |c| c.max(x)));
            } else if let Some(c) = cur.take() {
                maxima.push(c);
            }
        }
        maxima.extend(cur);
        assert!(maxima.len() >= 2, "e={e}");
        for (k, (x, _)) in rec.peaks.iter().enumerate() {
            // The sampled maximum is below the true one by at most v^2/2|a| over half a step.
            assert!(
                *x >= maxima[k] - 1e-15,
                "e={e} peak {k}: {x} < sampled {}",
                maxima[k]
            );
            assert!(
                *x - maxima[k] <= 1e-7,
                "e={e} peak {k}: {x} vs sampled {}",
                maxima[k]
            );
        }
    }
}

/// Regression (issue 5, found by the tradeoff ladder): with a loose event tolerance the
/// rebounds of a chatter became shorter than the tolerance before the chatter threshold was
/// reached, and the run ran into the impact cap. The threshold is now at least ten tolerances.
#[test]
fn loose_tolerance_still_ends_chatter_by_sticking() {
    for tol in [1e-6, 1e-4] {
        for e in [0.45, 0.46, 0.48, 0.49, 0.74] {
            let sys = System {
                e,
                ..System::TABLE_I
            };
            let settings = SolverSettings {
                tol,
                ..SolverSettings::default()
            };
            let rec = simulate(&sys, &settings, &Request::default(), None, &mut NoProbe);
            assert_eq!(rec.outcome, Outcome::Ok, "e={e} tol={tol}: {rec:?}");
            assert!(
                rec.sticks >= 1 && rec.impacts < 200,
                "e={e} tol={tol}: {rec:?}"
            );
            let tight = run(&sys);
            assert!(
                (rec.x1 - tight.x1).abs() <= 1e-4 * tight.x1,
                "e={e} tol={tol}"
            );
        }
    }
}

// ---- Issue 11: no slow extremes. Each ends with a named outcome (or is refused at validation
// with its key, value and range) and takes a bounded number of solver steps, noise-free and
// with the paper's noise (a sample every 1 ms over the 20 s horizon).

/// The run noise-free and with the paper's noise.
fn clean_and_noisy(sys: &System) -> [Record; 2] {
    use impactsweep::sim::NoiseSettings;
    use impactsweep::sim::noise::NoiseStream;
    sys.validate().unwrap();
    let ns = NoiseSettings {
        power: 5e-10,
        sample_time: 1e-3,
    };
    let mut stream = NoiseStream::new(2013, 1, 0);
    let noisy = simulate(
        sys,
        &SolverSettings::default(),
        &Request::default(),
        Some((&ns, &mut stream)),
        &mut NoProbe,
    );
    [run(sys), noisy]
}

#[test]
fn issue_11_c_1e6_ends_at_once() {
    // zeta = 79,000: x rises for about M/C = 1e-7 s, then creeps back without crossing zero
    // (an over-damped mass crosses zero at most once): the first half-cycle never closes.
    for rec in clean_and_noisy(&System { C: 1e6, ..T1 }) {
        assert_eq!(rec.outcome, Outcome::NoSecondPeak, "{rec:?}");
        assert_eq!(rec.impacts, 0);
        assert!(rec.steps <= 20, "{} steps", rec.steps);
    }
}

#[test]
fn issue_11_c_50_critical_ends_at_once() {
    for rec in clean_and_noisy(&System {
        C: 50.0 * crit(),
        ..T1
    }) {
        assert_eq!(rec.outcome, Outcome::NoSecondPeak, "{rec:?}");
        assert!(rec.steps <= 20, "{} steps", rec.steps);
    }
    // Started on the far side, it crosses zero once, upward, and never comes back down.
    let rec = run(&System {
        C: 50.0 * crit(),
        x0: -0.004,
        v0: 3.0,
        ..T1
    });
    assert_eq!(rec.outcome, Outcome::NoSecondPeak, "{rec:?}");
    assert!(rec.x1.is_nan() && rec.steps <= 20, "{rec:?}");
}

#[test]
fn issue_11_a_critically_damped_mass_ends_at_once() {
    // The impacts push the main mass back across zero, so a second half-cycle does come.
    for rec in clean_and_noisy(&System { C: crit(), ..T1 }) {
        assert_eq!(rec.outcome, Outcome::Ok, "{rec:?}");
        assert!(rec.steps <= 100, "{} steps", rec.steps);
    }
}

#[test]
fn issue_11_a_main_mass_of_1e_300_kg_is_refused() {
    let err = System { M: 1e-300, ..T1 }.validate().unwrap_err();
    assert_eq!(
        err.to_string(),
        "M = 1e-300: the main mass must be in [1e-12, 1e12] kg"
    );
}

#[test]
fn issue_11_v0_of_1e200_is_refused() {
    let err = System { v0: 1e200, ..T1 }.validate().unwrap_err();
    assert_eq!(
        err.to_string(),
        "v0 = 1e200: an initial velocity must be in [-1e6, 1e6] m/s"
    );
    // Up to the bound the run is fast: the same number of steps at any speed.
    let fast = run(&System { v0: 1e6, ..T1 });
    assert!(Outcome::ALL.contains(&fast.outcome));
    assert!(fast.steps < 10_000, "{fast:?}");
}
