//! Whether a part file is what the run directory says it is. Used by `status`, `reduce` and
//! `--resume` alike.
//!
//! * A part the manifest or a journal records is good when its bytes have the recorded checksum
//!   (one read and one hash, about 30 GB/s for xxh3).
//! * A part not recorded as finished (its writer stopped between the rename and the journal's
//!   `chunk` line) has the checksum it was written with, journaled before its rename (the
//!   `writing` line, [`crate::store::manifest::WritingEntry`]): it is good when its bytes still
//!   have it (issue 45: a part damaged since is run again, not kept), and when it is a readable
//!   Parquet file of this study with exactly the chunk's rows (count and point ids); it is then
//!   recorded. A part nothing records at all (the manifest was rebuilt, or a machine crash lost
//!   the `writing` line with the last writes) has only the second test.
//! * A chunk of a harmonic study with a census also has an attractors part
//!   ([`crate::store::attractors`]): recorded, it must have its recorded checksum; unrecorded
//!   (its points part says it has one), the checksum of its `writing` line and be a readable
//!   attractors table of this study whose rows belong to the chunk's runs. Either way a chunk is
//!   good only when both are.

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
    if let Some(why) = check_bytes(sizes, path, &entry.checksum) {
        return Some(why);
    }
    let a = entry.attractors.as_ref()?;
    let side = attractors_of(path, entry.chunk);
    check_bytes(sizes, &side, &a.checksum)
        .map(|why| format!("its attractors part {}: {why}", side.display()))
}

/// The attractors part beside the points part `path` of chunk `k`.
fn attractors_of(path: &Path, k: u64) -> std::path::PathBuf {
    let dir = path
        .parent()
        .and_then(Path::parent)
        .unwrap_or(Path::new("."));
    store::attractors::attractors_part_path(dir, k)
}

/// Why the file at `path` does not have `checksum`; `None` when it does.
fn check_bytes(sizes: &Manifest, path: &Path, checksum: &str) -> Option<String> {
    match std::fs::read(path) {
        Ok(bytes) => {
            let got = sizes.algorithm().hex(&bytes);
            (got != checksum).then(|| {
                format!("its checksum is {got}, the run recorded {checksum}: the file is damaged")
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
    if let Some(w) = sizes.writing(k) {
        written_with(sizes, &bytes, &w.checksum)?;
        if let Some(a) = &w.attractors {
            let side = attractors_of(path, k);
            let side_bytes = std::fs::read(&side).map_err(|e| {
                format!(
                    "its attractors part {}: cannot be read: {e}",
                    side.display()
                )
            })?;
            written_with(sizes, &side_bytes, a)
                .map_err(|why| format!("its attractors part {}: {why}", side.display()))?;
        }
    }
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
    let attractors = if meta
        .get(store::attractors::META_ATTRACTORS)
        .map(String::as_str)
        == Some("1")
    {
        let side = attractors_of(path, k);
        Some(
            check_unrecorded_attractors(sizes, study_text, &side, &ids)
                .map_err(|why| format!("its attractors part {}: {why}", side.display()))?,
        )
    } else {
        None
    };
    Ok(ChunkEntry {
        chunk: k,
        rows: want_rows,
        checksum: sizes.algorithm().hex(&bytes),
        outcomes,
        attractors,
    })
}

/// Why `bytes` (a part not recorded as finished) are not those it was written with, `checksum`
/// (its `writing` line); `Ok` when they are.
fn written_with(sizes: &Manifest, bytes: &[u8], checksum: &str) -> Result<(), String> {
    let got = sizes.algorithm().hex(bytes);
    if got == checksum {
        Ok(())
    } else {
        Err(format!(
            "its checksum is {got}, but it was written with {checksum} (recorded before its \
             rename): the file is damaged"
        ))
    }
}

/// The record of an unrecorded attractors part of the runs `ids` when it is good, else why not.
fn check_unrecorded_attractors(
    sizes: &Manifest,
    study_text: &str,
    path: &Path,
    ids: &std::ops::Range<u64>,
) -> Result<store::manifest::AttractorsEntry, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot be read: {e}"))?;
    let rows = store::attractors::read_part(path).map_err(|e| format!("is not readable: {e:#}"))?;
    if rows.iter().any(|a| !ids.contains(&a.run.point_id))
        || rows
            .windows(2)
            .any(|w| w[0].run.point_id > w[1].run.point_id)
    {
        return Err("its rows are not this chunk's runs (point ids)".into());
    }
    let meta = store::part_metadata(path).map_err(|e| format!("is not readable: {e:#}"))?;
    if meta.get(store::META_STUDY).map(String::as_str) != Some(study_text) {
        return Err("was written for another study (its study text differs)".into());
    }
    Ok(store::manifest::AttractorsEntry {
        rows: rows.len() as u64,
        checksum: sizes.algorithm().hex(&bytes),
    })
}
