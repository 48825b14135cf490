//! The one event map every scene uses (free decay, [`super::free`]; the forced scene,
//! [`super::harmonic`]; the random and record scenes, [`super::random`]), and the types the solvers
//! share, so that nothing in `sim/` imports in a circle: the solvers ([`super::exact`],
//! [`super::dense`] with [`super::rk4`] and [`super::dopri5`], [`super::driven`]) import this
//! module and [`super::linear`] only; the scenes import the solvers.
//!
//! A solver moves the main mass through one smooth phase and reports the first watched
//! [`Event`] ([`PhaseSolver`]); what happens at the event (the impact law at a wall, the chatter
//! rule, sticking and separation) is the same in both scenes and lives here.
//!
//! # Phases
//! * **Free**: the main mass is the oscillator `(M, K, C)` (driven by `F0 cos(omega t)` in the
//!   forced scene, by a load linear between samples in the random scene); the inner mass moves
//!   at constant velocity (under ground acceleration `a_g`, displacements relative to the
//!   ground, with `y'' = -a_g`: [`Motion::inner_accel`]); events are the walls, `x = 0`,
//!   `v = 0` (in positive half-cycles, or in the forced scene's measurement window) and time
//!   limits.
//! * **Stuck** on a wall: the pair is the oscillator `(M + m, K, C)` (driven alike) with
//!   `y = x ± d/2`; it separates when the contact force would have to pull: on the right wall
//!   contact holds while the pair's acceleration is `<= 0`, i.e. while `C v + K x >= 0`
//!   (`C v + K x - F0 cos(omega t) >= 0` when forced); on the left wall the reverse.
//!
//! # Chatter rule
//! After an impact on a wall, let `u >= 0` be the speed at which the inner mass leaves it and
//! `a` the acceleration with which the wall moves toward the inner mass (`a = -(x'' - y'')` on
//! the right wall, `+(x'' - y'')` on the left, from the free main mass's acceleration and the
//! inner mass's own, which is zero unless the ground accelerates). If `a > 0` the inner mass comes
//! back after `2u/a`, the next rebound is `e` times slower, and the impacts accumulate at a
//! finite time `2u / (a (1 - e))` later (a Zeno point). When that remaining time is below
//! `chatter_tol * period`, the rest of the sequence is replaced by its limit: a plastic impact
//! (relative velocity to zero, momentum conserved, the remaining relative kinetic energy
//! `mu u^2 / 2`, `mu = M m / (M + m)`, counted as impact loss) and a sticking phase. The
//! neglected motion lasts at most `chatter_tol * period`, during which the inner mass is never
//! more than `u^2 / (2a)` from the wall; the main mass's displacement error is of order
//! `(m / (M + m)) a (chatter_tol * period)^2`, about `4 pi^2 chatter_tol^2` of the amplitude.
//! `e = 0` gives `u = 0` and sticks at the first impact where the force allows. For `e` near 1
//! the denominator uses `max(1 - e, chatter_tol)`, so a rebound slower than
//! `a chatter_tol^2 period / 2` also sticks and `e = 1` cannot chatter forever. The threshold
//! used is `max(chatter_tol, 10 tol)`: rebounds shorter than the event tolerance cannot be
//! resolved, and without this a loose `tol` left chatters running into the impact cap. The number of
//! impacts in one chatter sequence is therefore at most about
//! `ln(chatter_tol period a (1 - e) / 2 u0) / ln e`; the impact cap bounds the rest.
//!
//! # Events
//! A solver reports the first of: a wall reached by the inner mass during free flight
//! (`|y - x| = d/2`, heading into it), `x = 0` (the free scene's half-cycles), `v = 0` (extrema,
//! when watched), the separation of a stuck pair (the contact force reaching zero) and the time
//! limit the scene sets (samples, sections, the horizon); or that the state left the finite
//! numbers, or that its step cap was hit ([`StepCap`]). Each crossing is reported only toward
//! zero from the side the scene names (the `*_side` fields of [`Watch`]).
//!
//! # The loop
//! `run` is the one event loop: it asks the [`SceneEvents`] what to watch, lets the solver find the
//! first event, brings the [`EventMap`] (phase, state, counts, the sign of `v`) to it, and at a
//! wall applies the impact law and the chatter rule ([`EventMap::collide`]), at a separation
//! frees the pair ([`EventMap::separate`]), at `v = 0` flips the sign of `v`; the scene books
//! its observables, energies and probes at each step and decides at `x = 0` and at its time
//! limits when the run ends. The free scene's noise, peaks and horizon
//! ([`super::free`]) and the forced scene's sections, window and transient
//! ([`super::harmonic`]) stay in their modules.

use std::cmp::Ordering;

use serde::Serialize;

use super::linear::Oscillator;
use super::record::Outcome;
use super::settings::SolverSettings;
use crate::model::System;

/// A wall of the cavity: `Right` is `y - x = +d/2`, `Left` is `y - x = -d/2`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Wall {
    Left,
    Right,
}

impl Wall {
    /// `+1` for the right wall, `-1` for the left.
    #[inline]
    pub fn sign(self) -> f64 {
        match self {
            Wall::Right => 1.0,
            Wall::Left => -1.0,
        }
    }
}

/// Positions and velocities of both masses (m, m/s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct State {
    pub x: f64,
    pub v: f64,
    pub y: f64,
    pub w: f64,
}

/// The impact law (eq. 3–4): velocities just after an impact from those just before.
/// Conserves momentum `M v + m w` exactly up to rounding and reverses the relative velocity
/// scaled by `e`. Written as the change of each velocity,
/// `x'_a = x'_b + m (1 + e) (y'_b - x'_b) / (M + m)` and
/// `y'_a = y'_b + M (1 + e) (x'_b - y'_b) / (M + m)`, so that a massless inner mass (`m = 0`,
/// no damper) leaves the main mass's velocity exactly as it was.
#[inline]
#[allow(non_snake_case)]
pub fn impact(M: f64, m: f64, e: f64, v: f64, w: f64) -> (f64, f64) {
    let k = (1.0 + e) / (M + m);
    let rel = w - v;
    (v + m * k * rel, w - M * k * rel)
}

/// The inner mass's free motion from `t0` and the half clearance: a line
/// `y(t) = y0 + w (t - t0)`, or, when it accelerates (under ground acceleration, relative to the
/// ground), the cubic `y0 + w tau + ya tau^2 / 2 + yj tau^3 / 6`, `tau = t - t0`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Walls {
    pub t0: f64,
    pub y0: f64,
    pub w: f64,
    pub half_d: f64,
    /// `y''` at `t0` and `y'''` (m/s^2, m/s^3); both 0 for a line.
    pub ya: f64,
    pub yj: f64,
    /// A bound of `|y''|` until the phase ends (m/s^2).
    pub ya_max: f64,
}

