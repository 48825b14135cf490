//! A harmonic study's per-design analysis, whole or in shards (docs/reduce.md, "The analysis in
//! shards").
//!
//! Two parts of `reduce` simulate: the periodic branches followed by continuation from each
//! design's stored attractors ([`super::steady`]), and the probes that locate jumps between the
//! grid's designs ([`super::probe`]). The rest (statistics, zones, the ranking, the report) reads
//! the dataset only. `reduce --shard I/N` runs the cheap streaming reduction, then only its share
//! of the simulating work: the designs `d` with `d % N == I`, and the jump probes on the grid
//! lines whose key falls to shard `I` ([`Shard::owns_line`]); it writes what it computed into
//! `RUN_DIR/analysis/` ([`super::shard`], [`crate::store::analysis`]) and no report. The
//! verification of the deciding designs ([`super::verify`]) is shared out the same way: every
//! shard reduces all the designs' runs, so each knows the ranking and which cases decide it, and
//! measures the cases that fall to it ([`super::verify::share`]). A later
//! `reduce` without `--shard` finds a complete set of `N` shards written for this study, takes
//! their branches and probes instead of computing them, and writes every output: the same bits a
//! `reduce` alone writes, since each design's branches and each probe are deterministic and
//! independent of everything else. What no shard computed (an incomplete set) is computed there.

use std::collections::{BTreeMap, HashMap};

use crate::orbits::response::BranchRow;
use crate::sim::noise::mix64;

/// Shard `index` of `count` of the analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    /// The designs a shard analyses: `design % count == index`.
    pub fn owns_design(&self, design: u64) -> bool {
        design % self.count.max(1) == self.index
    }

    /// The probes a shard computes: those whose grid line's key ([`line_key`]) falls to it. All
    /// probes of one line (a jump's bisection asks for several, and the bisections of the peak
    /// and of PR share their first midpoints) fall to one shard.
    pub fn owns_line(&self, key: u64) -> bool {
        mix64(key) % self.count.max(1) == self.index
    }
}

/// The key of the grid line a probe lies on: which axis is off the grid and the grid indices of
/// the others (not where along the line it is: the bisections of one line stay in one shard).
/// `grid` holds each design axis's values, `values` the probe's.
pub fn line_key(grid: &[Vec<f64>], values: &[f64]) -> u64 {
    let mut key = 0x5EED_u64;
    for (a, (axis, &v)) in grid.iter().zip(values).enumerate() {
        let part = match axis.iter().position(|&g| g == v) {
            Some(i) => i as u64,
            None => (1 << 40) | a as u64,
        };
        key = mix64(key ^ part);
    }
    key
}

/// Jump probes: the bits of a probe's design-axis values, and its `[peak amplitude, peak
/// reduction]` (`None`: the design is not valid or a run failed).
pub type Probes = Vec<(Vec<u64>, Option<[f64; 2]>)>;

/// What earlier shards computed, for the final reduction.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prior {
    /// Probe results by the bits of the probe's axis values.
    pub probes: HashMap<Vec<u64>, Option<[f64; 2]>>,
    /// Branch rows by design.
    pub branches: BTreeMap<u64, Vec<BranchRow>>,
    /// A complete set of shards: every design was analysed (one without a row has no branch).
    pub complete: bool,
    /// The direct measurements of the verification the shards made
    /// ([`super::verify::Measured`]).
    pub verified: super::verify::Measured,
}

impl Prior {
    /// The branches an earlier shard found for design `d`, if one analysed it.
    pub fn branches_of(&self, d: u64) -> Option<Vec<BranchRow>> {
        match self.branches.get(&d) {
            Some(b) => Some(b.clone()),
            None => self.complete.then(Vec::new),
        }
    }
}

/// How the analysis runs: whole (`shard: None`), or as one shard; with what earlier shards
/// computed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plan {
    pub shard: Option<Shard>,
    pub prior: Prior,
}

impl Plan {
    /// Whether this run analyses design `d` itself.
    pub fn computes_design(&self, d: u64) -> bool {
        self.prior.branches_of(d).is_none() && self.shard.is_none_or(|s| s.owns_design(d))
    }
}

/// Which lines of the design grid the bifurcation curves are followed along (`reduce
/// --bifurcation-curves`). A curve along axis `p` serves the designs of one line, those with the
/// other axes' values; the lines through one design are what the design map of that design's
/// plane draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurveLines {
    /// Along each design axis through the recommended design (the design map's lines): a few
    /// lines whatever the size of the grid.
    #[default]
    Recommended,
    /// Along every line of the grid: the cost grows like the number of designs times the number
    /// of axes (a 1,000-design study over three axes has 300 lines).
    All,
    /// No curves.
    None,
}

impl CurveLines {
    /// The names accepted on the command line, in the order of the variants.
    pub const NAMES: [&'static str; 3] = ["recommended", "all", "none"];

    pub fn parse(s: &str) -> Option<CurveLines> {
        match s {
            "recommended" => Some(CurveLines::Recommended),
            "all" => Some(CurveLines::All),
            "none" => Some(CurveLines::None),
            _ => None,
        }
    }
}
