//! The annual risk over the stripes' own fragility (model.md §13, docs/scenes.md): `lambda_f`
//! over the lognormal fitted to the share of motions that pass the limit at each stripe
//! (`P(f | IM)` itself, which needs no capacity; [`super::RandomSummary::lambda_f_stripes`]),
//! and its 95 % interval by a bootstrap over the motions.
//!
//! Every stripe scales the same motions (a motion is a case), so the stripes' counts are not
//! independent binomials: a resample draws motions ([`bootstrap::percentile`], a stream
//! seeded by the study's seed alone, the same at every design) and takes each drawn motion's
//! runs at every stripe together. Its counts are fitted ([`fragility::estimate`]) and
//! integrated over the hazard ([`lambda_f_lognormal`]). A resample without a fit (its counts
//! separated, or no drawn motion passing at any stripe) is left out of the quantiles.
//!
//! Cost: [`bootstrap::RESAMPLES`] fits and quadratures a design, about as many as the
//! capacities' bootstrap ([`super::risk`]) takes.

use rayon::prelude::*;

use super::risk::StripesFit;
use crate::numeric::mix64;
use crate::stats::bootstrap;
use crate::stats::fragility::{self, Counts, FitOutcome, Fragility};
use crate::stats::hazard::{Hazard, SiteHazard, lambda_f_lognormal};

/// The 95 % bootstrap interval `(lo, hi)` of `lambda_f` over the stripes' fitted fragility of
/// one design, from its runs `(case, im, exceeded)` sorted by case (every stripe's run of
/// every motion whose outcome is `ok`), the stripes' intensities `ims` (g) and the hazard.
/// NaN when no resample has a fit.
pub fn lambda_f_interval(
    runs: &[(u32, f64, bool)],
    ims: &[f64],
    hazard: &Hazard,
    seed: u64,
) -> (f64, f64) {
    // Each motion's runs: the stripe's index and whether it exceeded.
    let motions: Vec<Vec<(usize, bool)>> = runs
        .chunk_by(|a, b| a.0 == b.0)
        .map(|m| {
            m.iter()
                .filter_map(|r| Some((ims.iter().position(|&x| x == r.1)?, r.2)))
                .collect()
        })
        .collect();
    let stat = |idx: &[usize]| {
        let mut counts: Vec<Counts> = ims
            .iter()
            .map(|&im| Counts {
                im,
                n: 0,
                exceed: 0,
            })
            .collect();
        for &i in idx {
            for &(j, exceeded) in &motions[i] {
                counts[j].n += 1;
                counts[j].exceed += u64::from(exceeded);
            }
        }
        let lambda = fragility::estimate(&counts).map_or(f64::NAN, |(theta, beta)| {
            lambda_f_lognormal(hazard, theta, beta)
        });
        vec![lambda]
    };
    bootstrap::percentile(motions.len(), mix64(seed ^ 0x57_A1BE), stat)
        .first()
        .copied()
        .unwrap_or((f64::NAN, f64::NAN))
}

/// A design and the 95 % interval `(lo, hi)` of its `lambda_f` over its stripes' fit.
pub type StripesInterval = (u64, (f64, f64));

/// Design `design`'s own fit from its stripes where it ended ok, with its `lambda_f` and
/// interval when the study gives a hazard.
pub fn stripes_fit(
    design: u64,
    fits: &[(u64, Fragility)],
    intervals: &[StripesInterval],
    hazard: Option<&SiteHazard>,
) -> Option<StripesFit> {
    let f = fits
        .binary_search_by_key(&design, |f| f.0)
        .ok()
        .map(|i| fits[i].1)
        .filter(|f| f.outcome == FitOutcome::Ok)?;
    let lambda_f = hazard.and_then(|h| {
        let (lo, hi) = intervals
            .binary_search_by_key(&design, |x| x.0)
            .ok()
            .map(|i| intervals[i].1)?;
        Some((lambda_f_lognormal(&h.curve, f.theta, f.beta), lo, hi))
    });
    Some(StripesFit {
        theta: f.theta,
        beta: f.beta,
        lambda_f,
    })
}

