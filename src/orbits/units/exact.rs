//! The exact Jacobian of the map of several units (model.md §14; one unit's is
//! [`crate::orbits::map`]) on motions whose impacts come one unit at a time.
//!
//! In the coordinates `q = (x, x', y_1, y_1', ..., y_N, y_N')` (m, m/s) the motion between
//! events is linear in the state:
//!
//! * flight over a time `tau`: `(x, x')` by the state-transition matrix `Phi_{M_c}(tau)` of the
//!   main mass with what it carries, `M_c = M` plus the stuck unit's mass
//!   ([`crate::sim::linear::Oscillator::propagator`]; the force adds a term that does not depend
//!   on the state); each free unit by `[[1, tau], [0, 1]]`; a stuck unit follows the main mass
//!   (`y_i = x +- d_i/2`, `y_i' = x'`: its rows are those of `x`, `x'`).
//!
//! At the impact of unit `i` at `t*`, on the surface `h_i = y_i - x -+ d_i/2 = 0`
//! (`grad(h_i) = -e_x + e_{y_i}`), a perturbation jumps by the saltation matrix
//!
//! ```text
//! S = G + (f+ - G f-) grad(h_i)^T / (grad(h_i) . f-)
//! ```
//!
//! `G` the Jacobian of the jump on `(x', y_i')`, the identity elsewhere: for a rebound the
//! impact law (eq. 3–4 with `(m_i, e_i)` against `M`:
//! `x'+ = ((M - m_i e_i) x' + m_i (1 + e_i) y_i') / (M + m_i)`,
//! `y_i'+ = (M (1 + e_i) x' + (m_i - M e_i) y_i') / (M + m_i)`); for the impact whose chatter
//! ends in sticking, the plastic closing `x'+ = y_i'+ = (M x' + m_i y_i') / (M + m_i)` with
//! `y_i+ = x +- d_i/2` (its `y_i` row is `x`'s). `f-`, `f+` are the vector fields just before
//! and after (`x'' = (F0 cos(omega t) - C x' - K x) / M_c`; a free unit's `y_i'' = 0`, a stuck
//! one's `x''`); the other units' rows of `f+ - G f-` vanish. A separation happens where the
//! contact force, and so the difference of the fields, is zero: there `S = I`. The monodromy
//! matrix is the product of the segments' matrices and the saltations in time order, turned into
//! section coordinates `(x, x', y_i - x, y_i')`.
//!
//! Motions where two units hit at one instant (the simultaneous impact law is not
//! differentiable across the set where they do, [`super::map`]'s module doc), where a unit
//! hits while another is stuck (the impulse may release it, an event no probe reports), or with
//! a graze (`grad(h) . f- = 0`) have no exact Jacobian here (`None`): the caller takes central
//! differences ([`super::map::jacobian`]).

use nalgebra::DMatrix;

use super::map::{UnitsEval, eval_probe};
use crate::orbits::map::Forcing;
use crate::sim::linear::Oscillator;
use crate::sim::{Outcome, Probe, State, Wall};

/// One event of the map's motion, recorded for the Jacobian.
#[derive(Clone, Copy, Debug)]
enum Ev {
    /// Unit `unit` hit its wall at `t` (s): the state before and after (main mass and that
    /// unit); `stuck` when the chatter rule closed it onto the main mass.
    Hit {
        t: f64,
        unit: usize,
        before: State,
        after: State,
        stuck: bool,
    },
    /// The stuck units left the main mass at `t`.
    Separate { t: f64 },
}

/// The events of one evaluation; `unsupported` when something happened this module does not
/// linearise (module doc).
#[derive(Default)]
struct Recorder {
    events: Vec<Ev>,
    unsupported: bool,
}

impl Probe for Recorder {
    fn impact_of(&mut self, t: f64, unit: usize, _wall: Wall, before: &State, after: &State) {
        self.events.push(Ev::Hit {
            t,
            unit,
            before: *before,
            after: *after,
            stuck: false,
        });
    }
    fn stick(&mut self, _t: f64, _wall: Wall, _state: &State) {
        // Reported right after the impact of the unit that sticks.
        match self.events.last_mut() {
            Some(Ev::Hit { stuck, .. }) => *stuck = true,
            _ => self.unsupported = true,
        }
    }
    fn separate(&mut self, t: f64, _wall: Wall, _state: &State) {
        match self.events.last() {
            // Several units leaving together report one separation each.
            Some(Ev::Separate { t: t0 }) if *t0 == t => self.unsupported = true,
            _ => self.events.push(Ev::Separate { t }),
        }
    }
}

impl Ev {
    fn t(&self) -> f64 {
        match *self {
            Ev::Hit { t, .. } | Ev::Separate { t } => t,
        }
    }
}

