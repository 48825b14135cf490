//! Closed-form motion of the harmonically forced linear oscillator
//! `mass x'' + c x' + k x = F0 cos(omega t)`: the free motion of [`Oscillator`] plus the
//! particular solution `x_p = P cos(omega t) + Q sin(omega t)`,
//!
//! ```text
//! P = F0 (k - mass omega^2) / D,   Q = F0 c omega / D,   D = (k - mass omega^2)^2 + (c omega)^2.
//! ```
//!
//! A phase that starts at `t0` in `(x0, v0)` moves as `x(t) = x_h(t - t0) + x_p(t)`, where `x_h`
//! is the free motion from `(x0 - x_p(t0), v0 - x_p'(t0))`: every damping regime and the
//! neighbourhood of critical damping are handled by [`Oscillator::eval`]. `t` is the time from
//! the start of the run, so the forcing phase is 0 at `t = 0` in every phase.
//!
//! Derivative bounds for the event brackets: the free part's energy never increases, so
//! [`Oscillator::derivative_bounds`] of its energy bounds `|x_h^(j)|` for all later times; the
//! particular part has `|x_p^(j)| <= A omega^j`, `A = sqrt(P^2 + Q^2)`. Their sum bounds the
//! forced motion's derivatives for the rest of the phase.
//! [`Forced::bounds_over`] is often several times tighter over a horizon: as phasors the two
//! parts largely cancel near resonance, and their sum's modulus is the motion's own amplitude.

use crate::sim::driven::{Driven, Jet};
use crate::sim::linear::{Kinematics, Oscillator};
use crate::sim::phase::Motion;

/// The forced oscillator of one phase (the free main mass, or the stuck pair).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Forced {
    pub osc: Oscillator,
    pub f0: f64,
    pub omega: f64,
    /// Particular solution `P cos + Q sin` (m).
    pub p: f64,
    pub q: f64,
    /// `sqrt(P^2 + Q^2)` (m): the steady amplitude of this oscillator alone.
    pub amp: f64,
    /// The phasors' constants of [`Forced::bounds_over`] (an under-damped oscillator; unused
    /// otherwise): `omega^j` and `|lambda^j - (i omega)^j|` for `j = 0..=5`, with
    /// `lambda = -alpha + i w_d`; `|w_d - omega|`; `|lambda - i omega|`.
    pub wpow: [f64; 6],
    pub lag: [f64; 6],
    pub detune: f64,
    pub drift: f64,
}

/// `|K - mass omega^2 + i C omega|` below this fraction of `K` is refused as resonance without
/// damping: the particular amplitude would exceed `10^6 X_st` and cancel against the free part,
/// losing that many digits.
pub const RESONANCE_FLOOR: f64 = 1e-6;

impl Forced {
    /// The oscillator `(mass, k, c)` under `f0 cos(omega t)`. The caller has checked that the
    /// dynamic stiffness is above [`RESONANCE_FLOOR`]` k`.
    pub fn new(mass: f64, k: f64, c: f64, f0: f64, omega: f64) -> Self {
        let (p, q) = particular(mass, k, c, f0, omega);
        let osc = Oscillator::new(mass, k, c);
        let (lr, li) = (-osc.alpha, osc.root);
        let (mut zr, mut zi) = (1.0f64, 0.0f64);
        let mut wpow = [0.0; 6];
        let mut lag = [0.0; 6];
        let mut wj = 1.0;
        // (i omega)^j = omega^j i^j.
        for j in 0..6 {
            wpow[j] = wj;
            let (ir, ii) = match j % 4 {
                0 => (wj, 0.0),
                1 => (0.0, wj),
                2 => (-wj, 0.0),
                _ => (0.0, -wj),
            };
            lag[j] = (zr - ir).hypot(zi - ii);
            (zr, zi) = (zr * lr - zi * li, zr * li + zi * lr);
            wj *= omega;
        }
        Forced {
            osc,
            f0,
            omega,
            p,
            q,
            amp: p.hypot(q),
            wpow,
            lag,
            detune: (osc.root - omega).abs(),
            drift: osc.alpha.hypot(osc.root - omega),
        }
    }

    /// `(x_p, x_p', x_p'', x_p''')` at time `t`.
    #[inline]
    pub fn particular_at(&self, t: f64) -> [f64; 4] {
        let (s, c) = libm::sincos(self.omega * t);
        let w = self.omega;
        let x = self.p * c + self.q * s;
        let v = w * (self.q * c - self.p * s);
        [x, v, -w * w * x, -w * w * v]
    }

