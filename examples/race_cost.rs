//! What the race of the design life saves (issue 22): on the nine designs of
//! `configs/frequency-response.toml` (ideal case, 81 frequencies each, 8 starts, the study's
//! seed and design points), the census passes once, then the life amplitudes are measured two
//! ways from the same censuses: by the race (`orbits::race::race`, what the sweep does) and by
//! refining every motion that is not periodic to the tolerance (`race::refine_all`). Prints one
//! JSON object: per design and in all, the periods the census simulated, the motions that are
//! not periodic, the periods each way of measuring their lives spent, the wall time of each,
//! and whether the curve's design peak is the same both ways. Besides, every motion refined
//! without the life's floor (`LifeRun::without_floor`: every extremum located in every window),
//! its periods and wall time (`exact_periods`, `exact_s`): what the floor saves.
//!
//! `cargo run --release --example race_cost`

#[path = "showcase/curve.rs"]
mod showcase;

use impactsweep::orbits::census::{Census, Kind};
use impactsweep::orbits::life::LifeRun;
use impactsweep::orbits::map::Forcing;
use impactsweep::orbits::race::settings;
use impactsweep::orbits::race::{Serves, race, refine_all};
use impactsweep::sim::Harmonic;
use showcase::{ShowcaseCurve, showcase_curve};
use std::time::Instant;

/// Periods the life measurements spent, and the motions that are not periodic.
fn life_periods(cs: &[Option<Census>]) -> (u64, u64) {
    let mut periods = 0;
    let mut motions = 0;
    for a in cs.iter().flatten().flat_map(|c| &c.attractors) {
        if let Kind::NonPeriodic(w) = &a.kind {
            motions += 1;
            periods += w.life.map_or(0, |l| l.measured);
        }
    }
    (periods, motions)
}

/// The curve's design peak: the largest attractor amplitude over its frequencies.
fn peak(cs: &[Option<Census>]) -> f64 {
    cs.iter()
        .flatten()
        .flat_map(|c| &c.attractors)
        .map(|a| a.amplitude)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Every motion that is not periodic refined to its tolerance or cap without a floor: the
/// periods spent.
fn refine_exact(points: &[Option<(Forcing, Harmonic)>], cs: &[Option<Census>]) -> u64 {
    let mut periods = 0;
    for (c, p) in cs.iter().zip(points) {
        let (Some(c), Some((f, h))) = (c, p) else {
            continue;
        };
        for a in &c.attractors {
            if let Kind::NonPeriodic(w) = &a.kind
                && a.window_amplitude.is_finite()
            {
                let states = std::iter::once(a.section).chain(w.chains.iter().copied());
                let mut run = LifeRun::chains(states.collect()).without_floor();
                run.refine(f, &settings(f, h), w.probe.map_or(f64::NAN, |p| p.lambda));
                periods += run.periods();
            }
        }
    }
    periods
}

fn main() {
    let mut rows = Vec::new();
    let (mut census_total, mut race_total, mut all_total, mut motions_total) = (0, 0, 0, 0);
    let (mut race_s, mut all_s, mut exact_s, mut exact_total) = (0.0, 0.0, 0.0, 0);
    let study = showcase::study();
    for design in 0..showcase::designs(&study) {
        let ShowcaseCurve {
            censuses,
            race_points: rp,
        } = showcase_curve(&study, design, 0);
        let sys = impactsweep::plan::Plan::new(&study).point_system(design * study.curve_points());
        let (m, d) = (sys.m, sys.d);
        let census_periods: u64 = censuses.iter().flatten().map(|c| c.periods).sum();
        let mut raced = censuses.clone();
        let t = Instant::now();
        race(&rp, &mut raced, Serves::Curve);
        let t_race = t.elapsed().as_secs_f64();
        let mut all = censuses.clone();
        let t = Instant::now();
        refine_all(&rp, &mut all);
        let t_all = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let p_exact = refine_exact(&rp, &censuses);
        let t_exact = t.elapsed().as_secs_f64();
        let (p_race, motions) = life_periods(&raced);
        let (p_all, _) = life_periods(&all);
        rows.push(format!(
                "{{\"m\": {m}, \"d\": {d}, \"census_periods\": {census_periods}, \"motions\": {motions}, \"race_periods\": {p_race}, \"all_periods\": {p_all}, \"race_s\": {t_race:.3}, \"all_s\": {t_all:.3}, \"exact_periods\": {p_exact}, \"exact_s\": {t_exact:.3}, \"peak_race\": {:.6e}, \"peak_all\": {:.6e}}}",
                peak(&raced),
                peak(&all)
            ));
        census_total += census_periods;
        race_total += p_race;
        all_total += p_all;
        motions_total += motions;
        race_s += t_race;
        all_s += t_all;
        exact_total += p_exact;
        exact_s += t_exact;
    }
    println!(
        "{{\"designs\": [{}], \"census_periods\": {census_total}, \"motions\": {motions_total}, \"race_periods\": {race_total}, \"all_periods\": {all_total}, \"race_s\": {race_s:.3}, \"all_s\": {all_s:.3}, \"exact_periods\": {exact_total}, \"exact_s\": {exact_s:.3}}}",
        rows.join(", ")
    );
}
