//! Accuracy: how far a solver setting is from the truth, and what it costs.
//!
//! The truth is `exact` at its tightest tolerance ([`REFERENCE_TOL`]). Three users:
//!
//! * `impactsweep tradeoff` measures every solver over a ladder of its accuracy knob on a
//!   reference set ([`Reference`], [`ladder`], [`measure_all`]) and ranks the settings;
//! * `run --audit K` re-runs `K` design points of a sweep against the truth
//!   ([`crate::sweep::audit`], which builds an [`Audit`] from [`audit_errors`]);
//! * `plan` quotes the cost and error of the study's setting ([`quote_on`]).
//!
//! Errors are relative, `|a - b| / |b|` ([`rel_err`]), summarised by their max and median
//! ([`ErrorStats`]); times are medians over interleaved rounds of the thread's CPU time
//! ([`Timing`]).

mod errors;
mod peer;
mod reference;
mod timing;

pub use errors::{Audit, Comparison, ErrorStats, Observed, audit_errors, compare, rel_err};
pub use peer::{PeerFile, PeerMethod, PeerRun, peer_rows};
pub use reference::{MAX_STUDY_POINTS, Reference, ladder};
pub use timing::{
    Quote, Row, Timing, fmt_err, fmt_time, mark_cheapest, measure, measure_all, quote, quote_on,
};

use crate::sim::{SolverKind, SolverSettings};

/// DI error under which a setting is "good enough" (0.1 %).
pub const DI_GOAL: f64 = 1e-3;

/// Tightest `exact` tolerance: the reference every error is measured against.
pub const REFERENCE_TOL: f64 = 1e-14;

/// The reference solver: `exact` at [`REFERENCE_TOL`], the other settings (caps, chatter
/// tolerance) from `base`.
pub fn reference_settings(base: &SolverSettings) -> SolverSettings {
    SolverSettings {
        kind: SolverKind::Exact,
        tol: REFERENCE_TOL,
        ..*base
    }
}
