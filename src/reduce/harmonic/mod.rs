//! The harmonic scene's reduction (model.md §8, docs/reduce.md): every design's
//! frequency-response curve becomes one row of the reducer's grid.
//!
//! A **design** is a design point without its frequency: the study's grid with the frequency
//! axis (`r` or `omega`, always the last, [`crate::study`]) taken out ([`design_study`]). The
//! part files hold whole curves (a chunk is a whole number of them), so the reduction streams:
//! [`HarmonicReducer::push`](reducer::HarmonicReducer::push) turns each design's runs into
//!
//! * one core [`Run`](crate::reduce::Run) per case: its response is the case's **peak
//!   amplitude** over the swept band (the largest `amplitude` of its runs, the classic design
//!   target, [`PEAK_AMPLITUDE`]);
//!   its damping quantity is the **peak reduction** `PR = 1 - peak amplitude / peak of
//!   amplitude_linear` over the same band ([`PEAK_REDUCTION`], dimensionless: 0.9 means the
//!   damper removes 90 % of the linear system's resonance peak; negative when it makes the
//!   peak worse). A case with a run that did not end `ok` takes that run's outcome (its peak is
//!   unknown), so the reducer counts it as failed;
//! * the ideal case's [`Curve`] (kept for the charts, the report and the band columns: where
//!   the peak is, the band where the damper helps, how much of the band is periodic).
//!
//! The core's reducer ([`crate::reduce::common::Reducer`]) then does over the designs what it does
//! over free-decay design points: stress, R and the safety factor from the peak amplitudes of the
//! cases (each case's peak is a sample), perfectibility from R and PR, zones, jumps (located with
//! the ideal case's curve continued to each probe from its grid neighbours' attractors,
//! [`probe::HarmonicIdeal`]), sensitivity and the robust recommendation.
//!
//! The modules, each importing only those above it in this list (no circle):
//! * [`design`]: a design (the study without its frequency), its response and damping quantity;
//! * [`curve`]: a design's frequency-response curve ([`Curve`]), its peak and where it helps;
//! * [`analysis`]: how the per-design analysis runs, whole or as one shard ([`analysis::Plan`]),
//!   and along which lines the bifurcation curves are followed ([`analysis::CurveLines`]);
//! * [`summary`]: what the harmonic reduction adds to the core's summary ([`HarmonicSummary`]) and
//!   its band columns;
//! * [`probe`]: the ideal case between the grid's designs, for the jumps;
//! * [`reducer`]: the streaming reduction of the parts ([`HarmonicReducer`]);
//! * [`steady`]: the steady states of the curves (the attractors and the branches tables, the
//!   bifurcation diagram's sections);
//! * [`shard`]: what a shard of the analysis stores, and reads back;
//! * [`bifurcations`]: the bifurcation curves over the design space;
//! * [`verify`]: the designs that decide the ranking, their peak motions measured directly.

pub mod analysis;
pub mod bifurcations;
pub mod curve;
pub mod design;
pub mod probe;
pub mod reducer;
pub mod shard;
pub mod steady;
pub mod summary;
pub mod verify;

pub use curve::{Curve, CurvePoint, HELP_TOL, HelpBand};
pub use design::{PEAK_AMPLITUDE, PEAK_REDUCTION, design_peak, design_study, options};
pub use reducer::HarmonicReducer;
pub use summary::{HarmonicSummary, summary_columns};