impl Walls {
    /// `(y, y', y'', y''')` at `t`; on a line exactly `(y0 + w (t - t0), w, 0, 0)`.
    #[inline]
    pub fn at(&self, t: f64) -> (f64, f64, f64, f64) {
        let tau = t - self.t0;
        if self.ya == 0.0 && self.yj == 0.0 {
            return (self.y0 + self.w * tau, self.w, 0.0, 0.0);
        }
        let y = self.y0 + tau * (self.w + tau * (0.5 * self.ya + tau * self.yj / 6.0));
        let w = self.w + tau * (self.ya + 0.5 * tau * self.yj);
        (y, w, self.ya + tau * self.yj, self.yj)
    }

    /// The same line and clearance, bit for bit.
    #[inline]
    pub fn same(&self, o: &Walls) -> bool {
        let eq = |a: f64, b: f64| a.to_bits() == b.to_bits();
        eq(self.y0, o.y0)
            && eq(self.w, o.w)
            && eq(self.half_d, o.half_d)
            && eq(self.t0, o.t0)
            && eq(self.ya, o.ya)
            && eq(self.yj, o.yj)
            && eq(self.ya_max, o.ya_max)
    }

    /// Whether the gap `y - x` surely stays strictly inside `(-half_d, half_d)` from `t0` until
    /// `t1`, for a main mass now at `(x, v, a)` whose `|x'''|` stays below `jerk_max`. Taylor's
    /// theorem at `t0` bounds the gap by its quadratic `g0 + g1 tau + g2 tau^2 / 2` (with
    /// `g2 = y'' - a`) and a remainder `(jerk_max + |y'''|) tau^3 / 6`; the quadratic's largest
    /// `|.|` on `[0, tau1]` is at an end or its vertex. A margin of `1e-9` of the sizes covers
    /// the rounding. `false` when anything is not finite.
    #[inline]
    pub fn clear_until(&self, (x, v, a): (f64, f64, f64), jerk_max: f64, t1: f64) -> bool {
        let tau1 = t1 - self.t0;
        let (g0, g1, g2) = (self.y0 - x, self.w - v, self.ya - a);
        let q = |tau: f64| (g0 + tau * (g1 + 0.5 * g2 * tau)).abs();
        let mut top = q(0.0).max(q(tau1));
        if g2 != 0.0 {
            let vertex = -g1 / g2;
            if vertex > 0.0 && vertex < tau1 {
                top = top.max(q(vertex));
            }
        }
        let rest = (jerk_max + self.yj.abs()) * tau1 * tau1 * tau1 / 6.0;
        let margin = 1e-9 * (self.half_d + x.abs() + self.y0.abs());
        top + rest + margin < self.half_d
    }
}

/// What a solver watches during one call of [`PhaseSolver::next_event`]. Each `*_side` is the
/// sign the quantity has now (`+1`/`-1`); the solver reports when it reaches zero.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Watch {
    /// The walls, during free flight.
    pub walls: Option<Walls>,
    /// Sign of `x`, when half-cycles are being followed (the free scene).
    pub x_side: Option<f64>,
    /// Sign of `v`, when extrema are being looked for.
    pub v_side: Option<f64>,
    /// Extrema of `x` are located only where `|x|` can reach this (m); 0: every one. A solver
    /// that steps over an extremum below it reports `VZero` at the end of that step.
    pub x_floor: f64,
    /// The wall's sign while stuck: contact holds while that sign times the contact force
    /// (`C v + K x` in free decay, `C v + K x - F0 cos(omega t)` when forced) is `>= 0`.
    pub sep_side: Option<f64>,
    /// Stop here at the latest.
    pub t_limit: f64,
}

/// The first event a solver found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Event {
    Wall(Wall),
    XZero,
    VZero,
    Separation,
    Limit,
    NonFinite,
}

/// The solver's step cap was hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepCap;

/// The main mass's acceleration now, a bound of its jerk for the rest of the phase, and the
/// solver's time tolerance ([`PhaseSolver::reach`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reach {
    /// `x''` now (m/s^2).
    pub a: f64,
    /// A bound of `|x'''|` until the phase ends (m/s^3).
    pub jerk_max: f64,
    /// The events' time tolerance (s): a located event lies within it of the true one.
    pub tol_t: f64,
    /// The scene's own events (`x = 0`, `v = 0`, separation, and the watch's time limit) are
    /// found in closed form, at the same instant by every clone (the free scene's
    /// [`crate::sim::exact`]): a unit's whole search then runs no further past such a stop than
    /// a short one would ([`spared`]).
    pub closed_form_events: bool,
}

/// Moves the main mass through one smooth phase (free, or the stuck pair). A clone searches
/// from the same point on its own: with several units, one clone per unit looks for that
/// unit's walls ([`run`]).
pub(crate) trait PhaseSolver: Clone {
    /// The motion of a phase this solver follows ([`Oscillator`], or the forced one).
    type Motion: Motion;
    /// Starts a phase of `motion` at time `t` in state `(x, v)`.
    fn begin(&mut self, motion: &Self::Motion, t: f64, x: f64, v: f64);
    /// Advances to the first watched event (or `watch.t_limit`) and stops there.
    fn next_event(&mut self, watch: &Watch) -> Result<Event, StepCap>;
    /// The current time, displacement and velocity.
    fn state(&self) -> (f64, f64, f64);
    /// Steps taken so far.
    fn steps(&self) -> u64;
    /// Counts `n` more steps (the searches of the other units' clones) toward the step cap.
    fn add_steps(&mut self, n: u64);
    /// What [`EventMap::find`] needs to spare the searches of several units, when the solver
    /// has it. `None` (every unit searched to its own stop) by default.
    fn reach(&self, _watch: &Watch) -> Option<Reach> {
        None
    }
    /// The current phase in closed form, when the solver has it: the motion, the phase's
    /// start time and its state there. The free scene then evaluates noise samples itself, by a
    /// constant propagator, instead of stopping the solver at each.
    fn closed_form(&self) -> Option<(Self::Motion, f64, f64, f64)> {
        None
    }
}

/// The motion of one phase's main mass, as the event map needs it: the free oscillator of free
/// decay ([`Oscillator`]), the forced one ([`super::harmonic::motion::Forced`]) or the random
/// scene's ([`super::random`]).
pub(crate) trait Motion: Copy {
    /// The acceleration `x''` at time `t` in state `(x, v)` (m/s^2).
    fn accel_at(&self, t: f64, x: f64, v: f64) -> f64;

    /// The same motion for a main mass of `mass` (kg): the stuck units ride with it.
    fn with_mass(&self, mass: f64) -> Self;

    /// The free inner mass's acceleration `y''` at `t`, its derivative `y'''` and a bound of
    /// `|y''|` until the phase ends (m/s^2, m/s^3, m/s^2): zero unless the ground accelerates
    /// (then `y'' = -a_g`, displacements relative to the ground).
    #[inline]
    fn inner_accel(&self, _t: f64) -> (f64, f64, f64) {
        (0.0, 0.0, 0.0)
    }
}

