//! The largest amplitude of a stationary irregular motion over a design life, from a sample of
//! its per-period maxima (docs/model.md, "The amplitude over a design life").
//!
//! # Peaks over a threshold (the estimate used)
//! Let `z_k` be the largest `|x|` in forcing period `k`, `k = 1..n`. Above a high threshold `u`,
//! exceedances come in clusters (consecutive periods are correlated: the main mass's envelope
//! changes over `1 / (2 pi zeta)` periods), so they are **declustered** by runs: a cluster ends
//! after `run` periods below `u`, and only each cluster's maximum is kept. The cluster maxima's
//! excesses `y = z - u` follow a generalized Pareto law (Pickands; Coles, *An Introduction to
//! Statistical Modeling of Extreme Values*, ch. 4)
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
//! `(ln sigma, xi)`, `xi` in `[-0.95, 0.95]`), `nu` is the observed cluster rate.
//!
//! **The interval** of `z_q` is the profile likelihood's: `z` is in the 90 % interval when
//! `2 (l_max - l_p(z)) <= 2.706` (the chi-square quantile with one degree of freedom), `l_p(z)`
//! the likelihood maximised over `xi` with `sigma` tied to `z` by the formula above. It is
//! asymmetric, as the tail is, and needs no resampling; the rate's own error is left out (it is
//! small beside the tail's: the relative error of `nu` is `1/sqrt(clusters)`, and `z_q` depends on
//! `nu` only through `ln m`).
//!
//! **The threshold** is chosen automatically: of the candidates, the pooled empirical quantiles
//! of `z` from 0.80 to 0.998, the one that leaves about `sqrt(n) / 2` cluster maxima (at least
//! [`MIN_CLUSTERS`]), `n` the periods measured. Lower thresholds spend more of the sample but
//! reach into values that are not yet in their asymptotic tail: on the showcase's chaotic
//! motions the 0.80 quantile, although the fitted shape was as stable above it as the
//! threshold-stability test can see, biased the life amplitude high by 15 to 25 %, where about
//! `sqrt(n) / 2` clusters (the 0.98 to 0.99 quantile from 20,000 periods) came within 2 to 10 %
//! of brute-force maxima over ten times as long (BENCHMARKS.md).
//!
//! # Block maxima (the alternative)
//! The maxima of blocks of `b` periods follow a generalized extreme value law
//! `G(z) = exp(-(1 + xi (z - mu) / sigma)^(-1/xi))`, and the largest over `N` periods is the
//! largest of `N / b` blocks: `z_q = mu + sigma ((-ln q^(b/N))^(-xi) - 1) / xi`, with the same
//! profile-likelihood interval. It uses one value per block where the threshold method uses
//! every cluster above `u`, so from the same periods it is the less precise; it is here for
//! comparison and is tested like the other.

use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::brent::{BrentOpt, BrentRoot};
use argmin::solver::neldermead::NelderMead;

/// Chi-square quantile, one degree of freedom, at 0.90: the profile-likelihood interval's drop.
pub const CHI2_90: f64 = 2.705_543_454_095_404;

/// Fewest cluster maxima a threshold may leave (below it the shape cannot be fitted).
pub const MIN_CLUSTERS: usize = 30;

/// The shape is kept inside `[-XI_MAX, XI_MAX]`: beyond, the likelihood is not regular (at
/// `xi <= -1` it is unbounded) and no response of a damped structure has so heavy a tail.
pub const XI_MAX: f64 = 0.95;

/// A generalized Pareto law of excesses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gpd {
    pub sigma: f64,
    pub xi: f64,
}

impl Gpd {
    /// Negative log-likelihood of excesses `y` (all `> 0`); `+inf` outside the support.
    pub fn nll(&self, y: &[f64]) -> f64 {
        let Gpd { sigma, xi } = *self;
        if sigma.is_nan() || sigma <= 0.0 || !xi.is_finite() {
            return f64::INFINITY;
        }
        let n = y.len() as f64;
        if xi.abs() < 1e-9 {
            return n * sigma.ln() + y.iter().sum::<f64>() / sigma;
        }
        let mut s = 0.0;
        for &v in y {
            let t = 1.0 + xi * v / sigma;
            if t <= 0.0 {
                return f64::INFINITY;
            }
            s += t.ln();
        }
        n * sigma.ln() + (1.0 + 1.0 / xi) * s
    }
}

