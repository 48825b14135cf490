//! `tradeoff`: speed against accuracy of every solver (issue 5).
//! STUB: owned by the fidelity work; replace the bodies.

use std::path::PathBuf;

/// `impactsweep tradeoff [STUDY.toml] [--out DIR]`.
#[derive(Clone, Debug, Default)]
pub struct TradeoffArgs {
    pub study: Option<PathBuf>,
    pub out: PathBuf,
    pub quick: bool,
}

pub fn tradeoff(_args: &TradeoffArgs) -> anyhow::Result<()> {
    anyhow::bail!("tradeoff is not implemented yet")
}
