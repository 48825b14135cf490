//! The stroboscopic map of the forced scene and its exact Jacobian.
//!
//! # The map
//! The section state is `s = (x, x', z, y')` with `z = y - x`, taken at `t = k T_f`,
//! `T_f = 2 pi / omega`. Because the force `F0 cos(omega t)` is `T_f`-periodic, the state one
//! forcing period later is a function of `s` alone, `P(s)`, and a period-`p` steady state is a
//! fixed point of `P^p`. [`eval`] computes `P^p(s)` with the exact event-driven simulator of the
//! forced scene ([`crate::sim::harmonic::simulate_harmonic`], the same code a sweep runs), so every
//! impact is found, grazing contacts included, and an orbit found this way cannot pass through a
//! wall: the impact sequence is not imposed, it is what the simulator finds.
//!
//! # The Jacobian
//! Between events the motion is linear in the state. In the coordinates `q = (x, x', y, y')`:
//!
//! * free flight over a time `tau`: `x, x'` move by the main mass's state-transition matrix
//!   `Phi_M(tau)` (the closed form of [`crate::sim::linear::Oscillator::propagator`]; the forcing
//!   adds a term that does not depend on the state), the inner mass by `[[1, tau], [0, 1]]`;
//! * stuck on a wall: the pair `(M + m)` moves by `Phi_{M+m}(tau)` and the inner mass follows the
//!   wall (`y = x +- d/2`, `y' = x'`).
//!
//! At an event at `t*` on the surface `h(q) = 0` the perturbation jumps by the saltation matrix
//!
//! ```text
//! S = G + (f+ - G f-) grad(h)^T / (grad(h) . f-)
//! ```
//!
//! where `G` is the Jacobian of the event's jump map and `f-`, `f+` the vector fields just
//! before and after. An impact has `h = (y - x) -+ d/2`, `grad(h) = (-1, 0, 1, 0)`, `G` the impact
//! law (eq. 3–4) on the velocities; the plastic closing that starts a sticking phase has `G` the
//! common velocity `(M x' + m y') / (M + m)` and `f+` the stuck pair's field. A separation happens
//! where the contact force, and so the pair's acceleration, is zero: there the free and the
//! stuck fields agree and `S = I`. The monodromy matrix of `P^p` is the product of the segments'
//! matrices and the saltations in time order, turned into section coordinates. A test checks it
//! against central differences of the map.

use crate::model::System;
use crate::sim::harmonic::{Drive, Harmonic, simulate_harmonic, simulate_periods};
use crate::sim::linear::Oscillator;
use crate::sim::{Outcome, Probe, Request, SolverSettings, State, Wall};

/// A section state `(x, x', z, y')` (m, m/s, m, m/s), `z = y - x`.
pub type Section = [f64; 4];
/// A 4 x 4 matrix, row-major.
pub type Mat4 = [[f64; 4]; 4];

/// One forced system: the structure, the force and the simulator's settings. The initial state
/// of `sys` is not used (each evaluation starts from its own section state).
#[derive(Clone, Debug)]
#[allow(non_snake_case)]
pub struct Forcing {
    pub sys: System,
    /// Force amplitude (N), `> 0`.
    pub F0: f64,
    /// Forcing frequency (rad/s), `> 0`.
    pub omega: f64,
    pub settings: SolverSettings,
}

impl Forcing {
    /// `T_f = 2 pi / omega` (s).
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.omega
    }

    /// The frequency ratio `r = omega / sqrt(K/M)`.
    pub fn ratio(&self) -> f64 {
        self.omega / self.sys.omega()
    }

    /// The same system at another frequency ratio.
    pub fn at_ratio(&self, r: f64) -> Forcing {
        Forcing {
            omega: r * self.sys.omega(),
            ..self.clone()
        }
    }

    /// The same system under another force amplitude.
    #[allow(non_snake_case)]
    pub fn at_force(&self, F0: f64) -> Forcing {
        Forcing { F0, ..self.clone() }
    }

    /// Steady amplitude of the main mass without the inner mass,
    /// `X_st / sqrt((1 - r^2)^2 + (2 zeta r)^2)` (m).
    pub fn amplitude_linear(&self) -> f64 {
        self.sys.linear_amplitude(self.F0, self.ratio())
    }

    /// Half the clearance, `d / 2` (m).
    pub fn half_gap(&self) -> f64 {
        0.5 * self.sys.d
    }

    /// The harmonic scene that runs `periods` forcing periods from `t = 0` and measures over all
    /// of them.
    pub(crate) fn scene(&self, periods: u64) -> Harmonic {
        Harmonic {
            F0: self.F0,
            drive: Drive::Omega(self.omega),
            n_trans: Some(0),
            n_meas: periods,
            energies: false,
            ..Harmonic::default()
        }
    }

    /// The system started in section state `s` (its `z` clamped into the clearance).
    pub(crate) fn started(&self, s: &Section) -> System {
        System {
            x0: s[0],
            v0: s[1],
            y0: self.start_y(s),
            w0: s[3],
            ..self.sys
        }
    }

    /// The inner mass's place `y` at section state `s`: `x + z`, `z` clamped into the clearance.
    fn start_y(&self, s: &Section) -> f64 {
        let hd = self.half_gap();
        s[0] + s[2].clamp(-hd, hd)
    }
}

