//! Periodic orbits of several units by shooting: Newton on `P^p(s) - s = 0` in the `2 + 2N`
//! section dimensions of [`super::map`], the Floquet multipliers and stability.
//!
//! # Newton
//! The units in step at the start form groups ([`super::map::groups`]); the map keeps them in
//! step, so Newton works on the reduced state `r = (x, x', z_g, y_g')` of dimension `2 + 2G`:
//! `r_{k+1} = r_k - (J_k - I)^{-1} (P^p(r_k) - r_k)`, `J_k` the reduced Jacobian: the exact one
//! ([`super::exact`]) where it applies (units all distinct, impacts one unit at a time, no
//! sticking), else central differences of the map ([`super::map::jacobian`]). A step that would put a unit outside its cavity is
//! shortened to keep every `|z_g| <= d_g / 2`. It stops with the same typed
//! [`Termination`] as one unit's shooting ([`crate::orbits::shoot`]): converged when the
//! residual `|P^p(s) - s|` (the section norm of [`super::map::distance`], m) is at most
//! [`Newton::tol`] times the scale `L` (default `1e-10`), after at most [`Newton::max_iter`]
//! iterations.
//!
//! # Stability
//! The Floquet multipliers are the eigenvalues of the reduced monodromy matrix at the fixed
//! point; an impacting orbit is `stable` when every `|lambda| < 1`. With all units distinct the
//! reduced matrix is the full one, `2 + 2N` multipliers. With `k` identical units in step it has
//! the group's two multipliers where the full one would have `2k`: the other `2 (k - 1)` are the
//! units' relative motions, across which the map is not differentiable (module doc of
//! [`super::map`]); they are not reported (`relative_modes` counts them). A group that makes no
//! impact over the orbit (at rest in its cavity while the others rattle) flies freely: its
//! `y'` row of the monodromy matrix is a unit row to [`FREE_ROW_TOL`], and it contributes two
//! multipliers 1 (its position and velocity drift), which, as for the non-impacting family of
//! one unit, are neutral: the two multipliers nearest 1 per such group are set apart
//! (`free_modes`) and the orbit is `stable` when every other `|lambda| < 1` (the census's
//! start that reached it has settled).

use nalgebra::{DMatrix, DVector};

use super::exact::eval_exact;
use super::map::{
    UnitsEval, complete, distance, eval, expand, groups, half_gaps, jacobian, reduce, scale,
};
use crate::orbits::map::Forcing;
use crate::orbits::shoot::{Newton, Stability, Termination};
use crate::sim::Outcome;

/// The solver's state after each step.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsNewton {
    /// The full section state, `2 + 2N` components.
    pub s: Vec<f64>,
    pub residual: f64,
    pub iterations: u32,
    /// The map at `s`.
    pub last: UnitsEval,
}

/// A periodic orbit of several units.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsOrbit {
    /// The section state at `t = 0 (mod p T_f)`, `2 + 2N` components.
    pub s: Vec<f64>,
    /// Period in forcing periods.
    pub period: u32,
    /// `max |x|` over the orbit (m), exact.
    pub amplitude: f64,
    /// Impact instants over one orbit period.
    pub impacts: u64,
    /// Floquet multipliers `(re, im)` of the reduced monodromy matrix, sorted by decreasing
    /// modulus; empty when they could not be computed ([`multipliers`]; the orbit is then
    /// `Unstable`).
    pub multipliers: Vec<(f64, f64)>,
    pub stability: Stability,
    /// The units in step, by group (module doc).
    pub groups: Vec<Vec<usize>>,
    /// Multipliers of relative motions of units in step, not reported: `2 (N - G)`.
    pub relative_modes: usize,
    /// Multipliers of the groups that make no impact over the orbit (each flies freely in its
    /// cavity: its `y'` row of the monodromy matrix is a unit row), two per group, equal to 1
    /// (the drift of a free mass), not in `multipliers` and not counted in the stability, as the
    /// non-impacting family's are not (module doc).
    pub free_modes: usize,
    /// The reduced monodromy matrix.
    pub monodromy: DMatrix<f64>,
    /// Whether it is the exact one ([`super::exact`]) rather than central differences.
    pub exact: bool,
}

