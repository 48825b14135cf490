//! The sweep engine: plan → simulate → store, in parallel, resumable, sharded.
//!
//! A study's runs are cut into chunks ([`crate::plan`]: chunk `k` = a range of design points with
//! all their cases, in `point_id` order); each chunk becomes one Parquet part file
//! ([`crate::store`]). The engine processes this shard's pending chunks one after another as a
//! two-stage pipeline on a local rayon pool: while chunk `k` is encoded and written, chunk `k + 1`
//! is simulated, its runs spread over every thread by work stealing (`rayon::join` of the write
//! with a `par_iter` over the runs). So
//!
//! * every thread is busy until the last run (no tail of one slow chunk on one thread);
//! * at most two chunks are in memory (the one being written, the one being simulated), whatever
//!   the grid size;
//! * each run is a pure function of the study and its index (its noise stream is
//!   [`Plan::noise_stream`]), and `collect` keeps `point_id` order, so a part file's bytes do not
//!   depend on the thread count, the shard split, or an interruption.
//!
//! # The run directory `OUT/<name>/`
//!
//! * `study.toml`: the study text; a run directory holds one study and `--resume` refuses a
//!   different one.
//! * `points/part-NNNNNN.parquet`: written as `*.tmp`, then renamed (see [`store::write_part`]).
//!   **The part files are the source of truth**: a part file that is a readable Parquet file with
//!   the chunk's rows (their count and point ids) is a finished chunk.
//! * `manifest.json`: a summary ([`Manifest`]): tool and schema version, sizes, and per finished
//!   chunk its row count, outcome counts and checksum (64-bit FNV-1a of the file's bytes, hex).
//!   It is rewritten (temp file + rename) after every chunk while holding an exclusive `flock`
//!   on `.manifest.lock`: read, merge, write. So several shards may share one directory (Slurm
//!   array tasks): none loses another's entries. A crash between a part's rename and the
//!   manifest update only leaves a part the manifest does not list yet; `--resume` verifies it
//!   and adds it.
//! * `.lock` (unsharded) or `.lock-shard-I-of-N`: the writer's `PID HOSTNAME`, created
//!   exclusively and removed at the end. A second writer for the same shard is refused with the
//!   lock file's path and PID. A lock from this host whose PID no longer exists (`/proc/PID`) is
//!   stale: `--resume` removes it.
//!
//! Without `--resume`, an unsharded run refuses an existing non-empty directory (exit 2); a
//! sharded run joins a directory that holds the same study and nothing of its own shard (its
//! sibling shards may have created it), and refuses otherwise.
//!
//! # Accuracy audit
//!
//! With `audit = K > 0`, shard 0 re-runs the ideal case of `K` design points chosen from the study
//! seed with `exact` at `tol = 1e-14` and records the chosen solver's relative error in `xmax`,
//! `t1` and `di` (max and median) and how many runs changed outcome or impact count
//! ([`Audit`], the manifest's `"audit"`).

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::InputError;
use crate::plan::{Plan, RunSpec};
use crate::sim::noise::mix64;
use crate::sim::{NoProbe, Outcome, Record, SolverKind, SolverSettings, simulate};
use crate::store::{self, RunRow};
use crate::study::Study;

/// How to run a study.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Worker threads; `None` means all cores.
    pub threads: Option<usize>,
    /// `(i, n)`: run the chunks `k` with `k % n == i`. `(0, 1)` is the whole study.
    pub shard: (u64, u64),
    /// Continue an existing run directory.
    pub resume: bool,
    /// Show a progress bar (only drawn when stderr is a terminal).
    pub progress: bool,
    /// Design points per chunk; `None`: the existing manifest's, else `[run].chunk_points`.
    pub chunk_points: Option<u64>,
    /// Points to audit; `None`: `[run].audit`.
    pub audit: Option<u64>,
    /// Stop after this many chunks have been written (to test interruptions). `None`: all.
    pub stop_after: Option<u64>,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            threads: None,
            shard: (0, 1),
            resume: false,
            progress: false,
            chunk_points: None,
            audit: None,
            stop_after: None,
        }
    }
}

