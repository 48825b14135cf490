//! impactsweep: design impact dampers by exploring their design space in parallel.
//!
//! The pipeline is the architecture:
//! [`study`] (TOML → validated `Study`) → [`plan`] (points with their seeds) →
//! [`sim`] (one point → one `Record`, a pure function) → [`store`] (Parquet) →
//! [`reduce`] (reliability, zones, ranking) → [`report`] (tables, charts).
//! [`sweep`] drives plan → sim → store in parallel; [`app`] holds the commands and [`cli`] the
//! argument parsing.
//!
//! The physics and every equation are in `docs/model.md`; module docs repeat what
//! each stage needs.

pub mod accuracy;
pub mod app;
pub mod cli;
pub mod error;
pub mod model;
pub mod numeric;
pub mod plan;
pub mod reduce;
pub mod report;
pub mod sim;
pub mod slurm;
pub mod store;
pub mod study;
pub mod sweep;
