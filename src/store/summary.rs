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
use std::io::BufWriter;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use arrow_array::{ArrayRef, BooleanArray, Float64Array, RecordBatch, StringArray, UInt64Array};
use arrow_select::concat::concat_batches;
use parquet::arrow::ArrowWriter;

use super::schema::{TableKind, case_clashes};
use super::table::{Column, Table};

/// Rows built and written at a time.
pub const BATCH_ROWS: usize = 65_536;

/// The record batch of `table`, consuming its columns.
fn record_batch(kind: TableKind, table: Table) -> Result<RecordBatch> {
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
    let mut w = TableWriter::create(dir, kind)?;
    let mut start = 0;
    loop {
        // At least one batch, so that an empty table still gets its header and schema.
        let end = (start + BATCH_ROWS).min(n_rows);
        w.append(make(start..end))?;
        start = end;
        if start >= n_rows {
            break;
        }
    }
    w.finish()
}

/// A table written as it is made: [`TableWriter::append`] takes its rows a part at a time (a
/// table of the same columns each time), CSV lines at once and Parquet row groups of
/// [`BATCH_ROWS`] rows, so a table whose rows come from many designs holds at most one row
/// group's rows besides the part being appended (and never a copy of that part whole);
/// [`TableWriter::finish`] renames the temporary files into place. The bytes are those of
/// [`write_table`] of the whole table. Without [`TableWriter::finish`] (an error on the way)
/// only the temporary files exist.
pub struct TableWriter {
    /// The table's kind, `NAME.parquet` and its temporary name (`None`: a CSV file alone).
    parquet: Option<(TableKind, PathBuf, PathBuf)>,
    /// `NAME.csv` and its temporary name.
    csv: (PathBuf, PathBuf),
    csv_out: BufWriter<File>,
    writer: Option<ArrowWriter<BufWriter<File>>>,
    /// Rows appended and not yet written to Parquet, fewer than [`BATCH_ROWS`] in all, as the
    /// record batches they came in (arrow's columns: no `String` per cell); a row group is
    /// concatenated from them when it is complete.
    pending: Vec<RecordBatch>,
    pending_rows: usize,
    /// The first part's schema: a table without rows still has its columns.
    schema: Option<arrow_schema::SchemaRef>,
    header: bool,
}

fn create(p: &Path) -> Result<BufWriter<File>> {
    File::create(p)
        .map(BufWriter::new)
        .with_context(|| format!("creating {}", p.display()))
}

impl TableWriter {
    /// Starts `NAME.parquet` and `NAME.csv` in `dir` (`NAME` the table's name).
    pub fn create(dir: &Path, kind: TableKind) -> Result<TableWriter> {
        let parquet = dir.join(format!("{}.parquet", kind.name()));
        let ptmp = super::tmp_path(&parquet);
        let mut w = TableWriter::create_csv(&dir.join(format!("{}.csv", kind.name())))?;
        w.parquet = Some((kind, parquet, ptmp));
        Ok(w)
    }

    /// Starts the CSV file `path` alone (a chart's data, the attractors' CSV).
    pub fn create_csv(path: &Path) -> Result<TableWriter> {
        let tmp = super::tmp_path(path);
        Ok(TableWriter {
            parquet: None,
            csv_out: create(&tmp)?,
            csv: (path.to_path_buf(), tmp),
            writer: None,
            pending: Vec::new(),
            pending_rows: 0,
            schema: None,
            header: false,
        })
    }

    /// Appends `table`'s rows (the first table gives the header, even with no rows).
    pub fn append(&mut self, table: Table) -> Result<()> {
        let ctmp = &self.csv.1;
        if !self.header {
            table
                .write_csv_header(&mut self.csv_out)
                .with_context(|| format!("writing {}", ctmp.display()))?;
            self.header = true;
        }
        table
            .write_csv_rows(&mut self.csv_out)
            .with_context(|| format!("writing {}", ctmp.display()))?;
        let Some((kind, _, _)) = self.parquet else {
            return Ok(());
        };
        let n = table.n_rows();
        // The part as arrow columns at once (its Float64 columns move, the others are copied
        // once), and `table` freed.
        let part = record_batch(kind, table)?;
        let schema = self.schema.get_or_insert_with(|| part.schema()).clone();
        // The row groups the part completes are concatenated from the pending rows and the
        // part's, and written; only the part's rows past the last of them wait. Before issue 45
        // the part was appended to a table of the pending rows, which grew to hold it (to twice
        // a row group) before a row group was cut off it and the rest copied once more.
        let mut start = 0;
        while n - start >= BATCH_ROWS - self.pending_rows {
            let end = start + BATCH_ROWS - self.pending_rows;
            let mut parts = std::mem::take(&mut self.pending);
            parts.push(part.slice(start, end - start));
            let group = if parts.len() == 1 {
                parts.remove(0)
            } else {
                concat_batches(&schema, &parts).context("concatenating a row group")?
            };
            drop(parts);
            self.write_batch(group)?;
            self.pending_rows = 0;
            start = end;
        }
        if start < n {
            let rest = part.slice(start, n - start);
            // Past a row group written from it, the rest alone is kept (a copy, so that the part
            // is freed); a part that completed none waits as it came.
            let rest = if start == 0 {
                rest
            } else {
                concat_batches(&schema, [&rest]).context("keeping a part's last rows")?
            };
            self.pending.push(rest);
            self.pending_rows += n - start;
        }
        Ok(())
    }

