//! The range of a cubic Hermite interpolant over one interval, from its Bézier points: the
//! bound the random scene's whole-interval tests ([`super::run`]) and the Sa pass
//! ([`super::intensity`]) put on a watched function between two samples.
//!
//! The interpolant from `(g0, g0')` to `(g1, g1')` over an interval of `h` lies in the convex
//! hull of its Bézier points `g0, g0 + h g0' / 3, g1 - h g1' / 3, g1`; a function whose fourth
//! derivative is at most `B4` in size is within `B4 h^4 / 384` of its interpolant.

/// The range `(min, max)` of the convex hull of the Bézier points of the cubic Hermite
/// interpolant from `(g0, d0)` to `(g1, d1)` over an interval of `3 third` (module doc): the
/// smallest and largest of `g0, p, q, g1` with NaN points left out ([`f64::min`],
/// [`f64::max`]). Without a NaN among them (the rule), by plain comparisons in a tree, which are
/// the same values (a minimum does not depend on the order; a zero's sign can differ, which no
/// caller can see: the range is only added to and compared) with a shorter dependency chain than
/// the NaN-aware fold; a NaN anywhere (or `inf - inf` in the test's sum) takes the fold.
#[inline]
pub(super) fn hull(g0: f64, d0: f64, g1: f64, d1: f64, third: f64) -> (f64, f64) {
    let (p, q) = (g0 + third * d0, g1 - third * d1);
    if ((g0 + p) + (q + g1)).is_nan() {
        return hull_nan(g0, p, q, g1);
    }
    let min = |a: f64, b: f64| if a < b { a } else { b };
    let max = |a: f64, b: f64| if a > b { a } else { b };
    (min(min(g0, p), min(q, g1)), max(max(g0, p), max(q, g1)))
}

/// [`hull`] of Bézier points among which there may be NaNs: the NaN-aware fold.
#[cold]
#[inline(never)]
fn hull_nan(g0: f64, p: f64, q: f64, g1: f64) -> (f64, f64) {
    (g0.min(p).min(q).min(g1), g0.max(p).max(q).max(g1))
}
