//! How to run a study ([`SweepOptions`]): what the command line and the API ask of the sweep
//! engine ([`super::engine::run_study`]) and of the run directory it opens
//! ([`super::rundir`]), and which chunks a shard runs ([`shard_chunks`]).

/// How to run a study.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Worker threads; `None` means all cores.
    pub threads: Option<usize>,
    /// `(i, n)`: run the chunks `k` with `k % n == i`. `(0, 1)` is the whole study.
    pub shard: (u64, u64),
    /// Continue an existing run directory.
    pub resume: bool,
    /// Show a progress bar (only drawn when stderr is a terminal).
    pub progress: bool,
    /// Design points per chunk; `None`: the existing manifest's, else `[run].chunk_points`.
    pub chunk_points: Option<u64>,
    /// Points to audit; `None`: `[run].audit`.
    pub audit: Option<u64>,
    /// Stop after this many chunks have been written (to test interruptions). `None`: all.
    pub stop_after: Option<u64>,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            threads: None,
            shard: (0, 1),
            resume: false,
            progress: false,
            chunk_points: None,
            audit: None,
            stop_after: None,
        }
    }
}

/// The chunks of shard `(i, n)`.
pub fn shard_chunks(n_chunks: u64, shard: (u64, u64)) -> impl Iterator<Item = u64> {
    (shard.0..n_chunks).step_by(shard.1.max(1) as usize)
}
