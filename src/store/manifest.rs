//! `manifest.json`: the summary of a run directory (tool and schema version, sizes, and per
//! finished chunk its row count, outcome counts and checksum). The sweep engine writes it when a
//! run starts and folds its journal of finished chunks into it when the run ends
//! ([`crate::sweep::journal`]); `status` and `reduce` read it with the journals.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use super::Checksum;
use super::audit::Audit;

/// The manifest of a run directory (`manifest.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub tool: String,
    pub version: String,
    pub schema_version: u32,
    pub study: String,
    /// The checksum ([`Checksum::DEFAULT`], hex) of the study text (`study.toml`) the directory
    /// was written for: a manifest copied from another run directory is told apart by it.
    /// Absent in manifests written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study_checksum: Option<String>,
    pub seed: u64,
    /// The fingerprint of the math library that computed the records
    /// ([`crate::sim::math::fingerprint`]): a shard or a resume whose library computes
    /// otherwise is refused ([`Manifest::arithmetic_mismatch`]). Absent in manifests written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub math: Option<String>,
    /// The version of the records' arithmetic of the build that wrote them
    /// ([`crate::sim::math::NUMERICS`]): a build of another version is refused as `math` is.
    /// Absent in manifests written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub numerics: Option<u32>,
    pub n_points: u64,
    pub n_cases: u64,
    pub n_runs: u64,
    pub chunk_points: u64,
    /// A random study whose design points are split into blocks of realizations
    /// ([`crate::plan::Plan::chunk_runs`]): runs per block; absent when chunks hold whole points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chunk_cases: Option<u64>,
    pub n_chunks: u64,
    /// How `chunks[].checksum` is computed.
    pub checksum: String,
    pub chunks_done: u64,
    pub runs_done: u64,
    /// Outcome counts over the finished chunks.
    pub outcomes: BTreeMap<String, u64>,
    /// Finished chunks, by chunk id.
    pub chunks: Vec<ChunkEntry>,
    /// Chunks whose part files were being renamed into place when the journal was last folded,
    /// with the checksums they were written with (empty, and absent from the file, once every
    /// chunk written is recorded as finished).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub writing: Vec<WritingEntry>,
    /// Shards (`I/N`) that have written into this directory.
    pub shards: Vec<String>,
    pub audit: Option<Audit>,
}

/// The sizes of a run directory's dataset, as its plan gives them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sizes {
    pub n_points: u64,
    pub n_cases: u64,
    pub n_runs: u64,
    pub chunk_points: u64,
    /// Runs per block of a design point split into blocks; `None` for whole points.
    pub chunk_cases: Option<u64>,
    pub n_chunks: u64,
}

/// One finished chunk.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChunkEntry {
    pub chunk: u64,
    pub rows: u64,
    /// The part file's checksum by the manifest's algorithm (its `checksum` key), 16 hex digits.
    pub checksum: String,
    pub outcomes: BTreeMap<String, u64>,
    /// The chunk's attractors part (a harmonic study with a census), checked with its points
    /// part: absent for free decay and for datasets written before the sweep stored attractors.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attractors: Option<AttractorsEntry>,
}

/// A chunk's part files about to be renamed into place: their checksums, recorded before the
/// renames (the journal's `writing` line, [`crate::store::write_part`]). A part renamed but never
/// recorded as finished (its writer stopped between the rename and the `chunk` line) is held to
/// them, so a part damaged since is run again rather than kept ([`crate::sweep::verify`]).
/// [`crate::store::PartInfo::writing`] makes it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct WritingEntry {
    pub chunk: u64,
    /// The points part's checksum, and the attractors part's when the chunk has one.
    pub checksum: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attractors: Option<String>,
}

/// A chunk's attractors part ([`crate::store::attractors`]): its rows and checksum.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct AttractorsEntry {
    pub rows: u64,
    pub checksum: String,
}

