//! The attractors table: every run's steady states, one Parquet part file per chunk beside the
//! points (`attractors/part-NNNNNN.parquet`), written by the sweep of a harmonic study with a
//! census (docs/schema.md, "attractors").
//!
//! A chunk's attractors part is written before its points part, and the points part's metadata
//! says it has one (`impactsweep.attractors = "1"`): the points part stays the chunk's commit
//! marker. The journal records both files' checksums in one line ([`crate::store::manifest::AttractorsEntry`] in the
//! chunk's entry), and a chunk is good only when both verify; a chunk whose attractors part is
//! missing or damaged is run again whole. Rows are in `point_id` order, then attractor order.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, anyhow};
use arrow_array::builder::{Float64Builder, ListBuilder};
use arrow_array::cast::AsArray;
use arrow_array::{
    Array, ArrayRef, BooleanArray, Float64Array, ListArray, RecordBatch, StringArray, UInt32Array,
    UInt64Array,
};
use arrow_schema::{DataType, Schema, SchemaRef};

use super::schema::{META_STUDY, META_TABLE, TableKind};
use crate::orbits::attractors::{AttractorRow, RunId, SteadyKind};

/// The metadata key of a points part that has an attractors part beside it.
pub const META_ATTRACTORS: &str = "impactsweep.attractors";

/// The attractors part of chunk `k` in a run directory.
pub fn attractors_part_path(run_dir: &Path, k: u64) -> PathBuf {
    run_dir
        .join("attractors")
        .join(format!("part-{k:06}.parquet"))
}

