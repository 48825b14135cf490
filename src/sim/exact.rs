//! The `exact` solver: closed-form motion between events ([`super::linear`]) and event location
//! that cannot miss or step over an event.
//!
//! Within one phase (free, or the stuck pair) the main mass is a free linear oscillator, and
//! every solution `y` of its equation (`x`, `v`, any `p x + r v`, in particular the contact
//! force `C v + K x`) has an explicit shape:
//!
//! ```text
//! under-damped:          y(tau) = R e^{-alpha tau} sin(omega tau + phi)
//! critical / over-damped: y(tau) = e^{-(alpha + beta) tau} (y0 + D tau E(2 beta tau)),
//!                         D = y'(0) + (alpha + beta) y(0),  E(s) = (e^s - 1) / s
//! ```
//!
//! Events of a *pure* solution are therefore found in closed form, not by search: `x = 0`, `v = 0`
//! and the separation of a stuck pair (`C v + K x = 0`) happen where the sine vanishes,
//! `omega tau + phi = n pi` (one `atan2` per phase), or, when over- or critically damped, at
//! the single zero of `y0 + D tau E(2 beta tau)` (monotone in `tau`), `tau = log1p(u) / (2 beta)`
//! with `u = -2 beta y0 / D`. The direction of each crossing follows from `n`'s parity, or from
//! the sign of `D`, so only crossings toward zero from the watched side are reported.
//!
//! The walls are not pure solutions: the gap `g(t) = d/2 ± (x(t) - y(t))` adds the inner mass's
//! straight line to `±x`. Its curvature is `g'' = ±x''`, and `x''` is again a pure solution whose
//! zeros are explicit: between two consecutive zeros of `x''` (a *piece*; at most two pieces
//! when over-damped) each gap is **convex or concave**, with the sign known beforehand. That
//! settles where a root can be (the bracket argument):
//!
//! * a concave gap on `[p, q]` is at least `min(g(p), g(q))`, so with `g(p) > 0` it has a root
//!   in the piece exactly when `g(q) <= 0`, and then exactly one; it lies above its chords, so
//!   the chord's zero is a point before the root, and below its tangents, so a tangent's zero
//!   at a point past the root stays past it;
//! * a convex gap lies above each of its tangents: from a point with `g > 0, g' < 0` the
//!   tangent's zero is reached no later than the root (Newton from the left never passes a
//!   root), and two tangents with slopes of opposite signs bound `g` from below by their value
//!   where they cross. So a convex gap positive at both ends either stays positive (proved by
//!   that bound, or by `g'` not changing sign) or dips to zero between them, a grazing contact
//!   (a double root) included: the tangent steps from the left converge onto it.
//!
//! The solver marches from the current point toward the earliest explicit event (or the time
//! limit) through trial points, each evaluating the closed form once, and every trial point `q`
//! after a point `p` with `g(p) > 0` settles `[p, q]` for each gap by that argument: `g(q) <= 0`
//! brackets the first root (exactly one in `(p, q]`); on a concave piece `g(q) > 0` proves
//! there is none; on a convex one so does `g(q) > 0` with `g'(q) < 0` (the gap fell all the
//! way), while `g'(q) > 0` sends `[p, q]` to the dip test. A convex gap whose tangent at `p`
//! stays positive to the end of the piece needs no trial at all. Trial points are chosen, not
//! trusted: the root of the gap's local cubic Taylor model at `p`, aimed a thousandth of the
//! tolerance short, so that once the model is good they land just before the root; the piece
//! end when no model root comes first. A bracketed root is refined between the tangent and
//! chord bounds above, again from the local model, safeguarded by bisection, and declared on its
//! positive side: at a point `lo` with `g > 0` whose tangent reaches zero within the event
//! tolerance `tol * period` (on a concave piece this bounds the root, on a convex one it is the
//! tangent step that declares a contact, grazing included), or once the bounds pin the root
//! within half the tolerance, just before them. No event is missed or passed, grazing contacts
//! included; all of this holds up to the rounding of the closed form (about one unit in the
//! last place of the phase angle `omega tau`), as before.
//!
//! A gap at or below zero fires at once if it heads into the wall (slope `< 0`, or slope `0`
//! and curvature `< 0`); otherwise the inner mass is leaving that wall and the gap counts as
//! zero. A prefilter skips the walls while the inner mass's line stays farther from them than
//! the largest displacement the energy allows, `sqrt(2 E / K)`. Points within `0.02 / rate` of
//! the last closed-form evaluation (`rate = alpha + sqrt|K/M - alpha^2|`, the fastest rate of
//! the motion) are evaluated by that point's Taylor polynomials instead, whose remainders are
//! below `1e-18` of the amplitude: the refinement near a root costs a few multiplications, not
//! an exponential and a sine. Every evaluation counts as a step against `max_steps`.

use std::f64::consts::{FRAC_1_PI, PI, TAU};
use std::ops::ControlFlow;

use super::linear::{Kinematics, Oscillator};
use super::phase::{Event, PhaseSolver, Reach, StepCap, Wall, Walls, Watch, toward};