    /// The force `F0 cos(omega t)` and its first three derivatives.
    #[inline]
    pub fn force_at(&self, t: f64) -> [f64; 4] {
        let (s, c) = libm::sincos(self.omega * t);
        let w = self.omega;
        let f = self.f0 * c;
        let f1 = -self.f0 * w * s;
        [f, f1, -w * w * f, -w * w * f1]
    }

    /// Initial condition of the free part for a phase that starts at `t0` in `(x0, v0)`.
    #[inline]
    pub fn free_start(&self, t0: f64, x0: f64, v0: f64) -> (f64, f64) {
        let [xp, vp, _, _] = self.particular_at(t0);
        (x0 - xp, v0 - vp)
    }

    /// The start of a phase at `t0` in `(x0, v0)`: its free part `(h0, g0)` and its motion
    /// there, the same numbers as [`Forced::free_start`] then [`Forced::jet`] at `t = t0`, with
    /// one sine and cosine instead of three and no exponential.
    #[inline]
    pub fn start(&self, t0: f64, x0: f64, v0: f64) -> (f64, f64, Jet) {
        let particular = self.particular_at(t0);
        let (h0, g0) = (x0 - particular[0], v0 - particular[1]);
        let hk = self.osc.eval_fast(h0, g0, 0.0);
        (h0, g0, self.compose(hk, particular))
    }

    /// The motion at `t` of the phase that started at `t0` with free part `(h0, g0)`.
    #[inline]
    pub fn jet(&self, t0: f64, h0: f64, g0: f64, t: f64) -> Jet {
        let hk = self.osc.eval_fast(h0, g0, t - t0);
        self.compose(hk, self.particular_at(t))
    }

    /// The forced motion from its free part `hk` and its particular part (`x_p` and its first
    /// three derivatives).
    #[inline]
    fn compose(&self, hk: Kinematics, [xp, vp, ap, jp]: [f64; 4]) -> Jet {
        let o = &self.osc;
        let x = hk.x + xp;
        let v = hk.v + vp;
        let a = hk.a + ap;
        // Derivatives of the free part from its own equation, plus the particular part's.
        let jh = -(o.c * hk.a + o.k * hk.v) * o.inv_mass;
        let j2h = -(o.c * jh + o.k * hk.a) * o.inv_mass;
        let w2 = self.omega * self.omega;
        Jet {
            x,
            v,
            a,
            j: jh + jp,
            j2: j2h + w2 * w2 * xp,
            xh: hk.x,
            vh: hk.v,
        }
    }

    /// `B[j] >= |x^(j)|`, `j = 0..=5`, for every later time of this phase, from the free part's
    /// state now.
    #[inline]
    pub fn bounds(&self, jet: &Jet) -> [f64; 6] {
        let mut b = self.osc.derivative_bounds(jet.xh, jet.vh);
        let mut wj = self.amp;
        for bj in &mut b {
            *bj += wj;
            wj *= self.omega;
        }
        b
    }

    /// [`Forced::bounds`] made tighter over the next `horizon` seconds by the phasors: the free
    /// part is `Re(A e^(lambda s))`, `lambda = -alpha + i w_d`, the particular part
    /// `Re(P e^(i omega s))`, so that
    /// `x^(j) = Re((i omega)^j (A e^(lambda s) + P e^(i omega s)) + (lambda^j - (i omega)^j) A e^(lambda s))`
    /// and
    /// `|x^(j)| <= omega^j (|A + P| + rate s) + |lambda^j - (i omega)^j| |A|`, with
    /// `rate = min(alpha |A| + |w_d - omega| |P|, |lambda - i omega| |A|)`. Near resonance the
    /// free and particular parts largely cancel and `|A + P|` is the motion's amplitude: the
    /// bounds are then a few times below the sum of the parts'.
    #[inline]
    pub fn bounds_over(&self, jet: &Jet, horizon: f64) -> [f64; 6] {
        let mut b = self.bounds(jet);
        let o = &self.osc;
        if o.q <= 0.0 || !horizon.is_finite() {
            return b;
        }
        let ah = -(jet.vh + o.alpha * jet.xh) * o.inv_root;
        let ap = -(jet.v - jet.vh) / self.omega;
        let sum = ah + ap;
        let e = jet.x.mul_add(jet.x, sum * sum).sqrt();
        let a = jet.xh.mul_add(jet.xh, ah * ah).sqrt();
        let rate = (o.alpha * a + self.detune * self.amp).min(a * self.drift);
        let reach = (e + rate * horizon) * (1.0 + 1e-9);
        let free = a * (1.0 + 1e-9);
        for ((bj, wj), lj) in b.iter_mut().zip(self.wpow).zip(self.lag) {
            *bj = bj.min(wj * reach + lj * free);
        }
        b
    }

