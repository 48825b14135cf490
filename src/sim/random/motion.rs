//! Closed-form motion of an oscillator under a load linear in time over one interval of the
//! load's samples, `mass x'' + c x' + k x = f0 + s t` (`t` from the interval's start, N and
//! N/s): the free motion of [`Oscillator`] plus the particular solution
//!
//! ```text
//! x_p(t) = p0 + p1 t,   p0 = f0 / k - c s / k^2,   p1 = s / k,
//! ```
//!
//! whose second and higher derivatives vanish. A phase that starts at `t0` in `(x0, v0)` moves
//! as `x(t) = x_h(t - t0) + x_p(t)`, `x_h` the free motion from
//! `(x0 - x_p(t0), v0 - p1)` ([`Oscillator::eval`]: every damping regime, accurate at
//! `c = 0` and across critical damping).
//!
//! Derivative bounds for the event brackets ([`crate::sim::driven`]): the free part's energy
//! never increases, so [`Oscillator::derivative_bounds`] of its energy bound `|x_h^(j)|` for
//! the rest of the phase; the particular part adds `max(|x_p|)` over the interval to `B0` and
//! `|p1|` to `B1` and nothing beyond. Under ground acceleration the free inner mass moves with
//! `y'' = -a_g = ya + yj t` ([`Motion::inner_accel`]).
//!
//! # Square integrals from the ends of a piece
//! Over a piece `[t0, t1]` of one phase, `int x^2` and `int a^2` follow from the states at its
//! two ends alone ([`Ramp::squares_between`]), by the equation of motion's moments. Write
//! `[g] = g(t1) - g(t0)` and `f = f0 + s t`. Integrating the equation itself, and times `t`, `v`
//! and `x` (by parts where a derivative stands):
//!
//! ```text
//! k int x     = int f - mass [v] - c [x]
//! k int t x   = int t f - mass ([t v] - [x]) - c ([t x] - int x)
//!   int x v   = [x^2] / 2,      int v f = [x f] - s int x,      int x f = f0 int x + s int t x
//! c int v^2   = int v f - k int x v - mass [v^2] / 2
//! k int x^2   = int x f - c int x v - mass ([x v] - int v^2)
//! ```
//!
//! and `mass^2 int a^2` is the square of `L - c v - k x` integrated term by term (`L = f` for a
//! force on the main mass, 0 under ground acceleration, where `a = x'' + a_g`). No exponential,
//! sine or cosine is evaluated inside the piece. The price is accuracy: `int v^2` is what is
//! left of the energy balance (the load's work less the energy's change) after the damping is
//! divided out, so its rounding is about `eps W / c`, `W` the sizes of the balance's terms,
//! whatever the piece's length; `int x^2` inherits it over `k / mass`. The ends themselves
//! carry the rounding of the free part and the particular solution they are the sum of, which
//! a steep ramp makes large (`p1 = s / k`). [`Ramp::squares_between`] returns a first-order
//! estimate of both integrals' rounding with them, from those sizes; the random scene keeps the
//! pieces so taken within a budget of the run's integrals and integrates the others by
//! quadrature ([`crate::sim::random::run`], "Integrals").

use crate::sim::driven::{Driven, Jet};
use crate::sim::linear::{Kinematics, Oscillator};
use crate::sim::phase::Motion;

/// The oscillator of one phase (the free main mass or the stuck pair) under a linear load over
/// one interval.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ramp {
    pub osc: Oscillator,
    /// The load at the interval's start (N) and its slope (N/s).
    pub f0: f64,
    pub s: f64,
    /// The particular solution `p0 + p1 t` (m, m/s).
    pub p0: f64,
    pub p1: f64,
    /// The interval's length (s): the phase ends by then.
    pub len: f64,
    /// The free inner mass's acceleration `ya + yj t` (m/s^2, m/s^3) and its largest `|.|` over
    /// the interval.
    pub ya: f64,
    pub yj: f64,
    pub ya_max: f64,
    /// The contact function carries the load (a force on the main mass): `C v + K x - L`.
    pub contact: bool,
}

/// `int x^2` and `int a^2` over a piece ([`Ramp::squares_between`]) and estimates of their
/// rounding (to first order: the sizes of the terms that cancel, times four units).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Squares {
    pub x2: f64,
    pub a2: f64,
    pub err_x2: f64,
    pub err_a2: f64,
}

impl Ramp {
    /// `osc` under `f0 + s t` over an interval of `len` seconds; `inner` the free inner mass's
    /// acceleration at the start and its slope; `contact`: the load is a force on the main mass.
    pub fn new(
        osc: Oscillator,
        f0: f64,
        s: f64,
        len: f64,
        inner: (f64, f64),
        contact: bool,
    ) -> Ramp {
        let inv_k = 1.0 / osc.k;
        let p1 = s * inv_k;
        let p0 = (f0 - osc.c * p1) * inv_k;
        let (ya, yj) = inner;
        Ramp {
            osc,
            f0,
            s,
            p0,
            p1,
            len,
            ya,
            yj,
            ya_max: ya.abs().max((ya + yj * len).abs()),
            contact,
        }
    }

