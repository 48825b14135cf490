//! The core's tables that every scene's reduction writes beside its summary.

use std::path::{Path, PathBuf};

use crate::reduce::Summary;
use crate::reduce::common::tables;
use crate::store::{self, TableKind};

/// The core's tables every scene writes beside its summary: zones, jumps and sensitivity
/// (Parquet and CSV); returns the files written.
pub(crate) fn write_core_tables(summary: &Summary, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for (kind, t) in [
        (TableKind::Zones, tables::zones_table(summary)),
        (TableKind::Jumps, tables::jumps_table(summary)),
        (TableKind::Sensitivity, tables::sensitivity_table(summary)),
    ] {
        files.extend(store::summary::write_table(dir, kind, &t)?);
    }
    Ok(files)
}