    /// The acceleration of this oscillator in state `(x, v)` at time `t`.
    #[inline]
    pub fn accel(&self, t: f64, x: f64, v: f64) -> f64 {
        (self.f0 * (self.omega * t).cos() - self.osc.c * v - self.osc.k * x) / self.osc.mass
    }
}

/// The particular coefficients `(P, Q)` of `mass x'' + c x' + k x = f0 cos(omega t)`.
pub(crate) fn particular(mass: f64, k: f64, c: f64, f0: f64, omega: f64) -> (f64, f64) {
    let re = (-mass * omega).mul_add(omega, k);
    let im = c * omega;
    // f0 / (re + i im) = f0 (re - i im) / D; scaled to avoid overflow of D.
    let s = re.abs().max(im.abs());
    let (re_s, im_s) = (re / s, im / s);
    let d = re_s.mul_add(re_s, im_s * im_s);
    (f0 * re_s / (d * s), f0 * im_s / (d * s))
}

/// `|k - mass omega^2 + i c omega|` (N/m), the dynamic stiffness.
pub(crate) fn dynamic_stiffness(mass: f64, k: f64, c: f64, omega: f64) -> f64 {
    (-mass * omega).mul_add(omega, k).hypot(c * omega)
}

impl Motion for Forced {
    /// `(F0 cos(omega t) - c v - k x) / mass`.
    #[inline]
    fn accel_at(&self, t: f64, x: f64, v: f64) -> f64 {
        self.accel(t, x, v)
    }

    fn with_mass(&self, mass: f64) -> Self {
        Forced::new(mass, self.osc.k, self.osc.c, self.f0, self.omega)
    }
}

/// The harmonic force in the event finder of [`crate::sim::driven`]: the contact function of a
/// stuck pair is `C v + K x - F0 cos(omega t)`, whose load has `|L''| <= F0 omega^2` and
/// `|L''''| <= F0 omega^4`.
impl Driven for Forced {
    const PHASE_BOUNDS: bool = true;

    #[inline]
    fn start(&self, t0: f64, x0: f64, v0: f64) -> (f64, f64, Jet) {
        Forced::start(self, t0, x0, v0)
    }

    #[inline]
    fn jet(&self, t0: f64, h0: f64, g0: f64, t: f64) -> Jet {
        Forced::jet(self, t0, h0, g0, t)
    }

    #[inline]
    fn bounds(&self, jet: &Jet) -> [f64; 6] {
        Forced::bounds(self, jet)
    }

    #[inline]
    fn bounds_over(&self, jet: &Jet, horizon: f64) -> [f64; 6] {
        Forced::bounds_over(self, jet, horizon)
    }

    #[inline]
    fn oscillator(&self) -> &Oscillator {
        &self.osc
    }

    #[inline]
    fn contact_load(&self, t: f64) -> [f64; 4] {
        self.force_at(t)
    }

    #[inline]
    fn contact_load_bounds(&self) -> (f64, f64) {
        let w2 = self.omega * self.omega;
        (self.f0 * w2, self.f0 * w2 * w2)
    }