impl Motion for Oscillator {
    /// `-(c v + k x) / mass`: time plays no part.
    #[inline]
    fn accel_at(&self, _t: f64, x: f64, v: f64) -> f64 {
        self.accel(x, v)
    }

    fn with_mass(&self, mass: f64) -> Self {
        Oscillator::new(mass, self.k, self.c)
    }
}

/// A phase of the event map: free flight, or the pair stuck on a wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Phase {
    Free,
    Stuck(Wall),
}

/// What one impact did ([`EventMap::collide`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    /// The unit that hit (0 with one unit; model.md §14).
    pub unit: usize,
    /// With several units, at the first unit of one impact: the total energy just before it
    /// (J); `None` at the others and with one unit.
    pub lead: Option<f64>,
    pub wall: Wall,
    /// The state just before, as located (its `y - x` is within the event tolerance of the
    /// wall).
    pub before: State,
    /// Just after the impact law, the inner mass exactly on the wall.
    pub after: State,
    /// The chatter rule closed the sequence: the map's state is the stuck pair's, after the
    /// plastic closing.
    pub stuck: bool,
}

/// The state of the event map both scenes share: the phase, the two masses, the impact and
/// sticking counts and the sign of `v` (for extrema). The scene owns its clock's meaning: `t`
/// is the solver's time (absolute in free decay, since the last section when forced).
pub(crate) struct EventMap<'a, M> {
    pub sys: &'a System,
    pub settings: &'a SolverSettings,
    /// The free main mass (`M`, `K`, `C`, and the force when forced).
    pub free: M,
    /// The stuck pair (mass `M + m`).
    pub pair: M,
    /// The undamped period `2 pi sqrt(M/K)` (s), the chatter rule's time scale.
    pub period: f64,
    pub phase: Phase,
    pub t: f64,
    pub s: State,
    /// The sign `v` has now or is about to take (flipped at each watched `v = 0`, re-read after
    /// each impact).
    pub v_side: f64,
    /// Impacts so far (a chatter sequence ended by sticking counts its impacts).
    pub impacts: u64,
    /// Sticking phases entered.
    pub sticks: u64,
    /// Several units (model.md §14): each unit's state; empty with one unit, whose state is
    /// `s.y`, `s.w` and `phase` (then nothing below is read). With several, `s.y`, `s.w`
    /// mirror unit 0, and `phase` is `Stuck` while any unit is.
    pub units: Vec<UnitState>,
    /// With several units: the mass the main mass carries (kg), its own and the stuck units',
    /// and the motion of that mass.
    pub carried: f64,
    pub carrying: M,
    /// With several units: each unit's line during the current search (`None` while stuck).
    lines: Vec<Option<Line>>,
    /// With several units: the free units to search and when each is due, nearest first
    /// ([`EventMap::search_order`]), and each one's stop; kept between searches so that a
    /// search allocates and clears nothing of the units it does not carry.
    order: Vec<(f64, usize)>,
    stops: Vec<f64>,
    /// With several units: the units an impact moves and what it did to each
    /// ([`EventMap::collide_units`]), kept between impacts so that an impact allocates nothing.
    hit_units: Vec<(usize, Wall)>,
    hits: Vec<Hit>,
}

/// One unit's state in a system of several (model.md §14).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct UnitState {
    /// Mass (kg), half clearance (m), restitution.
    pub m: f64,
    pub half_d: f64,
    pub e: f64,
    /// Position (m) and velocity (m/s).
    pub y: f64,
    pub w: f64,
    /// The wall it is stuck on, riding with the main mass.
    pub stuck: Option<Wall>,
    /// Its impacts so far.
    pub impacts: u64,
}

/// A free unit's line during one search and where its own search stopped: at its wall
/// (`hit`), or at the search's other first event.
#[derive(Clone, Copy, Debug)]
struct Line {
    walls: Walls,
    hit: Option<Wall>,
}

impl<'a, M: Motion> EventMap<'a, M> {
    /// At `t = 0` in the system's initial state, free, with `v_side = +1`.
    pub fn new(sys: &'a System, settings: &'a SolverSettings, free: M, pair: M) -> Self {
        let units: Vec<UnitState> = if sys.unit_count() > 1 {
            sys.unit_list()
                .iter()
                .map(|u| UnitState {
                    m: u.m,
                    half_d: 0.5 * u.d,
                    e: u.e,
                    y: u.y0,
                    w: u.w0,
                    stuck: None,
                    impacts: 0,
                })
                .collect()
        } else {
            Vec::new()
        };
        EventMap {
            sys,
            settings,
            free,
            pair,
            period: sys.period(),
            phase: Phase::Free,
            t: 0.0,
            s: State {
                x: sys.x0,
                v: sys.v0,
                y: sys.y0,
                w: sys.w0,
            },
            v_side: 1.0,
            impacts: 0,
            sticks: 0,
            lines: Vec::with_capacity(units.len()),
            order: Vec::with_capacity(units.len()),
            stops: Vec::with_capacity(units.len()),
            hit_units: Vec::with_capacity(units.len()),
            hits: Vec::with_capacity(units.len()),
            units,
            carried: sys.M,
            carrying: free,
        }
    }

    /// Back to the state [`EventMap::new`] leaves, at `s` in place of the system's initial
    /// state (one unit): a run of one forcing period after another ([`crate::sim::harmonic`]'s
    /// `simulate_periods`) reuses one map, each period the bits of a map built anew.
    pub fn restart(&mut self, s: State) {
        debug_assert!(!self.several());
        self.phase = Phase::Free;
        self.t = 0.0;
        self.s = s;
        self.v_side = 1.0;
        self.impacts = 0;
        self.sticks = 0;
        self.carried = self.sys.M;
        self.carrying = self.free;
    }

    /// Several units (model.md §14), not the paper's one.
    #[inline]
    pub fn several(&self) -> bool {
        !self.units.is_empty()
    }

    /// The total mechanical energy (J) of the map's state: both kinetic energies (every
    /// unit's) and the spring's potential energy.
    pub fn energy(&self) -> f64 {
        let s = &self.s;
        if !self.several() {
            return self.sys.energy(s.x, s.v, s.w);
        }
        let units: f64 = self.units.iter().map(|u| u.m * u.w * u.w).sum();
        0.5 * (self.sys.M * s.v * s.v + units + self.sys.K * s.x * s.x)
    }

    /// The motion of the current phase.
    pub fn motion(&self) -> &M {
        if self.several() {
            return &self.carrying;
        }
        match self.phase {
            Phase::Free => &self.free,
            Phase::Stuck(_) => &self.pair,
        }
    }

