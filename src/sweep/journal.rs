//! The bookkeeping of finished chunks: one append-only journal per shard, folded into
//! `manifest.json` when the shard's run ends.
//!
//! A shard appends two JSON lines per chunk to its own journal (`journal.jsonl`, or
//! `journal-shard-I-of-N.jsonl`; only the holder of the shard's lock writes it): a `writing`
//! line with the part files' checksums while they still have their temporary names,
//! `{"kind":"writing","chunk":K,"checksum":"…","attractors":"…"}`, and a `chunk` line once the
//! part is complete under its final name, `{"kind":"chunk","chunk":K,"rows":R,"checksum":"…",
//! "outcomes":{…}}`; besides them `{"kind":"shard","shard":"I/N"}` and
//! `{"kind":"audit","audit":{…}}`. So recording a chunk costs two `write`s whatever the number of
//! chunks: no file is rewritten per chunk. The file system is synced about once a second
//! ([`crate::store::sync_file_system`]) and at the end.
//!
//! What the directory says is `manifest.json` with every journal line applied on top
//! ([`load`]): `status`, `reduce` and `--resume` read it so. When a shard's run ends, [`fold`]
//! writes that into `manifest.json` (temp file, synced, renamed) and then removes the shard's
//! journal; folds of shards sharing a directory take turns under an exclusive `flock` on
//! `.manifest.lock`, so none loses another's lines.
//!
//! A crash at any instant leaves a state `--resume` completes exactly: a line cut short (the
//! last one, without its newline) is ignored and cut off when the shard reopens its journal; a
//! part renamed but not yet recorded as finished is verified against the checksum its `writing`
//! line holds (and by reading it) and recorded, or run again when it no longer has it; a fold
//! cut short leaves the old manifest and the journal, or the new manifest and the journal (its
//! lines apply twice, to the same effect: a chunk's part file is the same bytes whoever writes
//! it).

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use super::lock::{Flock, flock};
use crate::accuracy::Audit;
use crate::store::manifest::{
    ChunkEntry, Manifest, ManifestFile, WritingEntry, read_manifest_file, write_manifest,
};

/// One journal line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Entry {
    /// A finished chunk: its part file is complete under its final name.
    Chunk(ChunkEntry),
    /// A chunk's part files written under their temporary names, about to be renamed: the
    /// checksums they must have.
    Writing(WritingEntry),
    /// Shard `I/N` writes into this directory.
    Shard { shard: String },
    /// The accuracy audit.
    Audit { audit: Audit },
}

/// The journal of a shard.
pub fn journal_path(dir: &Path, shard: (u64, u64)) -> PathBuf {
    if shard.1 <= 1 {
        dir.join("journal.jsonl")
    } else {
        dir.join(format!("journal-shard-{}-of-{}.jsonl", shard.0, shard.1))
    }
}

/// Whether a file name is a journal's.
pub fn is_journal_name(name: &str) -> bool {
    name == "journal.jsonl" || (name.starts_with("journal-shard-") && name.ends_with(".jsonl"))
}

/// A shard's journal, open for appending (only the holder of the shard's lock opens it).
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: File,
}

impl Journal {
    /// Opens (or creates) the journal of `shard`; a last line cut short by a crash is cut off.
    pub fn open(dir: &Path, shard: (u64, u64)) -> Result<Journal> {
        let path = journal_path(dir, shard);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .with_context(|| format!("opening {}", path.display()))?;
        let mut text = Vec::new();
        file.read_to_end(&mut text)
            .with_context(|| format!("reading {}", path.display()))?;
        let whole = text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        if whole < text.len() {
            file.set_len(whole as u64)
                .with_context(|| format!("cutting the torn last line of {}", path.display()))?;
        }
        file.seek(SeekFrom::Start(whole as u64))
            .with_context(|| format!("opening {}", path.display()))?;
        Ok(Journal { path, file })
    }

