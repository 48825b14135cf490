//! The reduction of a whole sweep ([`Summary`]): every design point's statistics, the zones, the
//! jumps, the sensitivity and the recommendation, with what the report needs to say how they
//! were computed.

use super::grid::{End, Grid};
use super::jumps::Jump;
use super::options::Options;
use super::point::{PointStats, Run};
use super::rank;
use super::stats::LogNormal;
use super::zones::{JumpStats, Zone};

/// The best designs on one end of one axis ([`super::recommend::edges`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeWarning {
    pub axis: usize,
    pub end: End,
    /// The axis value at that end.
    pub value: f64,
    /// How many of the top `top` designs ([`super::recommend::TOP`]) sit there.
    pub n_top: usize,
    pub top: usize,
    /// The best design (rank 1) sits there; the recommended one does.
    pub best: bool,
    pub recommended: bool,
    /// One more step beyond that end is a valid design (the model's ranges allow it).
    pub extendable: bool,
}

/// Sensitivity of one quantity to one axis ([`super::sensitivity`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// A summary column: the response's mean, `di`, `reliability` or `perfectibility`.
    pub quantity: String,
    pub axis: usize,
    pub first_order: f64,
    pub total: f64,
    /// The points it was computed over (those whose cases all ended ok and where it is known).
    pub n_points: usize,
}

/// Everything the report needs.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The swept axes.
    pub grid: Grid,
    /// One entry per design point found, in point order.
    pub points: Vec<PointStats>,
    /// Design points the study plans.
    pub n_points_planned: u64,
    /// Zones, named in the order of their first point.
    pub zones: Vec<Zone>,
    /// Jumps located along the axes, and how they were found.
    pub jumps: Vec<Jump>,
    pub jump_stats: JumpStats,
    /// First-order and total-effect indices per quantity and axis (two or more axes).
    pub sensitivity: Vec<Sensitivity>,
    /// The recommended design point ([`super::recommend`]) and the edges the best designs sit on.
    pub recommended: Option<u64>,
    pub edges: Vec<EdgeWarning>,
    /// The DI threshold used for "strong damping" (m/s).
    pub di_strong: f64,
    /// The reliability the lower end of R's interval must reach (`[zones].r_min`).
    pub r_min: f64,
    /// A region smaller than this (design points) was merged into a neighbour.
    pub min_zone_points: usize,
    /// The nominal design point (nearest the study's base system) and its runs.
    pub nominal: Option<(u64, Vec<Run>)>,
    /// Runs per outcome over the whole dataset, in [`crate::sim::Outcome::ALL`] order.
    pub outcome_totals: [u64; 6],
    /// The strength distribution (Pa).
    pub strength: LogNormal,
    /// `3 E r / L^2`: stress per metre of the response (Pa/m).
    pub stress_per_m: f64,
    pub options: Options,
    /// Confidence level of the bootstrap interval of R.
    pub confidence: f64,
    /// Best R and DI over the sweep (the eq. 11 denominators).
    pub r_max: f64,
    pub di_max: f64,
}

impl Summary {
    /// The axis values of a point, in axis order.
    pub fn values(&self, p: &PointStats) -> Vec<f64> {
        self.grid.values(p.point)
    }

    /// The point with index `point`, if it is in the dataset.
    pub fn point(&self, point: u64) -> Option<&PointStats> {
        self.points
            .binary_search_by_key(&point, |p| p.point)
            .ok()
            .map(|i| &self.points[i])
    }

    /// The zone of a point, if any.
    pub fn zone_of(&self, p: &PointStats) -> Option<&Zone> {
        self.zones.get(p.zone as usize)
    }

    /// Whether R is computed anywhere: false for a study without a strength
    /// ([`rank::computes_r`]).
    pub fn computes_r(&self) -> bool {
        rank::computes_r(&self.points)
    }

    /// The design point the report and the charts centre on: the recommended one, else the best
    /// ranked, else the first.
    pub fn anchor(&self) -> Option<u64> {
        self.recommended
            .or_else(|| {
                self.points
                    .iter()
                    .filter(|p| p.rank.is_some())
                    .min_by_key(|p| p.rank)
                    .map(|p| p.point)
            })
            .or_else(|| self.points.first().map(|p| p.point))
    }

    /// The point was merged into its zone from a smaller neighbouring region: its own class is
    /// not its zone's ([`Zone::n_merged`] counts them).
    pub fn merged(&self, p: &PointStats) -> bool {
        self.zone_of(p)
            .and_then(|z| z.class)
            .is_some_and(|c| c != p.class)
    }

    /// The name of a point's zone ("" when it has none).
    pub fn zone_name(&self, p: &PointStats) -> &str {
        self.zone_of(p).map_or("", |z| z.name.as_str())
    }
}