/// The checksum of a study text, as `study_checksum` holds it.
pub fn study_checksum(text: &str) -> String {
    Checksum::DEFAULT.hex(text.as_bytes())
}

/// The path of a run directory's manifest.
pub fn manifest_path(dir: &Path) -> std::path::PathBuf {
    dir.join("manifest.json")
}

/// Reads `dir/manifest.json`, `None` when absent.
///
/// Only the text is parsed here; whether this build can read the dataset is
/// [`Manifest::check_version`].
pub fn read_manifest(dir: &Path) -> Result<Option<Manifest>> {
    let path = manifest_path(dir);
    match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .with_context(|| format!("{}: not a valid manifest", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
    }
}

/// What `manifest.json` holds.
#[derive(Clone, Debug, PartialEq)]
pub enum ManifestFile {
    /// No `manifest.json`.
    Absent,
    /// A manifest this build reads (schema version and checksum algorithm known).
    Usable(Box<Manifest>),
    /// A file that is no usable manifest: why (`is empty`, `is not valid JSON …`), to be rebuilt
    /// from the part files or refused.
    Unusable(String),
}

/// Reads `dir/manifest.json` and says whether it can be used. A manifest of another schema
/// version is an error (bad input: the dataset needs another build), as is an I/O error.
pub fn read_manifest_file(dir: &Path) -> Result<ManifestFile> {
    let path = manifest_path(dir);
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(ManifestFile::Absent),
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Ok(ManifestFile::Unusable("is empty".into()));
    }
    let value: serde_json::Value = match serde_json::from_slice(&bytes) {
        Ok(v) => v,
        Err(e) => {
            return Ok(ManifestFile::Unusable(format!(
                "is not valid JSON (truncated or damaged: {e})"
            )));
        }
    };
    check_value_version(dir, &value)?;
    let m: Manifest = match serde_json::from_value(value) {
        Ok(m) => m,
        Err(e) => {
            return Ok(ManifestFile::Unusable(format!(
                "is not an impactsweep manifest ({e})"
            )));
        }
    };
    if Checksum::from_doc(&m.checksum).is_none() {
        let known: Vec<String> = Checksum::ALL
            .iter()
            .map(|c| format!("`{}`", c.doc()))
            .collect();
        return Ok(ManifestFile::Unusable(format!(
            "names checksum algorithm `{}`, which this build does not know (it verifies {})",
            m.checksum,
            known.join(" and ")
        )));
    }
    Ok(ManifestFile::Usable(Box::new(m)))
}

fn check_value_version(dir: &Path, v: &serde_json::Value) -> Result<()> {
    match v.get("schema_version").and_then(serde_json::Value::as_u64) {
        Some(found) if found != u64::from(super::SCHEMA_VERSION) => Err(super::version_error(
            &dir.display().to_string(),
            &found.to_string(),
            v.get("version").and_then(serde_json::Value::as_str),
        )
        .into()),
        _ => Ok(()),
    }
}

/// Refuses a run directory whose `manifest.json` names another schema version. Reads only the
/// `schema_version` and `version` keys, so a manifest this build could not parse otherwise (or
/// none at all) passes: the part files' own metadata is checked when they are read.
pub fn check_dir_version(dir: &Path) -> Result<()> {
    let Ok(text) = std::fs::read_to_string(manifest_path(dir)) else {
        return Ok(());
    };
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Ok(());
    };
    check_value_version(dir, &v)
}

/// Writes `dir/manifest.json` atomically and durably (a temp name unique to this process,
/// synced, renamed, the directory synced).
pub fn write_manifest(dir: &Path, m: &Manifest) -> Result<()> {
    let text = serde_json::to_string_pretty(m)? + "\n";
    super::write_shared(&manifest_path(dir), text.as_bytes())
}

