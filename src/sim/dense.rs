//! Event location on a step's interpolant, shared by the integrating solvers ([`super::rk4`],
//! [`super::dopri5`]).
//!
//! An integrator takes one step `[t_n, t_n + h]`; the motion inside it is described by
//! polynomials `x(s)`, `v(s)` in the step fraction `s = (t - t_n) / h` in `[0, 1]`: quintic
//! Hermite interpolants that match the value and the first three time derivatives at the step's
//! start (known exactly from the equation of motion, `x'' = -(c x' + k x) / mass` and its
//! derivatives) and the value and first derivative at its end (from the integrator). Their error
//! is `O(h^6)`, below either integrator's, and it vanishes like `s^4` at the start.
//!
//! Why not the textbook interpolants (a cubic Hermite for RK4, the 4th-order continuous
//! extension for DOPRI5)? Both match only the first derivative at the start. Right after a
//! separation the gap to the wall leaves zero as `g''' t^3 / 6` (the relative velocity and the
//! contact force are both zero there), and an `O(h^4)` to `O(h^5)` error in the `s^2` coefficient
//! turns that cubic negative just after the start: the inner mass is "caught" by the wall it
//! just left, at zero relative velocity, again and again (DOPRI5 with its own dense output ran
//! into the impact cap with 100000 such impacts at `e = 0.45`). Matching the start to the
//! third derivative keeps the departure's sign right.
//!
//! Every watched function of [`Watch`] is affine in `x`, `v` and `t` (wall gaps
//! `d/2 ∓ (y0 + w (t - t0) - x)`, `x`, `v`, the contact force `C v + K x`), hence a polynomial of
//! degree <= 5 in `s` too.
//!
//! The first event of a function is the first `s` in the step where it reaches zero coming from
//! the positive side: the polynomial is split at the real roots of its derivative (found
//! recursively, so all its extrema are known) into monotone pieces, and the first decreasing piece
//! that ends at or below zero holds the event. A grazing contact whose minimum dips to zero
//! between two positive end values is therefore found whenever the interpolant dips, not only when
//! the end values change sign. The root inside the piece is refined by the Illinois variant of
//! regula falsi to `tol * period`, keeping the bracket end still on the positive side, as
//! `exact` does. The state at the event is then recomputed by the integrator from the step's
//! start ([`Integrator::partial`]), so it carries the integrator's accuracy.
//!
//! Semantics shared with [`super::exact`]: a function that starts the step at or below zero fires
//! at once when heading into it (slope `< 0`, or slope `0` and curvature `< 0`); a separation is
//! reported just past the zero of the contact force (the force's sign checked on re-integrated
//! states), so the freed inner mass is not caught by the wall again at the same instant.

use super::linear::Oscillator;
use super::phase::{Event, PhaseSolver, StepCap, Wall, Watch, toward};

/// A polynomial `c[0] + c[1] s + ... + c[5] s^5` in the step fraction `s`.
pub(crate) type Poly = [f64; 6];

#[inline]
pub(crate) fn eval(p: &Poly, s: f64) -> f64 {
    ((((p[5] * s + p[4]) * s + p[3]) * s + p[2]) * s + p[1]) * s + p[0]
}

#[inline]
fn deriv(p: &Poly) -> Poly {
    [p[1], 2.0 * p[2], 3.0 * p[3], 4.0 * p[4], 5.0 * p[5], 0.0]
}

#[inline]
fn degree(p: &Poly) -> usize {
    (0..6).rev().find(|&i| p[i] != 0.0).unwrap_or(0)
}

/// `a x + b v + c + d s`, coefficient-wise.
#[inline]
fn combo(a: f64, x: &Poly, b: f64, v: &Poly, c: f64, d: f64) -> Poly {
    let mut p = [0.0; 6];
    for i in 0..6 {
        p[i] = a * x[i] + b * v[i];
    }
    p[0] += c;
    p[1] += d;
    p
}

