//! A design point's realizations as they stream in, one at a time and in case order, with
//! memory bounded by a fixed budget rather than by the study's realizations.
//!
//! * `p_f` and its interval, `n_exceed` and `rms_x_mean` ([`PfAcc`]) are exact counts and a
//!   running sum, in case order: the same bits as over the point's rows held together.
//! * The core's statistics of the point at the design intensity ([`PointRuns`]): while the
//!   point's realizations fit the budget ([`EXACT_BUDGET`], 131,072) their [`Run`]s are kept
//!   and the core reduces them exactly ([`crate::reduce::common::Reducer::point_stats`]); beyond
//!   it they stream ([`Streamed`]):
//!   - the response's mean as the running sum over `n` (the same bits as exact), its SD (and
//!     the third and fourth central moments) by the one-pass update of Pébay (2008, *Formulas
//!     for robust, one-pass parallel computation of covariances and arbitrary-order
//!     statistical moments*, SAND2008-6212), in case order;
//!   - its minimum and maximum exact, its quartiles and median from the [`Sketch`] (integer
//!     counts in fixed log-spaced bins), within a relative [`super::sketch::ALPHA`] = 0.195 % of the
//!     exact ones;
//!   - `p_s` (the damping quantity) as its mean and SD over the realizations, the same way
//!     (its mean the same bits as exact);
//!   - the interval of `R` (with a strength) by the delta method on the moments
//!     ([`delta_interval`]) instead of the bootstrap, which it approximates to `O(1/n)` at
//!     these sizes; Anderson–Darling on `ln` of the response over the point's first `budget`
//!     realizations by case (a fixed subset, the same for any chunking);
//!   - the nominal design's table of cases: its first [`NOMINAL_ROWS`] realizations.
//!
//! Every figure depends only on the realizations and their case order, never on how they were
//! chunked, sharded or resumed, nor on the thread count.

use super::sketch::Sketch;
use crate::reduce::common::stats::{self, LogNormal};
use crate::reduce::common::{
    Class, Options, PointStats, Reducer, ResponseStats, Run, outcome_index, regions,
};
use crate::sim::Outcome;
use crate::sim::random::RandomRecord;
use crate::study::{DiSource, SafetyForm};

/// Realizations of a design point the reduction holds to reduce it exactly (about 72 bytes
/// each, 9 MiB); beyond this its statistics stream (module doc).
pub const EXACT_BUDGET: usize = 1 << 17;

/// Runs of a streamed nominal design kept for the report's table of its cases.
pub const NOMINAL_ROWS: usize = 100;

/// The counts behind [`super::PointPf`], taken one realization at a time.
#[derive(Clone, Copy, Debug)]
pub struct PfAcc {
    n: u64,
    exceed: u64,
    rms_sum: f64,
}

impl Default for PfAcc {
    fn default() -> Self {
        PfAcc {
            n: 0,
            exceed: 0,
            // The neutral element `Iterator::sum` starts from: the same bits as summing the
            // point's values together.
            rms_sum: std::iter::empty::<f64>().sum(),
        }
    }
}

impl PfAcc {
    pub fn add(&mut self, rec: &RandomRecord, threshold: Option<f64>) {
        if rec.outcome != Outcome::Ok {
            return;
        }
        self.n += 1;
        self.rms_sum += rec.rms_x;
        if threshold.is_some_and(|b| rec.amplitude > b) {
            self.exceed += 1;
        }
    }

    /// The ok realizations, those that passed the threshold, and the mean of their `rms_x`
    /// (m): what [`super::PointPf`] is made of.
    pub fn counts(&self) -> (u64, u64, f64) {
        (self.n, self.exceed, self.rms_sum / self.n as f64)
    }
}

/// Running mean and central moments to the fourth (module doc: Pébay's update), and the plain
/// sum in the order the values came.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moments {
    n: f64,
    sum: f64,
    mean: f64,
    m2: f64,
    m3: f64,
    m4: f64,
}

impl Default for Moments {
    fn default() -> Self {
        Moments {
            n: 0.0,
            sum: std::iter::empty::<f64>().sum(),
            mean: 0.0,
            m2: 0.0,
            m3: 0.0,
            m4: 0.0,
        }
    }
}

impl Moments {
    pub fn add(&mut self, x: f64) {
        self.sum += x;
        let n1 = self.n;
        self.n += 1.0;
        let n = self.n;
        let delta = x - self.mean;
        let dn = delta / n;
        let dn2 = dn * dn;
        let t1 = delta * dn * n1;
        self.mean += dn;
        self.m4 += t1 * dn2 * (n * n - 3.0 * n + 3.0) + 6.0 * dn2 * self.m2 - 4.0 * dn * self.m3;
        self.m3 += t1 * dn * (n - 2.0) - 3.0 * dn * self.m2;
        self.m2 += t1;
    }

