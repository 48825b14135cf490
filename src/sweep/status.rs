//! What a run directory holds, every part verified: the part files are the truth, the manifest
//! and the journals say what they should be.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use rayon::prelude::*;

use super::journal;
use super::lock::{LockHolder, is_lock_name, read_lock};
use super::options::shard_chunks;
use super::verify::{check_recorded, check_unrecorded};
use crate::error::InputError;
use crate::sim::Outcome;
use crate::store::{self, Manifest, ManifestFile, read_manifest_file};

/// What a run directory holds.
#[derive(Clone, Debug)]
pub struct Status {
    /// `manifest.json` with the journals applied (and the chunks found good but not yet
    /// recorded).
    pub manifest: Manifest,
    /// Chunks whose part file is good, in order.
    pub done: Vec<u64>,
    /// Of those, the ones no journal or manifest records yet (`run --resume` records them).
    pub unrecorded: Vec<u64>,
    /// Chunks whose part file is damaged, or recorded but missing: (chunk, why).
    pub damaged: Vec<(u64, String)>,
    /// Chunks without a good part file (damaged ones included).
    pub missing: Vec<u64>,
    /// Rows in the good parts.
    pub runs_done: u64,
    /// Lock files present: (file name, holder).
    pub locks: Vec<(String, Option<LockHolder>)>,
}

impl Status {
    /// Every chunk has a good part file.
    pub fn complete(&self) -> bool {
        self.missing.is_empty()
    }

    /// The error `status` and `reduce` end with when a part is damaged: each file and why, and
    /// what to do.
    pub fn damage_error(&self, dir: &Path) -> Option<anyhow::Error> {
        if self.damaged.is_empty() {
            return None;
        }
        let n = self.damaged.len();
        let mut o = format!(
            "{}: {n} damaged part file{}:",
            dir.display(),
            if n == 1 { "" } else { "s" }
        );
        for (k, why) in &self.damaged {
            let _ = write!(o, "\n  {}: {why}", store::part_path(dir, *k).display());
        }
        let _ = write!(
            o,
            "\nrun `{}` to run {} again (it keeps every good part)",
            resume_command(dir),
            if n == 1 { "its chunk" } else { "their chunks" }
        );
        Some(anyhow::anyhow!(o))
    }

    /// The `status` command's text: chunks and runs done, missing chunks, per shard, outcomes,
    /// locks and the audit.
    pub fn report(&self, dir: &Path) -> String {
        let mut o = String::new();
        let m = &self.manifest;
        let _ = writeln!(o, "{}: study {}", dir.display(), m.study);
        let _ = writeln!(
            o,
            "chunks {}/{} done, runs {}/{} done ({} points x {} cases, {})",
            self.done.len(),
            m.n_chunks,
            self.runs_done,
            m.n_runs,
            m.n_points,
            m.n_cases,
            match m.chunk_cases {
                Some(c) => format!("a point's cases split into chunks of {c}"),
                None => format!("{} points per chunk", m.chunk_points),
            }
        );
        for (k, why) in &self.damaged {
            let _ = writeln!(o, "damaged: {}: {why}", store::part_path(dir, *k).display());
        }
        if !self.unrecorded.is_empty() {
            let _ = writeln!(
                o,
                "not yet recorded (good: readable, this study's rows; `run --resume` records \
                 them): chunks {}",
                ranges(&self.unrecorded)
            );
        }
        if self.missing.is_empty() {
            let _ = writeln!(o, "complete");
        } else {
            let _ = writeln!(o, "missing chunks: {}", ranges(&self.missing));
        }
        self.shard_lines(&mut o);
        arithmetic_lines(m, &mut o);
        if !m.outcomes.is_empty() {
            let outcomes: Vec<String> =
                m.outcomes.iter().map(|(k, v)| format!("{k} {v}")).collect();
            let _ = writeln!(o, "outcomes: {}", outcomes.join(", "));
        }
        self.lock_and_audit_lines(&mut o);
        o
    }

