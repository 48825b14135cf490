//! Closed-form motion of the free linear oscillator `mass x'' + c x' + k x = 0`.
//!
//! With `alpha = c / (2 mass)`, `w2 = k / mass` and `q = w2 - alpha^2` (the square of the
//! damped frequency, negative when over-damped), the motion from `(x0, v0)` after a time `tau` is
//!
//! ```text
//! x(tau) = e^{-alpha tau} [ x0 c(tau) + (v0 + alpha x0) s(tau) ]
//! v(tau) = e^{-alpha tau} [ v0 c(tau) - (alpha v0 + w2 x0) s(tau) ]
//! ```
//!
//! where `c = cos(sqrt(q) tau)`, `s = sin(sqrt(q) tau) / sqrt(q)` when under-damped,
//! `c = 1`, `s = tau` at critical damping and `c = cosh`, `s = sinh / sqrt(-q)` when
//! over-damped. Both `c` and `s` are entire functions of `q tau^2`, so the motion is continuous
//! across critical damping and no formula divides by a vanishing damped frequency:
//! `sin(theta) / omega_d = tau sin(theta) / theta` keeps full relative precision as
//! `omega_d -> 0`. `q` itself is formed as `(4 k mass - c^2) / (4 mass^2)` with a fused
//! multiply-add, so near `zeta = 1` it carries only the rounding of the inputs.
//!
//! Far into the over-damped regime `e^{-alpha tau}` underflows while `cosh(beta tau)` overflows;
//! there the motion is evaluated as the sum of the two real exponential modes
//! `e^{r1 tau}`, `e^{r2 tau}` with the slow root formed without cancellation,
//! `r1 = -w2 / (alpha + beta)`, `r2 = -(alpha + beta)`.

/// A free linear oscillator; `mass > 0`, `k > 0`, `c >= 0` (checked by the caller).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillator {
    pub mass: f64,
    pub k: f64,
    pub c: f64,
    /// `c / (2 mass)` (1/s).
    pub alpha: f64,
    /// `k / mass` (1/s^2).
    pub w2: f64,
    /// `w2 - alpha^2` (1/s^2): > 0 under-damped, 0 critical, < 0 over-damped.
    pub q: f64,
    /// `sqrt(|q|)` (1/s).
    pub root: f64,
    /// `sqrt(w2)` (1/s), the undamped natural frequency.
    pub wn: f64,
    /// `1 / w2` (s^2).
    pub inv_w2: f64,
    /// `1 / root` (s), infinite at critical damping.
    pub inv_root: f64,
    /// `1 / mass` (1/kg).
    pub inv_mass: f64,
}

/// The degree of [`Oscillator::taylor`]'s polynomial.
pub const TAYLOR_DEGREE: usize = 10;
/// The longest `rho h` over which [`Oscillator::taylor`]'s polynomial stands for the motion.
pub const TAYLOR_REACH: f64 = 0.1;

/// The free motion's Taylor polynomial ([`Oscillator::taylor`]): the coefficients of `x` and
/// of `x'`.
#[derive(Clone, Copy, Debug)]
pub struct Taylor {
    c: [f64; TAYLOR_DEGREE + 1],
    d: [f64; TAYLOR_DEGREE],
}

impl Taylor {
    /// `x(h)` and `x'(h)` (Horner).
    #[inline]
    pub fn at(&self, h: f64) -> (f64, f64) {
        let mut x = self.c[TAYLOR_DEGREE];
        let mut v = self.d[TAYLOR_DEGREE - 1];
        for n in (0..TAYLOR_DEGREE).rev() {
            x = x * h + self.c[n];
        }
        for n in (0..TAYLOR_DEGREE - 1).rev() {
            v = v * h + self.d[n];
        }
        (x, v)
    }
}

/// The state-transition matrix of the free motion over a fixed time `h`:
/// `(x, v)(t + h) = [[xx, xv], [vx, vv]] (x, v)(t)`. Stepping by it costs one 2 x 2 multiply
/// instead of an exponential and a sine and cosine (see [`Oscillator::propagator`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Propagator {
    pub xx: f64,
    pub xv: f64,
    pub vx: f64,
    pub vv: f64,
}

