//! The largest amplitude of a stationary irregular motion over a design life, from a sample of
//! its per-period maxima (docs/model.md, "The amplitude over a design life").
//!
//! # Peaks over a threshold
//! Let `z_k` be the largest `|x|` in forcing period `k`, `k = 1..n`. Above a high threshold `u`,
//! exceedances come in clusters (consecutive periods are correlated: on the rattling motions an
//! extreme is the top of a build-up of 10 to 30 periods), so they are **declustered** by runs: a
//! cluster ends after `run` periods below `u`, and only each cluster's maximum is kept. The
//! cluster maxima's excesses `y = z - u` follow a generalized Pareto law (Pickands; Coles, *An
//! Introduction to Statistical Modeling of Extreme Values*, ch. 4)
//!
//! ```text
//! P(Y > y | Y > 0) = (1 + xi y / sigma)^(-1/xi)        (exp(-y / sigma) at xi = 0)
//! ```
//!
//! and clusters arrive at `nu` per period. The largest value over `N` periods then has
//! `P(max_N <= z) = exp(-N nu (1 + xi (z - u) / sigma)^(-1/xi))`, and its quantile `q` is
//!
//! ```text
//! z_q = u + sigma (m^xi - 1) / xi,   m = N nu / (-ln q)          (u + sigma ln m at xi = 0).
//! ```
//!
//! `xi < 0` is a bounded tail with end point `u - sigma / xi`, which `z_q` approaches as `N`
//! grows. `(sigma, xi)` are fitted by maximum likelihood (argmin's Nelder–Mead on
//! `(ln sigma, xi)`), `nu` is the observed cluster rate.
//!
//! # The shape: bounded, and where the likelihood is regular
//! The main mass's excursion is bounded (the force's work over a period is bounded and the
//! damper and the impacts only dissipate), so `xi <= 0`. Brute force agrees (10^8 periods per
//! point, `results/life_validation.md`): the maxima approach an end point slowly, with a shape
//! near -0.35 to -0.4 once the threshold is high enough. The likelihood is regular only for
//! `xi > -1/2` (Smith 1985); below, the fit pins the end point at the sample's largest value
//! and its interval is far too narrow (measured: with the shape free down to -0.95, 12 to 14 of
//! 20 intervals held the brute-force value at the reference point, against 17 to 20 within
//! `[-1/2, 0]`). So the shape is fitted in [`Life::bounded`]'s `[-1/2, 0]`.
//!
//! # The thresholds
//! A threshold too low reaches into values that are not yet in the asymptotic tail: on the
//! rattling motions the local shape below about one exceedance in 10^4 periods is near 0 (a
//! sub-asymptotic, nearly exponential stretch) and only above it turns to -0.35 … -0.4, so a
//! low threshold extrapolates far too high (the estimates of 25 to 75 % too high that the
//! bundled study's ranking rested on). A threshold too high leaves too few clusters to fit.
//! The estimate therefore rests on a fixed number of cluster maxima, the highest ones, `k = 25`
//! whatever the sample's size ([`tail_sizes`]), so that a longer measurement raises the threshold
//! rather than lowering it: from `n` periods the middle fit's threshold is exceeded about `25 / n`
//! times a period. Three fits are made, with `k / 2`, `k` and `2 k` cluster maxima, and **the
//! estimate is their median**. The sub-asymptotic stretch reaches higher than one exceedance in
//! 10^4 periods: a count growing with the sample (`sqrt(n) / 4` in `[25, 100]`, 100 at 10^6
//! periods) extrapolated the slowest tail up to 10 % too high from 10^6 periods, where 25 stays
//! within 2.7 % over 20 seeds (`results/life_tail_sizes.md`).
//!
//! # The point value
//! Each fit's value is not the fitted law's quantile but its **posterior median** under Jeffreys's
//! prior for the generalized Pareto law, `pi(sigma, xi) = 1 / (sigma (1 + xi) sqrt(1 + 2 xi))`
//! (Castellanos & Cabras 2007), on the bounded shapes `[-1/2, 0]` ([`posterior_median`]). With 12
//! to 50 cluster maxima the likelihood's shape piles at the bound `-1/2` (at the slowest tail in
//! more than half the samples) and its quantile runs low; averaging over the shapes the data
//! allow removes that. On a law whose excesses are exactly generalized Pareto (shape -0.4, 25
//! maxima, 100 samples, a life of 10^7 periods; a test below): the likelihood's quantile median
//! -0.8 %, a flat prior on the shape +0.9 %, Jeffreys's -0.1 %, with 90 % of its errors within
//! 1.4 % against 2.1 %. Against brute force at the six points of `results/life_validation.md`
//! whose measurements run longest, 40 seeds each, the race emulated (`results/life_points.md`):
//! the largest error over the three horizons 11.7 % with the likelihood's quantile, 4.4 % with
//! Jeffreys's posterior median, every point's median error within 1 %. A shape range beyond
//! `[-1/2, 0]` (a general-purpose fit, [`Point::Posterior`]) keeps the likelihood's quantile.
//!
//! **The interval** is the union of the 90 % profile-likelihood intervals of those three fits and
//! of three more at the lower thresholds of the growing count ([`band_sizes`]), so that it carries
//! the threshold's own uncertainty. Few clusters alone give intervals too narrow where the shape
//! sits at its bound `-1/2`: a measurement that stops once its interval is within a tolerance then
//! stopped early, up to 11 % low (the race emulated on the same samples, the same file); with the
//! union it measures on, and every point's stopped estimate stayed within 5.1 %. (One threshold's
//! interval held the brute-force value in 12 to 16 of 20 samples at the reference point, the
//! union of three in 17 to 20.)
//!
//! **The interval** of one fit is the profile likelihood's: `z` is in the 90 % interval when
//! `2 (l_max - l_p(z)) <= 2.706` (the chi-square quantile with one degree of freedom), `l_p(z)`
//! the likelihood maximised over `xi` with `sigma` tied to `z` by the formula above. It is
//! asymmetric, as the tail is, and needs no resampling; the rate's own error is left out (it is
//! small beside the tail's: the relative error of `nu` is `1/sqrt(clusters)`, and `z_q` depends on
//! `nu` only through `ln m`).
//!
//! # Block maxima (the alternative, [`gev`])
//! The maxima of blocks of `b` periods follow a generalized extreme value law
//! `G(z) = exp(-(1 + xi (z - mu) / sigma)^(-1/xi))`, and the largest over `N` periods is the
//! largest of `N / b` blocks: `z_q = mu + sigma ((-ln q^(b/N))^(-xi) - 1) / xi`, with the same
//! profile-likelihood interval. It uses one value per block where the threshold method uses
//! every cluster above `u`, so from the same periods it is the less precise; it is here for
//! comparison (BENCHMARKS.md) and is tested like the other.

