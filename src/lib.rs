//! impactsweep: design impact dampers by exploring their design space in parallel.
//!
//! The pipeline is the architecture:
//! study (TOML → validated [`study::Study`]) → plan (points with their seeds) →
//! simulate (one point → one [`sim::Record`], a pure function) → store (Parquet) →
//! reduce (reliability, zones, ranking) → report (tables, charts).
//!
//! The physics and every equation are in `../shared/spec/model.md`; module docs repeat what
//! each stage needs.

pub mod model;
pub mod sim;
pub mod app;
pub mod cli;
pub mod error;
