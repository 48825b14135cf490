//! The lognormal fragility curve `P(exceed | IM) = Phi(ln(IM / theta) / beta)` fitted by
//! maximum likelihood on exceedance counts per intensity (Baker, "Efficient analytical
//! fragility function fitting using dynamic structural analysis", Earthquake Spectra 31 (2015)
//! 579–599): at intensity `IM_j`, `z_j` of `n_j` runs exceeded the limit, and the counts are
//! binomial,
//!
//! ```text
//! ln L(theta, beta) = sum_j [ z_j ln p_j + (n_j - z_j) ln(1 - p_j) ],
//! p_j = Phi(ln(IM_j / theta) / beta).
//! ```
//!
//! `theta` is the median capacity (the intensity at which half the runs exceed), `beta` the
//! dispersion. The likelihood is maximised by argmin's Nelder–Mead over `(ln theta, ln beta)`
//! from a probit least-squares start. It is a probit regression `p = Phi(a + b x)`,
//! `x = ln IM`, `a = -ln theta / beta`, `b = 1 / beta`, whose Fisher information is
//! `sum_j n_j phi(eta_j)^2 / (p_j (1 - p_j)) [1, x_j; x_j, x_j^2]`; its inverse, carried to
//! `(ln theta, ln beta)` by the delta method, gives the standard errors and the 95 % Wald
//! intervals `theta exp(+-1.96 se(ln theta))`, `beta exp(+-1.96 se(ln beta))`.
//!
//! The maximum does not exist when the counts do not overlap: every run below some intensity
//! safe and every run above it failed (`beta -> 0`), or no run (or every run) failed at any
//! intensity (`theta` out of the data's reach). Those are outcomes ([`FitOutcome`]), not
//! numbers.

use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::neldermead::NelderMead;
use statrs::distribution::{ContinuousCDF, Normal};
use statrs::function::erf::erfc;

/// The two-sided 95 % normal quantile.
pub const Z95: f64 = 1.959_963_984_540_054;

/// Runs and exceedances at one intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Counts {
    /// The intensity measure (`> 0`: a record's scale, `S0`, a PGA, `Sa(T1)`).
    pub im: f64,
    /// Runs at this intensity.
    pub n: u64,
    /// Runs that exceeded the limit (`<= n`).
    pub exceed: u64,
}

/// How a fit ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitOutcome {
    /// The maximum was found and the information is positive definite.
    Ok,
    /// No run exceeded, or every run did: the data say nothing of the median.
    NoOverlap,
    /// The exceedances are separated in intensity (all safe below, all failed above): the
    /// likelihood grows as `beta -> 0`; `theta` lies between the two intensities.
    Separated,
    /// Fewer than two intensities with runs, a non-positive intensity, or `exceed > n`.
    Invalid,
    /// The optimiser did not find a finite maximum.
    Failed,
}

/// A fitted fragility curve. With an outcome other than `Ok` the numbers are NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragility {
    pub outcome: FitOutcome,
    /// Median capacity (the intensity's unit) and dispersion.
    pub theta: f64,
    pub beta: f64,
    /// Standard errors of `ln theta` and of `ln beta`.
    pub se_ln_theta: f64,
    pub se_ln_beta: f64,
    /// 95 % Wald intervals (module doc).
    pub theta_lo: f64,
    pub theta_hi: f64,
    pub beta_lo: f64,
    pub beta_hi: f64,
    /// The log-likelihood at the fit.
    pub log_likelihood: f64,
}

impl Fragility {
    fn failed(outcome: FitOutcome) -> Fragility {
        let nan = f64::NAN;
        Fragility {
            outcome,
            theta: nan,
            beta: nan,
            se_ln_theta: nan,
            se_ln_beta: nan,
            theta_lo: nan,
            theta_hi: nan,
            beta_lo: nan,
            beta_hi: nan,
            log_likelihood: nan,
        }
    }

    /// `P(exceed | im)` on the fitted curve.
    pub fn probability(&self, im: f64) -> f64 {
        phi_cdf((im / self.theta).ln() / self.beta)
    }
}

/// The standard normal CDF, accurate in both tails.
pub(crate) fn phi_cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// The standard normal density.
pub(crate) fn phi_pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// The negative log-likelihood over `(ln theta, ln beta)`.
struct Nll<'a>(&'a [Counts]);

