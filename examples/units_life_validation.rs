//! The design life of several units against brute force (issue 68):
//! `results/units_life_validation.md`.
//!
//! Two chaotic points of the multi-unit showcase's structure (`configs/multi-unit.toml`: two
//! units sharing `m = 10 g`, clearances 0.5 and 1.5 cm, `e = 0.8`), each a one-frequency study
//! of 4 starts whose every start wanders. Three steps,
//! each its own subcommand, so that the long one runs once and its results are committed:
//!
//! * `brute NAME BLOCKS > results/units_life_validation/brute/NAME.csv`: `BLOCKS` independent
//!   runs on the motion: the state census start 0 of study seed 0 ended in, its main mass moved
//!   by `b` nm for block `b`, 2,000 periods run, then [`BLOCK`] periods whose per-period maxima
//!   of `|x|` are kept as the maxima of ten sub-blocks. The map of several units, period by
//!   period, as the design life measures.
//! * `estimate SEEDS [NAME] > results/units_life_validation/estimates.csv`: each point (or the
//!   one named) as a
//!   one-frequency study at study seeds `1..=SEEDS` (`A..B`: seeds `A` to `B`) and design lives
//!   of 10^6 and 10^7 periods, each run as the sweep runs a curve of one point (the census, then
//!   the race for its design life); one row per run: the life amplitude of the motion that is not
//!   periodic with the largest estimate (the design quantity), its interval, the periods
//!   measured and its starts.
//! * `report > results/units_life_validation.md`: both side by side. The brute-force median
//!   over `L` periods is the `0.5^(BLOCK / L)` quantile of the block maxima (max-stability,
//!   `F_L = F^(L / BLOCK)`), with a 90 % bootstrap interval (2,000 resamples of the blocks).
//!
//! `scripts/units_life_validation.sh` runs them.

use impactsweep::orbits::life::period_maxima;
use impactsweep::orbits::several::{UnitsRun, census_run_units, forced_run_units};
use impactsweep::orbits::units::map::UnitsMap;
use impactsweep::plan::Plan;
use impactsweep::sim::noise::mix64;
use impactsweep::sim::{Harmonic, NoProbe, Scene};
use impactsweep::study::Study;
use rayon::prelude::*;
use std::path::Path;

/// A validation point: its name and frequency ratio.
struct Point {
    name: &'static str,
    r: f64,
    why: &'static str,
}

const POINTS: [Point; 2] = [
    Point {
        name: "U1",
        r: 0.97,
        why: "below resonance: its 400-period window reads 0.50 cm, its life estimate over 1,000 h 0.78 cm",
    },
    Point {
        name: "U2",
        r: 1.0,
        why: "at the structure's resonance",
    },
];

/// Periods of a brute-force block, and its sub-blocks.
const BLOCK: u64 = 1_000_000;
const SUBS: u64 = 10;

/// The horizons validated (periods).
const HORIZONS: [f64; 2] = [1e6, 1e7];

/// The point's one-frequency study at study seed `seed` and a design life of `life` periods.
fn study(p: &Point, seed: u64, life: f64) -> Study {
    let omega = p.r * (400.0f64 / 0.1).sqrt();
    let design_life = life * std::f64::consts::TAU / omega;
    let text = format!(
        "[study]\nname = \"{}\"\nseed = {seed}\n\
         [system]\nM = 0.1\nK = 400.0\nC = 0.1\nm = 0.01\nd = 0.01\ne = 0.8\n\
         x0 = 0.0\nv0 = 0.0\ny0 = 0.0\nw0 = 0.0\nunits = 2\nd_spread = 0.5\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.1\nr = {}\nstarts = 4\nn_meas = 400\n\
         design_life = {design_life:e}\n",
        p.name, p.r
    );
    Study::parse(Path::new("units_life_validation.toml"), &text).expect("a valid study")
}

/// The study's one run: its system and scene.
fn run_of(s: &Study) -> (impactsweep::model::System, Harmonic) {
    let run = Plan::new(s).run(0, 0);
    let Scene::Harmonic(h) = run.scene else {
        panic!("not harmonic")
    };
    (run.system, h)
}

