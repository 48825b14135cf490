//! `cargo bench --bench simulate`: the exact solver on the paper's Table I system for
//! e in [0.45, 0.95] (51 two-peak runs per iteration), noise-free and with the paper's noise
//! (5e-10 m^2 s at 1 ms samples). Criterion reports the time of the whole set; the per-run and
//! per-impact figures divide by the run and impact counts printed at start.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use impactsweep::model::System;
use impactsweep::sim::noise::NoiseStream;
use impactsweep::sim::{NoProbe, NoiseSettings, Request, SolverSettings, simulate};
use std::hint::black_box;

fn systems() -> Vec<System> {
    (0..=50)
        .map(|i| System {
            e: 0.45 + i as f64 * 0.01,
            ..System::TABLE_I
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let sys = systems();
    let settings = SolverSettings::default();
    let req = Request::default();
    let impacts: u64 = sys
        .iter()
        .map(|s| simulate(s, &settings, &req, None, &mut NoProbe).impacts)
        .sum();
    eprintln!(
        "simulate: {} runs, {} impacts per iteration ({:.1} impacts per run)",
        sys.len(),
        impacts,
        impacts as f64 / sys.len() as f64
    );
    let mut g = c.benchmark_group("simulate");
    g.throughput(Throughput::Elements(sys.len() as u64));
    g.bench_function("table_i_e045_095_per_run", |b| {
        b.iter(|| {
            for s in &sys {
                black_box(simulate(black_box(s), &settings, &req, None, &mut NoProbe));
            }
        })
    });
    g.throughput(Throughput::Elements(impacts));
    g.bench_function("table_i_e045_095_per_impact", |b| {
        b.iter(|| {
            for s in &sys {
                black_box(simulate(black_box(s), &settings, &req, None, &mut NoProbe));
            }
        })
    });
    // The same runs with the paper's noise: the cost of noise is the difference.
    let ns = NoiseSettings {
        power: 5e-10,
        sample_time: 1e-3,
    };
    g.throughput(Throughput::Elements(sys.len() as u64));
    g.bench_function("table_i_e045_095_noisy_per_run", |b| {
        b.iter(|| {
            for (i, s) in sys.iter().enumerate() {
                let mut stream = NoiseStream::new(2013, 1, i as u64);
                black_box(simulate(
                    black_box(s),
                    &settings,
                    &req,
                    Some((&ns, &mut stream)),
                    &mut NoProbe,
                ));
            }
        })
    });
    g.finish();
    // One run per e, for the median over the set.
    let mut g = c.benchmark_group("simulate_one");
    for s in [&sys[0], &sys[29], &sys[45]] {
        g.bench_function(format!("e={:.2}", s.e), |b| {
            b.iter(|| black_box(simulate(black_box(s), &settings, &req, None, &mut NoProbe)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
