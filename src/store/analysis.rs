//! `RUN_DIR/analysis/`: what each shard of a harmonic study's analysis computed
//! ([`crate::reduce::forced::analysis`]): `probes-I-of-N.parquet` and
//! `branches-I-of-N.parquet`, each carrying the study text it was computed for. Intermediate
//! files: the final `reduce` reads a complete set of them and writes the study's tables.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::schema::{META_STUDY, TableKind};
use super::table::Table;

/// The analysis directory of a run directory.
pub fn analysis_dir(run_dir: &Path) -> PathBuf {
    run_dir.join("analysis")
}

fn shard_path(run_dir: &Path, kind: TableKind, index: u64, count: u64) -> PathBuf {
    analysis_dir(run_dir).join(format!("{}-{index}-of-{count}.parquet", kind.name()))
}

/// Writes shard `index` of `count`'s probes and branches (each atomically, synced); returns the
/// two paths.
pub fn write_shard(
    run_dir: &Path,
    (index, count): (u64, u64),
    study_text: &str,
    probes: Table,
    branches: Table,
) -> Result<Vec<PathBuf>> {
    let dir = analysis_dir(run_dir);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut out = Vec::new();
    for (kind, t) in [(TableKind::Probes, probes), (TableKind::Branches, branches)] {
        let path = shard_path(run_dir, kind, index, count);
        let opts = super::WriteOptions {
            dictionary: &[],
            extra: vec![(META_STUDY.to_string(), study_text.to_string())],
        };
        let bytes = super::summary::encode_table_with(kind, t, &opts)?;
        super::write_bytes(&path, &bytes, super::Durability::Now)?;
        out.push(path);
    }
    Ok(out)
}

/// The probes and branches tables of a complete set of shards written for `study_text`: the
/// largest `N` for which every shard `0..N` left both files. `None` when there is none.
pub fn read_complete(run_dir: &Path, study_text: &str) -> Result<Option<(Vec<Table>, Vec<Table>)>> {
    let dir = analysis_dir(run_dir);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Ok(None);
    };
    let mut counts: Vec<u64> = Vec::new();
    for e in entries {
        let name = e?.file_name().to_string_lossy().to_string();
        if let Some(n) = name
            .strip_prefix("probes-")
            .and_then(|r| r.strip_suffix(".parquet"))
            .and_then(|r| r.split_once("-of-"))
            .and_then(|(_, n)| n.parse::<u64>().ok())
            && !counts.contains(&n)
        {
            counts.push(n);
        }
    }
    counts.sort_unstable_by(|a, b| b.cmp(a));
    'sets: for n in counts {
        let (mut probes, mut branches) = (Vec::new(), Vec::new());
        for i in 0..n {
            for (kind, into) in [
                (TableKind::Probes, &mut probes),
                (TableKind::Branches, &mut branches),
            ] {
                let path = shard_path(run_dir, kind, i, n);
                let Ok(meta) = super::part_metadata(&path) else {
                    continue 'sets;
                };
                if meta.get(META_STUDY).map(String::as_str) != Some(study_text) {
                    continue 'sets;
                }
                into.push(super::summary::read_table(&path)?);
            }
        }
        return Ok(Some((probes, branches)));
    }
    Ok(None)
}