/// What one evaluation of `P^p` found.
#[derive(Clone, Debug, PartialEq)]
pub struct MapEval {
    /// The simulator's outcome; every other field is meaningful only when `Ok`.
    pub outcome: Outcome,
    /// `P^p(s)`.
    pub end: Section,
    /// `d P^p / d s` in section coordinates (`None` unless asked for, or when an impact was a
    /// graze, `grad(h) . f- = 0`, where the map is not differentiable).
    pub jacobian: Option<Mat4>,
    /// `d P^p / d omega` and `d P^p / d F0` in section coordinates (s and s/N), exact, with the
    /// Jacobian (`None` when it is).
    pub d_param: Option<ParamDerivatives>,
    /// `max |x|` over the `p` periods (m), exact.
    pub amplitude: f64,
    /// Impacts over the `p` periods.
    pub impacts: u64,
    /// Sticking phases begun over the `p` periods.
    pub sticks: u64,
    /// The smallest relative approach speed `|y' - x'|` of an impact (m/s), `inf` without
    /// impacts: near zero the orbit is grazing.
    pub min_impact_speed: f64,
}

/// The map's derivatives in the forcing's parameters at fixed `s` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamDerivatives {
    /// `d P^p / d omega` (section units per rad/s).
    pub omega: Section,
    /// `d P^p / d F0` (section units per N).
    pub force: Section,
}

/// Events of one evaluation, recorded for the Jacobian.
#[derive(Clone, Copy, Debug)]
enum Ev {
    Impact { t: f64, before: State, after: State },
    Stick { t: f64, wall: Wall, at: State },
    Separate { t: f64 },
}

/// The slowest impact, and the events when the Jacobian is asked for (`keep`).
#[derive(Default)]
struct Recorder {
    keep: bool,
    events: Vec<Ev>,
    min_speed: f64,
}

impl Probe for Recorder {
    fn impact(&mut self, t: f64, _wall: Wall, before: &State, after: &State) {
        self.min_speed = self.min_speed.min((before.w - before.v).abs());
        if self.keep {
            self.events.push(Ev::Impact {
                t,
                before: *before,
                after: *after,
            });
        }
    }
    fn stick(&mut self, t: f64, wall: Wall, at: &State) {
        if self.keep {
            self.events.push(Ev::Stick { t, wall, at: *at });
        }
    }
    fn separate(&mut self, t: f64, _wall: Wall, _at: &State) {
        if self.keep {
            self.events.push(Ev::Separate { t });
        }
    }
}

/// Evaluates `P^p(s)` (`p >= 1` forcing periods from `t = 0`), with its Jacobian when
/// `jacobian` is set. Pure.
pub fn eval(f: &Forcing, s: &Section, p: u64, jacobian: bool) -> MapEval {
    evaluate(f, s, &f.scene(p), jacobian)
}

/// [`eval`] without the Jacobian, locating only the extrema of `x` that reach `|x| >= floor`
/// (m; [`Harmonic::x_floor`]): the amplitude is exact when it is at least `floor`, and some
/// value below `floor` otherwise. The end state is the same motion's, stepped differently
/// (it agrees with [`eval`]'s to rounding). Pure.
pub fn eval_above(f: &Forcing, s: &Section, p: u64, floor: f64) -> MapEval {
    let scene = Harmonic {
        x_floor: floor,
        ..f.scene(p)
    };
    evaluate(f, s, &scene, false)
}

