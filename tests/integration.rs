//! The integration tests, one test binary (`cargo test --test integration`): each file of
//! `tests/` is a module of it, its tests named `file::test` (`cargo test --test integration
//! life::` runs `tests/life.rs`). One binary, not one per file: the files share one build and
//! one link (the test build compiled and linked 42 binaries before, 2 minutes of a cold build on
//! 2 cores) and their tests share the test threads. `tests/table_writer_memory.rs` stays its own
//! binary: it counts the process's allocations.

#[path = "common/mod.rs"]
mod common;

#[path = "build_sharing.rs"]
mod build_sharing;
#[path = "cli_simulate.rs"]
mod cli_simulate;
// Slurm job arrays on a real single-node cluster. Its main test waits on the scheduler for
// most of its 36 s, and libtest starts the tests in the order of their names: as `cluster::`
// it starts in the run's first seconds, so its waits overlap the CPU-bound tests. As `slurm::`
// it started two minutes in and ended the run alone, 18 s after the rest.
#[path = "cluster.rs"]
mod cluster;
#[path = "determinism.rs"]
mod determinism;
#[path = "faults.rs"]
mod faults;
#[path = "forced_golden.rs"]
mod forced_golden;
#[path = "forced_reduce.rs"]
mod forced_reduce;
#[path = "forced_study.rs"]
mod forced_study;
#[path = "fragility.rs"]
mod fragility;
#[path = "free_decay_golden.rs"]
mod free_decay_golden;
#[path = "grazing.rs"]
mod grazing;
#[path = "forced.rs"]
mod harmonic;
#[path = "html.rs"]
mod html;
#[path = "interop.rs"]
mod interop;
#[path = "layering.rs"]
mod layering;
#[path = "life.rs"]
mod life;
#[path = "orbits.rs"]
mod orbits;
#[path = "orbits_analytic.rs"]
mod orbits_analytic;
#[path = "overnight.rs"]
mod overnight;
#[path = "plan.rs"]
mod plan;
#[path = "properties.rs"]
mod properties;
#[path = "queue_reduce.rs"]
mod queue_reduce;
#[path = "random.rs"]
mod random;
#[path = "random_stream.rs"]
mod random_stream;
#[path = "random_study_errors.rs"]
mod random_study_errors;
#[path = "random_sweep.rs"]
mod random_sweep;
#[path = "realization_at_hand.rs"]
mod realization_at_hand;
#[path = "record_suite.rs"]
mod record_suite;
#[path = "reduce.rs"]
mod reduce;
#[path = "reduce_nd.rs"]
mod reduce_nd;
#[path = "refinement.rs"]
mod refinement;
#[path = "reproduce.rs"]
mod reproduce;
#[path = "schema.rs"]
mod schema;
#[path = "seismic_risk.rs"]
mod seismic_risk;
#[path = "self_contained.rs"]
mod self_contained;
#[path = "simulator.rs"]
mod simulator;
#[path = "solvers.rs"]
mod solvers;
#[path = "study_errors.rs"]
mod study_errors;
#[path = "study_fuzz.rs"]
mod study_fuzz;
#[path = "subset.rs"]
mod subset;
#[path = "sweep.rs"]
mod sweep;
#[path = "units.rs"]
mod units;
#[path = "units_census.rs"]
mod units_census;
#[path = "units_orbits.rs"]
mod units_orbits;
