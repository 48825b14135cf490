//! Closed-form phases of a driven oscillator and their event finder, shared by the scenes whose
//! load is a known function of time: the harmonic scene ([`super::harmonic`], a force
//! `F0 cos(omega t)` on the main mass) and the random and record scenes ([`super::random`], a
//! load linear between samples). A [`Driven`] motion is the free motion of [`super::linear`]
//! plus a particular solution of the load; [`DrivenPhase`] moves it through one phase and
//! locates its events by the guaranteed brackets of [`crate::sim::exact`].
//!
//! Each watched function (a gap to a wall, the displacement, the velocity, the contact force of a
//! stuck pair) is a smooth function of the motion whose second and fourth derivatives are
//! bounded for the rest of the phase by [`Driven::bounds`] (the free part's energy bound plus
//! the particular part's: `A omega^j` for the harmonic force, nothing beyond the first
//! derivative for a linear load; under the harmonic force a design-life measurement takes the
//! tighter [`Driven::bounds_over`] to the step's time limit once per phase,
//! [`Driven::PHASE_BOUNDS`]); for the contact force `C B3 + K B2 + |L''|` and
//! `C B5 + K B4 + |L''''|`, with `L` the load in the contact function
//! ([`Driven::contact_load_bounds`]). The gaps to the walls add the inner mass's own motion
//! (a cubic in time, `Walls::at` of [`crate::sim::phase`]): its acceleration enters the gaps' second derivative and
//! their bound. The safe step ([`safe_step`] of [`crate::sim::phase`]) from a point where the
//! function is `g >= 0` away from zero cannot step over a root, grazing (double) roots
//! included; an event is declared when a function heading into zero has a safe step below
//! `tol_t`, so its time is within `tol_t` of the true root.
//!
//! The extrema of `x` (the zeros of `v`, watched only to measure the amplitude) are the
//! exception: only their value `x` is kept, and `x` is stationary there, so the safe steps need
//! not crawl up to the root. Once the cubic Taylor model of `v` places the root close enough
//! that `x` there differs from `x` at the true root by at most `EPSILON |x|`
//! ([`polished_extremum`]), the solver moves to the model's root and declares the event: about
//! two evaluations of the motion fewer per extremum.

use super::linear::Oscillator;
use super::phase::{Event, Motion, PhaseSolver, Reach, StepCap, Wall, Watch, safe_step, toward};

/// Position, velocity and the next three derivatives at one time (SI).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Jet {
    pub x: f64,
    pub v: f64,
    pub a: f64,
    pub j: f64,
    pub j2: f64,
    /// The free part alone (its energy gives the bounds).
    pub xh: f64,
    pub vh: f64,
}

/// A driven oscillator's motion in closed form over one phase: the free motion of an
/// [`Oscillator`] from the free part `(h0, g0)` at the phase's start `t0`, plus a particular
/// solution of the load. Times are the scene's clock (the harmonic scene's since the last
/// section, the random scene's since the last load sample).
pub(crate) trait Driven: Motion {
    /// The start of a phase at `t0` in `(x0, v0)`: its free part `(h0, g0)` and its motion there.
    fn start(&self, t0: f64, x0: f64, v0: f64) -> (f64, f64, Jet);
    /// The motion at `t` of the phase that started at `t0` with free part `(h0, g0)`.
    fn jet(&self, t0: f64, h0: f64, g0: f64, t: f64) -> Jet;
    /// `B[j] >= |x^(j)|`, `j = 0..=5`, for every later time of this phase, from `jet` now.
    fn bounds(&self, jet: &Jet) -> [f64; 6];
    /// Whether the event finder takes its bounds once per phase and time limit
    /// ([`Driven::bounds_over`] from the phase's first step to the limit) instead of at every
    /// step ([`Driven::bounds`]) in a run with an extremum floor (a design-life measurement's
    /// periods after its first window).
    const PHASE_BOUNDS: bool = false;
    /// Bounds as [`Driven::bounds`] that hold over the next `horizon` seconds only (the default:
    /// the phase's).
    fn bounds_over(&self, jet: &Jet, _horizon: f64) -> [f64; 6] {
        self.bounds(jet)
    }
    /// The oscillator `(mass, k, c)` of the free part.
    fn oscillator(&self) -> &Oscillator;
    /// The load `L` in the contact function `C v + K x - L(t)` of a stuck pair (the force on the
    /// pair when the load is a force on the main mass; zero under ground acceleration) and its
    /// first three derivatives at `t`.
    fn contact_load(&self, t: f64) -> [f64; 4];
    /// Bounds of `|L''|` and `|L''''|` over the rest of the phase.
    fn contact_load_bounds(&self) -> (f64, f64);
    /// A number with the sign of the contact function at `jet` (at time `t`).
    fn contact_sign(&self, t: f64, jet: &Jet) -> f64;
}