    /// One line per shard the run was split into (`n > 1`): its chunks done and missing.
    fn shard_lines(&self, o: &mut String) {
        let m = &self.manifest;
        let mut shards: Vec<(u64, u64)> = m
            .shards
            .iter()
            .filter_map(|s| {
                let (i, n) = s.split_once('/')?;
                Some((i.parse().ok()?, n.parse().ok()?))
            })
            .filter(|&(_, n)| n > 1)
            .collect();
        shards.sort();
        for (i, n) in shards {
            let all: Vec<u64> = shard_chunks(m.n_chunks, (i, n)).collect();
            let missing: Vec<u64> = all
                .iter()
                .copied()
                .filter(|k| self.missing.binary_search(k).is_ok())
                .collect();
            let _ = writeln!(
                o,
                "shard {i}/{n}: chunks {}/{} done{}",
                all.len() - missing.len(),
                all.len(),
                if missing.is_empty() {
                    String::new()
                } else {
                    format!(", missing {}", ranges(&missing))
                }
            );
        }
    }

    /// A line per lock (its holder, running or stale) and the solver audit's line.
    fn lock_and_audit_lines(&self, o: &mut String) {
        let m = &self.manifest;
        for (name, holder) in &self.locks {
            let _ = match holder {
                Some(h) => writeln!(
                    o,
                    "lock {name}: PID {} on {}{}",
                    h.pid,
                    h.host,
                    if h.stale {
                        " (stale: that process is gone)"
                    } else {
                        " (running)"
                    }
                ),
                None => writeln!(o, "lock {name}: unreadable"),
            };
        }
        if let Some(a) = &m.audit {
            let _ = writeln!(
                o,
                "audit ({} points, {} {} = {:e} against {}): relative error max/median xmax {:.1e}/{:.1e}, t1 {:.1e}/{:.1e}, di {:.1e}/{:.1e}; outcome changed {}, impacts changed {}",
                a.points.len(),
                a.solver,
                a.knob,
                a.knob_value,
                a.reference,
                a.xmax.max,
                a.xmax.median,
                a.t1.max,
                a.t1.median,
                a.di.max,
                a.di.median,
                a.outcome_changed,
                a.impacts_changed
            );
        }
    }
}

/// What computed the records (the math library's fingerprint, the numerics version) against
/// this process: a resume is refused where they differ.
fn arithmetic_lines(m: &Manifest, o: &mut String) {
    let recorded = [
        m.math.as_ref().map(|theirs| {
            let ours = crate::sim::math::fingerprint().to_string();
            (
                "math library: fingerprint",
                theirs.clone(),
                ours,
                "machine's",
                "here",
            )
        }),
        m.numerics.map(|theirs| {
            let ours = crate::sim::math::NUMERICS.to_string();
            (
                "numerics version",
                theirs.to_string(),
                ours,
                "build's",
                "by it",
            )
        }),
    ];
    for (what, theirs, ours, whose, how) in recorded.into_iter().flatten() {
        let _ = if theirs == ours {
            writeln!(o, "{what} {theirs} (this {whose} too)")
        } else {
            writeln!(
                o,
                "{what} {theirs} (this {whose} is {ours}: a resume {how} is refused)"
            )
        };
    }
}

/// The command that resumes the run directory `dir` (its own `study.toml`, into its parent).
pub fn resume_command(dir: &Path) -> String {
    let parent = dir
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    format!(
        "impactsweep run {} --out {} --resume",
        dir.join("study.toml").display(),
        parent.display()
    )
}