/// `n` successive periods of [`eval_above`]`(f, s, 1, floor)`, each from the section the one
/// before ended on: each period's amplitude to `each`, and `s` moved to the last period's end.
/// The bits of `n` such calls, at less cost (the run is built once: [`simulate_periods`]).
/// `false` when the simulator stopped (`s` then the section the failing period started from; the
/// periods before it handed on). Pure.
pub fn periods_above(
    f: &Forcing,
    s: &mut Section,
    n: u64,
    floor: f64,
    mut each: impl FnMut(f64),
) -> bool {
    if n == 0 {
        return true;
    }
    // `m = 0` keeps the start's place in the cavity apart from the state, and several units
    // start each period from the system's own places: both run one call a period.
    if f.sys.m == 0.0 || f.sys.unit_count() > 1 {
        for _ in 0..n {
            let e = eval_above(f, s, 1, floor);
            if e.outcome != Outcome::Ok {
                return false;
            }
            each(e.amplitude);
            *s = e.end;
        }
        return true;
    }
    let sys = f.started(s);
    let scene = Harmonic {
        x_floor: floor,
        ..f.scene(1)
    };
    let state = |s: &Section| State {
        x: s[0],
        v: s[1],
        y: f.start_y(s),
        w: s[3],
    };
    let mut left = n;
    let mut end = *s;
    let ok = simulate_periods(&sys, &f.settings, &scene, state(s), |amplitude, at| {
        each(amplitude);
        end = [at.x, at.v, at.y - at.x, at.w];
        left -= 1;
        (left > 0).then(|| state(&end))
    });
    *s = end;
    ok
}

fn evaluate(f: &Forcing, s: &Section, scene: &Harmonic, jacobian: bool) -> MapEval {
    let sys = f.started(s);
    let mut rec = Recorder {
        keep: jacobian,
        events: Vec::new(),
        min_speed: f64::INFINITY,
    };
    let out = simulate_harmonic(
        &sys,
        &f.settings,
        &Request::default(),
        scene,
        None,
        &mut rec,
    );
    // `m = 0` is the main mass alone: a massless inner mass cannot act on it, so its state is
    // no part of the motion. The section keeps it at zero (as the sweep's record does): a start
    // anywhere in the cavity lands on the one steady state of the main mass, not on a family
    // of copies that differ only where the massless inner mass was left.
    let alone = sys.m == 0.0;
    let end = if alone {
        [out.end.x, out.end.v, 0.0, 0.0]
    } else {
        [out.end.x, out.end.v, out.end.y - out.end.x, out.end.w]
    };
    let end_state = out.end;
    let lin = (jacobian && out.outcome == Outcome::Ok)
        .then(|| linearise(f, &rec.events, out.t_stop, &end_state))
        .flatten()
        .map(|(mut j, mut d)| {
            if alone {
                for (i, row) in j.iter_mut().enumerate() {
                    for (k, v) in row.iter_mut().enumerate() {
                        if i >= 2 || k >= 2 {
                            *v = 0.0;
                        }
                    }
                }
                d.omega[2..].fill(0.0);
                d.force[2..].fill(0.0);
            }
            (j, d)
        });
    let (jac, d_param) = match lin {
        Some((j, d)) => (Some(j), Some(d)),
        None => (None, None),
    };
    MapEval {
        outcome: out.outcome,
        end,
        jacobian: jac,
        d_param,
        amplitude: out.amplitude,
        impacts: out.impacts,
        sticks: out.sticks,
        min_impact_speed: rec.min_speed,
    }
}

/// Which field moves the state between events.
#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Free,
    Stuck,
}

