//! `[run]`: engine settings (chunk size, audit).

use serde::Deserialize;

use super::Cx;
use crate::error::InputError;

/// `[run]`: engine settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    /// Design points per Parquet part file (each chunk holds whole design points).
    /// Default: enough points for about 65536 runs.
    pub chunk_points: u64,
    /// Accuracy audit: points re-run with `exact` at tight tolerance. Default 0 until the
    /// fidelity issue lands.
    pub audit: u64,
}

/// Runs per chunk aimed at when `[run].chunk_points` is absent.
pub const DEFAULT_CHUNK_RUNS: u64 = 65_536;

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRun {
    chunk_points: Option<u64>,
    audit: Option<u64>,
}

/// The validated `[run]`; the default chunk holds about [`DEFAULT_CHUNK_RUNS`] runs of
/// `n_cases` cases per point.
pub(super) fn run(cx: &Cx, raw: &RawRun, n_cases: u64) -> Result<RunSettings, InputError> {
    let mut run = RunSettings {
        chunk_points: (DEFAULT_CHUNK_RUNS / n_cases).max(1),
        audit: 0,
    };
    if let Some(c) = raw.chunk_points {
        if c == 0 {
            return Err(cx.err("[run].chunk_points", c, "must be a whole number >= 1"));
        }
        run.chunk_points = c;
    }
    if let Some(a) = raw.audit {
        run.audit = a;
    }
    Ok(run)
}
