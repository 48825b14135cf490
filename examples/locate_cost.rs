//! Issue 24's cost figures: what locating a bifurcation costs against an ordinary continuation
//! point, and what a point of a two-parameter bifurcation curve costs. The study (Table I's M, K, C = 0.1 N s/m, m = 5 g, d = 5 mm, e = 0.9,
//! F0 = 0.1 N, r = 0.85 … 1.15 by 0.01, 48 census starts): the census finds the periodic
//! attractors, and every branch through them is followed as `reduce` follows it (the doubled
//! branches included), `reps` times. Prints JSON: points, located points, forcing periods and
//! wall time split between continuation steps and locating (time split in proportion to the
//! periods simulated, which is where the time goes: every period is one evaluation of the map);
//! then every located fold, doubling and Neimark–Sacker point followed in `(r, d)` over
//! d = 4.5 … 5.5 mm (grid 4.5, 5, 5.5 mm): curve points, periods and wall time per point; then
//! every located grazing the same way.
//!
//! `cargo run --release --example locate_cost -- [reps]`

use std::time::Instant;

use impactsweep::model::System;
use impactsweep::orbits::attractors::SteadyKind;
use impactsweep::orbits::census::CensusSettings;
use impactsweep::orbits::continuation::{Branch, ContSettings, Label, Param, follow};
use impactsweep::orbits::map::Forcing;
use impactsweep::orbits::response::{MAX_BRANCHES, analyse, covers, orbit_from_section};
use impactsweep::orbits::twopar::{self, Axis, Seed};
use impactsweep::sim::SolverSettings;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let sys = System {
        m: 0.005,
        d: 0.005,
        e: 0.9,
        C: 0.1,
        x0: 0.0,
        v0: 0.0,
        ..System::TABLE_I
    };
    let f = Forcing {
        omega: 0.85 * sys.omega(),
        sys,
        F0: 0.1,
        settings: SolverSettings::default(),
    };
    let values: Vec<(u64, f64)> = (0..=30).map(|i| (i, 0.85 + 0.01 * i as f64)).collect();
    let census = CensusSettings {
        starts: 48,
        max_periods: 2000,
        handover: 1e-3,
        window: 200,
        seed: 1,
        point: 0,
        spent0: 0,
    };
    let resp = analyse(&f, 0, &[0.0; 4], &values, &census);
    let seeds: Vec<_> = resp
        .attractors
        .iter()
        .filter(|a| a.kind == SteadyKind::Periodic && a.impacts_per_period > 0.0)
        .filter_map(|a| {
            let g = f.at_ratio(a.run.r);
            orbit_from_section(&g, &a.section, a.period).map(|o| (g, o))
        })
        .collect();
    let cont = ContSettings {
        range: (0.85, 1.15),
        h0: 0.01 / 0.85,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 400,
        switch_pd: true,
    };
    let mut times = Vec::new();
    let mut branches: Vec<Branch> = Vec::new();
    for _ in 0..reps {
        let t = Instant::now();
        let mut followed: Vec<Branch> = Vec::new();
        for (g, o) in &seeds {
            if followed.len() >= MAX_BRANCHES {
                break;
            }
            if followed.iter().any(|b| covers(b, g, o, Param::Ratio)) {
                continue;
            }
            followed.extend(follow(g, o, Param::Ratio, &cont));
        }
        times.push(t.elapsed().as_secs_f64());
        branches = followed;
    }
    let points: usize = branches.iter().map(|b| b.points.len()).sum();
    let located: u32 = branches.iter().map(|b| b.located).sum();
    let periods: u64 = branches.iter().map(|b| b.periods).sum();
    let locating: u64 = branches.iter().map(|b| b.periods_locating).sum();
    let seconds = median(times);
    let plain = points - located as usize;
    let per_period = seconds / periods as f64;
    println!(
        "{{\"branches\": {}, \"points\": {points}, \"located\": {located}, \"periods\": {periods}, \
         \"periods_locating\": {locating}, \"seconds\": {seconds:.4}, \
         \"periods_per_point\": {:.1}, \"periods_per_located\": {:.1}, \
         \"us_per_point\": {:.1}, \"us_per_located\": {:.1}, \"locating_share\": {:.3}}}",
        branches.len(),
        (periods - locating) as f64 / plain as f64,
        locating as f64 / located.max(1) as f64,
        (periods - locating) as f64 / plain as f64 * per_period * 1e6,
        locating as f64 / located.max(1) as f64 * per_period * 1e6,
        locating as f64 / periods as f64,
    );
    // Two-parameter curves from every located SN, PD and NS, then from every located grazing.
    for kinds in [&[Label::SN, Label::PD, Label::NS][..], &[Label::GR][..]] {
        curve_cost(&f, &branches, kinds, reps);
    }
}

/// Follows every located point of `kinds` on `branches` in (r, d) and prints the cost per curve
/// point (median wall time over `reps`).
fn curve_cost(f: &Forcing, branches: &[Branch], kinds: &[Label], reps: usize) {
    let seeds2: Vec<Seed> = branches
        .iter()
        .flat_map(|b| b.points.iter())
        .filter(|p| p.located && kinds.contains(&p.label))
        .map(|p| Seed {
            f: f.at_ratio(p.r),
            s: p.s,
            period: p.period,
            label: p.label,
        })
        .collect();
    let mut times2 = Vec::new();
    let (mut curves, mut curve_points, mut curve_periods) = (0usize, 0usize, 0u64);
    for _ in 0..reps {
        let t = Instant::now();
        (curves, curve_points, curve_periods) = (0, 0, 0);
        for s in &seeds2 {
            if let Some(c) = twopar::follow(
                s,
                Axis::D,
                (0.0045, 0.0055),
                (0.85, 1.15),
                &[0.0045, 0.005, 0.0055],
            ) {
                curves += 1;
                curve_points += c.points.len();
                curve_periods += c.periods;
            }
        }
        times2.push(t.elapsed().as_secs_f64());
    }
    let seconds2 = median(times2);
    let names: Vec<&str> = kinds.iter().map(|k| k.name()).collect();
    println!(
        "{{\"kinds\": \"{}\", \"curves\": {curves}, \"curve_points\": {curve_points}, \
         \"curve_periods\": {curve_periods}, \"curve_seconds\": {seconds2:.4}, \
         \"periods_per_curve_point\": {:.1}, \"us_per_curve_point\": {:.1}}}",
        names.join(","),
        curve_periods as f64 / curve_points.max(1) as f64,
        seconds2 / curve_points.max(1) as f64 * 1e6,
    );
}
