//! Reduce: a dataset of runs → one summary row per design point, zones and a ranking
//! (model.md §5–6), each scene beside one core.
//!
//! * [`self::common`]: what every scene shares and no scene shapes: per-point statistics, classes,
//!   zones, jumps, the ranking, the sensitivity, the recommendation and their tables;
//! * [`free`]: the free-decay scene (`xmax` and DI per run, the jumps located by simulating the
//!   ideal case);
//! * [`harmonic`]: the harmonic scene (each design's frequency-response curve, its peak and peak
//!   reduction; the jump probes, the steady states and branches, the bifurcation curves, the
//!   per-design analysis in shards);
//! * [`random`]: the random and record scenes (first-passage `p_f` per design by Monte Carlo
//!   with its exact interval, the fragility fit over a swept intensity).
//!
//! A scene imports the core and never another scene; the core imports no scene
//! (`docs/architecture.md`, `tests/layering.rs`). The core's types are re-exported here.

pub mod common;
pub mod free;
pub mod harmonic;
pub mod random;
#[doc(hidden)]
pub mod testing;

pub use self::common::{
    Class, Damping, EdgeWarning, Grid, IdealCase, Jump, JumpKind, JumpStats, Options, PointStats,
    Quantity, Reducer, Response, ResponseStats, Run, Sensitivity, StepRule, Summary, Zone,
    ZoneParams,
};
