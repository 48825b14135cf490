//! Subset simulation (Au and Beck, "Estimation of small failure probabilities in high
//! dimensions by subset simulation", Probabilistic Engineering Mechanics 16 (2001) 263–277):
//! `P(Y(u) > b)` for a response `Y` of `n` independent standard normals `u` (a realization's
//! white-noise samples, [`crate::sim::random`]), down to probabilities far below what plain
//! Monte Carlo with the same number of runs can see.
//!
//! # Method
//! The failure event is reached through nested events `Y > b_1 > ... ` with `b_m = b`:
//! `P(Y > b) = P(Y > b_1) prod_i P(Y > b_{i+1} | Y > b_i)`.
//! * Level 0: `N` independent samples of `u`. Each intermediate threshold `b_i` is the
//!   `(1 - p0)` sample quantile of the level's responses (midway between the `N_c`-th and
//!   `N_c + 1`-th largest, `N_c = p0 N`), so each conditional probability is `p0` (0.1) by
//!   construction; the `N_c` samples above it seed the next level.
//! * Level `i + 1`: from each seed a Markov chain of `N_s = 1 / p0` states (the seed and
//!   `N_s - 1` new ones) whose stationary law is the normal law conditioned on `Y > b_i`, by
//!   the **modified Metropolis** algorithm: each component `u_j` gets a candidate
//!   `u_j + s e`, `e` uniform on `[-1, 1]`, accepted with probability
//!   `min(1, phi(candidate) / phi(u_j))` (one-dimensional Metropolis steps, which keep their
//!   acceptance in any number of dimensions); the candidate vector is then kept if its
//!   response exceeds `b_i`, else the chain repeats its state.
//! * The last level, where the `(1 - p0)` quantile would pass `b`, counts its samples above
//!   `b`: `P = p0^(m-1) N_b / N`.
//!
//! # Its coefficient of variation
//! Level 0 is plain Monte Carlo: `delta_0^2 = (1 - p_0) / (N p_0)`. At a later level the
//! samples are correlated along each chain, and
//! `delta_i^2 = (1 - p_i) / (N p_i) (1 + gamma_i)`,
//! `gamma_i = 2 sum_{k=1}^{N_s - 1} (1 - k / N_s) rho_i(k)`, with `rho_i(k) = R_i(k) / R_i(0)`
//! the correlation at lag `k` of the chains' indicators of the next event, estimated from the
//! chains themselves (`R_i(k) = sum_j sum_l I_{j,l} I_{j,l+k} / (N - k N_c) - p_i^2`; Au and
//! Beck eq. 29). The levels are taken as uncorrelated:
//! `delta = sqrt(sum delta_i^2)` ([`SubsetResult::cov`]); with fully correlated levels it
//! would be `sum delta_i` ([`SubsetResult::cov_upper`]), the bound Au and Beck give.
//!
//! # Determinism
//! Every chain (and every level-0 sample) draws from its own PCG-64 stream derived from (seed,
//! level, chain): the result is the same bits for any number of threads (the chains of a level
//! run in parallel on the current rayon pool).

use rand_core::Rng;
use rand_pcg::Pcg64;
use rayon::prelude::*;

use crate::numeric::{inverse_normal, mix64, open_uniform};

/// Settings of a subset simulation. Every field documents its default and range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubsetSettings {
    /// Samples per level `N`. Default 1000; a multiple of `1 / p0`, at least `10 / p0`.
    pub n: usize,
    /// Conditional probability of each level `p0`. Default 0.1 (Au and Beck's choice); in
    /// `[0.01, 0.5]` with `1 / p0` whole.
    pub p0: f64,
    /// Half-width `s` of the uniform component proposal (in standard deviations). Default 1.0.
    pub spread: f64,
    /// Most levels; the run ends `max_levels` with its estimate then. Default 20
    /// (`p0^20 = 1e-20`).
    pub max_levels: usize,
    /// Root of every stream.
    pub seed: u64,
}

impl Default for SubsetSettings {
    fn default() -> Self {
        SubsetSettings {
            n: 1000,
            p0: 0.1,
            spread: 1.0,
            max_levels: 20,
            seed: 0,
        }
    }
}