impl Manifest {
    /// The manifest of a fresh run directory of study `name` (its text `source`, its `seed`)
    /// of these sizes ([`crate::plan::Plan`]'s), nothing done.
    pub fn new(name: &str, source: &str, seed: u64, sizes: Sizes) -> Manifest {
        Manifest {
            tool: "impactsweep".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            schema_version: super::SCHEMA_VERSION,
            study: name.to_string(),
            study_checksum: Some(study_checksum(source)),
            seed,
            math: Some(crate::sim::math::fingerprint().to_string()),
            numerics: Some(crate::sim::math::NUMERICS),
            n_points: sizes.n_points,
            n_cases: sizes.n_cases,
            n_runs: sizes.n_runs,
            chunk_points: sizes.chunk_points,
            chunk_cases: sizes.chunk_cases,
            n_chunks: sizes.n_chunks,
            checksum: Checksum::DEFAULT.doc().into(),
            chunks_done: 0,
            runs_done: 0,
            outcomes: BTreeMap::new(),
            chunks: Vec::new(),
            writing: Vec::new(),
            shards: Vec::new(),
            audit: None,
        }
    }

    /// Refuses a dataset of another schema version (`dir` names it in the message).
    pub fn check_version(&self, dir: &Path) -> Result<(), crate::error::InputError> {
        if self.schema_version == super::SCHEMA_VERSION {
            return Ok(());
        }
        Err(super::version_error(
            &dir.display().to_string(),
            &self.schema_version.to_string(),
            Some(&self.version),
        ))
    }

    /// The algorithm of `chunks[].checksum` (a usable manifest always names a known one).
    pub fn algorithm(&self) -> Checksum {
        Checksum::from_doc(&self.checksum).unwrap_or(Checksum::DEFAULT)
    }

    /// Why this manifest does not describe the run directory `fresh` describes (another study,
    /// seed or size), or `None` when it does.
    pub fn mismatch(&self, fresh: &Manifest) -> Option<String> {
        let who = |m: &Manifest| {
            format!(
                "study `{}` (seed {}, {} points x {} cases, {} points per chunk)",
                m.study, m.seed, m.n_points, m.n_cases, m.chunk_points
            )
        };
        let text_differs = matches!(
            (&self.study_checksum, &fresh.study_checksum),
            (Some(a), Some(b)) if a != b
        );
        let same = !text_differs
            && self.tool == fresh.tool
            && self.study == fresh.study
            && self.seed == fresh.seed
            && self.n_points == fresh.n_points
            && self.n_cases == fresh.n_cases
            && self.n_runs == fresh.n_runs
            && self.chunk_points == fresh.chunk_points
            && self.chunk_cases == fresh.chunk_cases
            && self.n_chunks == fresh.n_chunks;
        (!same).then(|| {
            format!(
                "describes {}{}, not this directory's: {}",
                who(self),
                if text_differs {
                    " written from another study text"
                } else {
                    ""
                },
                who(fresh)
            )
        })
    }

    /// Why the records of this manifest's directory and those this process would write are not
    /// one build's and one math library's bits (`fresh`'s numerics version,
    /// [`crate::sim::math::NUMERICS`], or its fingerprint, [`crate::sim::math::fingerprint`],
    /// differs from the recorded one), or `None` (also when this manifest predates them). `dir`
    /// names the directory in the message.
    pub fn arithmetic_mismatch(&self, fresh: &Manifest, dir: &Path) -> Option<String> {
        if let (Some(theirs), Some(ours)) = (self.numerics, fresh.numerics)
            && theirs != ours
        {
            return Some(format!(
                "{}: its records were computed by a build of impactsweep whose arithmetic \
                 differs from this one's (numerics version {theirs} in manifest.json, {ours} \
                 here): the records written here would not be the same bits as the others. \
                 Resume it with the build that started it, or run the study again into another \
                 --out (nothing was written)",
                dir.display()
            ));
        }
        match (&self.math, &fresh.math) {
            (Some(theirs), Some(ours)) if theirs != ours => Some(format!(
                "{}: its records were computed by a math library that rounds differently from \
                 this machine's (fingerprint {theirs} in manifest.json, {ours} here; glibc picks \
                 its code for exp, sin and cos by the processor, FMA or not): the records \
                 written here would not be the same bits as the others. Run every shard and \
                 every resume of a study on processors of one kind (Slurm: --constraint), or \
                 choose another --out (nothing was written)",
                dir.display()
            )),
            _ => None,
        }
    }