    /// Mean and SD (`N - 1`), as [`stats::mean_sd`]: NaN when empty, the SD NaN for one value.
    /// The mean is the sum over `n` as there, the same bits for the same order of the values.
    pub fn mean_sd(&self) -> (f64, f64) {
        match self.n {
            0.0 => (f64::NAN, f64::NAN),
            1.0 => (self.sum, f64::NAN),
            n => (self.sum / n, (self.m2 / (n - 1.0)).sqrt()),
        }
    }
}

/// The core's part of a design point beyond its budget (module doc).
#[derive(Clone, Debug)]
pub struct Streamed {
    n_cases: u32,
    outcomes: [u32; 6],
    y: Moments,
    sketch: Sketch,
    di: Moments,
    /// Anderson–Darling over the first `budget` realizations.
    ad: (f64, f64),
    /// The first [`NOMINAL_ROWS`] runs.
    first: Vec<Run>,
}

impl Streamed {
    /// From the point's first runs (those that filled the budget).
    fn of(runs: &[Run]) -> Self {
        let logs: Vec<f64> = runs
            .iter()
            .filter(|r| r.outcome == Outcome::Ok && r.response > 0.0)
            .map(|r| r.response.ln())
            .collect();
        let mut s = Streamed {
            n_cases: 0,
            outcomes: [0; 6],
            y: Moments::default(),
            sketch: Sketch::new(),
            di: Moments::default(),
            ad: stats::anderson_darling(&logs),
            first: runs.iter().take(NOMINAL_ROWS).copied().collect(),
        };
        for r in runs {
            s.add(r);
        }
        s
    }

    fn add(&mut self, r: &Run) {
        self.n_cases += 1;
        self.outcomes[outcome_index(r.outcome)] += 1;
        if r.outcome == Outcome::Ok {
            self.y.add(r.response);
            self.sketch.add(r.response);
            self.di.add(r.di);
        }
    }
}

/// The core's runs of a design point at the design intensity as they come: held while they
/// fit the budget, streamed beyond it.
#[derive(Clone, Debug)]
pub enum PointRuns {
    Exact(Vec<Run>),
    Streamed(Box<Streamed>),
}

impl PointRuns {
    pub fn add(&mut self, run: Run, budget: usize) {
        match self {
            PointRuns::Exact(runs) => {
                runs.push(run);
                if runs.len() > budget {
                    *self = PointRuns::Streamed(Box::new(Streamed::of(runs)));
                }
            }
            PointRuns::Streamed(s) => s.add(&run),
        }
    }
}

/// A streamed point's statistics as [`Reducer::point_stats`] would give them from its runs,
/// with the estimates of the module doc where it needs them all; and its first runs (the
/// nominal design's table of cases).
pub fn point_stats(
    core: &Reducer,
    options: &Options,
    point: u64,
    s: Streamed,
) -> (PointStats, Vec<Run>) {
    let (mean, sd) = s.y.mean_sd();
    let k = core.stress_per_m();
    let strength = core.strength();
    let stress = LogNormal::from_mean_sd(k * mean, k * sd.max(0.0));
    let beta = stats::reliability_index(&strength, &stress);
    let (lo, hi) = if options.bootstrap == 0 {
        (f64::NAN, f64::NAN)
    } else {
        let confidence = core.study().reliability.confidence;
        delta_interval(&strength, k, &s.y, confidence)
    };
    let cn = stats::c_n(strength.cv(), stress.cv());
    let (di_mean, di_sd) = s.di.mean_sd();
    let n_ok = s.y.n as u32;
    let q = |p: f64| s.sketch.quantile(p);
    let stats = PointStats {
        point,
        n_cases: s.n_cases,
        n_ok,
        outcomes: s.outcomes,
        all_ok: n_ok == s.n_cases,
        response: ResponseStats {
            mean,
            sd,
            min: q(0.0),
            q1: q(0.25),
            median: q(0.5),
            q3: q(0.75),
            max: q(1.0),
            ideal: f64::NAN,
        },
        stress,
        reliability_index: beta,
        reliability: stats::phi(beta),
        reliability_lo: lo,
        reliability_hi: hi,
        cn,
        safety_factor: match options.safety_form {
            SafetyForm::Exact => stats::safety_factor_exact_z(-beta, cn),
            SafetyForm::Paper => stats::safety_factor_paper(beta, cn),
        },
        ad_stat: s.ad.0,
        ad_p: s.ad.1,
        di: match options.di_source {
            DiSource::Ideal => f64::NAN,
            DiSource::Mean => di_mean,
        },
        di_ideal: f64::NAN,
        di_sd,
        perfectibility: f64::NAN,
        rank: None,
        pareto: false,
        class: Class::NoData,
        zone: regions::NO_REGION,
        robust: false,
    };
    (stats, s.first)
}

