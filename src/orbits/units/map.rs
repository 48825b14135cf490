//! The stroboscopic map of several damper units (model.md §14) and its Jacobian by central
//! differences, for the motions the exact Jacobian ([`super::exact`]) does not cover.
//!
//! # The map
//! With `N` units the section state at `t = k T_f` (`T_f = 2 pi / omega`) has `2 + 2N`
//! components
//!
//! ```text
//! s = (x, x', z_1, y_1', ..., z_N, y_N')      z_i = y_i - x,   |z_i| <= d_i / 2
//! ```
//!
//! (m, m/s; unit `i` of [`crate::model::System::unit_list`], clearance `d_i`). The force is
//! `T_f`-periodic, so `p` forcing periods later the state is a function of `s` alone, `P^p(s)`,
//! and a period-`p` steady state is a fixed point `P^p(s) = s`. [`eval`] computes `P^p(s)`
//! with the exact event-driven simulator of several units
//! ([`crate::sim::harmonic::simulate_harmonic_units`]: each unit started at its own
//! `(y_i, y_i')`, the simultaneous impact law, sticking per unit). With `N = 1` the map is
//! [`crate::orbits::map::eval`]'s, bit for bit.
//!
//! # Units in step
//! Units with the same mass, clearance and restitution whose section states are equal bit for
//! bit stay in step: they reach their walls at the same instant, and the simultaneous impact law
//! makes them one unit of their total mass (model.md §14). Across that set the map is not
//! differentiable: moved apart by `h`, they hit one after the other, and two impacts in turn
//! change the main mass's velocity by a different amount than one simultaneous impact (by a
//! fraction of order `m_i / M` of the relative velocity, however small `h`). So the Jacobian is
//! taken on the set where units in step stay in step: the units are gathered into groups
//! ([`groups`]), and the reduced state `(x, x', z_g, y_g' for each group g)` is differentiated,
//! each group's units moved together. With units all distinct the groups are the units and the
//! Jacobian is the full `(2 + 2N) x (2 + 2N)` one.
//!
//! # The Jacobian
//! Column `k` of `dP^p/ds` is the central difference
//! `(P^p(s + h_k e_k) - P^p(s - h_k e_k)) / (2 h_k)` with `h_k = H L` for a displacement and
//! `h_k = H L wn` for a velocity, `L` the orbit's scale ([`scale`], about its amplitude),
//! `wn = sqrt(K/M)` and `H = 1e-5` ([`STEP`]). The map is evaluated to about `delta = 1e-12`
//! relative (the event tolerance: impact times to `1e-12` of the period), so a difference of
//! step `H` carries a rounding error of about `delta / H = 1e-7` relative, and its truncation
//! error is of order `H^2 = 1e-10` times the map's curvature relative to `L`: `H = 1e-5` is near
//! the optimum `delta^(1/3) = 1e-4`, kept smaller so that a step seldom crosses a grazing
//! contact. A difference whose two evaluations do not make the same impacts as the base point
//! (the step crossed a grazing, or a change of the impact sequence) leaves the Jacobian
//! undefined (`None`): there the map is not differentiable. The fixed point Newton finds is that
//! of the exact map; a Jacobian error of this size only slows the iteration (each step then
//! shrinks the error by about that relative size instead of squaring it).

use nalgebra::DMatrix;

use crate::model::System;
use crate::orbits::map::Forcing;
use crate::sim::harmonic::simulate_harmonic_units;
use crate::sim::{NoProbe, Outcome, Probe, Request};

/// Relative step of the central differences (module doc).
pub const STEP: f64 = 1e-5;

/// What one evaluation of `P^p` found.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsEval {
    /// The simulator's outcome; every other field is meaningful only when `Ok`.
    pub outcome: Outcome,
    /// `P^p(s)`, `2 + 2N` components (module doc).
    pub end: Vec<f64>,
    /// `max |x|` over the `p` periods (m), exact.
    pub amplitude: f64,
    /// Impact instants over the `p` periods (a simultaneous impact of several units is one).
    pub impacts: u64,
    /// Sticking phases begun over the `p` periods.
    pub sticks: u64,
}

/// The number of units `N` of `f`'s system.
pub fn unit_count(f: &Forcing) -> usize {
    f.sys.unit_count().max(1)
}

/// The section's dimension `2 + 2N`.
pub fn dim(f: &Forcing) -> usize {
    2 + 2 * unit_count(f)
}

/// The section state of the system's own initial state: every unit at `(y0, w0)`, in step.
pub fn initial(f: &Forcing) -> Vec<f64> {
    let sys = &f.sys;
    let mut s = vec![sys.x0, sys.v0];
    for _ in 0..unit_count(f) {
        s.extend([sys.y0 - sys.x0, sys.w0]);
    }
    s
}

/// Half clearances `d_i / 2` of the units (m).
pub fn half_gaps(f: &Forcing) -> Vec<f64> {
    f.sys.unit_list().iter().map(|u| 0.5 * u.d).collect()
}

