//! The design life's candidate methods side by side on the same samples (issue 43):
//! `results/life_methods.md`, the losers' figures of BENCHMARKS.md.
//!
//! For each point of `life_validation`'s brute force and 20 seeds, 16 runs from random starts on
//! the attractor (2,000 transient periods each) give `n` per-period maxima in all; every method
//! estimates the median of the largest `|x|` over 10^6, 10^7 periods and 1,000 h from the same
//! sample:
//!
//! * **bounded POT** (chosen, `stats::extremes::life_pot`): peaks over three thresholds that
//!   keep the highest `k/2`, `k`, `2k` cluster maxima, the shape in `[-1/2, 0]`, the median of the
//!   three and the union of their intervals;
//! * **POT before** (the estimator this issue replaced): one threshold leaving `sqrt(n)/2`
//!   clusters from the 0.80 to the 0.998 quantile, the shape in `[-0.95, 0]`;
//! * **GEV**: block maxima of `n / 128` periods, the shape in `[-1/2, 0]`;
//! * **sample max**: the largest value of the sample, no extrapolation (no interval);
//! * **AMS** (`ams`, its own sampling): adaptive multilevel splitting on the maximum over
//!   `T = 100` periods, 100 clones, a clone branched with a perturbation `delta` (relative to 1 cm
//!   and to `omega` cm/s) at its parent's first crossing of the level; the tail
//!   `p_T(z)` it estimates gives the median over `L` periods where `p_T = 1 - 0.5^(T/L)`.
//!
//! `cargo run --release --example life_methods -- [N ...]` (default 32000 128000 512000)

#[path = "life_validation.rs"]
#[allow(dead_code)]
pub mod validation;

use impactsweep::orbits::life::cluster_run;
use impactsweep::orbits::map::{Forcing, Section, eval, eval_above};
use impactsweep::sim::noise::mix64;
use impactsweep::stats::extremes::{
    Life, LifeEstimate, MIN_CLUSTERS, XI_MAX, decluster, fit_gpd, life_from_excesses, life_gev,
    life_pot,
};
use rayon::prelude::*;
use std::path::Path;
use validation::{POINTS, Point};

