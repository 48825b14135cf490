//! A swept axis, as `[sweep]` gives it (`RawAxis`) and validated (`Axis`), and the extent of a
//! key over the design points. Below `sweep.rs`, `scene/` and `perturb.rs`, which all use it,
//! so that none of them imports another that imports it back.

use serde::Deserialize;

use crate::model::System;

/// One swept axis: a system key (or, in a harmonic study, `F0`, `omega` or `r`) and its values
/// (computed from an integer index, never accumulated).
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub key: String,
    pub values: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum RawAxis {
    List(Vec<f64>),
    Range(RawRange),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRange {
    pub(super) start: f64,
    pub(super) stop: f64,
    pub(super) step: Option<f64>,
    pub(super) num: Option<u64>,
}

/// The smallest and largest value of a system key over the design points, and where the study
/// sets it (`[sweep].m` or `[system].m`), for cross-checks and their messages.
pub(super) fn extent(axes: &[Axis], system: &System, key: &str) -> (f64, f64, String) {
    match axes.iter().find(|a| a.key == key) {
        Some(a) => (
            a.values[0],
            a.values[a.values.len() - 1],
            format!("[sweep].{key}"),
        ),
        None => {
            let v = system.get(key).unwrap_or(f64::NAN);
            (v, v, format!("[system].{key}"))
        }
    }
}
