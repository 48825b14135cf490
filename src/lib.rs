//! impactsweep: design impact dampers by exploring their design space in parallel.
//!
//! The pipeline is the architecture:
//! [`study`] (TOML → validated `Study`) → [`plan`] (points with their seeds) →
//! [`sim`] (one point → one `Record`, a pure function) → [`store`] (Parquet) →
//! [`reduce`] (reliability, zones, ranking) → [`report`] (tables, charts).
//! [`sweep`] drives plan → sim → store in parallel (engine, journal, lock, audit, status);
//! [`accuracy`] measures a solver setting against the reference (for `tradeoff`, `run --audit`
//! and `plan`); [`store`] is the only module that knows arrow/parquet, and its
//! [`store::schema`] is the data contract (column names, units, version; `docs/schema.md`).
//! [`api`] holds what the command line and the Python binding share; the command line itself
//! (`app`, one file per command, and `cli.rs`, the argument parsing) is the binary's, not the
//! library's. [`numeric`] holds the one median, quantile and linspace.
//! [`orbits`] holds steady states of the forced scene known in closed form (Masri and
//! Caughey's symmetric orbit), against which the simulator is checked.
//!
//! A study states its scene (`sim::Scene`): the paper's free decay (`sim::Record`, the `points`
//! table, the reducer's design points) or harmonic forcing to a steady state
//! (`sim::HarmonicRecord`, the `forced_points` table, reduced per design over its frequency band
//! by [`reduce::harmonic`]); the reducer's scene-independent core is [`reduce::common`] and the
//! free-decay scene's part [`reduce::free`].
//!
//! The physics and every equation are in `docs/model.md`; module docs repeat what
//! each stage needs. `docs/architecture.md` has the layout: each scene's place at each layer and
//! the rules between the layers (`tests/layering.rs` checks them).
//!
//! The module docs link to the private items they explain (`cargo doc --document-private-items`
//! resolves them; the test suite builds the docs that way with warnings denied).
#![allow(rustdoc::private_intra_doc_links)]

pub mod accuracy;
pub mod api;
pub mod error;
pub mod model;
pub mod numeric;
pub mod orbits;
pub mod plan;
pub mod reduce;
pub mod report;
pub mod sim;
pub mod slurm;
pub mod stats;
pub mod store;
pub mod study;
pub mod sweep;
