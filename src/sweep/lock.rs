//! The writer lock of a shard: `.lock` (unsharded) or `.lock-shard-I-of-N` in the run
//! directory, holding the writer's `PID HOSTNAME`, created exclusively and removed at the end.
//! A second writer for the same shard is refused with the lock file's path and PID. A lock from
//! this host whose PID no longer exists (`/proc/PID`) is stale: `--resume` removes it.

use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

/// The lock file of a shard.
pub fn lock_path(dir: &Path, shard: (u64, u64)) -> PathBuf {
    if shard.1 <= 1 {
        dir.join(".lock")
    } else {
        dir.join(format!(".lock-shard-{}-of-{}", shard.0, shard.1))
    }
}

/// Whether a file name is a shard lock's.
pub fn is_lock_name(name: &str) -> bool {
    name == ".lock" || name.starts_with(".lock-shard-")
}

fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "unknown".to_string())
}

/// An exclusive writer lock on one shard of a run directory; removed when dropped.
#[derive(Debug)]
pub struct RunLock {
    path: PathBuf,
}

impl Drop for RunLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// What a lock file says about its holder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LockHolder {
    pub pid: u32,
    pub host: String,
    /// The holder runs on this host and its PID no longer exists.
    pub stale: bool,
}

/// Reads a lock file.
pub fn read_lock(path: &Path) -> Option<LockHolder> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut words = text.split_whitespace();
    let pid: u32 = words.next()?.parse().ok()?;
    let host = words.next().unwrap_or("").to_string();
    let stale = host == hostname() && !Path::new(&format!("/proc/{pid}")).exists();
    Some(LockHolder { pid, host, stale })
}

/// Takes the lock of `shard`; a stale lock (dead PID on this host) is replaced when `resume`.
pub fn acquire_lock(dir: &Path, shard: (u64, u64), resume: bool) -> Result<RunLock> {
    let path = lock_path(dir, shard);
    for _ in 0..3 {
        match OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(mut f) => {
                writeln!(f, "{} {}", std::process::id(), hostname())
                    .with_context(|| format!("writing {}", path.display()))?;
                return Ok(RunLock { path });
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => match read_lock(&path) {
                Some(h) if h.stale && resume => {
                    std::fs::remove_file(&path).or_else(|e| {
                        if e.kind() == std::io::ErrorKind::NotFound {
                            Ok(())
                        } else {
                            Err(e)
                        }
                    })?;
                    continue;
                }
                Some(h) => bail!(
                    "{}: another impactsweep process (PID {} on host {}) is writing this run \
                         directory{}; wait for it to finish{}",
                    path.display(),
                    h.pid,
                    h.host,
                    if h.stale {
                        " (that PID is gone: pass --resume to take over)"
                    } else {
                        ""
                    },
                    ", or delete the lock file if that process no longer exists"
                ),
                None => bail!(
                    "{}: the lock file is unreadable; delete it if no impactsweep process is \
                         writing this run directory",
                    path.display()
                ),
            },
            Err(e) => {
                return Err(e).with_context(|| format!("creating {}", path.display()));
            }
        }
    }
    bail!("{}: could not take the lock", path.display())
}
