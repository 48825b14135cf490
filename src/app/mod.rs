//! The commands, one module each, over the pipeline's library modules. Argument parsing lives in
//! [`crate::cli`]; these take plain structs.

pub mod plan;
pub mod reduce;
pub mod simulate;
pub mod slurm;
pub mod sweep;
pub mod tradeoff;