impl Nll<'_> {
    fn at(&self, ln_theta: f64, ln_beta: f64) -> f64 {
        let beta = ln_beta.exp();
        let mut nll = 0.0;
        for c in self.0 {
            let z = (c.im.ln() - ln_theta) / beta;
            // ln p and ln(1 - p) from the tails, without cancellation.
            let (ln_p, ln_q) = (phi_cdf(z).ln(), phi_cdf(-z).ln());
            if c.exceed > 0 {
                nll -= c.exceed as f64 * ln_p;
            }
            if c.n > c.exceed {
                nll -= (c.n - c.exceed) as f64 * ln_q;
            }
        }
        if nll.is_nan() { f64::INFINITY } else { nll }
    }
}

impl CostFunction for Nll<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        Ok(self.at(p[0], p[1]))
    }
}

/// Fits the lognormal fragility curve to `counts` (module doc). Intensities with no runs are
/// ignored.
pub fn fit(counts: &[Counts]) -> Fragility {
    let data: Vec<Counts> = counts.iter().copied().filter(|c| c.n > 0).collect();
    let valid = data.len() >= 2
        && data
            .iter()
            .all(|c| c.im.is_finite() && c.im > 0.0 && c.exceed <= c.n);
    if !valid {
        return Fragility::failed(FitOutcome::Invalid);
    }
    let total: u64 = data.iter().map(|c| c.n).sum();
    let exceed: u64 = data.iter().map(|c| c.exceed).sum();
    if exceed == 0 || exceed == total {
        return Fragility::failed(FitOutcome::NoOverlap);
    }
    if separated(&data) {
        return Fragility::failed(FitOutcome::Separated);
    }
    let (t0, b0) = start(&data);
    let simplex = vec![
        vec![t0, b0],
        vec![t0 + 0.2 * b0.exp(), b0],
        vec![t0, b0 + 0.3],
    ];
    let Some(best) = NelderMead::new(simplex)
        .with_sd_tolerance(1e-13)
        .ok()
        .and_then(|solver| {
            Executor::new(Nll(&data), solver)
                .configure(|s| s.max_iters(4000))
                .run()
                .ok()
        })
        .and_then(|r| r.state().get_best_param().cloned())
    else {
        return Fragility::failed(FitOutcome::Failed);
    };
    let (ln_theta, ln_beta) = (best[0], best[1]);
    let nll = Nll(&data).at(ln_theta, ln_beta);
    if !(ln_theta.is_finite() && ln_beta.is_finite() && nll.is_finite()) {
        return Fragility::failed(FitOutcome::Failed);
    }
    let (theta, beta) = (ln_theta.exp(), ln_beta.exp());
    let Some((se_t, se_b)) = standard_errors(&data, theta, beta) else {
        return Fragility::failed(FitOutcome::Failed);
    };
    Fragility {
        outcome: FitOutcome::Ok,
        theta,
        beta,
        se_ln_theta: se_t,
        se_ln_beta: se_b,
        theta_lo: theta * (-Z95 * se_t).exp(),
        theta_hi: theta * (Z95 * se_t).exp(),
        beta_lo: beta * (-Z95 * se_b).exp(),
        beta_hi: beta * (Z95 * se_b).exp(),
        log_likelihood: -nll,
    }
}

/// Whether every intensity with an exceedance lies above every intensity with a safe run
/// (then no finite `beta` maximises the likelihood).
fn separated(data: &[Counts]) -> bool {
    let highest_safe = data
        .iter()
        .filter(|c| c.exceed < c.n)
        .map(|c| c.im)
        .fold(f64::NEG_INFINITY, f64::max);
    let lowest_exceed = data
        .iter()
        .filter(|c| c.exceed > 0)
        .map(|c| c.im)
        .fold(f64::INFINITY, f64::min);
    highest_safe < lowest_exceed
}

