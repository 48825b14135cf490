//! What the race's drop factors rest on (`orbits::race::DROPS`): on the nine designs of
//! `configs/frequency-response.toml` and their four cases each (m and d 1 g and 1 mm off: 45
//! curves of 81 frequencies, 8 starts, the ideal case's design points), every motion that is
//! not periodic is measured as the race measures it (2,000 periods, then doubling) until it
//! meets its tolerance or its cap, and its final life amplitude is compared with the upper end
//! of its 90 % interval after 2,000, 4,000, 8,000 and 16,000 periods. Then the race itself
//! (`orbits::race::race`, what the sweep runs) measures the same curves, and the two decisions
//! it serves are compared with what refining every motion gives: each curve's design peak (its
//! largest attractor amplitude), and at each frequency whether the damper helps (the
//! frequency's largest attractor amplitude below the linear amplitude there, as `reduce` reads
//! it). Prints `results/race_drop.md`; with `--seed N` the study's seed is `N` (other census
//! starts, so other motions: a sample the factors were not read from); with `--config PATH`
//! another harmonic study's curves (every design, every case).
//!
//! `cargo run --release --example race_drop > results/race_drop.md`
//! `cargo run --release --example race_drop -- --seed 7 > results/race_drop_seed7.md`
//! `cargo run --release --example race_drop -- --config configs/design-map.toml > results/race_drop_design_map.md`

#[path = "showcase/curve.rs"]
mod showcase;

use impactsweep::orbits::census::{Census, Kind};
use impactsweep::orbits::life::LifeRun;
use impactsweep::orbits::map::Forcing;
use impactsweep::orbits::race::{drop_factor, race, settings};
use impactsweep::reduce::forced::HELP_TOL;
use rayon::prelude::*;
use showcase::{ShowcaseCurve, showcase_curve};

/// One motion: its interval after each refinement `(periods, lo, hi)` and its final amplitude.
type Motion = (Vec<(u64, f64, f64)>, f64);

/// What one curve gave: every motion refined, the design peak and life periods that way, and
/// the race's; the frequencies whose help decision differs between the two, of how many.
struct CurveOut {
    motions: Vec<Motion>,
    peak_all: f64,
    periods_all: u64,
    peak_race: f64,
    periods_race: u64,
    help_differs: usize,
    frequencies: usize,
}

/// Final life amplitude over the upper end (`upper`) or the lower end after `n` periods, for
/// every motion with both, sorted.
fn ratios(rows: &[Motion], n: u64, upper: bool) -> Vec<f64> {
    let mut r: Vec<f64> = rows
        .iter()
        .filter_map(|(his, fin)| {
            let &(_, lo, hi) = his.iter().find(|(p, _, _)| *p == n)?;
            let end = if upper { hi } else { lo };
            (end.is_finite() && end > 0.0 && fin.is_finite()).then(|| fin / end)
        })
        .collect();
    r.sort_by(f64::total_cmp);
    r
}

/// The largest attractor amplitude at each frequency (`None` without a census).
fn worst(cs: &[Option<Census>]) -> Vec<Option<f64>> {
    cs.iter()
        .map(|c| {
            c.as_ref().map(|c| {
                c.attractors
                    .iter()
                    .map(|a| a.amplitude)
                    .fold(f64::NEG_INFINITY, f64::max)
            })
        })
        .collect()
}

/// Whether the damper helps at a frequency whose largest amplitude is `a` (`reduce`'s rule).
fn helps(a: f64, f: &Forcing) -> bool {
    a / f.sys.linear_amplitude(f.F0, f.ratio()) < 1.0 - HELP_TOL
}

/// The periods the race's life measurements spent on a curve.
fn life_periods(cs: &[Option<Census>]) -> u64 {
    cs.iter()
        .flatten()
        .flat_map(|c| &c.attractors)
        .filter_map(|a| match &a.kind {
            Kind::NonPeriodic(w) => w.life.map(|l| l.measured),
            Kind::Periodic(_) => None,
        })
        .sum()
}