/// What one call of [`run_study`] did.
#[derive(Clone, Debug)]
pub struct SweepSummary {
    pub dir: PathBuf,
    /// Runs simulated by this call.
    pub runs: u64,
    /// Chunks written by this call.
    pub chunks_written: u64,
    /// Chunks of this shard found finished and kept.
    pub chunks_kept: u64,
    /// Chunks of this shard still missing (non-zero only with `stop_after`).
    pub chunks_left: u64,
    /// Outcome counts of the runs simulated by this call.
    pub outcomes: BTreeMap<String, u64>,
    pub wall: Duration,
    pub audit: Option<Audit>,
}

impl SweepSummary {
    /// The one-line summary printed at the end of a run.
    pub fn line(&self, name: &str) -> String {
        let outcomes: Vec<String> = self
            .outcomes
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect();
        let secs = self.wall.as_secs_f64();
        let rate = if secs > 0.0 {
            self.runs as f64 / secs
        } else {
            0.0
        };
        let mut line = format!(
            "{name}: {} runs ({}) in {secs:.2} s, {rate:.0} runs/s; {} chunks written, {} kept → {}",
            self.runs,
            if outcomes.is_empty() {
                "none".to_string()
            } else {
                outcomes.join(", ")
            },
            self.chunks_written,
            self.chunks_kept,
            self.dir.display()
        );
        if let Some(a) = &self.audit {
            line.push_str(&format!(
                "; audit of {} points ({} {} = {:e} against exact): max relative error \
                 xmax {:.1e}, t1 {:.1e}, di {:.1e}",
                a.points.len(),
                a.solver,
                a.knob,
                a.knob_value,
                a.xmax.max,
                a.t1.max,
                a.di.max
            ));
        }
        line
    }
}

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

/// Relative error statistics over the audited runs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorStats {
    /// Runs where both values were finite.
    pub n: u64,
    pub max: f64,
    pub median: f64,
}

/// The realised error of the study's solver against `exact` at `tol = 1e-14`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Audit {
    /// The audited design points (their ideal case).
    pub points: Vec<u64>,
    /// The study's solver, its accuracy knob (`tol`, `h` or `rtol`) and that knob's value.
    pub solver: String,
    pub knob: String,
    pub knob_value: f64,
    /// The study's event tolerance.
    pub tol: f64,
    /// The reference.
    pub reference: String,
    /// `|a - b| / |b|` (`|a - b|` when `b = 0`) over the runs where both are finite.
    pub xmax: ErrorStats,
    pub t1: ErrorStats,
    pub di: ErrorStats,
    pub outcome_changed: u64,
    pub impacts_changed: u64,
}

/// The tolerance of the audit's reference solver.
pub const AUDIT_TOL: f64 = 1e-14;

const CHECKSUM_DOC: &str = "fnv1a-64 of the part file's bytes (hex)";

/// Simulates one run: the study's solver and request, the run's noise stream when its case has
/// noise (no random number is drawn otherwise).
pub fn simulate_run(plan: &Plan, run: &RunSpec) -> Record {
    let study = plan.study;
    match (study.noise.as_ref(), plan.noise_stream(run)) {
        (Some(ns), Some(mut stream)) => simulate(
            &run.system,
            &study.solver,
            &study.request,
            Some((ns, &mut stream)),
            &mut NoProbe,
        ),
        _ => simulate(
            &run.system,
            &study.solver,
            &study.request,
            None,
            &mut NoProbe,
        ),
    }
}

/// The stored row of a run.
pub fn run_row(plan: &Plan, run: &RunSpec) -> RunRow {
    RunRow {
        point_id: run.point_id,
        point: run.point,
        case: run.case,
        ideal: run.spec.ideal,
        dm: run.spec.dm,
        dd: run.spec.dd,
        noise_seed: run.spec.noise_seed,
        system: run.system,
        solver: plan.study.solver.kind.name().to_string(),
        tol: plan.study.solver.tol,
        record: simulate_run(plan, run),
    }
}

/// Simulates chunk `k` (in parallel over its runs, on the current rayon pool), in `point_id`
/// order.
pub fn simulate_chunk(plan: &Plan, k: u64, progress: Option<&ProgressBar>) -> Vec<RunRow> {
    let points = plan.chunk_points(k);
    let n_cases = plan.n_cases();
    (points.start * n_cases..points.end * n_cases)
        .into_par_iter()
        .map(|id| {
            let run = plan.run(id / n_cases, (id % n_cases) as u32);
            let row = run_row(plan, &run);
            if let Some(pb) = progress {
                pb.inc(1);
            }
            row
        })
        .collect()
}