    /// Why this manifest does not belong to a directory whose `study.toml` is `study_text`, or
    /// `None` (also when the manifest predates `study_checksum`).
    pub fn study_text_mismatch(&self, study_text: &str) -> Option<String> {
        let want = study_checksum(study_text);
        match &self.study_checksum {
            Some(got) if *got != want => Some(format!(
                "describes study `{}` (seed {}, {} points x {} cases), written for another \
                 study text than this directory's study.toml (study checksum {got}, study.toml's \
                 {want})",
                self.study, self.seed, self.n_points, self.n_cases
            )),
            _ => None,
        }
    }

    /// The point ids (rows) of chunk `k`: whole design points with all their cases, or a block
    /// of one point's realizations ([`crate::plan::Plan::chunk_runs`]).
    pub fn chunk_ids(&self, k: u64) -> std::ops::Range<u64> {
        if let Some(c) = self.chunk_cases {
            let c = c.max(1);
            let b = self.n_cases.div_ceil(c).max(1);
            let p = (k / b).min(self.n_points);
            let start = (p * self.n_cases + (k % b) * c).min(self.n_points * self.n_cases);
            return start..(start + c).min((p + 1) * self.n_cases);
        }
        let per = self.chunk_points.max(1);
        let start = k.saturating_mul(per).min(self.n_points);
        let end = k.saturating_add(1).saturating_mul(per).min(self.n_points);
        start * self.n_cases..end * self.n_cases
    }

    /// Sorts the chunks and recomputes the totals from them.
    pub fn recount(&mut self) {
        self.chunks.sort_by_key(|c| c.chunk);
        self.chunks.dedup_by_key(|c| c.chunk);
        self.writing.sort_by_key(|w| w.chunk);
        self.writing.dedup_by_key(|w| w.chunk);
        self.chunks_done = self.chunks.len() as u64;
        self.runs_done = self.chunks.iter().map(|c| c.rows).sum();
        self.outcomes.clear();
        for c in &self.chunks {
            for (k, v) in &c.outcomes {
                *self.outcomes.entry(k.clone()).or_default() += v;
            }
        }
    }

    /// The entry of chunk `k`.
    pub fn chunk(&self, k: u64) -> Option<&ChunkEntry> {
        self.chunks
            .binary_search_by_key(&k, |c| c.chunk)
            .ok()
            .map(|i| &self.chunks[i])
    }

    /// Adds or replaces the entry of a chunk (it is no longer being written).
    pub fn upsert(&mut self, entry: ChunkEntry) {
        self.writing.retain(|w| w.chunk != entry.chunk);
        match self.chunks.binary_search_by_key(&entry.chunk, |c| c.chunk) {
            Ok(i) => self.chunks[i] = entry,
            Err(i) => self.chunks.insert(i, entry),
        }
    }

    /// Adds or replaces the checksums chunk `entry.chunk` is being written with.
    pub fn upsert_writing(&mut self, entry: WritingEntry) {
        match self.writing.binary_search_by_key(&entry.chunk, |w| w.chunk) {
            Ok(i) => self.writing[i] = entry,
            Err(i) => self.writing.insert(i, entry),
        }
    }

    /// The checksums chunk `k` was being written with, when it is not recorded as finished.
    pub fn writing(&self, k: u64) -> Option<&WritingEntry> {
        self.writing
            .binary_search_by_key(&k, |w| w.chunk)
            .ok()
            .map(|i| &self.writing[i])
    }
}
