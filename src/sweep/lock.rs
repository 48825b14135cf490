//! The writer lock of a shard: `.lock` (unsharded) or `.lock-shard-I-of-N` in the run directory.
//!
//! The writer holds an exclusive OS lock (`flock(2)`) on the file for as long as it runs and
//! writes `PID HOST START` into it (`START`: the boot id and start time of the process, so a
//! reused PID is not taken for the writer). The OS releases the lock when the process ends,
//! however it ends (`kill -9`, out of memory), and on a network file system whose locks reach
//! every host (NFS, Lustre mounted with `-o flock`) when its host dies (once the server's lease
//! expires); so a dead writer never strands a shard. The rules, in order:
//!
//! * the OS lock is held by another process: refused with the PID and host in the file;
//! * the file names a process on this host that is still alive (a writer that holds no OS lock,
//!   e.g. a lock file written by hand): refused;
//! * the file names a process on another host and this file system's `flock` stays on each host
//!   (NFS mounted with `local_lock=flock` or `all`, Lustre with `localflock`): refused, the lock
//!   file is to be deleted by hand once that process is gone;
//! * otherwise the previous writer is gone: `--resume` takes the lock over.
//!
//! Where the file system has no `flock` at all (ENOLCK, EOPNOTSUPP, ENOSYS), the lock falls back
//! to the file alone ([`LockMode::PidFile`]): created exclusively, removed at the end, stale when
//! it names a dead process on this host; a lock from another host must be deleted by hand.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::os::fd::AsRawFd;
use std::os::unix::fs::MetadataExt;
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

/// This host's name (`/proc/sys/kernel/hostname`, as `hostname` prints it).
pub fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "unknown".to_string())
}

/// What a `flock(2)` call gave.
#[derive(Debug)]
pub enum Flock {
    Locked,
    /// Another open file description holds it (only without waiting).
    Busy,
    /// The file system has no `flock` (ENOLCK, EOPNOTSUPP, ENOSYS, EINVAL).
    Unsupported(std::io::Error),
    Failed(std::io::Error),
}

/// Set (to anything but `0` or empty) to use no OS locks at all: the lock is then the file
/// alone, as on a file system without `flock`. For file systems whose `flock` hangs (an NFS
/// client whose lock daemon is down), and to test that rule.
pub const NO_FLOCK_ENV: &str = "IMPACTSWEEP_NO_FLOCK";

/// An exclusive `flock` on `file`, waiting for it when `wait`.
pub fn flock(file: &File, wait: bool) -> Flock {
    if std::env::var(NO_FLOCK_ENV).is_ok_and(|v| !v.is_empty() && v != "0") {
        return Flock::Unsupported(std::io::Error::other(format!("{NO_FLOCK_ENV} is set")));
    }
    let op = if wait {
        libc::LOCK_EX
    } else {
        libc::LOCK_EX | libc::LOCK_NB
    };
    loop {
        // SAFETY: flock on a descriptor we own; released when the file is closed.
        if unsafe { libc::flock(file.as_raw_fd(), op) } == 0 {
            return Flock::Locked;
        }
        let err = std::io::Error::last_os_error();
        return match err.raw_os_error() {
            Some(libc::EINTR) => continue,
            Some(libc::EWOULDBLOCK) => Flock::Busy,
            Some(libc::ENOLCK | libc::EOPNOTSUPP | libc::ENOSYS | libc::EINVAL) => {
                Flock::Unsupported(err)
            }
            _ => Flock::Failed(err),
        };
    }
}

/// How a [`RunLock`] holds its shard.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LockMode {
    /// An OS lock on the file, released by the OS when the process ends.
    Os,
    /// The file alone: the file system refused `flock` (the error says why).
    PidFile(String),
}

/// An exclusive writer lock on one shard of a run directory; the file is removed (then the OS
/// lock released) when dropped.
#[derive(Debug)]
pub struct RunLock {
    path: PathBuf,
    file: Option<File>,
    pub mode: LockMode,
}

impl Drop for RunLock {
    fn drop(&mut self) {
        // Removed while the OS lock is still held: a process that opened the old file meanwhile
        // finds, once it gets the lock, that the name no longer leads to it, and starts over.
        let _ = std::fs::remove_file(&self.path);
        self.file.take();
    }
}

