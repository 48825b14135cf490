//! Ranking: perfectibility (eq. 11), rank by it, and the Pareto set on (R, DI).
//!
//! A study without a strength (`[reliability] strength_mean`, `strength_sd`) has no R at any
//! point ([`computes_r`] is false): perfectibility is then the damping quantity alone,
//! `P = 100 DI / DI_max` (eq. 11 with `WF1 = 0`, `WF2 = 1`), the ranking follows it, and the
//! Pareto set, which needs R, is empty.

use super::PointStats;
use super::stats::perfectibility;

/// Fills `perfectibility`, `rank` and `pareto` of every point; returns `(R_max, DI_max)`, the
/// eq. 11 denominators (the best R and DI over the points where both are known).
///
/// Rank 1 is the highest perfectibility; ties go to the lower mean response (the design that
/// stays furthest from trouble: a random study whose designs all kept `p_s = 1` ranks by its
/// margin to the limit), then to the lower point index. A point whose R or
/// DI is unknown (no ok run, no ideal run) gets no rank and is never Pareto-optimal.
pub fn apply(points: &mut [PointStats], wf1: f64, wf2: f64) -> (f64, f64) {
    let with_r = computes_r(points);
    let known = |p: &PointStats| (!with_r || p.reliability.is_finite()) && p.di.is_finite();
    let r_max = points
        .iter()
        .filter(|p| known(p))
        .map(|p| p.reliability)
        .fold(f64::NAN, f64::max);
    let di_max = points
        .iter()
        .filter(|p| known(p))
        .map(|p| p.di)
        .fold(f64::NAN, f64::max);
    for p in points.iter_mut() {
        p.perfectibility = if known(p) && with_r {
            perfectibility(p.reliability, p.di, r_max, di_max, wf1, wf2)
        } else if known(p) {
            100.0 * super::stats::of_best(p.di, di_max)
        } else {
            f64::NAN
        };
        p.rank = None;
        p.pareto = false;
    }
    let mut order: Vec<usize> = (0..points.len()).filter(|&i| known(&points[i])).collect();
    order.sort_by(|&a, &b| {
        points[b]
            .perfectibility
            .total_cmp(&points[a].perfectibility)
            .then(points[a].response.mean.total_cmp(&points[b].response.mean))
            .then(points[a].point.cmp(&points[b].point))
    });
    for (r, &i) in order.iter().enumerate() {
        points[i].rank = Some(r as u64 + 1);
    }
    for i in pareto_front(points) {
        points[i].pareto = true;
    }
    (r_max, di_max)
}

/// Whether the sweep has an R anywhere: false for a study without a strength (module doc).
pub fn computes_r(points: &[PointStats]) -> bool {
    points.iter().any(|p| p.reliability.is_finite())
}

/// Indices of the points not dominated on (R, DI), both maximised: no other point has R and
/// DI at least as large and one of them larger. Equal points are all kept. O(n log n).
pub fn pareto_front(points: &[PointStats]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].reliability.is_finite() && points[i].di.is_finite())
        .collect();
    // R descending, then DI descending: a point is dominated iff an earlier point has a DI
    // larger than its own, or an equal DI with a larger R.
    order.sort_by(|&a, &b| {
        points[b]
            .reliability
            .total_cmp(&points[a].reliability)
            .then(points[b].di.total_cmp(&points[a].di))
    });
    let mut front = Vec::new();
    let mut best: Option<(f64, f64)> = None; // (R, DI) of the point holding the best DI so far
    for i in order {
        let (r, di) = (points[i].reliability, points[i].di);
        let keep = match best {
            None => true,
            Some((br, bd)) => di > bd || (di == bd && r == br),
        };
        if keep {
            front.push(i);
        }
        if best.is_none_or(|(_, bd)| di > bd) {
            best = Some((r, di));
        }
    }
    front.sort_unstable();
    front
}
