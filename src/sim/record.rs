//! The result of a free-decay run ([`Record`]) and how any run ended ([`Outcome`]). A leaf below
//! the simulator's modules, re-exported by [`crate::sim`].

use serde::Serialize;

/// How a run ended. Stored as a column; a failed run never stops a sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Every requested observable is known.
    Ok,
    /// Fewer than two positive half-cycle maxima before the horizon: `x2`, `t2`, `di` are NaN.
    NoSecondPeak,
    /// At least two maxima but fewer than `peaks` asked.
    FewPeaks,
    /// The impact cap was reached first.
    EventCap,
    /// The solver step cap was reached first.
    StepCap,
    /// The state left the finite numbers (a solver diverged).
    NonFinite,
}

impl Outcome {
    pub const ALL: [Outcome; 6] = [
        Outcome::Ok,
        Outcome::NoSecondPeak,
        Outcome::FewPeaks,
        Outcome::EventCap,
        Outcome::StepCap,
        Outcome::NonFinite,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Outcome::Ok => "ok",
            Outcome::NoSecondPeak => "no_second_peak",
            Outcome::FewPeaks => "few_peaks",
            Outcome::EventCap => "event_cap",
            Outcome::StepCap => "step_cap",
            Outcome::NonFinite => "non_finite",
        }
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The result of one run. Times in s, displacements in m, energies in J.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Record {
    pub outcome: Outcome,
    /// Positive half-cycle maxima `(X_k, t_k)`, at most `peaks` of them.
    pub peaks: Vec<(f64, f64)>,
    pub x1: f64,
    pub t1: f64,
    pub x2: f64,
    pub t2: f64,
    /// Largest of the computed half-cycle maxima.
    pub xmax: f64,
    /// Damping inclination `(X1 - X2) / (t2 - t1)` (m/s).
    pub di: f64,
    /// Impacts up to `t_stop` (a chatter sequence ended by sticking counts its impacts).
    pub impacts: u64,
    /// Sticking phases entered.
    pub sticks: u64,
    /// With several units (model.md §14): each unit's impacts, in unit order (a simultaneous
    /// impact counts once in `impacts` and once for each unit here); empty with one unit.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub unit_impacts: Vec<u64>,
    /// Energy dissipated by impacts (J).
    pub energy_impact: f64,
    /// Energy dissipated by the viscous damper (J).
    pub energy_viscous: f64,
    /// Time the run stopped (s).
    pub t_stop: f64,
    /// Solver steps taken: for `exact`, evaluations of the closed form (or of its local Taylor
    /// polynomials) plus one per event search; integration steps otherwise.
    pub steps: u64,
}
