//! `[ranking]`: the perfectibility weights (eq. 11) and where a point's DI comes from.

use serde::Deserialize;

use super::context::{Cx, num};
use crate::error::InputError;

/// Where a design point's DI comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiSource {
    /// The ideal case (default).
    Ideal,
    /// The mean over the cases.
    Mean,
}

/// `[ranking]`: perfectibility weights (eq. 11).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ranking {
    /// Weight of reliability. Default 0.5.
    pub wf1: f64,
    /// Weight of DI. Default 0.5.
    pub wf2: f64,
    pub di_source: DiSource,
    /// Periods of each direct measurement that verifies a harmonic study's ranking (docs/scenes.md,
    /// "The decision verified"). Default [`VERIFY_PERIODS`]; 0: no verification; otherwise
    /// `[2000, 1e8]`.
    pub verify_periods: u64,
}

/// The default of [`Ranking::verify_periods`]: 2,000 doubled nine times, at least 10^6.
pub const VERIFY_PERIODS: u64 = 1_024_000;

impl Default for Ranking {
    fn default() -> Self {
        Ranking {
            wf1: 0.5,
            wf2: 0.5,
            di_source: DiSource::Ideal,
            verify_periods: VERIFY_PERIODS,
        }
    }
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRanking {
    wf1: Option<f64>,
    wf2: Option<f64>,
    di_source: Option<String>,
    verify_periods: Option<f64>,
}

/// The validated `[ranking]`: the weights sum to 1.
pub(super) fn ranking(cx: &Cx, raw: &RawRanking) -> Result<Ranking, InputError> {
    let rk = raw;
    let (wf1, wf2) = match (rk.wf1, rk.wf2) {
        (None, None) => (0.5, 0.5),
        (Some(a), None) => (a, 1.0 - a),
        (None, Some(b)) => (1.0 - b, b),
        (Some(a), Some(b)) => (a, b),
    };
    for (key, v) in [("wf1", wf1), ("wf2", wf2)] {
        if !(0.0..=1.0).contains(&v) {
            return Err(cx.err(
                &format!("[ranking].{key}"),
                num(v),
                "a weight must be in [0, 1]",
            ));
        }
    }
    if ((wf1 + wf2) - 1.0).abs() > 1e-9 {
        return Err(cx.err(
            "[ranking].wf2",
            num(wf2),
            format!(
                "wf1 + wf2 must be 1 (here {}), so that perfectibility is a percentage",
                num(wf1 + wf2)
            ),
        ));
    }
    let di_source = match rk.di_source.as_deref() {
        None | Some("ideal") => DiSource::Ideal,
        Some("mean") => DiSource::Mean,
        Some(s) => {
            return Err(cx.err(
                "[ranking].di_source",
                format!("{s:?}"),
                "allowed: ideal, mean",
            ));
        }
    };
    let verify_periods = match rk.verify_periods {
        None => VERIFY_PERIODS,
        Some(v) if v == 0.0 || (v.fract() == 0.0 && (2000.0..=1e8).contains(&v)) => v as u64,
        Some(v) => {
            return Err(cx.err(
                "[ranking].verify_periods",
                num(v),
                "allowed: 0 (no verification) or a whole number of periods in [2000, 1e8]",
            ));
        }
    };
    Ok(Ranking {
        wf1,
        wf2,
        di_source,
        verify_periods,
    })
}
