//! What the race's drop factors rest on (`orbits::race::DROPS`): on the nine designs of
//! `configs/frequency-response.toml` and their four cases each (m and d 1 g and 1 mm off: 45
//! curves of 81 frequencies, 8 starts, the study's seed, the ideal case's design points), every
//! motion that is not periodic is measured as the race measures it
//! (2,000 periods, then doubling) until it meets its tolerance or its cap, and its final life
//! amplitude is compared with the upper end of its 90 % interval after 2,000, 4,000 and 8,000
//! periods. Prints `results/race_drop.md`.
//!
//! `cargo run --release --example race_drop > results/race_drop.md`

#[path = "showcase/curve.rs"]
mod showcase;

use impactsweep::orbits::census::Kind;
use impactsweep::orbits::life::LifeRun;
use impactsweep::orbits::race::{DROPS, settings};
use showcase::{ShowcaseCurve, showcase_curve};

/// Final life amplitude over the upper end after `n` periods, for every motion with both.
fn ratios(rows: &[(Vec<(u64, f64)>, f64)], n: u64) -> Vec<f64> {
    rows.iter()
        .filter_map(|(his, fin)| {
            let hi = his.iter().find(|(p, _)| *p == n)?.1;
            (hi.is_finite() && fin.is_finite()).then(|| fin / hi)
        })
        .collect()
}

fn main() {
    let mut rows = Vec::new();
    let study = showcase::study();
    for design in 0..showcase::designs(&study) {
        for case in 0..study.cases.len() as u32 {
            let ShowcaseCurve {
                censuses: cs,
                race_points: rp,
                ..
            } = showcase_curve(&study, design, case);
            for (c, p) in cs.iter().zip(&rp) {
                let (Some(c), Some((f, h))) = (c, p) else {
                    continue;
                };
                for a in &c.attractors {
                    let Kind::NonPeriodic(w) = &a.kind else {
                        continue;
                    };
                    let s = settings(f, h);
                    let lambda = w.probe.map_or(f64::NAN, |p| p.lambda);
                    let states = std::iter::once(a.section).chain(w.chains.iter().copied());
                    let mut run = LifeRun::chains(states.collect());
                    let mut his = Vec::new();
                    loop {
                        let more = run.grow(f, &s, lambda);
                        his.push((run.periods(), run.estimate.map_or(f64::NAN, |e| e.hi)));
                        if !more {
                            break;
                        }
                    }
                    rows.push((his, run.estimate.map_or(f64::NAN, |e| e.amplitude)));
                }
            }
        }
    }
    println!("## What the race's drop factors rest on\n");
    println!(
        "`cargo run --release --example race_drop` (module doc): the 45 curves of \
         `configs/frequency-response.toml` (nine designs, five cases each), {} motions that are \
         not periodic, each measured as the race measures it until it meets its tolerance or \
         its cap. The ratio of its final life amplitude to the upper end of its 90 % interval \
         after the first periods:\n",
        rows.len()
    );
    println!(
        "| after (periods) | motions | largest ratio | 99th percentile | median | drop factor | ratios above it |"
    );
    println!("|---|---|---|---|---|---|---|");
    for n in [2000, 4000, 8000, 16000] {
        let mut r = ratios(&rows, n);
        r.sort_by(f64::total_cmp);
        if r.is_empty() {
            continue;
        }
        let q = |p: f64| r[((r.len() - 1) as f64 * p).round() as usize];
        let factor = DROPS
            .iter()
            .rev()
            .find(|(k, _)| n >= *k)
            .map_or(f64::INFINITY, |&(_, f)| f);
        println!(
            "| {n} | {} | {:.3} | {:.3} | {:.3} | {factor} | {} |",
            r.len(),
            q(1.0),
            q(0.99),
            q(0.5),
            r.iter().filter(|&&x| x > factor).count()
        );
    }
    println!(
        "\nA motion leaves the race only when its upper end times the drop factor \
         (`orbits::race::DROPS`) is below the leader's lower bound; the largest ratio is what \
         the factor must exceed."
    );
}