/// How a subset simulation ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SubsetOutcome {
    /// The last level reached the threshold.
    Converged,
    /// `max_levels` levels did not reach it: the estimate is an upper bound's worth of levels
    /// (`p0^max_levels` times the last fraction).
    MaxLevels,
    /// The settings are out of range (`n`, `p0`, `spread`, `dim`).
    Invalid,
}

/// One level of a subset simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    /// The level's threshold (`b` at the last level).
    pub threshold: f64,
    /// Its conditional probability estimate.
    pub p: f64,
    /// The chains' correlation factor `gamma` (0 at level 0).
    pub gamma: f64,
    /// Its coefficient of variation `delta_i`.
    pub delta: f64,
    /// Share of the candidate vectors accepted by the chains (NaN at level 0).
    pub acceptance: f64,
}

/// The estimate and what it rests on.
#[derive(Clone, Debug, PartialEq)]
pub struct SubsetResult {
    pub outcome: SubsetOutcome,
    /// `P(Y > b)`.
    pub p_f: f64,
    /// Its coefficient of variation with uncorrelated levels, `sqrt(sum delta_i^2)`.
    pub cov: f64,
    /// With fully correlated levels, `sum delta_i`.
    pub cov_upper: f64,
    pub levels: Vec<Level>,
    /// Responses evaluated.
    pub evaluations: u64,
    /// Responses that were not finite (counted as not failing: `Y = -inf`).
    pub non_finite: u64,
}

/// The stream of chain `j` at `level` of a run seeded `seed`.
fn stream(seed: u64, level: u64, chain: u64) -> Pcg64 {
    let mix = mix64;
    let a = mix(seed ^ 0x5355_4253_4554_5353);
    let b = mix(a ^ mix(level));
    let c = mix(b ^ mix(chain.wrapping_add(0x5EED)));
    Pcg64::new(
        (u128::from(a ^ c) << 64) | u128::from(b),
        (u128::from(mix(c)) << 64) | u128::from(mix(a ^ b)),
    )
}

#[inline]
fn normal(rng: &mut Pcg64) -> f64 {
    inverse_normal(open_uniform(rng.next_u64()))
}

/// A sample and its response.
#[derive(Clone, Debug)]
struct Sample {
    u: Vec<f64>,
    y: f64,
}

