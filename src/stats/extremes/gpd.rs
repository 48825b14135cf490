//! The generalized Pareto law of excesses over a threshold: its likelihood, its fit by maximum
//! likelihood, and the quantile of the largest value over a life with its profile-likelihood
//! interval (the module doc of [`super`] gives the equations).

use super::{CHI2_90, Life, LifeEstimate};
use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::brent::{BrentOpt, BrentRoot};
use argmin::solver::neldermead::NelderMead;

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
    xi: (f64, f64),
}

impl CostFunction for GpdCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        if p[1] < self.xi.0 || p[1] > self.xi.1 {
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
/// `[xi.0, xi.1]` (`None` with fewer than 3).
pub fn fit_gpd(y: &[f64], xi: (f64, f64)) -> Option<GpdFit> {
    if y.len() < 3 {
        return None;
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let s0 = mean.max(f64::MIN_POSITIVE).ln();
    let x0 = xi.1.min(0.0).max(xi.0);
    let step = if x0 - 0.2 >= xi.0 { -0.2 } else { 0.2 };
    let start = vec![vec![s0, x0], vec![s0 + 0.3, x0], vec![s0, x0 + step]];
    let best = minimise(GpdCost { y, xi }, start)?;
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
pub(super) fn minimise<C>(cost: C, start: Vec<Vec<f64>>) -> Option<Vec<f64>>
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
        profile_min((life.xi_min, life.xi_max), |x| {
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
        lowest_threshold: u,
    })
}

/// `min over xi in [xi.0, xi.1]` of `f(xi)` (Brent).
fn profile_min(xi: (f64, f64), f: impl Fn(f64) -> f64) -> f64 {
    struct C<F>(F);
    impl<F: Fn(f64) -> f64> CostFunction for C<F> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> Result<f64, Error> {
            let v = (self.0)(*x);
            Ok(if v.is_finite() { v } else { 1e300 })
        }
    }
    let solver = BrentOpt::new(xi.0, xi.1);
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
pub(super) fn bound(drop: &dyn Fn(f64) -> f64, z_hat: f64, u: f64, upper: bool) -> f64 {
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
