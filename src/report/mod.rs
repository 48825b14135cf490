//! Report: markdown tables and charts (the only module that knows plotters).
//!
//! [`markdown`] writes `report.md` from a reduction, [`charts`] the summary charts and the
//! waveforms (SVG and PNG), [`tradeoff_chart`] the solver cost/error chart of `tradeoff`.

pub mod charts;
pub mod markdown;
pub mod tradeoff_chart;
