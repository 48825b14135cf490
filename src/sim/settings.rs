//! The solver settings ([`SolverSettings`], [`SolverKind`]): which solver moves the main mass
//! between events and every knob's unit, default and range. A leaf below the simulator's modules,
//! re-exported by [`crate::sim`].

use serde::Serialize;

use crate::model::{RangeError, fmt_value};

/// Which solver moves the main mass between events.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// Closed form between events, guaranteed root brackets, impact times to `tol`.
    Exact,
    /// Classical fixed-step Runge–Kutta 4 with step `h`; events on the step's cubic Hermite
    /// interpolant, event states by re-integration. Error O(h^4).
    Rk4,
    /// Adaptive Dormand–Prince 5(4) with `rtol`/`atol`, FSAL, events on its dense output.
    Dopri5,
}

impl SolverKind {
    pub const ALL: [SolverKind; 3] = [SolverKind::Exact, SolverKind::Rk4, SolverKind::Dopri5];

    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Exact => "exact",
            SolverKind::Rk4 => "rk4",
            SolverKind::Dopri5 => "dopri5",
        }
    }

    /// The name of the knob that sets this solver's accuracy (`tol`, `h` or `rtol`).
    pub fn knob(self) -> &'static str {
        match self {
            SolverKind::Exact => "tol",
            SolverKind::Rk4 => "h",
            SolverKind::Dopri5 => "rtol",
        }
    }

    pub fn parse(s: &str) -> Option<SolverKind> {
        SolverKind::ALL.into_iter().find(|k| k.name() == s)
    }
}

/// Solver settings. Every field documents its unit, default and valid range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolverSettings {
    /// The solver. Default `exact`.
    pub kind: SolverKind,
    /// Event-location tolerance, relative to the undamped period `2 pi sqrt(M/K)`: `exact`
    /// locates every event time within `tol * period` of the true root; `rk4` and `dopri5` refine
    /// event times on their interpolant to `tol * period`. Default `1e-12`, range `[1e-15, 1e-3]`.
    pub tol: f64,
    /// Step of `rk4` (s). Default `1e-4` (about `T/1000` for the Table I system, whose period is
    /// `T = 0.0993 s`), range `[1e-9, 1]`. RK4 is stable while `h` times the fastest rate
    /// (`sqrt(K/M)`, or `C/M` when heavily over-damped) stays below about 2.8.
    pub h: f64,
    /// Relative tolerance of `dopri5` (per step, on `x` and `v`). Default `1e-6`, range
    /// `[1e-14, 1e-1]`.
    pub rtol: f64,
    /// Absolute tolerance of `dopri5` (m): applied to `x` as is and to `v` as
    /// `atol * sqrt(K/mass)` (m/s), so both components are measured in metres of amplitude.
    /// Default `1e-9`, range `[1e-18, 1e-1]`.
    pub atol: f64,
    /// Chatter tolerance, relative to the undamped period: an accumulation of impacts whose
    /// predicted remaining duration `2 u / (a (1 - e))` is below `chatter_tol * period` is replaced by
    /// sticking (see [`phase`](super::phase)). Default `1e-6`, range `[1e-12, 1e-2]`.
    pub chatter_tol: f64,
    /// At most this many impacts, then the run ends with outcome `event_cap`. Default `100000`.
    pub max_impacts: u64,
    /// At most this many solver steps, then the run ends with outcome `step_cap`. Default `10^7`.
    pub max_steps: u64,
    /// Longest simulated time without a fixed horizon, in undamped periods; a run that has not
    /// found its peaks by then ends with `no_second_peak` (or `few_peaks`). Default `200`.
    pub t_max_periods: f64,
}

impl SolverSettings {
    /// The value of this solver's accuracy knob (see [`SolverKind::knob`]).
    pub fn knob_value(&self) -> f64 {
        match self.kind {
            SolverKind::Exact => self.tol,
            SolverKind::Rk4 => self.h,
            SolverKind::Dopri5 => self.rtol,
        }
    }

    /// The solver keys `simulate --set` and a study's `[solver]` table accept.
    pub const KEYS: [&'static str; 10] = [
        "solver",
        "tol",
        "h",
        "rtol",
        "atol",
        "chatter_tol",
        "max_impacts",
        "max_steps",
        "t_max_periods",
        "peaks",
    ];

    /// Checks every knob's range; the error names the key, the value and the range.
    pub fn validate(&self) -> Result<(), RangeError> {
        let check = |key: &str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && v >= lo && v <= hi {
                Ok(())
            } else {
                Err(RangeError::new(
                    key,
                    v,
                    format!("must be in [{}, {}]", fmt_value(lo), fmt_value(hi)),
                ))
            }
        };
        check("tol", self.tol, 1e-15, 1e-3)?;
        check("h", self.h, 1e-9, 1.0)?;
        check("rtol", self.rtol, 1e-14, 1e-1)?;
        check("atol", self.atol, 1e-18, 1e-1)?;
        check("chatter_tol", self.chatter_tol, 1e-12, 1e-2)?;
        check("max_impacts", self.max_impacts as f64, 1.0, 1e9)?;
        check("max_steps", self.max_steps as f64, 1.0, 1e12)?;
        check("t_max_periods", self.t_max_periods, 1.0, 1e6)?;
        Ok(())
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            kind: SolverKind::Exact,
            tol: 1e-12,
            h: 1e-4,
            rtol: 1e-6,
            atol: 1e-9,
            chatter_tol: 1e-6,
            max_impacts: 100_000,
            max_steps: 10_000_000,
            t_max_periods: 200.0,
        }
    }
}
