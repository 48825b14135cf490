//! The command line. The only module that knows clap: it turns arguments into plain argument
//! structs and calls the library's commands in [`crate::app`].
//!
//! The doc comments below are clap's help text, written for a terminal (`[run].audit`,
//! `<study>`), not rustdoc markup.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::app;
use crate::app::reduce::CurveLines;

const AFTER_HELP: &str = "\
The pipeline: a study file (TOML) expands into a grid of design points; `run` simulates every
point and its perturbation/noise cases in parallel and streams the records to Parquet;
`reduce` turns them into reliability, zones, a ranking, a report and charts.

Typical use:
  impactsweep simulate --set e=0.6 --json          one run of the paper's Table I system
  impactsweep plan configs/paper.toml              size, time and disk estimate
  impactsweep run configs/paper.toml --out out     the sweep (resumable with --resume)
  impactsweep reduce out/paper                     report.md, summary.parquet, charts
  impactsweep plot waveform --e 0.45 0.9           the paper's Figures 2 and 5
  impactsweep tradeoff                             what each solver setting costs and how wrong it is
  impactsweep slurm configs/paper.toml --tasks 16  the sweep as a Slurm job array (+ reduce)

Exit status: 0 success, 1 failure (I/O, a damaged dataset), 2 bad input (a key, a value or a
study file; the message names the file, the key, the value and the allowed range), 130 a sweep
stopped by Ctrl-C or SIGTERM after writing the chunks in hand (continue it with --resume).
Units are SI everywhere. The model: docs/model.md in the source tree (Afsharfard & Kolahan 2013).";

/// Design impact dampers by exploring their design space in parallel.
#[derive(Parser, Debug)]
#[command(name = "impactsweep", version, about, after_help = AFTER_HELP)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Simulate one system (Table I with e = 0.9 unless --set says otherwise).
    #[command(after_help = SIMULATE_HELP)]
    Simulate(SimulateCmd),
    /// Validate a study and print its size, output location, time and disk estimate.
    Plan(PlanCmd),
    /// Run one or more studies: every design point and case, streamed to Parquet.
    Run(RunCmd),
    /// Run every study file in a directory in name order; finished ones are skipped.
    Queue(QueueCmd),
    /// Report per shard what a run directory holds and what is missing, every part file
    /// verified against its checksum (exit 1 when one is damaged).
    Status(StatusCmd),
    /// Turn a run directory into reliability, zones, a ranking, a report and charts.
    Reduce(ReduceCmd),
    /// Draw charts that need their own simulations (waveforms).
    #[command(subcommand)]
    Plot(PlotCmd),
    /// Measure every solver's cost and error against `exact` on a reference set of runs.
    Tradeoff(TradeoffCmd),
    /// Submit a study to Slurm as a job array plus a dependent reduce job.
    Slurm(SlurmCmd),
}

#[derive(Args, Debug)]
pub struct PlanCmd {
    /// The study file.
    pub study: PathBuf,
    /// Output root: the dataset would go to OUT/<study name>/.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Accept a grid beyond the size guard.
    #[arg(long)]
    pub allow_large: bool,
}

#[derive(Args, Debug)]
pub struct RunCmd {
    /// Study files, run one after another.
    #[arg(required = true)]
    pub studies: Vec<PathBuf>,
    /// Output root: each study writes OUT/<study name>/.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only shard I of N (0-based): the chunks k with k % N == I.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<(u64, u64)>,
    /// Continue an interrupted run: finished chunks are kept, the rest is run.
    #[arg(long)]
    pub resume: bool,
    /// No progress bar and no summary line.
    #[arg(long)]
    pub quiet: bool,
    /// Accept a grid beyond the size guard.
    #[arg(long)]
    pub allow_large: bool,
    /// Design points per Parquet part file (overrides [run].chunk_points).
    #[arg(long)]
    pub chunk_points: Option<u64>,
    /// Re-run K points with `exact` at tight tolerance and record the realised error
    /// (overrides [run].audit; 0 disables).
    #[arg(long, value_name = "K")]
    pub audit: Option<u64>,
    /// Reduce each study as soon as its sweep is complete (report, charts, tables); a failed
    /// reduce is reported and the next study still runs.
    #[arg(long)]
    pub reduce: bool,
}