/// Estimates `P(Y(u) > b)` over `u` of `dim` independent standard normals (module doc). `y` is
/// the response; a NaN response counts as not failing (and in [`SubsetResult::non_finite`]).
pub fn subset_simulation<F>(dim: usize, b: f64, settings: &SubsetSettings, y: F) -> SubsetResult
where
    F: Fn(&[f64]) -> f64 + Sync,
{
    let s = settings;
    let ns = (1.0 / s.p0).round() as usize;
    let valid = dim > 0
        && (0.01..=0.5).contains(&s.p0)
        && ((1.0 / s.p0) - ns as f64).abs() < 1e-9
        && s.n >= 10 * ns
        && s.n.is_multiple_of(ns)
        && s.spread.is_finite()
        && s.spread > 0.0
        && s.max_levels >= 1;
    if !valid {
        return SubsetResult {
            outcome: SubsetOutcome::Invalid,
            p_f: f64::NAN,
            cov: f64::NAN,
            cov_upper: f64::NAN,
            levels: Vec::new(),
            evaluations: 0,
            non_finite: 0,
        };
    }
    let response = |u: &[f64]| {
        let v = y(u);
        if v.is_nan() { f64::NEG_INFINITY } else { v }
    };
    let nc = s.n / ns;
    // Level 0: plain Monte Carlo.
    let mut samples = level_zero(dim, s, &response);
    // Level 0's samples are independent; every later level's are `nc` chains.
    let mut chained = false;
    let mut acceptance = f64::NAN;
    let mut result = SubsetResult {
        outcome: SubsetOutcome::MaxLevels,
        p_f: 1.0,
        cov: 0.0,
        cov_upper: 0.0,
        levels: Vec::new(),
        evaluations: s.n as u64,
        non_finite: samples.iter().filter(|x| x.y == f64::NEG_INFINITY).count() as u64,
    };
    for level in 0..s.max_levels {
        let mut order: Vec<usize> = (0..s.n).collect();
        order.sort_by(|&i, &j| samples[j].y.total_cmp(&samples[i].y).then(i.cmp(&j)));
        let quantile = 0.5 * (samples[order[nc - 1]].y + samples[order[nc]].y);
        let last = quantile >= b || level + 1 == s.max_levels;
        let threshold = if last { b } else { quantile };
        let hits: Vec<bool> = samples.iter().map(|x| x.y > threshold).collect();
        let p = hits.iter().filter(|&&h| h).count() as f64 / s.n as f64;
        let gamma = if chained {
            correlation_factor(nc, &hits, p)
        } else {
            0.0
        };
        let delta = ((1.0 - p) / (s.n as f64 * p) * (1.0 + gamma)).sqrt();
        result.levels.push(Level {
            threshold,
            p,
            gamma,
            delta,
            acceptance,
        });
        result.p_f *= p;
        if last {
            if quantile >= b {
                result.outcome = SubsetOutcome::Converged;
            }
            break;
        }
        // The seeds (the nc largest responses, all above the threshold) and their chains.
        let seeds: Vec<Sample> = order[..nc].iter().map(|&i| samples[i].clone()).collect();
        let (next, accepted, bad) = grow(seeds, level as u64 + 1, threshold, s, &response);
        result.non_finite += bad;
        result.evaluations += (s.n - nc) as u64;
        acceptance = accepted as f64 / (s.n - nc) as f64;
        samples = next;
        chained = true;
    }
    let deltas = result.levels.iter().map(|l| l.delta);
    result.cov = deltas.clone().map(|d| d * d).sum::<f64>().sqrt();
    result.cov_upper = deltas.sum();
    if result.p_f == 0.0 {
        result.cov = f64::INFINITY;
        result.cov_upper = f64::INFINITY;
    }
    result
}

/// Level 0: `n` independent samples, sample `i` from its own stream.
fn level_zero<F: Fn(&[f64]) -> f64 + Sync>(
    dim: usize,
    s: &SubsetSettings,
    response: &F,
) -> Vec<Sample> {
    (0..s.n)
        .into_par_iter()
        .map(|i| {
            let mut rng = stream(s.seed, 0, i as u64);
            let u: Vec<f64> = (0..dim).map(|_| normal(&mut rng)).collect();
            let y = response(&u);
            Sample { u, y }
        })
        .collect()
}

/// The next level's samples: a chain of `1 / p0` states from each seed, chain `j` on its own
/// stream, in the seeds' order; with the candidates accepted and the non-finite responses.
fn grow<F: Fn(&[f64]) -> f64 + Sync>(
    seeds: Vec<Sample>,
    level: u64,
    threshold: f64,
    s: &SubsetSettings,
    response: &F,
) -> (Vec<Sample>, u64, u64) {
    let ns = (1.0 / s.p0).round() as usize;
    let grown: Vec<(Vec<Sample>, u64, u64)> = seeds
        .into_par_iter()
        .enumerate()
        .map(|(j, seed)| {
            let mut rng = stream(s.seed, level, j as u64);
            chain(seed, ns, threshold, s.spread, &mut rng, response)
        })
        .collect();
    let mut next = Vec::with_capacity(s.n);
    let (mut accepted, mut bad) = (0, 0);
    for (states, acc, b) in grown {
        accepted += acc;
        bad += b;
        next.extend(states);
    }
    (next, accepted, bad)
}

