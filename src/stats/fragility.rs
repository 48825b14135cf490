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
//! `(ln theta, ln beta)` by the delta method, gives the standard errors.
//!
//! The 95 % intervals are the profile likelihood's: the values of `ln theta` (of `ln beta`)
//! whose profile `max over the other of ln L` lies within `chi2_1(0.95) / 2 = 1.92` of the
//! maximum. Unlike the Wald interval `exp(+-1.96 se)` they follow the likelihood where it is
//! far from quadratic, as when few runs fail at few intensities or the counts come close to
//! separating: there the Wald interval of `theta` can span a hundred orders of magnitude while
//! the likelihood pins `theta` between two stripes. An end the likelihood does not bound (the
//! profile stays within 1.92 all the way) is `0` or infinite; `beta`'s lower end is `0` when the
//! profile stays within 1.92 down to `1e-4` times the estimate (the curve may be a step). The
//! probit log-likelihood is concave in `(a, b)`, so with one parameter held the other's profile
//! is unimodal: each inner maximum is a one-dimensional Brent search, each end a Brent root.
//!
//! The maximum does not exist when the counts do not overlap: every run below some intensity
//! safe and every run above it failed (`beta -> 0`), or no run (or every run) failed at any
//! intensity (`theta` out of the data's reach). Those are outcomes ([`FitOutcome`]), not
//! numbers.

use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::brent::{BrentOpt, BrentRoot};
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
    /// 95 % profile-likelihood intervals (module doc); `0` or infinite where the likelihood
    /// does not bound them.
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

