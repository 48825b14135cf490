//! Report: markdown tables and charts (the only module that knows plotters).
//! STUB: owned by the reducer work.

pub mod tradeoff_chart;