/// Why a search stopped early.
enum Stop {
    Cap,
    NonFinite,
}

/// A point of the current phase: time, displacement, velocity.
#[derive(Clone, Copy, Debug)]
struct Pt {
    t: f64,
    x: f64,
    v: f64,
}

/// The shape constants of an oscillator (see the module doc).
#[derive(Clone, Copy, Debug)]
enum Shape {
    /// `omega` the damped frequency; `chi` the phase a time derivative adds
    /// (`atan2(omega, -alpha)`); `chi_force` the phase of `C v + K x` relative to `x`.
    Under {
        omega: f64,
        inv_omega: f64,
        chi: f64,
        chi_force: f64,
    },
    /// `beta = sqrt(alpha^2 - K/M) >= 0`, `ab = alpha + beta`.
    Over { beta: f64, ab: f64 },
}

impl Shape {
    fn of(o: &Oscillator) -> Shape {
        if o.q > 0.0 {
            let omega = o.root;
            Shape::Under {
                omega,
                inv_omega: 1.0 / omega,
                chi: omega.atan2(-o.alpha),
                chi_force: (o.c * omega).atan2(o.k - o.c * o.alpha),
            }
        } else {
            Shape::Over {
                beta: o.root,
                ab: o.alpha + o.root,
            }
        }
    }
}

/// The pure solutions a scene watches.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(usize)]
enum Pure {
    X,
    V,
    Force,
}

/// `v.floor()` for `|v| < 2^52` without a library call (the default x86-64 target has no
/// rounding instruction).
#[inline]
fn floor(v: f64) -> f64 {
    let f = v as i64 as f64;
    if f > v { f - 1.0 } else { f }
}

/// `v.ceil()` for `|v| < 2^52`.
#[inline]
fn ceil(v: f64) -> f64 {
    let f = v as i64 as f64;
    if f < v { f + 1.0 } else { f }
}

/// `log1p(u) / u`, 1 at `u = 0`.
#[inline]
fn log1p_ratio(u: f64) -> f64 {
    if u == 0.0 { 1.0 } else { u.ln_1p() / u }
}

/// The zero of an over- or critically damped solution with `y(0) = y0`, `D = y'(0) + ab y(0)`:
/// `Some(tau)` (possibly negative) when it has one; the solution's sign after it is `sign(D)`.
#[inline]
fn over_zero(beta: f64, y0: f64, d: f64) -> Option<f64> {
    if d == 0.0 {
        return None;
    }
    let u = -2.0 * beta * y0 / d;
    (u > -1.0).then(|| (-y0 / d) * log1p_ratio(u))
}

/// A root of the local cubic model `g + g1 h + g2 h^2 / 2 + g3 h^3 / 6` of a gap: the first
/// `h > 0` (`first`, with `g >= 0`; infinity when the quadratic part has none), or the one
/// nearest to `h = 0`. Started at the quadratic model's root, refined by a Newton step on
/// the cubic. Only a trial point: the bracket argument does not rest on it.
#[inline]
fn model_root(g: f64, g1: f64, g2: f64, g3: f64, first: bool) -> f64 {
    let (r1, r2) = quadratic_roots(g, g1, 0.5 * g2);
    let mut h = if first {
        let pick = |r: f64| if r > 0.0 { r } else { f64::INFINITY };
        pick(r1).min(pick(r2))
    } else {
        match (r1.is_nan(), r2.is_nan()) {
            (false, false) if r1.abs() <= r2.abs() => r1,
            (false, false) | (true, false) => r2,
            (false, true) => r1,
            (true, true) => -g / g1,
        }
    };
    if !h.is_finite() {
        return h;
    }
    let (c2, c3) = (0.5 * g2, g3 / 6.0);
    let f = g + h * (g1 + h * (c2 + h * c3));
    let df = g1 + h * (g2 + h * 3.0 * c3);
    let next = h - f / df;
    if next.is_finite() && (!first || next > 0.0) {
        h = next;
    }
    h
}

/// The real roots of `c + b h + a h^2` in the form free of cancellation (NaN where none).
#[inline]
fn quadratic_roots(c: f64, b: f64, a: f64) -> (f64, f64) {
    if a == 0.0 {
        return (-c / b, f64::NAN);
    }
    let disc = b * b - 4.0 * a * c;
    if disc.is_nan() || disc < 0.0 {
        return (f64::NAN, f64::NAN);
    }
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    if q == 0.0 {
        return (0.0, f64::NAN);
    }
    (q / a, c / q)
}

/// The gap to the wall of sign `sg` (`+1` right, `-1` left) and its slope at `p`.
#[inline]
fn gap(wl: &Walls, sg: f64, p: &Pt) -> (f64, f64) {
    let y = wl.y0 + wl.w * (p.t - wl.t0);
    (wl.half_d + sg * (p.x - y), sg * (p.v - wl.w))
}

const WALLS: [(Wall, f64); 2] = [(Wall::Right, 1.0), (Wall::Left, -1.0)];

