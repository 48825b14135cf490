//! The one event map both scenes use (free decay, [`super::driver`]; the forced scene,
//! [`super::forced`]), and the types the solvers share, so that nothing in `sim/` imports in a
//! circle: the solvers ([`super::exact`], [`super::dense`] with [`super::rk4`] and
//! [`super::dopri5`], [`super::forced::events`]) import this module and [`super::linear`] only;
//! the scenes import the solvers.
//!
//! A solver moves the main mass through one smooth phase and reports the first watched
//! [`Event`] ([`PhaseSolver`]); what happens at the event (the impact law at a wall, the chatter
//! rule, sticking and separation) is the same in both scenes and lives here.
//!
//! # Phases
//! * **Free**: the main mass is the oscillator `(M, K, C)`; the inner mass moves at constant
//!   velocity; events are the walls, `x = 0`, `v = 0` (in positive half-cycles) and time limits.
//! * **Stuck** on a wall: the pair is the oscillator `(M + m, K, C)` with `y = x ± d/2`; it
//!   separates when the contact force would have to pull: on the right wall contact holds while
//!   the pair's acceleration is `<= 0`, i.e. while `C v + K x >= 0`; on the left wall the reverse.
//!
//! # Chatter rule
//! After an impact on a wall, let `u >= 0` be the speed at which the inner mass leaves it and
//! `a` the acceleration with which the wall moves toward the inner mass (`a = -x''` on the right
//! wall, `+x''` on the left, the free main mass's acceleration). If `a > 0` the inner mass comes
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

use serde::Serialize;

use super::SolverSettings;
use super::linear::Oscillator;

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

/// The inner mass's free motion `y(t) = y0 + w (t - t0)` and the half clearance.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Walls {
    pub t0: f64,
    pub y0: f64,
    pub w: f64,
    pub half_d: f64,
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

/// Moves the main mass through one smooth phase (free, or the stuck pair).
pub(crate) trait PhaseSolver {
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
    /// The current phase in closed form, when the solver has it: the motion, the phase's
    /// start time and its state there. The free scene then evaluates noise samples itself, by a
    /// constant propagator, instead of stopping the solver at each.
    fn closed_form(&self) -> Option<(Self::Motion, f64, f64, f64)> {
        None
    }
}

/// The motion of one phase's main mass, as the event map needs it: the free oscillator of free
/// decay ([`Oscillator`]) or the forced one ([`super::forced::motion::Forced`]).
pub(crate) trait Motion: Copy {
    /// The acceleration `x''` at time `t` in state `(x, v)` (m/s^2).
    fn accel_at(&self, t: f64, x: f64, v: f64) -> f64;
}

impl Motion for Oscillator {
    /// `-(c v + k x) / mass`: time plays no part.
    #[inline]
    fn accel_at(&self, _t: f64, x: f64, v: f64) -> f64 {
        self.accel(x, v)
    }
}

/// Safe step of one watched function from energy bounds (the forced scene's event finder,
/// [`super::forced::events`], steps by it): distance `g >= 0` to zero with derivatives `g1, g2,
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
