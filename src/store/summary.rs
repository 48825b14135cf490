//! The reducer's tables (summary, zones, jumps, sensitivity) → `NAME.parquet` and `NAME.csv`,
//! from the reducer's plain [`Table`] (so the reducer never sees arrow). Columns keep the
//! table's order and SI units (their unit in each Parquet field's metadata); Float64 NaN stays
//! NaN (an empty CSV cell), a missing integer is null. No timestamps: the same table always
//! gives the same bytes.
//!
//! A table is written in batches of [`BATCH_ROWS`] rows, each built, appended to both files as
//! one row group and dropped before the next, so writing the summary of a million design points
//! holds one batch, not the whole table twice over. A table of up to [`BATCH_ROWS`] rows is one
//! row group, like every other file the tool writes.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use arrow::array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt64Array};
use parquet::arrow::ArrowWriter;

use super::schema::{TableKind, case_clashes};
use crate::reduce::table::{Column, Table};

/// Rows built and written at a time.
pub const BATCH_ROWS: usize = 65_536;

/// The record batch of `table`, consuming its columns.
fn record_batch(kind: TableKind, table: Table) -> Result<arrow::record_batch::RecordBatch> {
    check_names(kind, &table)?;
    let columns = table
        .columns
        .into_iter()
        .map(|(name, col)| {
            let (array, nullable): (ArrayRef, bool) = match col {
                Column::F64(v) => (Arc::new(Float64Array::from(v)), false),
                Column::U64(v) => (Arc::new(UInt64Array::from(v)), true),
                Column::Bool(v) => (Arc::new(BooleanArray::from(v)), false),
                Column::Str(v) => (Arc::new(StringArray::from(v)), false),
            };
            (name, array, nullable)
        })
        .collect();
    super::batch(kind, columns)
}

/// Encodes `table` as Parquet in memory (one row group; see [`super::encode`]).
pub fn encode_table(kind: TableKind, table: Table) -> Result<Vec<u8>> {
    encode_table_with(kind, table, &super::WriteOptions::default())
}

/// [`encode_table`] with other write options (metadata).
pub fn encode_table_with(
    kind: TableKind,
    table: Table,
    opts: &super::WriteOptions,
) -> Result<Vec<u8>> {
    let batch = record_batch(kind, table)?;
    super::encode(kind, &batch, opts)
}

/// Writes `table` into `dir` as `NAME.parquet` and `NAME.csv` (`NAME` the table's name), each
/// atomically; returns the two paths.
pub fn write_table(dir: &Path, kind: TableKind, table: &Table) -> Result<Vec<PathBuf>> {
    write_table_in_batches(dir, kind, table.n_rows(), |r| table.rows(r))
}

/// Writes a table of `n_rows` rows whose rows `range` are `make(range)`, in batches of
/// [`BATCH_ROWS`], as `NAME.parquet` (a row group per batch) and `NAME.csv`, each to a
/// temporary name then renamed; returns the two paths.
pub fn write_table_in_batches(
    dir: &Path,
    kind: TableKind,
    n_rows: usize,
    make: impl Fn(Range<usize>) -> Table,
) -> Result<Vec<PathBuf>> {
    let parquet = dir.join(format!("{}.parquet", kind.name()));
    let csv = dir.join(format!("{}.csv", kind.name()));
    let (ptmp, ctmp) = (super::tmp_path(&parquet), super::tmp_path(&csv));
    let create = |p: &Path| {
        File::create(p)
            .map(BufWriter::new)
            .with_context(|| format!("creating {}", p.display()))
    };
    let mut csv_out = create(&ctmp)?;
    let mut writer: Option<ArrowWriter<BufWriter<File>>> = None;
    let mut start = 0;
    loop {
        // At least one batch, so that an empty table still gets its header and schema.
        let end = (start + BATCH_ROWS).min(n_rows);
        let table = make(start..end);
        if start == 0 {
            table
                .write_csv_header(&mut csv_out)
                .with_context(|| format!("writing {}", ctmp.display()))?;
        }
        table
            .write_csv_rows(&mut csv_out)
            .with_context(|| format!("writing {}", ctmp.display()))?;
        let batch = record_batch(kind, table)?;
        let w = match writer.as_mut() {
            Some(w) => w,
            None => writer.insert(
                ArrowWriter::try_new(
                    create(&ptmp)?,
                    batch.schema(),
                    Some(super::properties(
                        kind,
                        n_rows.min(BATCH_ROWS),
                        &super::WriteOptions::default(),
                    )),
                )
                .context("starting a Parquet writer")?,
            ),
        };
        w.write(&batch)
            .with_context(|| format!("writing {}", ptmp.display()))?;
        start = end;
        if start >= n_rows {
            break;
        }
    }
    if let Some(w) = writer {
        let file = w
            .into_inner()
            .with_context(|| format!("finishing {}", ptmp.display()))?;
        finish(file, &ptmp, &parquet)?;
    }
    finish(csv_out, &ctmp, &csv)?;
    Ok(vec![parquet, csv])
}

