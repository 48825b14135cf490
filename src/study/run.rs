//! `[run]`: engine settings (chunk size, audit).

use serde::Deserialize;

use super::axis::Axis;
use super::context::Cx;
use crate::error::InputError;

/// `[run]`: engine settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    /// Design points per Parquet part file (each chunk holds whole design points, and in a
    /// harmonic study whole frequency-response curves: a multiple of the frequency axis's
    /// length). Default: enough points for about 65536 runs.
    pub chunk_points: u64,
    /// A random or record study: realizations per chunk at most. A design point with more
    /// realizations than this is split into blocks of this many (the last shorter), one chunk
    /// each, so that a chunk's rows stay bounded in memory and an interruption loses at most
    /// one block. Default [`DEFAULT_CHUNK_RUNS`]; unused by the other scenes.
    pub chunk_realizations: u64,
    /// Accuracy audit: points re-run with `exact` at tight tolerance. Default 0 until the
    /// fidelity issue lands.
    pub audit: u64,
}

/// Runs per chunk aimed at when `[run].chunk_points` is absent.
pub const DEFAULT_CHUNK_RUNS: u64 = 65_536;

/// Runs per chunk aimed at in a harmonic study with an attractor census: such a run costs
/// milliseconds (tens of thousands of free-decay runs' worth), so a chunk of 4096 runs is
/// already seconds to minutes of work: what a crash can lose, and enough curves to keep every
/// core busy.
pub const DEFAULT_CHUNK_RUNS_CENSUS: u64 = 4_096;

/// What a scene asks of `[run]`: each scene's parser states it.
pub(super) struct RunRules<'a> {
    /// Runs per chunk aimed at when `[run].chunk_points` is absent ([`DEFAULT_CHUNK_RUNS`], or
    /// [`DEFAULT_CHUNK_RUNS_CENSUS`] for a harmonic study with an attractor census).
    pub aim: u64,
    /// Whether the scene's runs are realizations that `[run].chunk_realizations` may split.
    pub realizations: bool,
    /// Why `[run].audit > 0` is refused in the scene, if it is.
    pub no_audit: Option<&'static str>,
    /// The axis each chunk holds whole (a harmonic study's swept frequency).
    pub curve: Option<&'a Axis>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRun {
    chunk_points: Option<u64>,
    chunk_realizations: Option<u64>,
    audit: Option<u64>,
}

impl RawRun {
    /// `[run].audit` as given.
    pub(super) fn audit_given(&self) -> Option<u64> {
        self.audit
    }
}

/// The validated `[run]`; the default chunk holds about [`DEFAULT_CHUNK_RUNS`] runs of
/// `n_cases` cases per point. In a harmonic study with a swept frequency axis (`curve`) a chunk
/// holds whole frequency-response curves, so that `reduce` can stream: the default is rounded
/// down to a multiple of the curve's length (at least one curve) and a given `chunk_points`
/// must be one; the audit (free decay only) is refused.
pub(super) fn run(
    cx: &Cx,
    raw: &RawRun,
    n_cases: u64,
    rules: &RunRules,
) -> Result<RunSettings, InputError> {
    let curve = rules.curve;
    let per_curve = curve.map_or(1, |a| a.values.len() as u64);
    let default = (rules.aim / n_cases).max(1);
    let mut run = RunSettings {
        chunk_points: (default / per_curve).max(1) * per_curve,
        chunk_realizations: DEFAULT_CHUNK_RUNS,
        audit: 0,
    };
    if let Some(c) = raw.chunk_realizations {
        if !rules.realizations {
            return Err(cx.err(
                "[run].chunk_realizations",
                c,
                "belongs to the random and record scenes (their design points' realizations); \
                 this study's runs are chunked by [run].chunk_points",
            ));
        }
        if c == 0 {
            return Err(cx.err("[run].chunk_realizations", c, "must be a whole number >= 1"));
        }
        run.chunk_realizations = c;
    }
    if let Some(c) = raw.chunk_points {
        if c == 0 {
            return Err(cx.err("[run].chunk_points", c, "must be a whole number >= 1"));
        }
        if let Some(axis) = curve
            && let Some(msg) = whole_curves(c, axis)
        {
            return Err(cx.err("[run].chunk_points", c, msg));
        }
        run.chunk_points = c;
    }
    if let Some(a) = raw.audit {
        if a > 0
            && let Some(why) = rules.no_audit
        {
            return Err(cx.err("[run].audit", a, why));
        }
        run.audit = a;
    }
    Ok(run)
}

/// Why `chunk_points` would cut a frequency-response curve of `axis`, if it would.
pub fn whole_curves(chunk_points: u64, axis: &Axis) -> Option<String> {
    let n = axis.values.len() as u64;
    (!chunk_points.is_multiple_of(n)).then(|| {
        format!(
            "must be a multiple of the {n} values of the frequency axis [sweep].{}, so that \
             every chunk holds whole frequency-response curves",
            axis.key
        )
    })
}
