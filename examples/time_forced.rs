//! Times the harmonic scene per run and per forcing period on the paper's Table I system and
//! prints one JSON object. Cases: F0 = 0.3 N at r in {0.5, 0.8, 0.96, 0.98, 1.0, 1.2, 2.0}
//! (periodic, chaotic and impact-free), each run twice: with a fixed transient of
//! `n_trans` periods (the same work as the SciPy peer in `scripts/bench_forced.sh`) and with
//! the default transient (until the Poincaré section converges, at most 2000 periods).
//! The time of a case is the median over `BATCHES` timings of `REPS` runs.
//!
//! `cargo run --release --example time_forced [BATCHES] [REPS] [N_TRANS]`

use impactsweep::model::System;
use impactsweep::sim::{Drive, Harmonic, NoProbe, Request, SolverSettings, simulate_harmonic};
use std::hint::black_box;
use std::time::Instant;

pub const RATIOS: [f64; 7] = [0.5, 0.8, 0.96, 0.98, 1.0, 1.2, 2.0];

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let batches: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(7);
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(5);
    let n_trans: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(300);
    let settings = SolverSettings::default();
    let req = Request::default();
    let sys = System::TABLE_I;
    let mut rows = vec![];
    for r in RATIOS {
        for fixed in [true, false] {
            let h = Harmonic {
                F0: 0.3,
                drive: Drive::Ratio(r),
                n_trans: fixed.then_some(n_trans),
                ..Harmonic::default()
            };
            h.validate(&sys).expect("valid");
            let rec = simulate_harmonic(&sys, &settings, &req, &h, None, &mut NoProbe);
            let mut times: Vec<f64> = (0..batches)
                .map(|_| {
                    let start = Instant::now();
                    for _ in 0..reps {
                        black_box(simulate_harmonic(
                            black_box(&sys),
                            &settings,
                            &req,
                            &h,
                            None,
                            &mut NoProbe,
                        ));
                    }
                    start.elapsed().as_secs_f64() / reps as f64
                })
                .collect();
            let t = median(&mut times);
            let periods = rec.n_trans + h.n_meas;
            rows.push(format!(
                "{{\"r\":{r},\"fixed\":{fixed},\"seconds_per_run\":{t:e},\"periods\":{periods},\
                 \"seconds_per_period\":{:e},\"outcome\":\"{}\",\"period\":{},\
                 \"impacts_per_period\":{},\"amplitude\":{:e},\"impacts\":{},\"steps\":{}}}",
                t / periods as f64,
                rec.outcome,
                rec.period,
                rec.impacts_per_period,
                rec.amplitude,
                rec.impacts,
                rec.steps
            ));
        }
    }
    println!("{{\"n_trans\":{n_trans},\"runs\":[{}]}}", rows.join(","));
}