    /// Appends one line (one `write`; synced with the file system later).
    pub fn append(&mut self, entry: &Entry) -> Result<()> {
        let mut line = serde_json::to_vec(entry).context("encoding a journal line")?;
        line.push(b'\n');
        self.file
            .write_all(&line)
            .with_context(|| format!("writing {}", self.path.display()))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Every whole line of every journal in `dir` that parses (a line cut short or damaged is
/// skipped: the part files are the truth, and `--resume` re-verifies a part no line records).
pub fn read_journals(dir: &Path) -> Result<Vec<Entry>> {
    let mut names: Vec<PathBuf> = Vec::new();
    for e in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let e = e?;
        if is_journal_name(&e.file_name().to_string_lossy()) {
            names.push(e.path());
        }
    }
    names.sort();
    let mut entries = Vec::new();
    for path in names {
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            // Folded and removed by its shard meanwhile: its lines are in the manifest.
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
        };
        let whole = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        entries.extend(
            bytes[..whole]
                .split(|&b| b == b'\n')
                .filter_map(|line| serde_json::from_slice::<Entry>(line).ok()),
        );
    }
    Ok(entries)
}

/// What a run directory's bookkeeping says: `manifest.json` with every journal line applied.
#[derive(Clone, Debug)]
pub struct Ledger {
    pub manifest: Manifest,
    /// Why `manifest.json` could not be used (then [`Ledger::manifest`] is rebuilt from `fresh`
    /// and the journals), or `None`.
    pub problem: Option<String>,
    /// `manifest.json` is absent.
    pub absent: bool,
}

/// Applies one journal line.
pub fn apply(m: &mut Manifest, entry: Entry) {
    match entry {
        Entry::Chunk(c) => m.upsert(c),
        Entry::Writing(w) => m.upsert_writing(w),
        Entry::Shard { shard } => {
            if !m.shards.contains(&shard) {
                m.shards.push(shard);
                m.shards.sort();
            }
        }
        Entry::Audit { audit } => m.audit = Some(audit),
    }
}

/// Reads `manifest.json` and the journals of `dir`. `fresh` (the manifest of this directory's
/// study with nothing done) stands in for a manifest that is absent, unusable or of another
/// study; [`Ledger::problem`] says which.
pub fn load(dir: &Path, fresh: &Manifest) -> Result<Ledger> {
    let (mut manifest, problem, absent) = match read_manifest_file(dir)? {
        ManifestFile::Absent => (fresh.clone(), None, true),
        ManifestFile::Unusable(why) => (fresh.clone(), Some(why), false),
        ManifestFile::Usable(m) => match m.mismatch(fresh) {
            Some(why) => (fresh.clone(), Some(why), false),
            None => (*m, None, false),
        },
    };
    for e in read_journals(dir)? {
        apply(&mut manifest, e);
    }
    manifest.recount();
    Ok(Ledger {
        manifest,
        problem,
        absent,
    })
}

/// `manifest.json` with the journals applied, as it stands (no study to compare it with): the
/// inner error says why the manifest cannot be used (absent, empty, cut short, …).
pub fn load_recorded(dir: &Path) -> Result<Result<Manifest, String>> {
    let mut m = match read_manifest_file(dir)? {
        ManifestFile::Absent => return Ok(Err("is missing".into())),
        ManifestFile::Unusable(why) => return Ok(Err(why)),
        ManifestFile::Usable(m) => m,
    };
    for e in read_journals(dir)? {
        apply(&mut m, e);
    }
    m.recount();
    Ok(Ok(*m))
}

/// Holds an exclusive `flock` on `dir/.manifest.lock` while alive, so that folds (and the first
/// manifest of a directory) take turns. Where the file system has no `flock` it holds nothing
/// ([`ManifestLock::held`] is false) and folds then keep every journal.
pub struct ManifestLock {
    file: Option<File>,
}

impl ManifestLock {
    pub fn take(dir: &Path) -> Result<ManifestLock> {
        let path = dir.join(".manifest.lock");
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .with_context(|| format!("opening {}", path.display()))?;
        match flock(&file, true) {
            Flock::Locked => Ok(ManifestLock { file: Some(file) }),
            Flock::Unsupported(_) => Ok(ManifestLock { file: None }),
            Flock::Busy => anyhow::bail!("locking {}: busy", path.display()),
            Flock::Failed(e) => Err(e).with_context(|| format!("locking {}", path.display())),
        }
    }

