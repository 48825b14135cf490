//! The symmetric period-1 orbit with two impacts per forcing period, in closed form
//! (Masri and Caughey 1966; derived in `docs/model.md` §8, "The symmetric two-impact orbit").
//!
//! # The orbit
//! The main mass `M` on `K`, `C` under `F0 cos(omega t)`, the inner mass `m` free in a cavity of
//! clearance `d`, impacts with restitution `e` (eq. 3–4). On the orbit the inner mass hits the
//! right wall (`z = y - x = +d/2`) at `t1 = phase / omega` and the left wall (`z = -d/2`) half a
//! forcing period later, and the motion is odd over half a period:
//! `x(t + T/2) = -x(t)`, `y(t + T/2) = -y(t)`, `T = 2 pi / omega`, `tau = T/2 = pi / omega`.
//!
//! Just before the right-wall impact the state is `(X, V-, X + d/2, W-)`, just after
//! `(X, V+, X + d/2, W+)`. The symmetry and the inner mass's flight at constant velocity from
//! `X + d/2` to `-X - d/2` in `tau` give (with `mu = m / M`)
//!
//! ```text
//! W- = (2 X + d) / tau,   W+ = -W-,
//! V- = -(1 - e + 2 mu) / (1 + e) W-,   V+ = -(1 - e - 2 mu e) / (1 + e) W-.
//! ```
//!
//! The main mass's free part `x - x_p` goes from `(X - x_p(t1), V+ - x_p'(t1))` to
//! `-(X - x_p(t1), V- - x_p'(t1))` in `tau` (the particular solution `x_p` is odd over half a
//! period). With `Phi` the free oscillator's 2 x 2 state-transition matrix over `tau` and
//! `N = Phi + I`, that is one linear system, affine in `X`, for the forcing's state at the
//! impact:
//!
//! ```text
//! N (x_p(t1), x_p'(t1)) = N (X, V+) + (0, V- - V+)      =>      (x_p(t1), x_p'(t1) / omega) = u0 + X u1
//! ```
//!
//! and `x_p(t1)^2 + (x_p'(t1) / omega)^2 = A^2 = P^2 + Q^2` (the particular solution's
//! amplitude) eliminates the phase: a quadratic in `X`,
//!
//! ```text
//! X = X* ± sqrt(A^2 - delta^2) / |u1|,   X* = -(u0 . u1) / |u1|^2,   delta = |u0 x u1| / |u1|,
//! ```
//!
//! real when the line `u0 + X u1` comes within `A` of the origin. The phase follows from
//! `cos(phase) = (P x_p + Q x_p' / omega) / A^2`, `sin(phase) = (Q x_p - P x_p' / omega) / A^2`.
//!
//! # Admissibility
//! A root is a physical orbit when (a) the inner mass approaches the wall it hits,
//! `W- - V- = 2 (1 + mu) W- / (1 + e) > 0`, i.e. `X > -d/2`; (b) it leaves with a relative
//! velocity, `e > 0` (with `e = 0` it leaves the wall grazing, and the simulator sticks it);
//! (c) it reaches no wall between the impacts: `-d/2 <= z <= d/2` over the whole flight, checked
//! on a grid of at least 16 points per radian of the fastest rate (`omega`, `sqrt(K/M)`, `C/M`)
//! with every local extremum refined by golden-section search. By the symmetry one flight stands
//! for both.
//!
//! # Ranges
//! Any valid [`System`] with `m > 0`, `F0 > 0` (N), `omega > 0` (rad/s), every damping regime
//! (`Phi` is [`crate::sim::linear::Oscillator::propagator`]). No orbit is returned (an empty
//! vector) when `m = 0` (no damper), when the forcing is resonant without damping
//! (`|K - M omega^2 + i C omega| < 1e-6 K`, refused by the simulator too), or when `N` is
//! singular (`|det N| < 1e-10`: only `C = 0` and `omega = sqrt(K/M) / (2 k + 1)`, where the
//! free motion itself is odd over half a period and the orbit is not isolated).

use std::f64::consts::{PI, TAU};

use crate::model::System;
use crate::sim::harmonic::motion::{Forced, RESONANCE_FLOOR, dynamic_stiffness};