/// The run directory of a study.
pub fn run_dir(out_root: &Path, study: &Study) -> PathBuf {
    out_root.join(&study.name)
}

/// The lock file of a shard.
pub fn lock_path(dir: &Path, shard: (u64, u64)) -> PathBuf {
    if shard.1 <= 1 {
        dir.join(".lock")
    } else {
        dir.join(format!(".lock-shard-{}-of-{}", shard.0, shard.1))
    }
}

/// Set when an interrupt asks running sweeps to stop.
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Asks running sweeps to stop: each finishes and writes the chunks in hand, releases its lock
/// and returns [`crate::error::Interrupted`]. Called by the command's Ctrl-C/SIGTERM handler; the
/// library installs no handler itself.
pub fn request_stop() {
    STOP.store(true, std::sync::atomic::Ordering::SeqCst);
}

/// Whether a stop was requested.
pub fn stop_requested() -> bool {
    STOP.load(std::sync::atomic::Ordering::SeqCst)
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

/// Reads `dir/manifest.json`, `None` when absent.
pub fn read_manifest(dir: &Path) -> Result<Option<Manifest>> {
    let path = dir.join("manifest.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .with_context(|| format!("{}: not a valid manifest", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
    }
}

/// Writes a file atomically (a temp name unique to this process, then rename).
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp.{}", std::process::id()));
    let tmp = path.with_file_name(name);
    std::fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path)
        .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
}