pub mod gev;
pub mod gpd;
mod life;

pub use gev::{Gev, fit_gev, life_gev};
pub use gpd::{
    Gpd, GpdFit, POSTERIOR_GRID, PosteriorGrid, ShapePrior, fit_gpd, growth, life_from_excesses,
    posterior_median, posterior_quantiles,
};
pub use life::{CHI2_90, Life, LifeEstimate, XI_BOUNDED};

/// Fewest cluster maxima a fit may use (below it the shape cannot be fitted).
pub const MIN_CLUSTERS: usize = 12;

/// The widest shape range any fit allows, `[-XI_MAX, XI_MAX]`: beyond, the likelihood is not
/// regular (at `xi <= -1` it is unbounded) and no response of a damped structure has so heavy
/// a tail.
pub const XI_MAX: f64 = 0.95;

/// The cluster maxima counts of the three fits the estimate is the median of (module doc): `k / 2`,
/// `k` and `2 k` with [`TAIL_CLUSTERS`] `= k`, whatever the sample's size.
pub fn tail_sizes() -> [usize; 3] {
    [
        (TAIL_CLUSTERS / 2).max(MIN_CLUSTERS),
        TAIL_CLUSTERS,
        2 * TAIL_CLUSTERS,
    ]
}

/// The middle estimate fit's count of cluster maxima (module doc).
pub const TAIL_CLUSTERS: usize = 25;

/// The cluster maxima counts of the three fits whose intervals widen the estimate's, from `n`
/// periods (module doc): `k / 2` (at least [`MIN_CLUSTERS`]), `k` and `2 k`, `k = sqrt(n) / 4`
/// clamped to `[25, 100]` (up to 10^4 periods the same as [`tail_sizes`]).
pub fn band_sizes(n: usize) -> [usize; 3] {
    let k = (0.25 * (n as f64).sqrt()).clamp(25.0, 100.0).round() as usize;
    [(k / 2).max(MIN_CLUSTERS), k, 2 * k]
}

/// The cluster maxima of the exceedances of `u` in `z`: a cluster ends after `run` consecutive
/// values at or below `u` (module doc).
pub fn decluster(z: &[f64], u: f64, run: usize) -> Vec<f64> {
    let mut out = Vec::new();
    let (mut current, mut below) = (f64::NEG_INFINITY, run);
    for &v in z {
        if v > u {
            if below >= run && current > u {
                out.push(current);
                current = f64::NEG_INFINITY;
            }
            current = current.max(v);
            below = 0;
        } else {
            below += 1;
        }
    }
    if current > u {
        out.push(current);
    }
    out
}

