//! The `exact` solver: closed-form motion between events ([`super::linear`]) and event location
//! by guaranteed brackets.
//!
//! Every watched quantity is a smooth function `f(t)` of the main mass's motion (the gap to a
//! wall, `x`, `v`, or the contact force of a stuck pair) whose derivatives follow from the closed
//! form, and whose second and fourth derivatives are bounded for all later times by the energy
//! bound of [`Oscillator::derivative_bounds`]. From a point where `f` has distance `g >= 0` to
//! zero, slope `g'` and `|f''| <= B2`, `f` cannot reach zero before
//!
//! ```text
//! h_quad = largest tau with g + g' tau - B2 tau^2 / 2 > 0
//! ```
//!
//! and, when `g' >= 0` and `g'' >= 0` (moving away and curving away, as right after a
//! separation or a grazing contact), not before `h_convex`, the time `g''` needs to reach zero by
//! the same bound one derivative up (with `|f''''| <= B4`), since `g` grows while `g'' >= 0`.
//! The solver steps by the smallest such safe step among the watched functions, so it never
//! steps over a root: grazing contacts (a double root of the gap) included. Near a transversal
//! root the safe step converges quadratically; at a double root geometrically. An event is
//! declared when a function moving toward zero has a safe step below the tolerance
//! `tol * period`; the event time is then within that tolerance of the true root.

use super::driver::{Event, PhaseSolver, StepCap, Watch};
use super::linear::{Kinematics, Oscillator};

/// Safe step of one watched function: distance `g >= 0` to zero with derivatives `g1, g2, g3`,
/// and bounds `b2 >= |g''|`, `b4 >= |g''''|` over the future.
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

/// Does a function at distance `g` with slope `g1` and curvature `g2` head into its zero?
#[inline]
pub(crate) fn toward(g1: f64, g2: f64) -> bool {
    g1 < 0.0 || (g1 == 0.0 && g2 < 0.0)
}

/// One smooth phase of the main mass (free, or the stuck pair) solved in closed form.
pub(crate) struct ExactPhase {
    osc: Oscillator,
    t0: f64,
    x0: f64,
    v0: f64,
    t: f64,
    kin: Kinematics,
    tol_t: f64,
    steps: u64,
    max_steps: u64,
}

impl ExactPhase {
    /// `tol_t` is the absolute event-time tolerance (s).
    pub(crate) fn new(tol_t: f64, max_steps: u64) -> Self {
        let osc = Oscillator::new(1.0, 1.0, 0.0);
        ExactPhase {
            osc,
            t0: 0.0,
            x0: 0.0,
            v0: 0.0,
            t: 0.0,
            kin: Kinematics {
                x: 0.0,
                v: 0.0,
                a: 0.0,
            },
            tol_t,
            steps: 0,
            max_steps,
        }
    }

    /// Moves just past the zero of the contact force (within a few tolerances), so that the
    /// freed main mass accelerates away from the wall instead of being caught by it again at the
    /// same instant. Only the force's sign is checked in this tiny window.
    fn step_past_separation(&mut self, side: f64, h: f64) {
        let o = self.osc;
        let start = self.t;
        let mut tau = h.max(self.tol_t);
        for _ in 0..64 {
            self.seek(start + tau);
            if side * (o.c * self.kin.v + o.k * self.kin.x) < 0.0 {
                return;
            }
            tau *= 2.0;
        }
    }

    #[inline]
    fn seek(&mut self, t: f64) {
        self.t = t;
        self.kin = self.osc.eval(self.x0, self.v0, t - self.t0);
    }
}

impl PhaseSolver for ExactPhase {
    fn begin(&mut self, osc: &Oscillator, t: f64, x: f64, v: f64) {
        self.osc = *osc;
        self.t0 = t;
        self.x0 = x;
        self.v0 = v;
        self.t = t;
        self.kin = Kinematics {
            x,
            v,
            a: osc.accel(x, v),
        };
    }

    fn state(&self) -> (f64, f64, f64) {
        (self.t, self.kin.x, self.kin.v)
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn next_event(&mut self, w: &Watch) -> Result<Event, StepCap> {
        let o = self.osc;
        loop {
            self.steps += 1;
            if self.steps > self.max_steps {
                return Err(StepCap);
            }
            let Kinematics { x, v, a } = self.kin;
            let j = -(o.c * a + o.k * v) / o.mass;
            let b = o.derivative_bounds(o.energy(x, v));
            let mut h = w.t_limit - self.t;
            let mut fired: Option<(Event, f64)> = None;
            let mut consider = |ev: Event, g: f64, g1: f64, g2: f64, g3: f64, b2: f64, b4: f64| {
                let hi = safe_step(g, g1, g2, g3, b2, b4);
                if hi <= self.tol_t && toward(g1, g2) {
                    if fired.is_none_or(|(_, hf)| hi < hf) {
                        fired = Some((ev, hi));
                    }
                } else if hi < h {
                    h = hi;
                }
            };
            if let Some(walls) = &w.walls {
                // z = y - x; right gap d/2 - z, left gap z + d/2; y'' = 0 so gap'' = ±x''.
                let z = walls.y0 + walls.w * (self.t - walls.t0) - x;
                let z1 = walls.w - v;
                consider(
                    Event::Wall(super::Wall::Right),
                    walls.half_d - z,
                    -z1,
                    a,
                    j,
                    b[2],
                    b[4],
                );
                consider(
                    Event::Wall(super::Wall::Left),
                    z + walls.half_d,
                    z1,
                    -a,
                    -j,
                    b[2],
                    b[4],
                );
            }
            let s = w.x_side;
            consider(Event::XZero, s * x, s * v, s * a, s * j, b[2], b[4]);
            if let Some(s) = w.v_side {
                let j2 = -(o.c * j + o.k * a) / o.mass;
                consider(Event::VZero, s * v, s * a, s * j, s * j2, b[3], b[5]);
            }
            if let Some(s) = w.sep_side {
                // Contact holds while s (C v + K x) >= 0 (model.md §2).
                let j2 = -(o.c * j + o.k * a) / o.mass;
                let f = o.c * v + o.k * x;
                let f1 = o.c * a + o.k * v;
                let f2 = o.c * j + o.k * a;
                let f3 = o.c * j2 + o.k * j;
                let b2 = o.c * b[3] + o.k * b[2];
                let b4 = o.c * b[5] + o.k * b[4];
                consider(Event::Separation, s * f, s * f1, s * f2, s * f3, b2, b4);
            }
            if let Some((ev, hi)) = fired {
                if ev == Event::Separation
                    && let Some(side) = w.sep_side
                {
                    self.step_past_separation(side, hi);
                }
                return Ok(ev);
            }
            if w.t_limit - self.t <= h {
                let t = w.t_limit;
                self.seek(t);
                return Ok(Event::Limit);
            }
            // A function resting at its zero while moving away gives no useful bound; step by
            // the tolerance rather than stall (it cannot hide a root longer than that).
            let t = self.t + h.max(self.tol_t);
            self.seek(t.min(w.t_limit));
            if !self.kin.x.is_finite() || !self.kin.v.is_finite() {
                return Ok(Event::NonFinite);
            }
        }
    }
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