/// The census run (no race) of the point at study seed `seed`.
fn census_of(s: &Study) -> UnitsRun {
    let (sys, h) = run_of(s);
    census_run_units(
        &sys,
        &s.solver,
        &s.request,
        &h,
        None,
        &mut NoProbe,
        s.seed,
        0,
    )
}

fn brute(name: &str, blocks: u64) {
    let p = POINTS
        .iter()
        .find(|p| p.name == name)
        .expect("a point name");
    let s = study(p, 0, 1e6);
    let run = census_of(&s);
    let (f, _, c) = run.census.expect("a census");
    let start = c
        .motions
        .first()
        .and_then(|m| m.states.first())
        .cloned()
        .expect("a start that wanders");
    let map = UnitsMap(f);
    println!(
        "block,{}",
        (0..SUBS)
            .map(|k| format!("sub{k}"))
            .collect::<Vec<_>>()
            .join(",")
    );
    let rows: Vec<String> = (0..blocks)
        .into_par_iter()
        .map(|b| {
            let mut s0 = start.clone();
            s0[0] += b as f64 * 1e-9;
            let z = period_maxima(&map, &s0, 2000, BLOCK).expect("the simulator ran");
            let subs: Vec<String> = z
                .chunks((BLOCK / SUBS) as usize)
                .map(|c| format!("{:e}", c.iter().copied().fold(f64::NAN, f64::max)))
                .collect();
            format!("{b},{}", subs.join(","))
        })
        .collect();
    for r in rows {
        println!("{r}");
    }
}

fn estimate(seeds: std::ops::RangeInclusive<u64>, only: Option<&str>) {
    println!("point,seed,horizon,amplitude,lo,hi,periods,capped,starts");
    for p in POINTS.iter().filter(|p| only.is_none_or(|n| n == p.name)) {
        for seed in seeds.clone() {
            for &life in &HORIZONS {
                let s = study(p, seed, life);
                let (sys, h) = run_of(&s);
                let out = forced_run_units(
                    &sys,
                    &s.solver,
                    &s.request,
                    &h,
                    None,
                    &mut NoProbe,
                    s.seed,
                    0,
                );
                let (_, _, c) = out.census.expect("a census");
                // The design quantity: the motion of the largest estimate.
                let (m, l, e) = c
                    .motions
                    .iter()
                    .filter_map(|m| {
                        let l = m.life?;
                        Some((m, l, l.estimate?))
                    })
                    .max_by(|a, b| a.2.amplitude.total_cmp(&b.2.amplitude))
                    .expect("a motion that wanders, measured, with an estimate");
                println!(
                    "{},{seed},{life:e},{:e},{:e},{:e},{},{},{}",
                    p.name, e.amplitude, e.lo, e.hi, l.measured, l.capped, m.starts
                );
            }
        }
    }
}

/// The `q` quantile of `v` (sorted), linear between order statistics.
fn quantile(v: &[f64], q: f64) -> f64 {
    let h = q * (v.len() - 1) as f64;
    let (i, t) = (h.floor() as usize, h.fract());
    if i + 1 < v.len() {
        v[i] + t * (v[i + 1] - v[i])
    } else {
        v[i]
    }
}

/// The brute-force median over `horizon` periods from the block maxima `b`, with its 90 %
/// bootstrap interval.
fn truth(b: &[f64], horizon: f64) -> (f64, f64, f64) {
    let q = 0.5f64.powf(BLOCK as f64 / horizon);
    let mut s = b.to_vec();
    s.sort_by(f64::total_cmp);
    let mid = quantile(&s, q);
    let mut boots: Vec<f64> = (0..2000u64)
        .map(|k| {
            let mut r: Vec<f64> = (0..b.len() as u64)
                .map(|j| b[(mix64(k * 1_000_003 + j) % b.len() as u64) as usize])
                .collect();
            r.sort_by(f64::total_cmp);
            quantile(&r, q)
        })
        .collect();
    boots.sort_by(f64::total_cmp);
    (mid, quantile(&boots, 0.05), quantile(&boots, 0.95))
}

