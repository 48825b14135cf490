//! A fixed single-thread workload of the design life's measurement (issue 43's points): for each
//! point, one start on its attractor (2,000 transient periods), then `N` periods located in full
//! and `N` with a floor (`0.8 d`, at least 4 mm: extrema below it are not located, as in the
//! life measurement's later windows). Prints the time per period and a checksum of the maxima,
//! so the A/B of a simulator change compares both speed and bits (BENCHMARKS.md, "The
//! simulator's cost per period").
//!
//! `cargo run --release --example period_cost -- [N]` (default 20000)

#[path = "life_validation.rs"]
#[allow(dead_code)]
pub mod validation;

use impactsweep::orbits::map::{eval, eval_above};
use std::time::Instant;
use validation::{POINTS, forcing_of};

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20000);
    let (mut total, mut periods) = (0.0, 0u64);
    for p in POINTS.iter() {
        let f = forcing_of(p);
        let start = [0.003, 0.05, 0.0, 0.0];
        let st = eval(&f, &start, 2000, false).end;
        for floor in [0.0, 0.8 * f.sys.d.max(0.005)] {
            let t = Instant::now();
            let (mut s, mut sum, mut top) = (st, 0.0, 0.0f64);
            for _ in 0..n {
                let e = eval_above(&f, &s, 1, floor);
                s = e.end;
                sum += e.amplitude;
                top = top.max(e.amplitude);
            }
            let dt = t.elapsed().as_secs_f64();
            total += dt;
            periods += n;
            println!(
                "{} floor {:.4}: {:.2} us/period, max {:.6e}, sum {:.15e}",
                p.name,
                floor,
                dt / n as f64 * 1e6,
                top,
                sum
            );
        }
    }
    println!("all: {:.2} us/period", total / periods as f64 * 1e6);
}
