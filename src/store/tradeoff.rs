//! The trade-off table → `tradeoff.parquet` (written by `impactsweep tradeoff`), one row per
//! solver setting ([`crate::accuracy::Row`]). Every column, with its unit, is in
//! `docs/schema.md`; errors are relative (dimensionless) against `exact` at `tol = 1e-14`.

use std::path::Path;
use std::sync::Arc;

use anyhow::Result;
use arrow_array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt32Array, UInt64Array};

use super::audit::ErrorStats;
use super::schema::TableKind;

/// One row of the trade-off table: a solver at one knob setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// `exact`, `rk4`, `dopri5`, or a peer (`scipy-RK45`, `scipy-DOP853`).
    pub solver: String,
    /// The knob as a person reads it (`h = T/400`).
    pub setting: String,
    /// Knob name and value (`tol`, `h` in s, `rtol`).
    pub knob: String,
    pub value: f64,
    /// `dopri5`'s (and the peer's) absolute tolerance, NaN otherwise.
    pub atol: f64,
    /// Median wall time per run (s).
    pub time_per_run: f64,
    /// Median CPU time of the timing thread per run (s): what ranks and charts the settings,
    /// because on a shared machine it does not count the time other processes held the core.
    pub cpu_per_run: f64,
    /// Timed repetitions of the whole set.
    pub reps: u32,
    /// Mean solver steps per run (NaN for the peer).
    pub steps_per_run: f64,
    pub xmax: ErrorStats,
    pub t1: ErrorStats,
    pub di: ErrorStats,
    pub impacts: ErrorStats,
    /// Runs whose outcome differs from the reference's.
    pub changed_outcome: u64,
    /// Runs whose impact count differs from the reference's.
    pub changed_impacts: u64,
    /// Runs the solver could not finish (the peer's chatter guard).
    pub unfinished: u64,
    pub runs: u64,
    /// The cheapest setting of its solver with max DI error under [`crate::accuracy::DI_GOAL`].
    pub cheapest: bool,
}

/// Encodes the trade-off rows as Parquet.
pub fn encode(rows: &[Row]) -> Result<Vec<u8>> {
    let f64s = |f: &dyn Fn(&Row) -> f64| -> ArrayRef {
        Arc::new(Float64Array::from_iter_values(rows.iter().map(f)))
    };
    let u64s = |f: &dyn Fn(&Row) -> u64| -> ArrayRef {
        Arc::new(UInt64Array::from_iter_values(rows.iter().map(f)))
    };
    let strs = |f: &dyn Fn(&Row) -> &str| -> ArrayRef {
        Arc::new(StringArray::from_iter_values(rows.iter().map(f)))
    };
    let columns: Vec<(&str, ArrayRef)> = vec![
        ("solver", strs(&|r| &r.solver)),
        ("setting", strs(&|r| &r.setting)),
        ("knob", strs(&|r| &r.knob)),
        ("value", f64s(&|r| r.value)),
        ("atol", f64s(&|r| r.atol)),
        ("time_per_run", f64s(&|r| r.time_per_run)),
        ("cpu_per_run", f64s(&|r| r.cpu_per_run)),
        (
            "reps",
            Arc::new(UInt32Array::from_iter_values(rows.iter().map(|r| r.reps))),
        ),
        ("steps_per_run", f64s(&|r| r.steps_per_run)),
        ("xmax_err_max", f64s(&|r| r.xmax.max)),
        ("xmax_err_median", f64s(&|r| r.xmax.median)),
        ("t1_err_max", f64s(&|r| r.t1.max)),
        ("t1_err_median", f64s(&|r| r.t1.median)),
        ("di_err_max", f64s(&|r| r.di.max)),
        ("di_err_median", f64s(&|r| r.di.median)),
        ("impacts_err_max", f64s(&|r| r.impacts.max)),
        ("impacts_err_median", f64s(&|r| r.impacts.median)),
        ("changed_outcome", u64s(&|r| r.changed_outcome)),
        ("changed_impacts", u64s(&|r| r.changed_impacts)),
        ("unfinished", u64s(&|r| r.unfinished)),
        ("runs", u64s(&|r| r.runs)),
        (
            "cheapest",
            Arc::new(BooleanArray::from(
                rows.iter().map(|r| r.cheapest).collect::<Vec<_>>(),
            )),
        ),
    ];
    let batch = super::batch(
        TableKind::Tradeoff,
        columns
            .into_iter()
            .map(|(name, a)| (name.to_string(), a, false))
            .collect(),
    )?;
    super::encode(TableKind::Tradeoff, &batch, &super::WriteOptions::default())
}

/// Writes the trade-off rows to `path` (atomically).
pub fn write(path: &Path, rows: &[Row]) -> Result<()> {
    super::write_bytes(path, &encode(rows)?, super::Durability::Now)?;
    Ok(())
}