/// A closed-form point and the Taylor coefficients of `x` (degree 8) and `v` (degree 7) there.
#[derive(Clone, Copy, Debug)]
struct Base {
    t: f64,
    cx: [f64; 9],
    cv: [f64; 8],
    ready: bool,
}

/// One smooth phase of the main mass (free, or the stuck pair) solved in closed form.
#[derive(Clone)]
pub(crate) struct ExactPhase {
    osc: Oscillator,
    shape: Shape,
    t0: f64,
    x0: f64,
    v0: f64,
    a0: f64,
    /// Under-damped: phase and amplitude of `x` (`x = amp e^{-alpha tau} sin(omega tau + phi)`).
    phi: f64,
    amp: f64,
    /// Under-damped: `x = e^{-alpha tau} (x0 cos + cx sin)`, `v = e^{-alpha tau} (v0 cos + cv sin)`
    /// with the sine and cosine of `omega tau`.
    cx: f64,
    cv: f64,
    /// The closed-form crossing found for `x`, `v` and the force this phase: (side, time).
    crossings: [Option<(f64, f64)>; 3],
    /// The last closed-form point of the phase; points within `taylor_h` of it are evaluated
    /// by its Taylor polynomials (degree 8 in `x`, 7 in `v`) instead of the closed form. Every
    /// derivative of a solution is bounded by `amplitude * rate^n` with `rate = alpha + sqrt|q|`
    /// (`>= sqrt(K/M)` under-damped, the fast root over-damped), so with
    /// `rate * taylor_h = 0.02` the remainders are below `0.02^8 / 8! < 1e-18` of it.
    base: Base,
    taylor_h: f64,
    t: f64,
    kin: Kinematics,
    tol_t: f64,
    steps: u64,
    max_steps: u64,
    /// The oscillator of the phase before the current one, with its shape and `taylor_h`: a
    /// run alternates between the free main mass and the stuck pair, and switching back then
    /// costs no `atan2`.
    spare: Option<(Oscillator, Shape, f64)>,
}

impl ExactPhase {
    /// `tol_t` is the absolute event-time tolerance (s).
    pub(crate) fn new(tol_t: f64, max_steps: u64) -> Self {
        // No phase yet: an oscillator equal to none (NaN fields), whose shape is never read
        // (`begin` replaces both).
        let osc = Oscillator::new(f64::NAN, f64::NAN, f64::NAN);
        ExactPhase {
            osc,
            shape: Shape::Over {
                beta: f64::NAN,
                ab: f64::NAN,
            },
            t0: 0.0,
            x0: 0.0,
            v0: 0.0,
            a0: 0.0,
            phi: 0.0,
            amp: 0.0,
            cx: 0.0,
            cv: 0.0,
            crossings: [None; 3],
            base: Base {
                t: f64::NAN,
                cx: [0.0; 9],
                cv: [0.0; 8],
                ready: false,
            },
            taylor_h: 0.0,
            t: 0.0,
            kin: Kinematics {
                x: 0.0,
                v: 0.0,
                a: 0.0,
            },
            tol_t,
            steps: 0,
            max_steps,
            spare: None,
        }
    }

    /// The closed form at time `t` (one step).
    #[inline]
    fn eval(&mut self, t: f64) -> Result<Pt, Stop> {
        self.steps += 1;
        if self.steps > self.max_steps {
            return Err(Stop::Cap);
        }
        let h = t - self.base.t;
        if h.abs() <= self.taylor_h {
            if !self.base.ready {
                self.taylor_coefficients();
            }
            let b = &self.base;
            // Close to the last closed-form point: its Taylor polynomials, whose remainders are
            // below 1e-18 of the amplitude there (see `taylor_h`), in Estrin's form.
            let (h2, c, e) = (h * h, &b.cx, &b.cv);
            let h4 = h2 * h2;
            let x = (c[0] + c[1] * h)
                + h2 * (c[2] + c[3] * h)
                + h4 * ((c[4] + c[5] * h) + h2 * (c[6] + c[7] * h) + h4 * c[8]);
            let v = (e[0] + e[1] * h)
                + h2 * (e[2] + e[3] * h)
                + h4 * ((e[4] + e[5] * h) + h2 * (e[6] + e[7] * h));
            return Ok(Pt { t, x, v });
        }
        let tau = t - self.t0;
        let (x, v) = match self.shape {
            Shape::Under { omega, .. } => {
                // x = e^{-alpha tau} (x0 cos + cx sin), v = e^{-alpha tau} (v0 cos + cv sin)
                let (sn, cs) = (omega * tau).sin_cos();
                let env = if self.osc.alpha == 0.0 {
                    1.0
                } else {
                    (-self.osc.alpha * tau).exp()
                };
                (
                    env * (self.x0 * cs + self.cx * sn),
                    env * (self.v0 * cs + self.cv * sn),
                )
            }
            Shape::Over { .. } => {
                let k = self.osc.eval(self.x0, self.v0, tau);
                (k.x, k.v)
            }
        };
        if !(x.is_finite() && v.is_finite()) {
            return Err(Stop::NonFinite);
        }
        self.set_base(t, x, v);
        Ok(Pt { t, x, v })
    }