    /// `-x''`: `mass x'' = F - C v - K x` has the contact function's opposite sign.
    #[inline]
    fn contact_sign(&self, _t: f64, jet: &Jet) -> f64 {
        -jet.a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RK4 on the forced equation with a small step.
    fn rk4(f: &Forced, x0: f64, v0: f64, t0: f64, t1: f64, n: usize) -> (f64, f64) {
        let h = (t1 - t0) / n as f64;
        let (mut x, mut v) = (x0, v0);
        let acc = |t: f64, x: f64, v: f64| f.accel(t, x, v);
        for i in 0..n {
            let t = t0 + i as f64 * h;
            let (k1x, k1v) = (v, acc(t, x, v));
            let (k2x, k2v) = (
                v + 0.5 * h * k1v,
                acc(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v),
            );
            let (k3x, k3v) = (
                v + 0.5 * h * k2v,
                acc(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v),
            );
            let (k4x, k4v) = (v + h * k3v, acc(t + h, x + h * k3x, v + h * k3v));
            x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        (x, v)
    }

    #[test]
    fn closed_form_agrees_with_rk4_in_every_regime() {
        let (mass, k): (f64, f64) = (0.1, 400.0);
        let crit = 2.0 * (k * mass).sqrt();
        let wn = (k / mass).sqrt();
        for c in [0.0, 0.1, 0.5 * crit, crit, 2.0 * crit] {
            for r in [0.3, 0.97, 2.5] {
                let f = Forced::new(mass, k, c, 1.0, r * wn);
                let (t0, t1) = (0.013, 0.2);
                let (h0, g0) = f.free_start(t0, 0.004, -0.3);
                let jet = f.jet(t0, h0, g0, t1);
                let (x, v) = rk4(&f, 0.004, -0.3, t0, t1, 100_000);
                let scale = 0.004f64.max(f.amp);
                assert!((jet.x - x).abs() <= 1e-10 * scale, "c={c} r={r}");
                assert!((jet.v - v).abs() <= 1e-9 * scale * wn, "c={c} r={r}");
                // The equation of motion holds for the derivatives the brackets use.
                let [fo, f1, f2, _] = f.force_at(t1);
                assert!((mass * jet.a + c * jet.v + k * jet.x - fo).abs() <= 1e-9 * k * scale);
                assert!((mass * jet.j + c * jet.a + k * jet.v - f1).abs() <= 1e-8 * k * scale * wn);
                assert!(
                    (mass * jet.j2 + c * jet.j + k * jet.a - f2).abs()
                        <= 1e-8 * k * scale * wn * wn
                );
            }
        }
    }

    #[test]
    fn particular_solution_matches_the_textbook_amplitude() {
        let (mass, k, c): (f64, f64, f64) = (0.1, 400.0, 0.1);
        let wn = (k / mass).sqrt();
        let zeta = c / (2.0 * (k * mass).sqrt());
        for r in [0.1, 1.0, 5.0] {
            let f = Forced::new(mass, k, c, 2.0, r * wn);
            let lin = 2.0 / k / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
            assert!((f.amp - lin).abs() <= 1e-13 * lin, "r={r}");
        }
    }

    /// The phasor bounds hold over their horizon for free parts small, large and cancelling the
    /// particular part, below, at and above resonance; where the parts cancel near resonance
    /// they are several times below the parts' sum ([`Forced::bounds`]).
    #[test]
    fn bounds_over_a_horizon_hold_and_are_tighter_where_the_parts_cancel() {
        let wn = (400.0f64 / 0.1).sqrt();
        let horizon = 0.1;
        for r in [0.8, 0.99, 1.0, 1.01, 1.2] {
            let f = Forced::new(0.1, 400.0, 0.1, 0.1, r * wn);
            let [xp, vp, _, _] = f.particular_at(0.0);
            for (fx, fv) in [
                (0.0, 0.0),
                (0.1, -0.2),
                (-0.9, -0.9),
                (2.0, 1.5),
                (-1.1, 0.3),
            ] {
                let (h0, g0) = (fx * xp + 0.001 * fv, fv * vp);
                let b = f.bounds_over(&f.jet(0.0, h0, g0, 0.0), horizon);
                for i in 0..=2000 {
                    let jet = f.jet(0.0, h0, g0, horizon * i as f64 / 2000.0);
                    let d = [jet.x, jet.v, jet.a, jet.j, jet.j2];
                    for (j, dj) in d.iter().enumerate() {
                        assert!(
                            dj.abs() <= b[j],
                            "r = {r}, ({fx}, {fv}), x^({j}) = {dj} > {}",
                            b[j]
                        );
                    }
                }
            }
            if (r - 1.0f64).abs() <= 0.011 {
                // The free part nine tenths of the particular one, opposite.
                let jet = f.jet(0.0, -0.9 * xp, -0.9 * vp, 0.0);
                let (tight, wide) = (f.bounds_over(&jet, horizon), f.bounds(&jet));
                assert!(
                    tight[2] < 0.3 * wide[2],
                    "r = {r}: {} against {}",
                    tight[2],
                    wide[2]
                );
            }
        }
    }

    #[test]
    fn bounds_hold_along_a_phase() {
        let f = Forced::new(0.1, 400.0, 0.1, 1.0, 40.0);
        let (h0, g0) = f.free_start(0.0, 0.01, 1.0);
        let b = f.bounds(&f.jet(0.0, h0, g0, 0.0));
        for i in 0..2000 {
            let jet = f.jet(0.0, h0, g0, i as f64 * 1e-3);
            assert!(jet.x.abs() <= b[0] && jet.v.abs() <= b[1] && jet.a.abs() <= b[2]);
            assert!(jet.j.abs() <= b[3] && jet.j2.abs() <= b[4]);
        }
    }
}