/// `(m^xi - 1) / xi`, and `ln m` at `xi = 0`: how far above the threshold, in scales, the
/// quantile `z_q = u + sigma growth(m, xi)` of the largest over a life lies (module doc).
pub fn growth(m: f64, xi: f64) -> f64 {
    if xi.abs() < 1e-9 {
        m.ln()
    } else {
        (m.powf(xi) - 1.0) / xi
    }
}

/// A fitted generalized Pareto law, with the standard error of its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpdFit {
    pub gpd: Gpd,
    /// Negative log-likelihood at the fit.
    pub nll: f64,
    /// Standard error of `xi` from the observed information (NaN when not positive definite).
    pub xi_se: f64,
}

struct GpdCost<'a> {
    y: &'a [f64],
    xi_max: f64,
}

impl CostFunction for GpdCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        if p[1] < -XI_MAX || p[1] > self.xi_max {
            return Ok(f64::INFINITY);
        }
        Ok(Gpd {
            sigma: p[0].exp(),
            xi: p[1],
        }
        .nll(self.y))
    }
}

/// The maximum-likelihood generalized Pareto law of excesses `y`, its shape in
/// `[-XI_MAX, xi_max]` (`None` with fewer than 3).
pub fn fit_gpd(y: &[f64], xi_max: f64) -> Option<GpdFit> {
    if y.len() < 3 {
        return None;
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let s0 = mean.max(f64::MIN_POSITIVE).ln();
    let x0 = xi_max.min(0.0);
    let start = vec![vec![s0, x0], vec![s0 + 0.3, x0], vec![s0, x0 - 0.2]];
    let best = minimise(GpdCost { y, xi_max }, start)?;
    let gpd = Gpd {
        sigma: best[0].exp(),
        xi: best[1],
    };
    let nll = gpd.nll(y);
    Some(GpdFit {
        gpd,
        nll,
        xi_se: shape_se(|s, x| Gpd { sigma: s, xi: x }.nll(y), gpd.sigma, gpd.xi),
    })
}

/// Nelder–Mead from the simplex `start`; the best parameters when they are finite.
fn minimise<C>(cost: C, start: Vec<Vec<f64>>) -> Option<Vec<f64>>
where
    C: CostFunction<Param = Vec<f64>, Output = f64>,
{
    let solver = NelderMead::new(start).with_sd_tolerance(1e-12).ok()?;
    let res = Executor::new(cost, solver)
        .configure(|s| s.max_iters(2000))
        .run()
        .ok()?;
    let best = res.state().get_best_param()?.clone();
    (best.iter().all(|v| v.is_finite()) && res.state().get_best_cost().is_finite()).then_some(best)
}

/// The standard error of the shape from the observed information of `nll(sigma, xi)` at its
/// minimum (central differences of the Hessian in `(ln sigma, xi)`).
fn shape_se(nll: impl Fn(f64, f64) -> f64, sigma: f64, xi: f64) -> f64 {
    let f = |a: f64, b: f64| nll(sigma * a.exp(), xi + b);
    let (h1, h2) = (1e-4, 1e-4);
    let f0 = f(0.0, 0.0);
    let d11 = (f(h1, 0.0) - 2.0 * f0 + f(-h1, 0.0)) / (h1 * h1);
    let d22 = (f(0.0, h2) - 2.0 * f0 + f(0.0, -h2)) / (h2 * h2);
    let d12 = (f(h1, h2) - f(h1, -h2) - f(-h1, h2) + f(-h1, -h2)) / (4.0 * h1 * h2);
    let det = d11 * d22 - d12 * d12;
    if det > 0.0 && d11 > 0.0 {
        (d11 / det).sqrt()
    } else {
        f64::NAN
    }
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

/// The largest value over a design life, estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LifeEstimate {
    /// The quantile `q` of the largest value over `N` periods, and its 90 % interval (the upper
    /// end `inf` when the likelihood does not drop enough above the estimate).
    pub amplitude: f64,
    pub lo: f64,
    pub hi: f64,
    /// The tail's law: threshold, scale, shape (and the shape's standard error).
    pub threshold: f64,
    pub sigma: f64,
    pub xi: f64,
    pub xi_se: f64,
    /// The bounded tail's end point `u - sigma / xi` (NaN unless `xi < 0`).
    pub end_point: f64,
    /// Cluster maxima above the threshold, and periods measured.
    pub exceedances: u64,
    pub measured: u64,
}

impl LifeEstimate {
    /// The interval's half-width relative to the estimate.
    pub fn rel_halfwidth(&self) -> f64 {
        0.5 * (self.hi - self.lo) / self.amplitude
    }
}

/// The design-life question: `n_life` periods (`N`, may exceed the sample by far), the quantile
/// `q` of the largest value over them, and the largest tail shape allowed (`XI_MAX` for any
/// law; 0 for a bounded quantity, module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Life {
    pub n_life: f64,
    pub q: f64,
    pub xi_max: f64,
}

