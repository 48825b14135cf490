//! The accuracy audit as the manifest stores it (`run --audit`, the manifest's `"audit"`): plain
//! data, computed by [`crate::accuracy`] (`audit_errors`, `ErrorStats::of`).

use serde::{Deserialize, Serialize};

/// Max and median of a set of relative errors (NaN when the set is empty).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorStats {
    /// Runs where both values were finite.
    pub n: u64,
    pub max: f64,
    pub median: f64,
}

/// The realised error of a sweep's solver against the reference (`run --audit`, the
/// manifest's `"audit"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Audit {
    /// The audited design points (their ideal case).
    pub points: Vec<u64>,
    /// The study's solver, its accuracy knob (`tol`, `h` or `rtol`) and that knob's value.
    pub solver: String,
    pub knob: String,
    pub knob_value: f64,
    /// The study's event tolerance.
    pub tol: f64,
    /// The reference.
    pub reference: String,
    /// `|a - b| / |b|` (`|a - b|` when `b = 0`) over the runs where both are finite.
    pub xmax: ErrorStats,
    pub t1: ErrorStats,
    pub di: ErrorStats,
    pub outcome_changed: u64,
    pub impacts_changed: u64,
}