/// Parses `I/N` with `0 <= I < N`.
fn parse_shard(s: &str) -> Result<(u64, u64), String> {
    let err = || format!("'{s}': expected I/N with whole numbers 0 <= I < N, e.g. 0/4");
    let (i, n) = s.split_once('/').ok_or_else(err)?;
    let i: u64 = i.trim().parse().map_err(|_| err())?;
    let n: u64 = n.trim().parse().map_err(|_| err())?;
    if n == 0 || i >= n {
        return Err(err());
    }
    Ok((i, n))
}

#[derive(Args, Debug)]
pub struct QueueCmd {
    /// Directory of study files (*.toml), run in name order.
    pub dir: PathBuf,
    /// Output root.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
    /// Reduce each study as soon as its sweep ends (and finished ones not reduced yet), so an
    /// overnight queue leaves its reports; a failed reduce is reported and the queue goes on.
    #[arg(long)]
    pub reduce: bool,
}

#[derive(Args, Debug)]
pub struct StatusCmd {
    /// A run directory (OUT/<study name>), or an output root: every study in it with its state
    /// and its report.
    pub dir: PathBuf,
    /// For an output root, also write DIR/index.html: one row per study with its state, runs,
    /// wall time, recommended design, design chart and a link to its report.html.
    #[arg(long)]
    pub html: bool,
}

#[derive(Args, Debug)]
pub struct ReduceCmd {
    /// A run directory (OUT/<study name>), finished or partly finished.
    pub dir: PathBuf,
    /// Use the paper's small-C_n safety factor instead of Shigley's exact relation.
    #[arg(long)]
    pub paper_safety: bool,
    /// DI as the mean over the cases instead of the ideal case.
    #[arg(long)]
    pub di_mean: bool,
    /// Bootstrap resamples for R's interval (overrides [reliability].bootstrap; 0 disables the
    /// interval, and with it the lower end that decides "reliable").
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(0..=10_000_000))]
    pub bootstrap: Option<u64>,
    /// A harmonic study: run only shard I of N of the per-design analysis (continuation and jump
    /// probes) and write it to DIR/analysis/; a later `reduce` without --shard uses every shard's.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<(u64, u64)>,
    /// A harmonic study: the lines of the design grid its bifurcation curves are followed
    /// along: `recommended` (each design axis through the recommended design: the design map's
    /// lines), `all` (every line: the cost grows with the number of designs) or `none`.
    #[arg(long, value_name = "LINES", default_value = "recommended", value_parser = parse_curve_lines)]
    pub bifurcation_curves: CurveLines,
    /// A random study: subset simulation with N samples per level (a multiple of 10, at least
    /// 100; 1000 is Au and Beck's) for each design whose realizations passed the threshold
    /// fewer than 10 times, its estimate ranking it; about N runs per decade of p_f per such
    /// design (at most 10,000 with N = 1000). 0: Monte Carlo only.
    #[arg(long, value_name = "N", default_value = "1000", value_parser = parse_subset)]
    pub subset: u64,
    /// A random study: R independent subset simulations per such design (R times the runs);
    /// its p_f is their mean and, for R > 1, its interval comes from their spread instead of
    /// the method's stated coefficient of variation.
    #[arg(long, value_name = "R", default_value = "1", value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub subset_repeats: u64,
}

/// Parses `--subset N`: 0 (off), or a multiple of 10, at least 100 (subset simulation's chains
/// of 10 need 10 seeds at least), at most 10^6.
fn parse_subset(s: &str) -> Result<u64, String> {
    match s.parse::<u64>() {
        Ok(n) if n == 0 || ((100..=1_000_000).contains(&n) && n.is_multiple_of(10)) => Ok(n),
        _ => Err(format!(
            "'{s}': expected 0 (Monte Carlo only) or a whole number of samples per level, a \
             multiple of 10 in [100, 1000000]"
        )),
    }
}

/// Parses `recommended`, `all` or `none`.
fn parse_curve_lines(s: &str) -> Result<CurveLines, String> {
    CurveLines::parse(s)
        .ok_or_else(|| format!("'{s}': expected one of {}", CurveLines::NAMES.join(", ")))
}

#[derive(Subcommand, Debug)]
pub enum PlotCmd {
    /// Main-mass displacement with and without the damper, and for two values of e with the
    /// first peak magnified (the paper's Figures 2 and 5).
    Waveform(WaveformCmd),
}

#[derive(Args, Debug)]
pub struct WaveformCmd {
    /// Set a system key, as for `simulate`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Output directory for the SVG and PNG files.
    #[arg(long, default_value = "out/waveform")]
    pub out: PathBuf,
    /// The two coefficients of restitution to compare.
    #[arg(long, num_args = 2, default_values_t = [0.45, 0.9])]
    pub e: Vec<f64>,
    /// Simulated time (s).
    #[arg(long = "t-end", default_value_t = 0.5)]
    pub t_end: f64,
}