impl UnitsOrbit {
    /// The largest `|lambda|`; NaN when the multipliers could not be computed.
    pub fn multiplier_max(&self) -> f64 {
        if self.multipliers.is_empty() {
            return f64::NAN;
        }
        self.multipliers
            .iter()
            .map(|&(re, im)| re.hypot(im))
            .fold(0.0, f64::max)
    }

    /// Impacts per forcing period.
    pub fn impacts_per_period(&self) -> f64 {
        self.impacts as f64 / self.period as f64
    }
}

/// The reduced Jacobian of `P^p` at `s` on the groups `g` (`base` is the map at `s`): the
/// exact one when every group is one unit and [`eval_exact`] has it, else central differences;
/// with whether it is exact. `None` where neither is defined.
pub fn monodromy(
    f: &Forcing,
    s: &[f64],
    p: u64,
    base: &UnitsEval,
    g: &[Vec<usize>],
) -> Option<(DMatrix<f64>, bool)> {
    if g.iter().all(|grp| grp.len() == 1)
        && let (_, Some(j)) = eval_exact(f, s, p)
    {
        return Some((j, true));
    }
    jacobian(f, s, p, base, g).map(|j| (j, false))
}

/// One Newton step from `state` on the groups `g`. `Err` ends the search.
fn step(
    f: &Forcing,
    p: u64,
    g: &[Vec<usize>],
    state: &UnitsNewton,
) -> Result<UnitsNewton, Termination> {
    let (jac, _) = monodromy(f, &state.s, p, &state.last, g).ok_or(Termination::Singular)?;
    let r0 = reduce(&state.s, g);
    let res = DVector::from_iterator(
        r0.len(),
        reduce(&state.last.end, g)
            .iter()
            .zip(&r0)
            .map(|(a, b)| a - b),
    );
    let a = jac - DMatrix::identity(r0.len(), r0.len());
    let delta = a.lu().solve(&(-res)).ok_or(Termination::Singular)?;
    if delta.iter().any(|v| !v.is_finite()) {
        return Err(Termination::Singular);
    }
    // Keep every unit inside its cavity: shorten the step along its direction.
    let hd = half_gaps(f);
    let mut t: f64 = 1.0;
    for (k, grp) in g.iter().enumerate() {
        let (z, dz) = (r0[2 + 2 * k], delta[2 + 2 * k]);
        let h = hd[grp[0]];
        if (z + dz).abs() > h && dz != 0.0 {
            t = t.min(((h.copysign(z + dz) - z) / dz).clamp(0.0, 1.0));
        }
    }
    let r: Vec<f64> = r0
        .iter()
        .zip(delta.iter())
        .map(|(a, d)| a + t * d)
        .collect();
    let s = expand(&r, g, state.s.len() / 2 - 1);
    let last = eval(f, &s, p);
    if last.outcome != Outcome::Ok {
        return Err(Termination::Simulator(last.outcome));
    }
    Ok(UnitsNewton {
        residual: distance(f, &last.end, &s),
        s,
        iterations: state.iterations + 1,
        last,
    })
}

/// Newton on `P^p(s) - s = 0` from `s0` (`2 + 2N` components; read as
/// [`super::map::complete`]s), the units in step at `s0` kept in step. Returns how it ended and the last state.
pub fn solve(
    f: &Forcing,
    p: u64,
    s0: &[f64],
    newton: &Newton,
) -> (Termination, Option<UnitsNewton>) {
    let s0 = &complete(f, s0);
    let g = groups(f, s0);
    let last = eval(f, s0, p);
    if last.outcome != Outcome::Ok {
        return (Termination::Simulator(last.outcome), None);
    }
    let mut state = UnitsNewton {
        s: s0.to_vec(),
        residual: distance(f, &last.end, s0),
        iterations: 0,
        last,
    };
    loop {
        if state.residual <= newton.tol * scale(f, &state.s) {
            let done = Termination::Converged {
                residual: state.residual,
                iterations: state.iterations,
            };
            return (done, Some(state));
        }
        if state.iterations >= newton.max_iter {
            let t = Termination::MaxIterations {
                residual: state.residual,
            };
            return (t, Some(state));
        }
        match step(f, p, &g, &state) {
            Ok(next) => state = next,
            Err(t) => return (t, Some(state)),
        }
    }
}

/// Iterations the Schur decomposition of [`multipliers`] may take per row of the matrix:
/// LAPACK's QR iteration allows 30 per eigenvalue; twice that before it gives up.
pub const SCHUR_ITER_PER_ROW: usize = 60;

