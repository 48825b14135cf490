//! A run directory as the engine opens it: the study it holds, its chunk size, this shard's
//! claim on it, and which of this shard's chunks are already done.

use std::collections::BTreeSet;
use std::path::Path;

use anyhow::{Context, Result};

use super::journal::{Entry, Journal, Ledger, ManifestLock};
use super::lock::{RunLock, acquire_lock, check_other_splits, lock_path};
use super::options::SweepOptions;
use super::verify::{check_recorded, check_unrecorded};
use crate::error::InputError;
use crate::plan::Plan;
use crate::store::{self, ManifestFile, read_manifest_file};
use crate::study::Study;

/// The chunk size of a run directory: `cli` when given (refused when it differs from the
/// directory's), else the manifest's when it describes this study, else the one the part files
/// show (`part-000000`'s rows), else the study's.
pub fn chunk_points(study: &Study, dir: &Path, cli: Option<u64>) -> Result<u64> {
    let n_points: u64 = study.axes.iter().map(|a| a.values.len() as u64).product();
    let n_cases = study.n_cases().max(1);
    let recorded = match read_manifest_file(dir)? {
        ManifestFile::Usable(m)
            if m.study == study.name
                && m.study_text_mismatch(&study.source).is_none()
                && m.seed == study.seed
                && m.n_points == n_points
                && m.n_cases == n_cases =>
        {
            Some(m.chunk_points)
        }
        _ => None,
    };
    match (cli, recorded) {
        (Some(c), Some(m)) if m != c => Err(InputError::new(format!(
            "--chunk-points {c}: {} was written with chunk_points = {m}; resume with that value \
             (or without --chunk-points)",
            dir.display()
        ))
        .into()),
        (Some(c), _) => Ok(c),
        (None, Some(m)) => Ok(m),
        (None, None) => {
            let own = study.run.chunk_points.max(1);
            let first = store::part_path(dir, 0);
            Ok(match store::part_rows(&first) {
                Ok(rows) if rows > 0 && rows % n_cases == 0 => {
                    let shown = rows / n_cases;
                    if shown >= n_points {
                        own.max(n_points)
                    } else {
                        shown
                    }
                }
                _ => own,
            })
        }
    }
}

/// Checks what `dir` already holds against the study and the options: the same study text, a
/// dataset this build reads, the same chunk size. Returns the study with its chunk size settled
/// and whether the directory holds no study yet.
pub fn open(study: &Study, dir: &Path, opts: &SweepOptions) -> Result<(Study, bool)> {
    let existing_study = std::fs::read_to_string(dir.join("study.toml")).ok();
    if let Some(text) = &existing_study
        && *text != study.source
    {
        return Err(InputError::new(format!(
            "{}: holds a different study (its study.toml differs from {}); choose another --out",
            dir.display(),
            study.path.display()
        ))
        .into());
    }
    let chunk_points = chunk_points(study, dir, opts.chunk_points)?;
    let mut study = study.clone();
    study.run.chunk_points = chunk_points;
    Ok((study, existing_study.is_none()))
}

/// Whether a directory exists and holds anything.
fn non_empty(dir: &Path) -> bool {
    std::fs::read_dir(dir)
        .map(|mut d| d.next().is_some())
        .unwrap_or(false)
}