impl Life {
    /// `m = N nu / (-ln q)` for a cluster rate `nu` per period.
    fn m(&self, nu: f64) -> f64 {
        self.n_life * nu / (-self.q.ln())
    }
}

/// The peaks-over-threshold estimate (module doc) from the per-period maxima of one or more
/// runs of the same motion (`chains`, each declustered on its own; their cluster maxima pooled,
/// the rate over all their periods), clusters separated by `run` periods below the threshold;
/// `None` when no candidate threshold leaves [`MIN_CLUSTERS`] cluster maxima or a fit fails.
pub fn life_pot(chains: &[&[f64]], run: usize, life: Life) -> Option<LifeEstimate> {
    let (u, maxima, fit) = choose_threshold(chains, run, life.xi_max)?;
    let y: Vec<f64> = maxima.iter().map(|v| v - u).collect();
    let n: usize = chains.iter().map(|c| c.len()).sum();
    let nu = maxima.len() as f64 / n as f64;
    let mut est = life_from_excesses(&y, u, nu, life, fit)?;
    est.measured = n as u64;
    Some(est)
}

/// The life estimate from excesses `y` over `u` arriving at `nu` per period, with their fit.
pub fn life_from_excesses(
    y: &[f64],
    u: f64,
    nu: f64,
    life: Life,
    fit: GpdFit,
) -> Option<LifeEstimate> {
    let m = life.m(nu);
    if m.is_nan() || m <= 1.0 {
        return None;
    }
    let Gpd { sigma, xi } = fit.gpd;
    let z_hat = u + sigma * growth(m, xi);
    // The profile: sigma(z, xi) = (z - u) / growth(m, xi), the likelihood maximised over xi.
    let profile = |z: f64| -> f64 {
        if z <= u {
            return f64::INFINITY;
        }
        profile_min(life.xi_max, |x| {
            Gpd {
                sigma: (z - u) / growth(m, x),
                xi: x,
            }
            .nll(y)
        })
    };
    let drop = |z: f64| 2.0 * (profile(z) - fit.nll) - CHI2_90;
    let lo = bound(&drop, z_hat, u, false);
    let hi = bound(&drop, z_hat, u, true);
    Some(LifeEstimate {
        amplitude: z_hat,
        lo,
        hi,
        threshold: u,
        sigma,
        xi,
        xi_se: fit.xi_se,
        end_point: if xi < 0.0 { u - sigma / xi } else { f64::NAN },
        exceedances: y.len() as u64,
        measured: 0,
    })
}

/// `min over xi in [-XI_MAX, xi_max]` of `f(xi)` (Brent).
fn profile_min(xi_max: f64, f: impl Fn(f64) -> f64) -> f64 {
    struct C<F>(F);
    impl<F: Fn(f64) -> f64> CostFunction for C<F> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> Result<f64, Error> {
            let v = (self.0)(*x);
            Ok(if v.is_finite() { v } else { 1e300 })
        }
    }
    let solver = BrentOpt::new(-XI_MAX, xi_max);
    Executor::new(C(&f), solver)
        .configure(|s| s.max_iters(200))
        .run()
        .ok()
        .and_then(|r| r.state().get_best_param().map(|&x| f(x)))
        .unwrap_or(f64::INFINITY)
}