    /// Makes `(t, x, v)`, a closed-form point, the base of the local Taylor polynomials (their
    /// coefficients are computed when first needed).
    #[inline]
    fn set_base(&mut self, t: f64, x: f64, v: f64) {
        self.base.t = t;
        self.base.cx[0] = x;
        self.base.cv[0] = v;
        self.base.ready = false;
    }

    /// The Taylor coefficients at the base: the derivatives `x^(n)` by the equation of motion,
    /// `x^(n+2) = -(2 alpha x^(n+1) + w2 x^(n))`, over `n!` (for `v`, `x^(n+1) / n!`).
    fn taylor_coefficients(&mut self) {
        const INV_FACT: [f64; 9] = [
            1.0,
            1.0,
            1.0 / 2.0,
            1.0 / 6.0,
            1.0 / 24.0,
            1.0 / 120.0,
            1.0 / 720.0,
            1.0 / 5040.0,
            1.0 / 40320.0,
        ];
        let (a2, w2) = (2.0 * self.osc.alpha, self.osc.w2);
        let b = &mut self.base;
        let (mut d0, mut d1) = (b.cx[0], b.cv[0]);
        for n in 1..9 {
            let d2 = -(a2 * d1 + w2 * d0);
            b.cx[n] = d1 * INV_FACT[n];
            b.cv[n - 1] = d1 * INV_FACT[n - 1];
            (d0, d1) = (d1, d2);
        }
        b.ready = true;
    }

    /// How far short of a root near time `t` a trial point aims: a thousandth of the
    /// tolerance, far above the rounding of a converged model root and far below the
    /// tolerance, and at least a few units in the last place of `t`.
    #[inline]
    fn aim(&self, t: f64) -> f64 {
        (1e-3 * self.tol_t).max(8.0 * f64::EPSILON * t.abs())
    }

    /// The acceleration of the phase's oscillator in state `(x, v)`.
    #[inline]
    fn accel(&self, x: f64, v: f64) -> f64 {
        -(2.0 * self.osc.alpha * v + self.osc.w2 * x)
    }

    /// The third derivative `x'''` from the acceleration `a` and the velocity `v`.
    #[inline]
    fn jerk(&self, a: f64, v: f64) -> f64 {
        -(2.0 * self.osc.alpha * a + self.osc.w2 * v)
    }

    /// Makes `p` the current point.
    #[inline]
    fn go_to(&mut self, p: Pt) {
        self.t = p.t;
        self.kin = Kinematics {
            x: p.x,
            v: p.v,
            a: self.osc.accel(p.x, p.v),
        };
    }

    /// Value and slope at the phase origin, and value, slope and curvature now, of a pure
    /// solution (unsigned).
    #[inline]
    fn pure(&self, which: Pure) -> ((f64, f64), (f64, f64, f64)) {
        let o = &self.osc;
        let Kinematics { x, v, a } = self.kin;
        let j = self.jerk(a, v);
        match which {
            Pure::X => ((self.x0, self.v0), (x, v, a)),
            Pure::V => ((self.v0, self.a0), (v, a, j)),
            Pure::Force => (
                (o.c * self.v0 + o.k * self.x0, o.c * self.a0 + o.k * self.v0),
                (o.c * v + o.k * x, o.c * a + o.k * v, o.c * j + o.k * a),
            ),
        }
    }

    /// When the pure solution `which`, times the sign `s` it has now, next reaches zero from
    /// above: now if it is at or below zero and heading into it, else its next crossing downward
    /// in closed form (`None`: never).
    fn crossing(&mut self, which: Pure, s: f64) -> Option<f64> {
        let ((y0, y1), (g, g1, g2)) = self.pure(which);
        if s * g <= 0.0 && toward(s * g1, s * g2) {
            return Some(self.t);
        }
        let slot = &mut self.crossings[which as usize];
        let t = match *slot {
            Some((side, t)) if side == s && t >= self.t => t,
            _ => {
                let t = self.t0 + self.down_crossing(which, s, y0, y1)?;
                self.crossings[which as usize] = Some((s, t));
                t
            }
        };
        Some(t.max(self.t))
    }

    /// The time after the phase's start of the next downward crossing of `s y`, `y` the pure
    /// solution `which` with value `y0` and slope `y1` at the start (see [`Self::crossing`]).
    fn down_crossing(&self, which: Pure, s: f64, y0: f64, y1: f64) -> Option<f64> {
        let now = self.t - self.t0;
        match self.shape {
            Shape::Under {
                omega,
                inv_omega,
                chi,
                chi_force,
            } => {
                if self.amp == 0.0 {
                    return None; // x and everything built from it vanish identically
                }
                let shift = match which {
                    Pure::X => 0.0,
                    Pure::V => chi,
                    Pure::Force => chi_force,
                };
                let phi = self.phi + shift + if s < 0.0 { PI } else { 0.0 };
                // Downward crossings of sin(theta + phi) at theta = (2j + 1) pi - phi; one that
                // rounding puts a hair before now is the one at hand.
                let th = omega * now;
                let eps = 1e-12 * (1.0 + th.abs());
                let j = ceil((th - eps + phi - PI) * (1.0 / TAU));
                Some((j * TAU + PI - phi) * inv_omega)
            }
            Shape::Over { beta, ab } => {
                let (y0, y1) = (s * y0, s * y1);
                let d = y1 + ab * y0;
                if d.is_nan() || d >= 0.0 {
                    return None; // no zero, or one crossed upward
                }
                let tau = over_zero(beta, y0, d)?;
                (tau >= now - 1e-12 * now.abs()).then_some(tau)
            }
        }
    }