/// Eigenvalues of `m`, sorted by decreasing modulus: the real Schur form `m = Q T Q^T` by
/// nalgebra's shifted QR iteration, to `f64::EPSILON`, capped at [`SCHUR_ITER_PER_ROW`] times the
/// dimension. `None` when it does not converge within the cap or `m` is not finite (issue 68:
/// `complex_eigenvalues()`, which iterates without a cap, looped forever on the monodromy of 8
/// units with spread clearances); the caller then treats the orbit as not shown stable.
pub fn multipliers(m: &DMatrix<f64>) -> Option<Vec<(f64, f64)>> {
    if m.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let cap = SCHUR_ITER_PER_ROW * m.nrows().max(1);
    let schur = nalgebra::linalg::Schur::try_new(m.clone(), f64::EPSILON, cap)?;
    let mut ev: Vec<(f64, f64)> = schur
        .complex_eigenvalues()
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    if ev.iter().any(|z| !(z.0.is_finite() && z.1.is_finite())) {
        return None;
    }
    ev.sort_by(|x, y| y.0.hypot(y.1).total_cmp(&x.0.hypot(x.1)));
    Some(ev)
}

/// The orbit at a converged fixed point `state` of `P^p`: its minimal period (a divisor of `p`
/// whose map already closes to `1e3` times Newton's tolerance), multipliers and stability.
/// `None` when it does not impact, or the Jacobian is undefined there.
pub fn orbit_at(f: &Forcing, p: u64, state: &UnitsNewton, newton: &Newton) -> Option<UnitsOrbit> {
    if state.last.impacts == 0 {
        return None;
    }
    let tol = 1e3 * newton.tol * scale(f, &state.s);
    let (mut best, mut period) = (state.last.clone(), p);
    for q in (1..p).filter(|q| p.is_multiple_of(*q)) {
        let e = eval(f, &state.s, q);
        if e.outcome == Outcome::Ok && distance(f, &e.end, &state.s) <= tol {
            (best, period) = (e, q);
            break;
        }
    }
    let g = groups(f, &state.s);
    let (mono, exact) = monodromy(f, &state.s, period, &best, &g)?;
    // Multipliers that cannot be computed show no stability: the orbit counts as unstable
    // (the census's start then goes on, and ends not settled at worst).
    let free = free_groups(&mono, g.len());
    let (multipliers, stable) = match multipliers(&mono) {
        Some(mu) => {
            let (neutral, rest) = set_apart_free(mu, 2 * free);
            let stable = rest.iter().all(|&(re, im)| re.hypot(im) < 1.0)
                && neutral
                    .iter()
                    .all(|&(re, im)| (re - 1.0).hypot(im) <= FREE_MULTIPLIER_TOL);
            (rest, stable)
        }
        None => (Vec::new(), false),
    };
    Some(UnitsOrbit {
        s: state.s.clone(),
        period: period as u32,
        amplitude: best.amplitude,
        impacts: best.impacts,
        multipliers,
        stability: if stable {
            Stability::Stable
        } else {
            Stability::Unstable
        },
        relative_modes: 2 * (state.s.len() / 2 - 1 - g.len()),
        free_modes: 2 * free,
        groups: g,
        monodromy: mono,
        exact,
    })
}

/// How far (absolute) a row of the reduced monodromy matrix may lie from a unit row for its
/// group to fly freely: an exact Jacobian has it to rounding, central differences of an
/// unchanged velocity to about `1e-11` (module doc of [`super::map`]).
pub const FREE_ROW_TOL: f64 = 1e-9;

/// How far a free group's multipliers may lie from 1 (their Jordan block's eigenvalues split by
/// about the square root of the rounding).
pub const FREE_MULTIPLIER_TOL: f64 = 1e-6;

/// The groups (of `n`) of the reduced monodromy matrix `mono` that make no impact over the
/// orbit: their `y'` row (index `3 + 2k`) is the unit row to [`FREE_ROW_TOL`].
fn free_groups(mono: &DMatrix<f64>, n: usize) -> usize {
    free_mask(mono, n).iter().filter(|&&free| free).count()
}

