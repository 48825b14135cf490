//! The engine: this shard's pending chunks through the simulate → write pipeline (see the
//! module doc of [`crate::sweep`]).

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::audit::{audit_points, run_audit};
use super::journal::{self, Entry, Journal};
use super::lock::LockMode;
use super::options::{SweepOptions, shard_chunks};
use super::rundir;
use super::simulate::{ChunkRows, SceneRun};
use crate::accuracy::Audit;
use crate::error::InputError;
use crate::plan::Plan;
use crate::sim::random::RealizationRecord;
use crate::sim::{HarmonicRecord, Record, Scene};
use crate::store::{self, Checksum, ChunkEntry, Manifest, RunRow, StoredRecord};
use crate::study::{Study, whole_curves};

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
    /// Chunks of this shard found damaged or missing (though recorded) and run again (they are
    /// among [`SweepSummary::chunks_written`]).
    pub chunks_repaired: u64,
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
            "{name}: {} runs ({}) in {secs:.2} s, {rate:.0} runs/s; {} chunks written{}, {} kept → {}",
            self.runs,
            if outcomes.is_empty() {
                "none".to_string()
            } else {
                outcomes.join(", ")
            },
            self.chunks_written,
            if self.chunks_repaired > 0 {
                format!(" ({} damaged or missing, repaired)", self.chunks_repaired)
            } else {
                String::new()
            },
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

/// Withdraws a stop request, so that the next sweep in this process runs: for a long-lived
/// process (the Python package) that stopped one sweep and resumes it. The command line exits
/// instead.
pub fn clear_stop() {
    STOP.store(false, std::sync::atomic::Ordering::SeqCst);
}

/// Whether a stop was requested.
pub fn stop_requested() -> bool {
    STOP.load(std::sync::atomic::Ordering::SeqCst)
}

fn outcome_counts<R: StoredRecord>(rows: &[RunRow<R>]) -> BTreeMap<String, u64> {
    let mut counts = BTreeMap::new();
    for r in rows {
        *counts
            .entry(r.record.outcome().name().to_string())
            .or_default() += 1;
    }
    counts
}

/// The dataset's sizes as the manifest records them, with `chunk_points` the run directory's.
pub fn sizes(plan: &Plan, chunk_points: u64) -> crate::store::manifest::Sizes {
    crate::store::manifest::Sizes {
        n_points: plan.n_points(),
        n_cases: plan.n_cases(),
        n_runs: plan.n_runs(),
        chunk_points,
        chunk_cases: (plan.blocks() > 1).then(|| plan.chunk_cases()),
        n_chunks: plan.n_chunks(),
    }
}

/// Rows chunk `k` must have.
pub fn chunk_rows(plan: &Plan, k: u64) -> u64 {
    let r = plan.chunk_runs(k);
    r.end - r.start
}

/// How often the engine syncs its file system while writing: part files and journal lines are
/// written without an `fsync` each (3 ms and 0.7 ms here: more than a small chunk takes to
/// simulate) and made durable together, at most this long after they were written.
pub const SYNC_EVERY: Duration = Duration::from_secs(1);

