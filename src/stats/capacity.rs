//! A design's fragility from its motions' capacities (incremental dynamic analysis;
//! model.md §13, docs/scenes.md): the empirical curve, the lognormal fit with censoring, their
//! bootstrap intervals over the motions and a goodness-of-fit statement.
//!
//! # Equations
//! With capacities `c_1 .. c_n` (g), `r` of them censored (the motion never passed the limit up
//! to the largest intensity tried, `c_j` then that intensity, a lower bound):
//! * **Empirical**: `P(f | x) = #{uncensored c_j <= x} / n`, exact up to the censoring point.
//! * **Lognormal** `Phi(ln(x / theta) / beta)`: `y_j = ln c_j` normal with mean `ln theta` and
//!   standard deviation `beta`, right-censored. Without censoring the maximum likelihood is
//!   `ln theta = mean(y)`, `beta^2 = mean((y - ln theta)^2)` (the `1/n` variance); with it, the
//!   likelihood `sum_uncensored [ln phi(z_j) - ln beta] + sum_censored ln(1 - Phi(z_j))`,
//!   `z_j = (y_j - ln theta) / beta`, is maximised by Nelder–Mead from the uncensored estimate.
//! * **Intervals**: a percentile bootstrap over the motions ([`bootstrap::RESAMPLES`] resamples
//!   of `n` drawn with replacement, a PCG-64 stream from the study seed, the same at every
//!   design): `theta`, `beta` and any functional of the curve (the empirical `P(f | x)` at a stripe, `lambda_f`) get
//!   their 2.5 % and 97.5 % quantiles.
//! * **Goodness of fit**: the Kolmogorov–Smirnov distance `D = sup |F_n(x) - F(x)|` between the
//!   empirical curve and the fitted lognormal (over the uncensored range), against Lilliefors'
//!   5 % critical value for a normal law with estimated parameters, `0.886 / sqrt(n)` (n > 30;
//!   the tabled value below). A fit whose `D` exceeds it does not describe the capacities.

use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::neldermead::NelderMead;

use super::bootstrap;
use super::fragility::phi_cdf;

/// A lognormal fit to capacities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LognormalFit {
    /// Median capacity (g) and log standard deviation (per ln IM).
    pub theta: f64,
    pub beta: f64,
}

impl LognormalFit {
    /// `P(f | x)` on the curve.
    pub fn p(&self, x: f64) -> f64 {
        phi_cdf((x / self.theta).ln() / self.beta)
    }
}

/// Capacities of one design: sorted, with their censoring.
#[derive(Clone, Debug, PartialEq)]
pub struct Capacities {
    /// `(capacity, censored)`, sorted by capacity (uncensored first at a tie).
    pub values: Vec<(f64, bool)>,
}

impl Capacities {
    /// From `(capacity, censored)` pairs; NaN capacities (failed searches) are dropped.
    pub fn new(mut values: Vec<(f64, bool)>) -> Capacities {
        values.retain(|v| v.0.is_finite() && v.0 > 0.0);
        values.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        Capacities { values }
    }

    pub fn n(&self) -> usize {
        self.values.len()
    }

    pub fn censored(&self) -> usize {
        self.values.iter().filter(|v| v.1).count()
    }

    /// The empirical `P(f | x)`: the share of motions whose uncensored capacity is `<= x`.
    pub fn p(&self, x: f64) -> f64 {
        if self.values.is_empty() {
            return f64::NAN;
        }
        let k = self.values.iter().filter(|v| !v.1 && v.0 <= x).count();
        k as f64 / self.n() as f64
    }

    /// The lognormal fit by maximum likelihood (module doc); `None` with fewer than two
    /// uncensored capacities or no spread.
    pub fn lognormal(&self) -> Option<LognormalFit> {
        let y: Vec<f64> = self
            .values
            .iter()
            .filter(|v| !v.1)
            .map(|v| v.0.ln())
            .collect();
        if y.len() < 2 {
            return None;
        }
        let mu = y.iter().sum::<f64>() / y.len() as f64;
        let var = y.iter().map(|v| (v - mu).powi(2)).sum::<f64>() / y.len() as f64;
        if var <= 0.0 {
            return None;
        }
        let sigma = var.sqrt();
        if self.censored() == 0 {
            return Some(LognormalFit {
                theta: mu.exp(),
                beta: sigma,
            });
        }
        let cens: Vec<f64> = self
            .values
            .iter()
            .filter(|v| v.1)
            .map(|v| v.0.ln())
            .collect();
        let nll = CensoredNll { y: &y, cens: &cens };
        let simplex = vec![
            vec![mu, sigma.ln()],
            vec![mu + 0.2 * sigma, sigma.ln()],
            vec![mu, sigma.ln() + 0.2],
        ];
        let best = NelderMead::new(simplex)
            .with_sd_tolerance(1e-12)
            .ok()
            .and_then(|s| {
                Executor::new(nll, s)
                    .configure(|c| c.max_iters(2000))
                    .run()
                    .ok()
            })
            .and_then(|r| r.state().get_best_param().cloned())?;
        let fit = LognormalFit {
            theta: best[0].exp(),
            beta: best[1].exp(),
        };
        (fit.theta.is_finite() && fit.beta.is_finite() && fit.beta > 0.0).then_some(fit)
    }

