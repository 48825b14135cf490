//! The bookkeeping of finished chunks: every change to `manifest.json` goes through here.
//!
//! Today each change is a read-merge-write of the whole manifest (temp file + rename) while
//! holding an exclusive `flock` on `.manifest.lock`, so several shards may share one directory
//! (Slurm array tasks) and none loses another's entries. A crash between a part's rename and
//! [`record_chunk`] only leaves a part the manifest does not list yet; `--resume` verifies it
//! and records it.
//!
//! [`record_chunk`] is the per-chunk cost of a sweep (issue 9 item 3 replaces it with an
//! append-only journal folded into the manifest at the end).

use std::fs::{File, OpenOptions};
use std::path::Path;

use anyhow::{Context, Result};

use crate::accuracy::Audit;
use crate::store::manifest::{ChunkEntry, Manifest, read_manifest, write_manifest};

/// Holds an exclusive `flock` on `dir/.manifest.lock` while alive.
struct ManifestLock {
    _file: File,
}

impl ManifestLock {
    fn take(dir: &Path) -> Result<ManifestLock> {
        use std::os::fd::AsRawFd;
        let path = dir.join(".manifest.lock");
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .with_context(|| format!("opening {}", path.display()))?;
        loop {
            // SAFETY: flock on a descriptor we own; released when the file is closed.
            let rc = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) };
            if rc == 0 {
                break;
            }
            let err = std::io::Error::last_os_error();
            if err.kind() != std::io::ErrorKind::Interrupted {
                return Err(err).with_context(|| format!("locking {}", path.display()));
            }
        }
        Ok(ManifestLock { _file: file })
    }
}

/// Read-merge-write of the manifest under the directory's manifest lock (`fresh` when there is
/// no manifest yet).
fn update_manifest(dir: &Path, fresh: &Manifest, f: impl FnOnce(&mut Manifest)) -> Result<()> {
    let _guard = ManifestLock::take(dir)?;
    let mut m = read_manifest(dir)?.unwrap_or_else(|| fresh.clone());
    f(&mut m);
    m.recount();
    write_manifest(dir, &m)
}

/// Records a finished chunk (its part file is complete under its final name).
pub fn record_chunk(dir: &Path, fresh: &Manifest, entry: ChunkEntry) -> Result<()> {
    update_manifest(dir, fresh, |m| m.upsert(entry))
}

/// Records that shard `I/N` writes into this directory.
pub fn record_shard(dir: &Path, fresh: &Manifest, shard_name: &str) -> Result<()> {
    update_manifest(dir, fresh, |m| {
        if !m.shards.iter().any(|s| s == shard_name) {
            m.shards.push(shard_name.to_string());
            m.shards.sort();
        }
    })
}

/// Records the accuracy audit.
pub fn record_audit(dir: &Path, fresh: &Manifest, audit: Audit) -> Result<()> {
    update_manifest(dir, fresh, |m| m.audit = Some(audit))
}