/// The monodromy matrix in section coordinates from the recorded events, and the map's
/// derivatives in `omega` and `F0` (module doc); `None` at a graze.
fn linearise(
    f: &Forcing,
    events: &[Ev],
    t_end: f64,
    end: &State,
) -> Option<(Mat4, ParamDerivatives)> {
    let sys = &f.sys;
    let free = Oscillator::new(sys.M, sys.K, sys.C);
    let pair = Oscillator::new(sys.M + sys.m, sys.K, sys.C);
    let mut lin = Linearisation {
        f,
        free,
        pair,
        j: identity(),
        eta: [[0.0; 4]; 2],
        mode: Mode::Free,
        t_prev: 0.0,
    };
    let mut i = 0;
    while i < events.len() {
        match events[i] {
            Ev::Impact { t, before, after } => {
                lin.flow_to(t);
                let s = match events.get(i + 1) {
                    Some(Ev::Stick { t: ts, wall, at }) if *ts == t => {
                        i += 1;
                        lin.mode = Mode::Stuck;
                        stick_saltation(f, t, &before, at, *wall)?
                    }
                    _ => impact_saltation(f, t, &before, &after)?,
                };
                lin.jump(&s);
            }
            Ev::Stick { t, .. } => {
                // A stick not preceded by an impact at the same instant does not occur; treat
                // it as a change of field at a point where both agree.
                lin.flow_to(t);
                lin.mode = Mode::Stuck;
            }
            Ev::Separate { t } => {
                lin.flow_to(t);
                lin.mode = Mode::Free;
            }
        }
        i += 1;
    }
    lin.flow_to(t_end);
    // The map is the state at `t_end = 2 pi p / omega`, which moves with omega:
    // `dP/domega = dq/domega (fixed t) + q'(t_end) dt_end/domega`, `dt_end/domega = -t_end/omega`.
    let field = match lin.mode {
        Mode::Free => free_field(f, t_end, end),
        Mode::Stuck => stuck_field(f, t_end, end),
    };
    let mut d_omega = lin.eta[0];
    for (k, v) in d_omega.iter_mut().enumerate() {
        *v -= field[k] * t_end / f.omega;
    }
    let sec = |q: [f64; 4]| [q[0], q[1], q[2] - q[0], q[3]];
    let d = ParamDerivatives {
        omega: sec(d_omega),
        force: sec(lin.eta[1]),
    };
    Some((to_section(&lin.j), d))
}

/// The linearisation being built along the recorded motion: `j = dq(t)/dq(0)` and
/// `eta = (dq(t)/domega, dq(t)/dF0)` at fixed `t`, in `(x, x', y, y')`.
struct Linearisation<'a> {
    f: &'a Forcing,
    free: Oscillator,
    pair: Oscillator,
    j: Mat4,
    eta: [[f64; 4]; 2],
    mode: Mode,
    t_prev: f64,
}

impl Linearisation<'_> {
    /// Along the smooth segment from `t_prev` to `t`. The motion is
    /// `q(t) = Phi(t - t0) (q(t0) - q_p(t0)) + q_p(t)` with `q_p` the particular solution of the
    /// segment's oscillator, so at fixed `t`
    /// `d q(t) = Phi d q(t0) + d q_p(t) - Phi d q_p(t0)` for a change of `omega` or `F0`.
    fn flow_to(&mut self, t: f64) {
        let phi = segment(self.mode, &self.free, &self.pair, t - self.t_prev);
        self.j = mul(&phi, &self.j);
        let d0 = particular_derivatives(self.f, self.mode, self.t_prev);
        let d1 = particular_derivatives(self.f, self.mode, t);
        for (k, eta) in self.eta.iter_mut().enumerate() {
            let moved = apply(&phi, eta);
            let from = apply(&phi, &d0[k]);
            *eta = std::array::from_fn(|r| moved[r] + d1[k][r] - from[r]);
        }
        self.t_prev = t;
    }

    /// Across an event with saltation matrix `s`. The event surface and the jump law do not
    /// depend on `omega` or `F0`, so the parameter derivatives jump by the same `s`.
    fn jump(&mut self, s: &Mat4) {
        self.j = mul(s, &self.j);
        for eta in &mut self.eta {
            *eta = apply(s, eta);
        }
    }
}

