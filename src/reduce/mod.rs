//! Reduce: per design point statistics, reliability, safety factor, zones and ranking
//! (model.md §5–6).
pub mod stats;