/// One smooth phase of a driven main mass (free, or the stuck pair), in closed form.
#[derive(Clone)]
pub(crate) struct DrivenPhase<F: Driven> {
    f: F,
    t0: f64,
    h0: f64,
    g0: f64,
    t: f64,
    jet: Jet,
    tol_t: f64,
    steps: u64,
    max_steps: u64,
    /// The phase's bounds and the time limit they hold to ([`Driven::PHASE_BOUNDS`]).
    held: Option<(f64, [f64; 6])>,
}

impl<F: Driven> DrivenPhase<F> {
    pub fn new(f: &F, tol_t: f64, max_steps: u64) -> Self {
        DrivenPhase {
            f: *f,
            t0: 0.0,
            h0: 0.0,
            g0: 0.0,
            t: 0.0,
            jet: Jet::default(),
            tol_t,
            steps: 0,
            max_steps,
            held: None,
        }
    }

    /// The phase's motion at any time (for quadrature), without moving.
    #[inline]
    pub fn at(&self, t: f64) -> Jet {
        self.f.jet(self.t0, self.h0, self.g0, t)
    }

    /// The phase's motion, its start `t0` and free part `(h0, g0)` there.
    #[inline]
    pub fn phase(&self) -> (&F, f64, f64, f64) {
        (&self.f, self.t0, self.h0, self.g0)
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
            if side * self.f.contact_sign(self.t, &self.jet) < 0.0 {
                return;
            }
            tau *= 2.0;
        }
    }
}

/// The nearest event a step has found so far: the safe step `h` every watched function allows,
/// and the event (with its step) that fires within the tolerance `tol_t`, if any.
pub(crate) struct Nearest {
    pub(crate) h: f64,
    pub(crate) fired: Option<(Event, f64)>,
    pub(crate) tol_t: f64,
}

impl Nearest {
    /// Watched function `g` (derivatives `g1 … g3`, bounds `b2`, `b4` on the second and fourth)
    /// for event `ev`: fires when its safe step is within the tolerance and it heads to zero
    /// (the nearest such wins), else shortens the step to its safe step. Returns that safe
    /// step.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn consider(
        &mut self,
        ev: Event,
        g: f64,
        g1: f64,
        g2: f64,
        g3: f64,
        b2: f64,
        b4: f64,
    ) -> f64 {
        let hi = safe_step(g, g1, g2, g3, b2, b4);
        if hi <= self.tol_t && toward(g1, g2) {
            if self.fired.is_none_or(|(_, hf)| hi < hf) {
                self.fired = Some((ev, hi));
            }
        } else if hi < self.h {
            self.h = hi;
        }
        hi
    }
}

impl<F: Driven> DrivenPhase<F> {
    /// The bounds on the derivatives of `x` over the step: the phasors' where a design-life
    /// measurement runs (a floor set; computed once per limit `t_limit` and held), the census
    /// and every other run the energy bounds, step for step, and their bits.
    #[inline(always)]
    fn bounds(&mut self, w: &Watch) -> [f64; 6] {
        let f = self.f;
        let h = w.t_limit - self.t;
        if F::PHASE_BOUNDS && w.x_floor > 0.0 {
            match self.held {
                Some((limit, b)) if limit == w.t_limit => b,
                _ => {
                    let b = f.bounds_over(&self.jet, h);
                    self.held = Some((w.t_limit, b));
                    b
                }
            }
        } else {
            f.bounds(&self.jet)
        }
    }

    /// The walls, the zero of `x` and the separation from the stuck pair, each as watched
    /// (`w`), with the bounds `b`, into `near`.
    #[inline(always)]
    fn watch(&self, w: &Watch, b: &[f64; 6], near: &mut Nearest) {
        let f = self.f;
        let Jet { x, v, a, j, .. } = self.jet;
        if let Some(walls) = &w.walls {
            // z = y - x; the inner mass is a cubic in time (a line when it does not
            // accelerate, and then the gaps' derivatives are those of -x or +x).
            let (y, yv, ya, yj) = walls.at(self.t);
            let z = y - x;
            let z1 = yv - v;
            let b2 = b[2] + walls.ya_max;
            near.consider(
                Event::Wall(Wall::Right),
                walls.half_d - z,
                -z1,
                a - ya,
                j - yj,
                b2,
                b[4],
            );
            near.consider(
                Event::Wall(Wall::Left),
                z + walls.half_d,
                z1,
                -(a - ya),
                -(j - yj),
                b2,
                b[4],
            );
        }
        if let Some(s) = w.x_side {
            near.consider(Event::XZero, s * x, s * v, s * a, s * j, b[2], b[4]);
        }
        if let Some(s) = w.sep_side {
            let ([g, g1, g2, g3], b2, b4) = separation(&f, &self.jet, self.t, b);
            near.consider(Event::Separation, s * g, s * g1, s * g2, s * g3, b2, b4);
        }
    }
}

