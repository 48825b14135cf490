//! `plan`, `run`, `queue` and `status`: the sweep engine's commands (issue 3). With `--reduce`,
//! `run` and `queue` reduce each study once its sweep is complete (issue 10) and rewrite the
//! output root's `index.html` after each study (issue 18); `status` on an output root lists
//! every study with its state and report, and writes `index.html` with `--html`.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::error::InputError;
use crate::report::html::index;
use crate::study::{LoadOptions, Study};
use crate::sweep::{self, SweepOptions};

/// `impactsweep run STUDY.toml... [--out DIR] [--threads N] [--shard I/N] [--resume] [--quiet]`.
#[derive(Clone, Debug, Default)]
pub struct RunArgs {
    pub studies: Vec<PathBuf>,
    pub out: PathBuf,
    pub threads: Option<usize>,
    /// `(i, n)`: this process runs the chunks `k` with `k % n == i`.
    pub shard: Option<(u64, u64)>,
    pub resume: bool,
    pub quiet: bool,
    pub allow_large: bool,
    /// Overrides `[run].chunk_points`.
    pub chunk_points: Option<u64>,
    /// Overrides `[run].audit`.
    pub audit: Option<u64>,
    /// Reduce each study once its sweep is complete.
    pub reduce: bool,
}

/// `impactsweep queue DIR`.
#[derive(Clone, Debug, Default)]
pub struct QueueArgs {
    pub dir: PathBuf,
    pub out: PathBuf,
    pub threads: Option<usize>,
    pub quiet: bool,
    /// Reduce each study once its sweep is complete (and finished ones without a report).
    pub reduce: bool,
}

/// `impactsweep status RUN_DIR [--html]`.
#[derive(Clone, Debug, Default)]
pub struct StatusArgs {
    pub dir: PathBuf,
    /// For an output root, also write `DIR/index.html`.
    pub html: bool,
}

