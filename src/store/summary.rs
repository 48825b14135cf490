//! The reducer's tables (summary, zones, jumps) → `NAME.parquet` and `NAME.csv`, from the
//! reducer's plain [`Table`] (so the reducer never sees arrow). Columns keep the table's order
//! and SI units (their unit in each Parquet field's metadata); Float64 NaN stays NaN (an empty
//! CSV cell), a missing integer is null. No timestamps: the same table always gives the same
//! bytes.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Result, bail};
use arrow::array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt64Array};

use super::schema::{TableKind, case_clashes};
use crate::reduce::table::{Column, Table};

/// Encodes `table` as Parquet (one row group; see [`super::encode`]).
pub fn encode_table(kind: TableKind, table: &Table) -> Result<Vec<u8>> {
    check_names(kind, table)?;
    let columns = table
        .columns
        .iter()
        .map(|(name, col)| {
            let (array, nullable): (ArrayRef, bool) = match col {
                Column::F64(v) => (Arc::new(Float64Array::from(v.clone())), false),
                Column::U64(v) => (Arc::new(UInt64Array::from(v.clone())), true),
                Column::Bool(v) => (Arc::new(BooleanArray::from(v.clone())), false),
                Column::Str(v) => (Arc::new(StringArray::from(v.clone())), false),
            };
            (name.clone(), array, nullable)
        })
        .collect();
    let batch = super::batch(kind, columns)?;
    super::encode(kind, &batch, &super::WriteOptions::default())
}

/// Writes `table` into `dir` as `NAME.parquet` and `NAME.csv` (`NAME` the table's name), each
/// atomically; returns the two paths.
pub fn write_table(dir: &Path, kind: TableKind, table: &Table) -> Result<Vec<PathBuf>> {
    let parquet = dir.join(format!("{}.parquet", kind.name()));
    super::write_bytes(
        &parquet,
        &encode_table(kind, table)?,
        super::Durability::Now,
    )?;
    let csv = dir.join(format!("{}.csv", kind.name()));
    super::write_bytes(&csv, table.to_csv().as_bytes(), super::Durability::Now)?;
    Ok(vec![parquet, csv])
}

/// Column names must be unique without case (the data contract).
fn check_names(kind: TableKind, table: &Table) -> Result<()> {
    let clashes = case_clashes(table.columns.iter().map(|c| c.0.as_str()));
    if let Some((a, b)) = clashes.first() {
        bail!(
            "the {} table has columns `{a}` and `{b}`, equal without case",
            kind.name()
        );
    }
    Ok(())
}