    /// The next zero of `x''` after `t` (a piece end) and the sign of `x''` up to it (`0`: `x''`
    /// vanishes identically). `f64::INFINITY` when there is none.
    fn inflection_after(&self, t: f64) -> (f64, f64) {
        let tau = t - self.t0;
        match self.shape {
            Shape::Under {
                omega,
                inv_omega,
                chi,
                ..
            } => {
                if self.amp == 0.0 {
                    return (f64::INFINITY, 0.0);
                }
                // x'' = amp w^2 e^{-alpha tau} sin(theta + phi + 2 chi): zeros at n pi - phi2.
                let phi2 = self.phi + 2.0 * chi;
                let th = omega * tau;
                let mut n = floor((th + phi2) * FRAC_1_PI) + 1.0;
                let mut tz = self.t0 + (n * PI - phi2) * inv_omega;
                if tz <= t {
                    n += 1.0;
                    tz = self.t0 + (n * PI - phi2) * inv_omega;
                }
                // On ((n - 1) pi, n pi) the sine has the sign of (-1)^(n - 1).
                let sign = if (n as i64 - 1) & 1 == 0 { 1.0 } else { -1.0 };
                (tz, sign)
            }
            Shape::Over { beta, ab } => {
                let o = &self.osc;
                let (y0, y1) = (self.a0, -(o.c * self.a0 + o.k * self.v0) / o.mass);
                let d = y1 + ab * y0;
                match over_zero(beta, y0, d) {
                    Some(tz) if self.t0 + tz > t => (self.t0 + tz, -d.signum()),
                    Some(_) => (f64::INFINITY, d.signum()),
                    None if y0 != 0.0 => (f64::INFINITY, y0.signum()),
                    None => (f64::INFINITY, 0.0),
                }
            }
        }
    }

    /// The first contact with a wall before `t_end`: `Ok(Some(wall, point))`, or `Ok(None)` with
    /// the point at `t_end` when it was evaluated on the way.
    #[allow(clippy::type_complexity)]
    fn walls(&mut self, wl: &Walls, t_end: f64) -> Result<(Option<(Wall, Pt)>, Option<Pt>), Stop> {
        let now = Pt {
            t: self.t,
            x: self.kin.x,
            v: self.kin.v,
        };
        for (wall, sg) in WALLS {
            let (g, g1) = gap(wl, sg, &now);
            if g <= 0.0 && toward(g1, sg * self.kin.a) {
                return Ok((Some((wall, now)), None));
            }
        }
        if t_end.is_nan() || t_end <= now.t {
            return Ok((None, None));
        }
        let from = self.out_of_reach(wl, &now);
        let start = from[0].min(from[1]);
        if start >= t_end {
            return Ok((None, None));
        }
        let mut p = if start > now.t {
            self.eval(start)?
        } else {
            now
        };
        let (mut t_inf, mut sign) = self.inflection_after(p.t);
        loop {
            // March through the piece: each trial point either brackets a root or shows there
            // is none before it (see the module doc), so the next trial starts from it.
            if p.t >= t_inf {
                (t_inf, sign) = self.inflection_after(p.t);
            }
            let piece_end = t_inf.min(t_end);
            let mut trial = match self.trial(wl, &p, &from, (piece_end, sign)) {
                ControlFlow::Break(wall) => return Ok((Some((wall, p)), None)),
                ControlFlow::Continue(t) => t,
            };
            if trial.is_nan() || trial <= p.t {
                trial = piece_end;
            }
            let q = self.eval(trial)?;
            let hit = self.first_root(wl, (p, q), &from, sign)?;
            if hit.is_some() {
                return Ok((hit, None));
            }
            if q.t >= t_end {
                return Ok((None, Some(q)));
            }
            p = q;
        }
    }

