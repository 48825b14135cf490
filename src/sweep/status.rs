//! What a run directory holds: the part files are the truth, the manifest gives the sizes.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use super::lock::{LockHolder, is_lock_name, read_lock};
use crate::error::InputError;
use crate::sim::Outcome;
use crate::store::{self, Manifest, read_manifest};

/// What a run directory holds.
#[derive(Clone, Debug)]
pub struct Status {
    pub manifest: Manifest,
    /// Chunks whose part file exists.
    pub done: Vec<u64>,
    /// Chunks without a part file.
    pub missing: Vec<u64>,
    /// Rows in the finished parts (from their footers).
    pub runs_done: u64,
    /// Lock files present: (file name, holder).
    pub locks: Vec<(String, Option<LockHolder>)>,
}

impl Status {
    /// Every chunk has its part file.
    pub fn complete(&self) -> bool {
        self.missing.is_empty()
    }

    /// The `status` command's text: chunks and runs done, missing chunks, per shard, outcomes,
    /// locks and the audit.
    pub fn report(&self, dir: &Path) -> String {
        let mut o = String::new();
        let m = &self.manifest;
        let _ = writeln!(o, "{}: study {}", dir.display(), m.study);
        let _ = writeln!(
            o,
            "chunks {}/{} done, runs {}/{} done ({} points x {} cases, {} points per chunk)",
            self.done.len(),
            m.n_chunks,
            self.runs_done,
            m.n_runs,
            m.n_points,
            m.n_cases,
            m.chunk_points
        );
        if self.missing.is_empty() {
            let _ = writeln!(o, "complete");
        } else {
            let _ = writeln!(o, "missing chunks: {}", ranges(&self.missing));
        }
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
            let all: Vec<u64> = super::shard_chunks(m.n_chunks, (i, n)).collect();
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
        if !m.outcomes.is_empty() {
            let outcomes: Vec<String> =
                m.outcomes.iter().map(|(k, v)| format!("{k} {v}")).collect();
            let _ = writeln!(o, "outcomes: {}", outcomes.join(", "));
        }
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
        o
    }
}

/// Reads a run directory's state. A dataset of another schema version is refused with what it
/// is and what to do.
pub fn status(dir: &Path) -> Result<Status> {
    let manifest = read_manifest(dir)?.ok_or_else(|| {
        InputError::new(format!(
            "{}: not a run directory (no manifest.json)",
            dir.display()
        ))
    })?;
    manifest.check_version(dir)?;
    let mut done = Vec::new();
    let mut runs_done = 0;
    for path in store::part_files(dir)? {
        if let Some(k) = store::part_chunk(&path)
            && k < manifest.n_chunks
        {
            runs_done += store::part_rows(&path)?;
            done.push(k);
        }
    }
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
        manifest,
        done,
        missing,
        runs_done,
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
