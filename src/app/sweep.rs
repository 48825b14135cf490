//! `plan`, `run`, `queue` and `status`: the sweep engine's commands (issue 3).

use std::path::PathBuf;

use anyhow::Context;

use crate::error::InputError;
use crate::study::{LoadOptions, Study};
use crate::sweep::{self, SweepOptions};

/// `impactsweep plan STUDY.toml`.
#[derive(Clone, Debug, Default)]
pub struct PlanArgs {
    pub study: PathBuf,
    pub out: PathBuf,
    pub allow_large: bool,
}

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
}

/// `impactsweep queue DIR`.
#[derive(Clone, Debug, Default)]
pub struct QueueArgs {
    pub dir: PathBuf,
    pub out: PathBuf,
    pub threads: Option<usize>,
    pub quiet: bool,
}

/// `impactsweep status RUN_DIR`.
#[derive(Clone, Debug, Default)]
pub struct StatusArgs {
    pub dir: PathBuf,
}

pub fn plan(args: &PlanArgs) -> anyhow::Result<()> {
    crate::app::plan::plan(args)
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
    }
    Ok(())
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
    }
    Ok(())
}

/// Prints what a run directory holds: chunks and runs done, damaged and missing chunks, per
/// shard. Fails (exit 1) when a part file is damaged, naming it and the fix.
pub fn status(args: &StatusArgs) -> anyhow::Result<()> {
    let st = sweep::status(&args.dir)?;
    print!("{}", st.report(&args.dir));
    match st.damage_error(&args.dir) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
