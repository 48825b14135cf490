//! The engine: this shard's pending chunks through the simulate → write pipeline (see the
//! module doc of [`crate::sweep`]).

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;

use super::audit::{audit_points, run_audit};
use super::journal;
use super::lock::{acquire_lock, lock_path};
use crate::accuracy::Audit;
use crate::error::InputError;
use crate::plan::{Plan, RunSpec};
use crate::sim::{NoProbe, Record, simulate};
use crate::store::{self, ChunkEntry, Manifest, RunRow, read_manifest};
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
    check_options(opts)?;

    // 1. The directory: fresh, resumed, or joined by a sibling shard.
    let (study, fresh_dir) = open_dir(study, &dir, opts)?;
    let plan = Plan::new(&study);
    let mine: Vec<u64> = shard_chunks(plan.n_chunks(), opts.shard).collect();
    let _lock = claim_dir(&plan, &dir, opts, &mine, fresh_dir)?;
    let fresh = Manifest::new(&plan, study.run.chunk_points);
    journal::record_shard(&dir, &fresh, &format!("{}/{}", opts.shard.0, opts.shard.1))?;

    // 2. What is already done.
    let (mut pending, kept) = find_done(&plan, &dir, &mine, &fresh)?;
    if let Some(limit) = opts.stop_after {
        pending.truncate(limit as usize);
    }

    // 3. The pipeline: write chunk k while simulating chunk k + 1.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .context("starting the thread pool")?;
    let (outcomes, written) = pool.install(|| write_chunks(&plan, &dir, &pending, opts, &fresh))?;
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
    let audit = if k_audit > 0 && opts.shard.0 == 0 {
        Some(pool.install(|| audit_once(&plan, &dir, &fresh, k_audit))?)
    } else {
        None
    };

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

/// Refuses impossible options (exit 2).
fn check_options(opts: &SweepOptions) -> Result<()> {
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
    Ok(())
}

/// Checks what `dir` already holds against the study and the options: the same study text, a
/// dataset this build reads, the same chunk size. Returns the study with its chunk size settled
/// and whether the directory holds no study yet.
fn open_dir(study: &Study, dir: &Path, opts: &SweepOptions) -> Result<(Study, bool)> {
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
    let existing = read_manifest(dir)?;
    if let Some(m) = &existing {
        m.check_version(dir)?;
    }
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
    Ok((study, existing_study.is_none()))
}

/// Makes `dir` this shard's: refuses a non-empty directory without `--resume` (a sharded run
/// may join one its siblings created), takes the shard's lock and writes `study.toml` when the
/// directory holds none.
fn claim_dir(
    plan: &Plan,
    dir: &Path,
    opts: &SweepOptions,
    mine: &[u64],
    fresh_dir: bool,
) -> Result<super::lock::RunLock> {
    if !opts.resume && non_empty(dir) {
        let own_part = mine.iter().any(|&k| store::part_path(dir, k).exists());
        if opts.shard.1 <= 1 || own_part || lock_path(dir, opts.shard).exists() {
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
    let lock = acquire_lock(dir, opts.shard, opts.resume)?;
    if fresh_dir {
        store::write_shared(&dir.join("study.toml"), plan.study.source.as_bytes())?;
    }
    Ok(lock)
}

/// This shard's chunks that are already done, and those still to run. A chunk is done when its
/// part matches the manifest, or is a readable Parquet file with the chunk's rows (count and
/// point ids; then recorded). Anything else is removed and redone.
fn find_done(plan: &Plan, dir: &Path, mine: &[u64], fresh: &Manifest) -> Result<(Vec<u64>, u64)> {
    store::remove_dead_temp_files(dir)?;
    let manifest = read_manifest(dir)?.unwrap_or(fresh.clone());
    let mut pending = Vec::new();
    let mut kept = 0;
    for &k in mine {
        let path = store::part_path(dir, k);
        let tmp = store::tmp_path(&path);
        if tmp.exists() {
            std::fs::remove_file(&tmp).with_context(|| format!("removing {}", tmp.display()))?;
        }
        if !path.exists() {
            pending.push(k);
            continue;
        }
        let want_rows = chunk_rows(plan, k);
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
                journal::record_chunk(dir, fresh, entry)?;
                kept += 1;
            }
            _ => {
                std::fs::remove_file(&path)
                    .with_context(|| format!("removing {}", path.display()))?;
                pending.push(k);
            }
        }
    }
    Ok((pending, kept))
}

/// Simulates and writes the `pending` chunks (on the current rayon pool), chunk `k` written
/// while `k + 1` is simulated; stops early when a stop is requested. Returns the outcome counts
/// of the runs written and the number of chunks written.
fn write_chunks(
    plan: &Plan,
    dir: &Path,
    pending: &[u64],
    opts: &SweepOptions,
    fresh: &Manifest,
) -> Result<(BTreeMap<String, u64>, u64)> {
    let study = plan.study;
    let pending_runs: u64 = pending.iter().map(|&k| chunk_rows(plan, k)).sum();
    let pb = progress_bar(opts.progress, pending_runs);
    let mut outcomes = BTreeMap::new();
    let mut written = 0u64;
    let write = |k: u64, rows: Vec<RunRow>| -> Result<BTreeMap<String, u64>> {
        let info = store::write_part(
            &store::part_path(dir, k),
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
        journal::record_chunk(dir, fresh, entry)?;
        Ok(counts)
    };
    let mut prev: Option<(u64, Vec<RunRow>)> = None;
    for &k in pending {
        if stop_requested() {
            break;
        }
        let (done, rows) = rayon::join(
            || prev.take().map(|(pk, rows)| write(pk, rows)).transpose(),
            || simulate_chunk(plan, k, pb.as_ref()),
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
    if let Some(pb) = &pb {
        pb.finish_and_clear();
    }
    Ok((outcomes, written))
}

/// The audit of `k` points: the manifest's when it audited the same points, else run (on the
/// current rayon pool) and recorded.
fn audit_once(plan: &Plan, dir: &Path, fresh: &Manifest, k: u64) -> Result<Audit> {
    let have = read_manifest(dir)?.and_then(|m| m.audit);
    let want_points = audit_points(plan.study.seed, plan.n_points(), k);
    Ok(match have {
        Some(a) if a.points == want_points => a,
        _ => {
            let a = run_audit(plan, &want_points);
            journal::record_audit(dir, fresh, a.clone())?;
            a
        }
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