/// A start for `(ln theta, ln beta)`: the least-squares line of `Phi^-1(p_j)` on `ln IM_j`, the
/// fractions moved in from 0 and 1 by half a run (`beta` of 0.5 when the line is flat or
/// falls).
fn start(data: &[Counts]) -> (f64, f64) {
    let normal = Normal::standard();
    let pts: Vec<(f64, f64)> = data
        .iter()
        .map(|c| {
            let p = (c.exceed as f64 + 0.5) / (c.n as f64 + 1.0);
            (c.im.ln(), normal.inverse_cdf(p))
        })
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    if slope.is_finite() && slope > 0.0 {
        // z = (x - ln theta) / beta: slope 1 / beta, zero at x = ln theta.
        (mx - my / slope, (1.0 / slope).ln())
    } else {
        (mx, 0.5f64.ln())
    }
}

/// Standard errors of `(ln theta, ln beta)` at `(theta, beta)` from the inverse Fisher
/// information of the probit parameters `(a, b)` (module doc); `None` when it is not positive
/// definite.
fn standard_errors(data: &[Counts], theta: f64, beta: f64) -> Option<(f64, f64)> {
    let (b, a) = (1.0 / beta, -theta.ln() / beta);
    let (mut i00, mut i01, mut i11) = (0.0, 0.0, 0.0);
    for c in data {
        let x = c.im.ln();
        let eta = a + b * x;
        let (p, q) = (phi_cdf(eta), phi_cdf(-eta));
        let w = c.n as f64 * phi_pdf(eta).powi(2) / (p * q);
        if w.is_finite() {
            i00 += w;
            i01 += w * x;
            i11 += w * x * x;
        }
    }
    let det = i00 * i11 - i01 * i01;
    if !(det > 0.0 && det.is_finite()) {
        return None;
    }
    let (vaa, vab, vbb) = (i11 / det, -i01 / det, i00 / det);
    // ln theta = -a / b: gradient (-1 / b, a / b^2); ln beta = -ln b: gradient (0, -1 / b).
    let (ga, gb) = (-1.0 / b, a / (b * b));
    let var_t = ga * ga * vaa + 2.0 * ga * gb * vab + gb * gb * vbb;
    let var_b = vbb / (b * b);
    (var_t > 0.0 && var_b > 0.0).then(|| (var_t.sqrt(), var_b.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_fractions_give_back_the_curve() {
        // 10^6 runs per intensity with the curve's own fractions: the fit is the curve.
        let (theta, beta): (f64, f64) = (0.8, 0.45);
        let counts: Vec<Counts> = [0.3, 0.5, 0.7, 0.9, 1.2, 1.8]
            .iter()
            .map(|&im| {
                let n = 1_000_000u64;
                let p = phi_cdf((im / theta).ln() / beta);
                Counts {
                    im,
                    n,
                    exceed: (p * n as f64).round() as u64,
                }
            })
            .collect();
        let f = fit(&counts);
        assert_eq!(f.outcome, FitOutcome::Ok);
        assert!((f.theta / theta - 1.0).abs() < 1e-4, "{f:?}");
        assert!((f.beta / beta - 1.0).abs() < 1e-4, "{f:?}");
        assert!(f.theta_lo < theta && theta < f.theta_hi);
        assert!((f.probability(theta) - 0.5).abs() < 1e-4);
    }

    #[test]
    fn data_without_an_answer_are_outcomes() {
        let c = |im, n, exceed| Counts { im, n, exceed };
        assert_eq!(
            fit(&[c(1.0, 10, 0), c(2.0, 10, 0)]).outcome,
            FitOutcome::NoOverlap
        );
        assert_eq!(
            fit(&[c(1.0, 10, 10), c(2.0, 10, 10)]).outcome,
            FitOutcome::NoOverlap
        );
        assert_eq!(
            fit(&[c(1.0, 10, 0), c(2.0, 10, 10)]).outcome,
            FitOutcome::Separated
        );
        assert_eq!(fit(&[c(1.0, 10, 3)]).outcome, FitOutcome::Invalid);
        assert_eq!(
            fit(&[c(1.0, 10, 3), c(-1.0, 10, 3)]).outcome,
            FitOutcome::Invalid
        );
        assert_eq!(
            fit(&[c(1.0, 10, 11), c(2.0, 10, 3)]).outcome,
            FitOutcome::Invalid
        );
        assert!(fit(&[c(1.0, 10, 0), c(2.0, 10, 10)]).theta.is_nan());
    }
}