    /// When each wall (in [`WALLS`]' order) can first be reached from `now`: the main mass
    /// stays within `sqrt(2E/K)` of its rest position (energy never increases), so a wall is out
    /// of reach while the inner mass's line keeps farther from it than that. `now.t` for a wall
    /// already within reach, infinity for one the inner mass moves away from.
    #[inline]
    fn out_of_reach(&self, wl: &Walls, now: &Pt) -> [f64; 2] {
        // reach^2 = 2E/K, inflated far beyond its rounding; the square root only when a wall
        // may be out of reach.
        let reach2 = 2.0 * self.osc.energy(now.x, now.v) / self.osc.k * (1.0 + 1e-9) + 1e-300;
        let y_now = wl.y0 + wl.w * (now.t - wl.t0);
        let mut from = [now.t; 2];
        for (i, (_, sg)) in WALLS.iter().enumerate() {
            // Wall sg is touched only where sg * y >= half_d - reach.
            let room = wl.half_d - sg * y_now;
            if room > 0.0 && room * room > reach2 {
                let lack = room - reach2.sqrt();
                let closing = sg * wl.w;
                from[i] = if closing > 0.0 {
                    now.t + lack / closing
                } else {
                    f64::INFINITY
                };
            }
        }
        from
    }

    /// The next trial time from `p` on the piece ending at `piece_end` of convexity `sign`: a
    /// thousandth of the tolerance short of each reachable wall's cubic-model root, or the
    /// piece's end; `Break(wall)` where `p` is at a wall within the tolerance.
    #[inline]
    fn trial(
        &self,
        wl: &Walls,
        p: &Pt,
        from: &[f64; 2],
        (piece_end, sign): (f64, f64),
    ) -> ControlFlow<Wall, f64> {
        let ap = self.accel(p.x, p.v);
        let jp = self.jerk(ap, p.v);
        let mut trial = piece_end;
        for (i, (wall, sg)) in WALLS.into_iter().enumerate() {
            if from[i] >= piece_end {
                continue;
            }
            let (g, g1) = gap(wl, sg, p);
            let g = g.max(0.0);
            if g1 < 0.0 && g <= -g1 * self.tol_t {
                // Heading into the wall and its tangent meets it within the tolerance: on a
                // concave piece the root lies before the tangent's zero; on a convex one
                // this is the tangent step below the tolerance that declares a contact.
                return ControlFlow::Break(wall);
            }
            if sg * sign > 0.0 && (g1 >= 0.0 || g >= -g1 * (piece_end - p.t)) {
                continue; // convex and above its tangent, positive to the piece's end
            }
            // Aim a thousandth of the tolerance short of the local cubic model's root: once
            // the model is that good the trial lands on the positive side, at the wall to
            // well within the tolerance.
            let h = model_root(g, g1, sg * ap, sg * jp, true);
            let t = p.t + h;
            trial = trial.min(t - self.aim(t));
        }
        ControlFlow::Continue(trial)
    }

    /// The first wall contact between the trial points `p` and `q` (piece convexity `sign`):
    /// a root bracketed by `q` below a wall, or a dip below it between them on a convex piece.
    #[inline]
    fn first_root(
        &mut self,
        wl: &Walls,
        (p, q): (Pt, Pt),
        from: &[f64; 2],
        sign: f64,
    ) -> Result<Option<(Wall, Pt)>, Stop> {
        let mut hit: Option<(Wall, Pt)> = None;
        for (i, (wall, sg)) in WALLS.into_iter().enumerate() {
            if from[i] > q.t {
                continue;
            }
            let conv = sg * sign;
            let (gp, g1p) = gap(wl, sg, &p);
            let (gq, g1q) = gap(wl, sg, &q);
            let root = if gq <= 0.0 {
                Some(self.refine(wl, sg, p, q, conv)?)
            } else if conv > 0.0 && gp > 0.0 && g1p < 0.0 && g1q > 0.0 {
                self.dip(wl, sg, p, q)?
            } else {
                None
            };
            if let Some(r) = root
                && hit.is_none_or(|(_, h)| r.t < h.t)
            {
                hit = Some((wall, r));
            }
        }
        Ok(hit)
    }