    /// Starts the current phase on `solver` at the map's time and state.
    pub fn begin<S: PhaseSolver<Motion = M>>(&self, solver: &mut S) {
        solver.begin(self.motion(), self.t, self.s.x, self.s.v);
    }

    /// The sign `v` has now or is about to take, in the current phase.
    pub fn v_sign(&self) -> f64 {
        let a = self.motion().accel_at(self.t, self.s.x, self.s.v);
        side_of(self.s.v, a, 0.0)
    }

    /// What the current phase watches: the walls during free flight (the inner mass's line from
    /// now), the wall's sign for the separation while stuck.
    pub fn contact(&self) -> (Option<Walls>, Option<f64>) {
        if self.several() {
            // Every free unit's walls are searched by a clone of its own ([`run`]).
            let stuck = self.units.iter().find_map(|u| u.stuck);
            return (None, stuck.map(Wall::sign));
        }
        match self.phase {
            Phase::Free => {
                let (ya, yj, ya_max) = self.free.inner_accel(self.t);
                (
                    Some(Walls {
                        t0: self.t,
                        y0: self.s.y,
                        w: self.s.w,
                        half_d: 0.5 * self.sys.d,
                        ya,
                        yj,
                        ya_max,
                    }),
                    None,
                )
            }
            Phase::Stuck(wall) => (None, Some(wall.sign())),
        }
    }

    /// Brings the map to the solver's point `(t, x, v)`: the inner mass on its line while free
    /// (`walls`, as watched), on the wall with the main mass's velocity while stuck, carried
    /// along at its initial place in the cavity when no walls were watched in free flight (a
    /// massless inner mass, which the forced scene does not simulate).
    pub fn follow(&mut self, (t, x, v): (f64, f64, f64), walls: &Option<Walls>) {
        self.t = t;
        self.s.x = x;
        self.s.v = v;
        match (self.phase, walls) {
            (Phase::Free, Some(wl)) => (self.s.y, self.s.w, _, _) = wl.at(t),
            (Phase::Free, None) => {
                self.s.y = x + (self.sys.y0 - self.sys.x0);
                self.s.w = v;
            }
            (Phase::Stuck(wall), _) => {
                self.s.y = x + wall.sign() * 0.5 * self.sys.d;
                self.s.w = v;
            }
        }
    }

    /// Applies the impact law on `wall`, then decides between rebound and sticking by the
    /// chatter rule (module doc), with the free main mass's acceleration. The probe is the
    /// scene's: it reports [`Hit`].
    pub fn collide(&mut self, wall: Wall) -> Hit {
        let sys = self.sys;
        let sign = wall.sign();
        // The state as located; then the inner mass is put exactly on the wall (the event is
        // within tolerance of it) so the next phase starts from the wall.
        let before = self.s;
        self.s.y = self.s.x + sign * 0.5 * sys.d;
        let (va, wa) = impact(sys.M, sys.m, sys.e, before.v, before.w);
        self.s.v = va;
        self.s.w = wa;
        self.impacts += 1;
        let after = self.s;
        // Speed away from the wall and the wall's acceleration toward the inner mass (relative
        // to the inner mass's own).
        let u = (sign * (self.s.v - self.s.w)).max(0.0);
        let relative =
            self.free.accel_at(self.t, self.s.x, self.s.v) - self.free.inner_accel(self.t).0;
        let a = -sign * relative;
        let stuck = chatter_ends(u, a, sys.e, self.settings, self.period);
        if stuck {
            // The plastic closing: relative velocity to zero, momentum conserved.
            let common = (sys.M * self.s.v + sys.m * self.s.w) / (sys.M + sys.m);
            self.s.v = common;
            self.s.w = common;
            self.sticks += 1;
            self.phase = Phase::Stuck(wall);
        } else {
            self.phase = Phase::Free;
        }
        Hit {
            unit: 0,
            lead: None,
            wall,
            before,
            after,
            stuck,
        }
    }

    /// Ends a sticking phase: the wall the inner mass leaves, if it was stuck.
    pub fn separate(&mut self) -> Option<Wall> {
        let left = match self.phase {
            Phase::Stuck(wall) => Some(wall),
            Phase::Free => None,
        };
        self.phase = Phase::Free;
        left
    }
}

/// Several units (model.md §14): each free unit's walls searched by a clone of the solver, the
/// simultaneous impact law, sticking per unit.
impl<'a, M: Motion> EventMap<'a, M> {
    /// A free unit's line from now.
    pub fn line_of(&self, u: &UnitState) -> Walls {
        let (ya, yj, ya_max) = self.carrying.inner_accel(self.t);
        Walls {
            t0: self.t,
            y0: u.y,
            w: u.w,
            half_d: u.half_d,
            ya,
            yj,
            ya_max,
        }
    }

    /// The first watched event with every free unit's walls: one clone of `solver` per free
    /// unit searches that unit's walls and the scene's other events; the earliest stop wins
    /// and `solver` becomes that clone. Every unit whose own search stopped at a wall at that
    /// same instant (identical units in step do, bit for bit) takes part in the impact. The
    /// other clones' steps count toward the cap. A unit whose bit is set in `clear` (it surely
    /// reaches neither wall before the watch's limit, [`SceneEvents::units_clear`]) is not
    /// searched; it follows its line.
    ///
    /// The searches are spared where they cannot win: the units are visited nearest first
    /// ([`EventMap::search_order`]); a unit on the same line as one visited before takes that
    /// one's stop; once a stop is found, a unit that cannot stop before it ([`spared`]) is
    /// not searched. The winner's search is always a whole search of its own, so an impact is
    /// the one the unit's own search finds, bit for bit. What can differ from searching every
    /// unit is which clone's stop ends a step at an event of the scene's own (an extremum,
    /// which two clones may place a rounding apart, or one under the floor that each reports
    /// at the end of its own step): the same motion to rounding.
    fn find<S: PhaseSolver<Motion = M>>(
        &mut self,
        solver: &mut S,
        watch: &Watch,
        clear: u64,
    ) -> Result<Event, StepCap> {
        #[cfg(test)]
        if let Some(reach) = solver.reach(watch)
            && sparing::checked()
        {
            return self.find_checked(solver, watch, clear, reach);
        }
        self.find_sparing(solver, watch, clear, solver.reach(watch))
    }

    /// [`EventMap::find`], sparing searches with `reach` (every unit searched without).
    fn find_sparing<S: PhaseSolver<Motion = M>>(
        &mut self,
        solver: &mut S,
        watch: &Watch,
        clear: u64,
        reach: Option<Reach>,
    ) -> Result<Event, StepCap> {
        let (_, x, v) = solver.state();
        let mut order = std::mem::take(&mut self.order);
        self.search_order(x, v, clear, &mut order);
        let mut stops = std::mem::take(&mut self.stops);
        stops.clear();
        stops.resize(self.units.len(), f64::NAN);
        let found = self.search_units(solver, (watch, reach), &order, &mut stops);
        self.order = order;
        self.stops = stops;
        found
    }