    /// Writes one row group of Parquet (the writer starts with the first).
    fn write_batch(&mut self, batch: RecordBatch) -> Result<()> {
        let Some((kind, _, ptmp)) = &self.parquet else {
            return Ok(());
        };
        let w = match self.writer.as_mut() {
            Some(w) => w,
            None => self.writer.insert(
                ArrowWriter::try_new(
                    create(ptmp)?,
                    batch.schema(),
                    Some(super::properties(
                        *kind,
                        BATCH_ROWS,
                        &super::WriteOptions::default(),
                    )),
                )
                .context("starting a Parquet writer")?,
            ),
        };
        w.write(&batch)
            .with_context(|| format!("writing {}", ptmp.display()))
    }

    /// Writes what is pending, closes both files and renames them into place; returns their
    /// paths (Parquet first).
    pub fn finish(mut self) -> Result<Vec<PathBuf>> {
        let mut files = Vec::new();
        if let Some((kind, _, _)) = self.parquet {
            let parts = std::mem::take(&mut self.pending);
            match &self.schema {
                Some(schema) if self.pending_rows > 0 || self.writer.is_none() => {
                    let group =
                        concat_batches(schema, &parts).context("concatenating a row group")?;
                    self.write_batch(group)?;
                }
                // Nothing appended: a file without columns.
                None => self.write_batch(record_batch(kind, Table::default())?)?,
                Some(_) => {}
            }
        }
        if let (Some(w), Some((_, parquet, ptmp))) = (self.writer.take(), &self.parquet) {
            let file = w
                .into_inner()
                .with_context(|| format!("finishing {}", ptmp.display()))?;
            finish(file, ptmp, parquet)?;
            files.push(parquet.clone());
        }
        let (csv, ctmp) = &self.csv;
        finish(self.csv_out, ctmp, csv)?;
        files.push(csv.clone());
        Ok(files)
    }
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
    let mut w = TableWriter::create_csv(path)?;
    let mut start = 0;
    loop {
        let end = (start + BATCH_ROWS).min(n_rows);
        w.append(make(start..end))?;
        start = end;
        if start >= n_rows {
            break;
        }
    }
    w.finish().map(|_| ())
}

/// Reads a Parquet file of the reducer's kind of table back into a [`Table`] (Float64, UInt64,
/// Boolean and Utf8 columns, in file order): what an analysis shard wrote
/// ([`crate::reduce::harmonic::analysis`]).
pub fn read_table(path: &Path) -> Result<Table> {
    use arrow_array::Array;
    let builder = super::open(path)?;
    let meta = super::metadata_of(&builder);
    super::check_version(path, &meta)?;
    let mut table = Table::default();
    // Every column, even of a table without rows.
    for field in builder.schema().fields() {
        let empty = match field.data_type() {
            arrow_schema::DataType::Float64 => Column::F64(Vec::new()),
            arrow_schema::DataType::UInt64 => Column::U64(Vec::new()),
            arrow_schema::DataType::Boolean => Column::Bool(Vec::new()),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn table(rows: Range<usize>) -> Table {
        let mut t = Table::default();
        t.push(
            "point",
            Column::U64(rows.clone().map(|i| Some(i as u64)).collect()),
        );
        t.push(
            "r",
            Column::F64(rows.clone().map(|i| i as f64 / 7.0).collect()),
        );
        t.push(
            "label",
            Column::Str(rows.map(|i| format!("l{}", i % 5)).collect()),
        );
        t
    }

    /// `table(0..n)` appended in the pieces `cuts` gives the bytes of the whole written at once.
    fn appended_in_pieces(n: usize, cuts: &[Range<usize>]) {
        let (whole, pieces) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        write_table(whole.path(), TableKind::Branches, &table(0..n)).unwrap();
        let mut w = TableWriter::create(pieces.path(), TableKind::Branches).unwrap();
        for r in cuts {
            w.append(table(r.clone())).unwrap();
        }
        let files = w.finish().unwrap();
        assert_eq!(files.len(), 2);
        for name in ["branches.parquet", "branches.csv"] {
            let a = std::fs::read(whole.path().join(name)).unwrap();
            let b = std::fs::read(pieces.path().join(name)).unwrap();
            assert!(a == b, "{name} differs for pieces {cuts:?}");
        }
        assert_eq!(read_table(&files[0]).unwrap(), table(0..n));
    }

    #[test]
    fn a_table_appended_in_pieces_gives_the_bytes_of_the_whole() {
        let n = 2 * BATCH_ROWS + 1234;
        // Pieces that straddle the row groups' boundaries, an empty one among them.
        appended_in_pieces(n, &[0..1, 1..70_000, 70_000..70_000, 70_000..n]);
        // Issue 45: a whole row group at once, then a piece that completes one row group and
        // holds two more and a part of a fourth, then rows that complete it.
        let b = BATCH_ROWS;
        let n = 5 * b + 17;
        appended_in_pieces(n, &[0..b, b..b + 5, b + 5..4 * b + 9, 4 * b + 9..n]);
    }

    #[test]
    fn an_empty_table_still_has_its_header_and_schema() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = TableWriter::create(dir.path(), TableKind::Branches).unwrap();
        w.append(table(0..0)).unwrap();
        let files = w.finish().unwrap();
        let csv = std::fs::read_to_string(dir.path().join("branches.csv")).unwrap();
        assert_eq!(csv, "point,r,label\n");
        assert_eq!(read_table(&files[0]).unwrap().columns.len(), 3);
    }
}