impl Propagator {
    /// The state `h` later.
    #[inline]
    pub fn apply(&self, x: f64, v: f64) -> (f64, f64) {
        (self.xx * x + self.xv * v, self.vx * x + self.vv * v)
    }
}

/// Displacement, velocity and acceleration at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    pub x: f64,
    pub v: f64,
    pub a: f64,
}

impl Oscillator {
    pub fn new(mass: f64, k: f64, c: f64) -> Self {
        let alpha = c / (2.0 * mass);
        let w2 = k / mass;
        // 4 k mass - c^2 with one rounding (fma), then scaled: no cancellation beyond the inputs'.
        let q = c.mul_add(-c, 4.0 * k * mass) / (4.0 * mass * mass);
        Oscillator {
            mass,
            k,
            c,
            alpha,
            w2,
            q,
            root: q.abs().sqrt(),
            wn: w2.sqrt(),
            inv_w2: 1.0 / w2,
            inv_root: 1.0 / q.abs().sqrt(),
            inv_mass: 1.0 / mass,
        }
    }

    /// Acceleration of the free oscillator in state `(x, v)`.
    #[inline]
    pub fn accel(&self, x: f64, v: f64) -> f64 {
        -(self.c * v + self.k * x) / self.mass
    }

    /// The two mode functions `(e^{-alpha tau} c(tau), e^{-alpha tau} s(tau))`, with the
    /// standard library's sine and cosine and a division by the damped frequency (the bits the
    /// free-decay scene was minted with).
    #[inline]
    fn modes(&self, tau: f64) -> (f64, f64) {
        self.modes_by::<false>(tau)
    }

    /// `FAST`: the mode functions for the driven scenes' event finders, which evaluate them at
    /// every step: the sine and cosine of the pure-Rust `libm` crate (inlined, about 1.5 times
    /// as fast as the system's on these arguments, and the same bits on every platform) and a
    /// multiplication by `1 / root`. They agree with [`Oscillator::modes`] to an ulp or two.
    #[inline(always)]
    fn modes_by<const FAST: bool>(&self, tau: f64) -> (f64, f64) {
        if tau == 0.0 {
            // What every branch below gives at `tau = +-0` (a phase's start), without the
            // exponential and the sine and cosine.
            return (1.0, 0.0f64.copysign(tau));
        }
        if self.q > 0.0 {
            let th = self.root * tau;
            let (sn, cs) = if FAST { libm::sincos(th) } else { th.sin_cos() };
            let env = if self.alpha == 0.0 {
                1.0
            } else {
                (-self.alpha * tau).exp()
            };
            if FAST {
                (env * cs, env * sn * self.inv_root)
            } else {
                (env * cs, env * sn / self.root)
            }
        } else if self.q == 0.0 {
            let env = (-self.alpha * tau).exp();
            (env, env * tau)
        } else {
            let beta = self.root;
            let bt = beta * tau;
            if bt < 1.0 {
                let env = (-self.alpha * tau).exp();
                (env * bt.cosh(), env * bt.sinh() / beta)
            } else {
                let sum = self.alpha + beta;
                let e1 = (-self.w2 / sum * tau).exp();
                let e2 = (-sum * tau).exp();
                (0.5 * (e1 + e2), (e1 - e2) / (2.0 * beta))
            }
        }
    }

    /// The motion a time `tau >= 0` after the state `(x0, v0)`.
    #[inline]
    pub fn eval(&self, x0: f64, v0: f64, tau: f64) -> Kinematics {
        self.eval_by::<false>(x0, v0, tau)
    }

    /// [`Oscillator::eval`] with the fast mode functions (the `libm` crate's sine and cosine, a
    /// multiplication by `1 / root`) and the acceleration by a multiplication by `1 / mass`: what
    /// the driven scenes' closed forms evaluate at every step. It agrees with `eval` to a few
    /// ulps.
    #[inline]
    pub fn eval_fast(&self, x0: f64, v0: f64, tau: f64) -> Kinematics {
        self.eval_by::<true>(x0, v0, tau)
    }