    /// The searches of [`EventMap::find_sparing`], the units in `order`, each one's stop into
    /// `stops`.
    fn search_units<S: PhaseSolver<Motion = M>>(
        &mut self,
        solver: &mut S,
        (watch, reach): (&Watch, Option<Reach>),
        order: &[(f64, usize)],
        stops: &mut [f64],
    ) -> Result<Event, StepCap> {
        let start = solver.steps();
        let (_, x, v) = solver.state();
        let mut best: Option<(S, Event, f64, usize)> = None;
        let mut spent = 0;
        // A short search pays where a whole one would run past the best stop ([`spared`]).
        let closed_form = reach.is_some_and(|r| r.closed_form_events);
        let short = |ev: &Event| matches!(ev, Event::Wall(_)) || !closed_form;
        for (k, &(_, i)) in order.iter().enumerate() {
            let Some(Line { walls, .. }) = self.lines[i] else {
                continue;
            };
            // A unit on the same line as one visited before (identical units in step) has
            // the same search, bit for bit: its stop and wall are that one's.
            let same = |j: &&(f64, usize)| self.lines[j.1].is_some_and(|l| l.walls.same(&walls));
            if let Some(&(_, j)) = order[..k].iter().find(same) {
                stops[i] = stops[j];
                let hit = self.lines[j].and_then(|l| l.hit);
                if let Some(l) = self.lines[i].as_mut() {
                    l.hit = hit;
                }
                continue;
            }
            let best_stop = best.as_ref().map(|b| (b.2, short(&b.1)));
            if let (Some(stop), Some(r)) = (best_stop, reach)
                && spared(solver, (&walls, watch), (x, v, r), stop, &mut spent)
            {
                continue;
            }
            let walls = Some(walls);
            let mut clone = solver.clone();
            let found = clone.next_event(&Watch { walls, ..*watch });
            spent += clone.steps() - start;
            let ev = match found {
                Ok(ev) => ev,
                Err(cap) => {
                    *solver = clone;
                    return Err(cap);
                }
            };
            let t = clone.state().0;
            stops[i] = t;
            if let (Event::Wall(wall), Some(l)) = (ev, self.lines[i].as_mut()) {
                l.hit = Some(wall);
            }
            // The earliest stop wins; of equal ones, the lowest unit's (the order of the
            // searches does not matter).
            if best
                .as_ref()
                .is_none_or(|b| t < b.2 || (t == b.2 && i < b.3))
            {
                best = Some((clone, ev, t, i));
            }
        }
        let Some((winner, ev, t, _)) = best else {
            // No unit searched: every unit is stuck (the main mass carries them all, only
            // separation is watched) or clear of its walls; the scene's other events alone.
            return solver.next_event(watch);
        };
        let own = winner.steps() - start;
        *solver = winner;
        solver.add_steps(spent - own);
        for (line, &stop) in self.lines.iter_mut().zip(stops.iter()) {
            if let Some(l) = line
                && stop != t
            {
                l.hit = None;
            }
        }
        Ok(ev)
    }

    /// Every unit's line from now into `self.lines` (`None` while stuck), and into `order` the
    /// free units to search, not in `clear`, nearest first: by the time the gap's line, `y - x`
    /// moving at `w - v`, takes to reach the wall it moves toward (with that time). The first
    /// stop found is then usually the earliest, and most others are spared ([`spared`]).
    fn search_order(&mut self, x: f64, v: f64, clear: u64, order: &mut Vec<(f64, usize)>) {
        self.lines.clear();
        order.clear();
        for i in 0..self.units.len() {
            let u = self.units[i];
            if u.stuck.is_some() {
                self.lines.push(None);
                continue;
            }
            let walls = self.line_of(&u);
            self.lines.push(Some(Line { walls, hit: None }));
            if (clear >> i) & 1 == 1 {
                continue;
            }
            let (g, g1) = (walls.y0 - x, walls.w - v);
            let room = walls.half_d - g.abs().min(walls.half_d);
            let toward = if g1 * g >= 0.0 { g1.abs() } else { 0.0 };
            let e = if toward > 0.0 {
                room / toward
            } else {
                (walls.half_d + walls.half_d - room) / g1.abs().max(f64::MIN_POSITIVE)
            };
            // Insertion by the time, ties in unit order.
            let k = order
                .iter()
                .rposition(|&(due, _)| due.partial_cmp(&e) != Some(Ordering::Greater))
                .map_or(0, |p| p + 1);
            order.insert(k, (e, i));
        }
    }

    /// Brings the map to the solver's point: free units on their lines, stuck ones on their
    /// walls with the main mass's velocity.
    fn follow_units(&mut self, (t, x, v): (f64, f64, f64)) {
        self.t = t;
        self.s.x = x;
        self.s.v = v;
        for (u, line) in self.units.iter_mut().zip(&self.lines) {
            match (u.stuck, line) {
                (Some(wall), _) => {
                    u.y = x + wall.sign() * u.half_d;
                    u.w = v;
                }
                (None, Some(l)) => (u.y, u.w, _, _) = l.walls.at(t),
                (None, None) => {}
            }
        }
        self.mirror();
    }

    /// `s.y`, `s.w` and `phase` from the units: unit 0's state, stuck while any unit is.
    fn mirror(&mut self) {
        self.s.y = self.units[0].y;
        self.s.w = self.units[0].w;
        self.phase = match self.units.iter().find_map(|u| u.stuck) {
            Some(wall) => Phase::Stuck(wall),
            None => Phase::Free,
        };
    }

    /// With several units: starts unit `i` at its own `(y_i, w_i)` (m, m/s) instead of the
    /// system's common `(y0, w0)`, for `i < starts.len()` (the stroboscopic map of several
    /// units, [`crate::orbits::units`]). Every unit starts free. Nothing with one unit.
    pub fn start_units(&mut self, starts: &[(f64, f64)]) {
        if !self.several() {
            return;
        }
        for (u, &(y, w)) in self.units.iter_mut().zip(starts) {
            u.y = y;
            u.w = w;
        }
        self.mirror();
    }

    /// Each unit's `(y, w)` now (m, m/s); with one unit, `(s.y, s.w)`.
    pub fn unit_states(&self) -> Vec<(f64, f64)> {
        if !self.several() {
            return vec![(self.s.y, self.s.w)];
        }
        self.units.iter().map(|u| (u.y, u.w)).collect()
    }

    /// With several units: the motion of the mass carried, anew from `free` (a scene whose
    /// free motion changes, the random scene's at each load interval, calls it after).
    pub fn carry_anew(&mut self) {
        if self.several() {
            self.carrying = if self.carried == self.sys.M {
                self.free
            } else {
                self.free.with_mass(self.carried)
            };
        }
    }

    /// The main mass now carries `mass`.
    fn carry(&mut self, mass: f64) {
        if mass != self.carried {
            self.carried = mass;
            self.carry_anew();
        }
    }