/// The end of the interval on one side of `z_hat` where `drop` crosses 0 (bracketed by steps
/// growing away from `z_hat`; `u` bounds the lower side). `inf` (upper) or `u` (lower) when the
/// likelihood never drops enough.
fn bound(drop: &dyn Fn(f64) -> f64, z_hat: f64, u: f64, upper: bool) -> f64 {
    let span = (z_hat - u).max(f64::MIN_POSITIVE);
    let mut inner = z_hat;
    let mut step = 0.05 * span;
    for _ in 0..60 {
        let outer = if upper {
            inner + step
        } else {
            (inner - step).max(u + 1e-12 * span)
        };
        if drop(outer) > 0.0 {
            return root(drop, inner.min(outer), inner.max(outer));
        }
        if !upper && outer <= u + 1e-12 * span {
            return u;
        }
        inner = outer;
        step *= 1.6;
    }
    if upper { f64::INFINITY } else { u }
}

/// The root of `f` in `[a, b]` (a sign change), by Brent.
fn root(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    struct C<'a>(&'a dyn Fn(f64) -> f64);
    impl CostFunction for C<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> Result<f64, Error> {
            Ok((self.0)(*x))
        }
    }
    let tol = 1e-9 * a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
    Executor::new(C(f), BrentRoot::new(a, b, tol))
        .configure(|s| s.max_iters(100))
        .run()
        .ok()
        .and_then(|r| r.state().get_best_param().copied())
        .unwrap_or(0.5 * (a + b))
}

/// The lowest candidate threshold's quantile ([`choose_threshold`]): the values below the
/// pooled quantile there enter an estimate only as periods below its threshold.
pub const LOWEST_CANDIDATE: f64 = 0.80;

/// The threshold (module doc): `(u, cluster maxima, fit)`. Candidates are the pooled
/// quantiles of the chains' values at 0.80, 0.81, ..., 0.998; the one chosen leaves the number
/// of cluster maxima nearest (in ratio) to `max(MIN_CLUSTERS, sqrt(n) / 2)`, `n` the periods.
pub fn choose_threshold(
    chains: &[&[f64]],
    run: usize,
    xi_max: f64,
) -> Option<(f64, Vec<f64>, GpdFit)> {
    let mut sorted: Vec<f64> = chains
        .iter()
        .flat_map(|c| c.iter().copied())
        .filter(|x| !x.is_nan())
        .collect();
    sorted.sort_unstable_by(f64::total_cmp);
    let periods = chains.iter().map(|c| c.len()).sum::<usize>();
    let target = (0.5 * (periods as f64).sqrt()).max(MIN_CLUSTERS as f64);
    let probs = (0..=15)
        .map(|i| LOWEST_CANDIDATE + 0.01 * i as f64)
        .chain((1..=24).map(|i| 0.95 + 0.002 * i as f64));
    let mut best: Option<(f64, f64, Vec<f64>)> = None;
    for p in probs {
        let u = crate::numeric::quantile_sorted(&sorted, p);
        let maxima: Vec<f64> = chains.iter().flat_map(|c| decluster(c, u, run)).collect();
        if maxima.len() < MIN_CLUSTERS {
            break;
        }
        let miss = (maxima.len() as f64 / target).ln().abs();
        if best.as_ref().is_none_or(|b| miss < b.0) {
            best = Some((miss, u, maxima));
        }
    }
    let (_, u, maxima) = best?;
    let y: Vec<f64> = maxima.iter().map(|v| v - u).collect();
    let fit = fit_gpd(&y, xi_max)?;
    Some((u, maxima, fit))
}

/// A generalized extreme value law of block maxima.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gev {
    pub mu: f64,
    pub sigma: f64,
    pub xi: f64,
}

impl Gev {
    /// Negative log-likelihood of maxima `x`; `+inf` outside the support.
    pub fn nll(&self, x: &[f64]) -> f64 {
        let Gev { mu, sigma, xi } = *self;
        if sigma.is_nan() || sigma <= 0.0 || !xi.is_finite() || !mu.is_finite() {
            return f64::INFINITY;
        }
        let n = x.len() as f64;
        let mut s = n * sigma.ln();
        for &v in x {
            let w = (v - mu) / sigma;
            if xi.abs() < 1e-9 {
                s += w + (-w).exp();
            } else {
                let t = 1.0 + xi * w;
                if t <= 0.0 {
                    return f64::INFINITY;
                }
                s += (1.0 + 1.0 / xi) * t.ln() + t.powf(-1.0 / xi);
            }
        }
        s
    }
}