/// Quintic Hermite interpolant in `s` of a quantity with value and first three time
/// derivatives `d = [y, y', y'', y''']` at the start of a step of length `h`, and value `y1` and
/// derivative `d1` at its end. Its error is `h^6 |y^(6)| s^4 (1 - s)^2 / 720`: of the
/// integrators' order, and of order `s^4` near the start, where the motion is exact.
#[inline]
pub(crate) fn hermite(d: [f64; 4], y1: f64, d1: f64, h: f64) -> Poly {
    let c0 = d[0];
    let c1 = h * d[1];
    let c2 = 0.5 * h * h * d[2];
    let c3 = h * h * h * d[3] / 6.0;
    let r = y1 - (c0 + c1 + c2 + c3);
    let q = h * d1 - (c1 + 2.0 * c2 + 3.0 * c3);
    let c5 = q - 4.0 * r;
    [c0, c1, c2, c3, r - c5, c5]
}

/// Up to five sorted roots in an interval.
#[derive(Clone, Copy, Debug, Default)]
struct Roots {
    r: [f64; 5],
    n: usize,
}

impl Roots {
    fn push(&mut self, x: f64) {
        if self.n < 5 {
            self.r[self.n] = x;
            self.n += 1;
        }
    }
    fn as_slice(&self) -> &[f64] {
        &self.r[..self.n]
    }
}

/// Illinois regula falsi on `[a, b]` with `fa > 0 >= fb` (or the reverse signs): returns a
/// bracket `(lo, hi)` of width `<= tol` (or as narrow as floating point allows) around the sign
/// change, `lo` on the side of `a`.
fn illinois(p: &Poly, mut a: f64, mut fa: f64, mut b: f64, mut fb: f64, tol: f64) -> (f64, f64) {
    let mut side = 0i8;
    for it in 0..400 {
        if b - a <= tol {
            break;
        }
        // Regula falsi can stall at one end of a convex piece: every fourth trial bisects, which
        // bounds the iteration count by four times the bisection's.
        let mut m = if it % 4 == 3 {
            0.5 * (a + b)
        } else {
            (a * fb - b * fa) / (fb - fa)
        };
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
            if !(m > a && m < b) {
                break; // as narrow as the floating-point grid allows
            }
        }
        let fm = eval(p, m);
        if (fm > 0.0) == (fa > 0.0) {
            a = m;
            fa = fm;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = m;
            fb = fm;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    (a, b)
}

/// The real roots of `p` (degree `<= 4`) in the open interval `(a, b)`, sorted. Roots of even
/// multiplicity are found where `p` vanishes at an extremum on the floating-point grid.
fn roots_in(p: &Poly, a: f64, b: f64) -> Roots {
    let mut out = Roots::default();
    match degree(p) {
        0 => {}
        1 => {
            let r = -p[0] / p[1];
            if r > a && r < b {
                out.push(r);
            }
        }
        2 => {
            let (c, bq, aq) = (p[0], p[1], p[2]);
            let disc = bq * bq - 4.0 * aq * c;
            if disc >= 0.0 {
                let sgn = if bq >= 0.0 { 1.0 } else { -1.0 };
                let q = -0.5 * (bq + sgn * disc.sqrt());
                let mut rs = [q / aq, if q != 0.0 { c / q } else { q / aq }];
                if rs[0] > rs[1] {
                    rs.swap(0, 1);
                }
                for r in rs {
                    if r > a && r < b && (out.n == 0 || r != out.r[out.n - 1]) {
                        out.push(r);
                    }
                }
            }
        }
        _ => {
            let crit = roots_in(&deriv(p), a, b);
            let mut l = a;
            let mut fl = eval(p, a);
            let tol = 4.0 * f64::EPSILON * (b - a).abs().max(1.0);
            for &c in crit.as_slice().iter().chain(std::iter::once(&b)) {
                let fc = eval(p, c);
                if (fl > 0.0 && fc < 0.0) || (fl < 0.0 && fc > 0.0) {
                    let (lo, hi) = illinois(p, l, fl, c, fc, tol);
                    out.push(0.5 * (lo + hi));
                } else if fc == 0.0 && c < b {
                    out.push(c);
                }
                l = c;
                fl = fc;
            }
        }
    }
    out
}

/// The smallest Bernstein coefficient of `p` (degree 5) on `[0, 1]`:
/// `b_k = sum_{i <= k} C(k, i) / C(5, i) c_i`, a lower bound of `p` there.
#[inline]
fn bernstein_min(p: &Poly) -> f64 {
    // C(k, i) / C(5, i) for k = 0..=5, i = 0..=k.
    const W: [[f64; 6]; 6] = [
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1.0, 0.2, 0.0, 0.0, 0.0, 0.0],
        [1.0, 0.4, 0.1, 0.0, 0.0, 0.0],
        [1.0, 0.6, 0.3, 0.1, 0.0, 0.0],
        [1.0, 0.8, 0.6, 0.4, 0.2, 0.0],
        [1.0, 1.0, 1.0, 1.0, 1.0, 1.0],
    ];
    let mut lo = f64::INFINITY;
    for w in &W {
        let b: f64 = (0..6).map(|i| w[i] * p[i]).sum();
        lo = lo.min(b);
    }
    lo
}

