//! Times the extremes table (tests/simulator.rs, plus issue 11's `C = 1e6`, `M = 1e-300`,
//! `v0 = 1e200`): each row's outcome, impacts, solver steps and median time per run with the
//! default solver and request, noise-free and with the paper's noise (5e-10 m^2 s at 1 ms),
//! in thread CPU time.
//! A value refused at validation is listed with its error. Prints one JSON object; used by
//! `scripts/bench_e2e.sh` for "the slowest extreme per run".
//!
//! `cargo run --release --example time_extremes`

use impactsweep::model::System;
use impactsweep::sim::noise::NoiseStream;
use impactsweep::sim::{NoProbe, NoiseSettings, Record, Request, SolverSettings, simulate};
use std::hint::black_box;

fn rows() -> Vec<(&'static str, System)> {
    let t = System::TABLE_I;
    let crit = 2.0 * (t.K * t.M).sqrt();
    vec![
        ("Table I, e = 0.9", t),
        ("e = 0", System { e: 0.0, ..t }),
        ("e = 1e-9", System { e: 1e-9, ..t }),
        ("e = 0.45 (chatter)", System { e: 0.45, ..t }),
        ("e = 1", System { e: 1.0, ..t }),
        ("d = 1e-9", System { d: 1e-9, ..t }),
        ("d = 1e3", System { d: 1e3, ..t }),
        ("m/M = 1e-9", System { m: 1e-10, ..t }),
        ("m/M = 100", System { m: 10.0, ..t }),
        ("C = 0", System { C: 0.0, ..t }),
        (
            "C = crit (1 - 1e-12)",
            System {
                C: crit * (1.0 - 1e-12),
                ..t
            },
        ),
        (
            "C = crit (1 + 1e-12)",
            System {
                C: crit * (1.0 + 1e-12),
                ..t
            },
        ),
        (
            "C = 50 crit",
            System {
                C: 50.0 * crit,
                ..t
            },
        ),
        ("C = 1e6", System { C: 1e6, ..t }),
        ("v0 = 0", System { v0: 0.0, ..t }),
        ("M = 1e-300", System { M: 1e-300, ..t }),
        ("v0 = 1e200", System { v0: 1e200, ..t }),
    ]
}

fn run(sys: &System, noisy: bool) -> Record {
    let ns = NoiseSettings {
        power: 5e-10,
        sample_time: 1e-3,
    };
    let settings = SolverSettings::default();
    let req = Request::default();
    if noisy {
        let mut stream = NoiseStream::new(2013, 1, 0);
        simulate(sys, &settings, &req, Some((&ns, &mut stream)), &mut NoProbe)
    } else {
        simulate(sys, &settings, &req, None, &mut NoProbe)
    }
}

/// This thread's CPU time (s): unlike wall time, it does not count the time other processes
/// on a shared machine hold the core.
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Median CPU seconds per run over 7 batches, each long enough to time (>= 5 ms or 2000 runs).
fn time(sys: &System, noisy: bool) -> f64 {
    let start = cpu_seconds();
    black_box(run(sys, noisy));
    let once = (cpu_seconds() - start).max(1e-7);
    let reps = ((5e-3 / once).ceil() as usize).clamp(1, 2000);
    let mut v: Vec<f64> = (0..7)
        .map(|_| {
            let start = cpu_seconds();
            for _ in 0..reps {
                black_box(run(black_box(sys), noisy));
            }
            (cpu_seconds() - start) / reps as f64
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut out = vec![];
    for (name, sys) in rows() {
        for noisy in [false, true] {
            let row = match sys.validate() {
                Err(e) => serde_json::json!({
                    "name": name, "noisy": noisy, "refused": e.to_string(),
                }),
                Ok(()) => {
                    let rec = run(&sys, noisy);
                    serde_json::json!({
                        "name": name,
                        "noisy": noisy,
                        "outcome": rec.outcome.name(),
                        "impacts": rec.impacts,
                        "steps": rec.steps,
                        "seconds_per_run": time(&sys, noisy),
                    })
                }
            };
            out.push(row);
        }
    }
    println!("{}", serde_json::json!({ "rows": out }));
}
