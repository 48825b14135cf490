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

pub(crate) mod dense;
pub mod dopri5;
pub(crate) mod driven;
pub mod exact;
pub mod free;
pub mod harmonic;
pub mod linear;
pub mod noise;
pub mod phase;
pub mod random;
pub mod rk4;

use serde::Serialize;

use crate::model::{RangeError, fmt_value};

pub use free::simulate;
pub use harmonic::{Drive, Harmonic, HarmonicRecord, simulate_harmonic};
pub use phase::{State, Wall, impact};

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

/// Which solver moves the main mass between events.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// Closed form between events, guaranteed root brackets, impact times to `tol`.
    Exact,
    /// Classical fixed-step Runge–Kutta 4 with step `h`; events on the step's cubic Hermite
    /// interpolant, event states by re-integration. Error O(h^4).
    Rk4,
    /// Adaptive Dormand–Prince 5(4) with `rtol`/`atol`, FSAL, events on its dense output.
    Dopri5,
}

impl SolverKind {
    pub const ALL: [SolverKind; 3] = [SolverKind::Exact, SolverKind::Rk4, SolverKind::Dopri5];

    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Exact => "exact",
            SolverKind::Rk4 => "rk4",
            SolverKind::Dopri5 => "dopri5",
        }
    }

    /// The name of the knob that sets this solver's accuracy (`tol`, `h` or `rtol`).
    pub fn knob(self) -> &'static str {
        match self {
            SolverKind::Exact => "tol",
            SolverKind::Rk4 => "h",
            SolverKind::Dopri5 => "rtol",
        }
    }

    pub fn parse(s: &str) -> Option<SolverKind> {
        SolverKind::ALL.into_iter().find(|k| k.name() == s)
    }
}

/// Solver settings. Every field documents its unit, default and valid range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolverSettings {
    /// The solver. Default `exact`.
    pub kind: SolverKind,
    /// Event-location tolerance, relative to the undamped period `2 pi sqrt(M/K)`: `exact`
    /// locates every event time within `tol * period` of the true root; `rk4` and `dopri5` refine
    /// event times on their interpolant to `tol * period`. Default `1e-12`, range `[1e-15, 1e-3]`.
    pub tol: f64,
    /// Step of `rk4` (s). Default `1e-4` (about `T/1000` for the Table I system, whose period is
    /// `T = 0.0993 s`), range `[1e-9, 1]`. RK4 is stable while `h` times the fastest rate
    /// (`sqrt(K/M)`, or `C/M` when heavily over-damped) stays below about 2.8.
    pub h: f64,
    /// Relative tolerance of `dopri5` (per step, on `x` and `v`). Default `1e-6`, range
    /// `[1e-14, 1e-1]`.
    pub rtol: f64,
    /// Absolute tolerance of `dopri5` (m): applied to `x` as is and to `v` as
    /// `atol * sqrt(K/mass)` (m/s), so both components are measured in metres of amplitude.
    /// Default `1e-9`, range `[1e-18, 1e-1]`.
    pub atol: f64,
    /// Chatter tolerance, relative to the undamped period: an accumulation of impacts whose
    /// predicted remaining duration `2 u / (a (1 - e))` is below `chatter_tol * period` is replaced by
    /// sticking (see [`phase`]). Default `1e-6`, range `[1e-12, 1e-2]`.
    pub chatter_tol: f64,
    /// At most this many impacts, then the run ends with outcome `event_cap`. Default `100000`.
    pub max_impacts: u64,
    /// At most this many solver steps, then the run ends with outcome `step_cap`. Default `10^7`.
    pub max_steps: u64,
    /// Longest simulated time without a fixed horizon, in undamped periods; a run that has not
    /// found its peaks by then ends with `no_second_peak` (or `few_peaks`). Default `200`.
    pub t_max_periods: f64,
}

impl SolverSettings {
    /// The value of this solver's accuracy knob (see [`SolverKind::knob`]).
    pub fn knob_value(&self) -> f64 {
        match self.kind {
            SolverKind::Exact => self.tol,
            SolverKind::Rk4 => self.h,
            SolverKind::Dopri5 => self.rtol,
        }
    }

    /// The solver keys `simulate --set` and a study's `[solver]` table accept.
    pub const KEYS: [&'static str; 10] = [
        "solver",
        "tol",
        "h",
        "rtol",
        "atol",
        "chatter_tol",
        "max_impacts",
        "max_steps",
        "t_max_periods",
        "peaks",
    ];

