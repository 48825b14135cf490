//! Block maxima with a generalized extreme value law: the alternative to peaks over a
//! threshold, kept for comparison (the module doc of [`super`]).

use super::gpd::{bound, growth, minimise};
use super::life::{CHI2_90, Life, LifeEstimate};
use argmin::core::{CostFunction, Error};

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
    xi: (f64, f64),
}

impl CostFunction for GevCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        if p[2] < self.xi.0 || p[2] > self.xi.1 {
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

/// The maximum-likelihood GEV law of block maxima `x`, its shape in `[xi.0, xi.1]` (`None`
/// with fewer than 5).
pub fn fit_gev(x: &[f64], xi: (f64, f64)) -> Option<(Gev, f64)> {
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
    let x0 = xi.1.min(0.0).max(xi.0);
    let step = if x0 - 0.2 >= xi.0 { -0.2 } else { 0.2 };
    let start = vec![
        vec![m, s.ln(), x0],
        vec![m + 0.5 * s, s.ln(), x0],
        vec![m, s.ln() + 0.3, x0],
        vec![m, s.ln(), x0 + step],
    ];
    let best = minimise(GevCost { x, xi }, start)?;
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
    let range = (life.xi_min, life.xi_max);
    let (gev, nll) = fit_gev(x, range)?;
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
            xi: (f64, f64),
        }
        impl<G: Fn(f64) -> f64> CostFunction for P<'_, G> {
            type Param = Vec<f64>;
            type Output = f64;
            fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
                if p[1] < self.xi.0 || p[1] > self.xi.1 {
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
            vec![
                s0,
                if gev.xi - 0.1 >= range.0 {
                    gev.xi - 0.1
                } else {
                    gev.xi + 0.1
                },
            ],
        ];
        minimise(P { x, z, g, xi: range }, start)
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
        lowest_threshold: f64::NAN,
    })
}
