//! What the harmonic reduction adds to the core's summary ([`HarmonicSummary`]: the curves, the
//! runs' outcomes, how the design quantity and the analysis were chosen) and the summary columns
//! it adds for each design ([`summary_columns`]).

use super::analysis::{CurveLines, Plan};
use super::curve::{Curve, CurvePoint};
use super::verify::Verification;
use crate::orbits::attractors::AttractorRow;
use crate::reduce::common::PointStats;
use crate::sim::harmonic::{DesignPeak, LifeCurve, NonPeriodicPeak};
use crate::store::table::{Column, Table};

/// What the harmonic reduction adds to the core's [`crate::reduce::Summary`].
#[derive(Clone, Debug, PartialEq)]
pub struct HarmonicSummary {
    /// The frequency axis (`r` or `omega`) and its values; `None` when the study has a single
    /// frequency (then a "curve" is one point).
    pub frequency: Option<(String, Vec<f64>)>,
    /// Every design's ideal-case curve, in design order.
    pub curves: Vec<Curve>,
    /// Simulated runs, and their outcomes in [`crate::sim::Outcome::ALL`] order (the reducer's own
    /// counts are per design and case).
    pub runs: u64,
    pub outcomes: [u64; 6],
    /// Which steady state the design quantity is.
    pub design_peak: DesignPeak,
    /// How the per-design analysis runs (one shard of it, what earlier shards computed).
    pub analysis: Plan,
    /// The design life (s) a motion that is not periodic is measured over, and the quantile of
    /// its largest amplitude that is the design amplitude (`[scene]`).
    pub design_life: f64,
    pub life_quantile: f64,
    /// How a motion that is not periodic gets its design amplitude (`[scene]
    /// nonperiodic_peak`).
    pub nonperiodic_peak: NonPeriodicPeak,
    /// Where the race measured the design lives (`[scene] life_curve`).
    pub life_curve: LifeCurve,
    /// The lines of the grid the bifurcation curves are followed along.
    pub curve_lines: CurveLines,
    /// The deciding designs' peaks measured directly ([`super::verify`]).
    pub verification: Verification,
}

impl HarmonicSummary {
    /// The design life the motions that are not periodic were measured over (s); NaN when
    /// none was (`nonperiodic_peak = "window"`).
    pub fn measured_life(&self) -> f64 {
        match self.nonperiodic_peak {
            NonPeriodicPeak::Life => self.design_life,
            NonPeriodicPeak::Window => f64::NAN,
        }
    }

    /// The curve of a design, if it is in the dataset.
    pub fn curve(&self, design: u64) -> Option<&Curve> {
        self.curves
            .binary_search_by_key(&design, |c| c.design)
            .ok()
            .map(|i| &self.curves[i])
    }
}

/// The summary columns of a harmonic study beyond the reducer's, for the rows of `points`
/// (designs), from each design's ideal curve: `peak_r` (where its peak is), `linear_peak` and
/// `linear_peak_r` (the linear system's peak over the band), `help_r_from` and `help_r_to` (the
/// band where the damper helps, NaN when it does not help at the linear peak), `help_share` and
/// `periodic_share` (shares of the band's frequencies), `peak_periodic` (the motion at the peak
/// is periodic, [`Curve::peak_periodic`]).
pub fn summary_columns(t: &mut Table, fs: &HarmonicSummary, points: &[&PointStats]) {
    let col = |g: &dyn Fn(&Curve) -> f64| {
        Column::F64(
            points
                .iter()
                .map(|p| fs.curve(p.point).map_or(f64::NAN, g))
                .collect(),
        )
    };
    let band = |c: &Curve| c.help_band();
    t.push("peak_r", col(&|c| c.peak().1));
    t.push("peak_from_rest", col(&|c| c.peak_from_rest().0));
    t.push(
        "peak_attractor_period",
        Column::U64(
            points
                .iter()
                .map(|p| {
                    fs.curve(p.point)
                        .and_then(Curve::peak_point)
                        .map(|q| u64::from(q.design_period))
                })
                .collect(),
        ),
    );
    let at_peak = |g: fn(&CurvePoint) -> f64| move |c: &Curve| c.peak_point().map_or(f64::NAN, g);
    t.push(
        "peak_impacts_per_period",
        col(&at_peak(|q| q.design_impacts)),
    );
    t.push("peak_basin_share", col(&at_peak(|q| q.design_share)));
    t.push("linear_peak", col(&|c| c.linear_peak().0));
    t.push("linear_peak_r", col(&|c| c.linear_peak().1));
    t.push(
        "help_r_from",
        col(&|c| band(c).map_or(f64::NAN, |b| b.from)),
    );
    t.push("help_r_to", col(&|c| band(c).map_or(f64::NAN, |b| b.to)));
    t.push("help_share", col(&|c| c.help_share()));
    t.push("periodic_share", col(&|c| c.periodic_share()));
    t.push(
        "peak_periodic",
        Column::Bool(
            points
                .iter()
                .map(|p| fs.curve(p.point).is_some_and(Curve::peak_periodic))
                .collect(),
        ),
    );
    // Issue 22: the steady state carrying the peak, and the design life its amplitude is over.
    let attractor =
        |g: fn(&AttractorRow) -> f64| move |c: &Curve| c.peak_attractor().map_or(f64::NAN, g);
    t.push(
        "peak_kind",
        Column::Str(
            points
                .iter()
                .map(|p| {
                    fs.curve(p.point)
                        .and_then(Curve::peak_attractor)
                        .map_or(String::new(), |a| a.kind.name().to_string())
                })
                .collect(),
        ),
    );
    t.push(
        "peak_window_amplitude",
        col(&attractor(|a| a.window_amplitude)),
    );
    t.push("peak_life_lo", col(&attractor(|a| a.life_lo)));
    t.push("peak_life_hi", col(&attractor(|a| a.life_hi)));
    t.push("peak_lyapunov", col(&attractor(|a| a.lyapunov)));
    t.push(
        "design_life",
        Column::F64(vec![fs.measured_life(); points.len()]),
    );
}
