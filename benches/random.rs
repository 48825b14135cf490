//! `cargo bench --bench random`: one 20-s realization of Kanai–Tajimi ground acceleration
//! (firm soil, `omega_g = 5 pi`, `zeta_g = 0.6`) at `dt = 0.005` (4,000 samples) on a structure
//! tuned to the ground's band (`M = 1 kg`, `K = 246.7 N/m`: `omega_n = 5 pi`, 2 % damping),
//! without a damper (`m = 0`: no impacts) and with one (`m = 0.05 kg`, `d = 2 cm`, `e = 0.6`),
//! each realization on its own stream. Criterion reports the time per realization; the cost per
//! sample divides the first by 4,000 and the cost per impact divides the difference by the
//! impacts per realization printed at start. Setting a design up ([`RandomRun::new`]: the
//! filter's matrix exponential and the quadratic forms) is measured apart: a sweep does it once
//! per design point for all its realizations.
//!
//! Criterion's times are wall-clock: on a machine shared with other work they include the time
//! the thread waited for a core. So each case also prints the thread's CPU time per realization
//! over 2,000 realizations (`CLOCK_THREAD_CPUTIME_ID`), which is what one core costs whatever
//! else runs beside it.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use impactsweep::model::System;
use impactsweep::sim::random::{
    Excitation, Input, RandomLoad, RandomRun, RandomScene, RealizationStream, Spectrum,
};
use impactsweep::sim::{NoProbe, Request, SolverSettings};
use std::hint::black_box;

fn scene() -> RandomScene {
    RandomScene {
        input: Input::Base,
        excitation: Excitation::Random(RandomLoad {
            spectrum: Spectrum::KanaiTajimi {
                omega_g: 5.0 * std::f64::consts::PI,
                zeta_g: 0.6,
            },
            S0: 0.01,
            envelope: None,
        }),
        dt: 0.005,
        duration: 20.0,
        threshold: Some(0.05),
        intensity: None,
        im: None,
    }
}

fn structure(m: f64) -> System {
    let w = 5.0 * std::f64::consts::PI;
    System {
        M: 1.0,
        m,
        K: w * w,
        C: 2.0 * 0.02 * w,
        d: 0.02,
        e: 0.6,
        x0: 0.0,
        v0: 0.0,
        y0: 0.0,
        w0: 0.0,
    }
}

/// The calling thread's CPU time (s).
fn thread_cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid timespec for clock_gettime to fill.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

fn bench(c: &mut Criterion) {
    let scene = scene();
    let settings = SolverSettings::default();
    let req = Request::default();
    let mut g = c.benchmark_group("random");
    g.throughput(Throughput::Elements(1));
    for (name, m) in [
        ("kanai_tajimi_20s_no_impacts", 0.0),
        ("kanai_tajimi_20s_impacts", 0.05),
    ] {
        let sys = structure(m);
        let run = RandomRun::new(&sys, &settings, &scene);
        let probe: Vec<_> = (0..50)
            .map(|r| run.run(&req, RealizationStream::new(1, 0, r), &mut NoProbe))
            .collect();
        let impacts = probe.iter().map(|r| r.impacts).sum::<u64>() as f64 / 50.0;
        let steps = probe.iter().map(|r| r.steps).sum::<u64>() as f64 / 50.0;
        let n = 2000u64;
        let (wall, cpu) = (std::time::Instant::now(), thread_cpu());
        for r in 0..n {
            black_box(run.run(&req, RealizationStream::new(2, 0, r), &mut NoProbe));
        }
        let cpu = (thread_cpu() - cpu) / n as f64;
        let wall = wall.elapsed().as_secs_f64() / n as f64;
        eprintln!(
            "{name}: {} samples, {impacts:.1} impacts and {steps:.0} solver steps per \
             realization (mean of 50); thread CPU {:.1} us per realization ({:.1} ns per sample), \
             wall {:.1} us, over {n}",
            run.segments(),
            cpu * 1e6,
            cpu * 1e9 / run.segments() as f64,
            wall * 1e6
        );
        let mut r = 0u64;
        g.bench_function(name, |b| {
            b.iter(|| {
                r += 1;
                black_box(run.run(&req, RealizationStream::new(1, 0, r), &mut NoProbe))
            })
        });
    }
    g.bench_function("setup_kanai_tajimi", |b| {
        b.iter(|| {
            black_box(RandomRun::new(
                &structure(0.05),
                &settings,
                black_box(&scene),
            ))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