    /// The load at `t` (N).
    #[inline]
    pub fn load(&self, t: f64) -> f64 {
        self.f0 + self.s * t
    }

    /// The motion from the free part `hk` at time `t`.
    #[inline]
    fn compose(&self, hk: Kinematics, t: f64) -> Jet {
        let o = &self.osc;
        let inv_m = 1.0 / o.mass;
        let j = -(o.c * hk.a + o.k * hk.v) * inv_m;
        Jet {
            x: hk.x + (self.p0 + self.p1 * t),
            v: hk.v + self.p1,
            a: hk.a,
            j,
            j2: -(o.c * j + o.k * hk.a) * inv_m,
            xh: hk.x,
            vh: hk.v,
        }
    }

    /// `int x^2` (m^2 s) and `int a^2` (m^2 s^-3) over the piece from `(t0, x0, v0)` to
    /// `(t1, x1, v1)` of one smooth phase of this motion (times local to the interval, s; m,
    /// m/s), `a` the absolute acceleration ([`Ramp::absolute_accel`]), from the states at both
    /// ends by the equation of motion's moments (module doc), with a first-order estimate of
    /// each one's rounding. Needs `c > 0`.
    pub fn squares_between(
        &self,
        (t0, x0, v0): (f64, f64, f64),
        (t1, x1, v1): (f64, f64, f64),
    ) -> Squares {
        let Oscillator { mass, k, c, .. } = self.osc;
        let (f0, s) = (self.f0, self.s);
        let tau = t1 - t0;
        // int t, int t^2 over the piece.
        let t_1 = 0.5 * tau * (t0 + t1);
        let t_2 = tau * (t1 * t1 + t1 * t0 + t0 * t0) / 3.0;
        let int_f = f0 * tau + s * t_1;
        let int_tf = f0 * t_1 + s * t_2;
        let (dx, dv) = (x1 - x0, v1 - v0);
        let inv_k = 1.0 / k;
        let int_x = (int_f - mass * dv - c * dx) * inv_k;
        let int_tx =
            (int_tf - mass * (t1 * v1 - t0 * v0 - dx) - c * (t1 * x1 - t0 * x0 - int_x)) * inv_k;
        let int_xv = 0.5 * dx * (x1 + x0);
        let int_vf = x1 * self.load(t1) - x0 * self.load(t0) - s * int_x;
        let int_xf = f0 * int_x + s * int_tx;
        let kinetic = 0.5 * mass * dv * (v1 + v0);
        let int_vv = (int_vf - k * int_xv - kinetic) / c;
        let xv = x1 * v1 - x0 * v0;
        let int_xx = (int_xf - c * int_xv - mass * (xv - int_vv)) * inv_k;
        let mut a2 = c * c * int_vv + k * k * int_xx + 2.0 * c * k * int_xv;
        // The rounding, to first order: the sizes of each sum's terms times a few units, with
        // the ends' own rounding, which is that of the free part and the particular solution
        // they are the sum of (so sizes `|x| + 2 |x_p|`, `|v| + 2 |p1|`).
        let eps = 4.0 * f64::EPSILON;
        let size_x = |t: f64, x: f64| x.abs() + 2.0 * (self.p0.abs() + (self.p1 * t).abs());
        let (sx0, sx1) = (size_x(t0, x0), size_x(t1, x1));
        let (sv0, sv1) = (
            v0.abs() + 2.0 * self.p1.abs(),
            v1.abs() + 2.0 * self.p1.abs(),
        );
        let (sf0, sf1) = (self.load(t0).abs(), self.load(t1).abs());
        let size_int_x =
            (f0.abs() * tau + (s * t_1).abs() + mass * (sv0 + sv1) + c * (sx0 + sx1)) * inv_k;
        let size_int_tx = (f0.abs() * t_1
            + (s * t_2).abs()
            + mass * (t1 * sv1 + t0 * sv0 + sx0 + sx1)
            + c * (t1 * sx1 + t0 * sx0 + size_int_x))
            * inv_k;
        let size_xv = 0.5 * (sx0 * sx0 + sx1 * sx1);
        let size_vf = sx1 * sf1 + sx0 * sf0 + s.abs() * size_int_x;
        let size_xf = f0.abs() * size_int_x + s.abs() * size_int_tx;
        let err_vv = eps * (size_vf + k * size_xv + 0.5 * mass * (sv0 * sv0 + sv1 * sv1)) / c;
        let err_xx = (eps * (size_xf + c * size_xv + mass * (sx1 * sv1 + sx0 * sv0))
            + mass * err_vv)
            * inv_k;
        let mut err_a2 = c * c * err_vv + k * k * err_xx + eps * 2.0 * c * k * size_xv;
        if self.contact {
            let int_ff = f0 * f0 * tau + 2.0 * f0 * s * t_1 + s * s * t_2;
            let load = int_ff - 2.0 * c * int_vf - 2.0 * k * int_xf;
            a2 += load;
            err_a2 += eps * (int_ff.abs() + 2.0 * c * size_vf + 2.0 * k * size_xf);
        }
        let inv_m2 = 1.0 / (mass * mass);
        Squares {
            x2: int_xx,
            a2: a2 * inv_m2,
            err_x2: err_xx,
            err_a2: err_a2 * inv_m2,
        }
    }