    pub fn held(&self) -> bool {
        self.file.is_some()
    }
}

/// When a shard starts: writes `manifest.json` from `fresh` and the journals if it is absent,
/// unusable or of another study. Returns the problem it replaced, if any. Refuses, before
/// anything is written, a directory whose records another build's arithmetic or another math
/// library computed ([`Manifest::arithmetic_mismatch`]).
pub fn start(dir: &Path, fresh: &Manifest) -> Result<Option<String>> {
    let _guard = ManifestLock::take(dir)?;
    if let ManifestFile::Usable(m) = read_manifest_file(dir)?
        && m.mismatch(fresh).is_none()
        && let Some(why) = m.arithmetic_mismatch(fresh, dir)
    {
        return Err(crate::error::InputError::new(why).into());
    }
    let ledger = load(dir, fresh)?;
    if ledger.absent || ledger.problem.is_some() {
        write_manifest(dir, &ledger.manifest)?;
    }
    Ok(ledger.problem)
}

/// When a shard's run ends: writes `manifest.json` with every journal folded in, then removes
/// the shard's journal (kept where the file system has no `flock`: without turns, another
/// shard's fold might write over this one's).
pub fn fold(dir: &Path, fresh: &Manifest, journal: Journal) -> Result<()> {
    let guard = ManifestLock::take(dir)?;
    journal
        .file
        .sync_data()
        .with_context(|| format!("syncing {}", journal.path.display()))?;
    let ledger = load(dir, fresh)?;
    write_manifest(dir, &ledger.manifest)?;
    if guard.held() {
        let Journal { path, file } = journal;
        drop(file);
        std::fs::remove_file(&path).with_context(|| format!("removing {}", path.display()))?;
        crate::store::sync_dir(dir)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn chunk(k: u64) -> Entry {
        Entry::Chunk(ChunkEntry {
            chunk: k,
            rows: 4,
            checksum: format!("{k:016x}"),
            outcomes: BTreeMap::from([("ok".to_string(), 4)]),
            attractors: None,
        })
    }

    #[test]
    fn a_torn_last_line_is_skipped_and_cut_off_on_reopen() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let mut j = Journal::open(dir, (0, 1)).unwrap();
        j.append(&chunk(0)).unwrap();
        j.append(&chunk(1)).unwrap();
        drop(j);
        let path = journal_path(dir, (0, 1));
        let mut text = std::fs::read(&path).unwrap();
        text.extend_from_slice(br#"{"kind":"chunk","chunk":2,"ro"#);
        std::fs::write(&path, &text).unwrap();
        assert_eq!(read_journals(dir).unwrap(), vec![chunk(0), chunk(1)]);
        let mut j = Journal::open(dir, (0, 1)).unwrap();
        j.append(&chunk(2)).unwrap();
        assert_eq!(
            read_journals(dir).unwrap(),
            vec![chunk(0), chunk(1), chunk(2)]
        );
    }

    #[test]
    fn journal_names() {
        let d = Path::new("d");
        assert_eq!(journal_path(d, (0, 1)), d.join("journal.jsonl"));
        assert_eq!(
            journal_path(d, (2, 5)),
            d.join("journal-shard-2-of-5.jsonl")
        );
        assert!(is_journal_name("journal.jsonl"));
        assert!(is_journal_name("journal-shard-2-of-5.jsonl"));
        assert!(!is_journal_name("journal.jsonl.tmp.12"));
    }
}