/// What a lock file says about its holder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LockHolder {
    pub pid: u32,
    pub host: String,
    /// The holder ran on this host and is gone (its PID no longer exists, or is another
    /// process's now).
    pub stale: bool,
}

impl LockHolder {
    fn describe(&self) -> String {
        format!("PID {} on host {}", self.pid, self.host)
    }
}

/// `BOOT_ID:START_TICKS` of a process of this host, `None` when it does not exist.
fn process_start(pid: u32) -> Option<String> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // Field 22 (starttime), counted after the command name's closing parenthesis.
    let after = &stat[stat.rfind(')')? + 1..];
    let start = after.split_whitespace().nth(19)?;
    let boot = std::fs::read_to_string("/proc/sys/kernel/random/boot_id").ok()?;
    Some(format!("{}:{start}", boot.trim()))
}

/// Parses a lock file's text (`PID HOST [START]`).
pub fn parse_lock(text: &str) -> Option<LockHolder> {
    let mut words = text.split_whitespace();
    let pid: u32 = words.next()?.parse().ok()?;
    let host = words.next().unwrap_or("").to_string();
    let start = words.next();
    let stale = host == hostname()
        && match (process_start(pid), start) {
            (None, _) => true,
            (Some(now), Some(then)) => now != then,
            (Some(_), None) => false,
        };
    Some(LockHolder { pid, host, stale })
}

/// Reads a lock file.
pub fn read_lock(path: &Path) -> Option<LockHolder> {
    parse_lock(&std::fs::read_to_string(path).ok()?)
}

/// Why this file system's `flock` may not reach other hosts (from `/proc/self/mountinfo`), or
/// `None` when it does (or the file system is local).
pub fn host_local_flock(dir: &Path) -> Option<String> {
    let dir = dir.canonicalize().ok()?;
    let info = std::fs::read_to_string("/proc/self/mountinfo").ok()?;
    host_local_flock_in(&info, &dir)
}

/// [`host_local_flock`] on a given mountinfo text.
pub fn host_local_flock_in(mountinfo: &str, dir: &Path) -> Option<String> {
    // Each line: ID PARENT MAJ:MIN ROOT MOUNT_POINT OPTIONS [OPTIONAL...] - FSTYPE SOURCE SUPER.
    let mut best: Option<(usize, String, String)> = None;
    for line in mountinfo.lines() {
        let (head, tail) = line.split_once(" - ").unwrap_or((line, ""));
        let head: Vec<&str> = head.split(' ').collect();
        let tail: Vec<&str> = tail.split(' ').collect();
        let (Some(mount), Some(fstype)) = (head.get(4), tail.first()) else {
            continue;
        };
        let mount = mount.replace("\\040", " ");
        if !dir.starts_with(&mount) {
            continue;
        }
        let opts = format!(
            "{},{}",
            head.get(5).unwrap_or(&""),
            tail.get(2).unwrap_or(&"")
        );
        if best.as_ref().is_none_or(|b| mount.len() >= b.0) {
            best = Some((mount.len(), fstype.to_string(), opts));
        }
    }
    let (_, fstype, opts) = best?;
    let has = |o: &str| opts.split(',').any(|x| x == o);
    if fstype.starts_with("nfs") && (has("local_lock=flock") || has("local_lock=all")) {
        return Some(format!("{fstype} mounted with local_lock"));
    }
    if fstype == "lustre" && has("localflock") {
        return Some("lustre mounted with localflock".into());
    }
    None
}

/// The shard split `(I, N)` a lock file name stands for (`.lock` is `(0, 1)`).
pub fn lock_shard(name: &str) -> Option<(u64, u64)> {
    if name == ".lock" {
        return Some((0, 1));
    }
    let (i, n) = name.strip_prefix(".lock-shard-")?.split_once("-of-")?;
    Some((i.parse().ok()?, n.parse().ok()?))
}

