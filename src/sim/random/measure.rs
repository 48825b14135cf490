//! What a study states about intensity measures (model.md §13, docs/scenes.md): which measure
//! ([`Measure`], PGA or `Sa`), its settings ([`IntensitySpec`]) and a ground motion's own values
//! ([`OwnIntensity`]). A leaf: the scene ([`super::RandomScene`]) and the realization record hold
//! these types, and [`super::intensity`] computes the values.

use serde::Serialize;

/// Which intensity measure a study states its stripes, capacities and hazard in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Measure {
    /// Peak ground acceleration (g).
    Pga,
    /// Spectral acceleration at the period `T`, 5 % damping (g).
    Sa,
}

impl Measure {
    pub const NAMES: [&'static str; 2] = ["pga", "sa"];

    pub fn name(self) -> &'static str {
        match self {
            Measure::Pga => "pga",
            Measure::Sa => "sa",
        }
    }

    pub fn parse(s: &str) -> Option<Measure> {
        match s {
            "pga" => Some(Measure::Pga),
            "sa" => Some(Measure::Sa),
            _ => None,
        }
    }
}

/// A study's intensity measure: PGA, or Sa at `period` (s; by default the structure's own
/// `T1 = 2 pi sqrt(M / K)`), and the settings of its capacities by incremental dynamic analysis
/// ([`super::ida`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct IntensitySpec {
    pub measure: Measure,
    /// The period of `Sa` (s), in `[0.01, 100]` and at least `8 dt` (so that `u'` changes sign
    /// at most once per interval).
    pub period: f64,
    /// A capacity's relative tolerance (the bracket `[lo, hi]` ends with `hi / lo <= 1 + tol`),
    /// in `[1e-6, 0.5]`; default 0.01.
    pub ida_tol: f64,
    /// The largest intensity (g) a capacity search tries; a motion that never passes the limit
    /// below it has a censored capacity. In `(0, 1000]`, default 10 g.
    pub ida_max: f64,
}

/// Default relative tolerance of a capacity.
pub const DEFAULT_IDA_TOL: f64 = 0.01;
/// Default largest intensity a capacity search tries (g).
pub const DEFAULT_IDA_MAX: f64 = 10.0;

/// A ground motion's own intensity measures at scale 1 (g).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OwnIntensity {
    pub pga: f64,
    pub sa: f64,
}

impl OwnIntensity {
    /// The value of `measure`.
    pub fn of(&self, measure: Measure) -> f64 {
        match measure {
            Measure::Pga => self.pga,
            Measure::Sa => self.sa,
        }
    }
}
