//! Store: runs ↔ Parquet. The only module that knows arrow/parquet.
//!
//! CONTRACT (shared by the sweep engine and the reducer). A run directory `OUT/<name>/` holds
//! `study.toml` (the resolved study), `manifest.json` and `points/part-NNNNNN.parquet`, one file
//! per chunk (chunk `k` → `part-{k:06}.parquet`), rows in `point_id` order. Columns, SI units:
//!
//! | column | type | meaning |
//! |---|---|---|
//! | `point_id` | UInt64 | `point * n_cases + case`, stable |
//! | `point` | UInt64 | design point index |
//! | `case` | UInt32 | case index (0 is the ideal case) |
//! | `ideal` | Boolean | the unperturbed noise-free case |
//! | `dm`, `dd` | Float64 | perturbation of `m` (kg) and `d` (m) |
//! | `noise_seed` | UInt64, nullable | null without noise |
//! | `M m K C d e x0 v0 y0 w0` | Float64 | the run's system (after `dm`, `dd`) |
//! | `solver` | Dictionary(Int8, Utf8) | solver name |
//! | `tol` | Float64 | solver tolerance knob |
//! | `outcome` | Dictionary(Int8, Utf8) | `ok`, `no_second_peak`, ... |
//! | `x1 t1 x2 t2 xmax di` | Float64 | observables (NaN when the outcome says so) |
//! | `impacts sticks steps` | UInt64 | counts |
//! | `energy_impact energy_viscous t_stop` | Float64 | J, J, s |
//!
//! Key-value metadata: `impactsweep.study` (TOML), `impactsweep.version`,
//! `impactsweep.schema_version`.

use crate::sim::Record;

/// Schema version written to every file's metadata; bump on any column change.
pub const SCHEMA_VERSION: u32 = 1;

/// One stored run, as the reducer reads it back.
#[derive(Clone, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct RunRow {
    pub point_id: u64,
    pub point: u64,
    pub case: u32,
    pub ideal: bool,
    pub dm: f64,
    pub dd: f64,
    pub noise_seed: Option<u64>,
    pub system: crate::model::System,
    pub solver: String,
    pub tol: f64,
    /// The record; `peaks` holds at most `(x1, t1), (x2, t2)` when read back.
    pub record: Record,
}

// ---------------------------------------------------------------------------------------------
// Reader. STUB in the `reducer` branch so that `reduce` compiles before the sweep engine lands:
// the engine's branch implements `part_files` and `read_part` with these signatures. On merge,
// keep the engine's versions and drop these.

/// The part files of a run directory, `RUN_DIR/points/part-*.parquet`, in name (= chunk) order.
pub fn part_files(run_dir: &std::path::Path) -> anyhow::Result<Vec<std::path::PathBuf>> {
    let dir = run_dir.join("points");
    let mut out = Vec::new();
    let entries = std::fs::read_dir(&dir)
        .map_err(|e| anyhow::anyhow!("{}: cannot list the part files: {e}", dir.display()))?;
    for entry in entries {
        let path = entry?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with("part-") && name.ends_with(".parquet") {
            out.push(path);
        }
    }
    out.sort();
    Ok(out)
}

/// Reads one part file back (STUB, see above).
pub fn read_part(path: &std::path::Path) -> anyhow::Result<Vec<RunRow>> {
    anyhow::bail!(
        "{}: reading part files lands with the sweep engine",
        path.display()
    )
}