    /// Checks every knob's range; the error names the key, the value and the range.
    pub fn validate(&self) -> Result<(), RangeError> {
        let check = |key: &str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && v >= lo && v <= hi {
                Ok(())
            } else {
                Err(RangeError::new(
                    key,
                    v,
                    format!("must be in [{}, {}]", fmt_value(lo), fmt_value(hi)),
                ))
            }
        };
        check("tol", self.tol, 1e-15, 1e-3)?;
        check("h", self.h, 1e-9, 1.0)?;
        check("rtol", self.rtol, 1e-14, 1e-1)?;
        check("atol", self.atol, 1e-18, 1e-1)?;
        check("chatter_tol", self.chatter_tol, 1e-12, 1e-2)?;
        check("max_impacts", self.max_impacts as f64, 1.0, 1e9)?;
        check("max_steps", self.max_steps as f64, 1.0, 1e12)?;
        check("t_max_periods", self.t_max_periods, 1.0, 1e6)?;
        Ok(())
    }
}

impl Request {
    /// Checks `peaks >= 1`, `t_end > 0` and `trace_dt > 0` when given.
    pub fn validate(&self) -> Result<(), RangeError> {
        if self.peaks < 1 || self.peaks > 1_000_000 {
            return Err(RangeError::new(
                "peaks",
                self.peaks as f64,
                "must be an integer in [1, 1000000]",
            ));
        }
        for (key, v) in [("t_end", self.t_end), ("dt", self.trace_dt)] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                return Err(RangeError::new(key, v, "must be a finite time > 0 (s)"));
            }
        }
        Ok(())
    }
}

impl NoiseSettings {
    /// Checks `power >= 0` and `sample_time > 0`, both finite.
    pub fn validate(&self) -> Result<(), RangeError> {
        if !(self.power.is_finite() && self.power >= 0.0) {
            return Err(RangeError::new(
                "power",
                self.power,
                "the noise power must be a finite number >= 0 (m^2 s)",
            ));
        }
        if !(self.sample_time.is_finite() && self.sample_time > 0.0) {
            return Err(RangeError::new(
                "sample_time",
                self.sample_time,
                "the sample time must be a finite number > 0 (s)",
            ));
        }
        Ok(())
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            kind: SolverKind::Exact,
            tol: 1e-12,
            h: 1e-4,
            rtol: 1e-6,
            atol: 1e-9,
            chatter_tol: 1e-6,
            max_impacts: 100_000,
            max_steps: 10_000_000,
            t_max_periods: 200.0,
        }
    }
}

/// What a run must produce; the horizon follows from it (model.md §3, "model only what a scene
/// requires").
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Request {
    /// Positive half-cycle maxima wanted (>= 1). Default 2 (what `DI` needs): the run stops at
    /// the end of the `peaks`-th positive half-cycle.
    pub peaks: usize,
    /// A fixed horizon (s): the run goes to `t_end` whatever the peaks. Default none.
    pub t_end: Option<f64>,
    /// Emit the state every `trace_dt` seconds to the probe (for waveform plots). Default none.
    pub trace_dt: Option<f64>,
}

impl Default for Request {
    fn default() -> Self {
        Request {
            peaks: 2,
            t_end: None,
            trace_dt: None,
        }
    }
}

/// Band-limited white noise on the measured displacement, Simulink style (model.md §4):
/// independent Gaussian samples every `sample_time` seconds with variance `power / sample_time`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NoiseSettings {
    /// Noise power `P` (m^2 s), `>= 0`.
    pub power: f64,
    /// Sample time `Ts` (s), `> 0`.
    pub sample_time: f64,
}

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

/// Observer of a run's events, for traces and tests. Every method defaults to doing nothing, so
/// a sweep pays nothing for it.
pub trait Probe {
    /// An impact at `t` on `wall`: the state just before, as located (its `y - x` is within the
    /// event tolerance of the wall), and just after (inner mass exactly on the wall).
    fn impact(&mut self, _t: f64, _wall: Wall, _before: &State, _after: &State) {}
    /// The same for unit `unit` of several (model.md §14): `before` and `after` hold the main
    /// mass's state and that unit's. By default [`Probe::impact`].
    fn impact_of(&mut self, t: f64, _unit: usize, wall: Wall, before: &State, after: &State) {
        self.impact(t, wall, before, after);
    }
    /// A sticking phase begins at `t` on `wall` (after the plastic closing of a chatter).
    fn stick(&mut self, _t: f64, _wall: Wall, _state: &State) {}
    /// The inner mass leaves `wall` at `t`.
    fn separate(&mut self, _t: f64, _wall: Wall, _state: &State) {}
    /// A trace sample (only with [`Request::trace_dt`]).
    fn sample(&mut self, _t: f64, _state: &State) {}
    /// Any event, with the total mechanical energy after it (J).
    fn energy(&mut self, _t: f64, _energy: f64) {}
}

/// Collects trace rows: samples every [`Request::trace_dt`] and the state before every impact.
#[derive(Default)]
pub struct TraceProbe {
    pub rows: Vec<(f64, State)>,
}

impl Probe for TraceProbe {
    fn impact(&mut self, t: f64, _wall: Wall, before: &State, _after: &State) {
        self.rows.push((t, *before));
    }
    fn sample(&mut self, t: f64, state: &State) {
        self.rows.push((t, *state));
    }
}

/// A probe that observes nothing.
pub struct NoProbe;
impl Probe for NoProbe {}
