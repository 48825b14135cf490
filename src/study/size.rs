//! The size guard: how many runs a study may ask for before `--allow-large` must say so.

/// The default size guard: a study with more runs than this is refused unless the caller
/// passes `allow_large` (`--allow-large` on the command line). 10^7 runs is about ten minutes
/// of noise-free two-peak runs on two cores and about a gigabyte of Parquet.
pub const MAX_RUNS: u64 = 10_000_000;

/// Options of [`Study::load_with`](super::Study::load_with) and
/// [`Study::parse_with`](super::Study::parse_with).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Accept a study beyond the size guard [`MAX_RUNS`].
    pub allow_large: bool,
}
