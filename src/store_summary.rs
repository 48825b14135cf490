//! Store, reducer side: writes the reducer's tables (`summary.parquet`, `zones.parquet`) with
//! arrow/parquet, so that the reducer itself never sees arrow. Columns keep the table's order
//! and SI units; Float64 NaN stays NaN, a missing integer is null. No timestamps: the same
//! summary always gives the same bytes.

use std::path::Path;
use std::sync::Arc;

use anyhow::Context;
use arrow::array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt64Array};
use arrow::datatypes::{DataType, Field, Schema};
use arrow::record_batch::RecordBatch;
use parquet::arrow::ArrowWriter;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;

use crate::reduce::table::{Column, Table};

/// Writes `table` to `path` as one Parquet row group, with `impactsweep.version` and
/// `impactsweep.table` metadata.
pub fn write_table(path: &Path, name: &str, table: &Table) -> anyhow::Result<()> {
    let mut fields = Vec::new();
    let mut arrays: Vec<ArrayRef> = Vec::new();
    for (col_name, col) in &table.columns {
        let (dt, arr, nullable): (DataType, ArrayRef, bool) = match col {
            Column::F64(v) => (
                DataType::Float64,
                Arc::new(Float64Array::from(v.clone())),
                false,
            ),
            Column::U64(v) => (
                DataType::UInt64,
                Arc::new(UInt64Array::from(v.clone())),
                true,
            ),
            Column::Bool(v) => (
                DataType::Boolean,
                Arc::new(BooleanArray::from(v.clone())),
                false,
            ),
            Column::Str(v) => (
                DataType::Utf8,
                Arc::new(StringArray::from(v.clone())),
                false,
            ),
        };
        fields.push(Field::new(col_name, dt, nullable));
        arrays.push(arr);
    }
    let schema = Arc::new(Schema::new(fields));
    let batch = RecordBatch::try_new(schema.clone(), arrays)
        .with_context(|| format!("building the {name} table"))?;
    let props = WriterProperties::builder()
        .set_key_value_metadata(Some(vec![
            KeyValue::new(
                "impactsweep.version".to_string(),
                env!("CARGO_PKG_VERSION").to_string(),
            ),
            KeyValue::new("impactsweep.table".to_string(), name.to_string()),
        ]))
        .build();
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = ArrowWriter::try_new(file, schema, Some(props))
        .with_context(|| format!("writing {}", path.display()))?;
    w.write(&batch)
        .with_context(|| format!("writing {}", path.display()))?;
    w.close()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}
