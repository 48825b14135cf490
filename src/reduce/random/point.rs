//! The Monte Carlo reliability of one design point of a random or record study's grid: `p_f`,
//! the share of its realizations whose `|x|` passed the threshold, with its exact
//! (Clopper–Pearson) interval at [`CONFIDENCE`], and `beta = -Phi^-1(p_f)`.

use super::stream::PfAcc;
use crate::sim::random::RealizationRecord;
use crate::stats::binomial::clopper_pearson;
use crate::store::RunRow;

/// The confidence of `p_f`'s interval.
pub const CONFIDENCE: f64 = 0.95;

/// Monte Carlo reliability of one design point of the study's grid (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointPf {
    /// The design point (the study's grid, intensity included).
    pub point: u64,
    /// Realizations that ended `ok`, and those among them whose `|x|` passed the threshold.
    pub n: u64,
    pub exceed: u64,
    pub p_f: f64,
    pub p_f_lo: f64,
    pub p_f_hi: f64,
    /// `-Phi^-1(p_f)`.
    pub beta: f64,
    /// Mean of the realizations' `rms_x` (m).
    pub rms_x_mean: f64,
}

impl PointPf {
    /// The reliability of one design point from its realizations' rows; `threshold` (m) as the
    /// study sets it.
    pub fn of(point: u64, rows: &[RunRow<RealizationRecord>], threshold: Option<f64>) -> Self {
        let mut acc = PfAcc::default();
        for r in rows {
            acc.add(&r.record.record, threshold);
        }
        PointPf::of_counts(point, &acc, threshold)
    }

    /// The reliability of one design point from its realizations' counts.
    pub fn of_counts(point: u64, acc: &PfAcc, threshold: Option<f64>) -> Self {
        let (n, exceed, rms_x_mean) = acc.counts();
        if threshold.is_none() {
            return PointPf {
                point,
                n,
                exceed: 0,
                p_f: f64::NAN,
                p_f_lo: f64::NAN,
                p_f_hi: f64::NAN,
                beta: f64::NAN,
                rms_x_mean,
            };
        }
        let ci = clopper_pearson(exceed, n, CONFIDENCE);
        PointPf {
            point,
            n,
            exceed,
            p_f: ci.p,
            p_f_lo: ci.lo,
            p_f_hi: ci.hi,
            beta: beta_of(ci.p),
            rms_x_mean,
        }
    }
}

/// The reliability index `-Phi^-1(p)` (NaN for a NaN `p`).
pub fn beta_of(p: f64) -> f64 {
    if p.is_nan() {
        f64::NAN
    } else {
        -crate::reduce::common::stats::phi_inv(p)
    }
}