fn report() {
    let dir = Path::new("results/units_life_validation");
    let est = std::fs::read_to_string(dir.join("estimates.csv")).expect("estimates.csv");
    let rows: Vec<Vec<String>> = est
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    println!("# The design life of several units against brute force\n");
    println!(
        "Generated by `scripts/units_life_validation.sh` (`examples/units_life_validation.rs`): two \
         chaotic points of `configs/multi-unit.toml`'s structure with two units (clearances 0.5 and \
         1.5 cm, `m = 10 g` in all, `e = 0.8`, `F0 = 0.1` N), each a one-frequency study of 4 starts \
         whose every start wanders, its design-life estimate made as the sweep makes it (the census \
         of several units, then the race: docs/scenes.md, \"Several damper units\") at 20 study \
         seeds and two design lives, against brute force: independent blocks of 10^6 periods on the \
         same motion, the median over `L` periods being the `0.5^(10^6 / L)` quantile of the block \
         maxima (90 % bootstrap interval).\n"
    );
    println!(
        "| point | r | horizon (periods) | brute force (cm) [90 %] | estimates: median error | worst error | within 5 % | interval covers | median periods |\n|---|---|---|---|---|---|---|---|---|"
    );
    let mut counts = Vec::new();
    for p in &POINTS {
        let text = std::fs::read_to_string(dir.join("brute").join(format!("{}.csv", p.name)))
            .expect("the brute force");
        let blocks: Vec<f64> = text
            .lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .skip(1)
                    .map(|v| v.parse::<f64>().expect("a number"))
                    .fold(f64::NAN, f64::max)
            })
            .collect();
        counts.push((p.name, blocks.len()));
        for &h in &HORIZONS {
            let (t, lo, hi) = truth(&blocks, h);
            let mine: Vec<&Vec<String>> = rows
                .iter()
                .filter(|r| r[0] == p.name && r[2].parse::<f64>().ok() == Some(h))
                .collect();
            let num = |r: &Vec<String>, k: usize| r[k].parse::<f64>().expect("a number");
            let mut err: Vec<f64> = mine.iter().map(|r| num(r, 3) / t - 1.0).collect();
            let worst = err
                .iter()
                .copied()
                .fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
            let within = err.iter().filter(|e| e.abs() <= 0.05).count();
            let covers = mine
                .iter()
                .filter(|r| num(r, 4) <= t && t <= num(r, 5))
                .count();
            let mut periods: Vec<f64> = mine.iter().map(|r| num(r, 6)).collect();
            err.sort_by(f64::total_cmp);
            periods.sort_by(f64::total_cmp);
            println!(
                "| {} | {} | {:e} | {:.4} [{:.4}, {:.4}] | {:+.1} % | {:+.1} % | {} of {} | {} of {} | {} |",
                p.name,
                p.r,
                h,
                100.0 * t,
                100.0 * lo,
                100.0 * hi,
                100.0 * quantile(&err, 0.5),
                100.0 * worst,
                within,
                mine.len(),
                covers,
                mine.len(),
                quantile(&periods, 0.5)
            );
        }
    }
    println!();
    for p in &POINTS {
        println!("- **{}** (r = {}): {}.", p.name, p.r, p.why);
    }
    println!(
        "- Brute force: {} blocks of 10^6 periods per point (`brute/*.csv`, each as ten sub-block maxima of 10^5 periods).",
        counts
            .iter()
            .map(|(n, b)| format!("{n} {b}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
}

fn seeds(arg: Option<&str>) -> std::ops::RangeInclusive<u64> {
    match arg {
        None => 1..=20,
        Some(a) => match a.split_once("..") {
            Some((x, y)) => x.parse().expect("a seed")..=y.parse().expect("a seed"),
            None => 1..=a.parse().expect("a seed count"),
        },
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("brute") => brute(
            args.get(1).expect("NAME"),
            args.get(2).map_or(200, |b| b.parse().expect("BLOCKS")),
        ),
        Some("estimate") => estimate(
            seeds(args.get(1).map(String::as_str)),
            args.get(2).map(String::as_str),
        ),
        Some("report") => report(),
        _ => {
            eprintln!("usage: units_life_validation brute NAME BLOCKS | estimate [SEEDS] | report")
        }
    }
}