    /// The impact of every unit the search found at its wall, at once (model.md §14): with
    /// `r_i = w_i - v` and `b_i = (1 + e_i) r_i`, Newton's law at each contact gives
    /// `v' = v + S / M_t` and `w_i' = v' - e_i r_i`, `S = sum m_i b_i`,
    /// `M_t = M_c + sum m_i`, `M_c` the mass the main mass carries (its own and the stuck
    /// units', which ride with it unless the impulse moves the main mass away from them: then
    /// they are released first, with the velocity they had). One unit: eq. 3-4. Then the
    /// chatter rule per unit; the units that stick close plastically onto the main mass.
    /// Leaves one [`Hit`] per unit that hit, in unit order, in `self.hits` (the caller takes
    /// them and gives the vector back: [`run`]).
    fn collide_units(&mut self) {
        let mut hits = std::mem::take(&mut self.hit_units);
        hits.clear();
        hits.extend(
            self.lines
                .iter()
                .enumerate()
                .filter_map(|(i, l)| l.and_then(|l| l.hit).map(|w| (i, w))),
        );
        self.collide_these(&hits);
        self.hit_units = hits;
    }

    /// [`EventMap::collide_units`] for the units `hits` (unit, wall), in unit order.
    fn collide_these(&mut self, hits: &[(usize, Wall)]) {
        let (x, v) = (self.s.x, self.s.v);
        let energy = self.energy();
        // Each unit's state just before; the rest of each hit once the law has acted.
        let mut out = std::mem::take(&mut self.hits);
        out.clear();
        out.extend(hits.iter().map(|&(i, wall)| {
            let before = State {
                x,
                v,
                y: self.units[i].y,
                w: self.units[i].w,
            };
            Hit {
                unit: i,
                lead: None,
                wall,
                before,
                after: before,
                stuck: false,
            }
        }));
        let law = |units: &[UnitState], carried: f64| {
            let (mut sum, mut mt) = (0.0, carried);
            for &(i, _) in hits {
                let u = &units[i];
                sum += u.m * ((1.0 + u.e) * (u.w - v));
                mt += u.m;
            }
            sum / mt
        };
        let mut dv = law(&self.units, self.carried);
        let stuck_side = self.units.iter().find_map(|u| u.stuck).map(Wall::sign);
        if let Some(side) = stuck_side
            && side * dv > 0.0
            && !self.all_close(hits, v, dv)
        {
            // The impulse moves the main mass off the stuck units: they stay behind. (Not when
            // every unit that hit closes onto the main mass by the chatter rule: that is a
            // plastic joining, and releasing the stuck ones would only have them come back at
            // zero speed, an endless exchange of impulses of rounding size.)
            for u in &mut self.units {
                u.stuck = None;
            }
            self.carry(self.sys.M);
            dv = law(&self.units, self.carried);
        }
        let va = v + dv;
        self.s.v = va;
        self.impacts += 1;
        for &(i, wall) in hits {
            let u = &mut self.units[i];
            // The relative velocity reversed and scaled: `w_i' - v' = -e_i (w_i - v)`.
            u.w = va - u.e * (u.w - v);
            u.y = x + wall.sign() * u.half_d;
            u.impacts += 1;
        }
        for u in &mut self.units {
            if u.stuck.is_some() {
                u.w = va;
            }
        }
        // The chatter rule per unit, with the acceleration of the main mass as it carries now.
        let relative = self.wall_accel(va);
        let mut closing: Option<Wall> = None;
        for (k, h) in out.iter_mut().enumerate() {
            let u = self.units[h.unit];
            h.after = State {
                x,
                v: va,
                y: u.y,
                w: u.w,
            };
            h.stuck = self.closes(h.wall, u.e, u.w, va, relative);
            if h.stuck {
                closing = Some(h.wall);
                self.units[h.unit].stuck = Some(h.wall);
            }
            h.lead = (k == 0).then_some(energy);
        }
        if let Some(wall) = closing {
            self.close_onto(wall, &out, va);
        }
        self.carry_stuck();
        self.mirror();
        self.hits = out;
    }

    /// The plastic closing at `wall` after an impact that left the main mass at `va`: units
    /// stuck on the other wall let go (the main mass accelerates off them); the new stuck units
    /// of `out` and the main mass (with what it carried) move on at their common velocity,
    /// momentum conserved.
    fn close_onto(&mut self, wall: Wall, out: &[Hit], va: f64) {
        for u in &mut self.units {
            if u.stuck.is_some_and(|w| w != wall) {
                u.stuck = None;
            }
        }
        let (mut p, mut mass) = (self.carried * va, self.carried);
        for h in out.iter().filter(|h| h.stuck) {
            let u = &self.units[h.unit];
            p += u.m * u.w;
            mass += u.m;
        }
        let common = p / mass;
        self.s.v = common;
        for u in &mut self.units {
            if u.stuck.is_some() {
                u.w = common;
            }
        }
        self.sticks += 1;
    }

    /// The main mass carries its own mass and that of the stuck units.
    fn carry_stuck(&mut self) {
        let carried = self.sys.M
            + self
                .units
                .iter()
                .filter(|u| u.stuck.is_some())
                .map(|u| u.m)
                .sum::<f64>();
        self.carry(carried);
    }

    /// Whether every unit of `hits` would stick by the chatter rule after an impact that
    /// changes the main mass's velocity `v` by `dv` while it carries what it carries now.
    fn all_close(&self, hits: &[(usize, Wall)], v: f64, dv: f64) -> bool {
        let va = v + dv;
        let relative = self.wall_accel(va);
        hits.iter().all(|&(i, wall)| {
            let u = &self.units[i];
            self.closes(wall, u.e, va - u.e * (u.w - v), va, relative)
        })
    }

    /// The acceleration of the main mass as it carries now, at velocity `va`, relative to a
    /// free unit's own: what the chatter rule reads after an impact.
    fn wall_accel(&self, va: f64) -> f64 {
        self.carrying.accel_at(self.t, self.s.x, va) - self.carrying.inner_accel(self.t).0
    }

    /// The chatter rule for a unit of restitution `e` leaving `wall` at velocity `w` just after
    /// an impact that left the main mass at `va`, with `relative` from [`Self::wall_accel`].
    fn closes(&self, wall: Wall, e: f64, w: f64, va: f64, relative: f64) -> bool {
        let sign = wall.sign();
        let speed = (sign * (va - w)).max(0.0);
        chatter_ends(speed, -sign * relative, e, self.settings, self.period)
    }

    /// Ends a sticking phase: every stuck unit leaves the main mass (the contact force's zero
    /// does not depend on the mass carried, so all on one wall leave together). Returns how
    /// many left and from which wall.
    fn separate_units(&mut self) -> (usize, Option<Wall>) {
        let mut left = (0, None);
        for u in &mut self.units {
            if let Some(wall) = u.stuck.take() {
                left = (left.0 + 1, Some(wall));
            }
        }
        self.carry(self.sys.M);
        self.mirror();
        left
    }
}