impl Manifest {
    fn new(plan: &Plan, chunk_points: u64) -> Manifest {
        let study = plan.study;
        Manifest {
            tool: "impactsweep".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            schema_version: store::SCHEMA_VERSION,
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

    fn recount(&mut self) {
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

    fn upsert(&mut self, entry: ChunkEntry) {
        match self.chunks.binary_search_by_key(&entry.chunk, |c| c.chunk) {
            Ok(i) => self.chunks[i] = entry,
            Err(i) => self.chunks.insert(i, entry),
        }
    }
}

/// Read-merge-write of the manifest under the directory's manifest lock.
fn update_manifest(dir: &Path, fresh: &Manifest, f: impl FnOnce(&mut Manifest)) -> Result<()> {
    let _guard = ManifestLock::take(dir)?;
    let mut m = read_manifest(dir)?.unwrap_or_else(|| fresh.clone());
    f(&mut m);
    m.recount();
    let text = serde_json::to_string_pretty(&m)? + "\n";
    write_atomic(&dir.join("manifest.json"), text.as_bytes())
}

/// Removes `*.tmp.PID` files (from [`write_atomic`]) whose writer no longer runs on this host.
fn remove_dead_temp_files(dir: &Path) -> Result<()> {
    for entry in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let path = entry?.path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let Some((_, pid)) = name.rsplit_once(".tmp.") else {
            continue;
        };
        if pid.parse::<u32>().is_ok() && !Path::new(&format!("/proc/{pid}")).exists() {
            std::fs::remove_file(&path).with_context(|| format!("removing {}", path.display()))?;
        }
    }
    Ok(())
}

fn outcome_counts(rows: &[RunRow]) -> BTreeMap<String, u64> {
    let mut counts = BTreeMap::new();
    for r in rows {
        *counts
            .entry(r.record.outcome.name().to_string())
            .or_default() += 1;
    }
    counts
}

/// Whether a directory exists and holds anything.
fn non_empty(dir: &Path) -> bool {
    std::fs::read_dir(dir)
        .map(|mut d| d.next().is_some())
        .unwrap_or(false)
}

/// The chunks of shard `(i, n)`.
pub fn shard_chunks(n_chunks: u64, shard: (u64, u64)) -> impl Iterator<Item = u64> {
    (shard.0..n_chunks).step_by(shard.1.max(1) as usize)
}

/// Rows chunk `k` must have.
pub fn chunk_rows(plan: &Plan, k: u64) -> u64 {
    let p = plan.chunk_points(k);
    (p.end - p.start) * plan.n_cases()
}

/// Runs (or resumes) one study into `out_root/<name>/`.
pub fn run_study(study: &Study, out_root: &Path, opts: &SweepOptions) -> Result<SweepSummary> {
    let start = Instant::now();
    let dir = run_dir(out_root, study);
    let (si, sn) = opts.shard;
    if sn == 0 || si >= sn {
        return Err(
            InputError::new(format!("--shard {si}/{sn}: expected I/N with 0 <= I < N")).into(),
        );
    }
    if opts.threads == Some(0) {
        return Err(InputError::new("--threads 0: must be at least 1").into());
    }
    if opts.chunk_points == Some(0) {
        return Err(InputError::new("--chunk-points 0: must be at least 1").into());
    }

    // 1. The directory: fresh, resumed, or joined by a sibling shard.
    let existing_study = std::fs::read_to_string(dir.join("study.toml")).ok();
    if let Some(text) = &existing_study
        && *text != study.source
    {
        return Err(InputError::new(format!(
            "{}: holds a different study (its study.toml differs from {}); choose another --out",
            dir.display(),
            study.path.display()
        ))
        .into());
    }
    let existing = read_manifest(&dir)?;
    let chunk_points = match (opts.chunk_points, &existing) {
        (Some(c), Some(m)) if m.chunk_points != c => {
            return Err(InputError::new(format!(
                "--chunk-points {c}: {} was written with chunk_points = {}; resume with that \
                 value (or without --chunk-points)",
                dir.display(),
                m.chunk_points
            ))
            .into());
        }
        (Some(c), _) => c,
        (None, Some(m)) => m.chunk_points,
        (None, None) => study.run.chunk_points.max(1),
    };
    let mut study = study.clone();
    study.run.chunk_points = chunk_points;
    let plan = Plan::new(&study);
    let n_chunks = plan.n_chunks();
    let mine: Vec<u64> = shard_chunks(n_chunks, opts.shard).collect();

    if !opts.resume && non_empty(&dir) {
        let own_part = mine.iter().any(|&k| store::part_path(&dir, k).exists());
        if sn <= 1 || own_part || lock_path(&dir, opts.shard).exists() {
            return Err(InputError::new(format!(
                "{}: the output directory exists and is not empty; pass --resume to continue \
                 that run, or choose another --out (nothing was overwritten)",
                dir.display()
            ))
            .into());
        }
    }
    let points_dir = dir.join("points");
    std::fs::create_dir_all(&points_dir)
        .with_context(|| format!("creating {}", points_dir.display()))?;
    let _lock = acquire_lock(&dir, opts.shard, opts.resume)?;
    if existing_study.is_none() {
        write_atomic(&dir.join("study.toml"), study.source.as_bytes())?;
    }
    let fresh = Manifest::new(&plan, chunk_points);
    let shard_name = format!("{si}/{sn}");
    update_manifest(&dir, &fresh, |m| {
        if !m.shards.contains(&shard_name) {
            m.shards.push(shard_name.clone());
            m.shards.sort();
        }
    })?;

    // 2. What is already done: a part that matches the manifest, or a readable Parquet file
    // with the chunk's rows (count and point ids; then added to the manifest). Anything else is
    // redone.
    remove_dead_temp_files(&dir)?;
    let manifest = read_manifest(&dir)?.unwrap_or(fresh.clone());
    let mut pending = Vec::new();
    let mut kept = 0;
    for &k in &mine {
        let path = store::part_path(&dir, k);
        let tmp = store::tmp_path(&path);
        if tmp.exists() {
            std::fs::remove_file(&tmp).with_context(|| format!("removing {}", tmp.display()))?;
        }
        if !path.exists() {
            pending.push(k);
            continue;
        }
        let want_rows = chunk_rows(&plan, k);
        let sum = store::checksum_file(&path)?;
        let listed = manifest
            .chunk(k)
            .is_some_and(|c| c.rows == want_rows && c.checksum == format!("{sum:016x}"));
        if listed {
            kept += 1;
            continue;
        }
        let first_id = plan.chunk_points(k).start * plan.n_cases();
        let ids_match = |rows: &[RunRow]| {
            rows.iter()
                .enumerate()
                .all(|(i, r)| r.point_id == first_id + i as u64)
        };
        match store::read_part(&path) {
            Ok(rows) if rows.len() as u64 == want_rows && ids_match(&rows) => {
                let entry = ChunkEntry {
                    chunk: k,
                    rows: want_rows,
                    checksum: format!("{sum:016x}"),
                    outcomes: outcome_counts(&rows),
                };
                update_manifest(&dir, &fresh, |m| m.upsert(entry))?;
                kept += 1;
            }
            _ => {
                std::fs::remove_file(&path)
                    .with_context(|| format!("removing {}", path.display()))?;
                pending.push(k);
            }
        }
    }
    if let Some(limit) = opts.stop_after {
        pending.truncate(limit as usize);
    }

    // 3. The pipeline: write chunk k while simulating chunk k + 1.
    let pending_runs: u64 = pending.iter().map(|&k| chunk_rows(&plan, k)).sum();
    let pb = progress_bar(opts.progress, pending_runs);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .context("starting the thread pool")?;
    let mut outcomes = BTreeMap::new();
    let mut written = 0u64;
    let write = |k: u64, rows: Vec<RunRow>| -> Result<BTreeMap<String, u64>> {
        let info = store::write_part(
            &store::part_path(&dir, k),
            &rows,
            &study.source,
            &study.solver,
        )?;
        let counts = outcome_counts(&rows);
        let entry = ChunkEntry {
            chunk: k,
            rows: info.rows,
            checksum: format!("{:016x}", info.checksum),
            outcomes: counts.clone(),
        };
        update_manifest(&dir, &fresh, |m| m.upsert(entry))?;
        Ok(counts)
    };
    pool.install(|| -> Result<()> {
        let mut prev: Option<(u64, Vec<RunRow>)> = None;
        for &k in &pending {
            if stop_requested() {
                break;
            }
            let (done, rows) = rayon::join(
                || prev.take().map(|(pk, rows)| write(pk, rows)).transpose(),
                || simulate_chunk(&plan, k, pb.as_ref()),
            );
            if let Some(counts) = done? {
                merge_counts(&mut outcomes, &counts);
                written += 1;
            }
            prev = Some((k, rows));
        }
        if let Some((pk, rows)) = prev.take() {
            merge_counts(&mut outcomes, &write(pk, rows)?);
            written += 1;
        }
        Ok(())
    })?;
    if let Some(pb) = &pb {
        pb.finish_and_clear();
    }
    if stop_requested() {
        return Err(crate::error::Interrupted {
            dir: dir.display().to_string(),
            written,
            left: (mine.len() as u64).saturating_sub(kept + written),
        }
        .into());
    }

    // 4. The audit (shard 0, once per K).
    let k_audit = opts.audit.unwrap_or(study.run.audit);
    let mut audit = None;
    if k_audit > 0 && si == 0 {
        let have = read_manifest(&dir)?.and_then(|m| m.audit);
        let want_points = audit_points(study.seed, plan.n_points(), k_audit);
        audit = match have {
            Some(a) if a.points == want_points => Some(a),
            _ => {
                let a = pool.install(|| run_audit(&plan, &want_points));
                let stored = a.clone();
                update_manifest(&dir, &fresh, |m| m.audit = Some(stored))?;
                Some(a)
            }
        };
    }

    let chunks_left = (mine.len() as u64).saturating_sub(kept + written);
    Ok(SweepSummary {
        dir,
        runs: outcomes.values().sum(),
        chunks_written: written,
        chunks_kept: kept,
        chunks_left,
        outcomes,
        wall: start.elapsed(),
        audit,
    })
}

fn merge_counts(into: &mut BTreeMap<String, u64>, from: &BTreeMap<String, u64>) {
    for (k, v) in from {
        *into.entry(k.clone()).or_default() += v;
    }
}

fn progress_bar(wanted: bool, len: u64) -> Option<ProgressBar> {
    if !wanted || !std::io::stderr().is_terminal() {
        return None;
    }
    let pb = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template(
        "{bar:40} {human_pos}/{human_len} runs  {rate} runs/s  ETA {eta}  ({elapsed})",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .with_key(
        "rate",
        |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{:.0}", state.per_sec());
        },
    );
    pb.set_style(style);
    Some(pb)
}

/// `k` distinct design points out of `n`, chosen from the study seed alone, sorted.
pub fn audit_points(seed: u64, n: u64, k: u64) -> Vec<u64> {
    if k >= n {
        return (0..n).collect();
    }
    let key = mix64(seed ^ 0xA0D1_7A0D_17A0_D170);
    let mut chosen = std::collections::BTreeSet::new();
    let mut j = 0u64;
    while (chosen.len() as u64) < k {
        chosen.insert(mix64(key ^ mix64(j)) % n);
        j += 1;
    }
    chosen.into_iter().collect()
}

fn rel_err(a: f64, b: f64) -> Option<f64> {
    if !a.is_finite() || !b.is_finite() {
        return None;
    }
    let d = (a - b).abs();
    Some(if b == 0.0 { d } else { d / b.abs() })
}

fn stats(mut xs: Vec<f64>) -> ErrorStats {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    let median = match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => xs[n / 2],
        _ => 0.5 * (xs[n / 2 - 1] + xs[n / 2]),
    };
    ErrorStats {
        n: n as u64,
        max: xs.last().copied().unwrap_or(f64::NAN),
        median,
    }
}

/// Re-runs the ideal case of `points` with the study's solver and with `exact` at
/// [`AUDIT_TOL`], and measures the difference.
pub fn run_audit(plan: &Plan, points: &[u64]) -> Audit {
    let study = plan.study;
    let reference = SolverSettings {
        kind: SolverKind::Exact,
        tol: AUDIT_TOL,
        ..study.solver
    };
    let ideal = study.cases.iter().position(|c| c.ideal).unwrap_or(0) as u32;
    let pairs: Vec<(Record, Record)> = points
        .par_iter()
        .map(|&p| {
            let run = plan.run(p, ideal);
            let got = simulate(
                &run.system,
                &study.solver,
                &study.request,
                None,
                &mut NoProbe,
            );
            let want = simulate(&run.system, &reference, &study.request, None, &mut NoProbe);
            (got, want)
        })
        .collect();
    let errs = |f: fn(&Record) -> f64| {
        stats(
            pairs
                .iter()
                .filter_map(|(a, b)| rel_err(f(a), f(b)))
                .collect(),
        )
    };
    Audit {
        points: points.to_vec(),
        solver: study.solver.kind.name().to_string(),
        knob: study.solver.kind.knob().to_string(),
        knob_value: study.solver.knob_value(),
        tol: study.solver.tol,
        reference: format!("exact, tol = {AUDIT_TOL:e}"),
        xmax: errs(|r| r.xmax),
        t1: errs(|r| r.t1),
        di: errs(|r| r.di),
        outcome_changed: pairs.iter().filter(|(a, b)| a.outcome != b.outcome).count() as u64,
        impacts_changed: pairs.iter().filter(|(a, b)| a.impacts != b.impacts).count() as u64,
    }
}

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
}

