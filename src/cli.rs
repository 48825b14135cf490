//! The command line. The only module that knows clap: it turns arguments into plain argument
//! structs and calls the library's commands in [`crate::app`].

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::app;

const AFTER_HELP: &str = "\
The pipeline: a study file (TOML) expands into a grid of design points; `run` simulates every
point and its perturbation/noise cases in parallel and streams the records to Parquet;
`reduce` turns them into reliability, zones, a ranking, a report and charts.

Typical use:
  impactsweep simulate --set e=0.6 --json          one run of the paper's Table I system
  impactsweep plan configs/paper.toml              size, time and disk estimate
  impactsweep run configs/paper.toml --out out     the sweep (resumable with --resume)
  impactsweep reduce out/paper                     report.md, summary.parquet, charts

Exit status: 0 success, 1 failure (I/O, a damaged dataset), 2 bad input (a key, a value or a
study file; the message names the file, the key, the value and the allowed range).
Units are SI everywhere. The model: ../shared/spec/model.md (Afsharfard & Kolahan 2013).";

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

Examples:
  impactsweep simulate --set e=0.45 --json
  impactsweep simulate --set m=0 --set peaks=5
  impactsweep simulate --trace wave.csv --dt 1e-4 --t-end 0.5";

#[derive(Args, Debug)]
pub struct SimulateCmd {
    /// Set a system or solver key, e.g. `--set e=0.6` (repeatable; see the keys below).
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
    /// Simulate up to this time (s) instead of stopping after the requested peaks.
    #[arg(long = "t-end", value_name = "SECONDS")]
    pub t_end: Option<f64>,
}

/// Parses the arguments and runs the command.
pub fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Simulate(c) => app::simulate::run(&app::simulate::SimulateArgs {
            sets: c.sets,
            json: c.json,
            trace: c.trace,
            dt: Some(c.dt),
            t_end: c.t_end,
        }),
    }
}
