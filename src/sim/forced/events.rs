//! Event location for the forced scene, by the guaranteed brackets of [`crate::sim::exact`].
//!
//! Each watched function (a gap to a wall, the displacement, the velocity, the contact force of a
//! stuck pair) is a smooth function of the forced motion whose second and fourth derivatives
//! are bounded for the rest of the phase by `Forced::bounds` (the free part's energy bound plus
//! `A omega^j` of the particular part; for the contact force `C B3 + K B2 + F0 omega^2` and
//! `C B5 + K B4 + F0 omega^4`). The safe step ([`safe_step`] of [`crate::sim::phase`]) from a
//! point where the function is `g >= 0` away from zero cannot step over a root, grazing (double)
//! roots included; an event is declared when a function heading into zero has a safe step below
//! `tol_t`, so its time is within `tol_t` of the true root.

use super::motion::{Forced, Jet};
use crate::sim::phase::{Event, PhaseSolver, StepCap, Wall, Watch, safe_step, toward};

/// One smooth phase of the forced main mass (free, or the stuck pair), in closed form.
pub(crate) struct ForcedPhase {
    f: Forced,
    t0: f64,
    h0: f64,
    g0: f64,
    t: f64,
    jet: Jet,
    tol_t: f64,
    steps: u64,
    max_steps: u64,
}

impl ForcedPhase {
    pub fn new(f: &Forced, tol_t: f64, max_steps: u64) -> Self {
        ForcedPhase {
            f: *f,
            t0: 0.0,
            h0: 0.0,
            g0: 0.0,
            t: 0.0,
            jet: Jet::default(),
            tol_t,
            steps: 0,
            max_steps,
        }
    }

    /// The phase's motion at any time (for quadrature), without moving.
    #[inline]
    pub fn at(&self, t: f64) -> Jet {
        self.f.jet(self.t0, self.h0, self.g0, t)
    }

    #[inline]
    fn seek(&mut self, t: f64) {
        self.t = t;
        self.jet = self.at(t);
    }

    /// Moves just past the zero of the contact force so that the freed main mass leaves the
    /// wall (as the free-decay solver does); only the force's sign is checked in this window.
    fn step_past_separation(&mut self, side: f64, h: f64) {
        let start = self.t;
        let mut tau = h.max(self.tol_t);
        for _ in 0..64 {
            self.seek(start + tau);
            if side * -self.jet.a < 0.0 {
                return;
            }
            tau *= 2.0;
        }
    }
}

impl PhaseSolver for ForcedPhase {
    type Motion = Forced;

    fn begin(&mut self, f: &Forced, t: f64, x: f64, v: f64) {
        self.f = *f;
        self.t0 = t;
        (self.h0, self.g0) = f.free_start(t, x, v);
        self.t = t;
        self.jet = f.jet(t, self.h0, self.g0, t);
        // The phase starts exactly where it was asked to, not at the rounded sum.
        self.jet.x = x;
        self.jet.v = v;
    }

    fn state(&self) -> (f64, f64, f64) {
        (self.t, self.jet.x, self.jet.v)
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn next_event(&mut self, w: &Watch) -> Result<Event, StepCap> {
        let f = self.f;
        let (c, k) = (f.osc.c, f.osc.k);
        loop {
            self.steps += 1;
            if self.steps > self.max_steps {
                return Err(StepCap);
            }
            let Jet { x, v, a, j, j2, .. } = self.jet;
            let b = f.bounds(&self.jet);
            let mut h = w.t_limit - self.t;
            let mut fired: Option<(Event, f64)> = None;
            let tol_t = self.tol_t;
            let mut consider = |ev: Event, g: f64, g1: f64, g2: f64, g3: f64, b2: f64, b4: f64| {
                let hi = safe_step(g, g1, g2, g3, b2, b4);
                if hi <= tol_t && toward(g1, g2) {
                    if fired.is_none_or(|(_, hf)| hi < hf) {
                        fired = Some((ev, hi));
                    }
                } else if hi < h {
                    h = hi;
                }
            };
            if let Some(walls) = &w.walls {
                // z = y - x with y'' = 0: the gaps' derivatives are those of -x or +x.
                let z = walls.y0 + walls.w * (self.t - walls.t0) - x;
                let z1 = walls.w - v;
                consider(
                    Event::Wall(Wall::Right),
                    walls.half_d - z,
                    -z1,
                    a,
                    j,
                    b[2],
                    b[4],
                );
                consider(
                    Event::Wall(Wall::Left),
                    z + walls.half_d,
                    z1,
                    -a,
                    -j,
                    b[2],
                    b[4],
                );
            }
            if let Some(s) = w.x_side {
                consider(Event::XZero, s * x, s * v, s * a, s * j, b[2], b[4]);
            }
            if let Some(s) = w.v_side {
                consider(Event::VZero, s * v, s * a, s * j, s * j2, b[3], b[5]);
            }
            if let Some(s) = w.sep_side {
                // Contact holds while s (C v + K x - F) = -s mass x'' >= 0.
                let [fo, f1, f2, f3] = f.force_at(self.t);
                let g = c * v + k * x - fo;
                let g1 = c * a + k * v - f1;
                let g2 = c * j + k * a - f2;
                let g3 = c * j2 + k * j - f3;
                let w2 = f.omega * f.omega;
                let b2 = c * b[3] + k * b[2] + f.f0 * w2;
                let b4 = c * b[5] + k * b[4] + f.f0 * w2 * w2;
                consider(Event::Separation, s * g, s * g1, s * g2, s * g3, b2, b4);
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
            let t = self.t + h.max(self.tol_t);
            self.seek(t.min(w.t_limit));
            if !self.jet.x.is_finite() || !self.jet.v.is_finite() {
                return Ok(Event::NonFinite);
            }
        }
    }
}