/// Reads a run directory's state: the part files are the truth, the manifest gives the sizes.
pub fn status(dir: &Path) -> Result<Status> {
    let manifest = read_manifest(dir)?.ok_or_else(|| {
        InputError::new(format!(
            "{}: not a run directory (no manifest.json)",
            dir.display()
        ))
    })?;
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
        if name == ".lock" || name.starts_with(".lock-shard-") {
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

    #[test]
    fn shards_partition_the_chunks() {
        let mut all: Vec<u64> = (0..3).flat_map(|i| shard_chunks(10, (i, 3))).collect();
        all.sort();
        assert_eq!(all, (0..10).collect::<Vec<_>>());
        assert_eq!(shard_chunks(10, (1, 3)).collect::<Vec<_>>(), vec![1, 4, 7]);
    }

    #[test]
    fn audit_points_are_distinct_sorted_and_seeded() {
        let a = audit_points(7, 1000, 20);
        assert_eq!(a.len(), 20);
        assert!(a.windows(2).all(|w| w[0] < w[1]) && a[19] < 1000);
        assert_eq!(a, audit_points(7, 1000, 20));
        assert_ne!(a, audit_points(8, 1000, 20));
        assert_eq!(audit_points(7, 5, 20), vec![0, 1, 2, 3, 4]);
    }

    #[test]
    fn error_statistics() {
        assert_eq!(rel_err(1.1, 1.0).map(|e| (e * 1e6).round()), Some(1e5));
        assert_eq!(rel_err(0.5, 0.0), Some(0.5));
        assert_eq!(rel_err(f64::NAN, 1.0), None);
        let s = stats(vec![3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.n, s.max, s.median), (4, 10.0, 2.5));
        assert!(stats(vec![]).max.is_nan());
    }
}