/// `ln Phi(z)` finite for every finite `z`: the CDF's logarithm down to `z = -37` (where `Phi`
/// is `6e-300`, clear of underflow), below it the asymptotic series
/// `-z^2 / 2 - ln(-z sqrt(2 pi)) + ln(1 - 1/z^2 + 3/z^4 - 15/z^6 + 105/z^8)`, whose next term is
/// below `1e-12` there. A likelihood whose probabilities underflow keeps its shape (a profile's
/// search needs it: far out in a small `beta` every probability is below `1e-308`).
fn ln_phi(z: f64) -> f64 {
    if z > -37.0 {
        return phi_cdf(z).ln();
    }
    let r = 1.0 / (z * z);
    let series = 1.0 - r * (1.0 - r * (3.0 - r * (15.0 - r * 105.0)));
    -0.5 * z * z - (-z * (2.0 * std::f64::consts::PI).sqrt()).ln() + series.ln()
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
            // ln p and ln(1 - p) from the tails, without cancellation or underflow.
            let (ln_p, ln_q) = (ln_phi(z), ln_phi(-z));
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

/// The maximum of the likelihood of `counts` (module doc) alone: `(theta, beta)`, or the outcome
/// that says why there is none. [`fit`]'s estimate bit for bit, without its standard errors and
/// profile intervals (a bootstrap's statistic). Intensities with no runs are ignored.
pub fn estimate(counts: &[Counts]) -> Result<(f64, f64), FitOutcome> {
    let data: Vec<Counts> = counts.iter().copied().filter(|c| c.n > 0).collect();
    maximum(&data).map(|(t, b, _)| (t.exp(), b.exp()))
}

/// The maximum of the likelihood of `data` (runs at every intensity): `(ln theta, ln beta)`
/// and the negative log-likelihood there.
fn maximum(data: &[Counts]) -> Result<(f64, f64, f64), FitOutcome> {
    let valid = data.len() >= 2
        && data
            .iter()
            .all(|c| c.im.is_finite() && c.im > 0.0 && c.exceed <= c.n);
    if !valid {
        return Err(FitOutcome::Invalid);
    }
    let total: u64 = data.iter().map(|c| c.n).sum();
    let exceed: u64 = data.iter().map(|c| c.exceed).sum();
    if exceed == 0 || exceed == total {
        return Err(FitOutcome::NoOverlap);
    }
    if separated(data) {
        return Err(FitOutcome::Separated);
    }
    let (t0, b0) = start(data);
    let simplex = vec![
        vec![t0, b0],
        vec![t0 + 0.2 * b0.exp(), b0],
        vec![t0, b0 + 0.3],
    ];
    let best = NelderMead::new(simplex)
        .with_sd_tolerance(1e-13)
        .ok()
        .and_then(|solver| {
            Executor::new(Nll(data), solver)
                .configure(|s| s.max_iters(4000))
                .run()
                .ok()
        })
        .and_then(|r| r.state().get_best_param().cloned())
        .ok_or(FitOutcome::Failed)?;
    let (ln_theta, ln_beta) = (best[0], best[1]);
    let nll = Nll(data).at(ln_theta, ln_beta);
    if !(ln_theta.is_finite() && ln_beta.is_finite() && nll.is_finite()) {
        return Err(FitOutcome::Failed);
    }
    Ok((ln_theta, ln_beta, nll))
}

/// Fits the lognormal fragility curve to `counts` (module doc). Intensities with no runs are
/// ignored.
pub fn fit(counts: &[Counts]) -> Fragility {
    let data: Vec<Counts> = counts.iter().copied().filter(|c| c.n > 0).collect();
    let (ln_theta, ln_beta, nll) = match maximum(&data) {
        Ok(m) => m,
        Err(outcome) => return Fragility::failed(outcome),
    };
    let (theta, beta) = (ln_theta.exp(), ln_beta.exp());
    let Some((se_t, se_b)) = standard_errors(&data, theta, beta) else {
        return Fragility::failed(FitOutcome::Failed);
    };
    let profile = Profile {
        nll: Nll(&data),
        best: [ln_theta, ln_beta],
        nll_min: nll,
        theta_range: theta_range(&data, ln_theta),
    };
    let (t_lo, t_hi) = (profile.end(0, -1.0, se_t), profile.end(0, 1.0, se_t));
    let (b_lo, b_hi) = (profile.end(1, -1.0, se_b), profile.end(1, 1.0, se_b));
    Fragility {
        outcome: FitOutcome::Ok,
        theta,
        beta,
        se_ln_theta: se_t,
        se_ln_beta: se_b,
        theta_lo: t_lo.exp(),
        theta_hi: t_hi.exp(),
        beta_lo: b_lo.exp(),
        beta_hi: b_hi.exp(),
        log_likelihood: -nll,
    }
}

/// Half the 95 % quantile of chi-squared with one degree of freedom: a profile-likelihood
/// interval holds the values whose profile log-likelihood is within this of the maximum.
const HALF_CHI2_95: f64 = 0.5 * 3.841_458_820_694_124;

/// How far past the data a profile end is looked for, in `ln` units: farther, the end is
/// unbounded (`0` or infinite).
const REACH: f64 = 30.0;

/// The smallest `beta`, relative to the estimate, a profile's lower end is looked for at:
/// below it the curve is a step, and the interval reaches `beta = 0`.
const STEP: f64 = 1e-4;

/// The range of `ln theta` a profile searches: the data's `ln IM` widened by [`REACH`] (and
/// holding the maximum).
fn theta_range(data: &[Counts], ln_theta: f64) -> (f64, f64) {
    let (lo, hi) = data.iter().fold((ln_theta, ln_theta), |(lo, hi), c| {
        (lo.min(c.im.ln()), hi.max(c.im.ln()))
    });
    (lo - REACH, hi + REACH)
}

/// A function of one variable for argmin's one-dimensional solvers.
struct Line<F: Fn(f64) -> f64>(F);

impl<F: Fn(f64) -> f64> CostFunction for Line<F> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, p: &f64) -> Result<f64, Error> {
        Ok((self.0)(*p))
    }
}

/// The profile likelihood about the maximum `best` (`[ln theta, ln beta]`, where the negative
/// log-likelihood is `nll_min`).
struct Profile<'a> {
    nll: Nll<'a>,
    best: [f64; 2],
    nll_min: f64,
    theta_range: (f64, f64),
}

