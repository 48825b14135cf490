//! What a run must produce ([`Request`]): peaks, horizon and trace. A leaf below the simulator's
//! modules, re-exported by [`crate::sim`].

use serde::Serialize;

use crate::model::RangeError;

/// What a run must produce; the horizon follows from it (model.md §3, "model only what a scene
/// requires").
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Request {
    /// Positive half-cycle maxima wanted (>= 1). Default 2 (what `DI` needs): the run stops at
    /// the end of the `peaks`-th positive half-cycle.
    pub peaks: usize,
    /// A fixed horizon (s): the run goes to `t_end` whatever the peaks. Default none.
    pub t_end: Option<f64>,
    /// Emit the state every `trace_dt` seconds to the probe (for waveform plots). Default none.
    pub trace_dt: Option<f64>,
}

impl Default for Request {
    fn default() -> Self {
        Request {
            peaks: 2,
            t_end: None,
            trace_dt: None,
        }
    }
}

impl Request {
    /// Checks `peaks >= 1`, `t_end > 0` and `trace_dt > 0` when given.
    pub fn validate(&self) -> Result<(), RangeError> {
        if self.peaks < 1 || self.peaks > 1_000_000 {
            return Err(RangeError::new(
                "peaks",
                self.peaks as f64,
                "must be an integer in [1, 1000000]",
            ));
        }
        for (key, v) in [("t_end", self.t_end), ("dt", self.trace_dt)] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                return Err(RangeError::new(key, v, "must be a finite time > 0 (s)"));
            }
        }
        Ok(())
    }
}
