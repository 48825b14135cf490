//! The periodic branches of a curve of several damper units (docs/model.md §14), as rows of the
//! `branches` table: every stable periodic impacting attractor the sweep stored along the curve
//! is continued in the frequency ratio `r` over the curve's range
//! ([`super::units::continuation`]), once: a stored orbit that lies on a branch already followed
//! ([`covers`]) seeds none. At most [`MAX_BRANCHES`] branches per curve, as for one unit
//! ([`super::response`]).
//!
//! # The rows
//! The same columns as one unit's, read for `2 + 2N` section dimensions:
//! * `multiplier_max` and `mu1..mu4` are the largest multipliers of the reduced monodromy
//!   matrix by modulus (the relative modes of units in step and the free modes of a group at
//!   rest are set apart, as in the census: [`super::units::shoot`]); `NaN` past the ones it has;
//! * `SN`, `PD`, `NS` and `BP` are located between two points by bisection
//!   ([`super::units::continuation`]), `located = true`; a grazing (`GR`), and a label whose
//!   bisection failed, sits on the first point past the change, `located = false`. No
//!   bifurcation curve starts from them (the curves over the design space cover one unit);
//! * `min_impact_speed` is `NaN` (not computed for several units) and `grazing_outcome` is empty:
//!   a branch that reaches a grazing ends there (`grazing_end`);
//! * the section columns are the structure's and the first unit's, as `attractors`' are
//!   ([`section_of`]).
//!
//! No non-impacting family is drawn, and a curve along `F0` has no branches: the continuation
//! of several units moves `r` only.

use super::attractors::section_of;
use super::continuation::Param;
use super::map::Forcing;
use super::response::{BranchRow, MAX_BRANCHES, curve_steps};
use super::shoot::{Newton, Stability, Termination};
use super::units::continuation::{
    UnitsBranch, UnitsBranchPoint, UnitsContSettings, follow_units, shoot_holding,
};
use super::units::map::{distance, eval, scale};
use super::units::shoot::{UnitsOrbit, free_mask, orbit_at, same_orbit, solve};

/// The stable periodic impacting orbit of several units at `f` whose whole section state `s`
/// (`2 + 2N` components) a stored attractor gives, of period `p`: Newton from there (it
/// converges at once: the state is the orbit's to Newton's tolerance) and its multipliers;
/// `None` when it no longer converges to a stable impacting orbit. Pure.
pub fn units_orbit_from_section(f: &Forcing, s: &[f64], p: u32) -> Option<UnitsOrbit> {
    let newton = Newton::default();
    let p = u64::from(p.max(1));
    match solve(f, p, s, &newton) {
        (Termination::Converged { .. }, Some(st)) => {
            orbit_at(f, p, &st, &newton).filter(|o| o.stability == Stability::Stable)
        }
        _ => None,
    }
}

/// The branches of design `design`'s curve along the frequency (`values`: its points as
/// `(design point, r)`) from `seeds`, the stored orbits with their forcing, in the order given;
/// with the forcing periods the continuation simulated. The steps as one unit's: `h0` one
/// frequency step relative to the lowest `r` (at least `1e-3`), `h_min = 1e-6`,
/// `h_max = 0.05`, at most 2,000 points each way. Empty for a curve of one frequency. Pure.
pub fn units_branches(
    design: u64,
    values: &[(u64, f64)],
    seeds: Vec<(Forcing, UnitsOrbit)>,
) -> (Vec<BranchRow>, u64) {
    let Some((lo, hi, h0)) = curve_steps(values) else {
        return (Vec::new(), 0);
    };
    let cont = UnitsContSettings {
        range: (lo, hi),
        h0,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 2000,
    };
    let mut followed: Vec<(Forcing, UnitsBranch)> = Vec::new();
    let mut periods = 0;
    for (f, orbit) in seeds {
        if followed.len() >= MAX_BRANCHES {
            break;
        }
        if followed.iter().any(|(_, b)| covers(b, &f, &orbit)) {
            continue;
        }
        let b = follow_units(&f, &orbit, &cont);
        periods += b.periods;
        followed.push((f, b));
    }
    let mut rows = Vec::new();
    for (i, (f, b)) in followed.iter().enumerate() {
        push_units_branch(&mut rows, f, design, i as u32, b);
    }
    (rows, periods)
}