impl Profile<'_> {
    /// The smallest negative log-likelihood with parameter `which` (0: `ln theta`, 1:
    /// `ln beta`) held at `value`, over the other (a Brent search: the profile is unimodal).
    fn at(&self, which: usize, value: f64) -> f64 {
        let (lo, hi) = if which == 0 {
            (self.best[1] - REACH, self.best[1] + REACH)
        } else {
            self.theta_range
        };
        let cost = |other: f64| {
            let v = if which == 0 {
                self.nll.at(value, other)
            } else {
                self.nll.at(other, value)
            };
            v.min(f64::MAX)
        };
        // A grid first, then Brent between the best point's neighbours (the function is
        // unimodal, so its minimum lies there): the range is up to 60 `ln` units wide and the
        // valley, with a small `beta` held, about `beta` wide.
        const GRID: usize = 64;
        let x = |i: usize| lo + (hi - lo) * i as f64 / GRID as f64;
        let k = (0..=GRID)
            .map(|i| (i, cost(x(i))))
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .map_or(0, |p| p.0);
        let (a, b) = (x(k.saturating_sub(1)), x((k + 1).min(GRID)));
        // With `beta` held, the likelihood's valley in `ln theta` is about `beta` wide: the
        // search resolves it to a thousandth of that.
        let tol = if which == 1 {
            1e-3 * value.exp().min(1.0)
        } else {
            1e-7
        };
        Executor::new(Line(cost), BrentOpt::new(a, b).set_tolerance(1e-15, tol))
            .configure(|s| s.max_iters(500))
            .run()
            .ok()
            .map(|r| r.state().get_best_cost())
            .unwrap_or(f64::INFINITY)
    }

    /// The end of the 95 % interval of parameter `which` on the side `side` (`-1`, `+1`): where
    /// the profile rises `HALF_CHI2_95` above the maximum, bracketed by steps from the maximum
    /// that double from a quarter of the Wald standard error `se`, then a Brent root; `-inf` or
    /// `inf` when no step within [`REACH`] of the maximum (past the data, for `ln theta`; down to
    /// [`STEP`] times the estimate for `beta`'s lower end) gets there.
    fn end(&self, which: usize, side: f64, se: f64) -> f64 {
        let rise = |v: f64| self.at(which, v) - self.nll_min - HALF_CHI2_95;
        let from = self.best[which];
        let limit = if which == 1 {
            // A dispersion below `STEP` times the estimate is a step: no lower end above it
            // is no lower end.
            if side < 0.0 { -STEP.ln() } else { REACH }
        } else if side > 0.0 {
            self.theta_range.1 - from
        } else {
            from - self.theta_range.0
        };
        let mut near = from;
        let mut step = if se.is_finite() && se > 0.0 {
            0.25 * se.min(1.0)
        } else {
            0.05
        };
        loop {
            let far = from + side * step.min(limit);
            if rise(far) >= 0.0 {
                let (a, b) = if side > 0.0 { (near, far) } else { (far, near) };
                return Executor::new(Line(rise), BrentRoot::new(a, b, 1e-10))
                    .configure(|s| s.max_iters(200))
                    .run()
                    .ok()
                    .map(|r| r.state().best_param.unwrap_or(far))
                    .unwrap_or(far);
            }
            if step >= limit {
                return side * f64::INFINITY;
            }
            near = far;
            step *= 2.0;
        }
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
    fn ln_phi_is_the_log_cdf_and_stays_finite_in_the_far_tail() {
        for z in [-36.9, -30.0, -10.0, -1.0, 0.0, 2.0] {
            assert!((ln_phi(z) - phi_cdf(z).ln()).abs() <= 1e-12 * phi_cdf(z).ln().abs().max(1.0));
        }
        // At the switch (-37 takes the series) the two forms agree.
        let (a, b) = (phi_cdf(-37.0).ln(), ln_phi(-37.0));
        assert!((a - b).abs() <= 1e-12 * a.abs(), "{a} {b}");
        assert!(ln_phi(-1e3).is_finite() && ln_phi(-1e3) < ln_phi(-100.0));
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