/// Flushes and syncs `out` (written to `tmp`), then renames `tmp` to `path`.
fn finish(out: BufWriter<File>, tmp: &Path, path: &Path) -> Result<()> {
    let file = out
        .into_inner()
        .map_err(|e| e.into_error())
        .with_context(|| format!("writing {}", tmp.display()))?;
    file.sync_all()
        .with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(tmp, path)
        .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
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

/// Writes a CSV file of `n_rows` rows whose rows `range` are `make(range)`, in batches of
/// [`BATCH_ROWS`] (a chart's data), to a temporary name then renamed.
pub fn write_csv_in_batches(
    path: &Path,
    n_rows: usize,
    make: impl Fn(Range<usize>) -> Table,
) -> Result<()> {
    let tmp = super::tmp_path(path);
    let mut out = File::create(&tmp)
        .map(BufWriter::new)
        .with_context(|| format!("creating {}", tmp.display()))?;
    let mut start = 0;
    loop {
        let end = (start + BATCH_ROWS).min(n_rows);
        let table = make(start..end);
        if start == 0 {
            table.write_csv_header(&mut out)
        } else {
            Ok(())
        }
        .and_then(|()| table.write_csv_rows(&mut out))
        .with_context(|| format!("writing {}", tmp.display()))?;
        start = end;
        if start >= n_rows {
            break;
        }
    }
    out.flush()
        .with_context(|| format!("writing {}", tmp.display()))?;
    finish(out, &tmp, path)
}

/// Reads a Parquet file of the reducer's kind of table back into a [`Table`] (Float64, UInt64,
/// Boolean and Utf8 columns, in file order): what an analysis shard wrote
/// ([`crate::reduce::analysis`]).
pub fn read_table(path: &Path) -> Result<Table> {
    use arrow::array::Array;
    let builder = super::open(path)?;
    let meta = super::metadata_of(&builder);
    super::check_version(path, &meta)?;
    let mut table = Table::default();
    // Every column, even of a table without rows.
    for field in builder.schema().fields() {
        let empty = match field.data_type() {
            arrow::datatypes::DataType::Float64 => Column::F64(Vec::new()),
            arrow::datatypes::DataType::UInt64 => Column::U64(Vec::new()),
            arrow::datatypes::DataType::Boolean => Column::Bool(Vec::new()),
            _ => Column::Str(Vec::new()),
        };
        table.push(field.name().clone(), empty);
    }
    for batch in super::read_batches(path, builder)? {
        let schema = batch.schema();
        for (i, field) in schema.fields().iter().enumerate() {
            let a = batch.column(i);
            let col = if let Some(v) = a.as_any().downcast_ref::<Float64Array>() {
                Column::F64(v.values().to_vec())
            } else if let Some(v) = a.as_any().downcast_ref::<UInt64Array>() {
                Column::U64(v.iter().collect())
            } else if let Some(v) = a.as_any().downcast_ref::<BooleanArray>() {
                Column::Bool((0..v.len()).map(|k| v.value(k)).collect())
            } else if let Some(v) = a.as_any().downcast_ref::<StringArray>() {
                Column::Str((0..v.len()).map(|k| v.value(k).to_string()).collect())
            } else {
                bail!(
                    "{}: column `{}` has a type the reducer's tables do not use",
                    path.display(),
                    field.name()
                );
            };
            match table.columns.iter_mut().find(|c| c.0 == *field.name()) {
                Some((_, have)) => have.extend(col),
                None => table.push(field.name().clone(), col),
            }
        }
    }
    Ok(table)
}