/// `|det(Phi + I)|` below this is singular (dimensionless; `det(Phi + I) >= (1 - e^{-C tau / (2M)})^2`
/// when damped, `2 + 2 cos(pi sqrt(K/M) / omega)` when `C = 0`).
const SINGULAR: f64 = 1e-10;
/// Grid points per radian of the fastest rate of the motion when scanning a flight.
const POINTS_PER_RADIAN: f64 = 16.0;
/// Golden-section steps refining a local extremum: `0.618^100 ~ 1e-21` of a grid cell.
const GOLDEN_STEPS: usize = 100;

/// Why a root of the quadratic is not a physical orbit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inadmissible {
    /// `X <= -d/2`: the inner mass would be moving away from the wall it is to hit (`W- <= 0`).
    Recedes,
    /// `e = 0`: the inner mass would leave the wall with no relative velocity; the simulator
    /// sticks it to the wall instead.
    Grazes,
    /// The inner mass would reach a wall between the two impacts (`|y - x| > d/2` in flight).
    CrossesWall,
}

/// One symmetric period-1 orbit with two impacts per forcing period. Displacements in m,
/// velocities in m/s, the phase in rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetricOrbit {
    /// Forcing phase `omega t1` in `[0, 2 pi)` of the impact on the right wall (`y - x = +d/2`);
    /// the left-wall impact is at `phase + pi`.
    pub phase: f64,
    /// Displacement of the main mass at the right-wall impact, `X` (m); `-X` at the left one.
    pub x_impact: f64,
    /// Main mass's velocity just before (`V-`) and after (`V+`) the right-wall impact (m/s).
    pub v_before: f64,
    pub v_after: f64,
    /// Inner mass's velocity just before (`W- = (2 X + d) / tau`) and after (`W+ = -W-`) it.
    pub w_before: f64,
    pub w_after: f64,
    /// `max |x|` over the orbit (m): at a zero of `x'` in flight or at an impact (`|X|`).
    pub amplitude: f64,
    /// Whether the root is a physical orbit (`why` is `None`).
    pub admissible: bool,
    /// Why it is not, when it is not.
    pub why: Option<Inadmissible>,
    /// The Poincaré section of the forced scene, `(x, x', y - x, y')` at forcing phase 0
    /// (`t = 0 mod T`): a start for the simulator or a shooting solver that lies on the orbit.
    /// When an impact falls on phase 0 itself (`phase` 0 or `pi`, as without damping and with
    /// `e = 1`), the state just after it.
    pub section: [f64; 4],
}

/// The symmetric period-1 orbits with two impacts per forcing period of `sys` under
/// `f0 cos(omega t)` (`f0` in N, `omega` in rad/s): both roots of the quadratic when real
/// (module doc), in increasing `x_impact`, each with its admissibility. Empty when no root is
/// real or in the cases the module doc lists. The initial state of `sys` is not used.
pub fn symmetric_period1(sys: &System, f0: f64, omega: f64) -> Vec<SymmetricOrbit> {
    let (big_m, m, k, c) = (sys.M, sys.m, sys.K, sys.C);
    if !(m > 0.0 && f0.is_finite() && f0 > 0.0 && omega.is_finite() && omega > 0.0) {
        return Vec::new();
    }
    let stiffness = dynamic_stiffness(big_m, k, c, omega);
    if stiffness.is_nan() || stiffness < RESONANCE_FLOOR * k {
        return Vec::new();
    }
    let forced = Forced::new(big_m, k, c, f0, omega);
    let Some(af) = Affine::new(sys, &forced, omega) else {
        return Vec::new();
    };
    let (u0, u1, amp) = (af.u0, af.u1, forced.amp);
    let norm2 = u1[0] * u1[0] + u1[1] * u1[1];
    if !(norm2 > 0.0 && norm2.is_finite()) {
        return Vec::new();
    }
    let centre = -(u0[0] * u1[0] + u0[1] * u1[1]) / norm2;
    let cross = u0[0] * u1[1] - u0[1] * u1[0];
    // |u1|^2 (A^2 - delta^2), written without the cancellation of b^2 - 4 a c.
    let disc = (amp - cross.abs() / norm2.sqrt()) * (amp + cross.abs() / norm2.sqrt());
    if disc.is_nan() || disc < 0.0 {
        return Vec::new();
    }
    let half = disc.sqrt() / norm2.sqrt();
    let roots = if half == 0.0 {
        vec![centre]
    } else {
        vec![centre - half, centre + half]
    };
    roots
        .into_iter()
        .map(|x_impact| af.orbit(sys, &forced, omega, x_impact))
        .collect()
}