/// The sample quantile [`threshold_for`] starts from for `k` cluster maxima of `n` periods: low
/// enough to hold `k + 1` clusters of up to 20 exceedances each (a build-up of 10 to 30 periods),
/// or the median.
fn base_quantile(k: usize, n: usize) -> f64 {
    (1.0 - 20.0 * (k + 1) as f64 / n as f64).max(0.5)
}

/// The upper order statistics of a sample of `n` values: sorted ascending, those from rank
/// `offset = floor((n - 1) q_min)` up, the rest only counted. [`Upper::quantile`] at any
/// `q >= q_min` is [`crate::numeric::quantile_sorted`] of the whole sorted sample, bit for bit,
/// after a selection and a sort of the top instead of a sort of all (`O(n)` rather than
/// `O(n log n)`: the estimate of 10^6 periods reads its top 4,000).
#[derive(Clone, Debug, PartialEq)]
pub struct Upper {
    n: usize,
    offset: usize,
    top: Vec<f64>,
}

impl Upper {
    /// The upper order statistics of `values` (no NaN) from the quantile `q_min` up.
    pub fn new(mut values: Vec<f64>, q_min: f64) -> Upper {
        let n = values.len();
        let offset = Upper::rank(n, q_min).unwrap_or(0);
        if offset > 0 {
            values.select_nth_unstable_by(offset, f64::total_cmp);
            values.drain(..offset);
        }
        values.sort_unstable_by(f64::total_cmp);
        Upper {
            n,
            offset,
            top: values,
        }
    }

    /// `floor((n - 1) q)`, the lower rank [`crate::numeric::quantile_sorted`] reads (`None` when
    /// the sample is empty).
    fn rank(n: usize, q: f64) -> Option<usize> {
        (n > 0).then(|| ((n - 1) as f64 * q.clamp(0.0, 1.0)).floor() as usize)
    }

    /// Values in the sample.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether the sample is empty.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The upper order statistics [`fit_top`] reads for each count of cluster maxima in `ks`.
    pub fn for_fits(values: Vec<f64>, ks: impl IntoIterator<Item = usize>) -> Upper {
        let n = values.len();
        let q_min = ks
            .into_iter()
            .map(|k| base_quantile(k, n))
            .fold(1.0, f64::min);
        Upper::new(values, q_min)
    }

    /// The sample's quantile `q` as [`crate::numeric::quantile_sorted`] computes it; NaN when the
    /// sample is empty or `q` is below the `q_min` this was built for.
    pub fn quantile(&self, q: f64) -> f64 {
        match Upper::rank(self.n, q) {
            Some(lo) if lo >= self.offset => {
                crate::numeric::quantile_of_ranks(self.n, q, |i| self.top[i - self.offset])
            }
            _ => f64::NAN,
        }
    }
}

/// The threshold that leaves about `k` cluster maxima in `chains` (each declustered on its own):
/// the `(k + 1)`-th largest cluster maximum at a lower base threshold (the quantile
/// [`base_quantile`] of the per-period maxima `upper`), where clusters are found with the same
/// run. `None` when fewer than `k + 1` clusters exist above the base.
fn threshold_for(chains: &[&[f64]], upper: &Upper, k: usize, run: usize) -> Option<f64> {
    let base = upper.quantile(base_quantile(k, upper.len()));
    let mut maxima: Vec<f64> = chains
        .iter()
        .flat_map(|c| decluster(c, base, run))
        .collect();
    if maxima.len() <= k {
        return None;
    }
    maxima.sort_unstable_by(|a, b| b.total_cmp(a));
    Some(maxima[k])
}

/// Every chain's per-period maxima in one sample (NaN left out).
fn pooled(chains: &[&[f64]]) -> Vec<f64> {
    chains
        .iter()
        .flat_map(|c| c.iter().copied())
        .filter(|x| !x.is_nan())
        .collect()
}