/// The derivatives in `omega` and in `F0` of the particular state of the mode's oscillator at
/// time `t`, in `(x, x', y, y')` (while stuck the inner mass moves with the main mass). With
/// `X = P - i Q = F0 / Z`, `Z = k - mass omega^2 + i c omega`: `dX/domega = -X Z'/Z`,
/// `Z' = -2 mass omega + i c`; `x_p = P cos(omega t) + Q sin(omega t)` gives
/// `dx_p/domega = P' cos + Q' sin + t x_p'/omega` and
/// `dx_p'/domega = x_p'/omega + omega (Q' cos - P' sin) - omega t x_p`; both are linear in `F0`.
fn particular_derivatives(f: &Forcing, mode: Mode, t: f64) -> [[f64; 4]; 2] {
    let sys = &f.sys;
    let mass = match mode {
        Mode::Free => sys.M,
        Mode::Stuck => sys.M + sys.m,
    };
    let w = f.omega;
    let (p, q) = crate::sim::harmonic::motion::particular(mass, sys.K, sys.C, f.F0, w);
    // X = P - iQ, Z = re + i im.
    let (zr, zi) = ((-mass * w).mul_add(w, sys.K), sys.C * w);
    let (dzr, dzi) = (-2.0 * mass * w, sys.C);
    // X Z' / Z = X (Z' conj(Z)) / |Z|^2.
    let n = zr * zr + zi * zi;
    let (ur, ui) = ((dzr * zr + dzi * zi) / n, (dzi * zr - dzr * zi) / n);
    let (xr, xi) = (p, -q);
    let (dxr, dxi) = (-(xr * ur - xi * ui), -(xr * ui + xi * ur));
    let (dp, dq) = (dxr, -dxi);
    let (sn, cs) = (w * t).sin_cos();
    let x = p * cs + q * sn;
    let v = w * (q * cs - p * sn);
    let dx = dp * cs + dq * sn + t * v / w;
    let dv = v / w + w * (dq * cs - dp * sn) - w * t * x;
    let (fx, fv) = (x / f.F0, v / f.F0);
    match mode {
        Mode::Free => [[dx, dv, 0.0, 0.0], [fx, fv, 0.0, 0.0]],
        Mode::Stuck => [[dx, dv, dx, dv], [fx, fv, fx, fv]],
    }
}

/// The state-transition matrix of one smooth segment of length `tau` in `(x, x', y, y')`.
fn segment(mode: Mode, free: &Oscillator, pair: &Oscillator, tau: f64) -> Mat4 {
    let tau = tau.max(0.0);
    match mode {
        Mode::Free => {
            let p = free.propagator(tau);
            [
                [p.xx, p.xv, 0.0, 0.0],
                [p.vx, p.vv, 0.0, 0.0],
                [0.0, 0.0, 1.0, tau],
                [0.0, 0.0, 0.0, 1.0],
            ]
        }
        Mode::Stuck => {
            let p = pair.propagator(tau);
            [
                [p.xx, p.xv, 0.0, 0.0],
                [p.vx, p.vv, 0.0, 0.0],
                [p.xx, p.xv, 0.0, 0.0],
                [p.vx, p.vv, 0.0, 0.0],
            ]
        }
    }
}

/// The vector field `q' = (x', x'', y', y'')` of the free flight at time `t`.
fn free_field(f: &Forcing, t: f64, q: &State) -> [f64; 4] {
    let sys = &f.sys;
    let a = (f.F0 * (f.omega * t).cos() - sys.C * q.v - sys.K * q.x) / sys.M;
    [q.v, a, q.w, 0.0]
}

/// The vector field of the stuck pair at time `t`.
fn stuck_field(f: &Forcing, t: f64, q: &State) -> [f64; 4] {
    let sys = &f.sys;
    let a = (f.F0 * (f.omega * t).cos() - sys.C * q.v - sys.K * q.x) / (sys.M + sys.m);
    [q.v, a, q.v, a]
}

/// `S = G + (f+ - G f-) grad(h)^T / (grad(h) . f-)` with `grad(h) = (-1, 0, 1, 0)`.
fn saltation(g: Mat4, f_minus: [f64; 4], f_plus: [f64; 4]) -> Option<Mat4> {
    let grad = [-1.0, 0.0, 1.0, 0.0];
    let den: f64 = (0..4).map(|k| grad[k] * f_minus[k]).sum();
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let gf = apply(&g, &f_minus);
    let mut s = g;
    for (r, row) in s.iter_mut().enumerate() {
        for (c, cell) in row.iter_mut().enumerate() {
            *cell += (f_plus[r] - gf[r]) * grad[c] / den;
        }
    }
    Some(s)
}

/// The saltation matrix of an impact (eq. 3–4 on the velocities).
fn impact_saltation(f: &Forcing, t: f64, before: &State, after: &State) -> Option<Mat4> {
    let (big, m, e) = (f.sys.M, f.sys.m, f.sys.e);
    let tot = big + m;
    let g = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, (big - m * e) / tot, 0.0, m * (1.0 + e) / tot],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, big * (1.0 + e) / tot, 0.0, (m - big * e) / tot],
    ];
    saltation(g, free_field(f, t, before), free_field(f, t, after))
}