    /// The Kolmogorov–Smirnov distance to `fit` over the uncensored capacities (module doc).
    pub fn ks_distance(&self, fit: &LognormalFit) -> f64 {
        let n = self.n() as f64;
        let mut d: f64 = 0.0;
        for (i, v) in self.values.iter().enumerate() {
            if v.1 {
                break;
            }
            let f = fit.p(v.0);
            d = d
                .max((f - i as f64 / n).abs())
                .max(((i + 1) as f64 / n - f).abs());
        }
        d
    }

    /// The percentile bootstrap over the motions ([`bootstrap::percentile`]) of `stat`, seeded
    /// by `seed`: `(lo, hi)` of each of its values, NaN values left out.
    pub fn bootstrap(&self, seed: u64, stat: impl Fn(&Capacities) -> Vec<f64>) -> Vec<(f64, f64)> {
        bootstrap::percentile(self.n(), seed, |idx| {
            stat(&Capacities::new(
                idx.iter().map(|&i| self.values[i]).collect(),
            ))
        })
    }
}

/// Lilliefors' 5 % critical value of the Kolmogorov–Smirnov distance for a normal law with
/// estimated mean and variance (Lilliefors 1967; `0.886 / sqrt(n)` beyond 30).
pub fn lilliefors_5(n: usize) -> f64 {
    const TABLE: [(usize, f64); 8] = [
        (5, 0.337),
        (8, 0.285),
        (10, 0.258),
        (12, 0.242),
        (15, 0.220),
        (20, 0.190),
        (25, 0.173),
        (30, 0.161),
    ];
    if n > 30 {
        return 0.886 / (n as f64).sqrt();
    }
    TABLE
        .iter()
        .find(|(m, _)| n <= *m)
        .map_or(f64::NAN, |(_, d)| *d)
}

/// The censored negative log-likelihood over `(ln theta, ln beta)`.
struct CensoredNll<'a> {
    y: &'a [f64],
    cens: &'a [f64],
}

impl CostFunction for CensoredNll<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        let (mu, ln_b) = (p[0], p[1]);
        let b = ln_b.exp();
        let mut nll = 0.0;
        for &y in self.y {
            let z = (y - mu) / b;
            nll += 0.5 * z * z + ln_b;
        }
        for &y in self.cens {
            nll -= phi_cdf(-(y - mu) / b).ln();
        }
        Ok(if nll.is_nan() { f64::INFINITY } else { nll })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::inverse_normal;

    /// Capacities at the `n` quantiles `(i + 0.5) / n` of a lognormal.
    fn exact(n: usize, theta: f64, beta: f64) -> Vec<f64> {
        (0..n)
            .map(|i| theta * (beta * inverse_normal((i as f64 + 0.5) / n as f64)).exp())
            .collect()
    }

    #[test]
    fn quantiles_of_a_lognormal_give_back_its_parameters_and_pass_the_fit_test() {
        let c = Capacities::new(
            exact(500, 0.8, 0.4)
                .into_iter()
                .map(|v| (v, false))
                .collect(),
        );
        let f = c.lognormal().unwrap();
        assert!((f.theta / 0.8 - 1.0).abs() < 1e-3, "{f:?}");
        assert!((f.beta / 0.4 - 1.0).abs() < 0.01, "{f:?}");
        assert!(c.ks_distance(&f) < lilliefors_5(500));
    }

    #[test]
    fn censoring_keeps_the_fit_where_dropping_would_bias_it() {
        // The top 30 % censored at the 70 % quantile: the censored fit finds the parameters,
        // the uncensored values alone would put theta too low.
        let v = exact(1000, 1.0, 0.5);
        let cut = v[700];
        let c = Capacities::new(
            v.iter()
                .map(|&x| if x >= cut { (cut, true) } else { (x, false) })
                .collect(),
        );
        assert_eq!(c.censored(), 300);
        let f = c.lognormal().unwrap();
        assert!((f.theta - 1.0).abs() < 0.01, "{f:?}");
        assert!((f.beta / 0.5 - 1.0).abs() < 0.02, "{f:?}");
        // The empirical curve stops rising at the censoring point.
        assert!((c.p(cut * 0.999) - 0.7).abs() < 1e-9);
        assert!((c.p(100.0) - 0.7).abs() < 1e-9);
    }

    #[test]
    fn a_two_population_sample_fails_the_fit_test() {
        let mut v: Vec<(f64, bool)> = exact(300, 0.2, 0.1)
            .into_iter()
            .map(|x| (x, false))
            .collect();
        v.extend(exact(700, 2.0, 0.1).into_iter().map(|x| (x, false)));
        let c = Capacities::new(v);
        let f = c.lognormal().unwrap();
        assert!(c.ks_distance(&f) > lilliefors_5(1000));
    }

    #[test]
    fn the_bootstrap_is_seeded_and_brackets_the_estimate() {
        let c = Capacities::new(
            exact(400, 1.0, 0.3)
                .into_iter()
                .map(|v| (v, false))
                .collect(),
        );
        let stat = |s: &Capacities| {
            let f = s.lognormal().unwrap();
            vec![f.theta, f.beta]
        };
        let a = c.bootstrap(7, stat);
        assert_eq!(a, c.bootstrap(7, stat));
        assert!(a[0].0 < 1.0 && 1.0 < a[0].1, "{a:?}");
        // The standard error of ln theta is beta / sqrt(n) = 0.015: the interval about
        // +-3 %.
        assert!(a[0].1 / a[0].0 < 1.09 && a[0].1 / a[0].0 > 1.03, "{a:?}");
    }
}