/// Runs (or resumes) one study into `out_root/<name>/`.
pub fn run_study(study: &Study, out_root: &Path, opts: &SweepOptions) -> Result<SweepSummary> {
    let start = Instant::now();
    let dir = run_dir(out_root, study);
    check_options(opts)?;
    check_scene_options(study, opts)?;

    // 1. The directory: fresh, resumed, or joined by a sibling shard.
    let (study, fresh_dir) = rundir::open(study, &dir, opts)?;
    let plan = Plan::new(&study);
    let mine: Vec<u64> = shard_chunks(plan.n_chunks(), opts.shard).collect();
    let lock = rundir::claim(&plan, &dir, opts, &mine, fresh_dir)?;
    if let LockMode::PidFile(why) = &lock.mode {
        warn(&format!(
            "{}: this file system refuses flock ({why}): the shard's lock is its lock file \
             alone; should this host crash, delete the lock file by hand (see docs/cluster.md)",
            dir.display()
        ));
    }
    let (fresh, mut journal) = open_journal(&study, &plan, &dir, opts)?;

    // 2. What is already done.
    let ledger = journal::load(&dir, &fresh)?;
    let done = rundir::find_done(&plan, &dir, &mine, &ledger, &mut journal)?;
    report_damage(&dir, &done.damaged);
    let mut pending = done.pending;
    if let Some(limit) = opts.stop_after {
        pending.truncate(limit as usize);
    }

    // 3. The pipeline: write chunk k while simulating chunk k + 1, the scene's records.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .context("starting the thread pool")?;
    let algorithm = ledger.manifest.algorithm();
    let (outcomes, written) = pool
        .install(|| write_scene(&plan, &dir, &pending, opts, algorithm, &mut journal))
        .with_context(|| {
            format!(
                "the sweep stopped; every chunk written so far is kept: once the cause below is \
             fixed (space freed, the directory writable), `{}` continues it",
                super::status::resume_command(&dir)
            )
        })?;
    let kept = done.kept;
    if stop_requested() {
        finish(&dir, &fresh, journal)?;
        drop(lock);
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
        Some(pool.install(|| audit_once(&plan, &ledger.manifest, k_audit, &mut journal))?)
    } else {
        None
    };
    finish(&dir, &fresh, journal)?;
    drop(lock);

    let chunks_left = (mine.len() as u64).saturating_sub(kept + written);
    Ok(SweepSummary {
        dir,
        runs: outcomes.values().sum(),
        chunks_written: written,
        chunks_kept: kept,
        chunks_repaired: done.damaged.len() as u64,
        chunks_left,
        outcomes,
        wall: start.elapsed(),
        audit,
    })
}

/// The run's manifest as this study and plan make it, checked against (or rebuilding) the one
/// on disk, and this shard's journal opened with its first line.
fn open_journal(
    study: &Study,
    plan: &Plan,
    dir: &Path,
    opts: &SweepOptions,
) -> Result<(Manifest, Journal)> {
    let fresh = Manifest::new(
        &study.name,
        &study.source,
        study.seed,
        sizes(plan, study.run.chunk_points),
    );
    if let Some(problem) = journal::start(dir, &fresh)? {
        warn(&format!(
            "{}: manifest.json {problem}; rebuilt from the journals and the part files (each \
             part is verified)",
            dir.display()
        ));
    }
    let mut journal = Journal::open(dir, opts.shard)?;
    journal.append(&Entry::Shard {
        shard: format!("{}/{}", opts.shard.0, opts.shard.1),
    })?;
    Ok((fresh, journal))
}

/// [`write_chunks`] with the study's scene's records.
fn write_scene(
    plan: &Plan,
    dir: &Path,
    pending: &[u64],
    opts: &SweepOptions,
    algorithm: Checksum,
    journal: &mut Journal,
) -> Result<(BTreeMap<String, u64>, u64)> {
    match plan.study.scene {
        Scene::Free => write_chunks::<Record>(plan, dir, pending, opts, algorithm, journal),
        Scene::Harmonic(_) => {
            write_chunks::<HarmonicRecord>(plan, dir, pending, opts, algorithm, journal)
        }
        Scene::Random(_) => {
            write_chunks::<RealizationRecord>(plan, dir, pending, opts, algorithm, journal)
        }
    }
}

/// A warning on stderr (the run goes on).
fn warn(msg: &str) {
    eprintln!("warning: {msg}");
}

/// Says which chunks were found damaged and are run again.
fn report_damage(dir: &Path, damaged: &[(u64, String)]) {
    const SHOWN: usize = 10;
    for (k, why) in damaged.iter().take(SHOWN) {
        warn(&format!(
            "{}: {why}; chunk {k} is run again",
            store::part_path(dir, *k).display()
        ));
    }
    if damaged.len() > SHOWN {
        let ids: Vec<u64> = damaged.iter().map(|d| d.0).collect();
        warn(&format!(
            "{} damaged or missing chunks in all, run again: {}",
            damaged.len(),
            super::ranges(&ids)
        ));
    }
}

