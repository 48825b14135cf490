//! Scans the harmonic scene over `r` (and optionally `F0`, `d`, `e`) for the Table I system and
//! prints one line per run: how the SciPy cross-check's period-1 orbit with two impacts per
//! period was found (tests/forced.rs). Usage:
//! `cargo run --release --example forced_scan -- [F0] [d] [e] [r_lo] [r_hi] [n]`.

use impactsweep::model::System;
use impactsweep::sim::{Drive, Harmonic, NoProbe, Request, SolverSettings, simulate_harmonic};

fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("numbers"))
        .collect();
    let get = |i: usize, d: f64| a.get(i).copied().unwrap_or(d);
    let (f0, d, e) = (get(0, 1.0), get(1, 0.01), get(2, 0.9));
    let (lo, hi, n) = (get(3, 0.8), get(4, 1.2), get(5, 41.0) as usize);
    let sys = System {
        d,
        e,
        ..System::TABLE_I
    };
    println!("r\toutcome\tperiod\tipp\tamplitude\tattenuation\tn_trans\tconverged\tsticks");
    for i in 0..n {
        let r = lo + (hi - lo) * i as f64 / (n.max(2) - 1) as f64;
        let h = Harmonic {
            F0: f0,
            drive: Drive::Ratio(r),
            ..Harmonic::default()
        };
        h.validate(&sys).expect("valid");
        let rec = simulate_harmonic(
            &sys,
            &SolverSettings::default(),
            &Request::default(),
            &h,
            None,
            &mut NoProbe,
        );
        println!(
            "{r:.4}\t{}\t{}\t{:.3}\t{:.6e}\t{:.4}\t{}\t{}\t{}",
            rec.outcome,
            rec.period,
            rec.impacts_per_period,
            rec.amplitude,
            rec.attenuation,
            rec.n_trans,
            rec.converged,
            rec.sticks
        );
    }
}
