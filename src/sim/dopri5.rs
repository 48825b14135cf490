//! The `dopri5` solver: the adaptive embedded Runge–Kutta pair of Dormand and Prince, order 5
//! with a 4th-order error estimate (the method behind MATLAB's `ode45`, which the paper used),
//! on the phase's oscillator `(x, v)' = (v, -(c v + k x) / mass)`.
//!
//! * **FSAL**: the seventh stage is the derivative at the new point and serves as the next step's
//!   first stage (six new evaluations per step).
//! * **Step control** (Hairer–Nørsett–Wanner II.4): with the scale `sk_i = atol_i + rtol *
//!   max(|y_i|, |y_i,new|)` and the RMS norm `err = sqrt(mean((est_i / sk_i)^2))`, a step is
//!   accepted when `err <= 1`; the next step is `h * min(10, max(0.2, 0.9 err^(-1/5)))`, with
//!   no growth right after a rejection. `atol` (m) applies to `x`; for `v` it is
//!   `atol * sqrt(k / mass)` (m/s), so both are metres of amplitude. Steps never exceed a quarter
//!   of the phase's undamped period, so the interpolant sees every half-swing. The first step
//!   follows Hairer's `hinit`.
//! * **Events** are located on a quintic Hermite interpolant of the step (see [`super::dense`],
//!   which explains why it replaces the method's 4th-order continuous extension: that extension
//!   matches only the first derivative at the step's start and loses the sign of the gap right
//!   after a separation); the state at an event is recomputed by one Dormand–Prince step of
//!   length `t_event - t_n` from the step's start (5th order).
//!
//! Reference: J. R. Dormand, P. J. Prince, *A family of embedded Runge–Kutta formulae*, J. Comp.
//! Appl. Math. 6 (1980) 19–26; E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary
//! Differential Equations I*, 2nd ed., Springer 1993, §II.4–II.6 (the `DOPRI5` code).

use super::dense::{Integrator, Step};
use super::linear::Oscillator;
use super::phase::StepCap;

// Butcher tableau (nodes c = 0, 1/5, 3/10, 4/5, 8/9, 1, 1; autonomous ODE, so only a_ij enter).
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
/// A state or derivative `(x, v)`.
type Y = [f64; 2];

#[inline]
fn f(o: &Oscillator, y: Y) -> Y {
    [y[1], o.accel(y[0], y[1])]
}

#[inline]
fn lin(y: Y, h: f64, terms: &[(f64, &Y)]) -> Y {
    let mut out = y;
    for i in 0..2 {
        let mut s = 0.0;
        for (c, k) in terms {
            s += c * k[i];
        }
        out[i] += h * s;
    }
    out
}

/// All seven stages of one step of length `h` from `y` with first stage `k1`; returns the
/// 5th-order solution and the stages.
#[inline]
fn stages(o: &Oscillator, y: Y, k1: Y, h: f64) -> (Y, [Y; 7]) {
    let k2 = f(o, lin(y, h, &[(A21, &k1)]));
    let k3 = f(o, lin(y, h, &[(A31, &k1), (A32, &k2)]));
    let k4 = f(o, lin(y, h, &[(A41, &k1), (A42, &k2), (A43, &k3)]));
    let k5 = f(
        o,
        lin(y, h, &[(A51, &k1), (A52, &k2), (A53, &k3), (A54, &k4)]),
    );
    let k6 = f(
        o,
        lin(
            y,
            h,
            &[(A61, &k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
        ),
    );
    let y1 = lin(
        y,
        h,
        &[(A71, &k1), (A73, &k3), (A74, &k4), (A75, &k5), (A76, &k6)],
    );
    let k7 = f(o, y1);
    (y1, [k1, k2, k3, k4, k5, k6, k7])
}

/// The adaptive Dormand–Prince 5(4) integrator.
#[derive(Clone)]
pub(crate) struct Dopri5 {
    rtol: f64,
    atol: f64,
    /// Proposed next step (s); `None` before the first step.
    h: Option<f64>,
    /// The derivative at the current state (FSAL), when still valid.
    k1: Option<Y>,
    rejected: bool,
}

impl Dopri5 {
    pub(crate) fn new(rtol: f64, atol: f64) -> Self {
        Dopri5 {
            rtol,
            atol,
            h: None,
            k1: None,
            rejected: false,
        }
    }

    fn scale(&self, o: &Oscillator, a: Y, b: Y) -> Y {
        let atol_v = self.atol * o.w2.sqrt();
        [
            self.atol + self.rtol * a[0].abs().max(b[0].abs()),
            atol_v + self.rtol * a[1].abs().max(b[1].abs()),
        ]
    }

    /// Hairer's starting step: from the sizes of `y`, `f(y)` and an estimate of `f'`.
    fn initial_step(&self, o: &Oscillator, y: Y, k1: Y, h_max: f64) -> f64 {
        let sk = self.scale(o, y, y);
        let norm = |z: Y| ((z[0] / sk[0]).powi(2) + (z[1] / sk[1]).powi(2)).sqrt() / 2f64.sqrt();
        let (d0, d1) = (norm(y), norm(k1));
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(h_max);
        let k2 = f(o, lin(y, h0, &[(1.0, &k1)]));
        let d2 = norm([k2[0] - k1[0], k2[1] - k1[1]]) / h0;
        let big = d1.max(d2);
        let h1 = if big <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / big).powf(0.2)
        };
        (100.0 * h0).min(h1).min(h_max)
    }
}