/// A floor for the periods that extend `chains` to `next_n` periods in all (the extremum floor of
/// a design-life measurement, [`crate::orbits::life`]): the threshold that leaves the largest
/// count of cluster maxima any fit of [`life_pot`] takes from `next_n` periods (`2 k` of
/// [`band_sizes`], at least `2` [`TAIL_CLUSTERS`]), read from the periods measured so far.
/// The thresholds of the next estimate are each the `(c + 1)`-th largest cluster maximum of a
/// sample that holds these periods, for some `c` at most that count, so they lie at or above
/// it (up to clusters that join where the chains continue, and a base quantile that moves).
/// A floor at the last estimate's lowest threshold instead had the next thresholds fall below
/// it in one-frequency studies at m = 20 g, d = 10 mm, r = 0.90 (16 starts) at 6 of the study
/// seeds 1 to 8, and each time the whole measurement ran again without a floor: at seed 11
/// 128,000 and 256,000 periods of its 1.4 million. `None` when the sample has too few clusters.
pub fn floor_for(chains: &[&[f64]], run: usize, next_n: usize) -> Option<f64> {
    let values = pooled(chains);
    let c = band_sizes(next_n)[2].max(2 * TAIL_CLUSTERS);
    let upper = Upper::for_fits(values, [c]);
    threshold_for(chains, &upper, c, run)
}

/// The point value of a fit's life quantile (module doc, "The point value").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Point {
    /// The fitted law's quantile (maximum likelihood).
    Likelihood,
    /// The quantile's posterior median ([`posterior_median`] on [`POSTERIOR_GRID`]) for a
    /// bounded tail's shape range (within `[-1/2, 0]`, [`Life::bounded`]'s); any other range
    /// keeps the likelihood's quantile, as a general-purpose fit gives it.
    Posterior,
}

/// One fit (module doc) at the threshold that leaves about `k` cluster maxima of `chains`,
/// `upper` the upper order statistics of their values ([`Upper::for_fits`] of `k`), its point
/// value `point`.
pub fn fit_top(
    chains: &[&[f64]],
    upper: &Upper,
    k: usize,
    run: usize,
    life: Life,
    point: Point,
) -> Option<LifeEstimate> {
    let u = threshold_for(chains, upper, k, run)?;
    let maxima: Vec<f64> = chains.iter().flat_map(|c| decluster(c, u, run)).collect();
    if maxima.len() < MIN_CLUSTERS {
        return None;
    }
    let y: Vec<f64> = maxima.iter().map(|v| v - u).collect();
    let fit = fit_gpd(&y, (life.xi_min, life.xi_max))?;
    let nu = maxima.len() as f64 / upper.len() as f64;
    let mut est = life_from_excesses(&y, u, nu, life, fit)?;
    let bounded = life.xi_min >= XI_BOUNDED && life.xi_max <= 0.0;
    if point == Point::Posterior && bounded {
        let shapes = (life.xi_min, life.xi_max);
        est.amplitude = posterior_median(&y, u, life.m(nu), fit.gpd, shapes, POSTERIOR_GRID);
    }
    Some(est)
}

/// The peaks-over-threshold estimate (module doc) from the per-period maxima of one or more
/// runs of the same motion (`chains`, each declustered on its own; their cluster maxima pooled,
/// the rate over all their periods), clusters separated by `run` periods below the threshold:
/// the median of the three fits of [`tail_sizes`], and the union of their intervals and those of
/// [`band_sizes`]. `None` when no estimate fit can be made (too few clusters).
pub fn life_pot(chains: &[&[f64]], run: usize, life: Life) -> Option<LifeEstimate> {
    let values = pooled(chains);
    let n = values.len();
    let band_ks: Vec<usize> = band_sizes(n)
        .into_iter()
        .filter(|k| !tail_sizes().contains(k))
        .collect();
    let upper = Upper::for_fits(values, tail_sizes().iter().chain(&band_ks).copied());
    let fit = |k: &usize, point| fit_top(chains, &upper, *k, run, life, point);
    let fits: Vec<LifeEstimate> = tail_sizes()
        .iter()
        .filter_map(|k| fit(k, Point::Posterior))
        .collect();
    // The band's fits lend only their intervals.
    let band: Vec<LifeEstimate> = band_ks
        .iter()
        .filter_map(|k| fit(k, Point::Likelihood))
        .collect();
    let mut est = match fits.len() {
        0 => return None,
        // The median of three, or the lower of two.
        3 => {
            let mut by: Vec<&LifeEstimate> = fits.iter().collect();
            by.sort_by(|a, b| a.amplitude.total_cmp(&b.amplitude));
            *by[1]
        }
        _ => *fits
            .iter()
            .min_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
            .expect("a fit"),
    };
    let all = || fits.iter().chain(&band);
    est.lo = all().map(|f| f.lo).fold(f64::INFINITY, f64::min);
    est.hi = all().map(|f| f.hi).fold(f64::NEG_INFINITY, f64::max);
    est.lowest_threshold = all().map(|f| f.threshold).fold(f64::INFINITY, f64::min);
    est.measured = n as u64;
    Some(est)
}

#[cfg(test)]
mod tests;