struct GevCost<'a> {
    x: &'a [f64],
}

impl CostFunction for GevCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        if p[2].abs() > XI_MAX {
            return Ok(f64::INFINITY);
        }
        Ok(Gev {
            mu: p[0],
            sigma: p[1].exp(),
            xi: p[2],
        }
        .nll(self.x))
    }
}

/// The maximum-likelihood GEV law of block maxima `x` (`None` with fewer than 5).
pub fn fit_gev(x: &[f64]) -> Option<(Gev, f64)> {
    if x.len() < 5 {
        return None;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let sd = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n)
        .sqrt()
        .max(1e-300);
    // Gumbel moments: sigma = sd sqrt(6) / pi, mu = mean - 0.5772 sigma.
    let s = sd * 6f64.sqrt() / std::f64::consts::PI;
    let m = mean - 0.5772 * s;
    let start = vec![
        vec![m, s.ln(), 0.0],
        vec![m + 0.5 * s, s.ln(), 0.0],
        vec![m, s.ln() + 0.3, 0.0],
        vec![m, s.ln(), -0.2],
    ];
    let best = minimise(GevCost { x }, start)?;
    let gev = Gev {
        mu: best[0],
        sigma: best[1].exp(),
        xi: best[2],
    };
    Some((gev, gev.nll(x)))
}

