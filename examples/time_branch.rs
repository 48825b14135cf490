//! Issue 16's speed figure: a point on a continued periodic branch against today's transient run
//! at the same frequency, same build. The first design (Table I's M, K, C = 0.1 N s/m,
//! m = 5 g, d = 5 mm, e = 0.9, F0 = 0.1 N): the stable two-impact branch through r = 0.80 is
//! followed up to r = 0.86 by continuation; at each branch point the transient run from rest
//! (the sweep's default transient, 20 measured periods) is timed too. Prints JSON: per point
//! forcing periods and microseconds both ways, medians over `reps` repetitions.
//!
//! `cargo run --release --example time_branch -- [reps]`

use std::time::Instant;

use impactsweep::model::System;
use impactsweep::orbits::analytic::symmetric_period1;
use impactsweep::orbits::continuation::{ContSettings, Param, follow};
use impactsweep::orbits::map::Forcing;
use impactsweep::orbits::shoot::{Newton, orbit_at, solve};
use impactsweep::sim::{Drive, Harmonic, NoProbe, Request, SolverSettings, simulate_harmonic};

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
        omega: 0.8 * sys.omega(),
        sys,
        F0: 0.1,
        settings: SolverSettings::default(),
    };
    // The orbit at r = 0.8: Masri and Caughey's symmetric orbit (stable there), polished by
    // Newton.
    let scene = |r: f64| Harmonic {
        F0: 0.1,
        drive: Drive::Ratio(r),
        ..Harmonic::default()
    };
    let seed = symmetric_period1(&sys, f.F0, f.omega)
        .into_iter()
        .rfind(|o| o.admissible)
        .expect("the symmetric orbit at r = 0.8");
    let (_, st) = solve(&f, 1, &seed.section, &Newton::default());
    let orbit =
        orbit_at(&f, 1, &st.expect("newton"), &Newton::default()).expect("an impacting orbit");
    let cont = ContSettings {
        range: (0.8, 0.86),
        h0: 0.005,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 400,
        switch_pd: false,
    };
    let mut times = Vec::new();
    let mut branch = None;
    for _ in 0..reps {
        let t = Instant::now();
        let b = follow(&f, &orbit, Param::Ratio, &cont).remove(0);
        times.push(t.elapsed().as_secs_f64());
        branch = Some(b);
    }
    let b = branch.expect("reps >= 1");
    let n = b.points.len() as f64;
    let cont_us = median(times) / n * 1e6;
    let cont_periods = b.periods as f64 / n;
    // The transient runs at the branch's frequencies.
    let mut tr_us = Vec::new();
    let mut tr_periods = Vec::new();
    for p in &b.points {
        let mut ts = Vec::new();
        let mut periods = 0;
        for _ in 0..reps {
            let t = Instant::now();
            let rec = simulate_harmonic(
                &sys,
                &f.settings,
                &Request::default(),
                &scene(p.r),
                None,
                &mut NoProbe,
            );
            ts.push(t.elapsed().as_secs_f64());
            periods = rec.n_trans + rec.n_meas;
        }
        tr_us.push(median(ts) * 1e6);
        tr_periods.push(periods as f64);
    }
    let tr_us_m = median(tr_us);
    let tr_p_m = median(tr_periods);
    println!(
        "{{\"points\": {}, \"continuation_us_per_point\": {cont_us:.1}, \"continuation_periods_per_point\": {cont_periods:.1}, \"transient_us_per_point\": {tr_us_m:.1}, \"transient_periods_per_point\": {tr_p_m:.1}, \"ratio_time\": {:.1}, \"ratio_periods\": {:.1}, \"reps\": {reps}}}",
        b.points.len(),
        tr_us_m / cont_us,
        tr_p_m / cont_periods
    );
}