/// Makes `dir` this shard's: refuses a non-empty directory without `--resume` (a sharded run
/// may join one its siblings created), takes the shard's lock and writes `study.toml` when the
/// directory holds none.
pub fn claim(
    plan: &Plan,
    dir: &Path,
    opts: &SweepOptions,
    mine: &[u64],
    fresh_dir: bool,
) -> Result<RunLock> {
    if !opts.resume && non_empty(dir) {
        let own_part = mine.iter().any(|&k| store::part_path(dir, k).exists());
        if opts.shard.1 <= 1 || own_part || lock_path(dir, opts.shard).exists() {
            return Err(InputError::new(format!(
                "{}: the output directory exists and is not empty; pass --resume to continue \
                 that run, or choose another --out (nothing was overwritten)",
                dir.display()
            ))
            .into());
        }
    }
    let points_dir = dir.join("points");
    std::fs::create_dir_all(&points_dir)
        .with_context(|| format!("creating {}", points_dir.display()))?;
    let lock = {
        // One writer starts at a time, so two of different splits cannot both pass the check.
        let _turn = ManifestLock::take(dir)?;
        check_other_splits(dir, opts.shard)?;
        acquire_lock(dir, opts.shard, opts.resume)?
    };
    if fresh_dir {
        store::write_shared(&dir.join("study.toml"), plan.study.source.as_bytes())?;
    }
    // A record study's record (or its suite's records) beside its study.toml, so that the
    // directory's own study loads (`reduce`, `status`, the resume command) wherever the records
    // were.
    for (src, rel) in plan.study.record_files() {
        let copy = dir.join(rel);
        if let Some(parent) = copy.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("creating {}", parent.display()))?;
        }
        if src != copy && !copy.exists() {
            let bytes =
                std::fs::read(&src).with_context(|| format!("reading {}", src.display()))?;
            store::write_shared(&copy, &bytes)?;
        }
    }
    // The same for a hazard table.
    if let Some(src) = plan.study.hazard_path() {
        let copy = dir.join(crate::study::HAZARD_COPY);
        if src != copy && !copy.exists() {
            let bytes =
                std::fs::read(&src).with_context(|| format!("reading {}", src.display()))?;
            store::write_shared(&copy, &bytes)?;
        }
    }
    Ok(lock)
}

/// Removes the `part-K.parquet.tmp` files of this shard's chunks `mine` in `sub` (a part this
/// shard was writing when it stopped; other shards' may be in progress).
fn remove_own_temp_files(sub: &Path, mine: &[u64]) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(sub) else {
        return Ok(());
    };
    for e in entries {
        let path = e?.path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if let Some(base) = name.strip_suffix(".tmp")
            && let Some(k) = store::part_chunk(&sub.join(base))
            && mine.binary_search(&k).is_ok()
        {
            std::fs::remove_file(&path).with_context(|| format!("removing {}", path.display()))?;
        }
    }
    Ok(())
}

/// What [`find_done`] found.
#[derive(Debug, Default)]
pub struct Done {
    /// This shard's chunks still to run, in order.
    pub pending: Vec<u64>,
    /// Chunks found finished and kept.
    pub kept: u64,
    /// Chunks found damaged (or recorded but missing): removed, to be run again. With why.
    pub damaged: Vec<(u64, String)>,
}

/// This shard's chunks that are already done, and those still to run. A recorded part is kept
/// when its checksum matches; an unrecorded one when it is a readable part of this study with
/// the chunk's rows (then recorded in `journal`). Anything else is removed (with its `*.tmp`
/// leftovers) and run again.
pub fn find_done(
    plan: &Plan,
    dir: &Path,
    mine: &[u64],
    ledger: &Ledger,
    journal: &mut Journal,
) -> Result<Done> {
    store::remove_dead_temp_files(dir)?;
    let mut present = BTreeSet::new();
    let points = dir.join("points");
    for e in std::fs::read_dir(&points).with_context(|| format!("listing {}", points.display()))? {
        let path = e?.path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if let Some(base) = name.strip_suffix(".tmp") {
            // A part this shard was writing when it stopped (others' may be in progress).
            if let Some(k) = store::part_chunk(&points.join(base))
                && mine.binary_search(&k).is_ok()
            {
                std::fs::remove_file(&path)
                    .with_context(|| format!("removing {}", path.display()))?;
            }
        } else if let Some(k) = store::part_chunk(&path) {
            present.insert(k);
        }
    }
    remove_own_temp_files(&dir.join("attractors"), mine)?;
    let sizes = &ledger.manifest;
    let mut done = Done::default();
    for &k in mine {
        let path = store::part_path(dir, k);
        let entry = ledger.manifest.chunk(k);
        if !present.contains(&k) {
            if entry.is_some() {
                done.damaged
                    .push((k, "recorded as finished, but the file is missing".into()));
            }
            done.pending.push(k);
            continue;
        }
        let verdict = match entry {
            Some(e) => check_recorded(sizes, &path, e).map_or(Ok(None), Err),
            None => check_unrecorded(sizes, &plan.study.source, &path, k)?.map(Some),
        };
        match verdict {
            Ok(None) => done.kept += 1,
            Ok(Some(entry)) => {
                journal.append(&Entry::Chunk(entry))?;
                done.kept += 1;
            }
            Err(why) => {
                std::fs::remove_file(&path)
                    .with_context(|| format!("removing {}", path.display()))?;
                done.damaged.push((k, why));
                done.pending.push(k);
            }
        }
    }
    Ok(done)
}