    /// The absolute acceleration of the main mass in state `(x, v)` at `t` (m/s^2): with the
    /// load a force, `x''`; under ground acceleration `x'' + a_g = -(c v + k x) / mass`.
    #[inline]
    pub fn absolute_accel(&self, t: f64, x: f64, v: f64) -> f64 {
        let load = if self.contact { self.load(t) } else { 0.0 };
        (load - self.osc.c * v - self.osc.k * x) / self.osc.mass
    }
}

impl Motion for Ramp {
    /// `(f0 + s t - c v - k x) / mass`.
    #[inline]
    fn accel_at(&self, t: f64, x: f64, v: f64) -> f64 {
        (self.load(t) - self.osc.c * v - self.osc.k * x) / self.osc.mass
    }

    /// A force on the main mass stays; a ground acceleration's load `-mass a_g` scales with
    /// the mass.
    fn with_mass(&self, mass: f64) -> Self {
        let scale = if self.contact {
            1.0
        } else {
            mass / self.osc.mass
        };
        let osc = Oscillator::new(mass, self.osc.k, self.osc.c);
        Ramp::new(
            osc,
            self.f0 * scale,
            self.s * scale,
            self.len,
            (self.ya, self.yj),
            self.contact,
        )
    }

    #[inline]
    fn inner_accel(&self, t: f64) -> (f64, f64, f64) {
        (self.ya + self.yj * t, self.yj, self.ya_max)
    }
}

impl Driven for Ramp {
    #[inline]
    fn start(&self, t0: f64, x0: f64, v0: f64) -> (f64, f64, Jet) {
        let (h0, g0) = (x0 - (self.p0 + self.p1 * t0), v0 - self.p1);
        let hk = Kinematics {
            x: h0,
            v: g0,
            a: self.osc.accel(h0, g0),
        };
        (h0, g0, self.compose(hk, t0))
    }

    #[inline]
    fn jet(&self, t0: f64, h0: f64, g0: f64, t: f64) -> Jet {
        self.compose(self.osc.eval_fast(h0, g0, t - t0), t)
    }

    #[inline]
    fn bounds(&self, jet: &Jet) -> [f64; 6] {
        let mut b = self.osc.derivative_bounds(jet.xh, jet.vh);
        b[0] += self.p0.abs().max((self.p0 + self.p1 * self.len).abs());
        b[1] += self.p1.abs();
        b
    }

    #[inline]
    fn oscillator(&self) -> &Oscillator {
        &self.osc
    }

    #[inline]
    fn contact_load(&self, t: f64) -> [f64; 4] {
        if self.contact {
            [self.load(t), self.s, 0.0, 0.0]
        } else {
            [0.0; 4]
        }
    }

    #[inline]
    fn contact_load_bounds(&self) -> (f64, f64) {
        (0.0, 0.0)
    }