/// The first `s` in `[0, 1]` at which `g` reaches zero from the positive side (see the module
/// doc), located to `tol_s`; the returned point is on the positive side of the root when the
/// root is interior.
pub(crate) fn first_crossing(g: &Poly, tol_s: f64) -> Option<f64> {
    // Cheap exclusion: on [0, 1] a polynomial lies above the smallest of its Bernstein
    // coefficients (the convex-hull property); most steps end here.
    if bernstein_min(g) > 0.0 {
        return None;
    }
    if g[0] <= 0.0 && toward(g[1], g[2]) {
        return Some(0.0);
    }
    let crit = roots_in(&deriv(g), 0.0, 1.0);
    let mut l = 0.0;
    let mut gl = g[0];
    for &r in crit.as_slice().iter().chain(std::iter::once(&1.0)) {
        let gr = eval(g, r);
        if gl > 0.0 {
            if gr <= 0.0 {
                let (lo, _) = illinois(g, l, gl, r, gr, tol_s);
                return Some(lo);
            }
        } else if l > 0.0 && gr < gl {
            // At or below zero at the start of a decreasing piece (a piece that began at zero
            // moving away and turned back without getting clear of it): a grazing return.
            return Some(l);
        }
        l = r;
        gl = gr;
    }
    None
}

/// One accepted step: its length and end state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Step {
    pub h: f64,
    pub x1: f64,
    pub v1: f64,
}

/// The interpolants of `x` and `v` over one step of oscillator `o` from `(x, v)`.
fn interpolants(o: &Oscillator, x: f64, v: f64, st: &Step) -> (Poly, Poly) {
    let (m, c, k) = (o.mass, o.c, o.k);
    let a = -(c * v + k * x) / m;
    let j = -(c * a + k * v) / m;
    let s4 = -(c * j + k * a) / m;
    let a1 = o.accel(st.x1, st.v1);
    (
        hermite([x, v, a, j], st.x1, st.v1, st.h),
        hermite([v, a, j, s4], st.v1, a1, st.h),
    )
}

/// A one-step integrator of the oscillator's `(x, v)` ODE.
pub(crate) trait Integrator: Clone {
    /// A new phase starts (the oscillator or the state changed discontinuously).
    fn reset(&mut self, osc: &Oscillator);
    /// One accepted step from `(x, v)` of length at most `h_max`. Every attempted step counts
    /// one in `steps`; past `max_steps` the step cap is returned.
    fn step(
        &mut self,
        osc: &Oscillator,
        x: f64,
        v: f64,
        h_max: f64,
        steps: &mut u64,
        max_steps: u64,
    ) -> Result<Step, StepCap>;
    /// The state a time `tau` after `(x, v)`, the start of the last step, integrated afresh with
    /// one step of length `tau`.
    fn partial(&self, osc: &Oscillator, x: f64, v: f64, tau: f64) -> (f64, f64);
    /// The last step was cut short at an event: cached stage values are stale.
    fn cut(&mut self);
}

/// A [`PhaseSolver`] from any [`Integrator`]: steps, then looks for the first watched event on
/// each step's interpolant.
#[derive(Clone)]
pub(crate) struct Stepping<I: Integrator> {
    pub(crate) inner: I,
    osc: Oscillator,
    t: f64,
    x: f64,
    v: f64,
    tol_t: f64,
    steps: u64,
    max_steps: u64,
}

impl<I: Integrator> Stepping<I> {
    /// `tol_t` is the absolute event-time tolerance (s).
    pub(crate) fn new(inner: I, tol_t: f64, max_steps: u64) -> Self {
        Stepping {
            inner,
            osc: Oscillator::new(1.0, 1.0, 0.0),
            t: 0.0,
            x: 0.0,
            v: 0.0,
            tol_t,
            steps: 0,
            max_steps,
        }
    }