/// The block-maxima estimate (module doc) of the quantile `q` of the largest of `n_life`
/// periods from the maxima `x` of blocks of `block` periods, with its profile-likelihood 90 %
/// interval.
pub fn life_gev(x: &[f64], block: usize, life: Life) -> Option<LifeEstimate> {
    let (gev, nll) = fit_gev(x)?;
    // The quantile p = q^(b/N) of one block's maximum: y = -ln p.
    let y = -(life.q.ln()) * block as f64 / life.n_life;
    let g = |xi: f64| growth(1.0 / y, xi);
    let z_hat = gev.mu + gev.sigma * g(gev.xi);
    // The profile in z: mu(z, sigma, xi) = z - sigma g(xi), minimised over (ln sigma, xi).
    let profile = |z: f64| -> f64 {
        struct P<'a, G: Fn(f64) -> f64> {
            x: &'a [f64],
            z: f64,
            g: G,
        }
        impl<G: Fn(f64) -> f64> CostFunction for P<'_, G> {
            type Param = Vec<f64>;
            type Output = f64;
            fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
                if p[1].abs() > XI_MAX {
                    return Ok(f64::INFINITY);
                }
                let sigma = p[0].exp();
                Ok(Gev {
                    mu: self.z - sigma * (self.g)(p[1]),
                    sigma,
                    xi: p[1],
                }
                .nll(self.x))
            }
        }
        let s0 = gev.sigma.ln();
        let start = vec![
            vec![s0, gev.xi],
            vec![s0 + 0.2, gev.xi],
            vec![s0, gev.xi - 0.1],
        ];
        minimise(P { x, z, g }, start)
            .map(|p| {
                let sigma = p[0].exp();
                Gev {
                    mu: z - sigma * g(p[1]),
                    sigma,
                    xi: p[1],
                }
                .nll(x)
            })
            .unwrap_or(f64::INFINITY)
    };
    let drop = |z: f64| 2.0 * (profile(z) - nll) - CHI2_90;
    let floor = x.iter().copied().fold(f64::INFINITY, f64::min) - 10.0 * gev.sigma;
    Some(LifeEstimate {
        amplitude: z_hat,
        lo: bound(&drop, z_hat, floor, false),
        hi: bound(&drop, z_hat, floor, true),
        threshold: f64::NAN,
        sigma: gev.sigma,
        xi: gev.xi,
        xi_se: f64::NAN,
        end_point: if gev.xi < 0.0 {
            gev.mu - gev.sigma / gev.xi
        } else {
            f64::NAN
        },
        exceedances: x.len() as u64,
        measured: (x.len() * block) as u64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::noise::mix64;

    /// A uniform number in (0, 1) from a seed and an index.
    fn unif(seed: u64, i: u64) -> f64 {
        ((mix64(seed ^ mix64(i)) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn gpd_sample(seed: u64, n: usize, sigma: f64, xi: f64) -> Vec<f64> {
        (0..n as u64)
            .map(|i| {
                let p = unif(seed, i);
                sigma * growth(1.0 / p, xi)
            })
            .collect()
    }

    #[test]
    fn gpd_fit_recovers_known_laws_and_the_exponential_limit() {
        for (sigma, xi) in [(0.5, -0.3), (1.0, 0.0), (2.0, 0.2)] {
            let y = gpd_sample(3, 4000, sigma, xi);
            let fit = fit_gpd(&y, XI_MAX).unwrap();
            assert!((fit.gpd.xi - xi).abs() < 4.0 * fit.xi_se, "{fit:?} vs {xi}");
            assert!(
                (fit.gpd.sigma / sigma - 1.0).abs() < 0.1,
                "{fit:?} vs {sigma}"
            );
        }
        // xi -> 0: the likelihood is continuous.
        let y = gpd_sample(4, 100, 1.0, 0.0);
        let a = Gpd {
            sigma: 1.0,
            xi: 0.0,
        }
        .nll(&y);
        let b = Gpd {
            sigma: 1.0,
            xi: 1e-7,
        }
        .nll(&y);
        assert!((a - b).abs() < 1e-4 * a.abs(), "{a} {b}");
    }

    #[test]
    fn declustering_keeps_one_maximum_per_run() {
        let z = [0.0, 2.0, 3.0, 0.0, 2.5, 0.0, 0.0, 0.0, 4.0, 0.0];
        assert_eq!(decluster(&z, 1.0, 1), vec![3.0, 2.5, 4.0]);
        assert_eq!(decluster(&z, 1.0, 2), vec![3.0, 4.0]);
        assert_eq!(decluster(&z, 1.0, 5), vec![4.0]);
    }

    /// Coverage of the 90 % profile-likelihood interval of the life quantile on excesses of a
    /// known law: 200 seeds, each 150 excesses (a rate of 0.05 per period over 3000 periods),
    /// a life of 10^6 periods, the median of its maximum.
    #[test]
    fn pot_interval_covers_the_true_life_quantile_at_its_nominal_rate() {
        // Any shape allowed (a heavy tail among them), and the bounded fit on a bounded law.
        for (sigma, xi, xi_max) in [(1.0, -0.2, XI_MAX), (1.0, 0.1, XI_MAX), (1.0, -0.2, 0.0)] {
            let life = Life {
                n_life: 1e6,
                q: 0.5,
                xi_max,
            };
            let nu = 0.05;
            let truth = sigma * growth(life.m(nu), xi);
            let mut covered = 0;
            let seeds = 200;
            for seed in 0..seeds {
                let y = gpd_sample(1000 + seed, 150, sigma, xi);
                let fit = fit_gpd(&y, xi_max).unwrap();
                let est = life_from_excesses(&y, 0.0, nu, life, fit).unwrap();
                if est.lo <= truth && truth <= est.hi {
                    covered += 1;
                }
            }
            let rate = covered as f64 / seeds as f64;
            eprintln!("GPD xi {xi} (fitted in [-0.95, {xi_max}]): coverage {rate}");
            assert!((0.80..=0.97).contains(&rate), "xi {xi}: coverage {rate}");
        }
    }

    /// The same for block maxima of a known GEV law: 200 seeds of 60 blocks of 100 periods.
    #[test]
    fn gev_interval_covers_the_true_life_quantile_at_its_nominal_rate() {
        let (mu, sigma, xi) = (10.0, 1.0, -0.15);
        let life = Life {
            n_life: 1e6,
            q: 0.5,
            xi_max: XI_MAX,
        };
        let block = 100;
        let y = -(life.q.ln()) * block as f64 / life.n_life;
        let truth = mu + sigma * growth(1.0 / y, xi);
        let mut covered = 0;
        let seeds = 200;
        for seed in 0..seeds {
            let x: Vec<f64> = (0..60)
                .map(|i| {
                    let p = unif(5000 + seed, i);
                    mu + sigma * growth(1.0 / -p.ln(), xi)
                })
                .collect();
            let est = life_gev(&x, block, life).unwrap();
            if est.lo <= truth && truth <= est.hi {
                covered += 1;
            }
        }
        let rate = covered as f64 / seeds as f64;
        eprintln!("GEV: coverage {rate}");
        assert!((0.80..=0.97).contains(&rate), "coverage {rate}");
    }
}