/// The particular solution at the impact, affine in the impact displacement `X` (module doc):
/// `(x_p, x_p' / omega) = u0 + X u1`, with the half period `tau = pi / omega` and the velocity
/// ratios `V- = beta_b W-`, `V+ = beta_a W-` (`W- = (2 X + d) / tau`).
struct Affine {
    tau: f64,
    beta_a: f64,
    beta_b: f64,
    u0: [f64; 2],
    u1: [f64; 2],
}

impl Affine {
    /// `None` where `Phi + I` is singular (or an input is not finite).
    fn new(sys: &System, forced: &Forced, omega: f64) -> Option<Affine> {
        let (big_m, m, d, e) = (sys.M, sys.m, sys.d, sys.e);
        let tau = PI / omega;
        let phi = forced.osc.propagator(tau);
        let mu = m / big_m;
        let beta_b = -(1.0 - e + 2.0 * mu) / (1.0 + e);
        let beta_a = -(1.0 - e - 2.0 * mu * e) / (1.0 + e);
        // N = Phi + I; N (x_p, x_p') = N (X, V+) + (0, V- - V+), the right side affine in X.
        let (n11, n12, n21, n22) = (phi.xx + 1.0, phi.xv, phi.vx, phi.vv + 1.0);
        let det = n11 * n22 - n12 * n21;
        // NaN (a non-finite input) fails the test too.
        if det.abs().is_nan() || det.abs() < SINGULAR {
            return None;
        }
        let rhs1 = [
            n11 + n12 * 2.0 * beta_a / tau,
            n21 + (n22 * beta_a + (beta_b - beta_a)) * 2.0 / tau,
        ];
        let rhs0 = [
            n12 * beta_a * d / tau,
            (n22 * beta_a + (beta_b - beta_a)) * d / tau,
        ];
        let solve = |r: [f64; 2]| {
            let xp = (n22 * r[0] - n12 * r[1]) / det;
            let vp = (n11 * r[1] - n21 * r[0]) / det;
            [xp, vp / omega]
        };
        Some(Affine {
            tau,
            beta_a,
            beta_b,
            u0: solve(rhs0),
            u1: solve(rhs1),
        })
    }

    /// The orbit whose right-wall impact is at `x_impact`: its impact phase and velocities, its
    /// amplitude, its admissibility and its Poincaré section.
    fn orbit(&self, sys: &System, forced: &Forced, omega: f64, x_impact: f64) -> SymmetricOrbit {
        let Affine {
            tau,
            beta_a,
            beta_b,
            u0,
            u1,
        } = *self;
        let (big_m, c, d, e) = (sys.M, sys.C, sys.d, sys.e);
        let (p, q, amp) = (forced.p, forced.q, forced.amp);
        let w_before = (2.0 * x_impact + d) / tau;
        let (v_before, v_after, w_after) = (beta_b * w_before, beta_a * w_before, -w_before);
        let xp = u0[0] + x_impact * u1[0];
        let sp = u0[1] + x_impact * u1[1];
        let a2 = amp * amp;
        let (cos, sin) = ((p * xp + q * sp) / a2, (q * xp - p * sp) / a2);
        let phase = sin.atan2(cos).rem_euclid(TAU);
        // rem_euclid can round up to exactly TAU.
        let phase = if phase >= TAU { 0.0 } else { phase };
        let t1 = phase / omega;
        let (h0, g0) = forced.free_start(t1, x_impact, v_after);
        let flight = Flight {
            forced: *forced,
            t1,
            h0,
            g0,
            y0: x_impact + 0.5 * d,
            w: w_after,
        };
        let rate = omega.max(sys.omega()).max(c / big_m);
        let n = ((POINTS_PER_RADIAN * tau * rate).ceil() as usize).clamp(64, 1 << 20);
        let (x_lo, x_hi) = interior_extremes(|s| flight.x(s), [v_after, -v_before], tau, n);
        let amplitude = x_impact.abs().max(x_hi).max(-x_lo);
        let why = if w_before <= 0.0 {
            Some(Inadmissible::Recedes)
        } else if e <= 0.0 {
            Some(Inadmissible::Grazes)
        } else {
            let slopes = [w_after - v_after, w_after + v_before];
            let (z_lo, z_hi) = interior_extremes(|s| flight.z(s), slopes, tau, n);
            (z_hi > 0.5 * d || z_lo < -0.5 * d).then_some(Inadmissible::CrossesWall)
        };
        // t = 0 mod T lies in the flight after the right-wall impact when t1 > tau, otherwise
        // in the flight after the left-wall one, the mirror image. An impact at t = 0 mod T
        // itself (phase 0 or pi) gives the state just after it.
        let section = if t1 == 0.0 {
            flight.state(0.0)
        } else if t1 > tau {
            flight.state(TAU / omega - t1)
        } else {
            flight.state(tau - t1).map(|v| -v)
        };
        SymmetricOrbit {
            phase,
            x_impact,
            v_before,
            v_after,
            w_before,
            w_after,
            amplitude,
            admissible: why.is_none(),
            why,
            section,
        }
    }
}