/// Refuses to start shard `shard` while a writer with another split (`N`) writes `dir`: their
/// chunks overlap, so both would write the same parts. Call it while holding the directory's
/// manifest lock, so that no other writer starts meanwhile.
pub fn check_other_splits(dir: &Path, shard: (u64, u64)) -> Result<()> {
    for e in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let path = e?.path();
        let name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let Some(other) = lock_shard(&name) else {
            continue;
        };
        if other.1 == shard.1.max(1) {
            continue;
        }
        let Ok(file) = File::open(&path) else {
            continue;
        };
        let live = match flock(&file, false) {
            Flock::Busy => true,
            Flock::Locked => false,
            Flock::Unsupported(_) | Flock::Failed(_) => read_lock(&path).is_some_and(|h| !h.stale),
        };
        drop(file);
        if live {
            let who =
                read_lock(&path).map_or("its PID is not written yet".into(), |h| h.describe());
            let split = |(i, n): (u64, u64)| {
                if n <= 1 {
                    "an unsharded run".to_string()
                } else {
                    format!("shard {i}/{n}")
                }
            };
            bail!(
                "{}: {} ({who}) is writing this run directory; {} would write some of the same \
                 chunks. Wait for it to finish, or run with the same split (--shard I/{})",
                path.display(),
                split(other),
                split(shard),
                other.1
            );
        }
    }
    Ok(())
}

fn refuse(path: &Path, who: &str, why: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{}: another impactsweep process ({who}) is writing this run directory{why}; wait for it \
         to finish",
        path.display()
    )
}

/// Takes the lock of `shard`; a lock whose writer is gone is taken over when `resume`.
pub fn acquire_lock(dir: &Path, shard: (u64, u64), resume: bool) -> Result<RunLock> {
    let path = lock_path(dir, shard);
    for _ in 0..20 {
        let (file, created) = match OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(f) => (f, true),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                match OpenOptions::new().read(true).write(true).open(&path) {
                    Ok(f) => (f, false),
                    // Removed by its holder meanwhile.
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                    Err(e) => return Err(e).with_context(|| format!("opening {}", path.display())),
                }
            }
            Err(e) => return Err(e).with_context(|| format!("creating {}", path.display())),
        };
        match flock(&file, false) {
            Flock::Locked => {
                let same = match (file.metadata(), std::fs::metadata(&path)) {
                    (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
                    _ => false,
                };
                if !same {
                    continue; // its holder removed it before we got the lock: start over
                }
                if !created {
                    check_gone(dir, &path, &file, resume)?;
                }
                return hold(path, file, LockMode::Os);
            }
            Flock::Busy => {
                // A holder that has just created the file may not have written it yet.
                let mut holder = None;
                for _ in 0..50 {
                    holder = read_lock(&path);
                    if holder.is_some() {
                        break;
                    }
                    std::thread::sleep(std::time::Duration::from_millis(10));
                }
                let who = holder.map_or("its PID is not written yet".into(), |h| h.describe());
                return Err(refuse(&path, &who, " (it holds the OS lock on the file)"));
            }
            Flock::Unsupported(e) => {
                let why = format!("{e}");
                if created {
                    return hold(path, file, LockMode::PidFile(why));
                }
                drop(file);
                match read_lock(&path) {
                    Some(h) if h.stale && resume => {
                        remove_if_present(&path)?;
                        continue;
                    }
                    Some(h) => bail!(
                        "{}: another impactsweep process ({}) is writing this run directory{}; \
                         wait for it to finish, or delete the lock file if that process no \
                         longer exists (this file system has no flock: {why})",
                        path.display(),
                        h.describe(),
                        if h.stale {
                            " (that PID is gone: pass --resume to take over)"
                        } else {
                            ""
                        }
                    ),
                    None => bail!(
                        "{}: the lock file is unreadable; delete it if no impactsweep process is \
                         writing this run directory",
                        path.display()
                    ),
                }
            }
            Flock::Failed(e) => {
                return Err(e).with_context(|| format!("locking {}", path.display()));
            }
        }
    }
    bail!("{}: could not take the lock", path.display())
}