    #[inline(always)]
    fn eval_by<const FAST: bool>(&self, x0: f64, v0: f64, tau: f64) -> Kinematics {
        let (c, s) = self.modes_by::<FAST>(tau);
        let x = x0 * c + (v0 + self.alpha * x0) * s;
        let v = v0 * c - (self.alpha * v0 + self.w2 * x0) * s;
        let a = if FAST {
            -(self.c * v + self.k * x) * self.inv_mass
        } else {
            self.accel(x, v)
        };
        Kinematics { x, v, a }
    }

    /// The propagator over a fixed time `h >= 0`: from the closed form,
    /// `x(h) = (c + alpha s) x0 + s v0` and `v(h) = -w2 s x0 + (c - alpha s) v0` with the mode
    /// functions `(c, s)` at `h`. Each application rounds once more, so a long chain drifts by
    /// about one ulp a step; restart it from [`Oscillator::eval`] now and then.
    pub fn propagator(&self, h: f64) -> Propagator {
        let (c, s) = self.modes(h);
        Propagator {
            xx: c + self.alpha * s,
            xv: s,
            vx: -self.w2 * s,
            vv: c - self.alpha * s,
        }
    }

    /// The Taylor coefficients `x^(n)(0) / n!`, `n = 0..=TAYLOR_DEGREE`, of the free motion from
    /// `(x, v)`: `x'' = -(2 alpha x' + w2 x)` differentiated, so
    /// `c_n = -(2 alpha c_(n-1) / n + w2 c_(n-2) / (n (n - 1)))`. No exponential, no sine.
    ///
    /// The remainder over `[0, h]`: every derivative obeys `|x^(n)| <= B0 rho^n`, with `B0` the
    /// energy's amplitude `sqrt(x^2 + v^2 / w2)` and `rho = alpha + sqrt(alpha^2 + w2)` (the
    /// recurrence `B_n = 2 alpha B_(n-1) + w2 B_(n-2)` of [`Oscillator::derivative_bounds`] grows
    /// by `rho`, and `|x'| <= wn B0 <= rho B0`). So with `rho h <= TAYLOR_REACH` the polynomial
    /// is off `x` by at most `B0 0.1^11 / 11! = 2.5e-19 B0` and off `x'` by at most
    /// `rho B0 0.1^10 / 10! = 2.8e-17 rho B0`: below a thousandth and an eighth of the rounding
    /// `eps B0` that any evaluation of the motion carries.
    pub fn taylor(&self, x: f64, v: f64) -> Taylor {
        // 1 / n and 1 / (n (n - 1)), n = 0..=TAYLOR_DEGREE (the first two unused).
        const INV: [f64; TAYLOR_DEGREE + 1] = {
            let mut a = [0.0; TAYLOR_DEGREE + 1];
            let mut n = 1;
            while n <= TAYLOR_DEGREE {
                a[n] = 1.0 / n as f64;
                n += 1;
            }
            a
        };
        const INV2: [f64; TAYLOR_DEGREE + 1] = {
            let mut a = [0.0; TAYLOR_DEGREE + 1];
            let mut n = 2;
            while n <= TAYLOR_DEGREE {
                a[n] = 1.0 / (n * (n - 1)) as f64;
                n += 1;
            }
            a
        };
        let mut c = [0.0; TAYLOR_DEGREE + 1];
        c[0] = x;
        c[1] = v;
        let two_alpha = 2.0 * self.alpha;
        for n in 2..=TAYLOR_DEGREE {
            c[n] = -(two_alpha * c[n - 1] * INV[n] + self.w2 * c[n - 2] * INV2[n]);
        }
        let mut d = [0.0; TAYLOR_DEGREE];
        for n in 0..TAYLOR_DEGREE {
            d[n] = (n + 1) as f64 * c[n + 1];
        }
        Taylor { c, d }
    }

    /// `rho = alpha + sqrt(alpha^2 + w2)` (1/s): the rate that bounds the free motion's
    /// derivatives ([`Oscillator::taylor`]).
    pub fn derivative_rate(&self) -> f64 {
        self.alpha + (self.alpha * self.alpha + self.w2).sqrt()
    }

    /// Energy `(mass v^2 + k x^2) / 2` (J); it never increases along a free motion.
    #[inline]
    pub fn energy(&self, x: f64, v: f64) -> f64 {
        0.5 * (self.mass * v * v + self.k * x * x)
    }