/// The section norm (m): `sqrt(dx^2 + (dx'/wn)^2 + sum_i (dz_i^2 + (dy_i'/wn)^2))`,
/// `wn = sqrt(K/M)`; for one unit [`crate::orbits::shoot::distance`].
pub fn distance(f: &Forcing, a: &[f64], b: &[f64]) -> f64 {
    let wn = f.sys.omega();
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(k, (p, q))| {
            let d = if k % 2 == 1 { (p - q) / wn } else { p - q };
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// The orbit's scale `L = max(|x|, |x'|/omega, d/1000)` (m), as for one unit.
pub fn scale(f: &Forcing, s: &[f64]) -> f64 {
    s[0].abs().max(s[1].abs() / f.omega).max(1e-3 * f.sys.d)
}

/// `s` as a full section state of [`dim`] components: a shorter one completed as [`eval`]
/// reads it (missing units in step with unit 1, a missing unit 1 at `(0, 0)`), a longer one cut.
pub fn complete(f: &Forcing, s: &[f64]) -> Vec<f64> {
    let n = unit_count(f);
    let at = |k: usize| s.get(k).copied().unwrap_or(0.0);
    let mut out = vec![at(0), at(1)];
    for i in 0..n {
        let k = if 3 + 2 * i < s.len() { i } else { 0 };
        out.extend([at(2 + 2 * k), at(3 + 2 * k)]);
    }
    out
}

/// Evaluates `P^p(s)` (`p >= 1` forcing periods from `t = 0`). Each `z_i` is clamped into its
/// cavity. `s` shorter than [`dim`] is read as far as it goes (missing units start in step with
/// unit 1). Pure.
pub fn eval(f: &Forcing, s: &[f64], p: u64) -> UnitsEval {
    eval_probe(f, s, p, &mut NoProbe)
}

/// [`eval`] with the simulator's events handed to `probe`.
pub fn eval_probe<P: Probe>(f: &Forcing, s: &[f64], p: u64, probe: &mut P) -> UnitsEval {
    let s = complete(f, s);
    let (x, v) = (s[0], s[1]);
    let starts: Vec<(f64, f64)> = half_gaps(f)
        .iter()
        .enumerate()
        .map(|(i, hd)| (x + s[2 + 2 * i].clamp(-hd, *hd), s[3 + 2 * i]))
        .collect();
    let sys = System {
        x0: x,
        v0: v,
        y0: starts[0].0,
        w0: starts[0].1,
        ..f.sys
    };
    let (rec, units) = simulate_harmonic_units(
        &sys,
        &f.settings,
        &Request::default(),
        &f.scene(p),
        &starts,
        probe,
    );
    // A massless damper does not act on the main mass: its state is no part of the motion and
    // the section keeps it at zero, as for one unit.
    let alone = sys.m == 0.0;
    let mut end = vec![rec.end.x, rec.end.v];
    for &(y, w) in &units {
        if alone {
            end.extend([0.0, 0.0]);
        } else {
            end.extend([y - rec.end.x, w]);
        }
    }
    UnitsEval {
        outcome: rec.outcome,
        end,
        amplitude: rec.amplitude,
        impacts: rec.impacts,
        sticks: rec.sticks,
    }
}

/// The map of several units one period at a time, for a design-life measurement
/// ([`crate::orbits::life::LifeRun`]): [`eval`] over one period, every extremum located (no
/// floor: the event finder of several units has none).
#[derive(Clone, Debug)]
pub struct UnitsMap(pub Forcing);

impl crate::orbits::life::PeriodMap for UnitsMap {
    type State = Vec<f64>;
    const FLOORS: bool = false;

    fn period(&self, s: &Vec<f64>, _floor: f64) -> Option<(f64, Vec<f64>)> {
        let e = eval(&self.0, s, 1);
        (e.outcome == Outcome::Ok).then_some((e.amplitude, e.end))
    }

    fn run(&self, s: &Vec<f64>, p: u64) -> Option<Vec<f64>> {
        let e = eval(&self.0, s, p);
        (e.outcome == Outcome::Ok).then_some(e.end)
    }
}

/// The groups of units in step at `s` (module doc): units with the same mass, clearance and
/// restitution whose `(z_i, y_i')` are equal bit for bit, each group listed by its unit indices
/// in increasing order, groups in the order of their first unit. `s` is read as [`complete`]s.
pub fn groups(f: &Forcing, s: &[f64]) -> Vec<Vec<usize>> {
    let s = complete(f, s);
    let units = f.sys.unit_list();
    let key = |i: usize| {
        let u = &units[i];
        [u.m, u.d, u.e, s[2 + 2 * i], s[3 + 2 * i]].map(f64::to_bits)
    };
    let mut out: Vec<Vec<usize>> = Vec::new();
    for i in 0..units.len() {
        match out.iter_mut().find(|g| key(g[0]) == key(i)) {
            Some(g) => g.push(i),
            None => out.push(vec![i]),
        }
    }
    out
}

/// The reduced state of `s` on the groups: `(x, x', z_g, y_g')`, each group's first unit's.
pub fn reduce(s: &[f64], groups: &[Vec<usize>]) -> Vec<f64> {
    let mut r = vec![s[0], s[1]];
    for g in groups {
        r.extend([s[2 + 2 * g[0]], s[3 + 2 * g[0]]]);
    }
    r
}

/// The full state of a reduced one: every unit of a group at the group's `(z, y')`.
pub fn expand(r: &[f64], groups: &[Vec<usize>], n: usize) -> Vec<f64> {
    let mut s = vec![0.0; 2 + 2 * n];
    s[0] = r[0];
    s[1] = r[1];
    for (k, g) in groups.iter().enumerate() {
        for &i in g {
            s[2 + 2 * i] = r[2 + 2 * k];
            s[3 + 2 * i] = r[3 + 2 * k];
        }
    }
    s
}

/// The Jacobian `dP^p/dr` of the reduced map on `groups` at `s` (module doc), `(2 + 2G)`
/// square, by central differences; `base` is `eval(f, s, p)`. `None` where the map is not
/// differentiable (a step changes the impacts) or an evaluation fails.
pub fn jacobian(
    f: &Forcing,
    s: &[f64],
    p: u64,
    base: &UnitsEval,
    groups: &[Vec<usize>],
) -> Option<DMatrix<f64>> {
    let n = unit_count(f);
    let s = &complete(f, s);
    let r0 = reduce(s, groups);
    let dim = r0.len();
    let l = scale(f, s);
    let wn = f.sys.omega();
    let mut jac = DMatrix::zeros(dim, dim);
    for c in 0..dim {
        let h = if c % 2 == 1 { STEP * l * wn } else { STEP * l };
        let moved = |sign: f64| {
            let mut r = r0.clone();
            r[c] += sign * h;
            eval(f, &expand(&r, groups, n), p)
        };
        let (ep, em) = (moved(1.0), moved(-1.0));
        for e in [&ep, &em] {
            if e.outcome != Outcome::Ok || e.impacts != base.impacts || e.sticks != base.sticks {
                return None;
            }
        }
        let (rp, rm) = (reduce(&ep.end, groups), reduce(&em.end, groups));
        for r in 0..dim {
            jac[(r, c)] = (rp[r] - rm[r]) / (2.0 * h);
        }
    }
    jac.iter().all(|v| v.is_finite()).then_some(jac)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::map::tests::table_i;

    /// With one unit the map is one unit's map bit for bit, and its central-difference
    /// Jacobian agrees with the exact one (`crate::orbits::map`) to `1e-6` of each column.
    #[test]
    fn one_unit_is_the_one_unit_map() {
        for (f, s, p) in [
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
        ] {
            let exact = crate::orbits::map::eval(&f, &s, p, true);
            let ours = eval(&f, &s, p);
            assert_eq!(ours.outcome, Outcome::Ok);
            for k in 0..4 {
                assert_eq!(ours.end[k].to_bits(), exact.end[k].to_bits(), "{k}");
            }
            assert_eq!(ours.impacts, exact.impacts);
            let j = exact.jacobian.unwrap();
            let g = groups(&f, &s);
            let fd = jacobian(&f, &s, p, &ours, &g).unwrap();
            let wn = f.sys.omega();
            let unit = |r: usize| if r % 2 == 1 { wn } else { 1.0 };
            for c in 0..4 {
                let norm = (0..4)
                    .map(|r| (j[r][c] / unit(r)).abs())
                    .fold(0.0, f64::max)
                    .max(1e-3);
                for r in 0..4 {
                    let err = ((fd[(r, c)] - j[r][c]) / unit(r)).abs() / norm;
                    assert!(err < 1e-6, "{s:?} p = {p}: ({r}, {c}) {err:e}");
                }
            }
        }
    }

    #[test]
    fn groups_gather_identical_units_in_step() {
        let mut f = table_i(0.02, 0.01, 0.8, 0.1, 0.3, 1.0);
        f.sys.units = 3.0;
        let s = [0.001, 0.0, 0.002, 0.1, 0.001, 0.0, 0.002, 0.1];
        assert_eq!(groups(&f, &s), vec![vec![0, 2], vec![1]]);
        let r = reduce(&s, &groups(&f, &s));
        assert_eq!(r, vec![0.001, 0.0, 0.002, 0.1, 0.001, 0.0]);
        assert_eq!(expand(&r, &groups(&f, &s), 3), s.to_vec());
        f.sys.d_spread = 0.1;
        assert_eq!(groups(&f, &s).len(), 3);
        // A short state is completed with units in step with unit 1, a long one cut.
        let short = complete(&f, &[0.001, 0.0, 0.002, 0.1]);
        assert_eq!(short, vec![0.001, 0.0, 0.002, 0.1, 0.002, 0.1, 0.002, 0.1]);
        assert_eq!(complete(&f, &[]), vec![0.0; 8]);
        assert_eq!(complete(&f, &[1.0; 12]).len(), 8);
        assert_eq!(eval(&f, &[0.001], 1).end.len(), 8);
    }
}
