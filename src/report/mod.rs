//! Report: markdown tables and charts (the only module that knows plotters).
pub mod charts;
pub mod markdown;
