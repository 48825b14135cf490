//! Report: markdown, HTML and charts (the only module that knows plotters).
//!
//! [`markdown`] writes `report.md` from a reduction, one function per section; [`html`] the
//! same report as one self-contained page, `report.html`, and an output root's `index.html`;
//! [`charts`] the summary charts, the waveforms and the solver cost/error chart of `tradeoff`,
//! each with its data beside it; [`text`] the words and numbers all three share.

pub mod charts;
pub mod html;
pub mod markdown;
pub mod text;

/// The solver chart of `tradeoff` (kept at its old path for its callers).
pub use charts::tradeoff as tradeoff_chart;
pub use text::axis_unit;
