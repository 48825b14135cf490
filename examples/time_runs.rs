//! Times the exact solver per run on the paper's Table I system for each e in [0.45, 0.95]
//! (step 0.01) and prints one JSON object: per-e median time per run over repeated batches,
//! impacts per run, and the overall median. Used by `scripts/bench_simulate.sh`, which times
//! the SciPy peer on the same runs in the same script run.
//!
//! `cargo run --release --example time_runs [BATCHES] [REPS]`

use impactsweep::model::System;
use impactsweep::sim::{NoProbe, Request, SolverSettings, simulate};
use std::hint::black_box;
use std::time::Instant;

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
    let batches: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(15);
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(200);
    let settings = SolverSettings::default();
    let req = Request::default();
    let mut rows = vec![];
    let mut per_run = vec![];
    let mut per_impact = vec![];
    for i in 0..=50 {
        let sys = System {
            e: 0.45 + i as f64 * 0.01,
            ..System::TABLE_I
        };
        let rec = simulate(&sys, &settings, &req, None, &mut NoProbe);
        let mut times: Vec<f64> = (0..batches)
            .map(|_| {
                let start = Instant::now();
                for _ in 0..reps {
                    black_box(simulate(
                        black_box(&sys),
                        &settings,
                        &req,
                        None,
                        &mut NoProbe,
                    ));
                }
                start.elapsed().as_secs_f64() / reps as f64
            })
            .collect();
        let t = median(&mut times);
        per_run.push(t);
        per_impact.push(t / rec.impacts.max(1) as f64);
        rows.push(format!(
            "{{\"e\": {:.2}, \"seconds_per_run\": {t:e}, \"impacts\": {}, \"outcome\": \"{}\", \"x1\": {:e}, \"di\": {:e}}}",
            sys.e, rec.impacts, rec.outcome, rec.x1, rec.di
        ));
    }
    println!(
        "{{\"solver\": \"impactsweep exact (tol 1e-12)\", \"median_seconds_per_run\": {:e}, \"median_seconds_per_impact\": {:e}, \"runs\": [{}]}}",
        median(&mut per_run),
        median(&mut per_impact),
        rows.join(", ")
    );
}