/// Tests: [`EventMap::find`] checked against searching every unit at each call, on this thread.
#[cfg(test)]
pub(crate) mod sparing {
    use std::cell::Cell;

    /// What the check found: calls, those where the spared search stopped elsewhere than the
    /// full one, and how.
    #[derive(Clone, Copy, Debug, Default, PartialEq)]
    pub struct Tally {
        pub calls: u64,
        pub walls: u64,
        /// The full search's stop at an event of the scene (no wall), the spared one later
        /// (another clone's placing of it, or a wall after it).
        pub later: u64,
        /// The largest such delay over the watch's span.
        pub worst_later: f64,
    }

    thread_local! {
        static ON: Cell<Option<Tally>> = const { Cell::new(None) };
    }

    pub fn checked() -> bool {
        ON.with(|c| c.get().is_some())
    }

    /// Runs `f` with every several-units search checked; the tally.
    pub fn check(f: impl FnOnce()) -> Tally {
        ON.with(|c| c.set(Some(Tally::default())));
        f();
        ON.with(|c| c.take()).expect("on")
    }

    pub fn add(f: impl FnOnce(&mut Tally)) {
        ON.with(|c| {
            let mut t = c.get().expect("on");
            f(&mut t);
            c.set(Some(t));
        });
    }
}

#[cfg(test)]
impl<'a, M: Motion> EventMap<'a, M> {
    /// [`EventMap::find`] with sparing, checked against the search of every unit from the same
    /// point: where the full search stops at a wall, the spared one is the same bits (state,
    /// event, every unit's hit); elsewhere it stops no sooner, at an event of the scene's own.
    fn find_checked<S: PhaseSolver<Motion = M>>(
        &mut self,
        solver: &mut S,
        watch: &Watch,
        clear: u64,
        reach: Reach,
    ) -> Result<Event, StepCap> {
        let mut full = solver.clone();
        let t0 = solver.state().0;
        let ef = self.find_sparing(&mut full, watch, clear, None);
        let hits_full: Vec<_> = self.lines.iter().map(|l| l.map(|l| l.hit)).collect();
        let es = self.find_sparing(solver, watch, clear, Some(reach));
        let hits: Vec<_> = self.lines.iter().map(|l| l.map(|l| l.hit)).collect();
        let (Ok(ef), Ok(es)) = (ef, es) else {
            return es;
        };
        let (tf, ts) = (full.state().0, solver.state().0);
        sparing::add(|t| t.calls += 1);
        if matches!(ef, Event::Wall(_)) {
            assert_eq!((ef, hits_full), (es, hits), "at t = {t0}");
            assert_eq!(full.state(), solver.state(), "at t = {t0}");
            sparing::add(|t| t.walls += 1);
        } else if (ef, tf) != (es, ts) || full.state() != solver.state() {
            assert!(
                ts >= tf,
                "{es:?} at {ts} before the full search's {ef:?} at {tf}"
            );
            let span = (watch.t_limit - t0).max(f64::MIN_POSITIVE);
            sparing::add(|t| {
                t.later += 1;
                t.worst_later = t.worst_later.max((ts - tf) / span);
            });
        }
        Ok(es)
    }
}

/// Whether a unit's search (its `walls` under `watch`, from the solver's point, where the main
/// mass is at `(x, v)` with `reach`) can be spared because it stops no sooner than `tb`, the
/// best stop so far, and not at a wall there: it can neither win nor tie. Its gap is clear of its
/// walls until `tb` ([`Walls::clear_until`]), or, when `short`, a search of its walls alone only
/// as far as `tb` and a little beyond (the time tolerance a thousand times over; at most the
/// watch's limit) finds none; its steps count into `spent`. The scene's own events are the
/// winner's search's to find: it watches them.
///
/// The short search saves only where the whole one would run past `tb`. Where `tb` is an event
/// of the scene's own found in closed form ([`Reach::closed_form_events`]), every clone stops
/// there too, so the short search would cost what the whole one does, and twice that when the
/// unit wins: the caller passes `short` false there (free decay's 2 units lost 17 % of their
/// time so, BENCHMARKS.md, "Several units"). A unit not spared is searched whole, so that its
/// stop is the one a search of its own finds.
fn spared<S: PhaseSolver>(
    solver: &S,
    (walls, watch): (&Walls, &Watch),
    (x, v, r): (f64, f64, Reach),
    (tb, short): (f64, bool),
    spent: &mut u64,
) -> bool {
    if walls.clear_until((x, v, r.a), r.jerk_max, tb) {
        return true;
    }
    if !short {
        return false;
    }
    let start = solver.steps();
    let mut clone = solver.clone();
    let found = clone.next_event(&Watch {
        walls: Some(*walls),
        x_side: None,
        v_side: None,
        t_limit: (tb + 1e3 * r.tol_t).min(watch.t_limit),
        ..*watch
    });
    *spent += clone.steps() - start;
    matches!(found, Ok(Event::Limit))
}

/// A scene on the event map: what it watches and what it makes of the events. `run` calls it;
/// the optional hooks ([`SceneEvents::arrived`], [`SceneEvents::at_wall`],
/// [`SceneEvents::v_zero`], [`SceneEvents::x_zero`]) do nothing by default.
pub(crate) trait SceneEvents<'a, S: PhaseSolver> {
    /// The scene's event map.
    fn map(&self) -> &EventMap<'a, S::Motion>;
    fn map_mut(&mut self) -> &mut EventMap<'a, S::Motion>;
    /// What the solver watches next (walls and separation from [`EventMap::contact`]).
    fn watch(&self) -> Watch;
    /// The solver has stopped at `ev`; the map has not yet followed it.
    fn arrived(&mut self, _solver: &S, _ev: Event) {}
    /// The map has followed the solver to its point (energies, probes).
    fn synced(&mut self, solver: &S);
    /// A wall is reached, before the cap check and the impact law.
    fn at_wall(&mut self) {}
    /// An impact happened ([`EventMap::collide`]): bookkeeping and probes.
    fn impacted(&mut self, hit: &Hit);
    /// The inner mass left `wall` (the map is free again).
    fn separated(&mut self, wall: Wall);
    /// `v` reached zero from the watched side, before `v_side` flips.
    fn v_zero(&mut self) {}
    /// `x` reached zero; `Some` ends the run.
    fn x_zero(&mut self) -> Option<Outcome> {
        None
    }
    /// The watched time limit is reached; `Some` ends the run.
    fn limit(&mut self, solver: &mut S) -> Option<Outcome>;
    /// With several units: bit `i` set for each free unit `i` that surely reaches neither wall
    /// before `watch.t_limit`, whose own search [`EventMap::find`] then skips. None by default
    /// (every free unit searched).
    fn units_clear(&self, _watch: &Watch) -> u64 {
        0
    }
}

