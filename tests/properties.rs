//! Property tests over wide random parameters (issue 2): no panic, always a named outcome,
//! finite observables when `ok`, total energy never increases, the inner mass never leaves the
//! cavity (a missed impact would let it through a wall), and the same input gives the same bits.

use impactsweep::model::System;
use impactsweep::sim::{Outcome, Probe, Record, Request, SolverSettings, State, Wall, simulate};
use proptest::prelude::*;

/// Watches energy and the cavity along a run.
#[derive(Default)]
struct Watch {
    half_d: f64,
    e0: f64,
    last_energy: f64,
    energy_rise: f64,
    worst_gap: f64,
}

impl Probe for Watch {
    fn energy(&mut self, _t: f64, e: f64) {
        self.energy_rise = self
            .energy_rise
            .max((e - self.last_energy) / self.e0.max(1e-300));
        self.last_energy = e;
    }
    fn sample(&mut self, _t: f64, s: &State) {
        self.worst_gap = self.worst_gap.max((s.y - s.x).abs() / self.half_d);
    }
    fn impact(&mut self, t: f64, _w: Wall, before: &State, _after: &State) {
        self.sample(t, before);
    }
}

fn system() -> impl Strategy<Value = System> {
    (
        -2.0..2.0f64,                                       // log10 M
        prop_oneof![Just(f64::NEG_INFINITY), -6.0..2.0f64], // log10 m/M (or no damper)
        0.0..5.0f64,                                        // log10 K
        prop_oneof![Just(0.0), 0.0..3.0f64],                // zeta
        -3.0..1.0f64,                                       // log10 d / amplitude
        0.0..=1.0f64,                                       // e
        -5.0..5.0f64,                                       // v0
        -1.0..1.0f64,                                       // x0 / amplitude
        -0.5..=0.5f64,                                      // (y0 - x0) / d
        -5.0..5.0f64,                                       // w0
    )
        .prop_map(|(lm, lr, lk, zeta, ld, e, v0, x0, z0, w0)| {
            let big_m = 10f64.powf(lm);
            let k = 10f64.powf(lk);
            let amp = (v0.abs().max(0.1)) / (k / big_m).sqrt();
            let d = amp * 10f64.powf(ld);
            let x0 = x0 * amp;
            System {
                M: big_m,
                m: big_m * 10f64.powf(lr),
                K: k,
                C: 2.0 * zeta * (k * big_m).sqrt(),
                d,
                e,
                x0,
                v0,
                y0: x0 + z0 * d,
                w0,
                units: 1.0,
                d_spread: 0.0,
                table: None,
            }
        })
}

fn settings() -> SolverSettings {
    SolverSettings {
        t_max_periods: 20.0,
        max_impacts: 20_000,
        ..SolverSettings::default()
    }
}

fn run(sys: &System, req: &Request, w: &mut Watch) -> Record {
    w.half_d = sys.d / 2.0;
    w.e0 = sys.energy(sys.x0, sys.v0, sys.w0);
    w.last_energy = w.e0;
    simulate(sys, &settings(), req, None, w)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn every_run_ends_well(sys in system()) {
        prop_assume!(sys.validate().is_ok());
        let mut w = Watch::default();
        let rec = run(&sys, &Request::default(), &mut w);
        prop_assert!(Outcome::ALL.contains(&rec.outcome));
        prop_assert!(rec.t_stop.is_finite());
        if rec.outcome == Outcome::Ok {
            for v in [rec.x1, rec.t1, rec.x2, rec.t2, rec.xmax, rec.di] {
                prop_assert!(v.is_finite(), "{:?}", rec);
            }
        }
        prop_assert!(w.energy_rise <= 1e-12, "energy rose by {} of E0", w.energy_rise);
        prop_assert!(rec.energy_impact >= 0.0 && rec.energy_viscous >= 0.0);
    }

    #[test]
    fn inner_mass_stays_in_the_cavity(sys in system()) {
        prop_assume!(sys.validate().is_ok());
        let mut w = Watch::default();
        let req = Request {
            t_end: Some(2.0 * sys.period()),
            trace_dt: Some(sys.period() / 400.0),
            ..Request::default()
        };
        run(&sys, &req, &mut w);
        prop_assert!(w.worst_gap <= 1.0 + 1e-9, "|y - x| reached {} d/2", w.worst_gap);
    }

    #[test]
    fn same_input_same_bits(sys in system()) {
        prop_assume!(sys.validate().is_ok());
        let a = run(&sys, &Request::default(), &mut Watch::default());
        let b = run(&sys, &Request::default(), &mut Watch::default());
        prop_assert_eq!(a.outcome, b.outcome);
        prop_assert_eq!(a.impacts, b.impacts);
        for (x, y) in [(a.xmax, b.xmax), (a.di, b.di), (a.t_stop, b.t_stop), (a.energy_impact, b.energy_impact)] {
            prop_assert_eq!(x.to_bits(), y.to_bits());
        }
    }
}