/// Whether branch `b` passes through `orbit` (a fixed point at `f`): two consecutive points of
/// the branch with the orbit's period and impacts bracket its `r`, and either the branch's
/// amplitude interpolated there is within `1e-3` of the orbit's, or Newton at `f` from the
/// branch's state interpolated there converges to the same orbit ([`same_orbit`]); as
/// [`super::response::covers`] for one unit. Units at rest over `orbit` are put where it has
/// them, held there by Newton ([`shoot_holding`]) and left out of the comparison: where a unit
/// rests does not change the motion.
pub fn covers(b: &UnitsBranch, f: &Forcing, orbit: &UnitsOrbit) -> bool {
    let r = Param::Ratio.get(f);
    let p = u64::from(orbit.period);
    let resting = at_rest(orbit);
    b.points.windows(2).any(|w| {
        let alike = |q: &UnitsBranchPoint| {
            q.orbit.period == orbit.period
                && q.orbit.impacts == orbit.impacts
                && q.orbit.s.len() == orbit.s.len()
        };
        if !alike(&w[0]) || !alike(&w[1]) {
            return false;
        }
        let (lo, hi) = if w[0].r <= w[1].r {
            (&w[0], &w[1])
        } else {
            (&w[1], &w[0])
        };
        if r < lo.r || r > hi.r {
            return false;
        }
        let t = if hi.r > lo.r {
            (r - lo.r) / (hi.r - lo.r)
        } else {
            0.0
        };
        let amp = lo.orbit.amplitude + t * (hi.orbit.amplitude - lo.orbit.amplitude);
        if (amp - orbit.amplitude).abs() <= 1e-3 * orbit.amplitude {
            return true;
        }
        let mut s: Vec<f64> = (lo.orbit.s.iter().zip(&hi.orbit.s))
            .map(|(a, c)| a + t * (c - a))
            .collect();
        // Units at rest over the orbit may rest anywhere their cavities let them: where the
        // orbit has them is where Newton looks.
        for &i in &resting {
            s[2 + 2 * i] = orbit.s[2 + 2 * i];
            s[3 + 2 * i] = orbit.s[3 + 2 * i];
        }
        if resting.is_empty() {
            return matches!(
                solve(f, p, &s, &Newton::default()),
                (Termination::Converged { .. }, Some(st)) if same_orbit(f, &st.s, &orbit.s, p)
            );
        }
        // Shooting on the whole section is singular with units at rest: they are held.
        shoot_holding(f, orbit, &s).is_some_and(|st| same_motion(f, &st, &orbit.s, p, &resting))
    })
}

/// Whether `b` lies on the period-`p` orbit through `a` (as [`same_orbit`]: within `1e-6` of
/// the scale of one of its `p` sections), the units `resting` (at rest over the orbit, where
/// Newton leaves them) left out of the distance.
fn same_motion(f: &Forcing, a: &[f64], b: &[f64], p: u64, resting: &[usize]) -> bool {
    let keep = |s: &[f64]| -> Vec<f64> {
        s.iter()
            .enumerate()
            .filter(|(k, _)| *k < 2 || !resting.contains(&((k - 2) / 2)))
            .map(|(_, v)| *v)
            .collect()
    };
    let tol = 1e-6 * scale(f, a);
    let target = keep(b);
    let mut s = a.to_vec();
    for _ in 0..p.max(1) {
        if distance(f, &keep(&s), &target) <= tol {
            return true;
        }
        s = eval(f, &s, 1).end;
    }
    false
}

/// The units of `orbit` that make no impact over it (their group's row of the monodromy
/// matrix is free, [`free_mask`]).
fn at_rest(orbit: &UnitsOrbit) -> Vec<usize> {
    let g = &orbit.groups;
    if orbit.monodromy.nrows() != 2 + 2 * g.len() {
        return Vec::new();
    }
    let free = free_mask(&orbit.monodromy, g.len());
    g.iter()
        .zip(free)
        .filter(|(_, f)| *f)
        .flat_map(|(units, _)| units.iter().copied())
        .collect()
}

/// The rows of branch `b` (seeded at `f`) of design `design` (module doc).
fn push_units_branch(
    rows: &mut Vec<BranchRow>,
    f: &Forcing,
    design: u64,
    branch: u32,
    b: &UnitsBranch,
) {
    let n = b.points.len();
    for (k, p) in b.points.iter().enumerate() {
        let end = if k == 0 {
            b.ends.0.name()
        } else if k + 1 == n {
            b.ends.1.name()
        } else {
            ""
        };
        let o = &p.orbit;
        let stable = o.stability == Stability::Stable;
        rows.push(BranchRow {
            design,
            branch,
            r: p.r,
            omega: f.at_ratio(p.r).omega,
            F0: f.F0,
            amplitude: o.amplitude,
            period: o.period,
            impacts_per_period: o.impacts_per_period(),
            stable,
            stability: if stable { "stable" } else { "unstable" },
            multiplier_max: o.multiplier_max(),
            multipliers: std::array::from_fn(|i| {
                o.multipliers
                    .get(i)
                    .copied()
                    .unwrap_or((f64::NAN, f64::NAN))
            }),
            min_impact_speed: f64::NAN,
            label: p.label.name(),
            located: p.located,
            end,
            grazing_outcome: "",
            s: section_of(&o.s),
        });
    }
}
