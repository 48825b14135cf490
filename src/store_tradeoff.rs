//! The tradeoff table ↔ Parquet (`tradeoff.parquet`, written by `impactsweep tradeoff`). Part of
//! the store: the only place besides [`crate::store`] that knows arrow/parquet.
//!
//! One row per solver setting. Columns (SI units; errors are relative, dimensionless):
//!
//! | column | type | meaning |
//! |---|---|---|
//! | `solver` | Utf8 | `exact`, `rk4`, `dopri5`, `scipy-RK45`, `scipy-DOP853` |
//! | `setting` | Utf8 | the knob as a person reads it (`h = T/400`) |
//! | `knob`, `value` | Utf8, Float64 | knob name (`tol`, `h` in s, `rtol`) and value |
//! | `atol` | Float64 | absolute tolerance (m) of `dopri5` and the peer, NaN otherwise |
//! | `time_per_run` | Float64 | median wall time per run (s), single thread |
//! | `cpu_per_run` | Float64 | median CPU time of the timing thread per run (s) |
//! | `reps` | UInt32 | timed repetitions of the whole reference set |
//! | `steps_per_run` | Float64 | mean solver steps per run (NaN for the peer) |
//! | `{xmax,t1,di,impacts}_err_{max,median}` | Float64 | relative error against `exact` at `tol = 1e-14` |
//! | `changed_outcome`, `changed_impacts`, `unfinished`, `runs` | UInt64 | run counts |
//! | `cheapest` | Boolean | cheapest setting of its solver with max DI error < 0.1 % |

use std::path::Path;
use std::sync::Arc;

use anyhow::Context;
use arrow::array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt32Array, UInt64Array};
use arrow::datatypes::{DataType, Field, Schema};
use arrow::record_batch::RecordBatch;
use parquet::arrow::ArrowWriter;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;

use crate::app::tradeoff::Row;

/// Writes the tradeoff rows to `path`.
pub fn write(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
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
    let schema = Arc::new(Schema::new(
        columns
            .iter()
            .map(|(name, a)| Field::new(*name, a.data_type().clone(), false))
            .collect::<Vec<_>>(),
    ));
    debug_assert!(
        schema
            .fields()
            .iter()
            .all(|f| f.data_type() != &DataType::Null)
    );
    let batch = RecordBatch::try_new(schema.clone(), columns.into_iter().map(|c| c.1).collect())
        .context("building the tradeoff table")?;
    let props = WriterProperties::builder()
        .set_key_value_metadata(Some(vec![KeyValue::new(
            "impactsweep.version".to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        )]))
        .build();
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut writer = ArrowWriter::try_new(file, schema, Some(props))
        .with_context(|| format!("writing {}", path.display()))?;
    writer
        .write(&batch)
        .with_context(|| format!("writing {}", path.display()))?;
    writer
        .close()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}