/// With the OS lock in hand on an existing lock file: refuses when what the file names may still
/// be writing (see the module doc), or when the writer is gone but `resume` is not set.
fn check_gone(dir: &Path, path: &Path, mut file: &File, resume: bool) -> Result<()> {
    let mut text = String::new();
    let _ = file.read_to_string(&mut text);
    let Some(h) = parse_lock(&text) else {
        // Empty or cut short: its writer died before writing it.
        return Ok(());
    };
    if h.host == hostname() && !h.stale {
        return Err(refuse(
            path,
            &h.describe(),
            " (it holds no OS lock on the file: an older impactsweep, or a lock file written by hand)",
        ));
    }
    if h.host != hostname()
        && let Some(local) = host_local_flock(dir)
    {
        bail!(
            "{}: locked by {}; on this file system ({local}) the OS lock does not reach other \
             hosts, so whether that process still runs is unknown: delete the lock file once it \
             is gone",
            path.display(),
            h.describe()
        );
    }
    if !resume {
        bail!(
            "{}: left by {}, which is gone: pass --resume to take over",
            path.display(),
            h.describe()
        );
    }
    Ok(())
}

/// Writes `PID HOST START` into a lock file this process holds.
fn hold(path: PathBuf, mut file: File, mode: LockMode) -> Result<RunLock> {
    let pid = std::process::id();
    let start = process_start(pid).unwrap_or_else(|| "-".into());
    file.set_len(0)
        .and_then(|()| file.seek(SeekFrom::Start(0)).map(|_| ()))
        .and_then(|()| writeln!(file, "{pid} {} {start}", hostname()))
        .and_then(|()| file.sync_all())
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(RunLock {
        path,
        file: Some(file),
        mode,
    })
}

fn remove_if_present(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("removing {}", path.display()))
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOUNTS: &str = "\
22 1 8:1 / / rw,relatime shared:1 - ext4 /dev/sda1 rw
40 22 0:40 / /scratch rw,relatime shared:20 - nfs4 fs:/scratch rw,vers=4.2,local_lock=none,addr=10.0.0.1
41 22 0:41 / /home rw,relatime - nfs fs:/home rw,vers=3,local_lock=all
42 22 0:42 / /lus rw - lustre mgs@tcp:/lus rw,localflock
43 22 0:43 / /lus2 rw - lustre mgs@tcp:/lus2 rw,flock
";

    #[test]
    fn flock_scope_follows_the_mount_options() {
        let at = |p: &str| host_local_flock_in(MOUNTS, Path::new(p));
        assert_eq!(at("/tmp/x"), None);
        assert_eq!(at("/scratch/out/run"), None);
        assert_eq!(
            at("/home/me/out").as_deref(),
            Some("nfs mounted with local_lock")
        );
        assert_eq!(
            at("/lus/out").as_deref(),
            Some("lustre mounted with localflock")
        );
        assert_eq!(at("/lus2/out"), None);
    }

    #[test]
    fn a_reused_pid_is_stale() {
        let me = std::process::id();
        let host = hostname();
        let start = process_start(me).unwrap();
        assert!(!parse_lock(&format!("{me} {host} {start}")).unwrap().stale);
        assert!(!parse_lock(&format!("{me} {host}")).unwrap().stale);
        assert!(parse_lock(&format!("{me} {host} x:1")).unwrap().stale);
        assert!(!parse_lock(&format!("{me} elsewhere x:1")).unwrap().stale);
        assert_eq!(parse_lock("garbage"), None);
    }

    #[test]
    fn lock_names_give_their_split() {
        assert_eq!(lock_shard(".lock"), Some((0, 1)));
        assert_eq!(lock_shard(".lock-shard-3-of-16"), Some((3, 16)));
        assert_eq!(lock_shard(".manifest.lock"), None);
        assert_eq!(lock_shard(".lock-shard-x-of-2"), None);
    }

    #[test]
    fn the_os_lock_refuses_a_second_writer_and_is_released_on_drop() {
        let tmp = tempfile::tempdir().unwrap();
        let a = acquire_lock(tmp.path(), (0, 1), false).unwrap();
        assert_eq!(a.mode, LockMode::Os);
        let e = acquire_lock(tmp.path(), (0, 1), true).unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("PID {} on host", std::process::id())),
            "{e}"
        );
        drop(a);
        assert!(!lock_path(tmp.path(), (0, 1)).exists());
        let b = acquire_lock(tmp.path(), (0, 1), false).unwrap();
        drop(b);
    }
}
