//! Runs the benchmark set once (for instruction counting with callgrind).
use impactsweep::model::System;
use impactsweep::sim::{NoProbe, Request, SolverSettings, simulate};
fn main() {
    let reps: usize = std::env::args().nth(1).map_or(1, |s| s.parse().unwrap());
    let mut acc = 0.0;
    let mut steps = 0;
    for _ in 0..reps {
        for i in 0..=50 {
            let s = System {
                e: 0.45 + i as f64 * 0.01,
                ..System::TABLE_I
            };
            let r = simulate(
                &s,
                &SolverSettings::default(),
                &Request::default(),
                None,
                &mut NoProbe,
            );
            acc += r.xmax;
            steps += r.steps;
        }
    }
    println!("{acc} steps {steps}");
}