/// The interval of `R = Phi(beta)` at `confidence` by the delta method, for a point whose
/// response (in m; stress `k` times it) has the moments `y`:
///
/// ```text
/// beta(m, v) = (mu_ln_s - ln m + l / 2) / sqrt(sigma_ln_s^2 + l),   l = ln(1 + v / m^2),
/// Var(beta) ~ g_m^2 Var(m) + 2 g_m g_v Cov(m, v) + g_v^2 Var(v),   g = grad beta,
/// Var(m) = k^2 mu_2 / n,  Cov(m, v) = k^3 mu_3 / n,  Var(v) = k^4 (mu_4 - mu_2^2) / n,
/// ```
///
/// `m`, `v` the stress's mean and variance, `mu_j` the response's central moments; then
/// `[Phi(beta - z se), Phi(beta + z se)]`, `z = Phi^-1((1 + confidence) / 2)`. The bootstrap's
/// percentile interval tends to it as `n` grows (both are first-order correct); NaN for fewer
/// than 2 values or without a strength.
pub fn delta_interval(strength: &LogNormal, k: f64, y: &Moments, confidence: f64) -> (f64, f64) {
    let n = y.n;
    if n < 2.0 {
        return (f64::NAN, f64::NAN);
    }
    let (mu2, mu3, mu4) = (y.m2 / n, y.m3 / n, y.m4 / n);
    let m = k * y.sum / n;
    let v = k * k * y.m2 / (n - 1.0);
    let r = v / (m * m);
    let l = r.ln_1p();
    let num = strength.mu_ln - (m.ln() - l / 2.0);
    let den = (strength.sigma_ln * strength.sigma_ln + l).sqrt();
    let beta = num / den;
    let dl_dm = -2.0 * r / m / (1.0 + r);
    let dl_dv = 1.0 / (m * m) / (1.0 + r);
    let grad = |dl: f64, dnum: f64| (dnum * den - num * dl / (2.0 * den)) / (den * den);
    let g_m = grad(dl_dm, -1.0 / m + dl_dm / 2.0);
    let g_v = grad(dl_dv, dl_dv / 2.0);
    let var = (g_m * g_m * k * k * mu2
        + 2.0 * g_m * g_v * k.powi(3) * mu3
        + g_v * g_v * k.powi(4) * (mu4 - mu2 * mu2))
        / n;
    let se = var.max(0.0).sqrt();
    if !(beta.is_finite() && se.is_finite()) {
        return (f64::NAN, f64::NAN);
    }
    let z = stats::phi_inv(0.5 + confidence / 2.0);
    (stats::phi(beta - z * se), stats::phi(beta + z * se))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::Rng;
    use rand_pcg::Pcg64Mcg;

    /// A lognormal sample of `n` values (median 0.01, log-SD 0.2) from `seed`.
    fn lognormal(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = Pcg64Mcg::new(u128::from(seed) << 1 | 1);
        (0..n)
            .map(|_| {
                // A uniform in (0, 1) from the top 53 bits, never 0.
                let u = ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
                0.01 * (0.2 * stats::phi_inv(u)).exp()
            })
            .collect()
    }

    #[test]
    fn moments_match_the_two_pass_mean_and_sd() {
        let xs = lognormal(10_000, 1);
        let mut m = Moments::default();
        xs.iter().for_each(|&x| m.add(x));
        let (a, b) = (m.mean_sd(), stats::mean_sd(&xs));
        assert_eq!(a.0.to_bits(), b.0.to_bits());
        assert!((a.1 / b.1 - 1.0).abs() < 1e-10);
        let mut one = Moments::default();
        assert!(one.mean_sd().0.is_nan());
        one.add(2.5);
        assert_eq!(one.mean_sd().0, 2.5);
        assert!(one.mean_sd().1.is_nan());
    }

    #[test]
    fn the_delta_interval_agrees_with_the_bootstrap() {
        // A strength whose R is about 0.98, so that the interval is not pinned at 1.
        let xs = lognormal(20_000, 7);
        let k = 1e10;
        let strength = LogNormal::from_mean_sd(1.6e8, 1.2e7);
        let mut m = Moments::default();
        xs.iter().for_each(|&x| m.add(x));
        let stresses: Vec<f64> = xs.iter().map(|x| k * x).collect();
        let (blo, bhi) = stats::bootstrap_reliability(&stresses, &strength, 2000, 0.95, 3);
        let (lo, hi) = delta_interval(&strength, k, &m, 0.95);
        let z = |p: f64| stats::phi_inv(p);
        // In the index, the two intervals' ends within 10 % of the interval's width.
        let w = z(bhi) - z(blo);
        assert!(w > 0.0 && (z(lo) - z(blo)).abs() < 0.1 * w, "{lo} {blo}");
        assert!((z(hi) - z(bhi)).abs() < 0.1 * w, "{hi} {bhi}");
        let no_strength = LogNormal::from_mean_sd(f64::NAN, f64::NAN);
        assert!(delta_interval(&no_strength, k, &m, 0.95).0.is_nan());
    }
}
