//! Intensity measures of a ground motion (model.md §13, docs/scenes.md): its peak ground
//! acceleration and its spectral acceleration, both in g, as hazard curves and fragility
//! databases state them.
//!
//! # Equations
//! The ground acceleration `a_g` is given at samples `t_k = k dt` and is linear between them
//! ([`super::load`]), so
//!
//! ```text
//! PGA = max_k |a_g(t_k)| / g,
//! Sa(T, zeta) = omega^2 max_t |u(t)| / g,   u'' + 2 zeta omega u' + omega^2 u = -a_g(t),
//! omega = 2 pi / T, u(0) = u'(0) = 0,
//! ```
//!
//! `g = 9.80665 m/s^2`. Both are exact: the piecewise-linear load's extremes sit at samples, and
//! the oscillator moves in closed form between them ([`Oscillator`] plus the linear particular
//! solution of a ramp load); an extremum of `u` inside an interval (a sign change of `u'`) is
//! located by bisection on the closed form to a relative `1e-12` of the interval. `Sa` is the
//! pseudo-spectral acceleration of codes and of eqsig's and pyrotd's response spectra; those
//! evaluate `u` at the samples only, so they read up to `1 - cos(omega dt / 2)` lower (8e-4 at
//! `T = 0.4 s`, `dt = 0.005 s`).
//!
//! Over the run's duration only (the last interval possibly shorter), and at scale 1: a
//! realization scaled by `s` has `s PGA` and `s Sa`, since the oscillator is linear.

use super::RandomScene;
use super::hull::hull;
use super::load::{Normals, Plan, Samples};
pub use super::measure::{DEFAULT_IDA_MAX, DEFAULT_IDA_TOL, IntensitySpec, Measure, OwnIntensity};
use crate::sim::linear::Oscillator;

/// Standard gravity (m/s^2): an acceleration in g is `a / G`.
pub const G: f64 = 9.80665;

/// The damping ratio of the spectral acceleration, 5 % (codes' and hazard curves').
pub const SA_ZETA: f64 = 0.05;

/// PGA and `Sa(period, 5 %)` (g) of the load of `scene` drawn from `normals` (a record draws
/// none) at scale 1 over the scene's duration (module doc). Pure. A design's runs share one
/// motion's samples through [`super::RandomRun::own_intensity`] instead (the same bits).
pub fn own_intensity<N: Normals>(scene: &RandomScene, period: f64, normals: N) -> OwnIntensity {
    let plan = Plan::new(scene);
    of_samples(scene, period, Samples::new(&plan, scene.dt, normals, 1.0))
}

/// [`own_intensity`] of the load `samples` gives, interval by interval.
pub(crate) fn of_samples<N: Normals>(
    scene: &RandomScene,
    period: f64,
    mut samples: Samples<'_, N>,
) -> OwnIntensity {
    let dt = scene.dt;
    let omega = std::f64::consts::TAU / period;
    let osc = Oscillator::new(1.0, omega * omega, 2.0 * SA_ZETA * omega);
    let prop = osc.propagator(dt);
    // The cubic Hermite interpolant's error per unit B0 of the free part ([`may_exceed`]).
    let err4 = osc.derivative_bounds(1.0, 0.0)[4] * dt.powi(4) / 384.0;
    let third = dt / 3.0;
    let segments = scene.segments();
    let (mut u, mut v) = (0.0f64, 0.0f64);
    let (mut pga, mut umax) = (0.0f64, 0.0f64);
    for k in 0..segments {
        let (q0, slope) = samples.next();
        let len = if k + 1 == segments {
            (scene.duration - k as f64 * dt).clamp(0.0, dt)
        } else {
            dt
        };
        pga = pga.max(q0.abs()).max((q0 + slope * len).abs());
        // u'' + c u' + k u = f0 + s t with f0 = -q0, s = -slope: the particular solution
        // p0 + p1 t, p1 = s / k, p0 = (f0 - c p1) / k; the free part from (u - p0, v - p1).
        let p1 = -slope * osc.inv_w2;
        let p0 = (-q0 - osc.c * p1) * osc.inv_w2;
        let (hx, hv) = (u - p0, v - p1);
        let (hx1, hv1) = if len == dt {
            prop.apply(hx, hv)
        } else {
            let e = osc.eval(hx, hv, len);
            (e.x, e.v)
        };
        let (u1, v1) = (hx1 + p0 + p1 * len, hv1 + p1);
        if v * v1 < 0.0
            && (len < dt
                || may_exceed(
                    umax,
                    (u, v),
                    (u1, v1),
                    (hx, hv, p0, p1),
                    &osc,
                    (dt, third),
                    err4,
                ))
        {
            let m = extremum_time(&osc, (hx, hv), p1, len, v, v1);
            umax = umax.max((osc.eval(hx, hv, m).x + p0 + p1 * m).abs());
        }
        umax = umax.max(u1.abs());
        u = u1;
        v = v1;
    }
    OwnIntensity {
        pga: pga / G,
        sa: omega * omega * umax / G,
    }
}

