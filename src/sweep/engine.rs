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
use super::journal::{self, Entry, Journal};
use super::lock::LockMode;
use super::rundir;
use crate::accuracy::Audit;
use crate::error::InputError;
use crate::orbits::attractors::{AttractorRow, RunId};
use crate::orbits::curve::{CurveFrequency, curve_census, fill_steady, from_rest};
use crate::orbits::forced_run;
use crate::plan::{Plan, RunSpec};
use crate::sim::{ForcedRecord, Harmonic, NoProbe, Record, Scene, simulate};
use crate::store::{self, Checksum, ChunkEntry, Manifest, RunRow, StoredRecord};
use crate::study::{Study, whole_curves};

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

/// A scene's record as the engine simulates and stores it: [`Record`] for free decay,
/// [`ForcedRecord`] for the harmonic scene. The engine picks it from the study's scene.
pub trait SceneRun: StoredRecord + Send + Sync {
    /// Simulates one run of the plan.
    fn simulate(plan: &Plan, run: &RunSpec) -> Self;

    /// Simulates chunk `k` (in parallel, on the current rayon pool): its rows in `point_id`
    /// order, and the attractors of its runs when the scene takes a census. By default each run
    /// on its own ([`SceneRun::simulate`]).
    fn simulate_chunk(plan: &Plan, k: u64, progress: Option<&ProgressBar>) -> ChunkRows<Self> {
        ChunkRows {
            rows: simulate_chunk(plan, k, progress),
            attractors: None,
        }
    }
}

/// A simulated chunk: its runs, and their attractors (a harmonic study with a census).
pub struct ChunkRows<R> {
    pub rows: Vec<RunRow<R>>,
    pub attractors: Option<Vec<AttractorRow>>,
}

impl SceneRun for Record {
    fn simulate(plan: &Plan, run: &RunSpec) -> Self {
        simulate_run(plan, run)
    }
}

impl SceneRun for ForcedRecord {
    fn simulate(plan: &Plan, run: &RunSpec) -> Self {
        simulate_forced_run(plan, run)
    }

    /// With a census, each frequency-response curve (a design and a case) is one task
    /// ([`simulate_curve`]); without one, each run on its own.
    fn simulate_chunk(plan: &Plan, k: u64, progress: Option<&ProgressBar>) -> ChunkRows<Self> {
        let census = matches!(plan.study.scene, Scene::Harmonic(h) if h.starts > 0);
        if !census {
            return ChunkRows {
                rows: simulate_chunk(plan, k, progress),
                attractors: None,
            };
        }
        let n_f = plan.study.curve_points();
        let points = plan.chunk_points(k);
        let designs: Vec<u64> = (points.start / n_f..points.end.div_ceil(n_f)).collect();
        let tasks: Vec<(u64, Vec<u32>)> = designs
            .into_iter()
            .flat_map(|design| {
                same_system_cases(plan, design)
                    .into_iter()
                    .map(move |cases| (design, cases))
            })
            .collect();
        let done: Vec<(Vec<RunRow<ForcedRecord>>, Vec<AttractorRow>)> = tasks
            .into_par_iter()
            .map(|(design, cases)| {
                let out = simulate_curve(plan, design, &cases);
                if let Some(pb) = progress {
                    pb.inc(out.0.len() as u64);
                }
                out
            })
            .collect();
        let mut rows = Vec::with_capacity(done.iter().map(|d| d.0.len()).sum());
        let mut attractors = Vec::new();
        for (r, a) in done {
            rows.extend(r);
            attractors.extend(a);
        }
        rows.sort_by_key(|r| r.point_id);
        // Stable: each run's attractors stay in their census order.
        attractors.sort_by_key(|a| a.run.point_id);
        ChunkRows {
            rows,
            attractors: Some(attractors),
        }
    }
}

/// The cases of design `design` grouped by their system (a case that differs from another only
/// in its noise has the same system, and so the same census), in case order.
fn same_system_cases(plan: &Plan, design: u64) -> Vec<Vec<u32>> {
    let n_f = plan.study.curve_points();
    let mut groups: Vec<(Vec<u64>, Vec<u32>)> = Vec::new();
    for c in 0..plan.n_cases() as u32 {
        let sys = plan.run(design * n_f, c).system;
        let key: Vec<u64> = crate::model::SYSTEM_KEYS
            .iter()
            .map(|k| sys.get(k).unwrap_or(f64::NAN).to_bits())
            .collect();
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push(c),
            None => groups.push((key, vec![c])),
        }
    }
    groups.into_iter().map(|g| g.1).collect()
}