    #[inline]
    fn contact_sign(&self, t: f64, jet: &Jet) -> f64 {
        let load = if self.contact { self.load(t) } else { 0.0 };
        self.osc.c * jet.v + self.osc.k * jet.x - load
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RK4 on `mass x'' + c x' + k x = f0 + s t` with a small step.
    fn rk4(r: &Ramp, x0: f64, v0: f64, t0: f64, t1: f64, n: usize) -> (f64, f64) {
        let h = (t1 - t0) / n as f64;
        let (mut x, mut v) = (x0, v0);
        let acc = |t: f64, x: f64, v: f64| r.accel_at(t, x, v);
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
        for c in [0.0, 0.1, 0.5 * crit, crit, 3.0 * crit] {
            for (f0, s) in [(0.0, 0.0), (0.3, -40.0), (-2.0, 300.0)] {
                let r = Ramp::new(Oscillator::new(mass, k, c), f0, s, 0.01, (0.0, 0.0), true);
                let (t0, t1) = (0.002, 0.01);
                let (h0, g0, _) = r.start(t0, 0.003, -0.2);
                let jet = r.jet(t0, h0, g0, t1);
                let (x, v) = rk4(&r, 0.003, -0.2, t0, t1, 20_000);
                assert!((jet.x - x).abs() <= 1e-12, "c={c} s={s}: {} vs {x}", jet.x);
                assert!((jet.v - v).abs() <= 1e-10, "c={c} s={s}: {} vs {v}", jet.v);
                // The equation of motion holds for the derivatives the brackets use.
                let res = mass * jet.a + c * jet.v + k * jet.x - r.load(t1);
                assert!(res.abs() <= 1e-11 * (1.0 + f0.abs() + s.abs()), "{res}");
                let res1 = mass * jet.j + c * jet.a + k * jet.v - s;
                assert!(res1.abs() <= 1e-9 * (1.0 + s.abs()), "{res1}");
            }
        }
    }

    #[test]
    fn square_integrals_from_the_ends_are_the_quadratures_within_their_estimate() {
        // Issue 69: `int x^2` and `int a^2` from a piece's two ends against 8-point
        // Gauss–Legendre on the closed form over 64 sub-pieces (to rounding), in every damping
        // regime, short and whole pieces, gentle and steep ramps, a force and ground
        // acceleration: within the returned estimate of their rounding (plus the quadrature's
        // own few units).
        let (mass, k): (f64, f64) = (1.0, 246.7);
        let crit = 2.0 * (k * mass).sqrt();
        let mut worst = 0.0f64;
        for c in [0.01, 0.628, 0.5 * crit, crit, 3.0 * crit] {
            for (f0, s) in [(0.0, 0.0), (0.3, -40.0), (-2.0, 1700.0)] {
                for contact in [false, true] {
                    let r = Ramp::new(
                        Oscillator::new(mass, k, c),
                        f0,
                        s,
                        0.005,
                        (0.0, 0.0),
                        contact,
                    );
                    for (t0, t1) in [(0.0, 0.005), (0.0012, 0.0013), (0.004, 0.005)] {
                        let (x0, v0) = (0.003, -0.2);
                        let (h0, g0, _) = r.start(t0, x0, v0);
                        let end = r.jet(t0, h0, g0, t1);
                        let got = r.squares_between((t0, x0, v0), (t1, end.x, end.v));
                        let want =
                            crate::numeric::gauss_legendre_n(t0, t1, (t1 - t0) / 64.0, |t| {
                                let jet = r.jet(t0, h0, g0, t);
                                let a = r.absolute_accel(t, jet.x, jet.v);
                                [jet.x * jet.x, a * a]
                            });
                        for (g, w, e) in
                            [(got.x2, want[0], got.err_x2), (got.a2, want[1], got.err_a2)]
                        {
                            let off = (g - w).abs();
                            assert!(
                                off <= e + 16.0 * f64::EPSILON * w,
                                "c={c} s={s} contact={contact} [{t0}, {t1}]: {g} against {w}, estimate {e}"
                            );
                            worst = worst.max(off / (e + 16.0 * f64::EPSILON * w));
                        }
                    }
                }
            }
        }
        eprintln!("from the ends: worst error {worst:.3} of its estimate");
    }

    #[test]
    fn bounds_hold_over_the_interval() {
        let r = Ramp::new(
            Oscillator::new(0.1, 400.0, 0.1),
            1.0,
            -150.0,
            0.02,
            (0.0, 0.0),
            true,
        );
        let (h0, g0, j0) = r.start(0.0, 0.01, 1.0);
        let b = r.bounds(&j0);
        for i in 0..=200 {
            let jet = r.jet(0.0, h0, g0, i as f64 * 1e-4);
            assert!(jet.x.abs() <= b[0] && jet.v.abs() <= b[1] && jet.a.abs() <= b[2]);
            assert!(jet.j.abs() <= b[3] && jet.j2.abs() <= b[4]);
        }
    }

    #[test]
    fn the_contact_function_changes_sign_with_the_pair_acceleration() {
        // A force on the pair: mass x'' = F - (c v + k x), so the contact function
        // c v + k x - F has the sign of -x''. Under ground acceleration the load drops out.
        let osc = Oscillator::new(0.12, 400.0, 0.1);
        let force = Ramp::new(osc, 2.0, 10.0, 0.01, (0.0, 0.0), true);
        let (_, _, jet) = force.start(0.004, 0.001, 0.3);
        let g = force.contact_sign(0.004, &jet);
        assert!(g * -jet.a > 0.0);
        assert!((g + osc.mass * jet.a).abs() < 1e-12);
        let base = Ramp::new(osc, 2.0, 10.0, 0.01, (-1.0, 5.0), false);
        let (_, _, jet) = base.start(0.004, 0.001, 0.3);
        assert_eq!(base.contact_sign(0.004, &jet), 0.1 * 0.3 + 400.0 * 0.001);
    }
}