/// Runs each study in turn into `OUT/<name>/`. Every study file is validated before the first
/// runs, so a mistake in the last one does not surface hours later.
/// Ctrl-C or SIGTERM (Slurm's stop signal) asks the sweep to stop after the chunks in hand, so
/// the lock is released and the directory resumes cleanly; a second interrupt exits at once.
fn on_interrupt_finish_the_chunk() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if sweep::stop_requested() {
                std::process::exit(crate::error::EXIT_INTERRUPTED);
            }
            sweep::request_stop();
            eprintln!(
                "\ninterrupt: finishing the chunk in hand, then stopping (interrupt again to stop at once)"
            );
        });
    });
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    on_interrupt_finish_the_chunk();
    let (si, sn) = args.shard.unwrap_or((0, 1));
    let studies = args
        .studies
        .iter()
        .map(|path| {
            Study::load_with(
                path,
                LoadOptions {
                    allow_large: args.allow_large,
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut reductions = Reductions::default();
    for study in &studies {
        let opts = SweepOptions {
            threads: args.threads,
            shard: (si, sn),
            resume: args.resume,
            progress: !args.quiet,
            chunk_points: args.chunk_points,
            audit: args.audit,
            stop_after: None,
        };
        let summary = sweep::run_study(study, &args.out, &opts)?;
        if !args.quiet {
            eprintln!("{}", summary.line(&study.name));
        }
        if args.reduce {
            reductions.reduce_if_complete(study, &sweep::run_dir(&args.out, study));
            refresh_index(&args.out);
        }
    }
    reductions.result()
}

/// Runs every `*.toml` in `DIR` in name order: finished studies are skipped, partial ones
/// resumed, new ones started.
pub fn queue(args: &QueueArgs) -> anyhow::Result<()> {
    on_interrupt_finish_the_chunk();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&args.dir)
        .with_context(|| format!("listing {}", args.dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml") && p.is_file())
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(InputError::new(format!(
            "{}: no study files (*.toml) in this directory",
            args.dir.display()
        ))
        .into());
    }
    let mut reductions = Reductions::default();
    for path in &files {
        let study = Study::load(path)?;
        let dir = sweep::run_dir(&args.out, &study);
        if let Ok(st) = sweep::status(&dir)
            && st.complete()
        {
            if !args.quiet {
                eprintln!(
                    "{}: finished ({} runs in {}), skipped",
                    study.name,
                    st.runs_done,
                    dir.display()
                );
            }
            if args.reduce && report_state(&dir) != ReportState::Current {
                reductions.reduce_if_complete(&study, &dir);
            }
            if args.reduce {
                refresh_index(&args.out);
            }
            continue;
        }
        let opts = SweepOptions {
            threads: args.threads,
            resume: true,
            progress: !args.quiet,
            ..SweepOptions::default()
        };
        let summary = sweep::run_study(&study, &args.out, &opts)?;
        if !args.quiet {
            eprintln!("{}", summary.line(&study.name));
        }
        if args.reduce {
            reductions.reduce_if_complete(&study, &dir);
            refresh_index(&args.out);
        }
    }
    reductions.result()
}

/// The reductions `--reduce` made: a failure is reported at once and counted, and the next
/// study still runs; the command fails at the end if any did.
#[derive(Default)]
struct Reductions {
    failed: Vec<String>,
}

impl Reductions {
    /// Reduces the run directory of `study` when its sweep is complete.
    fn reduce_if_complete(&mut self, study: &Study, dir: &Path) {
        match sweep::status(dir) {
            Ok(st) if st.complete() => {}
            Ok(st) => {
                eprintln!(
                    "{}: not reduced: {} of {} chunks missing (another shard still running?)",
                    study.name,
                    st.missing.len(),
                    st.manifest.n_chunks
                );
                return;
            }
            Err(e) => {
                eprintln!("error: {}: not reduced: {e:#}", study.name);
                self.failed.push(study.name.clone());
                return;
            }
        }
        let args = crate::api::reduce::ReduceArgs {
            dir: dir.to_path_buf(),
            ..Default::default()
        };
        match crate::api::reduce::reduce_dir(&args) {
            Ok((line, _)) => eprintln!(
                "{}: {line}; report {} (and report.html)",
                study.name,
                dir.join("report.md").display()
            ),
            Err(e) => {
                eprintln!("error: {}: reduce failed: {e:#}", study.name);
                self.failed.push(study.name.clone());
            }
        }
    }

    fn result(self) -> anyhow::Result<()> {
        if self.failed.is_empty() {
            Ok(())
        } else {
            anyhow::bail!(
                "reduce failed for {} stud{}: {} (their sweeps are complete; run `impactsweep reduce` on them once the cause is fixed)",
                self.failed.len(),
                if self.failed.len() == 1 { "y" } else { "ies" },
                self.failed.join(", ")
            )
        }
    }
}

/// Whether a run directory has its report, and whether it is newer than every part file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportState {
    Missing,
    /// Older than the newest part file: the run went on after it was written.
    Stale,
    Current,
}

pub fn report_state(dir: &Path) -> ReportState {
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    let Some(report) = modified(&dir.join("report.md")) else {
        return ReportState::Missing;
    };
    let newest = crate::store::part_files(dir)
        .unwrap_or_default()
        .iter()
        .filter_map(|p| modified(p))
        .max();
    match newest {
        Some(t) if t > report => ReportState::Stale,
        _ => ReportState::Current,
    }
}

/// Prints what a run directory holds (chunks and runs done, damaged and missing chunks, per
/// shard; fails, exit 1, when a part file is damaged, naming it and the fix), or for an output
/// root every study in it with its state and its report.
pub fn status(args: &StatusArgs) -> anyhow::Result<()> {
    if crate::store::manifest::manifest_path(&args.dir).exists() {
        if args.html {
            return Err(InputError::new(format!(
                "{}: --html writes the page of an output root (OUT/index.html); this is a run directory: pass its parent, {}",
                args.dir.display(),
                args.dir
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."))
                    .display()
            ))
            .into());
        }
        let st = sweep::status(&args.dir)?;
        print!("{}", st.report(&args.dir));
        return match st.damage_error(&args.dir) {
            Some(e) => Err(e),
            None => Ok(()),
        };
    }
    let dirs = run_dirs(&args.dir)?;
    if dirs.is_empty() {
        return Err(InputError::new(format!(
            "{}: not a run directory (no manifest.json), nor an output root (no run directory in it)",
            args.dir.display()
        ))
        .into());
    }
    print!("{}", root_status(&args.dir, &dirs));
    if args.html {
        println!("wrote {}", write_index(&args.dir)?.display());
    }
    Ok(())
}

/// One line per run directory: study, state, report.
pub fn root_status(root: &Path, dirs: &[PathBuf]) -> String {
    use std::fmt::Write as _;
    let mut o = format!(
        "{}: {} stud{}\n",
        root.display(),
        dirs.len(),
        if dirs.len() == 1 { "y" } else { "ies" }
    );
    for dir in dirs {
        let row = study_row(dir);
        let report = match row.report {
            index::Report::NotReduced => "not reduced".to_string(),
            index::Report::Stale => format!(
                "{} (older than the data: reduce again)",
                dir.join("report.md").display()
            ),
            index::Report::Current => dir.join("report.md").display().to_string(),
        };
        let _ = writeln!(o, "{}: {}; report: {report}", row.name, row.state_text);
    }
    o
}

/// What a run directory holds, as `status OUT` and `OUT/index.html` say it.
pub fn study_row(dir: &Path) -> index::Row {
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let report = match report_state(dir) {
        ReportState::Missing => index::Report::NotReduced,
        ReportState::Stale => index::Report::Stale,
        ReportState::Current => index::Report::Current,
    };
    let st = match sweep::status(dir) {
        Ok(st) => st,
        Err(e) => {
            return index::Row {
                name,
                state: index::State::Unreadable(format!("{e:#}")),
                state_text: format!("unreadable: {e:#}"),
                runs_done: 0,
                n_runs: 0,
                wall_s: None,
                report,
            };
        }
    };
    let running = st
        .locks
        .iter()
        .any(|(_, h)| h.as_ref().is_some_and(|h| !h.stale));
    let m = &st.manifest;
    let (state, what) = if !st.damaged.is_empty() {
        (
            index::State::Damaged,
            format!(
                "{} of {} chunks damaged (status {} says which and what to do)",
                st.damaged.len(),
                m.n_chunks,
                dir.display()
            ),
        )
    } else if st.complete() {
        (
            index::State::Complete,
            format!("complete, {} runs", st.runs_done),
        )
    } else {
        (
            index::State::Partial,
            format!(
                "chunks {}/{} done, {} of {} runs",
                st.done.len(),
                m.n_chunks,
                st.runs_done,
                m.n_runs
            ),
        )
    };
    let (state, state_text) = if running {
        let state = if state == index::State::Damaged {
            state
        } else {
            index::State::Running
        };
        (state, format!("{what} (running)"))
    } else {
        (state, what)
    };
    index::Row {
        name,
        state,
        state_text,
        runs_done: st.runs_done,
        n_runs: m.n_runs,
        wall_s: wall_time(dir),
        report,
    }
}

/// From the study's start (`study.toml` is written once, when its directory is made) to its
/// newest part file, by the files' modification times.
fn wall_time(dir: &Path) -> Option<f64> {
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    let start = modified(&dir.join("study.toml"))?;
    let end = crate::store::part_files(dir)
        .unwrap_or_default()
        .iter()
        .filter_map(|p| modified(p))
        .max()?;
    end.duration_since(start).ok().map(|d| d.as_secs_f64())
}

/// The run directories of an output root, in name order.
fn run_dirs(root: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(root)
        .with_context(|| format!("listing {}", root.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| crate::store::manifest::manifest_path(p).exists())
        .collect();
    dirs.sort();
    Ok(dirs)
}

/// Writes `root/index.html`: one row per run directory in it.
pub fn write_index(root: &Path) -> anyhow::Result<PathBuf> {
    let rows: Vec<index::Row> = run_dirs(root)?.iter().map(|d| study_row(d)).collect();
    index::write(root, &rows)
}

/// After a study of `run`/`queue --reduce`: the output root's page again. A failure to write
/// it is reported and does not stop the queue.
fn refresh_index(root: &Path) {
    match write_index(root) {
        Ok(p) => eprintln!("index: {}", p.display()),
        Err(e) => eprintln!("warning: {}: index.html not written: {e:#}", root.display()),
    }
}
