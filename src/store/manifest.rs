//! `manifest.json`: the summary of a run directory (tool and schema version, sizes, and per
//! finished chunk its row count, outcome counts and checksum). The sweep engine keeps it up to
//! date ([`crate::sweep`]); `status` and `reduce` read it.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use crate::accuracy::Audit;
use crate::plan::Plan;

/// How `chunks[].checksum` is computed (the manifest's `checksum` field).
pub const CHECKSUM_DOC: &str = "fnv1a-64 of the part file's bytes (hex)";

/// The manifest of a run directory (`manifest.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub tool: String,
    pub version: String,
    pub schema_version: u32,
    pub study: String,
    pub seed: u64,
    pub n_points: u64,
    pub n_cases: u64,
    pub n_runs: u64,
    pub chunk_points: u64,
    pub n_chunks: u64,
    /// How `chunks[].checksum` is computed.
    pub checksum: String,
    pub chunks_done: u64,
    pub runs_done: u64,
    /// Outcome counts over the finished chunks.
    pub outcomes: BTreeMap<String, u64>,
    /// Finished chunks, by chunk id.
    pub chunks: Vec<ChunkEntry>,
    /// Shards (`I/N`) that have written into this directory.
    pub shards: Vec<String>,
    pub audit: Option<Audit>,
}

/// One finished chunk.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChunkEntry {
    pub chunk: u64,
    pub rows: u64,
    /// 64-bit FNV-1a of the part file's bytes, 16 hex digits.
    pub checksum: String,
    pub outcomes: BTreeMap<String, u64>,
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

/// Writes `dir/manifest.json` atomically (a temp name unique to this process, then rename).
pub fn write_manifest(dir: &Path, m: &Manifest) -> Result<()> {
    let text = serde_json::to_string_pretty(m)? + "\n";
    super::write_shared(&manifest_path(dir), text.as_bytes())
}

impl Manifest {
    /// The manifest of a fresh run directory: sizes from the plan, nothing done.
    pub fn new(plan: &Plan, chunk_points: u64) -> Manifest {
        let study = plan.study;
        Manifest {
            tool: "impactsweep".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            schema_version: super::SCHEMA_VERSION,
            study: study.name.clone(),
            seed: study.seed,
            n_points: plan.n_points(),
            n_cases: plan.n_cases(),
            n_runs: plan.n_runs(),
            chunk_points,
            n_chunks: plan.n_chunks(),
            checksum: CHECKSUM_DOC.into(),
            chunks_done: 0,
            runs_done: 0,
            outcomes: BTreeMap::new(),
            chunks: Vec::new(),
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

    /// Sorts the chunks and recomputes the totals from them.
    pub fn recount(&mut self) {
        self.chunks.sort_by_key(|c| c.chunk);
        self.chunks.dedup_by_key(|c| c.chunk);
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

    /// Adds or replaces the entry of a chunk.
    pub fn upsert(&mut self, entry: ChunkEntry) {
        match self.chunks.binary_search_by_key(&entry.chunk, |c| c.chunk) {
            Ok(i) => self.chunks[i] = entry,
            Err(i) => self.chunks.insert(i, entry),
        }
    }
}
