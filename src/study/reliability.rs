//! `[reliability]`: the stress model (beam `E`, `r`, `L`), the lognormal strength and the
//! reliability options read by the reducer (docs/model.md §5).

use serde::Deserialize;

use super::context::{Cx, num};
use crate::error::InputError;

/// Which relation turns reliability into a safety factor (model.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SafetyForm {
    /// Shigley's exact lognormal relation (default).
    Exact,
    /// The paper's small-`C_n` form.
    Paper,
}

/// `[reliability]`: stress model and strength distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct Reliability {
    /// Young's modulus (Pa). Default 200e9.
    pub E: f64,
    /// Radius of the cantilever's circular section (m). Default 3.4e-3.
    pub r: f64,
    /// Cantilever length (m). Default 0.5.
    pub L: f64,
    /// Mean strength (Pa), `> 0`. The paper does not state it, so there is no default: without
    /// `strength_mean` and `strength_sd` both hold NaN ([`Reliability::has_strength`] is false)
    /// and the reducer reports reliability as unavailable.
    pub strength_mean: f64,
    /// Standard deviation of strength (Pa), `>= 0`; given together with `strength_mean`.
    pub strength_sd: f64,
    /// Safety-factor relation. Default exact.
    pub safety_form: SafetyForm,
    /// Bootstrap resamples for the confidence interval of R. Default 2000.
    pub bootstrap: usize,
    /// Confidence level of that interval. Default 0.95.
    pub confidence: f64,
}

impl Reliability {
    /// Whether the study gave a strength distribution (`strength_mean`, `strength_sd`). Without
    /// one both hold NaN and the reducer reports reliability as unavailable.
    pub fn has_strength(&self) -> bool {
        self.strength_mean.is_finite() && self.strength_sd.is_finite()
    }
}

impl Default for Reliability {
    fn default() -> Self {
        Reliability {
            E: 200e9,
            r: 3.4e-3,
            L: 0.5,
            strength_mean: f64::NAN,
            strength_sd: f64::NAN,
            safety_form: SafetyForm::Exact,
            bootstrap: 2000,
            confidence: 0.95,
        }
    }
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub(super) struct RawReliability {
    E: Option<f64>,
    r: Option<f64>,
    L: Option<f64>,
    strength_mean: Option<f64>,
    strength_sd: Option<f64>,
    safety_form: Option<String>,
    bootstrap: Option<u64>,
    confidence: Option<f64>,
}

/// The validated `[reliability]`.
pub(super) fn reliability(cx: &Cx, raw: &RawReliability) -> Result<Reliability, InputError> {
    let rr = raw;
    let mut reliability = Reliability::default();
    for (key, v, slot) in [
        ("E", rr.E, &mut reliability.E),
        ("r", rr.r, &mut reliability.r),
        ("L", rr.L, &mut reliability.L),
    ] {
        if let Some(v) = v {
            if !(v.is_finite() && v > 0.0) {
                return Err(cx.err(
                    &format!("[reliability].{key}"),
                    num(v),
                    "must be a finite number > 0 (SI units)",
                ));
            }
            *slot = v;
        }
    }
    match (rr.strength_mean, rr.strength_sd) {
        (None, None) => {}
        (Some(mean), Some(sd)) => {
            if !(mean.is_finite() && mean > 0.0) {
                return Err(cx.err(
                    "[reliability].strength_mean",
                    num(mean),
                    "the mean strength must be a finite number > 0 (Pa)",
                ));
            }
            if !(sd.is_finite() && sd >= 0.0) {
                return Err(cx.err(
                    "[reliability].strength_sd",
                    num(sd),
                    "the standard deviation of strength must be a finite number >= 0 (Pa)",
                ));
            }
            reliability.strength_mean = mean;
            reliability.strength_sd = sd;
        }
        (Some(v), None) => {
            return Err(cx.err(
                "[reliability].strength_mean",
                num(v),
                "strength_sd must be given too (both or neither)",
            ));
        }
        (None, Some(v)) => {
            return Err(cx.err(
                "[reliability].strength_sd",
                num(v),
                "strength_mean must be given too (both or neither)",
            ));
        }
    }
    if let Some(s) = &rr.safety_form {
        reliability.safety_form = match s.as_str() {
            "exact" => SafetyForm::Exact,
            "paper" => SafetyForm::Paper,
            _ => {
                return Err(cx.err(
                    "[reliability].safety_form",
                    format!("{s:?}"),
                    "allowed: exact, paper",
                ));
            }
        };
    }
    if let Some(b) = rr.bootstrap {
        if b > 10_000_000 {
            return Err(cx.err(
                "[reliability].bootstrap",
                b,
                "must be a whole number in [0, 10000000] (0 disables the interval)",
            ));
        }
        reliability.bootstrap = b as usize;
    }
    if let Some(c) = rr.confidence {
        if !(c > 0.0 && c < 1.0) {
            return Err(cx.err(
                "[reliability].confidence",
                num(c),
                "the confidence level must be in (0, 1)",
            ));
        }
        reliability.confidence = c;
    }
    Ok(reliability)
}