/// The Jacobian of the symmetric orbit's half-period impact map, in closed form.
///
/// Coordinates `q = (t, x, x', y')` just after an impact on the right wall (`y - x = +d/2`, so
/// `y` is not a coordinate). The map `H` flies to the next impact (on the left wall) and applies
/// the impact law there; the mirror `S q = (t - tau, -x, -x', -y')` brings the left wall back to
/// the right one, and the orbit is a fixed point of `S H`. Over one forcing period the orbit's
/// return map is `(S H)^2` (the left-to-right half is `S H S`), so its Floquet multipliers are
/// the squares of the eigenvalues of `J = S DH` (both maps are Poincaré maps of the same flow,
/// on the impact surface and at the forcing phase 0, so they share their multipliers).
///
/// `DH` by the implicit function theorem (derived in `docs/model.md` §12, "The symmetric orbit's
/// stability in closed form"): over the flight time `s`, `dxi1/d(x0, v0) = Phi(s)`,
/// `dxi1/dt0 = -Phi(s) f0`, `dy1 = dx0 + s dw0 - w0 dt0 + w0 dt1`; the impact condition
/// `y1 - x1 + d/2 = 0` gives `dt1 = -(dy1 - dx1)|_{t1} / (w0 - v1-)`; then
/// `dxi1 += f1 dt1`, and the impact law (eq. 3–4) maps `(v1-, w0)` to the velocities after.
/// `f = (x', (F0 cos(omega t) - K x - C x') / M)` is the main mass's vector field.
/// Row-major, `None` when the orbit's approach speed is zero (a graze: not differentiable).
pub fn half_map_jacobian(
    sys: &System,
    f0: f64,
    omega: f64,
    orbit: &SymmetricOrbit,
) -> Option<[[f64; 4]; 4]> {
    let (big_m, m, k, c, e) = (sys.M, sys.m, sys.K, sys.C, sys.e);
    let tau = PI / omega;
    let forced = Forced::new(big_m, k, c, f0, omega);
    let phi = forced.osc.propagator(tau);
    let field = |t: f64, x: f64, v: f64| [v, (f0 * (omega * t).cos() - k * x - c * v) / big_m];
    // Just after the right-wall impact, and just before the left-wall one (mirror image).
    let (t0, x0, v0, w0) = (
        orbit.phase / omega,
        orbit.x_impact,
        orbit.v_after,
        orbit.w_after,
    );
    let (x1, v1) = (-orbit.x_impact, -orbit.v_before);
    let f_0 = field(t0, x0, v0);
    let f_1 = field(t0 + tau, x1, v1);
    let approach = w0 - v1;
    if approach.abs() == 0.0 || !approach.is_finite() {
        return None;
    }
    // d xi1 / dq at a fixed arrival time, q = (t0, x0, v0, w0).
    let phi_f0 = [
        phi.xx * f_0[0] + phi.xv * f_0[1],
        phi.vx * f_0[0] + phi.vv * f_0[1],
    ];
    let dx = [-phi_f0[0], phi.xx, phi.xv, 0.0];
    let dv = [-phi_f0[1], phi.vx, phi.vv, 0.0];
    let dy = [-w0, 1.0, 0.0, tau];
    // The arrival time from the impact condition.
    let dt1: [f64; 4] = std::array::from_fn(|j| -(dy[j] - dx[j]) / approach);
    let dx1: [f64; 4] = std::array::from_fn(|j| dx[j] + f_1[0] * dt1[j]);
    let dv1: [f64; 4] = std::array::from_fn(|j| dv[j] + f_1[1] * dt1[j]);
    let dw0 = [0.0, 0.0, 0.0, 1.0];
    // The impact law: v+ = v- + a (w - v-), w+ = w - b (w - v-).
    let a = m * (1.0 + e) / (big_m + m);
    let b = big_m * (1.0 + e) / (big_m + m);
    let dv_after: [f64; 4] = std::array::from_fn(|j| (1.0 - a) * dv1[j] + a * dw0[j]);
    let dw_after: [f64; 4] = std::array::from_fn(|j| b * dv1[j] + (1.0 - b) * dw0[j]);
    // The mirror: time shifts by a constant, the rest change sign.
    let neg = |r: [f64; 4]| r.map(|v| -v);
    Some([dt1, neg(dx1), neg(dv_after), neg(dw_after)])
}

