//! The `rk4` solver: the classical fourth-order Runge–Kutta method with a fixed step `h` on the
//! phase's oscillator `mass x'' + c x' + k x = 0`, written as the first-order system
//! `(x, v)' = (v, -(c v + k x) / mass)`.
//!
//! Events are located inside each step on Hermite interpolants of `x` and `v` through the step's
//! end values (see [`super::dense`] for their form and why they also match the start's higher
//! derivatives), split at their extrema so that a grazing contact is caught whenever the
//! interpolant dips; the event time is refined to `tol * period`, and the state at the event is
//! recomputed by one RK4 step of length `t_event - t_n` from the step's start. The global error
//! of positions, and so of the event times and the observables, is O(h^4); the interpolant's own
//! error is O(h^6).
//!
//! Each phase restarts the step grid at its start (an impact or a separation), and the last
//! step before a time limit is shortened to end on it. Reference: E. Hairer, S. P. Nørsett,
//! G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993, §II.1.

use super::dense::{Integrator, Step};
use super::linear::Oscillator;
use super::phase::StepCap;

/// One RK4 step of length `h` from `(x, v)`.
#[inline]
pub(crate) fn rk4_step(o: &Oscillator, x: f64, v: f64, h: f64) -> (f64, f64) {
    let f = |x: f64, v: f64| o.accel(x, v);
    let (k1x, k1v) = (v, f(x, v));
    let (k2x, k2v) = {
        let (xx, vv) = (x + 0.5 * h * k1x, v + 0.5 * h * k1v);
        (vv, f(xx, vv))
    };
    let (k3x, k3v) = {
        let (xx, vv) = (x + 0.5 * h * k2x, v + 0.5 * h * k2v);
        (vv, f(xx, vv))
    };
    let (k4x, k4v) = {
        let (xx, vv) = (x + h * k3x, v + h * k3v);
        (vv, f(xx, vv))
    };
    (
        x + h / 6.0 * (k1x + 2.0 * (k2x + k3x) + k4x),
        v + h / 6.0 * (k1v + 2.0 * (k2v + k3v) + k4v),
    )
}

/// The fixed-step RK4 integrator; `h` in seconds.
#[derive(Clone)]
pub(crate) struct Rk4 {
    pub(crate) h: f64,
}

impl Integrator for Rk4 {
    fn reset(&mut self, _osc: &Oscillator) {}

    fn step(
        &mut self,
        o: &Oscillator,
        x: f64,
        v: f64,
        h_max: f64,
        steps: &mut u64,
        max_steps: u64,
    ) -> Result<Step, StepCap> {
        *steps += 1;
        if *steps > max_steps {
            return Err(StepCap);
        }
        let h = self.h.min(h_max);
        let (x1, v1) = rk4_step(o, x, v, h);
        Ok(Step { h, x1, v1 })
    }

    fn partial(&self, o: &Oscillator, x: f64, v: f64, tau: f64) -> (f64, f64) {
        rk4_step(o, x, v, tau)
    }

    fn cut(&mut self) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_step_error_is_fifth_order() {
        let o = Oscillator::new(0.1, 400.0, 0.1);
        let err = |h: f64| {
            let (x, _) = rk4_step(&o, 0.0, 2.0, h);
            (x - o.eval(0.0, 2.0, h).x).abs()
        };
        let ratio = err(1e-3) / err(5e-4);
        // Local error O(h^5): halving h divides it by about 32.
        assert!(ratio > 28.0 && ratio < 36.0, "{ratio}");
    }
}
