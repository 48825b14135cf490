//! A number with its 95 % interval, or only a bound (no run passed), drawn on a `log10` scale:
//! a load study's risk (`lambda_f` or `p_f`) on its plotters charts ([`crate::report::charts::risk`])
//! and on its page ([`crate::report::html::numbers`]). The axis' span, the colour span of a map,
//! and the two-digit labels.

use super::super::plumbing::pad;

/// A design's number: its value and 95 % interval; `bound` when no run passed (the value is
/// then the interval's upper end).
#[derive(Clone, Copy, Debug)]
pub struct Value {
    pub v: f64,
    pub lo: f64,
    pub hi: f64,
    pub bound: bool,
}

impl Value {
    /// `log10` of what is drawn: the value, or the bound.
    pub fn log(&self) -> f64 {
        self.v.log10()
    }
}

/// A value as a label, two significant digits: `0.011`, `0.43`, `3.4e-5`.
pub fn short(v: f64) -> String {
    if (1e-3..10.0).contains(&v) {
        let digits = (1.0 - v.log10().floor()).max(0.0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.1e}")
    }
}

/// Decades of the profile's axis below a number known only as a bound.
const BOUND_DECADES: f64 = 1.0;

/// The profile's `log10` axis: every drawn value, interval end and the bare structure's line,
/// padded; at least 0.2 wide, and reaching [`BOUND_DECADES`] below a number known only as a
/// bound (no run passed), which lies anywhere below it, so that what the bound leaves open
/// shows.
pub fn log_span(pts: &[(f64, Value)], bare: Option<Value>) -> (f64, f64) {
    let values = || pts.iter().map(|(_, v)| v).chain(bare.iter());
    let (y0, y1) = pts
        .iter()
        .flat_map(|(_, v)| [v.lo, v.hi, v.v])
        .chain(bare.map(|b| b.v))
        .filter(|v| *v > 0.0)
        .map(f64::log10)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(y), b.max(y))
        });
    let open_below = values()
        .filter(|v| v.bound && v.v > 0.0)
        .map(|v| v.log() - BOUND_DECADES)
        .fold(f64::INFINITY, f64::min);
    pad(y0.min(open_below), y1.max(y0 + 0.2), 0.1)
}

/// The map's colour span in `log10` of the number: the values' range `[l0, l1]`, widened about
/// its middle to the median width of the cells' 95 % intervals when it is narrower, so that
/// designs the estimates do not tell apart are not painted apart. Whether it was widened.
pub fn colour_span(l0: f64, l1: f64, cells: &[(u64, Option<Value>)]) -> (f64, f64, bool) {
    let mut widths: Vec<f64> = cells
        .iter()
        .filter_map(|c| c.1)
        .filter(|v| !v.bound && v.lo > 0.0 && v.hi > v.lo)
        .map(|v| v.hi.log10() - v.lo.log10())
        .collect();
    if widths.is_empty() || !l0.is_finite() || !l1.is_finite() {
        return (l0, l1, false);
    }
    widths.sort_by(f64::total_cmp);
    let w = widths[widths.len() / 2];
    if l1 - l0 >= w {
        return (l0, l1, false);
    }
    let mid = 0.5 * (l0 + l1);
    (mid - 0.5 * w, mid + 0.5 * w, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(v: f64, lo: f64, hi: f64, bound: bool) -> Value {
        Value { v, lo, hi, bound }
    }

    /// A design no run of which passed is drawn at its bound with the axis a decade below it;
    /// estimates keep their own tight axis.
    #[test]
    fn a_bound_leaves_a_decade_open_below_it() {
        let bound = value(0.018, 0.0, 0.018, true);
        let (y0, y1) = log_span(&[(0.0, bound)], Some(bound));
        assert!(y0 <= 0.018f64.log10() - BOUND_DECADES, "{y0}");
        assert!(y1 > 0.018f64.log10(), "{y1}");
        let estimate = value(0.02, 0.018, 0.022, false);
        let (y0, y1) = log_span(&[(0.0, estimate)], None);
        assert!(
            y0 > 0.018f64.log10() - 0.05 && y1 < 0.022f64.log10() + 0.2,
            "{y0} {y1}"
        );
    }
}
