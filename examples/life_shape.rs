//! What a known tail shape would buy the design life: the most any estimate that shares the
//! shape (for example along a chaotic plateau of a curve) can save against today's, which fits
//! the shape of every motion on its own (`stats::extremes::life_pot`, docs/scenes.md).
//!
//! On the nine ideal curves of `configs/frequency-response.toml` every motion that is not
//! periodic is measured as the race measures it (2,000 periods, then doubling) until its 90 %
//! interval meets `life_tol` (5 %) or the cap (20,000 periods). After each window its interval
//! is computed three ways, on the same threshold and cluster maxima:
//!
//! * **fitted**: today's, the shape fitted with the scale (profile likelihood over both);
//! * **known shape**: the shape fixed at the motion's own final fitted shape (an oracle: no
//!   shared estimate can know it better), the interval from the scale's likelihood alone;
//! * **exponential**: the shape fixed at 0 (the largest the bounded-tail rule allows).
//!
//! Prints, per way, the motions whose interval meets the tolerance after each window and the
//! periods that refining every motion until it does (or reaches the cap) would take: the
//! saving a shared shape can buy at most. Prints `results/life_shape.md`.
//!
//! `cargo run --release --example life_shape > results/life_shape.md`

#[path = "showcase/curve.rs"]
mod showcase;

use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::brent::{BrentOpt, BrentRoot};
use impactsweep::orbits::census::Kind;
use impactsweep::orbits::life::{LifeRun, cluster_run};
use impactsweep::orbits::race::settings;
use impactsweep::stats::extremes::{CHI2_90, Gpd, choose_threshold, growth};
use rayon::prelude::*;
use showcase::{ShowcaseCurve, showcase_curve};

/// The windows after which the intervals are compared.
const WINDOWS: [u64; 5] = [2000, 4000, 8000, 16000, 20000];

/// The relative half-width of the 90 % interval of the life amplitude with the shape fixed at
/// `xi`: the excesses' likelihood in the scale alone, the life amplitude `u + sigma g(m, xi)`
/// linear in it. NaN when it cannot be made.
fn known_shape(y: &[f64], u: f64, m: f64, xi: f64) -> f64 {
    struct C<'a>(&'a [f64], f64);
    impl CostFunction for C<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, ls: &f64) -> Result<f64, Error> {
            let v = Gpd {
                sigma: ls.exp(),
                xi: self.1,
            }
            .nll(self.0);
            Ok(if v.is_finite() { v } else { 1e300 })
        }
    }
    let ymax = y.iter().fold(0.0f64, |a, &b| a.max(b));
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    // The support needs sigma > -xi ymax.
    let lo = if xi < 0.0 {
        (-xi * ymax).ln() + 1e-9
    } else {
        (mean * 1e-3).ln()
    };
    let hi = (mean * 1e3).ln().max(lo + 1.0);
    let Some(ls) = Executor::new(C(y, xi), BrentOpt::new(lo, hi))
        .configure(|s| s.max_iters(200))
        .run()
        .ok()
        .and_then(|r| r.state().get_best_param().copied())
    else {
        return f64::NAN;
    };
    let nll = |ls: f64| {
        Gpd {
            sigma: ls.exp(),
            xi,
        }
        .nll(y)
    };
    let best = nll(ls);
    let drop = |x: f64| 2.0 * (nll(x) - best) - CHI2_90;
    let root = |a: f64, b: f64| -> f64 {
        struct R<'a>(&'a dyn Fn(f64) -> f64);
        impl CostFunction for R<'_> {
            type Param = f64;
            type Output = f64;
            fn cost(&self, x: &f64) -> Result<f64, Error> {
                Ok((self.0)(*x))
            }
        }
        Executor::new(R(&drop), BrentRoot::new(a, b, 1e-10))
            .configure(|s| s.max_iters(100))
            .run()
            .ok()
            .and_then(|r| r.state().get_best_param().copied())
            .unwrap_or(f64::NAN)
    };
    // Bracket each side in ln sigma.
    let side = |dir: f64| -> f64 {
        let mut step = 0.05;
        for _ in 0..60 {
            let x = ls + dir * step;
            if !drop(x).is_finite() || drop(x) > 0.0 {
                return if drop(x).is_finite() {
                    root(ls.min(x), ls.max(x))
                } else {
                    f64::NAN
                };
            }
            step *= 1.6;
        }
        f64::NAN
    };
    let (a, b) = (side(-1.0), side(1.0));
    let z = |ls: f64| u + ls.exp() * growth(m, xi);
    0.5 * (z(b) - z(a)) / z(ls)
}