/// Evaluates `P^p(s)` and its exact Jacobian in section coordinates (`(2 + 2N)` square);
/// `None` for the Jacobian where the module doc says so, or when the map failed.
pub fn eval_exact(f: &Forcing, s: &[f64], p: u64) -> (UnitsEval, Option<DMatrix<f64>>) {
    let mut rec = Recorder::default();
    let e = eval_probe(f, s, p, &mut rec);
    let simultaneous = rec
        .events
        .windows(2)
        .any(|w| matches!((w[0], w[1]), (Ev::Hit { .. }, Ev::Hit { .. })) && w[0].t() == w[1].t());
    if e.outcome != Outcome::Ok || rec.unsupported || simultaneous || f.sys.m == 0.0 {
        return (e, None);
    }
    let jac = linearise(f, &rec.events, f.period() * p as f64, e.end.len());
    (e, jac)
}

/// The monodromy matrix in section coordinates from the recorded events (module doc); `None`
/// at a graze or an unsupported sequence.
fn linearise(f: &Forcing, events: &[Ev], t_end: f64, n: usize) -> Option<DMatrix<f64>> {
    let units = f.sys.unit_list();
    let mut j = DMatrix::<f64>::identity(n, n);
    let mut t_prev = 0.0;
    // The unit stuck to the main mass, if any.
    let mut stuck: Option<usize> = None;
    for ev in events {
        j = flight(f, stuck.map(|i| units[i].m), stuck, ev.t() - t_prev, n) * j;
        t_prev = ev.t();
        match *ev {
            Ev::Hit {
                t,
                unit,
                before,
                after,
                stuck: sticks,
            } => {
                if stuck.is_some() {
                    return None;
                }
                let u = units.get(unit)?;
                let jump = Jump {
                    t,
                    unit,
                    m: u.m,
                    e: u.e,
                    before,
                    after,
                };
                j = saltation(f, &jump, sticks, n)? * j;
                if sticks {
                    stuck = Some(unit);
                }
            }
            Ev::Separate { .. } => stuck = None,
        }
    }
    j = flight(f, stuck.map(|i| units[i].m), stuck, t_end - t_prev, n) * j;
    // J_sec = T J T^-1 with T: y_i -> y_i - x.
    let mut t = DMatrix::<f64>::identity(n, n);
    let mut t_inv = DMatrix::<f64>::identity(n, n);
    for i in (2..n).step_by(2) {
        t[(i, 0)] = -1.0;
        t_inv[(i, 0)] = 1.0;
    }
    let out = t * j * t_inv;
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// The matrix of a smooth segment of length `tau` (module doc): the main mass carrying
/// `carried` (kg, besides `M`), unit `stuck` on its wall, the other units free.
fn flight(
    f: &Forcing,
    carried: Option<f64>,
    stuck: Option<usize>,
    tau: f64,
    n: usize,
) -> DMatrix<f64> {
    let sys = &f.sys;
    let tau = tau.max(0.0);
    let pr = Oscillator::new(sys.M + carried.unwrap_or(0.0), sys.K, sys.C).propagator(tau);
    let mut m = DMatrix::<f64>::identity(n, n);
    let rows = [[pr.xx, pr.xv], [pr.vx, pr.vv]];
    let mut set = |r: usize, row: [f64; 2]| {
        m[(r, r)] = 0.0;
        m[(r, 0)] = row[0];
        m[(r, 1)] = row[1];
    };
    set(0, rows[0]);
    set(1, rows[1]);
    for i in 0..(n - 2) / 2 {
        if stuck == Some(i) {
            set(2 + 2 * i, rows[0]);
            set(3 + 2 * i, rows[1]);
        }
    }
    for i in 0..(n - 2) / 2 {
        if stuck != Some(i) {
            m[(2 + 2 * i, 3 + 2 * i)] = tau;
        }
    }
    m
}

/// One impact of unit `unit` (mass `m`, restitution `e`) at `t` (s).
struct Jump {
    t: f64,
    unit: usize,
    m: f64,
    e: f64,
    before: State,
    after: State,
}

/// The saltation matrix of the impact `h`, a rebound or (`sticks`) the plastic closing of a
/// chatter (module doc); `None` at a graze.
fn saltation(f: &Forcing, h: &Jump, sticks: bool, n: usize) -> Option<DMatrix<f64>> {
    let (big, m, e) = (f.sys.M, h.m, h.e);
    let tot = big + m;
    let (iy, iw) = (2 + 2 * h.unit, 3 + 2 * h.unit);
    let mut g = DMatrix::<f64>::identity(n, n);
    if sticks {
        for r in [1, iw] {
            g[(r, r)] = 0.0;
            g[(r, 1)] = big / tot;
            g[(r, iw)] = m / tot;
        }
        g[(iy, iy)] = 0.0;
        g[(iy, 0)] = 1.0;
    } else {
        g[(1, 1)] = (big - m * e) / tot;
        g[(1, iw)] = m * (1.0 + e) / tot;
        g[(iw, 1)] = big * (1.0 + e) / tot;
        g[(iw, iw)] = (m - big * e) / tot;
    }
    let force = |q: &State| f.F0 * (f.omega * h.t).cos() - f.sys.C * q.v - f.sys.K * q.x;
    // The fields on (x, x', y_i, y_i'); the other units' rows of f+ - G f- vanish.
    let minus = [h.before.v, force(&h.before) / big, h.before.w, 0.0];
    let plus = if sticks {
        // After the closing the pair moves together at the common velocity.
        let common = (big * h.before.v + m * h.before.w) / tot;
        let a = force(&State {
            v: common,
            ..h.before
        }) / tot;
        [common, a, common, a]
    } else {
        [h.after.v, force(&h.after) / big, h.after.w, 0.0]
    };
    let den = minus[2] - minus[0];
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let idx = [0, 1, iy, iw];
    let gf: Vec<f64> = idx
        .iter()
        .map(|&r| idx.iter().zip(&minus).map(|(&c, fm)| g[(r, c)] * fm).sum())
        .collect();
    for (k, &r) in idx.iter().enumerate() {
        let dr = plus[k] - gf[k];
        g[(r, 0)] -= dr / den;
        g[(r, iy)] += dr / den;
    }
    Some(g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::map::tests::table_i;
    use crate::orbits::units::map::{eval, groups, jacobian};

    /// Two and three units of different clearances on impacting motions without sticking: the
    /// exact Jacobian against central differences of the map, to `1e-6` of each column's size
    /// (velocities scaled by `wn`).
    #[test]
    fn exact_jacobian_matches_central_differences() {
        let mut cases = Vec::new();
        let rebounds = table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
        let sticking = table_i(0.02, 0.004, 0.2, 0.1, 0.5, 1.1);
        for (f, n, spread, s, p) in [
            (
                &rebounds,
                2.0,
                0.2,
                vec![-0.0005, 0.05, -0.003, 0.2, -0.004, -0.27],
                1,
            ),
            (
                &rebounds,
                2.0,
                0.2,
                vec![0.002, 0.0, 0.001, 0.1, -0.002, -0.1],
                2,
            ),
            (
                &rebounds,
                3.0,
                0.3,
                vec![0.001, 0.03, 0.002, 0.1, -0.001, -0.2, 0.0, 0.15],
                1,
            ),
            (
                &sticking,
                2.0,
                0.2,
                vec![0.001, 0.1, 0.001, 0.0, -0.001, 0.05],
                1,
            ),
            (
                &sticking,
                2.0,
                0.5,
                vec![0.0, 0.1, 0.0005, 0.0, -0.001, 0.1],
                1,
            ),
        ] {
            let mut f = f.clone();
            f.sys.units = n;
            f.sys.d_spread = spread;
            cases.push((f, s, p));
        }
        let (mut checked, mut stuck) = (0, 0);
        let mut worst: f64 = 0.0;
        for (f, s, p) in cases {
            let (base, exact) = eval_exact(&f, &s, p);
            assert_eq!(base.outcome, Outcome::Ok);
            let Some(j) = exact else { continue };
            assert!(base.impacts >= 2, "{s:?}: {} impacts", base.impacts);
            let g = groups(&f, &s);
            let Some(fd) = jacobian(&f, &s, p, &eval(&f, &s, p), &g) else {
                continue;
            };
            let wn = f.sys.omega();
            let unit = |r: usize| if r % 2 == 1 { wn } else { 1.0 };
            let n = s.len();
            for c in 0..n {
                let norm = (0..n)
                    .map(|r| (j[(r, c)] / unit(r)).abs() * unit(c))
                    .fold(0.0, f64::max)
                    .max(1e-3);
                for r in 0..n {
                    let err = ((fd[(r, c)] - j[(r, c)]) / unit(r)).abs() * unit(c) / norm;
                    worst = worst.max(err);
                    assert!(err < 1e-6, "{s:?} p = {p}: ({r}, {c}) {err:e}");
                }
            }
            checked += 1;
            stuck += usize::from(base.sticks > 0);
        }
        eprintln!(
            "exact against central differences: worst {worst:e}, {checked} motions, {stuck} sticking"
        );
        assert!(checked >= 3, "only {checked} motions checked");
        assert!(stuck >= 1, "no sticking motion checked");
    }
}