/// For each of the `n` groups of the reduced monodromy matrix `mono`, whether it makes no
/// impact over the orbit (its `y'` row is the unit row to [`FREE_ROW_TOL`]).
pub fn free_mask(mono: &DMatrix<f64>, n: usize) -> Vec<bool> {
    (0..n)
        .map(|k| {
            let i = 3 + 2 * k;
            i < mono.nrows()
                && (0..mono.ncols()).all(|j| {
                    let unit = if j == i { 1.0 } else { 0.0 };
                    (mono[(i, j)] - unit).abs() <= FREE_ROW_TOL
                })
        })
        .collect()
}

/// Multipliers `(re, im)`.
type Multipliers = Vec<(f64, f64)>;

/// `mu` split into the `k` multipliers nearest 1 and the rest (each in decreasing modulus).
fn set_apart_free(mu: Multipliers, k: usize) -> (Multipliers, Multipliers) {
    let mut by_distance: Vec<usize> = (0..mu.len()).collect();
    by_distance.sort_by(|&a, &b| {
        let d = |i: usize| (mu[i].0 - 1.0).hypot(mu[i].1);
        d(a).total_cmp(&d(b)).then(a.cmp(&b))
    });
    let near: Vec<usize> = by_distance.into_iter().take(k).collect();
    let (mut neutral, mut rest) = (Vec::new(), Vec::new());
    for (i, m) in mu.into_iter().enumerate() {
        if near.contains(&i) {
            neutral.push(m);
        } else {
            rest.push(m);
        }
    }
    (neutral, rest)
}

/// Whether `b` lies on the period-`p` orbit through `a`: within `1e-6` of the scale of one of
/// its `p` sections.
pub fn same_orbit(f: &Forcing, a: &[f64], b: &[f64], p: u64) -> bool {
    let tol = 1e-6 * scale(f, a);
    let mut s = a.to_vec();
    for _ in 0..p.max(1) {
        if distance(f, &s, b) <= tol {
            return true;
        }
        s = eval(f, &s, 1).end;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rotation by 0.3 rad scaled by 0.9 beside a real 0.5: the multipliers `0.9 e^{+-0.3 i}`
    /// and 0.5, largest first.
    #[test]
    fn multipliers_of_a_known_matrix_and_none_for_one_not_finite() {
        let (c, s) = (0.9 * 0.3f64.cos(), 0.9 * 0.3f64.sin());
        let m = DMatrix::from_row_slice(3, 3, &[c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 0.5]);
        let mu = multipliers(&m).expect("multipliers");
        assert_eq!(mu.len(), 3);
        for (re, im) in &mu[..2] {
            assert!((re.hypot(*im) - 0.9).abs() < 1e-14);
            assert!((re - c).abs() < 1e-14 && (im.abs() - s).abs() < 1e-14);
        }
        assert!((mu[2].0 - 0.5).abs() < 1e-14 && mu[2].1 == 0.0);
        let mut bad = m.clone();
        bad[(1, 2)] = f64::NAN;
        assert_eq!(multipliers(&bad), None);
    }

    /// A group at rest in its cavity while the structure rattles (the two-unit orbit at
    /// `r = 1.01` of `configs/multi-unit.toml`): its `y'` row is a unit row, its two
    /// multipliers 1 are set apart, and the orbit is stable on the others.
    #[test]
    fn a_group_that_flies_freely_has_neutral_multipliers() {
        let mut m = DMatrix::<f64>::zeros(4, 4);
        m[(0, 0)] = 0.5;
        m[(0, 1)] = 0.1;
        m[(1, 1)] = 0.4;
        m[(2, 0)] = 0.3;
        m[(2, 2)] = 1.0;
        m[(2, 3)] = 0.09;
        m[(3, 3)] = 1.0;
        assert_eq!(free_groups(&m, 1), 1);
        let mu = multipliers(&m).unwrap();
        let (neutral, rest) = set_apart_free(mu, 2);
        assert_eq!((neutral.len(), rest.len()), (2, 2));
        for (re, im) in &neutral {
            assert!((re - 1.0).hypot(*im) <= FREE_MULTIPLIER_TOL, "{neutral:?}");
        }
        for ((re, im), want) in rest.iter().zip([0.5, 0.4]) {
            assert!((re - want).abs() < 1e-14 && im.abs() < 1e-14, "{rest:?}");
        }
        m[(3, 0)] = 1e-3;
        assert_eq!(free_groups(&m, 1), 0);
    }
}