/// The Floquet multipliers of a symmetric orbit over one forcing period, in closed form: the
/// squares of the eigenvalues of [`half_map_jacobian`], as `(re, im)` by decreasing modulus.
/// `None` where the Jacobian is.
pub fn symmetric_multipliers(
    sys: &System,
    f0: f64,
    omega: f64,
    orbit: &SymmetricOrbit,
) -> Option<[(f64, f64); 4]> {
    let j = half_map_jacobian(sys, f0, omega, orbit)?;
    let jm = nalgebra::Matrix4::from_fn(|r, c| j[r][c]);
    let eig = jm.complex_eigenvalues();
    let mut mu: Vec<(f64, f64)> = eig
        .iter()
        .map(|l| {
            let sq = l * l;
            (sq.re, sq.im)
        })
        .collect();
    mu.sort_by(|p, q| q.0.hypot(q.1).total_cmp(&p.0.hypot(p.1)));
    Some([mu[0], mu[1], mu[2], mu[3]])
}

/// The flight that follows the right-wall impact, `s` in `[0, tau]` after it.
struct Flight {
    forced: Forced,
    t1: f64,
    /// The main mass's free part just after the impact.
    h0: f64,
    g0: f64,
    /// The inner mass just after the impact: position and velocity.
    y0: f64,
    w: f64,
}

impl Flight {
    fn x(&self, s: f64) -> f64 {
        self.forced.jet(self.t1, self.h0, self.g0, self.t1 + s).x
    }

    /// `y - x`.
    fn z(&self, s: f64) -> f64 {
        self.y0 + self.w * s - self.x(s)
    }

    /// `(x, x', y - x, y')`.
    fn state(&self, s: f64) -> [f64; 4] {
        let jet = self.forced.jet(self.t1, self.h0, self.g0, self.t1 + s);
        [jet.x, jet.v, self.y0 + self.w * s - jet.x, self.w]
    }
}

/// `(min, max)` of `f` over the open interval `(0, len)`: the largest and smallest of `n - 1`
/// interior grid points and of its local extrema ([`local_extremes`]).
fn interior_extremes(f: impl Fn(f64) -> f64, slopes: [f64; 2], len: f64, n: usize) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (v, sign) in local_extremes(&f, slopes, len, n, GOLDEN_STEPS) {
        if sign > 0.0 {
            hi = hi.max(v);
        } else {
            lo = lo.min(v);
        }
    }
    for i in 1..n {
        let v = f(len * i as f64 / n as f64);
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo, hi)
}

/// The local extrema of `f` inside `(0, len)` as `(value, sign)` (`sign = 1` a maximum, `-1` a
/// minimum): each local extremum of a grid of `n` cells refined by `steps` steps of
/// golden-section search between its neighbours (the bracket shrinks by `0.618^steps`; the
/// value's error by its square). `slopes` are `f'` just after `0` and just before `len`: an extremum in an end
/// cell, which the grid cannot show, is there when the slope at the end disagrees with the
/// cell's chord.
pub(crate) fn local_extremes(
    f: &impl Fn(f64) -> f64,
    slopes: [f64; 2],
    len: f64,
    n: usize,
    steps: usize,
) -> Vec<(f64, f64)> {
    local_extremes_at(f, slopes, len, n, steps)
        .into_iter()
        .map(|(v, sign, _)| (v, sign))
        .collect()
}

