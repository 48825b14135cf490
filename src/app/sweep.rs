//! `plan`, `run`, `queue` and `status`: the sweep engine's commands (issue 3).
//! STUB: owned by the sweep-engine work; replace the bodies.

use std::path::PathBuf;

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

pub fn run(_args: &RunArgs) -> anyhow::Result<()> {
    anyhow::bail!("run is not implemented yet")
}

pub fn queue(_args: &QueueArgs) -> anyhow::Result<()> {
    anyhow::bail!("queue is not implemented yet")
}

pub fn status(_args: &StatusArgs) -> anyhow::Result<()> {
    anyhow::bail!("status is not implemented yet")
}