#[derive(Args, Debug)]
pub struct TradeoffCmd {
    /// Reference runs: this study's design points (default: the paper system, e in [0.45, 0.95]).
    pub study: Option<PathBuf>,
    /// Where tradeoff.parquet and the chart go.
    #[arg(long, default_value = "out/tradeoff")]
    pub out: PathBuf,
    /// A shorter knob ladder and fewer repetitions.
    #[arg(long)]
    pub quick: bool,
    /// The SciPy peer's JSON (scripts/peer_scipy.py); default OUT/peer_scipy.json when present.
    #[arg(long)]
    pub peer: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct SlurmCmd {
    /// The study file.
    pub study: PathBuf,
    /// Array tasks (shards).
    #[arg(long)]
    pub tasks: u64,
    /// Output root (must be visible to the compute nodes).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Slurm partition.
    #[arg(long)]
    pub partition: Option<String>,
    /// Node features every task needs (Slurm's --constraint, e.g. avx2): keeps every shard and
    /// re-run on processors that compute the same bits.
    #[arg(long)]
    pub constraint: Option<String>,
    /// Time limit per task, in Slurm's format (e.g. 02:00:00).
    #[arg(long)]
    pub time: Option<String>,
    /// CPUs per task (each task runs that many threads).
    #[arg(long)]
    pub cpus_per_task: Option<u32>,
    /// Print the sbatch script instead of submitting it.
    #[arg(long)]
    pub dry_run: bool,
}

const SIMULATE_HELP: &str = "\
Keys (SI units, model.md names):
  M m K C d e       main mass (kg), inner mass (kg), stiffness (N/m), damping (N s/m),
                    clearance (m), coefficient of restitution [0, 1]
  x0 v0 y0 w0       initial displacement/velocity of the main mass and of the inner mass
  solver            exact
  tol               event-time tolerance relative to the undamped period (default 1e-12)
  chatter_tol       chatter-to-sticking threshold relative to the period (default 1e-6)
  peaks             positive half-cycle maxima wanted (default 2: what DI needs)
  t_end             fixed horizon (s) instead of stopping after the peaks
  max_impacts max_steps t_max_periods   caps that turn a runaway run into an outcome

The harmonic scene (steady state under F0 cos(omega t) on the main mass; docs/scenes.md):
  scene             free (default: the paper's free decay) or harmonic
  F0                force amplitude (N, default 1)
  omega | r         forcing frequency (rad/s), or r = omega / sqrt(K/M) (default r = 1); not both
  n_trans           transient periods (default: until the Poincare section converges)
  n_trans_max       cap of that default transient (default 2000)
  n_meas            measured periods (default 20)
  trans_tol period_tol   section convergence (1e-10) and repeat (1e-6) tolerances

One realization of a random or record design (docs/scenes.md; a study's [scene] keys, the
same defaults: firm soil, 20 s, dt 0.005 s, the structure at rest; the row its sweep stores):
  scene             random or record
  spectrum S0       white, kanai-tajimi or clough-penzien; its density ((m/s^2)^2 per rad/s)
  omega_g zeta_g omega_f zeta_f   the filters (default 5 pi, 0.6, pi/2, 0.6)
  dt duration input envelope=t1,t2,c   the load's samples (s), length (s), base or force
  record scale      a record's CSV or Parquet file (t,a or t,F) and its factor
  threshold drift_ratio storey_height yield_coefficient   the limit of |x|
  intensity T ida_tol ida_max im   pga or sa (g), its period (s), capacities, a stripe (g)
  realization seed  the load: realization C (default 0) of study seed S (default 0)

Examples:
  impactsweep simulate --set e=0.45 --json
  impactsweep simulate --set m=0 --set peaks=5
  impactsweep simulate --trace wave.csv --dt 1e-4 --t-end 0.5
  impactsweep simulate --set scene=harmonic --set F0=0.3 --set r=0.98 --json
  impactsweep simulate --study configs/seismic.toml --point 14 --realization 7 --trace q.csv
  impactsweep simulate --set scene=random --set spectrum=clough-penzien --set S0=0.005 \\
    --set threshold=0.02 --set intensity=pga --set im=0.3 --set realization=7 --set seed=1";

#[derive(Args, Debug)]
pub struct SimulateCmd {
    /// Set a system, solver or scene key, e.g. `--set e=0.6` (repeatable; see the keys below).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Print the record as one JSON object (SI units).
    #[arg(long)]
    pub json: bool,
    /// Write the displacements `t,x,y` to this CSV, sampled every --dt plus every impact.
    #[arg(long, value_name = "FILE.csv")]
    pub trace: Option<PathBuf>,
    /// Trace sample interval (s).
    #[arg(long, value_name = "SECONDS", default_value_t = 1e-4)]
    pub dt: f64,
    /// Simulate up to this time (s) instead of stopping after the requested peaks (free decay).
    #[arg(long = "t-end", value_name = "SECONDS")]
    pub t_end: Option<f64>,
    /// A random or record study: run one of its realizations as its sweep does (the same
    /// bits as its row), printed as JSON; with --trace its time series at the stripe's scale.
    #[arg(long, value_name = "STUDY.toml", conflicts_with_all = ["sets", "t_end"])]
    pub study: Option<PathBuf>,
    /// With --study: the design point (as in the points table's `point`).
    #[arg(long, value_name = "P", default_value_t = 0, requires = "study")]
    pub point: u64,
    /// With --study: the realization (the points table's `case`).
    #[arg(long, value_name = "C", default_value_t = 0, requires = "study")]
    pub realization: u32,
}

/// Parses the arguments and runs the command.
pub fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Simulate(c) => match c.study {
            Some(study) => {
                app::simulate::realization(&study, c.point, c.realization, c.trace, c.dt)
            }
            None => app::simulate::run(&app::simulate::SimulateArgs {
                sets: c.sets,
                json: c.json,
                trace: c.trace,
                dt: Some(c.dt),
                t_end: c.t_end,
            }),
        },
        Command::Plan(c) => app::plan::plan(&app::plan::PlanArgs {
            study: c.study,
            out: c.out,
            allow_large: c.allow_large,
        }),
        Command::Run(c) => app::sweep::run(&app::sweep::RunArgs {
            studies: c.studies,
            out: c.out,
            threads: c.threads,
            shard: c.shard,
            resume: c.resume,
            quiet: c.quiet,
            allow_large: c.allow_large,
            chunk_points: c.chunk_points,
            audit: c.audit,
            reduce: c.reduce,
        }),
        Command::Queue(c) => app::sweep::queue(&app::sweep::QueueArgs {
            dir: c.dir,
            out: c.out,
            threads: c.threads,
            quiet: c.quiet,
            reduce: c.reduce,
        }),
        Command::Status(c) => app::sweep::status(&app::sweep::StatusArgs {
            dir: c.dir,
            html: c.html,
        }),
        Command::Reduce(c) => app::reduce::reduce(&app::reduce::ReduceArgs {
            dir: c.dir,
            paper_safety: c.paper_safety,
            di_mean: c.di_mean,
            bootstrap: c.bootstrap.map(|b| b as usize),
            shard: c.shard,
            bifurcation_curves: c.bifurcation_curves,
            subset: (c.subset > 0).then_some(c.subset as usize),
            subset_repeats: c.subset_repeats as usize,
        }),
        Command::Plot(PlotCmd::Waveform(c)) => app::reduce::waveform(&app::reduce::WaveformArgs {
            sets: c.sets,
            out: c.out,
            e: c.e,
            t_end: c.t_end,
        }),
        Command::Tradeoff(c) => app::tradeoff::tradeoff(&app::tradeoff::TradeoffArgs {
            study: c.study,
            out: c.out,
            quick: c.quick,
            peer: c.peer,
        }),
        Command::Slurm(c) => app::slurm::slurm(&app::slurm::SlurmArgs {
            study: c.study,
            tasks: c.tasks,
            out: c.out,
            partition: c.partition,
            constraint: c.constraint,
            time: c.time,
            cpus_per_task: c.cpus_per_task,
            dry_run: c.dry_run,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    fn reduce(args: &[&str]) -> Result<ReduceCmd, clap::Error> {
        let all = [&["impactsweep", "reduce", "out/x"], args].concat();
        Cli::try_parse_from(all).map(|c| match c.command {
            Command::Reduce(r) => r,
            _ => panic!("not reduce"),
        })
    }

    #[test]
    fn subset_repeats_default_to_one_and_take_a_count_from_1() {
        assert_eq!(reduce(&[]).unwrap().subset_repeats, 1);
        let r = reduce(&["--subset", "500", "--subset-repeats", "20"]).unwrap();
        assert_eq!((r.subset, r.subset_repeats), (500, 20));
        assert!(reduce(&["--subset-repeats", "0"]).is_err());
    }
}
