//! Plain numeric columns from a Parquet file the user wrote (a record study's accelerogram or
//! force history, `[scene] record = "quake.parquet"`): every column by name, as `f64`, in file
//! order. Integer and float columns are read (widened to `f64`); a column of another type, or a
//! null in a column, is an error naming the column (and the row). The study layer checks what
//! the columns mean ([`crate::study`]'s record reader).

use std::path::Path;

use arrow_array::cast::AsArray;
use arrow_array::types::{
    ArrowPrimitiveType, Float16Type, Float32Type, Float64Type, Int8Type, Int16Type, Int32Type,
    Int64Type, UInt8Type, UInt16Type, UInt32Type, UInt64Type,
};
use arrow_array::{Array, PrimitiveArray};
use arrow_schema::DataType;

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
            let col = batch.column(i);
            if col.null_count() > 0 {
                let row = (0..col.len()).find(|&r| col.is_null(r)).unwrap_or(0);
                return Err(format!(
                    "row {}: {name} is null: every value must be a finite number",
                    out.len() + row + 1
                ));
            }
            widen(col.as_ref(), out)
                .ok_or_else(|| format!("column {name}: not readable as numbers"))?;
        }
    }
    Ok(cols)
}

/// Appends a numeric column's values to `out`, each widened to `f64` the way `as f64` does
/// (exact for every float and for integers up to 2^53 in magnitude, the nearest `f64` beyond);
/// `None` for a column of another type.
fn widen(col: &dyn Array, out: &mut Vec<f64>) -> Option<()> {
    fn ext<T: ArrowPrimitiveType>(
        col: &dyn Array,
        out: &mut Vec<f64>,
        f: impl Fn(T::Native) -> f64,
    ) -> Option<()> {
        let a: &PrimitiveArray<T> = col.as_primitive_opt::<T>()?;
        out.extend(a.values().iter().map(|&v| f(v)));
        Some(())
    }
    match col.data_type() {
        DataType::Float64 => ext::<Float64Type>(col, out, |v| v),
        DataType::Float32 => ext::<Float32Type>(col, out, f64::from),
        DataType::Float16 => ext::<Float16Type>(col, out, |v| v.to_f64()),
        DataType::Int8 => ext::<Int8Type>(col, out, f64::from),
        DataType::Int16 => ext::<Int16Type>(col, out, f64::from),
        DataType::Int32 => ext::<Int32Type>(col, out, f64::from),
        DataType::Int64 => ext::<Int64Type>(col, out, |v| v as f64),
        DataType::UInt8 => ext::<UInt8Type>(col, out, f64::from),
        DataType::UInt16 => ext::<UInt16Type>(col, out, f64::from),
        DataType::UInt32 => ext::<UInt32Type>(col, out, f64::from),
        DataType::UInt64 => ext::<UInt64Type>(col, out, |v| v as f64),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use arrow_array::{
        ArrayRef, Float16Array, Float32Array, Float64Array, Int8Array, Int32Array, Int64Array,
        RecordBatch, StringArray, UInt16Array, UInt64Array,
    };
    use parquet::arrow::ArrowWriter;

    use super::*;

    type F16 = <Float16Type as ArrowPrimitiveType>::Native;

    fn write(path: &Path, cols: Vec<(&str, ArrayRef)>) {
        let batch = RecordBatch::try_from_iter(cols).unwrap();
        let mut w =
            ArrowWriter::try_new(std::fs::File::create(path).unwrap(), batch.schema(), None)
                .unwrap();
        w.write(&batch).unwrap();
        w.close().unwrap();
    }

    #[test]
    fn every_numeric_type_widens_as_rust_does_and_text_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("record.parquet");
        let big = (1i64 << 53) + 1;
        write(
            &path,
            vec![
                ("f64", Arc::new(Float64Array::from(vec![0.1, -2.5e-300]))),
                ("f32", Arc::new(Float32Array::from(vec![0.1f32, -3.0]))),
                (
                    "f16",
                    Arc::new(Float16Array::from(vec![
                        F16::from_f64(0.1),
                        F16::from_f64(-65504.0),
                    ])),
                ),
                ("i8", Arc::new(Int8Array::from(vec![-128i8, 127]))),
                ("i32", Arc::new(Int32Array::from(vec![i32::MIN, 7]))),
                ("i64", Arc::new(Int64Array::from(vec![big, -big]))),
                ("u16", Arc::new(UInt16Array::from(vec![0u16, u16::MAX]))),
                ("u64", Arc::new(UInt64Array::from(vec![u64::MAX, 1]))),
            ],
        );
        let got = read_f64_columns(&path).unwrap();
        let want: Vec<(&str, Vec<f64>)> = vec![
            ("f64", vec![0.1, -2.5e-300]),
            ("f32", vec![f64::from(0.1f32), -3.0]),
            ("f16", vec![F16::from_f64(0.1).to_f64(), -65504.0]),
            ("i8", vec![-128.0, 127.0]),
            ("i32", vec![f64::from(i32::MIN), 7.0]),
            ("i64", vec![big as f64, -big as f64]),
            ("u16", vec![0.0, 65535.0]),
            ("u64", vec![u64::MAX as f64, 1.0]),
        ];
        assert_eq!(got.len(), want.len());
        for ((name, values), (wname, wvalues)) in got.iter().zip(&want) {
            assert_eq!(name, wname);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(values), bits(wvalues), "column {name}");
        }

        let text = dir.path().join("text.parquet");
        write(
            &text,
            vec![("t", Arc::new(StringArray::from(vec!["a", "b"])))],
        );
        let err = read_f64_columns(&text).unwrap_err();
        assert!(err.contains("column t holds Utf8"), "{err}");
    }
}