/// Every motion of the curve refined to its tolerance or cap, step by step; then the race.
fn curve(study: &impactsweep::study::Study, design: u64, case: u32) -> CurveOut {
    let ShowcaseCurve {
        censuses: cs,
        race_points: rp,
    } = showcase_curve(study, design, case);
    let mut motions = Vec::new();
    let mut periods_all = 0;
    let mut all = cs.clone();
    for (c, p) in all.iter_mut().zip(&rp) {
        let Some(c) = c else { continue };
        for a in &mut c.attractors {
            let (Kind::NonPeriodic(w), Some((f, h))) = (&a.kind, p) else {
                continue;
            };
            if !a.window_amplitude.is_finite() {
                continue;
            }
            let s = settings(f, h);
            let lambda = w.probe.map_or(f64::NAN, |p| p.lambda);
            let states = std::iter::once(a.section).chain(w.chains.iter().copied());
            let mut run = LifeRun::chains(states.collect());
            let mut his = Vec::new();
            loop {
                let more = run.grow(f, &s, lambda);
                let (lo, hi) = run.estimate.map_or((f64::NAN, f64::NAN), |e| (e.lo, e.hi));
                his.push((run.periods(), lo, hi));
                if !more {
                    break;
                }
            }
            periods_all += run.periods();
            motions.push((his, run.estimate.map_or(f64::NAN, |e| e.amplitude)));
            if let Some(e) = run.estimate {
                a.amplitude = e.amplitude.max(a.window_amplitude);
            }
        }
    }
    let mut raced = cs;
    race(&rp, &mut raced);
    let (w_all, w_race) = (worst(&all), worst(&raced));
    let mut help_differs = 0;
    let mut frequencies = 0;
    for ((a, b), p) in w_all.iter().zip(&w_race).zip(&rp) {
        if let (Some(a), Some(b), Some((f, _))) = (a, b, p) {
            frequencies += 1;
            help_differs += usize::from(helps(*a, f) != helps(*b, f));
        }
    }
    let peak = |w: &[Option<f64>]| w.iter().flatten().fold(f64::NEG_INFINITY, |m, &a| m.max(a));
    CurveOut {
        motions,
        peak_all: peak(&w_all),
        periods_all,
        peak_race: peak(&w_race),
        periods_race: life_periods(&raced),
        help_differs,
        frequencies,
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut study = match args.iter().position(|a| a == "--config") {
        Some(i) => {
            let path = std::path::Path::new(args.get(i + 1).expect("--config takes a path"));
            impactsweep::study::Study::load(path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        }
        None => showcase::study(),
    };
    if let Some(i) = args.iter().position(|a| a == "--seed") {
        study.seed = args
            .get(i + 1)
            .and_then(|s| s.parse().ok())
            .expect("--seed takes a whole number");
    }
    let cases = study.cases.len() as u32;
    let curves: Vec<(u64, u32)> = (0..showcase::designs(&study))
        .flat_map(|d| (0..cases).map(move |c| (d, c)))
        .collect();
    let outs: Vec<CurveOut> = curves
        .par_iter()
        .map(|&(design, case)| curve(&study, design, case))
        .collect();
    let rows: Vec<Motion> = outs.iter().flat_map(|o| o.motions.clone()).collect();
    print_ratios(&study, outs.len(), &rows);
    print_race(&outs);
}

/// The ratios' table (module doc).
fn print_ratios(study: &impactsweep::study::Study, curves: usize, rows: &[Motion]) {
    println!(
        "## What the race's drop factors rest on (seed {})\n",
        study.seed
    );
    println!(
        "`cargo run --release --example race_drop` (module doc): the {} curves of study `{}` \
         (every design and case) with `seed = {}`, {} motions that are not periodic, each \
         measured as the race measures it until it meets its tolerance or its cap. The ratio of \
         its final life amplitude to the upper end of its 90 % interval after the first \
         periods, and to its lower end:\n",
        curves,
        study.name,
        study.seed,
        rows.len()
    );
    println!(
        "| after (periods) | motions | largest ratio | 99.5th percentile | 99th percentile | median | drop factor k | ratios above k | to the lower end: smallest | 0.5th percentile | ratios below 1/k |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for n in [2000, 4000, 8000, 16000] {
        let r = ratios(rows, n, true);
        let l = ratios(rows, n, false);
        if r.is_empty() || l.is_empty() {
            continue;
        }
        let q = |v: &[f64], p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
        let k = drop_factor(n).unwrap_or(f64::INFINITY);
        println!(
            "| {n} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {k} | {} | {:.3} | {:.3} | {} |",
            r.len(),
            q(&r, 1.0),
            q(&r, 0.995),
            q(&r, 0.99),
            q(&r, 0.5),
            r.iter().filter(|&&x| x > k).count(),
            q(&l, 0.0),
            q(&l, 0.005),
            l.iter().filter(|&&x| x < 1.0 / k).count()
        );
    }
    println!(
        "\nA motion leaves the race when its interval widened by the drop factor k \
         (`orbits::race::DROPS`), `[lo / k, hi k]`, is below the leader's lower bound and does \
         not hold the linear amplitude at its frequency. A ratio outside `[1/k, k]` is a motion \
         that could leave the race too early; what that costs is whether a decision moves \
         (below)."
    );
}

/// The race against refining every motion, per curve (module doc).
fn print_race(outs: &[CurveOut]) {
    let same = outs.iter().filter(|o| o.peak_race == o.peak_all).count();
    let lowest = outs
        .iter()
        .map(|o| o.peak_race / o.peak_all)
        .fold(f64::INFINITY, f64::min);
    let highest = outs
        .iter()
        .map(|o| o.peak_race / o.peak_all)
        .fold(f64::NEG_INFINITY, f64::max);
    let race: u64 = outs.iter().map(|o| o.periods_race).sum();
    let all: u64 = outs.iter().map(|o| o.periods_all).sum();
    let differs: usize = outs.iter().map(|o| o.help_differs).sum();
    let frequencies: usize = outs.iter().map(|o| o.frequencies).sum();
    println!("\n### The race against refining every motion\n");
    println!(
        "| curves | design peak the same | race / all, lowest | highest | frequencies whose help decision differs | life periods, race | every motion refined | share |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    println!(
        "| {} | {same} | {lowest:.4} | {highest:.4} | {differs} of {frequencies} | {race} | {all} | {:.3} |",
        outs.len(),
        race as f64 / all as f64
    );
}
