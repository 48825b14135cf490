//! The reduction of a free-decay study's run directory ([`reduce`]): its part files streamed
//! through the reducer, the store's rows converted to the reducer's own ([`free::run_of`]),
//! then the outputs every scene writes ([`write_outputs`]); the scene adds nothing to them.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::api::outputs::{Reduced, write_outputs};
use crate::api::reduce_options::{ReduceArgs, options};
use crate::reduce::free;
use crate::store;
use crate::study::Study;

/// Reduces the done parts `parts` of a free-decay study into `dir`.
pub(crate) fn reduce(
    study: &Study,
    dir: &Path,
    parts: &[PathBuf],
    args: &ReduceArgs,
    audit: Option<&crate::accuracy::Audit>,
) -> anyhow::Result<Reduced> {
    let opts = options(study, args);
    let chunks = parts.iter().map(|p| {
        store::read_part(p)
            .map(|rows| rows.iter().map(free::run_of).collect())
            .with_context(|| format!("reading {}", p.display()))
    });
    let summary = free::reduce(study, opts, chunks)?;
    let files = write_outputs(study, &summary, dir, audit)?;
    Ok(Reduced::Whole {
        summary: Box::new(summary),
        files,
        from_shards: 0,
    })
}
