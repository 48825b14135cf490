//! The words every section shares: how a scene words the core's sections ([`SceneText`]), the
//! size of a table ([`MAX_ROWS`]), numbers at fixed precision, probabilities, intervals, design
//! points and the ranked points.

use crate::reduce::{PointStats, Summary};
use crate::report::text::{axis_value, fmt_num};

/// Rows a report table shows at most.
pub const MAX_ROWS: usize = 30;

/// What a scene adds to the report, and how the core's sections word it for that scene. The
/// default is the free-decay scene's: no section of its own, design points, cases per point,
/// no motion that is not periodic. The harmonic scene's is [`super::harmonic::scene_text`].
#[derive(Clone, Debug, PartialEq)]
pub struct SceneText {
    /// The scene's own section, after the recommendation.
    pub section: String,
    /// What one design point is called, and several (`design point`, `design points`).
    pub point: (&'static str, &'static str),
    /// The runs of one design point (`81 frequencies × 5 cases per design`); `None`: its cases
    /// (`4 cases per point`).
    pub per_point: Option<String>,
    /// The study's motions that are not periodic carry their window maxima
    /// (`nonperiodic_peak = "window"`), not amplitudes over a design life.
    pub window_peaks: bool,
    /// Every run the study's numbers rest on, when the core's count (its runs at the design
    /// intensity) is not all of them, and what they were (`80,000 at 5 intensities, 16,000
    /// capacity searches`).
    pub runs: Option<(u64, String)>,
    /// What the study is, stated at the report's top (the random scene's load, structure,
    /// limit, intensity measure and hazard).
    pub head: String,
    /// The scene's own decision in place of the core's recommendation (a random study ranks by
    /// first-passage probability or annual risk, not by the paper's R); `None`: the core's.
    pub decision: Option<String>,
    /// Whether the laboratory's sections are written: zones by class, the top by
    /// perfectibility, the Pareto set on (R, p_s), the nominal design's cases, the lognormal
    /// test of the response and the stress and strength settings. A load study without a
    /// strength has none of what they rest on, and leaves them out.
    pub laboratory: bool,
}

impl Default for SceneText {
    fn default() -> Self {
        SceneText {
            section: String::new(),
            point: ("design point", "design points"),
            per_point: None,
            window_peaks: false,
            runs: None,
            head: String::new(),
            decision: None,
            laboratory: true,
        }
    }
}

/// A probability to two significant digits: `0.12`, `0.0031`, `4.7e-6` (below 1e-3), `0`.
pub(crate) fn prob(p: f64) -> String {
    if p == 0.0 || !p.is_finite() {
        return f(p, 0);
    }
    if p < 1e-3 {
        return format!("{p:.1e}");
    }
    let digits = (1 - p.log10().floor() as i32).max(2) as usize;
    f(p, digits)
}

/// A number to `n` significant digits in plain notation (`n` >= 1): `0.250`, `0.0312`, `1.20`;
/// `0` for zero, and as [`f`] for what is not finite. For values read as measured, not as
/// computed: an intensity in g, a median capacity.
pub(crate) fn sig(v: f64, n: i32) -> String {
    if v == 0.0 || !v.is_finite() {
        return f(v, 0);
    }
    let digits = (n - 1 - v.abs().log10().floor() as i32).max(0) as usize;
    f(v, digits)
}

/// A number at fixed precision; `–` for NaN, `∞` for infinities.
pub(crate) fn f(v: f64, digits: usize) -> String {
    if v.is_finite() {
        format!("{v:.digits$}")
    } else if v.is_nan() {
        "–".into()
    } else if v > 0.0 {
        "∞".into()
    } else {
        "−∞".into()
    }
}

/// An interval `lo – hi` with `digits` decimals; one dash when neither end is known (R without a
/// strength, a single case).
pub(crate) fn interval(lo: f64, hi: f64, digits: usize) -> String {
    if lo.is_nan() && hi.is_nan() {
        "–".into()
    } else {
        format!("{} – {}", f(lo, digits), f(hi, digits))
    }
}

/// `R = … (95 % interval …), μn = …` of design `p` (μn with `mu_digits` decimals); empty when
/// the study gives no strength (the report's head says what R needs).
pub(crate) fn reliability_clause(s: &Summary, p: &PointStats, mu_digits: usize) -> String {
    if !s.computes_r() {
        return String::new();
    }
    format!(
        "R = {} ({} interval {}), μn = {}",
        f(p.reliability, 5),
        confidence(s),
        interval(p.reliability_lo, p.reliability_hi, 5),
        f(p.safety_factor, mu_digits)
    )
}

/// Metres in centimetres, three decimals.
pub(crate) fn cm(v: f64) -> String {
    f(v * 100.0, 3)
}

/// A design point's axis values: `e = 0.5, m = 0.02 kg, d = 0.01 m`.
pub fn design_text(s: &Summary, p: u64) -> String {
    if s.grid.n_axes() == 0 {
        // Nothing swept but the frequency (or nothing at all): one design, the study's system.
        return "the study's system (its only design)".to_string();
    }
    (0..s.grid.n_axes())
        .map(|a| axis_value(s.grid.key(a), s.grid.value(p, a)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The confidence level as the text says it: `95 %`.
pub(crate) fn confidence(s: &Summary) -> String {
    format!("{} %", fmt_num(100.0 * s.confidence))
}

/// The ranked points, best first.
pub(crate) fn ranked(s: &Summary) -> Vec<&PointStats> {
    let mut r: Vec<&PointStats> = s.points.iter().filter(|p| p.rank.is_some()).collect();
    r.sort_by_key(|p| p.rank);
    r
}

#[cfg(test)]
mod tests {
    use super::sig;

    #[test]
    fn significant_digits_in_plain_notation() {
        assert_eq!(sig(0.249726, 4), "0.2497");
        assert_eq!(sig(0.25195, 4), "0.2520");
        assert_eq!(sig(0.219382, 3), "0.219");
        assert_eq!(sig(0.0312345, 3), "0.0312");
        assert_eq!(sig(1.2004, 3), "1.20");
        assert_eq!(sig(12.34, 3), "12.3");
        assert_eq!(sig(1234.6, 3), "1235");
        assert_eq!(sig(0.0, 3), "0");
        assert_eq!(sig(f64::NAN, 3), "–");
    }
}
