//! The reducer's core, the same for every scene (model.md §5–6): per-point statistics →
//! classes → regions (zones) → the ranking, the sensitivity and the recommendation. It knows no
//! scene: a scene hands it runs ([`Run`]: per case a response and a damping quantity, which the
//! scene names with a [`Response`] and a [`Damping`]) and its ideal case anywhere in the design
//! space ([`IdealCase`], where the jumps are located), and reads back a [`Summary`].
//!
//! * [`reducer`]: the streaming reducer ([`Reducer`]); [`options`]: the choices it takes;
//! * [`point`] and [`summary`]: what it knows of one design point and of the whole sweep;
//! * [`stats`]: means, lognormals, R and its bootstrap interval, the safety factor,
//!   Anderson–Darling, perfectibility; [`rank`]: the ranking and the Pareto set;
//! * [`grid`]: the design grid; [`jumps`]: jumps along its axes, located with the scene's ideal
//!   case; [`class`]: the classes of the design points; [`zones`] and [`regions`]: how the
//!   points get them and the zones they make;
//! * [`sensitivity`]: the variance decomposition; [`recommend`]: the robust recommendation;
//! * [`tables`]: the summary, zones, jumps and sensitivity tables the store writes.

pub mod class;
pub mod grid;
pub mod jumps;
pub mod options;
pub mod point;
pub mod rank;
pub mod recommend;
pub mod reducer;
pub mod regions;
pub mod sensitivity;
pub mod stats;
pub mod summary;
pub mod tables;
pub mod zones;

pub use class::Class;
pub use grid::Grid;
pub use jumps::{IdealCase, Jump, JumpKind, Quantity};
pub use options::Options;
pub use point::{Damping, PointStats, Response, ResponseStats, Run};
pub use reducer::{Reducer, nominal_point, outcome_index};
pub use summary::{EdgeWarning, Sensitivity, Summary};
pub use zones::{JumpStats, StepRule, Zone, ZoneParams};