impl Integrator for Dopri5 {
    fn reset(&mut self, _osc: &Oscillator) {
        self.k1 = None;
        self.rejected = false;
    }

    fn step(
        &mut self,
        o: &Oscillator,
        x: f64,
        v: f64,
        h_room: f64,
        steps: &mut u64,
        max_steps: u64,
    ) -> Result<Step, StepCap> {
        let y = [x, v];
        let k1 = *self.k1.get_or_insert_with(|| f(o, y));
        // A quarter of the undamped period of the phase's oscillator.
        let h_cap = 0.25 * std::f64::consts::TAU / o.w2.sqrt();
        let mut h_prop = match self.h {
            Some(h) => h.min(h_cap),
            None => self.initial_step(o, y, k1, h_cap),
        };
        loop {
            *steps += 1;
            if *steps > max_steps {
                return Err(StepCap);
            }
            let h = h_prop.min(h_room);
            let (y1, k) = stages(o, y, k1, h);
            let sk = self.scale(o, y, y1);
            let mut sum = 0.0;
            for i in 0..2 {
                let est = h
                    * (E1 * k[0][i]
                        + E3 * k[2][i]
                        + E4 * k[3][i]
                        + E5 * k[4][i]
                        + E6 * k[5][i]
                        + E7 * k[6][i]);
                sum += (est / sk[i]).powi(2);
            }
            let err = (0.5 * sum).sqrt();
            if !(err.is_finite() && y1[0].is_finite() && y1[1].is_finite()) {
                if h <= f64::EPSILON * h_cap {
                    // Give up shrinking: let the caller see the non-finite state.
                    return Ok(Step {
                        h,
                        x1: f64::NAN,
                        v1: f64::NAN,
                    });
                }
                h_prop = 0.2 * h;
                self.rejected = true;
                continue;
            }
            let fac = (0.9 * err.powf(-0.2)).clamp(0.2, 10.0);
            if err <= 1.0 {
                let grow = if self.rejected { fac.min(1.0) } else { fac };
                let next = h * grow;
                // A step cut short by the time limit says nothing about the proposal's size.
                self.h = Some(if h < h_prop { h_prop.max(next) } else { next }.min(h_cap));
                self.rejected = false;
                self.k1 = Some(k[6]);
                return Ok(Step {
                    h,
                    x1: y1[0],
                    v1: y1[1],
                });
            }
            h_prop = h * fac.min(1.0);
            self.rejected = true;
        }
    }

    fn partial(&self, o: &Oscillator, x: f64, v: f64, tau: f64) -> (f64, f64) {
        let y = [x, v];
        let (y1, _) = stages(o, y, f(o, y), tau);
        (y1[0], y1[1])
    }

    fn cut(&mut self) {
        self.k1 = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_step_error_is_sixth_order() {
        let o = Oscillator::new(0.1, 400.0, 0.1);
        // Error of the state in metres of amplitude, from a generic start.
        let err = |h: f64| {
            let (x, v) = Dopri5::new(1e-6, 1e-9).partial(&o, 0.01, 1.0, h);
            let k = o.eval(0.01, 1.0, h);
            (x - k.x).hypot((v - k.v) / o.w2.sqrt())
        };
        let ratio = err(2e-3) / err(1e-3);
        // Local error O(h^6): halving h divides it by about 64.
        assert!(ratio > 56.0 && ratio < 72.0, "{ratio}");
    }
}
