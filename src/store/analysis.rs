//! `RUN_DIR/analysis/`: what each shard of a harmonic study's analysis computed
//! ([`crate::reduce::harmonic::analysis`]): `probes-I-of-N.parquet`, `branches-I-of-N.parquet`
//! and `verification-I-of-N.parquet`, each carrying the study text it was computed for. Intermediate
//! files: the final `reduce` reads a complete set of them and writes the study's tables.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::schema::{META_MATH, META_STUDY, TableKind};
use super::table::Table;

/// The analysis directory of a run directory.
pub fn analysis_dir(run_dir: &Path) -> PathBuf {
    run_dir.join("analysis")
}

fn shard_path(run_dir: &Path, kind: TableKind, index: u64, count: u64) -> PathBuf {
    analysis_dir(run_dir).join(format!("{}-{index}-of-{count}.parquet", kind.name()))
}

/// Writes shard `index` of `count`'s tables (each atomically, synced): its probes, its branches
/// and its share of the verification ([`TableKind::Verification`]); returns the paths.
pub fn write_shard(
    run_dir: &Path,
    (index, count): (u64, u64),
    study_text: &str,
    tables: Vec<(TableKind, Table)>,
) -> Result<Vec<PathBuf>> {
    let dir = analysis_dir(run_dir);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut out = Vec::new();
    for (kind, t) in tables {
        let path = shard_path(run_dir, kind, index, count);
        let opts = super::WriteOptions {
            dictionary: &[],
            extra: vec![
                (META_STUDY.to_string(), study_text.to_string()),
                (
                    META_MATH.to_string(),
                    crate::sim::math::fingerprint().to_string(),
                ),
            ],
        };
        let bytes = super::summary::encode_table_with(kind, t, &opts)?;
        super::write_bytes(&path, &bytes, super::Durability::Now)?;
        out.push(path);
    }
    Ok(out)
}

/// The tables of a complete set of analysis shards, each kind in shard order.
#[derive(Debug, Default)]
pub struct ShardSet {
    pub probes: Vec<Table>,
    pub branches: Vec<Table>,
    /// The verification's direct measurements (absent from shards of earlier versions, and
    /// from a shard whose file is missing: the final reduction measures those cases itself).
    pub verification: Vec<Table>,
}

/// The tables of a complete set of shards written for `study_text`: the largest `N` for which
/// every shard `0..N` left its probes and branches. `None` when there is none. Refused when its
/// shards were computed by math libraries that round differently (their fingerprints,
/// [`META_MATH`], differ; docs/run.md, "Determinism across machines"): the merged tables would
/// be no single machine's bits.
pub fn read_complete(run_dir: &Path, study_text: &str) -> Result<Option<ShardSet>> {
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
    // The math library's fingerprint of a file written for `study_text` (`Some(None)` for a
    // shard written before the fingerprint), `None` for a file of another study or none.
    let written_for = |path: &Path| {
        let meta = super::part_metadata(path).ok()?;
        (meta.get(META_STUDY).map(String::as_str) == Some(study_text))
            .then(|| meta.get(META_MATH).cloned())
    };
    'sets: for n in counts {
        let mut set = ShardSet::default();
        let mut maths: Vec<(u64, String)> = Vec::new();
        for i in 0..n {
            for (kind, into) in [
                (TableKind::Probes, &mut set.probes),
                (TableKind::Branches, &mut set.branches),
            ] {
                let path = shard_path(run_dir, kind, i, n);
                let Some(math) = written_for(&path) else {
                    continue 'sets;
                };
                // The shard's fingerprint, from its probes file.
                if let (TableKind::Probes, Some(math)) = (kind, math) {
                    maths.push((i, math));
                }
                into.push(super::summary::read_table(&path)?);
            }
            let path = shard_path(run_dir, TableKind::Verification, i, n);
            if written_for(&path).is_some() {
                set.verification.push(super::summary::read_table(&path)?);
            }
        }
        if maths.iter().any(|(_, m)| *m != maths[0].1) {
            let seen: Vec<String> = maths
                .iter()
                .map(|(i, m)| format!("shard {i}/{n} {m}"))
                .collect();
            return Err(crate::error::InputError::new(format!(
                "{}: the analysis shards were computed by math libraries that round differently \
                 (fingerprints: {}; glibc picks its code for exp, sin and cos by the processor, FMA or not): \
                 merged, they would be no single machine's bits. Run `impactsweep reduce {} \
                 --shard I/{n}` again for the shards of one kind on nodes of the other kind, or \
                 delete {} and reduce without shards",
                dir.display(),
                seen.join(", "),
                run_dir.display(),
                dir.display()
            ))
            .into());
        }
        return Ok(Some(set));
    }
    Ok(None)
}