/// One motion: after each window reached, its periods and the three relative half-widths.
type Motion = Vec<(u64, f64, f64, f64)>;

/// Every motion of the ideal curve of `design`, refined to its tolerance or cap.
fn curve(study: &impactsweep::study::Study, design: u64) -> Vec<Motion> {
    let ShowcaseCurve {
        censuses,
        race_points,
    } = showcase_curve(study, design, 0);
    let mut out = Vec::new();
    for (c, p) in censuses.iter().zip(&race_points) {
        let (Some(c), Some((f, h))) = (c, p) else {
            continue;
        };
        for a in &c.attractors {
            let Kind::NonPeriodic(w) = &a.kind else {
                continue;
            };
            if !a.window_amplitude.is_finite() {
                continue;
            }
            let mut s = settings(f, h);
            s.tol = 0.0; // run every motion to the cap; the tolerance is applied below
            let lambda = w.probe.map_or(f64::NAN, |p| p.lambda);
            let states = std::iter::once(a.section).chain(w.chains.iter().copied());
            let mut run = LifeRun::chains(states.collect());
            let mut seen = Vec::new();
            loop {
                let more = run.grow(f, &s, lambda);
                let chains: Vec<Vec<f64>> = run.chains.iter().map(|c| c.0.clone()).collect();
                seen.push((run.periods(), run.estimate, chains));
                if !more {
                    break;
                }
            }
            let Some(last) = seen.last().and_then(|l| l.1) else {
                continue;
            };
            let mut motion = Vec::new();
            for (n, est, chains) in &seen {
                let Some(e) = est else { continue };
                let refs: Vec<&[f64]> = chains.iter().map(Vec::as_slice).collect();
                let run_len = cluster_run(lambda);
                let Some((u, maxima, _)) = choose_threshold(&refs, run_len, 0.0) else {
                    continue;
                };
                let y: Vec<f64> = maxima.iter().map(|v| v - u).collect();
                let nu = maxima.len() as f64 / *n as f64;
                let m = s.n_life * nu / (-s.quantile.ln());
                motion.push((
                    *n,
                    e.rel_halfwidth(),
                    known_shape(&y, u, m, last.xi),
                    known_shape(&y, u, m, 0.0),
                ));
            }
            out.push(motion);
        }
    }
    out
}

fn main() {
    let study = showcase::study();
    let tol = match study.scene {
        impactsweep::sim::Scene::Harmonic(h) => h.life_tol,
        impactsweep::sim::Scene::Free => unreachable!("the showcase is harmonic"),
    };
    let motions: Vec<Motion> = (0..showcase::designs(&study))
        .into_par_iter()
        .flat_map(|d| curve(&study, d))
        .collect();
    println!("## What a known tail shape would buy the design life\n");
    println!(
        "`cargo run --release --example life_shape` (module doc): the {} motions that are not \
         periodic on the nine ideal curves of `configs/frequency-response.toml`, each measured \
         to the cap. The motions whose 90 % interval's half-width is within `life_tol` = {tol} \
         of the estimate after each window:\n",
        motions.len()
    );
    println!(
        "| after (periods) | motions measured | fitted shape (today) | known shape (oracle) | exponential (shape 0) |"
    );
    println!("|---|---|---|---|---|");
    let ways = 3;
    for n in WINDOWS {
        let at: Vec<&(u64, f64, f64, f64)> = motions
            .iter()
            .filter_map(|m| m.iter().find(|w| w.0 == n))
            .collect();
        let met = |k: usize| at.iter().filter(|w| [w.1, w.2, w.3][k] <= tol).count();
        println!(
            "| {n} | {} | {} | {} | {} |",
            at.len(),
            met(0),
            met(1),
            met(2)
        );
    }
    // Periods to refine every motion until its interval meets the tolerance, or the cap.
    let mut totals = vec![0u64; ways];
    for m in &motions {
        let cap = m.last().map_or(0, |w| w.0);
        for (k, total) in totals.iter_mut().enumerate() {
            *total += m
                .iter()
                .find(|w| [w.1, w.2, w.3][k] <= tol)
                .map_or(cap, |w| w.0);
        }
    }
    println!(
        "\nEvery motion refined until its interval meets the tolerance, or to the cap: {} \
         periods with the fitted shape (today's estimate), {} with a known shape ({:.2} of \
         today's), {} with shape 0 ({:.2}).",
        totals[0],
        totals[1],
        totals[1] as f64 / totals[0] as f64,
        totals[2],
        totals[2] as f64 / totals[0] as f64
    );
}
