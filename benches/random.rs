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
//!
//! First, where a realization of the seismic showcase's structure spends its CPU (issue 69,
//! BENCHMARKS.md "Random realizations at half the cost"): its samples drawn once, its own Sa
//! from them, its run at the 0.2-g stripe drawing its load and from the samples, and a stripe's
//! whole realization, for the structure alone and four dampers. `SEISMIC_ONLY=1` stops there;
//! `cargo bench --profile dev --bench random` builds it without the release profile's LTO.
//!
//! Under `cargo test` (criterion's test mode, no `--bench` argument) every measurement runs as a
//! smoke test on 20 realizations, one round: the printed figures are then not measurements (the
//! whole set, 150,000 realizations, took 35 s of one core in CI).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use impactsweep::model::System;
use impactsweep::sim::random::{
    Envelope, Excitation, Input, IntensitySpec, LoadBlock, Measure, RandomLoad, RandomRun,
    RandomScene, RealizationStream, Spectrum, own_intensity,
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
        units: 1.0,
        d_spread: 0.0,
        table: None,
    }
}

/// Realizations per measurement and rounds of it: `(2000, 5)` under `cargo bench`, `(20, 1)` as
/// a smoke test under `cargo test`.
fn sizes() -> (u64, usize) {
    if std::env::args().any(|a| a == "--bench") {
        (2000, 5)
    } else {
        (20, 1)
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
        let n = sizes().0;
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

/// The seismic showcase's scene (`configs/seismic.toml`): 20 s of enveloped Clough–Penzien
/// ground acceleration at `dt = 0.005`, the first yield's drift as the threshold, Sa(T1, 5 %)
/// as the intensity measure.
fn seismic_scene() -> RandomScene {
    let k = 246.7;
    let yield_drift = 0.25 * 9.80665 / k;
    RandomScene {
        input: Input::Base,
        excitation: Excitation::Random(RandomLoad {
            spectrum: Spectrum::CloughPenzien {
                omega_g: 15.708,
                zeta_g: 0.6,
                // The showcase's, a tenth of omega_g (not pi / 2).
                #[allow(clippy::approx_constant)]
                omega_f: 1.5708,
                zeta_f: 0.6,
            },
            S0: 0.005,
            envelope: Some(Envelope {
                t1: 2.0,
                t2: 12.0,
                c: 0.3,
            }),
        }),
        dt: 0.005,
        duration: 20.0,
        threshold: Some(yield_drift),
        intensity: Some(IntensitySpec {
            measure: Measure::Sa,
            period: std::f64::consts::TAU * (1.0 / k).sqrt(),
            ida_tol: 0.01,
            ida_max: 10.0,
        }),
        im: Some(0.2),
    }
}

/// The showcase's structure with a damper of mass `m` and clearance `d`.
fn seismic_structure(m: f64, d: f64) -> System {
    System {
        M: 1.0,
        m,
        K: 246.7,
        C: 0.628,
        d,
        e: 0.6,
        x0: 0.0,
        v0: 0.0,
        y0: 0.0,
        w0: 0.0,
        units: 1.0,
        d_spread: 0.0,
        table: None,
    }
}

/// The median of `rounds` measurements of `f`'s thread CPU per call over `n` calls (us).
fn cpu_us(rounds: usize, n: u64, mut f: impl FnMut(u64)) -> f64 {
    let mut v: Vec<f64> = (0..rounds)
        .map(|_| {
            let t = thread_cpu();
            for r in 0..n {
                f(r);
            }
            (thread_cpu() - t) / n as f64 * 1e6
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[rounds / 2]
}

/// Where a realization of the seismic showcase's structure spends its CPU (issue 69): the
/// motion's own Sa (one pass over its load through the 5 % oscillator), the run at the
/// 0.2-g stripe without a damper and with the showcase's dampers. Prints medians of 5 rounds of
/// 2,000 realizations of thread CPU; `SEISMIC_ONLY=1` skips criterion.
fn seismic() {
    let scene = seismic_scene();
    let spec = scene.intensity.expect("an intensity measure");
    let settings = SolverSettings::default();
    let req = Request::default();
    let (n, rounds) = sizes();
    let stream = |r: u64| RealizationStream::new(2026, 0, r);
    let gains: Vec<f64> = (0..n)
        .map(|r| 0.2 / own_intensity(&scene, spec.period, stream(r)).sa)
        .collect();
    let own = cpu_us(rounds, n, |r| {
        black_box(own_intensity(&scene, spec.period, stream(r)));
    });
    eprintln!("seismic own Sa pass: {own:.1} us of thread CPU per realization");
    // The motion drawn once (issue 69): its samples, its own Sa from them.
    let setup = RandomRun::new(&seismic_structure(0.1, 0.01), &settings, &scene);
    let mut block = LoadBlock::default();
    let load = cpu_us(rounds, n, |r| setup.load_into(stream(r), &mut block));
    let blocks: Vec<LoadBlock> = (0..n).map(|r| setup.load(stream(r))).collect();
    let own_block = cpu_us(rounds, n, |r| {
        black_box(setup.own_intensity(spec.period, &blocks[r as usize]));
    });
    eprintln!(
        "seismic samples (noise, filter, envelope) drawn once: {load:.1} us; own Sa from them: \
         {own_block:.1} us of thread CPU per realization"
    );
    for (m, d) in [
        (0.0, 0.01),
        (0.05, 0.02),
        (0.1, 0.01),
        (0.2, 0.005),
        (0.2, 0.04),
    ] {
        let run = RandomRun::new(&seismic_structure(m, d), &settings, &scene);
        let recs: Vec<_> = (0..200.min(n))
            .map(|r| run.run_scaled(&req, stream(r), gains[r as usize], &mut NoProbe))
            .collect();
        let mean = |f: &dyn Fn(&impactsweep::sim::random::RandomRecord) -> f64| {
            recs.iter().map(f).sum::<f64>() / recs.len() as f64
        };
        let (impacts, steps) = (mean(&|r| r.impacts as f64), mean(&|r| r.steps as f64));
        let us = cpu_us(rounds, n, |r| {
            black_box(run.run_scaled(&req, stream(r), gains[r as usize], &mut NoProbe));
        });
        let from_block = cpu_us(rounds, n, |r| {
            let i = r as usize;
            black_box(run.run_block(&req, &blocks[i], gains[i], &mut NoProbe));
        });
        // The same runs without `int x^2` and `int a^2` (a capacity search's trial runs): what
        // the record's two RMS fields cost.
        let no_integrals = cpu_us(rounds, n, |r| {
            let i = r as usize;
            black_box(run.amplitude_block(&req, &blocks[i], gains[i]));
        });
        let whole = cpu_us(rounds, n, |r| {
            run.load_into(stream(r), &mut block);
            let own = run.own_intensity(spec.period, &block);
            black_box(run.run_block(&req, &block, 0.2 / own.sa, &mut NoProbe));
        });
        eprintln!(
            "seismic run m = {m}, d = {d}: {us:.1} us of thread CPU per realization at the 0.2-g \
             stripe drawing its load, {from_block:.1} us from its samples drawn before \
             ({no_integrals:.1} us without the RMS integrals); a stripe's realization (samples, own Sa, run) {whole:.1} us; {impacts:.1} impacts, \
             {steps:.0} solver steps (mean of {})",
            recs.len()
        );
    }
}

fn all(c: &mut Criterion) {
    seismic();
    if std::env::var_os("SEISMIC_ONLY").is_none() {
        bench(c);
    }
}

criterion_group!(benches, all);
criterion_main!(benches);
