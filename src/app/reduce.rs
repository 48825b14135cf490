//! `reduce` and `plot`: the reducer's commands (issue 4).
//! STUB: owned by the reducer work; replace the bodies.

use std::path::PathBuf;

/// `impactsweep reduce RUN_DIR`.
#[derive(Clone, Debug, Default)]
pub struct ReduceArgs {
    pub dir: PathBuf,
    /// Use the paper's small-C_n safety factor instead of Shigley's exact relation.
    pub paper_safety: bool,
    /// DI as the mean over cases instead of the ideal case.
    pub di_mean: bool,
}

/// `impactsweep plot waveform`.
#[derive(Clone, Debug, Default)]
pub struct WaveformArgs {
    pub sets: Vec<String>,
    pub out: PathBuf,
    pub e: Vec<f64>,
    pub t_end: f64,
}

pub fn reduce(_args: &ReduceArgs) -> anyhow::Result<()> {
    anyhow::bail!("reduce is not implemented yet")
}

pub fn waveform(_args: &WaveformArgs) -> anyhow::Result<()> {
    anyhow::bail!("plot waveform is not implemented yet")
}
