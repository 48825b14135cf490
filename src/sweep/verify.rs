//! Whether a part file is what the run directory says it is. Used by `status`, `reduce` and
//! `--resume` alike.
//!
//! * A part the manifest or a journal records is good when its bytes have the recorded checksum
//!   (one read and one hash, about 30 GB/s for xxh3).
//! * A part nothing records (its writer stopped between the rename and the journal line, or the
//!   manifest was rebuilt) is good when it is a readable Parquet file of this study with exactly
//!   the chunk's rows (count and point ids); it is then recorded.

use std::path::Path;

use crate::store::{self, ChunkEntry, Manifest};

/// Why the part recorded as `entry` is not good; `None` when it is. `sizes` is the directory's
/// manifest (sizes and checksum algorithm).
pub fn check_recorded(sizes: &Manifest, path: &Path, entry: &ChunkEntry) -> Option<String> {
    let ids = sizes.chunk_ids(entry.chunk);
    let want_rows = ids.end - ids.start;
    if entry.rows != want_rows {
        return Some(format!(
            "recorded with {} rows, but chunk {} has {want_rows}",
            entry.rows, entry.chunk
        ));
    }
    match std::fs::read(path) {
        Ok(bytes) => {
            let got = sizes.algorithm().hex(&bytes);
            (got != entry.checksum).then(|| {
                format!(
                    "its checksum is {got}, the run recorded {}: the file is damaged",
                    entry.checksum
                )
            })
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Some("recorded as finished, but the file is missing".into())
        }
        Err(e) => Some(format!("cannot be read: {e}")),
    }
}

/// The record of an unrecorded part of chunk `k` when it is good (see the module doc), else why
/// not. `study_text` is the directory's `study.toml`. A part of another schema version is an
/// error (the dataset needs another build; nothing is to be removed).
pub fn check_unrecorded(
    sizes: &Manifest,
    study_text: &str,
    path: &Path,
    k: u64,
) -> anyhow::Result<Result<ChunkEntry, String>> {
    if let Ok(meta) = store::part_metadata(path) {
        store::check_version(path, &meta)?;
    }
    Ok(check_unrecorded_part(sizes, study_text, path, k))
}

fn check_unrecorded_part(
    sizes: &Manifest,
    study_text: &str,
    path: &Path,
    k: u64,
) -> Result<ChunkEntry, String> {
    let ids = sizes.chunk_ids(k);
    let want_rows = ids.end - ids.start;
    let bytes = std::fs::read(path).map_err(|e| format!("cannot be read: {e}"))?;
    // Either scene's table (the study text below says which study wrote it).
    let (point_ids, outcomes) =
        store::read_ids_outcomes(path).map_err(|e| format!("is not readable: {e:#}"))?;
    if point_ids.len() as u64 != want_rows {
        return Err(format!(
            "holds {} rows, but chunk {k} has {want_rows}",
            point_ids.len()
        ));
    }
    if !point_ids
        .iter()
        .enumerate()
        .all(|(i, id)| *id == ids.start + i as u64)
    {
        return Err(format!("its rows are not chunk {k}'s (point ids)"));
    }
    let meta = store::part_metadata(path).map_err(|e| format!("is not readable: {e:#}"))?;
    if meta.get(store::META_STUDY).map(String::as_str) != Some(study_text) {
        return Err("was written for another study (its study text differs)".into());
    }
    Ok(ChunkEntry {
        chunk: k,
        rows: want_rows,
        checksum: sizes.algorithm().hex(&bytes),
        outcomes,
    })
}