/// Reads a run directory's state and verifies every part file (see [`super::verify`]). A
/// directory without a manifest is bad input; a dataset of another schema version is refused
/// with what it is and what to do; a manifest that is unusable (empty, cut short, of another
/// study) is refused with how to rebuild it.
pub fn status(dir: &Path) -> Result<Status> {
    if read_manifest_file(dir)? == ManifestFile::Absent {
        let parts = store::part_files(dir)?;
        let Some(first) = parts.first() else {
            return Err(InputError::new(format!(
                "{}: not a run directory (no manifest.json)",
                dir.display()
            ))
            .into());
        };
        // A dataset of another schema version is told by its part files' own metadata.
        if let Ok(meta) = store::part_metadata(first) {
            store::check_version(first, &meta)?;
        }
        anyhow::bail!(
            "{}: no manifest.json beside {} part files; run `{}` to rebuild it from the part \
             files (each is verified)",
            dir.display(),
            parts.len(),
            resume_command(dir)
        );
    }
    let study_path = dir.join("study.toml");
    let study_text = std::fs::read_to_string(&study_path)
        .with_context(|| format!("reading {}", study_path.display()))?;
    let refuse = |problem: &str| {
        anyhow::anyhow!(
            "{}: {problem}; run `{}` to rebuild it from the part files (each is verified)",
            store::manifest::manifest_path(dir).display(),
            resume_command(dir)
        )
    };
    let mut manifest = journal::load_recorded(dir)?.map_err(|why| refuse(&why))?;
    if let Some(why) = manifest.study_text_mismatch(&study_text) {
        return Err(refuse(&why));
    }
    let present: Vec<u64> = store::part_files(dir)?
        .iter()
        .filter_map(|p| store::part_chunk(p))
        .filter(|&k| k < manifest.n_chunks)
        .collect();
    let checked = present
        .par_iter()
        .map(|&k| {
            let path = store::part_path(dir, k);
            let verdict = match manifest.chunk(k) {
                Some(e) => check_recorded(&manifest, &path, e).map_or(Ok(None), Err),
                None => check_unrecorded(&manifest, &study_text, &path, k)?.map(Some),
            };
            Ok((k, verdict))
        })
        .collect::<Result<Vec<(u64, Result<Option<store::ChunkEntry>, String>)>>>()?;
    let mut done = Vec::new();
    let mut unrecorded = Vec::new();
    let mut damaged = Vec::new();
    for (k, verdict) in checked {
        match verdict {
            Ok(None) => done.push(k),
            Ok(Some(entry)) => {
                done.push(k);
                unrecorded.push(k);
                manifest.upsert(entry);
            }
            Err(why) => damaged.push((k, why)),
        }
    }
    for c in &manifest.chunks {
        if present.binary_search(&c.chunk).is_err() {
            damaged.push((
                c.chunk,
                "recorded as finished, but the file is missing".into(),
            ));
        }
    }
    damaged.sort_by_key(|d| d.0);
    // Only the good parts count.
    manifest
        .chunks
        .retain(|c| done.binary_search(&c.chunk).is_ok());
    manifest.recount();
    let missing = missing_chunks(manifest.n_chunks, &done);
    let mut locks = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().to_string();
        if is_lock_name(&name) {
            locks.push((name, read_lock(&entry.path())));
        }
    }
    locks.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(Status {
        runs_done: manifest.runs_done,
        manifest,
        done,
        unrecorded,
        damaged,
        missing,
        locks,
    })
}

/// The chunks of `0..n` not in the sorted list `done`.
pub fn missing_chunks(n: u64, done: &[u64]) -> Vec<u64> {
    let mut out = Vec::new();
    let mut it = done.iter().peekable();
    for k in 0..n {
        while it.peek().is_some_and(|&&d| d < k) {
            it.next();
        }
        if it.peek() != Some(&&k) {
            out.push(k);
        }
    }
    out
}

/// Sorted ids as compressed ranges: `0-3, 7, 9-12`.
pub fn ranges(ids: &[u64]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < ids.len() {
        let mut j = i;
        while j + 1 < ids.len() && ids[j + 1] == ids[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            ids[i].to_string()
        } else {
            format!("{}-{}", ids[i], ids[j])
        });
        i = j + 1;
    }
    parts.join(", ")
}

/// Outcome names in the order of [`Outcome::ALL`] (for summaries).
pub fn outcome_names() -> Vec<&'static str> {
    Outcome::ALL.iter().map(|o| o.name()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_compress_runs_of_ids() {
        assert_eq!(ranges(&[]), "");
        assert_eq!(ranges(&[4]), "4");
        assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10, 11]), "0-3, 7, 9-11");
    }

    #[test]
    fn missing_chunks_are_the_complement() {
        assert_eq!(missing_chunks(6, &[0, 2, 3]), vec![1, 4, 5]);
        assert_eq!(missing_chunks(3, &[0, 1, 2]), Vec::<u64>::new());
        assert_eq!(missing_chunks(2, &[]), vec![0, 1]);
    }
}
