//! The simulator: one system + solver settings + what is asked → one [`Record`].
//!
//! A pure function ([`simulate`]): no I/O, no global state, the noise generator passed in.
//! The physics is `docs/model.md` §1–3:
//!
//! * between impacts the main mass is a free damped oscillator `M x'' + C x' + K x = 0` and the
//!   inner mass moves at constant velocity (`y'' = 0`), see [`linear`];
//! * an impact happens when `|y - x| = d/2` and obeys the momentum-conserving law (eq. 3–4)
//!   ```text
//!   x'_a = ((M - m e) x'_b + m (1 + e) y'_b) / (M + m)
//!   y'_a = (M (1 + e) x'_b + (m - M e) y'_b) / (M + m)
//!   ```
//!   see [`impact`];
//! * chatter (an accumulation of impacts on a wall that accelerates into the inner mass) is
//!   detected and replaced by sticking: the pair moves as one oscillator of mass `M + m` until the
//!   contact force would have to pull (see [`phase`] for the rule and its error);
//! * observables: positive half-cycle maxima `X_k, t_k`, `xmax`, the damping inclination
//!   `DI = (X1 - X2) / (t2 - t1)` (eq. 5, m/s), impact and sticking counts, energy lost in
//!   impacts and in the damper.
//!
//! That is the free-decay scene. The forced scene (model.md §8, a harmonic force on the main
//! mass, run to its steady state) lives in [`harmonic`]; [`Scene`] and [`simulate_scene`] pick
//! one, and [`simulate`] is free decay exactly as it always was. The random and record scenes
//! (model.md §13, a random load per realization or a recorded one) live in [`random`]; the
//! sweep does not run them yet, so [`Scene`] does not name them.
//!
//! Solvers share all of that and differ only in how they move the main mass between events and
//! locate those events: [`SolverKind::Exact`] uses the closed form and a root bracket that cannot
//! miss an impact (see [`exact`]); [`SolverKind::Rk4`] (fixed step, see [`rk4`]) and
//! [`SolverKind::Dopri5`] (adaptive Dormand–Prince 5(4), see [`dopri5`]) integrate the equation
//! of motion and locate events on each step's interpolant (see [`dense`]).
//!
//! The types every scene and solver shares live in leaves below them, re-exported here so that
//! `crate::sim::Record` and the like name them from outside: [`settings`] ([`SolverSettings`],
//! [`SolverKind`]), [`request`] ([`Request`]), [`record`] ([`Record`], [`Outcome`]), [`probe`]
//! ([`Probe`], [`TraceProbe`], [`NoProbe`]), [`noise`] ([`NoiseSettings`]) and [`phase`]
//! ([`State`], [`Wall`]). The modules of `sim/` import them from there, never from this file,
//! whose own code ([`Scene`], [`simulate_scene`]) uses the scenes: no import circle.

pub(crate) mod dense;
pub mod dopri5;
pub(crate) mod driven;
pub mod exact;
pub mod free;
pub mod harmonic;
pub mod linear;
pub mod math;
pub mod noise;
pub mod phase;
pub mod probe;
pub mod random;
pub mod record;
pub mod request;
pub mod rk4;
pub mod settings;

use serde::Serialize;

pub use free::simulate;
pub use harmonic::{Drive, Harmonic, HarmonicRecord, simulate_harmonic};
pub use noise::NoiseSettings;
pub use phase::{State, Wall, impact};
pub use probe::{NoProbe, Probe, TraceProbe};
pub use record::{Outcome, Record};
pub use request::Request;
pub use settings::{SolverKind, SolverSettings};

/// What a run simulates: the paper's free decay, or steady-state forced vibration (model.md §8).
/// A study states its scene; the free-decay scene is exactly what [`simulate`] does.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Scene {
    /// Free decay from the initial state (model.md §1–3): [`Record`].
    Free,
    /// Harmonic force `F0 cos(omega t)` on the main mass, steady state: [`HarmonicRecord`].
    Harmonic(Harmonic),
    /// A random or recorded load (model.md §13): [`random::RandomRecord`]. A record's samples
    /// are shared ([`random::Recorded`]), so a clone is cheap.
    Random(random::RandomScene),
}

impl Scene {
    /// The scene names `--set scene=` and a study's `[scene] kind` accept.
    pub const NAMES: [&'static str; 2] = ["free", "harmonic"];

    pub fn name(&self) -> &'static str {
        match self {
            Scene::Free => "free",
            Scene::Harmonic(_) => "harmonic",
            Scene::Random(_) => "random",
        }
    }

    /// The harmonic scene's settings; `None` for another scene. A scene's own modules read their
    /// settings through these accessors, so that only the dispatch points name every scene.
    pub fn harmonic(&self) -> Option<&Harmonic> {
        match self {
            Scene::Harmonic(h) => Some(h),
            _ => None,
        }
    }

    /// [`Scene::harmonic`], to change.
    pub fn harmonic_mut(&mut self) -> Option<&mut Harmonic> {
        match self {
            Scene::Harmonic(h) => Some(h),
            _ => None,
        }
    }

    /// The harmonic settings of a harmonic scene, the default ones for another (what a run of
    /// another scene's study reads where it needs a forcing, e.g. a harmonic record's columns).
    pub fn harmonic_or_default(&self) -> Harmonic {
        self.harmonic().copied().unwrap_or_default()
    }

    /// The random or record scene's settings; `None` for another scene.
    pub fn random(&self) -> Option<&random::RandomScene> {
        match self {
            Scene::Random(r) => Some(r),
            _ => None,
        }
    }

    /// [`Scene::random`], to change.
    pub fn random_mut(&mut self) -> Option<&mut random::RandomScene> {
        match self {
            Scene::Random(r) => Some(r),
            _ => None,
        }
    }

    /// Sets a sweepable key of the scene ([`Harmonic::AXES`]); `false` for the free scene (it
    /// has none) and for any other key.
    pub fn set(&mut self, key: &str, value: f64) -> bool {
        match self {
            Scene::Free => false,
            Scene::Harmonic(h) => h.set(key, value),
            Scene::Random(r) => r.set(key, value),
        }
    }
}

/// The record of either scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SceneRecord {
    Free(Record),
    Harmonic(HarmonicRecord),
    Random(random::RandomRecord),
}

impl SceneRecord {
    pub fn outcome(&self) -> Outcome {
        match self {
            SceneRecord::Free(r) => r.outcome,
            SceneRecord::Harmonic(r) => r.outcome,
            SceneRecord::Random(r) => r.outcome,
        }
    }
}

/// Runs one system in `scene`: [`simulate`] for free decay, [`simulate_harmonic`] for the forced
/// scene, [`random::simulate_random`] for a random or recorded load (a random load's
/// realization 0 of study seed 0 at design point 0; `noise` is not used: the load is the
/// scene's). Pure, as all three are.
pub fn simulate_scene<P: Probe>(
    sys: &crate::model::System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Scene,
    noise: Option<(&NoiseSettings, &mut noise::NoiseStream)>,
    probe: &mut P,
) -> SceneRecord {
    match scene {
        Scene::Free => SceneRecord::Free(simulate(sys, settings, req, noise, probe)),
        Scene::Harmonic(h) => {
            SceneRecord::Harmonic(simulate_harmonic(sys, settings, req, h, noise, probe))
        }
        Scene::Random(r) => SceneRecord::Random(random::simulate_random(
            sys,
            settings,
            req,
            r,
            random::RealizationStream::new(0, 0, 0),
            probe,
        )),
    }
}