/// The saltation matrix of the plastic closing that starts a sticking phase.
fn stick_saltation(f: &Forcing, t: f64, before: &State, at: &State, _wall: Wall) -> Option<Mat4> {
    let (big, m) = (f.sys.M, f.sys.m);
    let tot = big + m;
    let g = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, big / tot, 0.0, m / tot],
        [1.0, 0.0, 0.0, 0.0],
        [0.0, big / tot, 0.0, m / tot],
    ];
    saltation(g, free_field(f, t, before), stuck_field(f, t, at))
}

/// `J_sec = T J T^-1` with `T: (x, x', y, y') -> (x, x', y - x, y')`.
fn to_section(j: &Mat4) -> Mat4 {
    let t = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [-1.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let t_inv = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    mul(&mul(&t, j), &t_inv)
}

pub(crate) fn identity() -> Mat4 {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

pub(crate) fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut c = [[0.0; 4]; 4];
    for i in 0..4 {
        for k in 0..4 {
            let aik = a[i][k];
            for j in 0..4 {
                c[i][j] += aik * b[k][j];
            }
        }
    }
    c
}

pub(crate) fn apply(a: &Mat4, v: &[f64; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for i in 0..4 {
        out[i] = (0..4).map(|k| a[i][k] * v[k]).sum();
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Table I's `M`, `K` with the inner mass, clearance, restitution and damping given, at
    /// rest, under `f0 cos(omega t)` at `omega = r sqrt(K/M)`: the orbits tests' system.
    pub(crate) fn table_i(m: f64, d: f64, e: f64, c: f64, f0: f64, r: f64) -> Forcing {
        let sys = System {
            m,
            d,
            e,
            C: c,
            x0: 0.0,
            v0: 0.0,
            ..System::TABLE_I
        };
        Forcing {
            omega: r * sys.omega(),
            sys,
            F0: f0,
            settings: SolverSettings::default(),
        }
    }

    /// Impacting motions, with and without sticking, away from grazing: `(system, start, p)`.
    fn motions() -> [(Forcing, Section, u64); 4] {
        [
            (
                table_i(0.005, 0.005, 0.9, 0.1, 0.1, 0.9),
                [0.0018, 0.0, 0.001, 0.1],
                1,
            ),
            (
                table_i(0.02, 0.01, 0.8, 0.1, 0.3, 1.0),
                [0.003, -0.05, -0.002, 0.2],
                2,
            ),
            (
                table_i(0.01, 0.01, 0.5, 0.3, 0.3, 0.9),
                [0.002, 0.1, 0.0, -0.1],
                3,
            ),
            (
                table_i(0.02, 0.004, 0.2, 0.1, 0.5, 1.1),
                [0.001, 0.1, 0.001, 0.0],
                1,
            ),
        ]
    }

    /// A chain of one-period runs built once ([`periods_above`], the design life's) is, bit for
    /// bit, one [`eval_above`] call a period: the amplitudes and every section, on four chaotic
    /// motions of the design life's validation (S4, P2, S2, P1), the impacting motions with
    /// and without sticking above and one whose periods mostly end stuck, each with every
    /// extremum located and with the life's floor, and on the main mass alone (`m = 0`, its own
    /// path). Any difference would grow on the chaotic motions within a few hundred periods.
    #[test]
    fn a_chain_of_periods_built_once_is_one_call_a_period_bit_for_bit() {
        let chaotic = [
            (0.02, 0.01, 0.90),
            (0.005, 0.005, 0.975),
            (0.005, 0.02, 0.99),
            (0.02, 0.02, 1.01),
        ]
        .map(|(m, d, r)| (table_i(m, d, 0.9, 0.1, 0.1, r), [0.003, 0.05, 0.0, 0.0]));
        let sticking = motions().map(|(f, s, _)| (f, s));
        // Plastic impacts (e = 0): most periods end stuck on a wall, the next starts free.
        let stuck = (
            table_i(0.05, 0.002, 0.0, 0.1, 0.5, 0.9),
            [0.001, 0.1, 0.0, 0.0],
        );
        let alone = (
            table_i(0.0, 0.01, 0.9, 0.1, 0.1, 0.9),
            [0.003, 0.05, 0.002, 0.0],
        );
        let mut periods = 0;
        for (f, s) in chaotic.into_iter().chain(sticking).chain([stuck, alone]) {
            let on = eval(&f, &s, 200, false).end;
            for floor in [0.0, 0.8 * f.sys.d.max(0.005)] {
                let (mut one, mut z1) = (on, Vec::new());
                for _ in 0..600 {
                    let e = eval_above(&f, &one, 1, floor);
                    assert_eq!(e.outcome, Outcome::Ok);
                    z1.push(e.amplitude.to_bits());
                    one = e.end;
                }
                let (mut chain, mut z2) = (on, Vec::new());
                assert!(periods_above(&f, &mut chain, 600, floor, |a| z2.push(a.to_bits())));
                assert_eq!(z1, z2, "m {}, d {}, floor {floor}", f.sys.m, f.sys.d);
                assert_eq!(one.map(f64::to_bits), chain.map(f64::to_bits));
                periods += z2.len();
            }
        }
        assert_eq!(periods, 10 * 2 * 600);
    }

    /// Central differences of `P^p` against the exact Jacobian, on impacting motions (with and
    /// without sticking) away from grazing. Issue 16.
    #[test]
    fn jacobian_matches_central_differences() {
        let cases = motions();
        let mut checked = 0;
        for (f, s, p) in cases {
            let base = eval(&f, &s, p, true);
            assert_eq!(base.outcome, Outcome::Ok);
            let Some(jac) = base.jacobian else { continue };
            assert!(base.impacts > 0);
            let scale = [1e-7, 1e-7 * f.sys.omega(), 1e-7, 1e-7 * f.sys.omega()];
            let mut worst: f64 = 0.0;
            for c in 0..4 {
                let (mut sp, mut sm) = (s, s);
                sp[c] += scale[c];
                sm[c] -= scale[c];
                let ep = eval(&f, &sp, p, false);
                let em = eval(&f, &sm, p, false);
                if ep.impacts != base.impacts || em.impacts != base.impacts {
                    continue;
                }
                for r in 0..4 {
                    let fd = (ep.end[r] - em.end[r]) / (2.0 * scale[c]);
                    // Relative to the column's size in the section's scaled norm.
                    let norm = (0..4)
                        .map(|k| (jac[k][c] / if k % 2 == 1 { f.sys.omega() } else { 1.0 }).abs())
                        .fold(0.0, f64::max)
                        .max(1e-3);
                    let row_scale = if r % 2 == 1 { f.sys.omega() } else { 1.0 };
                    worst = worst.max(((fd - jac[r][c]) / row_scale).abs() / norm);
                }
                checked += 1;
            }
            assert!(
                worst < 1e-6,
                "{s:?}, p = {p}: worst relative error {worst:e}"
            );
        }
        assert!(checked >= 8, "only {checked} columns checked");
    }

    /// Central differences of `P^p` in `omega` and in `F0` against the exact derivatives, on
    /// the same motions (sticking included). Issue 16.
    #[test]
    fn parameter_derivatives_match_central_differences() {
        let cases = motions();
        let wn = |f: &Forcing| f.sys.omega();
        let mut checked = 0;
        for (f, s, p) in cases {
            let base = eval(&f, &s, p, true);
            let Some(d) = base.d_param else { continue };
            let steps = [1e-7 * f.omega, 1e-7 * f.F0];
            for (k, exact) in [d.omega, d.force].iter().enumerate() {
                let moved = |h: f64| {
                    let g = if k == 0 {
                        Forcing {
                            omega: f.omega + h,
                            ..f.clone()
                        }
                    } else {
                        f.at_force(f.F0 + h)
                    };
                    eval(&g, &s, p, false)
                };
                let (ep, em) = (moved(steps[k]), moved(-steps[k]));
                if ep.impacts != base.impacts || em.impacts != base.impacts {
                    continue;
                }
                let unit = |r: usize| if r % 2 == 1 { wn(&f) } else { 1.0 };
                let norm = (0..4)
                    .map(|r| (exact[r] / unit(r)).abs())
                    .fold(0.0, f64::max)
                    .max(1e-12);
                for (r, want) in exact.iter().enumerate() {
                    let fd = (ep.end[r] - em.end[r]) / (2.0 * steps[k]);
                    let err = ((fd - want) / unit(r)).abs() / norm;
                    assert!(
                        err < 1e-6,
                        "{s:?}, p = {p}, parameter {k}, row {r}: {err:e}"
                    );
                }
                checked += 1;
            }
        }
        assert!(checked >= 6, "only {checked} derivatives checked");
    }
}
