//! Helpers for tests: a study with the paper's defaults, synthetic runs, an ideal case given as a
//! function, and a free-decay study simulated and reduced (not part of the tool's interface).

use super::common::{IdealCase, Reducer, Run, Summary};
use super::free;
use crate::model::System;
use crate::orbits::attractors::{AttractorRow, RunId, SteadyKind, section_of};
use crate::sim::{Outcome, Request, SolverSettings};
use crate::study::{
    Axis, Case, DiSource, Ranking, Reliability, RunSettings, SafetyForm, Study, VERIFY_PERIODS,
    Zones,
};

/// A study over the given axes with `n_cases` cases (case 0 ideal), paper defaults for the
/// reliability (strength mean 300 MPa, SD 24 MPa), zones and ranking.
pub fn study(axes: Vec<(&str, Vec<f64>)>, n_cases: usize) -> Study {
    let cases = (0..n_cases)
        .map(|c| Case {
            dm: 0.0,
            dd: 0.0,
            noise_seed: (c > 0).then_some(c as u64),
            ideal: c == 0,
        })
        .collect();
    Study {
        path: "synthetic.toml".into(),
        source: String::new(),
        name: "synthetic".into(),
        seed: 7,
        request: Request::default(),
        scene: crate::sim::Scene::Free,
        system: System::TABLE_I,
        axes: axes
            .into_iter()
            .map(|(k, v)| Axis {
                key: k.to_string(),
                values: v,
            })
            .collect(),
        cases,
        realizations: 0,
        design_intensity: None,
        hazard: None,
        noise: None,
        solver: SolverSettings::default(),
        reliability: Reliability {
            E: 200e9,
            r: 3.4e-3,
            L: 0.5,
            strength_mean: 300e6,
            strength_sd: 24e6,
            safety_form: SafetyForm::Exact,
            bootstrap: 2000,
            confidence: 0.95,
        },
        zones: Zones::default(),
        ranking: Ranking {
            wf1: 0.5,
            wf2: 0.5,
            di_source: DiSource::Ideal,
            verify_periods: VERIFY_PERIODS,
        },
        run: RunSettings {
            chunk_points: 16,
            chunk_realizations: crate::study::DEFAULT_CHUNK_RUNS,
            audit: 0,
        },
    }
}

/// A run with the given observables (the response is `xmax`).
pub fn row(study: &Study, point: u64, case: u32, outcome: Outcome, xmax: f64, di: f64) -> Run {
    Run {
        point,
        case,
        ideal: case == 0,
        dm: 0.0,
        dd: 0.0,
        noise_seed: study.cases[case as usize].noise_seed,
        outcome,
        response: xmax,
        di,
    }
}

/// The ideal case of synthetic data: a function of the axis values.
pub struct FnIdeal<F>(pub F);

impl<F: Fn(&[f64]) -> Option<[f64; 2]> + Sync> IdealCase for FnIdeal<F> {
    fn at(&self, values: &[f64]) -> Option<[f64; 2]> {
        (self.0)(values)
    }
}

/// The study simulated ([`simulate_chunks`]) and reduced with its own options, jumps
/// located with its own simulator.
pub fn reduce_simulated(study: &Study) -> Summary {
    let mut r = Reducer::new(study, free::options(study));
    for chunk in simulate_chunks(study) {
        r.push(chunk);
    }
    free::finish(r)
}

/// Runs the simulator over every run of the study's plan, chunk by chunk, as the sweep
/// engine would store them.
pub fn simulate_chunks(study: &Study) -> Vec<Vec<Run>> {
    let plan = crate::plan::Plan::new(study);
    (0..plan.n_chunks())
        .map(|k| {
            let mut rows = Vec::new();
            for p in plan.chunk_points(k) {
                for c in 0..plan.n_cases() as u32 {
                    let run = plan.run(p, c);
                    let mut noise = plan.noise_stream(&run);
                    let ns = study.noise;
                    let rec = crate::sim::simulate(
                        &run.system,
                        &study.solver,
                        &study.request,
                        match (&ns, noise.as_mut()) {
                            (Some(ns), Some(st)) => Some((ns, st)),
                            _ => None,
                        },
                        &mut crate::sim::NoProbe,
                    );
                    rows.push(Run {
                        point: p,
                        case: c,
                        ideal: run.spec.ideal,
                        dm: run.spec.dm,
                        dd: run.spec.dd,
                        noise_seed: run.spec.noise_seed,
                        outcome: rec.outcome,
                        response: rec.xmax,
                        di: rec.di,
                    });
                }
            }
            rows
        })
        .collect()
}

/// The paper's study as `configs/paper.toml` states it: `e` from 0.45 to 0.95 step 0.01,
/// the 12 cases of Table II (the Simulink seed vectors written as integers), noise power
/// 5e-10 m^2 s at Ts = 1 ms, strength LN(285 MPa, 20 MPa).
pub fn paper_study() -> Study {
    let e: Vec<f64> = (0..=50).map(|i| 0.45 + i as f64 * 0.01).collect();
    let mut s = study(vec![("e", e)], 1);
    s.seed = 2013;
    s.reliability.strength_mean = 285e6;
    s.reliability.strength_sd = 20e6;
    let g = 1e-3;
    let mm = 1e-3;
    let c = |dm: f64, dd: f64, seed: Option<u64>| Case {
        dm,
        dd,
        noise_seed: seed,
        ideal: dm == 0.0 && dd == 0.0 && seed.is_none(),
    };
    let (a, b, c3, d) = (Some(23341), Some(32324), Some(22413), Some(41313));
    s.cases = vec![
        c(0.0, 0.0, None),
        c(0.0, mm, None),
        c(0.0, -mm, None),
        c(0.0, 0.0, a),
        c(0.0, 0.0, b),
        c(0.0, 0.0, c3),
        c(0.0, 0.0, d),
        c(0.0, 0.0, b),
        c(g, mm, d),
        c(g, -mm, c3),
        c(-g, -mm, c3),
        c(-g, mm, a),
    ];
    s.noise = Some(crate::sim::NoiseSettings {
        power: 5e-10,
        sample_time: 1e-3,
    });
    s
}

/// A stored attractor of a harmonic curve's run at point `i` (design 0's `i`-th frequency,
/// `r = 0.9 + 0.1 i`): of `kind`, design amplitude `amplitude` (m), largest multiplier
/// `multiplier` and basin share `share`, found from a start.
pub fn attractor_row(
    i: u64,
    kind: SteadyKind,
    amplitude: f64,
    multiplier: f64,
    share: f64,
) -> AttractorRow {
    AttractorRow {
        run: RunId {
            point_id: i,
            point: i,
            case: 0,
            ideal: true,
            r: 0.9 + 0.1 * i as f64,
            omega: 63.0,
            F0: 1.0,
        },
        attractor: 0,
        kind,
        stability: "stable",
        period: u32::from(kind.periodic()),
        amplitude,
        window_amplitude: amplitude,
        impacts_per_period: 2.0,
        basin_share: share,
        starts: 0,
        origin: "start",
        multiplier_max: multiplier,
        lyapunov: f64::NAN,
        lyapunov_per_s: f64::NAN,
        lyapunov_se: f64::NAN,
        life_amplitude: amplitude,
        life_lo: amplitude,
        life_hi: amplitude,
        life_capped: false,
        tail_shape: f64::NAN,
        tail_end: f64::NAN,
        exceedances: 0,
        measured_periods: 1,
        section: section_of(&[0.0, 0.0, 0.0, 0.0]),
        section_units: Vec::new(),
    }
}