/// Whether `|u|` may exceed `umax` inside a whole interval of `dt` from `(u0, v0)` to
/// `(u1, v1)` (the free part from `(hx, hv)`, the particular `p0 + p1 t`): `false` only when it
/// cannot, nor can the closed form evaluated anywhere in it. `u` is within
/// `max |u''''| dt^4 / 384` of its cubic Hermite interpolant (`u'''' = h_x''''`, at most
/// `err4 B0`, [`Oscillator::derivative_bounds`]), which lies in the convex hull of its Bézier
/// points `u0, u0 + dt v0 / 3, u1 - dt v1 / 3, u1` ([`hull`]; `third = dt / 3`); a margin of
/// `1e-12` of the sizes covers the rounding. An extremum that cannot exceed `umax` leaves
/// `max(umax, |u(t_m)|)` as it is, so its location (a bisection) is skipped with the same
/// result, bit for bit.
fn may_exceed(
    umax: f64,
    (u0, v0): (f64, f64),
    (u1, v1): (f64, f64),
    (hx, hv, p0, p1): (f64, f64, f64, f64),
    osc: &Oscillator,
    (dt, third): (f64, f64),
    err4: f64,
) -> bool {
    let (lo, hi) = hull(u0, v0, u1, v1, third);
    let b0 = hx.mul_add(hx, hv * hv * osc.inv_w2).sqrt();
    let bound = hi.max(-lo) + err4 * b0;
    let margin = 1e-12 * (bound + b0 + p0.abs() + p1.abs() * dt);
    // (NaN: it may.)
    let below = bound + margin < umax;
    !below
}

/// The time in `(0, len)` of the sign change of `u'(t) = h_v(t) + p1` (the free part from `h`,
/// `u'(0) = va`, `u'(len) = vb` of opposite signs): bisection on the closed form to a relative
/// `1e-12` of the interval, its midpoint.
///
/// The bisection's halvings are decided without evaluating the closed form where the answer is
/// certain: Newton's method first finds the root `t*`, and a midpoint farther than `delta` from
/// it lies on the side of `0` or of `len` that its position says, where `delta` is a thousand
/// times the rounding of `u'` (eight ulps of its terms) over half the slope `|u''(t*)|`, and at
/// least `1e-11 len`. Only the few midpoints within `delta` of the root are evaluated, so the
/// bisection takes the same halvings as with every midpoint evaluated (the same bits) at about
/// a quarter of the evaluations. When Newton's method does not settle inside the interval, or
/// the slope at its root is too small for the margin, every midpoint is evaluated.
fn extremum_time(
    osc: &Oscillator,
    (hx, hv): (f64, f64),
    p1: f64,
    len: f64,
    va: f64,
    vb: f64,
) -> f64 {
    let vel = |t: f64| osc.eval(hx, hv, t).v + p1;
    let root = newton_root(osc, (hx, hv), p1, len, va, vb);
    let (mut a, mut b) = (0.0, len);
    let a_neg = va < 0.0;
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        let neg = match root {
            Some((t, delta)) if m < t - delta => a_neg,
            Some((t, delta)) if m > t + delta => !a_neg,
            _ => vel(m) < 0.0,
        };
        if neg == a_neg {
            a = m;
        } else {
            b = m;
        }
        if b - a <= 1e-12 * len {
            break;
        }
    }
    0.5 * (a + b)
}

