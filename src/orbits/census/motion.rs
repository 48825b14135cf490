//! What a census start is given and what it finds, shared by the census and its starts
//! ([`mod@super::start`]): the settings, how an attractor was first reached, the exponent of a
//! tangent-map probe, and what is known of a motion that is not periodic.

use super::cloud::{CHAOS_FLOOR, Cloud};
use crate::orbits::life::LifeSummary;
use crate::orbits::map::Section;
use crate::orbits::shoot::Orbit;

/// The census's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CensusSettings {
    /// Starts per frequency point (start 0 is the study's initial state), `>= 1`.
    pub starts: u32,
    /// Periods a start may run before it is measured as non-periodic.
    pub max_periods: u64,
    /// Relative `p`-step difference at which Newton takes over. Default `1e-3`.
    pub handover: f64,
    /// Measurement window of a non-periodic motion (forcing periods). Default 200.
    pub window: u64,
    /// The study seed and the design point: they fix the starts.
    pub seed: u64,
    pub point: u64,
    /// Periods start 0 has already run without converging (the run from the initial state it
    /// goes on from): they count toward its budget. 0 by default.
    pub spent0: u64,
}

/// What is known of a motion that is not periodic.
#[derive(Clone, Debug, PartialEq)]
pub struct Wandering {
    /// Where in the section it wanders (from its probe, or its window).
    pub cloud: Cloud,
    /// The tangent-map probe of its first wandering periods (`None` when the start's first
    /// check came at the end of its budget).
    pub probe: Option<ProbeResult>,
    /// It ran its whole budget without reaching a periodic orbit.
    pub exhausted: bool,
    /// Stable periodic orbits found by Newton from its close returns ([`super::close_returns`]).
    pub embedded: Vec<Orbit>,
    /// Its largest amplitude over the design life, when the curve's race measured it
    /// ([`crate::orbits::race`]).
    pub life: Option<LifeSummary>,
    /// States on it of other starts that joined it (at most [`super::CHAINS`] - 1): the race
    /// measures its life from these and its own section, one run each.
    pub chains: Vec<Section>,
}

/// The exponent a tangent-map probe measured (`cloud::ChaosProbe`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeResult {
    /// Largest Lyapunov exponent per forcing period and its standard error.
    pub lambda: f64,
    pub se: f64,
    pub periods: u64,
}

impl ProbeResult {
    /// Chaotic: `lambda > 3 se` and above [`CHAOS_FLOOR`].
    pub fn chaotic(&self) -> bool {
        self.lambda > 3.0 * self.se && self.lambda > CHAOS_FLOOR
    }
}

/// How an attractor of a census was first reached.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Census start `k` (0: the study's initial state).
    Start(u32),
    /// Continued from an attractor of the next lower frequency of the curve (the up pass).
    Up,
    /// Continued from an attractor of the next higher frequency (the down pass).
    Down,
    /// A stable periodic orbit found by Newton from the close returns of a wandering motion
    /// ([`super::close_returns`]); no start is known to reach it.
    Recurrence,
}

impl Origin {
    /// The name stored in the `origin` column.
    pub fn name(self) -> &'static str {
        match self {
            Origin::Start(_) => "start",
            Origin::Up => "up",
            Origin::Down => "down",
            Origin::Recurrence => "recurrence",
        }
    }
}
