//! The trade-off table → `tradeoff.parquet` (written by `impactsweep tradeoff`), one row per
//! solver setting ([`crate::accuracy::Row`]). Every column, with its unit, is in
//! `docs/schema.md`; errors are relative (dimensionless) against `exact` at `tol = 1e-14`.

use std::path::Path;
use std::sync::Arc;

use anyhow::Result;
use arrow::array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt32Array, UInt64Array};

use super::schema::TableKind;
use crate::accuracy::Row;

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