/// The frequency-response curves of a harmonic study's design `design` for `cases` (cases with
/// one system), as one task: each case's runs at every frequency from the initial state (with
/// its noise), and one census along the curve ([`curve_census`]: in frequency order, each
/// frequency seeded with its neighbours' attractors), which every case of the group shares.
/// Returns the rows and their attractors (every case's).
pub fn simulate_curve(
    plan: &Plan,
    design: u64,
    cases: &[u32],
) -> (Vec<RunRow<ForcedRecord>>, Vec<AttractorRow>) {
    let study = plan.study;
    let n_f = study.curve_points();
    let mut censuses = None;
    let mut rows = Vec::with_capacity(cases.len() * n_f as usize);
    let mut attractors = Vec::new();
    for &case in cases {
        let runs: Vec<RunSpec> = (design * n_f..(design + 1) * n_f)
            .map(|p| plan.run(p, case))
            .collect();
        let freqs: Vec<CurveFrequency> = runs.iter().map(|run| plan.curve_frequency(run)).collect();
        let targets: Vec<(Harmonic, u64)> = freqs.iter().map(|f| (f.scene, f.point)).collect();
        let sys = runs[0].system;
        let mut records = from_rest(
            &sys,
            &study.solver,
            &study.request,
            study.noise.as_ref(),
            freqs,
        );
        let cs = censuses.get_or_insert_with(|| {
            curve_census(&sys, &study.solver, study.seed, &targets, &records)
        });
        fill_steady(&mut records, cs);
        for ((run, record), census) in runs.iter().zip(records).zip(cs.iter()) {
            if let Some(c) = census {
                let id = RunId {
                    point_id: run.point_id,
                    point: run.point,
                    case: run.case,
                    ideal: run.spec.ideal,
                    r: record.r,
                    omega: record.omega,
                    F0: record.F0,
                };
                attractors.extend(AttractorRow::of_census(
                    id,
                    c,
                    std::f64::consts::TAU / record.omega,
                ));
            }
            rows.push(row_of(plan, run, record));
        }
    }
    (rows, attractors)
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

/// Simulates one run of a harmonic study ([`forced_run`]: from the study's initial state, then
/// the attractor census seeded by the study seed and the design point): the run's scene (the study's, with the design point's
/// `F0`, `omega` or `r`; the default harmonic scene if the study is a free-decay one), the study's
/// solver, the run's noise stream when its case has noise. The study has validated the scene
/// for every run ([`Harmonic::validate`]).
pub fn simulate_forced_run(plan: &Plan, run: &RunSpec) -> ForcedRecord {
    let study = plan.study;
    let scene = match run.scene {
        Scene::Harmonic(h) => h,
        Scene::Free => Harmonic::default(),
    };
    let (seed, point) = (study.seed, run.point);
    match (study.noise.as_ref(), plan.noise_stream(run)) {
        (Some(ns), Some(mut stream)) => forced_run(
            &run.system,
            &study.solver,
            &study.request,
            &scene,
            Some((ns, &mut stream)),
            &mut NoProbe,
            seed,
            point,
        ),
        _ => forced_run(
            &run.system,
            &study.solver,
            &study.request,
            &scene,
            None,
            &mut NoProbe,
            seed,
            point,
        ),
    }
}

/// The stored row of a run.
pub fn run_row<R: SceneRun>(plan: &Plan, run: &RunSpec) -> RunRow<R> {
    row_of(plan, run, R::simulate(plan, run))
}

/// The stored row of `run` with its simulated `record`.
fn row_of<R>(plan: &Plan, run: &RunSpec, record: R) -> RunRow<R> {
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
        record,
    }
}

/// Simulates chunk `k` (in parallel over its runs, on the current rayon pool), in `point_id`
/// order.
pub fn simulate_chunk<R: SceneRun>(
    plan: &Plan,
    k: u64,
    progress: Option<&ProgressBar>,
) -> Vec<RunRow<R>> {
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

/// The chunks of shard `(i, n)`.
pub fn shard_chunks(n_chunks: u64, shard: (u64, u64)) -> impl Iterator<Item = u64> {
    (shard.0..n_chunks).step_by(shard.1.max(1) as usize)
}

/// Rows chunk `k` must have.
pub fn chunk_rows(plan: &Plan, k: u64) -> u64 {
    let p = plan.chunk_points(k);
    (p.end - p.start) * plan.n_cases()
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
    let fresh = Manifest::new(&plan, study.run.chunk_points);
    if let Some(problem) = journal::start(&dir, &fresh)? {
        warn(&format!(
            "{}: manifest.json {problem}; rebuilt from the journals and the part files (each \
             part is verified)",
            dir.display()
        ));
    }
    let mut journal = Journal::open(&dir, opts.shard)?;
    journal.append(&Entry::Shard {
        shard: format!("{}/{}", opts.shard.0, opts.shard.1),
    })?;

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
        .install(|| match study.scene {
            Scene::Free => {
                write_chunks::<Record>(&plan, &dir, &pending, opts, algorithm, &mut journal)
            }
            Scene::Harmonic(_) => {
                write_chunks::<ForcedRecord>(&plan, &dir, &pending, opts, algorithm, &mut journal)
            }
        })
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

/// Refuses options a harmonic study cannot take (exit 2): a chunk size that would cut a
/// frequency-response curve (the reducer streams whole curves), and the audit (free decay only).
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
            "--audit {k}: the accuracy audit re-runs free-decay runs; a harmonic study has none"
        ))
        .into());
    }
    Ok(())
}

/// Simulates and writes the `pending` chunks (on the current rayon pool), chunk `k` written
/// while `k + 1` is simulated; stops early when a stop is requested. Each part is recorded in
/// the journal once complete; the file system is synced every [`SYNC_EVERY`]. Returns the outcome
/// counts of the runs written and the number of chunks written.
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
            algorithm,
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