/// The stuck pair's contact function `C v + K x - L` at `t` (contact holds while `s` times it
/// stays `>= 0`, module doc) with its first three derivatives, and the bounds on its second and
/// fourth from the bounds `b` on `x`'s.
#[inline(always)]
pub(crate) fn separation<F: Driven>(
    f: &F,
    jet: &Jet,
    t: f64,
    b: &[f64; 6],
) -> ([f64; 4], f64, f64) {
    let (c, k) = (f.oscillator().c, f.oscillator().k);
    let Jet { x, v, a, j, j2, .. } = *jet;
    let [fo, f1, f2, f3] = f.contact_load(t);
    let g = c * v + k * x - fo;
    let g1 = c * a + k * v - f1;
    let g2 = c * j + k * a - f2;
    let g3 = c * j2 + k * j - f3;
    let (l2, l4) = f.contact_load_bounds();
    let b2 = c * b[3] + k * b[2] + l2;
    let b4 = c * b[5] + k * b[4] + l4;
    ([g, g1, g2, g3], b2, b4)
}

impl<F: Driven> PhaseSolver for DrivenPhase<F> {
    type Motion = F;

    fn begin(&mut self, f: &F, t: f64, x: f64, v: f64) {
        self.f = *f;
        self.t0 = t;
        self.held = None;
        (self.h0, self.g0, self.jet) = f.start(t, x, v);
        self.t = t;
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

    fn add_steps(&mut self, n: u64) {
        self.steps += n;
    }

    fn reach(&self, _watch: &Watch) -> Option<Reach> {
        Some(Reach {
            a: self.jet.a,
            jerk_max: self.f.bounds(&self.jet)[3],
            tol_t: self.tol_t,
            closed_form_events: false,
        })
    }

    fn next_event(&mut self, w: &Watch) -> Result<Event, StepCap> {
        loop {
            self.steps += 1;
            if self.steps > self.max_steps {
                return Err(StepCap);
            }
            let Jet { x, v, a, j, .. } = self.jet;
            let b = self.bounds(w);
            let mut near = Nearest {
                h: w.t_limit - self.t,
                fired: None,
                tol_t: self.tol_t,
            };
            self.watch(w, &b, &mut near);
            let Nearest {
                mut h, mut fired, ..
            } = near;
            // The velocity last: an extremum polished now must lie within the others' safe
            // step `h`.
            let mut v_unwatched = None;
            if let Some(s) = w.v_side {
                let (g, g1, g2, g3) = (s * v, s * a, s * j, s * self.jet.j2);
                let hi = safe_step(g, g1, g2, g3, b[3], b[5]);
                // A step shorter than the others' is worth taking only when v allows less.
                let shortest = if hi < h { hi } else { 0.5 * h };
                let skip = if w.x_floor > 0.0 {
                    skip_step(w.x_floor, [x, v, a, j], b[4], h, shortest)
                } else {
                    None
                };
                if let Some(tau) = skip {
                    // |x| stays below the floor over the step: no extremum to locate in it.
                    h = tau;
                    v_unwatched = Some(s);
                } else if hi <= self.tol_t && toward(g1, g2) {
                    if fired.is_none_or(|(_, hf)| hi < hf) {
                        fired = Some((Event::VZero, hi));
                    }
                } else {
                    if fired.is_none()
                        && let Some(tau) = polished_extremum([g, g1, g2, g3], b[5], b[2], x)
                        && tau < h
                        && tau <= w.t_limit - self.t
                    {
                        self.seek(self.t + tau);
                        return Ok(Event::VZero);
                    }
                    h = h.min(hi);
                }
            }
            if let Some((ev, hi)) = fired {
                if ev == Event::Separation
                    && let Some(side) = w.sep_side
                {
                    self.step_past_separation(side, hi);
                }
                return Ok(ev);
            }
            // `v` changed sign in a step that did not watch it: the extremum stayed below the
            // floor, and the side flips here.
            let flipped = |p: &Self| v_unwatched.is_some_and(|s| s * p.jet.v < 0.0);
            if w.t_limit - self.t <= h {
                let t = w.t_limit;
                self.seek(t);
                return Ok(if flipped(self) {
                    Event::VZero
                } else {
                    Event::Limit
                });
            }
            let t = self.t + h.max(self.tol_t);
            self.seek(t.min(w.t_limit));
            if !self.jet.x.is_finite() || !self.jet.v.is_finite() {
                return Ok(Event::NonFinite);
            }
            if flipped(self) {
                return Ok(Event::VZero);
            }
        }
    }
}

/// The longest of `h`, `h/2`, `h/4`, `h/8` that is longer than `shortest` and over which `|x|`
/// surely stays below `floor` ([`below_floor`]).
#[inline]
pub(crate) fn skip_step(floor: f64, jet: [f64; 4], b4: f64, h: f64, shortest: f64) -> Option<f64> {
    let mut tau = h;
    // The model's stationary points do not depend on the step: found once, when first needed.
    let mut stationary = None;
    for _ in 0..4 {
        if tau <= shortest {
            return None;
        }
        if below_floor_with(floor, jet, b4, tau, &mut stationary) {
            return Some(tau);
        }
        tau *= 0.5;
    }
    None
}

/// Whether `|x|` surely stays below `floor > 0` over the next `h` (false when the floor is 0):
/// the largest `|c(tau)|` of the cubic Taylor model `c = x + v tau + a tau^2/2 + j tau^3/6` over
/// `[0, h]` (its ends and its stationary points) plus the model's error `b4 h^4 / 24`
/// (`b4 >= |x''''|` for the rest of the phase) is below it.
#[inline]
pub(crate) fn below_floor(floor: f64, jet: [f64; 4], b4: f64, h: f64) -> bool {
    below_floor_with(floor, jet, b4, h, &mut None)
}

/// [`below_floor`], the model's stationary points taken from `stationary` or found and kept
/// there ([`stationary_times`]): the same decision for any `h`, the points found once.
#[inline]
fn below_floor_with(
    floor: f64,
    [x, v, a, j]: [f64; 4],
    b4: f64,
    h: f64,
    stationary: &mut Option<[f64; 2]>,
) -> bool {
    if floor <= 0.0 || !h.is_finite() {
        return false;
    }
    let j6 = j * (1.0 / 6.0);
    let c = |t: f64| x + t * (v + t * (0.5 * a + t * j6));
    let h2 = h * h;
    let err = b4 * h2 * h2 * (1.0 / 24.0);
    let below = |top: f64| (top + err) * (1.0 + 1e-12) < floor;
    let mut top = x.abs().max(c(h).abs());
    // Two shortcuts before the stationary points: the ends alone reach the floor, or the
    // model's terms in absolute value stay below it.
    if !below(top) {
        return false;
    }
    if below(x.abs() + h * (v.abs() + h * (0.5 * a.abs() + h * j6.abs()))) {
        return true;
    }
    for t in *stationary.get_or_insert_with(|| stationary_times(v, a, j)) {
        // NaN (no such point) is in no interval.
        if t > 0.0 && t < h {
            top = top.max(c(t).abs());
        }
    }
    below(top)
}

/// The times at which the cubic model `x + v t + a t^2 / 2 + j t^3 / 6` is stationary, the roots
/// of `v + a t + j t^2 / 2` (in the order [`below_floor`] visits them; NaN where there is none).
#[inline]
fn stationary_times(v: f64, a: f64, j: f64) -> [f64; 2] {
    let (qa, qb, qc) = (0.5 * j, a, v);
    let none = f64::NAN;
    if qa == 0.0 {
        return [if qb != 0.0 { -qc / qb } else { none }, none];
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc >= 0.0 {
        let q = -0.5 * (qb + qb.signum() * disc.sqrt());
        if q != 0.0 {
            return [q / qa, qc / q];
        }
    }
    [none, none]
}

/// The time to the next zero of `g = s v` (heading into it: `g > 0`, `g1 < 0`) from its cubic
/// Taylor model `g + g1 tau + g2 tau^2 / 2 + g3 tau^3 / 6`, when `x` at the model's root is
/// within `EPSILON |x|` of `x` at the true one; `None` while the root is too far for that.
///
/// The model's error is at most `b4 tau^4 / 24` (`b4 >= |g''''| = |x^(5)|` for the rest of the
/// phase), which moves the root by `delta <= b4 tau^4 / (24 |m'(tau)|)`; `x' = 0` there, so `x`
/// differs by at most `b2 delta^2 / 2` (`b2 >= |x''|`), asked to be below `EPSILON |x|`.
pub(crate) fn polished_extremum(
    [g, g1, g2, g3]: [f64; 4],
    b4: f64,
    b2: f64,
    x: f64,
) -> Option<f64> {
    if !(g > 0.0 && g1 < 0.0) {
        return None;
    }
    let g3_6 = g3 * (1.0 / 6.0);
    let model = |t: f64| ((g3_6 * t + 0.5 * g2) * t + g1) * t + g;
    let slope = |t: f64| (0.5 * g3 * t + g2) * t + g1;
    // From the quadratic model's first root (or the tangent's), two Newton steps on the cubic.
    let disc = g1.mul_add(g1, -2.0 * g2 * g);
    let mut tau = if disc >= 0.0 {
        2.0 * g / (disc.sqrt() - g1)
    } else {
        -g / g1
    };
    for _ in 0..2 {
        let d = slope(tau);
        if d.is_nan() || d >= 0.0 {
            return None;
        }
        tau -= model(tau) / d;
    }
    // `0.5 b2 delta^2 <= EPSILON |x|` with `delta = e / d`, multiplied out by `d^2`.
    let d = slope(tau).abs();
    let e = b4 * tau.powi(4) * (1.0 / 24.0);
    let ok = tau > 0.0
        && tau.is_finite()
        && d > 0.0
        && 0.5 * b2 * e * e <= f64::EPSILON * x.abs() * d * d;
    ok.then_some(tau)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::harmonic::motion::Forced;

    /// The root of `v` in `[lo, hi]` (where it changes sign) by bisection on the closed form.
    fn v_root(p: &DrivenPhase<Forced>, mut lo: f64, mut hi: f64) -> f64 {
        let s = p.at(lo).v.signum();
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if p.at(mid).v.signum() == s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    #[test]
    fn polished_extrema_have_the_value_of_the_true_ones() {
        // The showcase's structure near resonance, a large free part (every event watched only
        // for `v`): 40 extrema of the forced motion, each against the bisected root of `v`.
        for r in [0.85, 1.0, 1.15] {
            let wn = (400.0f64 / 0.1).sqrt();
            let f = Forced::new(0.1, 400.0, 0.1, 0.1, r * wn);
            let tol_t = 1e-12 * std::f64::consts::TAU / wn;
            let mut p = DrivenPhase::new(&f, tol_t, 1_000_000);
            p.begin(&f, 0.0, 0.01, 0.3);
            let mut side = p.jet.v.signum();
            for _ in 0..40 {
                let w = Watch {
                    walls: None,
                    x_side: None,
                    v_side: Some(side),
                    x_floor: 0.0,
                    sep_side: None,
                    t_limit: 100.0,
                };
                assert!(matches!(p.next_event(&w), Ok(Event::VZero)));
                let t = p.t;
                let root = v_root(&p, t - 1e-4, t + 1e-4);
                let (x, x_true) = (p.jet.x, p.at(root).x);
                // The closed form's own rounding: x is the sum of a free and a particular part,
                // each up to larger than x, of phases `omega t` whose rounding grows with `t`.
                let parts = p.jet.xh.abs() + (x - p.jet.xh).abs();
                let rounding = 4.0 * f64::EPSILON * parts * (1.0 + wn.max(r * wn) * t);
                assert!(
                    (x - x_true).abs() <= rounding,
                    "r = {r}: x = {x:e} at t = {t}, true {x_true:e} at {root}"
                );
                side = -side;
            }
        }
    }

    #[test]
    fn a_far_root_is_not_polished() {
        // A quarter period from the extremum of a 1 cm oscillation at 10 Hz: the model's error
        // moves the root by far more than `x` allows.
        let w = std::f64::consts::TAU * 10.0;
        let (g, g1, g2, g3) = (0.01 * w, 0.0 - 1e-3, -0.01 * w * w * w, 0.0);
        let b4 = 0.01 * w.powi(5);
        assert_eq!(
            polished_extremum([g, g1, g2, g3], b4, 0.01 * w * w, 0.001),
            None
        );
        // Close to it the same model is polished.
        let tau = 1e-6;
        let g = 0.01 * w * w * tau;
        let p = polished_extremum(
            [g, -0.01 * w * w, 0.0, 0.01 * w.powi(4)],
            b4,
            0.01 * w * w,
            0.01,
        );
        assert!(p.is_some_and(|t| (t - tau).abs() <= 1e-9 * tau), "{p:?}");
    }
}