/// The end of a shard's run: its writes synced, its journal folded into the manifest.
fn finish(dir: &Path, fresh: &Manifest, journal: Journal) -> Result<()> {
    store::sync_file_system(dir)?;
    journal::fold(dir, fresh, journal)
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

/// Refuses options a harmonic, random or record study cannot take (exit 2): a chunk size that
/// would cut a frequency-response curve (the reducer streams whole curves), and the audit (free
/// decay only).
fn check_scene_options(study: &Study, opts: &SweepOptions) -> Result<()> {
    if let Scene::Free = study.scene {
        return Ok(());
    }
    if let (Some(c), Some(axis)) = (opts.chunk_points, study.frequency_axis())
        && let Some(msg) = whole_curves(c, axis)
    {
        return Err(InputError::new(format!("--chunk-points {c}: {msg}")).into());
    }
    if let Some(k) = opts.audit
        && k > 0
    {
        return Err(InputError::new(format!(
            "--audit {k}: the accuracy audit re-runs free-decay runs; a {} study has none",
            study.scene.name()
        ))
        .into());
    }
    Ok(())
}

/// Simulates and writes the `pending` chunks (on the current rayon pool), chunk `k` written
/// while `k + 1` is simulated; stops early when a stop is requested. Each part's checksums are
/// journaled before its files are renamed into place (a `writing` line), and the part is recorded
/// once complete (a `chunk` line); the file system is synced every [`SYNC_EVERY`]. Returns the
/// outcome counts of the runs written and the number of chunks written.
fn write_chunks<R: SceneRun>(
    plan: &Plan,
    dir: &Path,
    pending: &[u64],
    opts: &SweepOptions,
    algorithm: Checksum,
    journal: &mut Journal,
) -> Result<(BTreeMap<String, u64>, u64)> {
    let study = plan.study;
    let pending_runs: u64 = pending.iter().map(|&k| chunk_rows(plan, k)).sum();
    let pb = progress_bar(opts.progress, pending_runs);
    let mut outcomes = BTreeMap::new();
    let mut written = 0u64;
    let mut last_sync = Instant::now();
    let mut write = |k: u64, chunk: ChunkRows<R>| -> Result<BTreeMap<String, u64>> {
        let rows = chunk.rows;
        let info = store::write_part(
            dir,
            k,
            &rows,
            chunk.attractors.as_deref(),
            &study.source,
            &study.solver,
            study.several_units(),
            algorithm,
            |info| journal.append(&Entry::Writing(info.writing(k))),
        )?;
        let counts = outcome_counts(&rows);
        journal.append(&Entry::Chunk(ChunkEntry {
            chunk: k,
            rows: info.rows,
            checksum: info.checksum,
            outcomes: counts.clone(),
            attractors: info.attractors,
        }))?;
        if last_sync.elapsed() >= SYNC_EVERY {
            store::sync_file_system(dir)?;
            last_sync = Instant::now();
        }
        Ok(counts)
    };
    let mut prev: Option<(u64, ChunkRows<R>)> = None;
    for &k in pending {
        if stop_requested() {
            break;
        }
        let (done, rows) = rayon::join(
            || prev.take().map(|(pk, rows)| write(pk, rows)).transpose(),
            || R::simulate_chunk(plan, k, pb.as_ref()),
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

/// The audit of `k` points: the directory's when it audited the same points, else run (on the
/// current rayon pool) and recorded.
fn audit_once(plan: &Plan, recorded: &Manifest, k: u64, journal: &mut Journal) -> Result<Audit> {
    let want_points = audit_points(plan.study.seed, plan.n_points(), k);
    Ok(match &recorded.audit {
        Some(a) if a.points == want_points => a.clone(),
        _ => {
            let a = run_audit(plan, &want_points);
            journal.append(&Entry::Audit { audit: a.clone() })?;
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
