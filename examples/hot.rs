//! A fixed workload for counting instructions (`valgrind --tool=callgrind`, repeatable even on a
//! loaded machine; see BENCHMARKS.md, "Profile"): the Table I system over e in [0.6, 0.95]
//! (36 two-peak runs), REPS times, noise-free or with the paper's noise (5e-10 m^2 s at 1 ms).
//!
//! `cargo run --release --example hot -- [REPS] [clean|noisy]`
//!
//! Prints the runs, impacts and solver steps, and a checksum of the records so the work cannot
//! be optimised away.
use impactsweep::model::System;
use impactsweep::sim::noise::NoiseStream;
use impactsweep::sim::{NoProbe, NoiseSettings, Request, SolverSettings, simulate};

fn main() {
    let mut args = std::env::args().skip(1);
    let reps: u64 = args.next().map_or(1, |s| s.parse().expect("REPS"));
    let noisy = match args.next().as_deref() {
        None | Some("clean") => false,
        Some("noisy") => true,
        Some(other) => panic!("mode {other}: clean or noisy"),
    };
    let ns = NoiseSettings {
        power: 5e-10,
        sample_time: 1e-3,
    };
    let settings = SolverSettings::default();
    let req = Request::default();
    let (mut acc, mut runs, mut impacts, mut steps) = (0.0, 0u64, 0u64, 0u64);
    for rep in 0..reps {
        for i in 0..=35 {
            let sys = System {
                e: 0.6 + i as f64 * 0.01,
                ..System::TABLE_I
            };
            let rec = if noisy {
                let mut stream = NoiseStream::new(2013, 1 + rep, i);
                simulate(
                    &sys,
                    &settings,
                    &req,
                    Some((&ns, &mut stream)),
                    &mut NoProbe,
                )
            } else {
                simulate(&sys, &settings, &req, None, &mut NoProbe)
            };
            acc += rec.xmax + rec.di;
            runs += 1;
            impacts += rec.impacts;
            steps += rec.steps;
        }
    }
    println!("runs {runs} impacts {impacts} steps {steps} checksum {acc:.15e}");
}