/// A `Float64` column of the table: its name and how a row gives it.
pub type F64Col = (&'static str, fn(&AttractorRow) -> f64);

/// The table's `Float64` columns after the run's identity, in schema order (docs/schema.md).
pub const F64_COLUMNS: [F64Col; 17] = [
    ("amplitude", |a| a.amplitude),
    ("window_amplitude", |a| a.window_amplitude),
    ("impacts_per_period", |a| a.impacts_per_period),
    ("basin_share", |a| a.basin_share),
    ("multiplier_max", |a| a.multiplier_max),
    ("lyapunov", |a| a.lyapunov),
    ("lyapunov_per_s", |a| a.lyapunov_per_s),
    ("lyapunov_se", |a| a.lyapunov_se),
    ("life_amplitude", |a| a.life_amplitude),
    ("life_lo", |a| a.life_lo),
    ("life_hi", |a| a.life_hi),
    ("tail_shape", |a| a.tail_shape),
    ("tail_end", |a| a.tail_end),
    ("section_x", |a| a.section[0]),
    ("section_v", |a| a.section[1]),
    ("section_z", |a| a.section[2]),
    ("section_w", |a| a.section[3]),
];

/// The `section_units` column's type: a list of `Float64` (a study of several units only;
/// arrow's default item field, which a list builder writes).
fn units_list() -> DataType {
    DataType::List(Arc::new(arrow_schema::Field::new_list_field(
        DataType::Float64,
        true,
    )))
}

/// The Arrow schema of an attractors part; a study of several units (`units`) adds
/// `section_units`, every component of the section state (one unit's parts keep today's
/// columns, byte for byte).
pub fn schema(units: bool) -> SchemaRef {
    let t = TableKind::Attractors;
    let mut cols: Vec<(&str, DataType)> = vec![
        ("point_id", DataType::UInt64),
        ("point", DataType::UInt64),
        ("case", DataType::UInt32),
        ("ideal", DataType::Boolean),
        ("r", DataType::Float64),
        ("omega", DataType::Float64),
        ("F0", DataType::Float64),
        ("attractor", DataType::UInt32),
        ("kind", DataType::Utf8),
        ("stability", DataType::Utf8),
        ("origin", DataType::Utf8),
        ("period", DataType::UInt32),
        ("starts", DataType::UInt32),
        ("life_capped", DataType::Boolean),
        ("exceedances", DataType::UInt64),
        ("measured_periods", DataType::UInt64),
    ];
    cols.extend(F64_COLUMNS.iter().map(|(n, _)| (*n, DataType::Float64)));
    if units {
        cols.push(("section_units", units_list()));
    }
    let fields: Vec<_> = cols
        .into_iter()
        .map(|(name, dt)| {
            super::field(t, name, dt, false).expect("every attractors column has a unit")
        })
        .collect();
    Arc::new(Schema::new(fields))
}

/// The rows as one record batch ([`schema`]; `units`: a study of several units).
pub fn to_batch(rows: &[AttractorRow], units: bool) -> Result<RecordBatch> {
    let u64s = |f: fn(&AttractorRow) -> u64| -> ArrayRef {
        Arc::new(UInt64Array::from_iter_values(rows.iter().map(f)))
    };
    let u32s = |f: fn(&AttractorRow) -> u32| -> ArrayRef {
        Arc::new(UInt32Array::from_iter_values(rows.iter().map(f)))
    };
    let strs = |f: fn(&AttractorRow) -> &str| -> ArrayRef {
        Arc::new(StringArray::from_iter_values(rows.iter().map(f)))
    };
    let bools = |f: fn(&AttractorRow) -> bool| -> ArrayRef {
        Arc::new(BooleanArray::from_iter(rows.iter().map(|a| Some(f(a)))))
    };
    let mut cols: Vec<ArrayRef> = vec![
        u64s(|a| a.run.point_id),
        u64s(|a| a.run.point),
        u32s(|a| a.run.case),
        bools(|a| a.run.ideal),
        Arc::new(Float64Array::from_iter_values(rows.iter().map(|a| a.run.r))),
        Arc::new(Float64Array::from_iter_values(
            rows.iter().map(|a| a.run.omega),
        )),
        Arc::new(Float64Array::from_iter_values(
            rows.iter().map(|a| a.run.F0),
        )),
        u32s(|a| a.attractor),
        strs(|a| a.kind.name()),
        strs(|a| a.stability),
        strs(|a| a.origin),
        u32s(|a| a.period),
        u32s(|a| a.starts),
        bools(|a| a.life_capped),
        u64s(|a| a.exceedances),
        u64s(|a| a.measured_periods),
    ];
    for (_, f) in F64_COLUMNS {
        cols.push(Arc::new(Float64Array::from_iter_values(rows.iter().map(f))));
    }
    if units {
        let mut list = ListBuilder::new(Float64Builder::new());
        for a in rows {
            list.values().append_slice(&a.section_units);
            list.append(true);
        }
        cols.push(Arc::new(list.finish()));
    }
    Ok(RecordBatch::try_new(schema(units), cols)?)
}

/// Encodes rows as one attractors part (one row group, the study text in the metadata);
/// `units`: a study of several units ([`schema`]).
pub fn encode_part(rows: &[AttractorRow], study_toml: &str, units: bool) -> Result<Vec<u8>> {
    super::encode(
        TableKind::Attractors,
        &to_batch(rows, units)?,
        &super::WriteOptions {
            dictionary: &["kind", "stability", "origin"],
            extra: vec![(META_STUDY.to_string(), study_toml.to_string())],
        },
    )
}

fn col<'a, T: 'static>(batch: &'a RecordBatch, name: &str) -> Result<&'a T> {
    batch
        .column_by_name(name)
        .ok_or_else(|| anyhow!("column `{name}` is missing"))?
        .as_any()
        .downcast_ref::<T>()
        .ok_or_else(|| anyhow!("column `{name}` has an unexpected type"))
}

/// A string column, plain or dictionary-encoded, as owned strings.
fn strings(batch: &RecordBatch, name: &str) -> Result<Vec<String>> {
    let c = batch
        .column_by_name(name)
        .ok_or_else(|| anyhow!("column `{name}` is missing"))?;
    let text = |a: &dyn Array| -> Result<Vec<String>> {
        let s = a
            .as_string_opt::<i32>()
            .ok_or_else(|| anyhow!("column `{name}` is not text"))?;
        Ok((0..s.len()).map(|i| s.value(i).to_string()).collect())
    };
    match c.as_any_dictionary_opt() {
        Some(dict) => {
            let values = text(dict.values())?;
            dict.normalized_keys()
                .into_iter()
                .map(|k| {
                    values
                        .get(k)
                        .cloned()
                        .ok_or_else(|| anyhow!("column `{name}`: key {k} outside its dictionary"))
                })
                .collect()
        }
        None => text(c),
    }
}

/// A stored name back as the `'static` name it was written from.
fn known(names: &[&'static str], got: &str, column: &str) -> Result<&'static str> {
    names
        .iter()
        .find(|n| **n == got)
        .copied()
        .ok_or_else(|| anyhow!("column `{column}`: unknown value {got:?}"))
}

fn read_batch(batch: &RecordBatch, out: &mut Vec<AttractorRow>) -> Result<()> {
    let u64c = |n| col::<UInt64Array>(batch, n);
    let u32c = |n| col::<UInt32Array>(batch, n);
    let boolc = |n| col::<BooleanArray>(batch, n);
    let (point_id, point, case) = (u64c("point_id")?, u64c("point")?, u32c("case")?);
    let ideal = boolc("ideal")?;
    let f64c = |n| col::<Float64Array>(batch, n);
    let (r, omega, f0) = (f64c("r")?, f64c("omega")?, f64c("F0")?);
    let (attractor, period, starts) = (u32c("attractor")?, u32c("period")?, u32c("starts")?);
    let capped = boolc("life_capped")?;
    let (exceed, measured) = (u64c("exceedances")?, u64c("measured_periods")?);
    let (kind, stability, origin) = (
        strings(batch, "kind")?,
        strings(batch, "stability")?,
        strings(batch, "origin")?,
    );
    let f: Vec<&Float64Array> = F64_COLUMNS
        .iter()
        .map(|(n, _)| col::<Float64Array>(batch, n))
        .collect::<Result<_>>()?;
    // Present in the parts of a study of several units only.
    let units = match batch.column_by_name("section_units") {
        Some(_) => Some(col::<ListArray>(batch, "section_units")?),
        None => None,
    };
    let units_at = |i: usize| -> Result<Vec<f64>> {
        let Some(list) = units else {
            return Ok(Vec::new());
        };
        let v = list.value(i);
        let v = v
            .as_any()
            .downcast_ref::<Float64Array>()
            .ok_or_else(|| anyhow!("column `section_units` does not hold Float64 lists"))?;
        Ok(v.values().to_vec())
    };
    for i in 0..batch.num_rows() {
        let v = |j: usize| f[j].value(i);
        out.push(AttractorRow {
            run: RunId {
                point_id: point_id.value(i),
                point: point.value(i),
                case: case.value(i),
                ideal: ideal.value(i),
                r: r.value(i),
                omega: omega.value(i),
                F0: f0.value(i),
            },
            attractor: attractor.value(i),
            kind: SteadyKind::parse(&kind[i])
                .ok_or_else(|| anyhow!("column `kind`: unknown value {:?}", kind[i]))?,
            stability: known(&["stable", "neutral", ""], &stability[i], "stability")?,
            origin: known(&["start", "up", "down", "recurrence"], &origin[i], "origin")?,
            period: period.value(i),
            starts: starts.value(i),
            life_capped: capped.value(i),
            exceedances: exceed.value(i),
            measured_periods: measured.value(i),
            amplitude: v(0),
            window_amplitude: v(1),
            impacts_per_period: v(2),
            basin_share: v(3),
            multiplier_max: v(4),
            lyapunov: v(5),
            lyapunov_per_s: v(6),
            lyapunov_se: v(7),
            life_amplitude: v(8),
            life_lo: v(9),
            life_hi: v(10),
            tail_shape: v(11),
            tail_end: v(12),
            section: [v(13), v(14), v(15), v(16)],
            section_units: units_at(i)?,
        });
    }
    Ok(())
}

/// Reads an attractors part back (a file of another schema version or table is refused).
pub fn read_part(path: &Path) -> Result<Vec<AttractorRow>> {
    let builder = super::open(path)?;
    let meta = super::metadata_of(&builder);
    super::check_version(path, &meta)?;
    if meta.get(META_TABLE).map(String::as_str) != Some(TableKind::Attractors.name()) {
        return Err(anyhow!(
            "{}: does not hold the attractors table (docs/schema.md)",
            path.display()
        ));
    }
    let mut rows = Vec::new();
    for batch in super::read_batches(path, builder)? {
        read_batch(&batch, &mut rows).with_context(|| format!("reading {}", path.display()))?;
    }
    Ok(rows)
}
