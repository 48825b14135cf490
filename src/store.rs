//! Store: records ↔ Parquet (the only module that knows arrow/parquet).
//! STUB: owned by the sweep-engine work.