/// [`local_extremes`] with where each lies: `(value, sign, s)`, `s` in `[0, len]` the argument
/// of the larger of the golden-section search's last two values.
pub(crate) fn local_extremes_at(
    f: &impl Fn(f64) -> f64,
    slopes: [f64; 2],
    len: f64,
    n: usize,
    steps: usize,
) -> Vec<(f64, f64, f64)> {
    let n = n.max(2);
    let s = |i: usize| len * i as f64 / n as f64;
    let vals: Vec<f64> = (0..=n).map(|i| f(s(i))).collect();
    let mut out = Vec::new();
    let mut refine = |a: f64, b: f64, sign: f64| {
        let (at, v) = golden(f, a, b, sign, steps);
        out.push((v, sign, at));
    };
    for i in 1..n {
        let v = vals[i];
        if v >= vals[i - 1] && v >= vals[i + 1] {
            refine(s(i - 1), s(i + 1), 1.0);
        }
        if v <= vals[i - 1] && v <= vals[i + 1] {
            refine(s(i - 1), s(i + 1), -1.0);
        }
    }
    // Rising out of 0 but lower at the first grid point: a maximum inside the first cell.
    let first = vals[1] - vals[0];
    if slopes[0] > 0.0 && first < 0.0 {
        refine(0.0, s(1), 1.0);
    } else if slopes[0] < 0.0 && first > 0.0 {
        refine(0.0, s(1), -1.0);
    }
    let last = vals[n] - vals[n - 1];
    if slopes[1] > 0.0 && last < 0.0 {
        refine(s(n - 1), len, -1.0);
    } else if slopes[1] < 0.0 && last > 0.0 {
        refine(s(n - 1), len, 1.0);
    }
    out
}