/// The root `t*` of `u'` in `(0, len)` by Newton's method from the secant's, and the margin
/// `delta` beyond which the sign of the evaluated `u'` is certain ([`extremum_time`]); `None`
/// when the method leaves the interval, does not settle in 8 steps, or the margin is wider than
/// a hundredth of the interval.
fn newton_root(
    osc: &Oscillator,
    (hx, hv): (f64, f64),
    p1: f64,
    len: f64,
    va: f64,
    vb: f64,
) -> Option<(f64, f64)> {
    let mut t = len * va / (va - vb);
    for _ in 0..8 {
        let e = osc.eval(hx, hv, t);
        let step = (e.v + p1) / e.a;
        let next = t - step;
        if !(next > 0.0 && next < len) {
            return None;
        }
        t = next;
        if step.abs() <= 1e-13 * len {
            // The rounding of u' = h_v + p1: eight ulps of the sizes of its terms (the closed
            // form's, bounded by the free part's energy, and p1), over half the slope (the last
            // step's, the same at t* to a relative 1e-13 and more).
            let size = (hv * hv + osc.w2 * hx * hx).sqrt() + p1.abs();
            let slope = 0.5 * e.a.abs();
            let delta = (1e3 * 8.0 * f64::EPSILON * size / slope).max(1e-11 * len) + step.abs();
            return (delta.is_finite() && delta < 0.01 * len).then_some((t, delta));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::random::{Excitation, Recorded};

    fn record(values: Vec<f64>, dt: f64) -> RandomScene {
        let n = values.len();
        RandomScene {
            excitation: Excitation::Record(Recorded {
                values: values.into(),
                scale: 1.0,
            }),
            dt,
            duration: (n - 1) as f64 * dt,
            ..RandomScene::placeholder()
        }
    }

    #[test]
    fn a_sine_records_sa_as_its_steady_response_and_pga_as_its_peak() {
        // a_g = A sin(w t) at T far from the drive: the steady amplitude of u is
        // A / sqrt((w0^2 - w^2)^2 + (2 zeta w0 w)^2); over 60 s the transient has died
        // (zeta w0 t = 0.05 * 2 pi * 60 / 0.5 >> 1) but the start's transient sets the early
        // peak, so compare against an independent fine Runge–Kutta run instead.
        let dt = 0.001;
        let (amp, w) = (3.0, 7.0);
        let values: Vec<f64> = (0..=20_000)
            .map(|k| amp * (w * k as f64 * dt).sin())
            .collect();
        let scene = record(values.clone(), dt);
        let own = own_intensity(&scene, 0.5, crate::sim::random::GivenNormals::new(&[]));
        assert!((own.pga - amp / G).abs() < 1e-4 * amp / G, "{}", own.pga);
        // RK4 at dt / 20 on the same piecewise-linear load.
        let w0 = std::f64::consts::TAU / 0.5;
        let h = dt / 20.0;
        let load = |t: f64| {
            let k = ((t / dt).floor() as usize).min(values.len() - 2);
            let f = t / dt - k as f64;
            values[k] * (1.0 - f) + values[k + 1] * f
        };
        let acc = |t: f64, u: f64, v: f64| -load(t) - 2.0 * SA_ZETA * w0 * v - w0 * w0 * u;
        let (mut u, mut v, mut umax) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..(20_000 * 20) {
            let t = i as f64 * h;
            let (k1u, k1v) = (v, acc(t, u, v));
            let (k2u, k2v) = (
                v + 0.5 * h * k1v,
                acc(t + 0.5 * h, u + 0.5 * h * k1u, v + 0.5 * h * k1v),
            );
            let (k3u, k3v) = (
                v + 0.5 * h * k2v,
                acc(t + 0.5 * h, u + 0.5 * h * k2u, v + 0.5 * h * k2v),
            );
            let (k4u, k4v) = (v + h * k3v, acc(t + h, u + h * k3u, v + h * k3v));
            u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            umax = umax.max(u.abs());
        }
        let sa_rk = w0 * w0 * umax / G;
        assert!(
            (own.sa - sa_rk).abs() < 1e-6 * sa_rk,
            "exact {} against RK4 {}",
            own.sa,
            sa_rk
        );
    }

    /// The bisection as it was before the Newton root decided its halvings (issue 69): every
    /// midpoint evaluated.
    fn plain_bisection(osc: &Oscillator, (hx, hv): (f64, f64), p1: f64, len: f64, va: f64) -> f64 {
        let (mut a, mut b) = (0.0, len);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            let vm = osc.eval(hx, hv, m).v + p1;
            if (vm < 0.0) == (va < 0.0) {
                a = m;
            } else {
                b = m;
            }
            if b - a <= 1e-12 * len {
                break;
            }
        }
        0.5 * (a + b)
    }

    #[test]
    fn the_extremum_time_is_the_plain_bisections_bit_for_bit() {
        // Issue 69: intervals of 5 ms and 20 ms on oscillators of 0.05 to 2 s under random
        // states and ramps, every one with a sign change of u' inside: the same time to the bit
        // as the bisection that evaluates every midpoint, and the shortcut taken in most.
        let mut rng = crate::sim::random::RealizationStream::new(69, 5, 0);
        let (mut n, mut fast) = (0, 0);
        for period in [0.05, 0.1, 0.4, 1.0, 2.0] {
            let omega = std::f64::consts::TAU / period;
            let osc = Oscillator::new(1.0, omega * omega, 2.0 * SA_ZETA * omega);
            for len in [0.005, 0.02] {
                for _ in 0..4000 {
                    let hx = 1e-2 * rng.next_normal();
                    let hv = 1e-2 * omega * rng.next_normal();
                    let p1 = 1e-3 * omega * rng.next_normal();
                    let va = hv + p1;
                    let vb = osc.eval(hx, hv, len).v + p1;
                    if va * vb >= 0.0 {
                        continue;
                    }
                    n += 1;
                    if newton_root(&osc, (hx, hv), p1, len, va, vb).is_some() {
                        fast += 1;
                    }
                    let t = extremum_time(&osc, (hx, hv), p1, len, va, vb);
                    let r = plain_bisection(&osc, (hx, hv), p1, len, va);
                    assert_eq!(
                        t.to_bits(),
                        r.to_bits(),
                        "T {period}, len {len}: {t} vs {r}"
                    );
                }
            }
        }
        assert!(n > 1000 && fast * 10 > 9 * n, "{fast} of {n}");
    }

    /// The Sa pass as it was before issue 69: every extremum located by the plain bisection.
    fn plain_sa(scene: &RandomScene, period: f64, normals: impl Normals) -> f64 {
        let plan = Plan::new(scene);
        let dt = scene.dt;
        let mut samples = Samples::new(&plan, dt, normals, 1.0);
        let omega = std::f64::consts::TAU / period;
        let osc = Oscillator::new(1.0, omega * omega, 2.0 * SA_ZETA * omega);
        let prop = osc.propagator(dt);
        let (mut u, mut v, mut umax) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..scene.segments() {
            let (q0, slope) = samples.next();
            let p1 = -slope * osc.inv_w2;
            let p0 = (-q0 - osc.c * p1) * osc.inv_w2;
            let (hx, hv) = (u - p0, v - p1);
            let (hx1, hv1) = prop.apply(hx, hv);
            let (u1, v1) = (hx1 + p0 + p1 * dt, hv1 + p1);
            if v * v1 < 0.0 {
                let m = plain_bisection(&osc, (hx, hv), p1, dt, v);
                umax = umax.max((osc.eval(hx, hv, m).x + p0 + p1 * m).abs());
            }
            umax = umax.max(u1.abs());
            u = u1;
            v = v1;
        }
        omega * omega * umax / G
    }

    #[test]
    fn the_sa_pass_is_the_plain_passes_bit_for_bit() {
        // Issue 69: the seismic showcase's motions (enveloped Clough-Penzien, 20 s at 5 ms)
        // at three periods: the same Sa to the bit with the extrema that cannot raise the
        // maximum skipped and the others located by the Newton-guided bisection.
        use crate::sim::random::{Envelope, RandomLoad, RealizationStream, Spectrum};
        let scene = RandomScene {
            excitation: Excitation::Random(RandomLoad {
                spectrum: Spectrum::CloughPenzien {
                    omega_g: 15.708,
                    zeta_g: 0.6,
                    // The showcase's, a tenth of omega_g (not pi / 2).
                    #[allow(clippy::approx_constant)]
                    omega_f: 1.5708,
                    zeta_f: 0.6,
                },
                S0: 0.005,
                envelope: Some(Envelope {
                    t1: 2.0,
                    t2: 12.0,
                    c: 0.3,
                }),
            }),
            duration: 20.0,
            ..RandomScene::placeholder()
        };
        for period in [0.1, 0.4, 1.5] {
            for r in 0..100 {
                let a = own_intensity(&scene, period, RealizationStream::new(2026, 0, r)).sa;
                let b = plain_sa(&scene, period, RealizationStream::new(2026, 0, r));
                assert_eq!(a.to_bits(), b.to_bits(), "T {period}, realization {r}");
            }
        }
    }

    #[test]
    fn intensity_scales_with_the_load() {
        let values: Vec<f64> = (0..2000)
            .map(|k| ((k * 7919) % 101) as f64 - 50.0)
            .collect();
        let a = own_intensity(
            &record(values.clone(), 0.01),
            0.4,
            crate::sim::random::GivenNormals::new(&[]),
        );
        let doubled: Vec<f64> = values.iter().map(|v| 2.0 * v).collect();
        let b = own_intensity(
            &record(doubled, 0.01),
            0.4,
            crate::sim::random::GivenNormals::new(&[]),
        );
        assert!((b.pga - 2.0 * a.pga).abs() < 1e-12 * b.pga);
        assert!((b.sa - 2.0 * a.sa).abs() < 1e-12 * b.sa);
    }
}