    /// Bounds `B[j] >= |x^(j)(t)|`, `j = 0..=5`, valid for all later times of the free motion
    /// now in `(x, v)`: the energy `E = (mass v^2 + k x^2) / 2` never increases, so
    /// `|x| <= sqrt(2E/k) = sqrt(x^2 + v^2 / w2)` and `|v| <= sqrt(2E/mass) = wn sqrt(2E/k)`, and
    /// the equation of motion bounds each higher derivative,
    /// `|x^(j+2)| <= (c |x^(j+1)| + k |x^(j)|) / mass`. One square root and no division: the
    /// event finders call this at every step.
    #[inline]
    pub fn derivative_bounds(&self, x: f64, v: f64) -> [f64; 6] {
        let mut b = [0.0; 6];
        b[0] = x.mul_add(x, v * v * self.inv_w2).sqrt();
        b[1] = self.wn * b[0];
        for j in 2..6 {
            b[j] = 2.0 * self.alpha * b[j - 1] + self.w2 * b[j - 2];
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RK4 with a small step as an independent reference.
    fn rk4(o: &Oscillator, x0: f64, v0: f64, t: f64, n: usize) -> (f64, f64) {
        let h = t / n as f64;
        let (mut x, mut v) = (x0, v0);
        let f = |x: f64, v: f64| (v, o.accel(x, v));
        for _ in 0..n {
            let (k1x, k1v) = f(x, v);
            let (k2x, k2v) = f(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
            let (k3x, k3v) = f(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
            let (k4x, k4v) = f(x + h * k3x, v + h * k3v);
            x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        (x, v)
    }

    #[test]
    fn the_taylor_polynomial_is_the_closed_form_to_rounding_within_its_reach() {
        // Issue 69: the random scene's pieces integrate on the free part's Taylor polynomial
        // when `rho h <= TAYLOR_REACH`; there it is the closed form to a few rounding units of
        // the motion's amplitude, in every damping regime.
        let crit = 2.0 * (400.0f64 * 0.1).sqrt();
        let mut worst = (0.0f64, 0.0f64);
        for c in [0.0, 0.1, crit * 0.5, crit, crit * 2.0, crit * 50.0] {
            let o = Oscillator::new(0.1, 400.0, c);
            let rho = o.derivative_rate();
            for (x0, v0) in [(0.003, 2.0), (-1.0, 0.0), (0.0, 1e-3), (2e-3, -0.5)] {
                let b0 = (x0 * x0 + v0 * v0 / o.w2).sqrt();
                let poly = o.taylor(x0, v0);
                for i in 0..=50 {
                    let h = TAYLOR_REACH / rho * i as f64 / 50.0;
                    let exact = o.eval(x0, v0, h);
                    let (x, v) = poly.at(h);
                    let (ex, ev) = ((x - exact.x).abs() / b0, (v - exact.v).abs() / (rho * b0));
                    worst = (worst.0.max(ex), worst.1.max(ev));
                    assert!(ex <= 4.0 * f64::EPSILON, "c {c} h {h}: x off by {ex:e} B0");
                    assert!(
                        ev <= 4.0 * f64::EPSILON,
                        "c {c} h {h}: v off by {ev:e} rho B0"
                    );
                }
            }
        }
        eprintln!(
            "taylor against the closed form: x {:e} B0, v {:e} rho B0",
            worst.0, worst.1
        );
    }

    #[test]
    fn agrees_with_rk4_in_every_regime() {
        let crit = 2.0 * (400.0f64 * 0.1).sqrt();
        for c in [0.0, 0.1, crit * 0.5, crit, crit * 2.0, crit * 50.0] {
            let o = Oscillator::new(0.1, 400.0, c);
            for t in [1e-3, 0.02, 0.1] {
                let exact = o.eval(0.003, 2.0, t);
                let (x, v) = rk4(&o, 0.003, 2.0, t, 200_000);
                let scale = 2.0 / o.w2.sqrt();
                assert!(
                    (exact.x - x).abs() <= 1e-9 * scale,
                    "c={c} t={t}: {} vs {x}",
                    exact.x
                );
                assert!(
                    (exact.v - v).abs() <= 1e-8 * 2.0,
                    "c={c} t={t}: {} vs {v}",
                    exact.v
                );
            }
        }
    }

    #[test]
    fn continuous_across_critical_damping() {
        // zeta = 1 - 1e-12, 1, 1 + 1e-12 must agree to near machine precision.
        let (mass, k): (f64, f64) = (0.1, 400.0);
        let crit = 2.0 * (k * mass).sqrt();
        let at = |c: f64| Oscillator::new(mass, k, c).eval(0.0, 2.0, 0.05);
        let below = at(crit * (1.0 - 1e-12));
        let exactly = at(crit);
        let above = at(crit * (1.0 + 1e-12));
        for other in [below, above] {
            assert!((other.x - exactly.x).abs() <= 1e-11 * exactly.x.abs());
            assert!((other.v - exactly.v).abs() <= 1e-10 * exactly.v.abs().max(1e-3));
        }
        // Critical damping closed form: x = v0 t e^{-w t}.
        let w = (k / mass).sqrt();
        let expect = 2.0 * 0.05 * (-w * 0.05).exp();
        assert!((exactly.x - expect).abs() <= 1e-15 * expect.abs() * 4.0);
    }

    #[test]
    fn propagator_steps_agree_with_the_closed_form() {
        let crit = 2.0 * (400.0f64 * 0.1).sqrt();
        for c in [0.0, 0.1, crit, crit * 3.0] {
            let o = Oscillator::new(0.1, 400.0, c);
            let p = o.propagator(1e-3);
            let (mut x, mut v) = (0.003, 2.0);
            for i in 1..=64 {
                (x, v) = p.apply(x, v);
                let k = o.eval(0.003, 2.0, i as f64 * 1e-3);
                assert!(
                    (x - k.x).abs() <= 1e-13 * 0.1,
                    "c={c} i={i}: {x} vs {}",
                    k.x
                );
                assert!(
                    (v - k.v).abs() <= 1e-12 * 2.0,
                    "c={c} i={i}: {v} vs {}",
                    k.v
                );
            }
        }
    }

    #[test]
    fn the_fast_evaluation_agrees_with_the_standard_one() {
        let crit = 2.0 * (400.0f64 * 0.1).sqrt();
        for c in [0.0, 0.1, crit * 0.5, crit, crit * 2.0] {
            let o = Oscillator::new(0.1, 400.0, c);
            for i in 0..2000 {
                let t = i as f64 * 7.3e-4;
                let (a, b) = (o.eval(0.003, 2.0, t), o.eval_fast(0.003, 2.0, t));
                let scale = 0.003f64.hypot(2.0 / o.w2.sqrt());
                assert!((a.x - b.x).abs() <= 1e-14 * scale, "c={c} t={t}");
                assert!(
                    (a.v - b.v).abs() <= 1e-14 * scale * o.w2.sqrt(),
                    "c={c} t={t}"
                );
                assert!((a.a - b.a).abs() <= 1e-14 * scale * o.w2, "c={c} t={t}");
            }
        }
    }

    #[test]
    fn heavy_damping_far_in_time_is_finite() {
        let crit = 2.0 * (400.0f64 * 0.1).sqrt();
        let o = Oscillator::new(0.1, 400.0, 50.0 * crit);
        let k = o.eval(0.01, 2.0, 100.0);
        assert!(k.x.is_finite() && k.v.is_finite());
        assert!(k.x > 0.0 && k.x < 0.011);
    }

    #[test]
    fn energy_never_increases_and_bounds_hold() {
        let o = Oscillator::new(0.1, 400.0, 0.1);
        let e0 = o.energy(0.0, 2.0);
        let b = o.derivative_bounds(0.0, 2.0);
        let mut last = e0;
        for i in 1..1000 {
            let k = o.eval(0.0, 2.0, i as f64 * 1e-3);
            let e = o.energy(k.x, k.v);
            assert!(e <= last * (1.0 + 1e-14));
            last = e;
            assert!(k.x.abs() <= b[0] && k.v.abs() <= b[1] && k.a.abs() <= b[2]);
        }
    }
}
