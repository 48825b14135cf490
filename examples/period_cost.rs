//! A fixed single-thread workload of the design life's measurement (issue 43's points): for each
//! point, one start on its attractor (2,000 transient periods), then `N` periods located in full
//! and `N` with a floor (`0.8 d`, at least 4 mm: extrema below it are not located, as in the
//! life measurement's later windows). Prints the time per period and a checksum of the maxima,
//! so the A/B of a simulator change compares both speed and bits (BENCHMARKS.md, "The
//! simulator's cost per period"). The second argument picks the harmonic scene's event finder
//! (`safe_steps`, today's, or `bracketed`, issue 69), so one binary runs both sides of an A/B
//! (`scripts/bench_period_ab.sh`); `chain` runs today's finder through
//! `orbits::map::periods_above`, the design life's chains (each period the bits of a call of its
//! own, the run built once; steps not counted: printed as 0); the third, a point's name, runs
//! that point alone.
//!
//! `cargo run --release --example period_cost -- [N] [safe_steps|bracketed|chain] [POINT]`
//! (default 20000, the default finder, every point)

#[path = "life_validation.rs"]
#[allow(dead_code)]
pub mod validation;

use impactsweep::model::System;
use impactsweep::orbits::map::{Forcing, Section, periods_above};
use impactsweep::sim::harmonic::Finder;
use impactsweep::sim::{Drive, Harmonic, NoProbe, Request, simulate_harmonic};
use std::time::Instant;
use validation::{POINTS, forcing_of};

/// `p` periods of the forced motion from section `s`, extrema located above `floor`, by
/// `finder`: the end section and the window's amplitude (what `orbits::map::eval_above`
/// returns, with the finder chosen).
fn periods(f: &Forcing, s: &Section, p: u64, floor: f64, finder: Finder) -> (Section, f64, u64) {
    let hd = 0.5 * f.sys.d;
    let sys = System {
        x0: s[0],
        v0: s[1],
        y0: s[0] + s[2].clamp(-hd, hd),
        w0: s[3],
        ..f.sys
    };
    let scene = Harmonic {
        F0: f.F0,
        drive: Drive::Omega(f.omega),
        n_trans: Some(0),
        n_meas: p,
        energies: false,
        x_floor: floor,
        finder,
        ..Harmonic::default()
    };
    let out = simulate_harmonic(
        &sys,
        &f.settings,
        &Request::default(),
        &scene,
        None,
        &mut NoProbe,
    );
    let e = out.end;
    ([e.x, e.v, e.y - e.x, e.w], out.amplitude, out.steps)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(20000);
    let chain = args.get(2).is_some_and(|a| a == "chain");
    let finder = match args.get(2).map(String::as_str) {
        None | Some("chain") => Finder::DEFAULT,
        Some("safe_steps") => Finder::SafeSteps,
        Some("bracketed") => Finder::Bracketed,
        Some(other) => panic!("finder {other}: expected safe_steps, bracketed or chain"),
    };
    let only = args.get(3);
    let (mut total, mut periods_run) = (0.0, 0u64);
    for p in POINTS.iter().filter(|p| only.is_none_or(|o| o == p.name)) {
        let f = forcing_of(p);
        let start = [0.003, 0.05, 0.0, 0.0];
        let st = periods(&f, &start, 2000, 0.0, Finder::SafeSteps).0;
        for floor in [0.0, 0.8 * f.sys.d.max(0.005)] {
            let t = Instant::now();
            let (mut s, mut sum, mut top, mut steps) = (st, 0.0, 0.0f64, 0u64);
            if chain {
                assert!(periods_above(&f, &mut s, n, floor, |amplitude| {
                    sum += amplitude;
                    top = top.max(amplitude);
                }));
            } else {
                for _ in 0..n {
                    let (end, amplitude, st) = periods(&f, &s, 1, floor, finder);
                    steps += st;
                    s = end;
                    sum += amplitude;
                    top = top.max(amplitude);
                }
            }
            let dt = t.elapsed().as_secs_f64();
            total += dt;
            periods_run += n;
            println!(
                "{} floor {:.4}: {:.2} us/period, max {:.6e}, sum {:.15e}, {:.2} steps/period",
                p.name,
                floor,
                dt / n as f64 * 1e6,
                top,
                sum,
                steps as f64 / n as f64
            );
        }
    }
    println!("all: {:.2} us/period", total / periods_run as f64 * 1e6);
}
