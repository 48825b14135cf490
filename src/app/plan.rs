//! `impactsweep plan STUDY.toml`: validates a study and prints its size, where its dataset would
//! go, and an estimate of run time and disk size ([`crate::api::plan`]).

use std::path::PathBuf;

use crate::api::plan::{describe, time_sample};
use crate::study::{LoadOptions, Study};

/// `impactsweep plan STUDY.toml`.
#[derive(Clone, Debug, Default)]
pub struct PlanArgs {
    pub study: PathBuf,
    pub out: PathBuf,
    pub allow_large: bool,
}

/// `impactsweep plan`.
pub fn plan(args: &PlanArgs) -> anyhow::Result<()> {
    let study = Study::load_with(
        &args.study,
        LoadOptions {
            allow_large: args.allow_large,
        },
    )?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let sample = time_sample(&study);
    print!("{}", describe(&study, &args.out, threads, Some(sample)));
    Ok(())
}