    /// Refines the root bracketed by `lo` (gap `> 0`, or at zero leaving) and `hi` (gap `<= 0`)
    /// on a piece of known convexity; returns a point on the positive side within the tolerance.
    ///
    /// The tangents and the chord bound the root on both sides (convex: the tangents' zeros
    /// before it, the chord's after; concave: the reverse). Trial points come from the local
    /// quadratic model at the end nearer the root, kept inside the bounds; once the bounds are
    /// within half a tolerance, the point a thousandth of a tolerance before the lower bound is
    /// taken.
    fn refine(
        &mut self,
        wl: &Walls,
        sg: f64,
        mut lo: Pt,
        mut hi: Pt,
        conv: f64,
    ) -> Result<Pt, Stop> {
        loop {
            if hi.t - lo.t <= self.tol_t {
                return Ok(lo);
            }
            let (gl, g1l) = gap(wl, sg, &lo);
            let gl = gl.max(0.0);
            let (gh, g1h) = gap(wl, sg, &hi);
            let tc = if gl > gh {
                lo.t + gl / (gl - gh) * (hi.t - lo.t)
            } else {
                lo.t
            };
            let (tl, th) = (
                if g1l < 0.0 {
                    lo.t + gl / -g1l
                } else {
                    f64::NAN
                },
                if g1h < 0.0 { hi.t - gh / g1h } else { f64::NAN },
            );
            let (lb, ub) = if conv > 0.0 {
                if tl - lo.t <= self.tol_t {
                    return Ok(lo); // the tangent step from lo is below the tolerance
                }
                (lo.t.max(tl).max(th), hi.t.min(tc))
            } else {
                (lo.t.max(tc), hi.t.min(tl).min(th))
            };
            if ub - lo.t <= self.tol_t {
                return Ok(lo); // the root is within the tolerance after lo
            }
            // Once the bounds pin the root (or cross, which only rounding makes them do), land
            // just before them; otherwise aim just short of the local model's root (see `aim`),
            // from the end nearer the root, kept within the bounds.
            let mut landing = ub - lb <= 0.5 * self.tol_t;
            let mut t = if landing {
                let t = lb.min(ub);
                t - self.aim(t)
            } else {
                let (base, g, g1) = if gl <= -gh {
                    (lo, gl, g1l)
                } else {
                    (hi, gh, g1h)
                };
                let a = self.accel(base.x, base.v);
                let t = base.t + model_root(g, g1, sg * a, sg * self.jerk(a, base.v), false);
                let t = t - self.aim(t);
                if t.is_nan() || t < lb {
                    lb // the lower bound itself is before the root
                } else if t >= ub {
                    0.5 * (lb + ub)
                } else {
                    t
                }
            };
            if !(t > lo.t && t < hi.t) {
                // Every trial lies strictly inside the bracket, so it always shrinks.
                landing = false;
                t = 0.5 * (lo.t + hi.t);
                if !(t > lo.t && t < hi.t) {
                    return Ok(lo); // as narrow as the floating-point grid allows
                }
            }
            let pt = self.eval(t)?;
            if gap(wl, sg, &pt).0 > 0.0 {
                if landing {
                    return Ok(pt);
                }
                lo = pt;
            } else {
                hi = pt;
            }
        }
    }

    /// A convex gap positive at both ends, falling at `lo` and rising at `hi`: does it dip to
    /// zero in between? Tangent steps from `lo` never pass a root; the two tangents bound the gap
    /// from below where they cross.
    fn dip(&mut self, wl: &Walls, sg: f64, mut lo: Pt, mut hi: Pt) -> Result<Option<Pt>, Stop> {
        loop {
            let (gl, g1l) = gap(wl, sg, &lo);
            let (gh, g1h) = gap(wl, sg, &hi);
            if gl / -g1l <= self.tol_t {
                return Ok(Some(lo)); // a grazing contact, to the tolerance
            }
            let t = (gh - gl + g1l * lo.t - g1h * hi.t) / (g1l - g1h);
            if gl + g1l * (t - lo.t) > 0.0 {
                return Ok(None);
            }
            let t = if t > lo.t && t < hi.t {
                t
            } else {
                let m = 0.5 * (lo.t + hi.t);
                if !(m > lo.t && m < hi.t) {
                    return Ok(Some(lo));
                }
                m
            };
            let pt = self.eval(t)?;
            let (g, g1) = gap(wl, sg, &pt);
            if g <= 0.0 {
                return self.refine(wl, sg, lo, pt, 1.0).map(Some);
            }
            if g1 < 0.0 {
                lo = pt;
            } else if g1 > 0.0 {
                hi = pt;
            } else {
                return Ok(None); // the minimum, and it is positive
            }
        }
    }

    /// Moves just past the zero of the contact force (within a few tolerances), so that the
    /// freed main mass accelerates away from the wall instead of being caught by it again at the
    /// same instant. Only the force's sign is checked in this tiny window.
    fn step_past_separation(&mut self, side: f64) -> Result<(), Stop> {
        let o = self.osc;
        let start = self.t;
        let mut tau = self.tol_t;
        for _ in 0..64 {
            let p = self.eval(start + tau)?;
            self.go_to(p);
            if side * (o.c * p.v + o.k * p.x) < 0.0 {
                return Ok(());
            }
            tau *= 2.0;
        }
        Ok(())
    }

    fn find(&mut self, w: &Watch) -> Result<Event, Stop> {
        // Every call counts, so the step cap also bounds events that take no evaluation.
        self.steps += 1;
        if self.steps > self.max_steps {
            return Err(Stop::Cap);
        }
        // Explicit events first: the earliest bounds the wall search.
        let mut best = (w.t_limit.max(self.t), Event::Limit);
        let mut take = |t: Option<f64>, ev: Event| {
            if let Some(t) = t
                && t < best.0
            {
                best = (t, ev);
            }
        };
        if let Some(s) = w.x_side {
            take(self.crossing(Pure::X, s), Event::XZero);
        }
        if let Some(s) = w.v_side {
            take(self.crossing(Pure::V, s), Event::VZero);
        }
        if let Some(s) = w.sep_side {
            take(self.crossing(Pure::Force, s), Event::Separation);
        }
        let mut at_end = None;
        if let Some(wl) = &w.walls {
            let (hit, end) = self.walls(wl, best.0)?;
            if let Some((wall, p)) = hit {
                self.go_to(p);
                return Ok(Event::Wall(wall));
            }
            at_end = end;
        }
        let (t, ev) = best;
        if t > self.t {
            let p = match at_end {
                Some(p) if p.t == t => p,
                _ => self.eval(t)?,
            };
            self.go_to(p);
        }
        if ev == Event::Separation
            && let Some(side) = w.sep_side
        {
            self.step_past_separation(side)?;
        }
        Ok(ev)
    }
}