fn unif(seed: u64, i: u64) -> f64 {
    ((mix64(seed ^ mix64(i)) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// 16 chains of `n / 16` per-period maxima from random starts on the point's attractor (a
/// start that settles on a periodic orbit is replaced by the next).
pub fn sample(f: &Forcing, seed: u64, n: u64) -> Vec<Vec<f64>> {
    let per = n / 16;
    let mut chains = Vec::new();
    let mut k = 0u64;
    while chains.len() < 16 {
        let batch: Vec<Option<Vec<f64>>> = (k..k + 16 - chains.len() as u64)
            .into_par_iter()
            .map(|b| {
                let s = mix64(seed.wrapping_mul(0x51_7CC1) ^ b);
                let start = [0.02 * (unif(s, 0) - 0.5), unif(s, 1) - 0.5, 0.0, 0.0];
                let st = eval(f, &start, 2000, false).end;
                let z = impactsweep::orbits::life::period_maxima(f, &st, 0, per)?;
                let tail = &z[z.len().saturating_sub(64)..];
                let mut v = tail.to_vec();
                v.sort_by(f64::total_cmp);
                v.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
                (v.len() > 8).then_some(z)
            })
            .collect();
        k += batch.len() as u64;
        chains.extend(batch.into_iter().flatten());
    }
    chains
}

/// The estimator before this issue: one threshold, the pooled quantile from 0.80 to 0.998 that
/// leaves `sqrt(n) / 2` clusters (at least 30), the shape in `[-0.95, 0]`.
fn pot_before(chains: &[&[f64]], run: usize, n_life: f64) -> Option<LifeEstimate> {
    let mut sorted: Vec<f64> = chains.iter().flat_map(|c| c.iter().copied()).collect();
    sorted.sort_by(f64::total_cmp);
    let target = (0.5 * (sorted.len() as f64).sqrt()).max(30.0);
    let probs = (0..=15)
        .map(|i| 0.80 + 0.01 * i as f64)
        .chain((1..=24).map(|i| 0.95 + 0.002 * i as f64));
    let mut best: Option<(f64, f64, Vec<f64>)> = None;
    for p in probs {
        let u = impactsweep::numeric::quantile_sorted(&sorted, p);
        let maxima: Vec<f64> = chains.iter().flat_map(|c| decluster(c, u, run)).collect();
        if maxima.len() < 30.max(MIN_CLUSTERS) {
            break;
        }
        let miss = (maxima.len() as f64 / target).ln().abs();
        if best.as_ref().is_none_or(|b| miss < b.0) {
            best = Some((miss, u, maxima));
        }
    }
    let (_, u, maxima) = best?;
    let y: Vec<f64> = maxima.iter().map(|v| v - u).collect();
    let fit = fit_gpd(&y, (-XI_MAX, 0.0))?;
    let life = Life {
        n_life,
        q: 0.5,
        xi_min: -XI_MAX,
        xi_max: 0.0,
    };
    life_from_excesses(&y, u, maxima.len() as f64 / sorted.len() as f64, life, fit)
}

/// Block maxima of `n / 128` periods with a GEV (module doc).
fn gev(chains: &[&[f64]], n_life: f64) -> Option<LifeEstimate> {
    let total: usize = chains.iter().map(|c| c.len()).sum();
    let b = (total / 128).max(1);
    let x: Vec<f64> = chains
        .iter()
        .flat_map(|c| {
            c.chunks_exact(b)
                .map(|w| w.iter().copied().fold(f64::MIN, f64::max))
        })
        .collect();
    life_gev(&x, b, Life::bounded(n_life, 0.5))
}

/// Adaptive multilevel splitting (module doc): the levels at tail probabilities `10^-1 ..`,
/// and the periods it simulated.
fn ams(f: &Forcing, seed: u64, delta: f64) -> (Vec<(f64, f64)>, u64) {
    const T: usize = 100;
    const N: usize = 100;
    struct C {
        z: Vec<f64>,
        s: Vec<Section>,
        score: f64,
    }
    let mut count = 0u64;
    let run = |start: Section, mut z: Vec<f64>, mut s: Vec<Section>, count: &mut u64| {
        let mut st = start;
        while z.len() < T {
            let e = eval_above(f, &st, 1, 0.0);
            *count += 1;
            st = e.end;
            z.push(e.amplitude);
            s.push(st);
        }
        let score = z.iter().copied().fold(f64::MIN, f64::max);
        C { z, s, score }
    };
    let sd = mix64(seed ^ 0xA5);
    let start = [0.02 * (unif(sd, 1) - 0.5), unif(sd, 2) - 0.5, 0.0, 0.0];
    let mut st = eval(f, &start, 2000, false).end;
    count += 2000;
    let mut clones: Vec<C> = Vec::new();
    for _ in 0..N {
        st = eval(f, &st, 50, false).end;
        count += 50;
        clones.push(run(st, Vec::new(), Vec::new(), &mut count));
    }
    let (w, d) = (f.omega, f.sys.d);
    let mut logp = 0.0f64;
    let mut curve = Vec::new();
    for it in 0..20_000u64 {
        let smin = clones.iter().map(|c| c.score).fold(f64::MAX, f64::min);
        let dead: Vec<usize> = (0..N).filter(|&i| clones[i].score <= smin).collect();
        let alive: Vec<usize> = (0..N).filter(|&i| clones[i].score > smin).collect();
        if alive.is_empty() || logp < -18.0 {
            break;
        }
        logp += ((N - dead.len()) as f64 / N as f64).ln();
        curve.push((logp, smin));
        for (q, &i) in dead.iter().enumerate() {
            let key = it * 64 + q as u64;
            let j = alive[(unif(sd ^ 0xABC, key) * alive.len() as f64) as usize];
            let t = clones[j]
                .z
                .iter()
                .position(|&v| v > smin)
                .expect("a crossing");
            let mut s0 = clones[j].s[t];
            let kk = key * 4;
            s0[0] += delta * 0.01 * (2.0 * unif(sd, kk) - 1.0);
            s0[1] += delta * 0.01 * w * (2.0 * unif(sd, kk + 1) - 1.0);
            s0[2] =
                (s0[2] + delta * 0.01 * (2.0 * unif(sd, kk + 2) - 1.0)).clamp(-0.5 * d, 0.5 * d);
            s0[3] += delta * 0.01 * w * (2.0 * unif(sd, kk + 3) - 1.0);
            let (z, s) = (clones[j].z[..=t].to_vec(), clones[j].s[..=t].to_vec());
            clones[i] = run(s0, z, s, &mut count);
        }
    }
    (curve, count)
}

/// The median of the largest of `l` periods from an AMS tail curve `(ln p_T, level)`.
fn ams_level(curve: &[(f64, f64)], l: f64) -> f64 {
    let target = (1.0 - 0.5f64.powf(100.0 / l)).ln();
    curve
        .iter()
        .find(|c| c.0 <= target)
        .map_or(f64::NAN, |c| c.1)
}

/// One method's results at one horizon over the seeds: errors (%) and intervals holding.
#[derive(Default)]
struct Tally {
    err: Vec<f64>,
    hold: usize,
    with_interval: usize,
}

impl Tally {
    fn add(&mut self, v: Option<(f64, f64, f64)>, truth: f64) {
        let Some((a, lo, hi)) = v else { return };
        self.err.push(100.0 * (a / truth - 1.0));
        if lo.is_finite() || hi.is_finite() {
            self.with_interval += 1;
            self.hold += usize::from(lo <= truth && truth <= hi);
        }
    }
    fn cell(&self) -> String {
        if self.err.is_empty() {
            return "–".into();
        }
        let lo = self.err.iter().copied().fold(f64::MAX, f64::min);
        let hi = self.err.iter().copied().fold(f64::MIN, f64::max);
        let med = impactsweep::numeric::median(&self.err);
        let cov = if self.with_interval > 0 {
            format!(", {} of {}", self.hold, self.with_interval)
        } else {
            String::new()
        };
        format!("{lo:.1} / {med:.1} / {hi:.1}{cov}")
    }
}

/// The brute-force medians of the point at 10^6, 10^7 periods and 1,000 h, `(periods, median)`.
pub fn truths(p: &Point, f: &Forcing) -> Option<[(f64, f64); 3]> {
    let text = std::fs::read_to_string(
        Path::new("results/life_validation/brute").join(format!("{}.json", p.name)),
    )
    .ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let blocks: Vec<f64> = v["blocks"]
        .as_array()?
        .iter()
        .map(|b| {
            b.as_array().map_or(f64::NAN, |s| {
                s.iter().filter_map(|x| x.as_f64()).fold(f64::MIN, f64::max)
            })
        })
        .collect();
    let life = 3.6e6 / f.period();
    let at = |l: f64| {
        (
            l,
            impactsweep::numeric::quantile(&blocks, 0.5f64.powf(1e6 / l)),
        )
    };
    Some([at(1e6), at(1e7), at(life)])
}

fn main() {
    let ns: Vec<u64> = {
        let a: Vec<u64> = std::env::args()
            .skip(1)
            .filter_map(|s| s.parse().ok())
            .collect();
        if a.is_empty() {
            vec![32_000, 128_000, 512_000]
        } else {
            a
        }
    };
    let only: Vec<String> = std::env::args()
        .skip(1)
        .filter(|s| s.parse::<u64>().is_err())
        .collect();
    println!(
        "| point | periods | horizon | bounded POT (chosen) | POT before | GEV | sample max |\n|---|---|---|---|---|---|---|"
    );
    for p in POINTS
        .iter()
        .filter(|p| only.is_empty() || only.iter().any(|o| o == p.name))
    {
        let f = validation::forcing_of(p);
        let Some(tr) = truths(p, &f) else { continue };
        for &n in &ns {
            let mut t: Vec<[Tally; 4]> = (0..3).map(|_| Default::default()).collect();
            for seed in 1..=20u64 {
                let chains = sample(&f, seed, n);
                let refs: Vec<&[f64]> = chains.iter().map(Vec::as_slice).collect();
                let run = cluster_run(1.0);
                for (h, &(l, truth)) in tr.iter().enumerate() {
                    let e3 = |e: Option<LifeEstimate>| e.map(|e| (e.amplitude, e.lo, e.hi));
                    t[h][0].add(e3(life_pot(&refs, run, Life::bounded(l, 0.5))), truth);
                    t[h][1].add(e3(pot_before(&refs, run, l)), truth);
                    t[h][2].add(e3(gev(&refs, l)), truth);
                    let mx = refs
                        .iter()
                        .flat_map(|c| c.iter().copied())
                        .fold(f64::MIN, f64::max);
                    t[h][3].add(Some((mx, f64::NAN, f64::NAN)), truth);
                }
            }
            for (h, name) in ["1e6", "1e7", "life"].iter().enumerate() {
                println!(
                    "| {} | {n} | {name} | {} | {} | {} | {} |",
                    p.name,
                    t[h][0].cell(),
                    t[h][1].cell(),
                    t[h][2].cell(),
                    t[h][3].cell()
                );
            }
        }
        if p.name == "P1" {
            for delta in [1e-4, 1e-3, 1e-2] {
                let mut t: Vec<Tally> = (0..3).map(|_| Default::default()).collect();
                let mut periods = Vec::new();
                let runs: Vec<(Vec<(f64, f64)>, u64)> = (1..=10u64)
                    .into_par_iter()
                    .map(|s| ams(&f, s, delta))
                    .collect();
                for (curve, count) in runs {
                    periods.push(count as f64);
                    for (h, &(l, truth)) in tr.iter().enumerate() {
                        let v = ams_level(&curve, l);
                        t[h].add(v.is_finite().then_some((v, f64::NAN, f64::NAN)), truth);
                    }
                }
                for (h, name) in ["1e6", "1e7", "life"].iter().enumerate() {
                    println!(
                        "| {} AMS delta {delta:e} (10 runs) | {:.0} | {name} | {} | | | |",
                        p.name,
                        impactsweep::numeric::median(&periods),
                        t[h].cell()
                    );
                }
            }
        }
    }
}