    /// The watched functions of this step, in the order ties are broken, as polynomials in `s`.
    fn functions(&self, w: &Watch, st: &Step) -> [(Event, Option<Poly>); 5] {
        let o = &self.osc;
        let (xp, vp) = interpolants(o, self.x, self.v, st);
        let walls = w.walls.map(|wl| {
            // z = y - x with y = y0 + w (t - t0); t = t_n + s h.
            let y_n = wl.y0 + wl.w * (self.t - wl.t0);
            let dy = wl.w * st.h;
            (
                combo(1.0, &xp, 0.0, &vp, wl.half_d - y_n, -dy),
                combo(-1.0, &xp, 0.0, &vp, wl.half_d + y_n, dy),
            )
        });
        [
            (Event::Wall(Wall::Right), walls.map(|p| p.0)),
            (Event::Wall(Wall::Left), walls.map(|p| p.1)),
            (
                Event::XZero,
                w.x_side.map(|s| combo(s, &xp, 0.0, &vp, 0.0, 0.0)),
            ),
            (
                Event::VZero,
                w.v_side.map(|s| combo(0.0, &xp, s, &vp, 0.0, 0.0)),
            ),
            (
                Event::Separation,
                w.sep_side
                    .map(|s| combo(s * o.k, &xp, s * o.c, &vp, 0.0, 0.0)),
            ),
        ]
    }

    /// Moves just past the zero of the contact force: doubles a small offset from `tau` until
    /// the re-integrated force has the separating sign.
    fn past_separation(&self, side: f64, x: f64, v: f64, tau: f64) -> (f64, f64, f64) {
        let o = &self.osc;
        let mut dt = self.tol_t;
        let mut last = self.inner.partial(o, x, v, tau);
        for _ in 0..64 {
            let (xe, ve) = self.inner.partial(o, x, v, tau + dt);
            last = (xe, ve);
            if side * (o.c * ve + o.k * xe) < 0.0 {
                return (tau + dt, xe, ve);
            }
            dt *= 2.0;
        }
        (tau + dt, last.0, last.1)
    }
}

impl<I: Integrator> PhaseSolver for Stepping<I> {
    type Motion = Oscillator;

    fn begin(&mut self, osc: &Oscillator, t: f64, x: f64, v: f64) {
        self.osc = *osc;
        self.t = t;
        self.x = x;
        self.v = v;
        self.inner.reset(osc);
    }

