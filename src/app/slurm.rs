//! `slurm`: sweeps as Slurm job arrays (issue 6).
//! STUB: owned by the cluster work; replace the bodies.

use std::path::PathBuf;

/// `impactsweep slurm STUDY.toml --tasks N [--out DIR] [--partition P] [--time T] [--cpus-per-task C] [--dry-run]`.
#[derive(Clone, Debug, Default)]
pub struct SlurmArgs {
    pub study: PathBuf,
    pub tasks: u64,
    pub out: PathBuf,
    pub partition: Option<String>,
    pub time: Option<String>,
    pub cpus_per_task: Option<u32>,
    pub dry_run: bool,
}

pub fn slurm(_args: &SlurmArgs) -> anyhow::Result<()> {
    anyhow::bail!("slurm is not implemented yet")
}