/// The one event loop: moves `solver` from event to event and applies the event map (impact law
/// and chatter rule at the walls, separation, the sign of `v`), handing the scene its events,
/// until the scene ends the run or the solver's caps or the finite numbers do.
pub(crate) fn run<'a, S: PhaseSolver, C: SceneEvents<'a, S>>(
    scene: &mut C,
    solver: &mut S,
) -> Outcome {
    scene.map().begin(solver);
    loop {
        let watch = scene.watch();
        let several = scene.map().several();
        let found = if several {
            let clear = scene.units_clear(&watch);
            scene.map_mut().find(solver, &watch, clear)
        } else {
            solver.next_event(&watch)
        };
        let ev = match found {
            Ok(ev) => ev,
            Err(StepCap) => {
                sync(scene, solver, &watch.walls);
                return Outcome::StepCap;
            }
        };
        scene.arrived(solver, ev);
        sync(scene, solver, &watch.walls);
        match ev {
            Event::NonFinite => return Outcome::NonFinite,
            Event::Wall(wall) => {
                scene.at_wall();
                let map = scene.map_mut();
                if map.impacts >= map.settings.max_impacts {
                    return Outcome::EventCap;
                }
                if several {
                    map.collide_units();
                    let hits = std::mem::take(&mut map.hits);
                    for hit in &hits {
                        scene.impacted(hit);
                    }
                    scene.map_mut().hits = hits;
                } else {
                    let hit = map.collide(wall);
                    scene.impacted(&hit);
                }
                // The impact changed v discontinuously; re-read its sign, or a maximum that
                // follows an impact reversing v inside a positive half-cycle goes unwatched
                // (found at e = 0.80..0.83 by a dense-trace test and by the SciPy peer;
                // regression tests in tests/simulator.rs and tests/solvers.rs).
                let map = scene.map_mut();
                map.v_side = map.v_sign();
                map.begin(solver);
            }
            Event::Separation => {
                if several {
                    if let (n, Some(wall)) = scene.map_mut().separate_units() {
                        for _ in 0..n {
                            scene.separated(wall);
                        }
                    }
                } else if let Some(wall) = scene.map_mut().separate() {
                    scene.separated(wall);
                }
                scene.map().begin(solver);
            }
            Event::VZero => {
                scene.v_zero();
                let map = scene.map_mut();
                map.v_side = -map.v_side;
            }
            Event::XZero => {
                if let Some(outcome) = scene.x_zero() {
                    return outcome;
                }
            }
            Event::Limit => {
                if let Some(outcome) = scene.limit(solver) {
                    return outcome;
                }
            }
        }
    }
}

/// The map follows the solver, then the scene books what it keeps.
fn sync<'a, S: PhaseSolver, C: SceneEvents<'a, S>>(
    scene: &mut C,
    solver: &S,
    walls: &Option<Walls>,
) {
    let map = scene.map_mut();
    if map.several() {
        map.follow_units(solver.state());
    } else {
        map.follow(solver.state(), walls);
    }
    scene.synced(solver);
}

/// Safe step of one watched function from energy bounds (the forced scene's event finder,
/// [`super::driven`], steps by it): distance `g >= 0` to zero with derivatives `g1, g2,
/// g3`, and bounds `b2 >= |g''|`, `b4 >= |g''''|` over the future. The function cannot reach
/// zero before `g + g1 tau - b2 tau^2 / 2` does, nor, when `g1 >= 0` and `g2 > 0`, before
/// `g''` can (by the same bound one derivative up).
#[inline]
pub(crate) fn safe_step(g: f64, g1: f64, g2: f64, g3: f64, b2: f64, b4: f64) -> f64 {
    let g = g.max(0.0);
    let hq = quad_step(g, g1, b2);
    if g1 >= 0.0 && g2 > 0.0 {
        hq.max(quad_step(g2, g3, b4))
    } else {
        hq
    }
}

/// Largest `tau` with `g + g1 tau - b tau^2 / 2 > 0`, in the form free of cancellation.
#[inline]
fn quad_step(g: f64, g1: f64, b: f64) -> f64 {
    if b > 0.0 {
        let disc = (g1 * g1 + 2.0 * b * g).sqrt();
        if g1 >= 0.0 {
            (g1 + disc) / b
        } else {
            2.0 * g / (disc - g1)
        }
    } else if g1 < 0.0 {
        g / -g1
    } else {
        f64::INFINITY
    }
}

/// Does a function at (or below) zero with slope `g1` and curvature `g2` head into it?
#[inline]
pub(crate) fn toward(g1: f64, g2: f64) -> bool {
    g1 < 0.0 || (g1 == 0.0 && g2 < 0.0)
}

/// The chatter rule (module doc): after an impact the inner mass leaves the wall at speed
/// `u >= 0` while the wall accelerates toward it at `a`; `true` when the accumulation of the
/// rebounds that follow ends within the chatter threshold, so the pair sticks now.
#[inline]
pub(crate) fn chatter_ends(u: f64, a: f64, e: f64, settings: &SolverSettings, period: f64) -> bool {
    // A rebound shorter than the event tolerance cannot be resolved: the threshold is at least
    // ten tolerances, so a loose `tol` cannot turn a chatter into an endless one.
    let ct = settings.chatter_tol.max(10.0 * settings.tol);
    let remaining = 2.0 * u / (a * (1.0 - e).max(ct));
    a > 0.0 && remaining <= ct * period || (u == 0.0 && a >= 0.0)
}

/// The sign a quantity has now or, when exactly zero, is about to take from its derivatives.
pub(crate) fn side_of(f: f64, f1: f64, f2: f64) -> f64 {
    for g in [f, f1, f2] {
        if g > 0.0 {
            return 1.0;
        }
        if g < 0.0 {
            return -1.0;
        }
    }
    -1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_step_is_the_root_of_the_bound() {
        for (g, g1, b) in [(1.0, 2.0, 3.0), (1.0, -2.0, 3.0), (0.5, 0.0, 1.0)] {
            let h = quad_step(g, g1, b);
            let r = g + g1 * h - 0.5 * b * h * h;
            assert!(r.abs() < 1e-12, "{g} {g1} {b}: {r}");
        }
        assert_eq!(quad_step(1.0, -2.0, 0.0), 0.5);
        assert_eq!(quad_step(1.0, 2.0, 0.0), f64::INFINITY);
    }

    #[test]
    fn convex_step_lets_a_resting_function_depart() {
        // At zero, at rest, curving away: the quadratic bound gives nothing, the convex one does.
        assert_eq!(quad_step(0.0, 0.0, 1.0), 0.0);
        assert!(safe_step(0.0, 0.0, 1.0, 0.0, 1.0, 1.0) > 1.0);
    }
}