    fn state(&self) -> (f64, f64, f64) {
        (self.t, self.x, self.v)
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn add_steps(&mut self, n: u64) {
        self.steps += n;
    }

    fn next_event(&mut self, w: &Watch) -> Result<Event, StepCap> {
        loop {
            let room = w.t_limit - self.t;
            if room <= 0.0 {
                return Ok(Event::Limit);
            }
            let osc = self.osc;
            let st =
                self.inner
                    .step(&osc, self.x, self.v, room, &mut self.steps, self.max_steps)?;
            if !(st.x1.is_finite() && st.v1.is_finite()) {
                self.t += st.h;
                self.x = st.x1;
                self.v = st.v1;
                return Ok(Event::NonFinite);
            }
            let tol_s = self.tol_t / st.h;
            let mut first: Option<(Event, f64)> = None;
            for (ev, g) in self.functions(w, &st) {
                if let Some(g) = g
                    && let Some(s) = first_crossing(&g, tol_s)
                    && first.is_none_or(|(_, sf)| s < sf)
                {
                    first = Some((ev, s));
                }
            }
            if let Some((ev, s)) = first {
                let tau = s * st.h;
                let (x0, v0) = (self.x, self.v);
                let (tau, xe, ve) = match (ev, w.sep_side) {
                    (Event::Separation, Some(side)) => self.past_separation(side, x0, v0, tau),
                    _ if tau == 0.0 => (0.0, x0, v0),
                    _ => {
                        let (xe, ve) = self.inner.partial(&osc, x0, v0, tau);
                        (tau, xe, ve)
                    }
                };
                self.t += tau;
                self.x = xe;
                self.v = ve;
                self.inner.cut();
                return Ok(ev);
            }
            self.x = st.x1;
            self.v = st.v1;
            if st.h >= room {
                self.t = w.t_limit;
                return Ok(Event::Limit);
            }
            self.t += st.h;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly_from_roots(rs: &[f64], lead: f64) -> Poly {
        let mut p = [0.0; 6];
        p[0] = lead;
        for &r in rs {
            // multiply by (s - r)
            let mut q = [0.0; 6];
            for i in 0..5 {
                q[i + 1] += p[i];
                q[i] -= r * p[i];
            }
            p = q;
        }
        p
    }

    #[test]
    fn roots_of_a_quartic_are_all_found() {
        let p = poly_from_roots(&[0.1, 0.35, 0.6, 0.9], 1.0);
        let r = roots_in(&p, 0.0, 1.0);
        assert_eq!(r.n, 4, "{r:?}");
        for (got, want) in r.as_slice().iter().zip([0.1, 0.35, 0.6, 0.9]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    #[test]
    fn first_crossing_takes_the_earliest_and_stays_positive() {
        // Positive at 0, roots at 0.3 and 0.7 (dips below between): first is 0.3.
        let p = poly_from_roots(&[0.3, 0.7], 2.0);
        let s = first_crossing(&p, 1e-14).unwrap();
        assert!((s - 0.3).abs() < 1e-13 && eval(&p, s) >= 0.0, "{s}");
    }

    #[test]
    fn grazing_between_positive_ends_is_found() {
        // (s - 0.5)^2 - 1e-9: positive at both ends, dips below zero near 0.5.
        let mut p = poly_from_roots(&[0.5, 0.5], 1.0);
        p[0] -= 1e-9;
        let s = first_crossing(&p, 1e-14).unwrap();
        assert!((s - (0.5 - 1e-9f64.sqrt())).abs() < 1e-12, "{s}");
        // Lifted clear of zero, no event.
        p[0] += 2e-9;
        assert_eq!(first_crossing(&p, 1e-14), None);
    }

    #[test]
    fn start_at_zero_fires_only_when_heading_into_it() {
        assert_eq!(
            first_crossing(&[0.0, -1.0, 0.0, 0.0, 0.0, 0.0], 1e-12),
            Some(0.0)
        );
        assert_eq!(
            first_crossing(&[0.0, 0.0, -1.0, 0.0, 0.0, 0.0], 1e-12),
            Some(0.0)
        );
        // Slightly below zero but moving away: no event while it stays clear.
        assert_eq!(
            first_crossing(&[-1e-19, 1.0, 0.0, 0.0, 0.0, 0.0], 1e-12),
            None
        );
        // Moving away from zero and coming back: the return is found.
        let s = first_crossing(&[-1e-19, 1.0, -2.0, 0.0, 0.0, 0.0], 1e-14).unwrap();
        assert!((s - 0.5).abs() < 1e-12, "{s}");
    }

    #[test]
    fn hermite_reproduces_a_quintic() {
        let h = 0.3;
        let c = [1.0, 2.0, -1.0, 0.5, -0.7, 0.3];
        let y = |t: f64| c.iter().rev().fold(0.0, |acc, ci| acc * t + ci);
        let d1 = |t: f64| (1..6).rev().fold(0.0, |acc, i| acc * t + i as f64 * c[i]);
        let p = hermite([c[0], c[1], 2.0 * c[2], 6.0 * c[3]], y(h), d1(h), h);
        for s in [0.0, 0.25, 0.5, 0.8, 1.0] {
            assert!((eval(&p, s) - y(s * h)).abs() < 1e-14, "{s}");
        }
    }

    #[test]
    fn bernstein_bound_is_a_tight_lower_bound() {
        let p = poly_from_roots(&[0.3, 0.7], 1.0); // min -0.04 at 0.5
        let lo = bernstein_min(&p);
        let min = (0..=1000)
            .map(|i| eval(&p, i as f64 / 1000.0))
            .fold(f64::INFINITY, f64::min);
        assert!(lo <= min && lo > -0.2, "{lo} vs {min}");
        let mut q = p;
        q[0] += 0.3; // lifted clear: (s-0.3)(s-0.7)+0.3 > 0 on [0, 1]
        assert!(bernstein_min(&q) > 0.0);
    }

    #[test]
    fn departure_from_a_triple_zero_is_not_an_event() {
        // The gap right after a separation: 0 + 0 s + tiny s^2 + g3 s^3 - ...; never an event.
        let g = [-1e-19, 0.0, 1e-22, 1e-6, -2e-7, 1e-8];
        assert_eq!(first_crossing(&g, 1e-12), None);
    }
}