/// Each design's interval of `lambda_f` over its stripes' fit ([`lambda_f_interval`]), where
/// the fit ended ok and the study gives a hazard: `fits` in design order, `runs` every stripe's
/// run of every motion `(design, case, im, exceeded)` sorted by design then case, `ims` the
/// stripes.
pub fn stripes_intervals(
    fits: &[(u64, Fragility)],
    runs: &[(u64, u32, f64, bool)],
    ims: &[f64],
    hazard: Option<&SiteHazard>,
    seed: u64,
) -> Vec<StripesInterval> {
    let Some(h) = hazard else {
        return Vec::new();
    };
    fits.par_iter()
        .filter(|(_, f)| f.outcome == FitOutcome::Ok)
        .map(|(design, _)| {
            let lo = runs.partition_point(|r| r.0 < *design);
            let hi = runs.partition_point(|r| r.0 <= *design);
            let own: Vec<(u32, f64, bool)> = runs[lo..hi].iter().map(|r| (r.1, r.2, r.3)).collect();
            (*design, lambda_f_interval(&own, ims, &h.curve, seed))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Motions whose exceedance at each stripe follows a lognormal capacity: a motion of
    /// capacity `c` exceeds at every stripe above `c` (the capacities at the quantiles of
    /// `(theta, beta)`).
    fn runs(n: usize, theta: f64, beta: f64, ims: &[f64]) -> Vec<(u32, f64, bool)> {
        let normal = statrs::distribution::Normal::standard();
        let mut out = Vec::new();
        for i in 0..n {
            let z = statrs::distribution::ContinuousCDF::inverse_cdf(
                &normal,
                (i as f64 + 0.5) / n as f64,
            );
            let c = theta * (beta * z).exp();
            for &im in ims {
                out.push((i as u32, im, im > c));
            }
        }
        out
    }

    #[test]
    fn the_interval_brackets_the_fit_and_narrows_with_the_motions() {
        let ims = [0.1, 0.15, 0.2, 0.25, 0.3, 0.4];
        let h = Hazard::Power {
            k0: 3.72e-4,
            k: 2.5,
        };
        let (theta, beta) = (0.25, 0.4);
        let width = |n: usize| {
            let r = runs(n, theta, beta, &ims);
            let counts: Vec<Counts> = ims
                .iter()
                .map(|&im| Counts {
                    im,
                    n: n as u64,
                    exceed: r.iter().filter(|x| x.1 == im && x.2).count() as u64,
                })
                .collect();
            let (t, b) = fragility::estimate(&counts).unwrap();
            let value = lambda_f_lognormal(&h, t, b);
            let (lo, hi) = lambda_f_interval(&r, &ims, &h, 7);
            assert!(lo < value && value < hi, "{lo} {value} {hi}");
            // Seeded: the same interval again.
            assert_eq!(lambda_f_interval(&r, &ims, &h, 7), (lo, hi));
            (hi - lo) / value
        };
        let (w100, w1600) = (width(100), width(1600));
        // The interval narrows as 1 / sqrt(n): 16 times the motions, about a quarter the width.
        assert!(w1600 < 0.4 * w100 && w1600 > 0.15 * w100, "{w100} {w1600}");
        // The exact curve's rate lies inside the larger sample's interval.
        let exact = lambda_f_lognormal(&h, theta, beta);
        let r = runs(1600, theta, beta, &ims);
        let (lo, hi) = lambda_f_interval(&r, &ims, &h, 7);
        assert!(lo < exact && exact < hi, "{lo} {exact} {hi}");
    }

    #[test]
    fn motions_without_a_fit_give_no_interval() {
        let ims = [0.1, 0.2];
        let h = Hazard::Power {
            k0: 3.72e-4,
            k: 2.5,
        };
        // No motion ever exceeds.
        let r: Vec<(u32, f64, bool)> = (0..50u32)
            .flat_map(|i| ims.iter().map(move |&im| (i, im, false)))
            .collect();
        let (lo, hi) = lambda_f_interval(&r, &ims, &h, 1);
        assert!(lo.is_nan() && hi.is_nan());
        assert!(lambda_f_interval(&[], &ims, &h, 1).0.is_nan());
    }
}