/// A modified-Metropolis chain of `ns` states from `seed` (module doc), conditioned on
/// `Y > threshold`: the states, the candidates accepted and the non-finite responses.
fn chain<F: Fn(&[f64]) -> f64>(
    seed: Sample,
    ns: usize,
    threshold: f64,
    spread: f64,
    rng: &mut Pcg64,
    response: &F,
) -> (Vec<Sample>, u64, u64) {
    let mut states = Vec::with_capacity(ns);
    let (mut accepted, mut bad) = (0, 0);
    let mut current = seed;
    let mut candidate = current.u.clone();
    for _ in 1..ns {
        for (c, &u) in candidate.iter_mut().zip(&current.u) {
            let xi = u + spread * (2.0 * open_uniform(rng.next_u64()) - 1.0);
            // Accept with probability min(1, phi(xi) / phi(u)).
            let ratio = (0.5 * (u * u - xi * xi)).exp();
            *c = if ratio >= 1.0 || open_uniform(rng.next_u64()) < ratio {
                xi
            } else {
                u
            };
        }
        let y = response(&candidate);
        if y == f64::NEG_INFINITY {
            bad += 1;
        }
        let next = if y > threshold {
            accepted += 1;
            Sample {
                u: candidate.clone(),
                y,
            }
        } else {
            current.clone()
        };
        states.push(std::mem::replace(&mut current, next));
    }
    states.push(current);
    (states, accepted, bad)
}

/// Au and Beck's `gamma` of one level (module doc): `hits` are the indicators of the next
/// event over the level's samples, chain after chain (`nc` chains of equal length, in the
/// order [`subset_simulation`] stores them), `p` their mean. Clamped at 0 (a negative estimate
/// is noise around independent chains).
fn correlation_factor(nc: usize, hits: &[bool], p: f64) -> f64 {
    let n = hits.len();
    let ns = n / nc;
    let r0 = p * (1.0 - p);
    if r0.is_nan() || r0 <= 0.0 {
        return 0.0;
    }
    let mut gamma = 0.0;
    for k in 1..ns {
        let mut sum = 0.0;
        for c in hits.chunks(ns) {
            for l in 0..ns - k {
                if c[l] && c[l + k] {
                    sum += 1.0;
                }
            }
        }
        let rk = sum / (n - k * nc) as f64 - p * p;
        gamma += 2.0 * (1.0 - k as f64 / ns as f64) * rk / r0;
    }
    gamma.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_indicators_correlation_of_independent_chains_is_small_and_of_repeats_large() {
        // Chains that repeat their first state are fully correlated: gamma = 2 sum (1 - k/ns).
        let ns = 10;
        let hits: Vec<bool> = (0..100).map(|i| (i / ns) % 3 == 0).collect();
        let p = hits.iter().filter(|&&h| h).count() as f64 / 100.0;
        let g = correlation_factor(10, &hits, p);
        let full: f64 = (1..ns).map(|k| 2.0 * (1.0 - k as f64 / ns as f64)).sum();
        assert!((g - full).abs() < 0.6, "{g} vs {full}");
        let alternating: Vec<bool> = (0..100).map(|i| i % 2 == 0).collect();
        assert_eq!(correlation_factor(10, &alternating, 0.5), 0.0);
    }

    #[test]
    fn a_probability_plain_monte_carlo_sees_needs_one_level() {
        // Y = u_0 > 0: p = 1/2 is above p0, the first level ends it.
        let r = subset_simulation(3, 0.0, &SubsetSettings::default(), |u| u[0]);
        assert_eq!(r.outcome, SubsetOutcome::Converged);
        assert_eq!(r.levels.len(), 1);
        assert!(
            (r.p_f - 0.5).abs() < 4.0 * (0.25f64 / 1000.0).sqrt(),
            "{r:?}"
        );
    }

    #[test]
    fn the_same_seed_gives_the_same_bits_on_any_thread_count() {
        let y = |u: &[f64]| u.iter().sum::<f64>() / (u.len() as f64).sqrt();
        let s = SubsetSettings {
            seed: 9,
            ..SubsetSettings::default()
        };
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| subset_simulation(20, 3.5, &s, y))
        };
        let one = run(1);
        assert_eq!(one.outcome, SubsetOutcome::Converged);
        for threads in [2, 3] {
            let other = run(threads);
            assert_eq!(other.p_f.to_bits(), one.p_f.to_bits());
            assert_eq!(other.cov.to_bits(), one.cov.to_bits());
        }
    }

    #[test]
    fn bad_settings_are_an_outcome() {
        let s = SubsetSettings {
            p0: 0.3,
            ..SubsetSettings::default()
        };
        let r = subset_simulation(3, 0.0, &s, |u| u[0]);
        assert_eq!(r.outcome, SubsetOutcome::Invalid);
    }
}
