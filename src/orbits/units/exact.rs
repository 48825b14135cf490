//! The exact Jacobian of the map of several units on motions whose impacts are one unit at a
//! time and that do not stick (model.md §14; one unit's is [`crate::orbits::map`]).
//!
//! In the coordinates `q = (x, x', y_1, y_1', ..., y_N, y_N')` (m, m/s) the motion between
//! events is linear in the state:
//!
//! * flight over a time `tau`: `(x, x')` by the main mass's state-transition matrix
//!   `Phi_M(tau)` ([`crate::sim::linear::Oscillator::propagator`]; the force adds a term that
//!   does not depend on the state), each unit by `[[1, tau], [0, 1]]`.
//!
//! At the impact of unit `i` at `t*`, on the surface `h_i = y_i - x -+ d_i/2 = 0`
//! (`grad(h_i) = -e_x + e_{y_i}`), a perturbation jumps by the saltation matrix
//!
//! ```text
//! S = G + (f+ - G f-) grad(h_i)^T / (grad(h_i) . f-)
//! ```
//!
//! `G` the Jacobian of the impact law on `(x', y_i')` (eq. 3–4 with `(m_i, e_i)` against the
//! main mass `M`: `x'' = ((M - m_i e_i) x' + m_i (1 + e_i) y_i') / (M + m_i)`,
//! `y_i'' = (M (1 + e_i) x' + (m_i - M e_i) y_i') / (M + m_i)` for the velocities after), the
//! identity elsewhere; `f-`, `f+` the vector fields just before and after
//! (`(x', (F0 cos(omega t) - C x' - K x) / M, y_1', 0, ...)`). The other units' rows of
//! `f+ - G f-` vanish. The monodromy matrix is the product of the flights' matrices and the
//! saltations in time order, turned into section coordinates `(x, x', y_i - x, y_i')`.
//!
//! Motions where two units hit at one instant (the simultaneous impact law is not
//! differentiable across the set where they do, [`super::map`]'s module doc), where a unit
//! sticks, or with a graze (`grad(h) . f- = 0`) have no exact Jacobian here (`None`): the
//! caller takes central differences ([`super::map::jacobian`]).

use nalgebra::DMatrix;

use super::map::{UnitsEval, eval_probe};
use crate::orbits::map::Forcing;
use crate::sim::linear::Oscillator;
use crate::sim::{Outcome, Probe, State, Wall};

/// One impact of one unit: time (s), unit, state before and after.
#[derive(Clone, Copy, Debug)]
struct Hit {
    t: f64,
    unit: usize,
    before: State,
    after: State,
}

/// The impacts of one evaluation; `unsupported` when something happened this module does not
/// linearise (a stick or a separation).
#[derive(Default)]
struct Recorder {
    hits: Vec<Hit>,
    unsupported: bool,
}

impl Probe for Recorder {
    fn impact_of(&mut self, t: f64, unit: usize, _wall: Wall, before: &State, after: &State) {
        self.hits.push(Hit {
            t,
            unit,
            before: *before,
            after: *after,
        });
    }
    fn stick(&mut self, _t: f64, _wall: Wall, _state: &State) {
        self.unsupported = true;
    }
    fn separate(&mut self, _t: f64, _wall: Wall, _state: &State) {
        self.unsupported = true;
    }
}

/// Evaluates `P^p(s)` and its exact Jacobian in section coordinates (`(2 + 2N)` square);
/// `None` for the Jacobian where the module doc says so, or when the map failed.
pub fn eval_exact(f: &Forcing, s: &[f64], p: u64) -> (UnitsEval, Option<DMatrix<f64>>) {
    let mut rec = Recorder::default();
    let e = eval_probe(f, s, p, &mut rec);
    let simultaneous = rec.hits.windows(2).any(|w| w[0].t == w[1].t);
    if e.outcome != Outcome::Ok || rec.unsupported || simultaneous || f.sys.m == 0.0 {
        return (e, None);
    }
    let jac = linearise(f, &rec.hits, f.period() * p as f64, e.end.len());
    (e, jac)
}

/// The monodromy matrix in section coordinates from the recorded impacts (module doc).
fn linearise(f: &Forcing, hits: &[Hit], t_end: f64, n: usize) -> Option<DMatrix<f64>> {
    let sys = &f.sys;
    let osc = Oscillator::new(sys.M, sys.K, sys.C);
    let units = sys.unit_list();
    let mut j = DMatrix::<f64>::identity(n, n);
    let mut t_prev = 0.0;
    let flight = |tau: f64| {
        let tau = tau.max(0.0);
        let pr = osc.propagator(tau);
        let mut m = DMatrix::<f64>::identity(n, n);
        m[(0, 0)] = pr.xx;
        m[(0, 1)] = pr.xv;
        m[(1, 0)] = pr.vx;
        m[(1, 1)] = pr.vv;
        for i in (2..n).step_by(2) {
            m[(i, i + 1)] = tau;
        }
        m
    };
    for h in hits {
        j = flight(h.t - t_prev) * j;
        t_prev = h.t;
        let u = units.get(h.unit)?;
        j = saltation(f, h, u.m, u.e, n)? * j;
    }
    j = flight(t_end - t_prev) * j;
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

/// The saltation matrix of unit `i`'s impact `h` (module doc); `None` at a graze.
fn saltation(f: &Forcing, h: &Hit, m: f64, e: f64, n: usize) -> Option<DMatrix<f64>> {
    let big = f.sys.M;
    let tot = big + m;
    let (iy, iw) = (2 + 2 * h.unit, 3 + 2 * h.unit);
    let mut g = DMatrix::<f64>::identity(n, n);
    g[(1, 1)] = (big - m * e) / tot;
    g[(1, iw)] = m * (1.0 + e) / tot;
    g[(iw, 1)] = big * (1.0 + e) / tot;
    g[(iw, iw)] = (m - big * e) / tot;
    let accel = |q: &State| (f.F0 * (f.omega * h.t).cos() - f.sys.C * q.v - f.sys.K * q.x) / big;
    // Only the main mass's and unit i's components of f+ - G f- can differ from zero.
    let (fm_x, fm_v, fm_y, fm_w) = (h.before.v, accel(&h.before), h.before.w, 0.0);
    let (fp_x, fp_v, fp_y, fp_w) = (h.after.v, accel(&h.after), h.after.w, 0.0);
    let den = fm_y - fm_x;
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    // G f- on the rows that differ: x and y_i rows are the identity's.
    let gf_v = g[(1, 1)] * fm_v + g[(1, iw)] * fm_w;
    let gf_w = g[(iw, 1)] * fm_v + g[(iw, iw)] * fm_w;
    let diff = [
        (0, fp_x - fm_x),
        (1, fp_v - gf_v),
        (iy, fp_y - fm_y),
        (iw, fp_w - gf_w),
    ];
    for (r, dr) in diff {
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
        for (n, spread, s, p) in [
            (2.0, 0.2, vec![-0.0005, 0.05, -0.003, 0.2, -0.004, -0.27], 1),
            (2.0, 0.2, vec![0.002, 0.0, 0.001, 0.1, -0.002, -0.1], 2),
            (
                3.0,
                0.3,
                vec![0.001, 0.03, 0.002, 0.1, -0.001, -0.2, 0.0, 0.15],
                1,
            ),
        ] {
            let mut f = table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
            f.sys.units = n;
            f.sys.d_spread = spread;
            cases.push((f, s, p));
        }
        let mut checked = 0;
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
        }
        eprintln!("exact against central differences: worst {worst:e}");
        assert!(checked >= 2, "only {checked} motions checked");
    }
}