impl PhaseSolver for ExactPhase {
    type Motion = Oscillator;

    fn begin(&mut self, osc: &Oscillator, t: f64, x: f64, v: f64) {
        if *osc != self.osc {
            let before = (self.osc, self.shape, self.taylor_h);
            (self.shape, self.taylor_h) = match self.spare {
                Some((o, shape, h)) if o == *osc => (shape, h),
                _ => (Shape::of(osc), 0.02 / (osc.alpha + osc.root)),
            };
            self.osc = *osc;
            // The dummy of `new` is not kept.
            if !before.0.mass.is_nan() {
                self.spare = Some(before);
            }
        }
        let a = osc.accel(x, v);
        self.t0 = t;
        self.x0 = x;
        self.v0 = v;
        self.a0 = a;
        self.t = t;
        self.kin = Kinematics { x, v, a };
        self.crossings = [None; 3];
        self.set_base(t, x, v);
        if let Shape::Under { omega, .. } = self.shape {
            // x = e^{-alpha tau} (x0 cos + (v0 + alpha x0) / omega sin) = amp e^{..} sin(. + phi)
            let b = (v + osc.alpha * x) / omega;
            self.cx = b;
            self.cv = -(osc.alpha * v + osc.w2 * x) / omega;
            self.phi = x.atan2(b);
            self.amp = (x * x + b * b).sqrt();
        }
    }

    fn state(&self) -> (f64, f64, f64) {
        (self.t, self.kin.x, self.kin.v)
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn add_steps(&mut self, n: u64) {
        self.steps += n;
    }

    fn closed_form(&self) -> Option<(Oscillator, f64, f64, f64)> {
        Some((self.osc, self.t0, self.x0, self.v0))
    }

    fn reach(&self, _watch: &Watch) -> Option<Reach> {
        let Kinematics { x, v, a } = self.kin;
        Some(Reach {
            a,
            jerk_max: self.osc.derivative_bounds(x, v)[3],
            tol_t: self.tol_t,
            closed_form_events: true,
        })
    }

    fn next_event(&mut self, w: &Watch) -> Result<Event, StepCap> {
        match self.find(w) {
            Ok(ev) => Ok(ev),
            Err(Stop::Cap) => Err(StepCap),
            Err(Stop::NonFinite) => Ok(Event::NonFinite),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn over_zero_is_continuous_at_critical_damping() {
        // (y0 + D tau) e^{..} has its zero at -y0 / D; beta -> 0 must approach it.
        let (y0, d) = (0.01, -2.0);
        let crit = over_zero(0.0, y0, d).unwrap();
        assert_eq!(crit, 0.005);
        // The zero moves by about beta * tau relative to it (u = -2 beta y0 / D).
        let near = over_zero(1e-12, y0, d).unwrap();
        assert!((near - crit).abs() <= 1e-13 * crit, "{near} vs {crit}");
        // Over-damped: the zero of y0 + D tau E(2 beta tau), E(s) = (e^s - 1) / s.
        let beta = 10.0;
        let tau = over_zero(beta, y0, d).unwrap();
        let reduced = y0 + d * (2.0 * beta * tau).exp_m1() / (2.0 * beta);
        assert!(reduced.abs() <= 1e-16, "{reduced}");
        // Rising toward zero from below and D > 0: the zero is ahead and upward.
        assert!(over_zero(3.0, -0.01, 2.0).unwrap() > 0.0);
        assert_eq!(over_zero(3.0, 0.01, 0.0), None);
    }

    #[test]
    fn model_root_solves_the_cubic() {
        // g = 1 - 2 h + 0.5 h^2 + 0.1 h^3 / 6 near h = 0.59, one Newton step past the quadratic root.
        let (g, g1, g2, g3) = (1.0, -2.0, 1.0, 0.1);
        let h = model_root(g, g1, g2, g3, true);
        let f = g + g1 * h + 0.5 * g2 * h * h + g3 * h * h * h / 6.0;
        assert!(f.abs() < 1e-4, "{h}: {f}");
        assert_eq!(model_root(1.0, 1.0, 1.0, 0.0, true), f64::INFINITY);
        // The nearest root may lie behind.
        assert!(model_root(-1.0, -2.0, 0.0, 0.0, false) < 0.0);
    }

    #[test]
    fn floor_and_ceil_agree_with_std() {
        for v in [-2.5, -2.0, -0.3, 0.0, 0.3, 2.0, 2.5, 1e15 + 0.5] {
            assert_eq!(floor(v), v.floor(), "{v}");
            assert_eq!(ceil(v), v.ceil(), "{v}");
        }
    }
}