/// The extreme value of `f` on `[a, b]` by golden-section search: the maximum for `sign = 1`,
/// the minimum for `sign = -1` (of a function unimodal there; otherwise a value `f` takes), and
/// where it is taken: `(s, f(s))`.
fn golden(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, sign: f64, steps: usize) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - g * (b - a);
    let mut e = a + g * (b - a);
    let (mut fc, mut fe) = (sign * f(c), sign * f(e));
    for _ in 0..steps {
        if fc >= fe {
            b = e;
            e = c;
            fe = fc;
            c = b - g * (b - a);
            fc = sign * f(c);
        } else {
            a = c;
            c = e;
            fc = fe;
            e = a + g * (b - a);
            fe = sign * f(e);
        }
        if b - a <= f64::EPSILON * b.abs() {
            break;
        }
    }
    // As `fc.max(fe)`: the one that is not NaN.
    if fc >= fe || fe.is_nan() {
        (c, sign * fc)
    } else {
        (e, sign * fe)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::impact;

    /// The Table I system with the given inner mass, clearance, restitution and damping.
    fn system(m: f64, d: f64, e: f64, c: f64) -> System {
        System {
            m,
            d,
            e,
            C: c,
            ..System::TABLE_I
        }
    }

    /// Every root solves the conditions it was derived from, checked on the closed form itself:
    /// the impact law, the inner mass's flight, and the main mass's flight from just after the
    /// right-wall impact to minus the state just before it, half a period later.
    #[test]
    fn roots_solve_the_matching_conditions_in_every_damping_regime() {
        let crit = 2.0 * (400.0f64 * 0.1).sqrt();
        let mut checked = 0;
        for c in [0.0, 0.1, 0.5 * crit, crit, 2.0 * crit] {
            for (m, d, e) in [(0.005, 0.01, 0.9), (0.02, 0.005, 0.5), (0.01, 0.02, 1.0)] {
                let sys = system(m, d, e, c);
                for r in [0.7, 0.95, 1.05, 1.3] {
                    for f0 in [0.1, 1.0, 10.0] {
                        let omega = r * sys.omega();
                        let tau = PI / omega;
                        for o in symmetric_period1(&sys, f0, omega) {
                            let scale_v = o.w_before.abs().max(o.v_before.abs());
                            let (va, wa) = impact(sys.M, m, e, o.v_before, o.w_before);
                            assert!((va - o.v_after).abs() <= 1e-12 * scale_v, "{o:?}");
                            assert!((wa - o.w_after).abs() <= 1e-12 * scale_v, "{o:?}");
                            let y_end = o.x_impact + 0.5 * d + o.w_after * tau;
                            let scale_x = o.x_impact.abs().max(d);
                            assert!((y_end + o.x_impact + 0.5 * d).abs() <= 1e-12 * scale_x);
                            let f = Forced::new(sys.M, sys.K, c, f0, omega);
                            let t1 = o.phase / omega;
                            let (h0, g0) = f.free_start(t1, o.x_impact, o.v_after);
                            let end = f.jet(t1, h0, g0, t1 + tau);
                            let scale = scale_x.max(f.amp);
                            assert!(
                                (end.x + o.x_impact).abs() <= 1e-9 * scale,
                                "c={c} m={m} d={d} e={e} r={r} f0={f0}: {o:?} ends at {}",
                                end.x
                            );
                            assert!(
                                (end.v + o.v_before).abs() <= 1e-9 * scale * omega.max(sys.omega()),
                                "c={c} m={m} d={d} e={e} r={r} f0={f0}: {o:?} ends at {}",
                                end.v
                            );
                            assert!(o.amplitude >= o.x_impact.abs());
                            assert!((0.0..TAU).contains(&o.phase));
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked >= 100, "only {checked} roots checked");
    }

    /// Two roots while the line `u0 + X u1` cuts the circle of radius `A`; as the force weakens
    /// they close in on each other and vanish together at a fold.
    #[test]
    fn roots_come_in_pairs_that_merge_where_the_orbit_ceases_to_exist() {
        let sys = system(0.005, 0.01, 0.9, 0.1);
        let omega = 1.01 * sys.omega();
        let count = |f0: f64| symmetric_period1(&sys, f0, omega).len();
        let (mut lo, mut hi) = (1e-6, 1.0);
        assert_eq!(count(lo), 0);
        assert_eq!(count(hi), 2);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if count(mid) == 0 { lo = mid } else { hi = mid }
        }
        // At the fold itself the discriminant may round to zero: one double root.
        let pair = symmetric_period1(&sys, hi, omega);
        assert!(!pair.is_empty());
        let spread = pair[pair.len() - 1].x_impact - pair[0].x_impact;
        assert!(spread <= 1e-6 * pair[0].x_impact.abs(), "{pair:?}");
        let wide = symmetric_period1(&sys, 2.0 * hi, omega);
        assert!((wide[1].x_impact - wide[0].x_impact).abs() > 1e3 * spread);
    }

    #[test]
    fn no_orbit_without_a_damper_or_where_the_half_period_map_is_singular() {
        let wn = System::TABLE_I.omega();
        assert!(symmetric_period1(&system(0.0, 0.01, 0.9, 0.1), 1.0, wn).is_empty());
        // Undamped: N = Phi + I is singular at r = 1/3, and r = 1 is refused as resonance.
        let undamped = system(0.01, 0.01, 0.9, 0.0);
        assert!(symmetric_period1(&undamped, 1.0, wn / 3.0).is_empty());
        assert!(symmetric_period1(&undamped, 1.0, wn).is_empty());
        assert!(symmetric_period1(&undamped, 0.0, 1.05 * wn).is_empty());
        assert!(!symmetric_period1(&undamped, 1.0, 1.05 * wn).is_empty());
    }

    /// The relations of the impact at the right wall: the inner mass's velocity reverses, the
    /// main mass moves against it; `e = 1` and `e = 0` are the named limits.
    #[test]
    fn impact_velocities_and_the_elastic_and_plastic_limits() {
        for e in [0.0, 0.5, 1.0] {
            let sys = system(0.01, 0.01, e, 0.1);
            let orbits = symmetric_period1(&sys, 1.0, 1.05 * sys.omega());
            assert_eq!(orbits.len(), 2);
            for o in orbits {
                assert_eq!(o.w_after, -o.w_before);
                if o.w_before > 0.0 {
                    assert!(o.v_before < 0.0);
                } else {
                    assert_eq!(o.why, Some(Inadmissible::Recedes));
                }
                if e == 1.0 {
                    // Elastic and symmetric: the main mass's velocity reverses too.
                    assert!((o.v_after + o.v_before).abs() <= 1e-14 * o.v_before.abs());
                }
                if e == 0.0 && o.w_before > 0.0 {
                    assert_eq!(o.why, Some(Inadmissible::Grazes));
                }
                assert_eq!(o.admissible, o.why.is_none());
            }
        }
    }

    #[test]
    fn golden_section_finds_an_interior_extremum() {
        let f = |s: f64| (s - 0.3).powi(2);
        assert!(golden(&f, 0.0, 1.0, -1.0, GOLDEN_STEPS).1.abs() <= 1e-15);
        let (lo, hi) = interior_extremes(|s| (7.0 * s).sin(), [7.0, 7.0 * 7f64.cos()], 1.0, 64);
        assert!((hi - 1.0).abs() <= 1e-15 && (lo + 1.0).abs() <= 1e-15);
    }
}
