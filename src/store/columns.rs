//! Plain numeric columns from a Parquet file the user wrote (a record study's accelerogram or
//! force history, `[scene] record = "quake.parquet"`): every column by name, as `f64`, in file
//! order. Integer and float columns are read (widened to `f64`); a column of another type, or a
//! null in a column, is an error naming the column (and the row). The study layer checks what
//! the columns mean ([`crate::study`]'s record reader).

use std::path::Path;

use arrow::array::{Array, Float64Array};
use arrow::compute::cast;
use arrow::datatypes::DataType;

/// The file's columns: `(name, values)` in file order, each as long as the file.
pub fn read_f64_columns(path: &Path) -> Result<Vec<(String, Vec<f64>)>, String> {
    let builder = super::open(path).map_err(|e| format!("{e:#}"))?;
    let schema = builder.schema().clone();
    let mut cols: Vec<(String, Vec<f64>)> = schema
        .fields()
        .iter()
        .map(|f| (f.name().clone(), Vec::new()))
        .collect();
    for f in schema.fields() {
        let t = f.data_type();
        if !(t.is_integer() || t.is_floating()) {
            return Err(format!(
                "column {} holds {t}; a record's columns hold numbers (floats or integers)",
                f.name()
            ));
        }
    }
    let reader = builder.build().map_err(|e| e.to_string())?;
    for batch in reader {
        let batch = batch.map_err(|e| e.to_string())?;
        for (i, (name, out)) in cols.iter_mut().enumerate() {
            let col = cast(batch.column(i), &DataType::Float64).map_err(|e| e.to_string())?;
            let col = col
                .as_any()
                .downcast_ref::<Float64Array>()
                .ok_or_else(|| format!("column {name}: not readable as numbers"))?;
            if col.null_count() > 0 {
                let row = (0..col.len()).find(|&r| col.is_null(r)).unwrap_or(0);
                return Err(format!(
                    "row {}: {name} is null: every value must be a finite number",
                    out.len() + row + 1
                ));
            }
            out.extend_from_slice(col.values());
        }
    }
    Ok(cols)
}
