//! A label located between two points of a branch (the module doc of [`super`], and
//! [`crate::orbits::locate`]), and the other branch followed from a located branch point.

use super::branch::{BranchPoint, ContSettings, Curve, V5, point, tangent};
use crate::orbits::label::Label;
use crate::orbits::locate::{self, OnBranch, test_function};
use crate::orbits::map::Forcing;
use crate::orbits::shoot::Orbit;

/// `label` located between the points `here` and `next` (the step from `here` along `t` of
/// length `h` found `next`), as a branch point at the located parameter
/// ([`crate::orbits::locate`]); `None` when it cannot be solved there or falls outside the swept
/// range.
#[allow(clippy::too_many_arguments)]
pub(super) fn locate_between(
    curve: &mut Curve,
    f: &Forcing,
    here: &OnBranch,
    next: &OnBranch,
    t: &V5,
    h: f64,
    label: Label,
    settings: &ContSettings,
) -> Option<(BranchPoint, OnBranch)> {
    let periods0 = curve.periods;
    let impacts_left = here.eval.impacts;
    let phi = |p: &OnBranch| test_function(label, p, &|a| tangent(a, t), impacts_left);
    let ends = (phi(here), phi(next));
    let at = |sigma: f64| {
        let (u, a, eval, _) = curve.correct(&(here.u + t * sigma), t)?;
        Some(OnBranch { u, a, eval })
    };
    let found = if label == Label::GR {
        // The side with more impacts has the grazing contact as an impact.
        let rough = if here.eval.impacts > next.eval.impacts {
            ends.0
        } else {
            ends.1
        };
        locate::solve_grazing(h, ends, rough, at, phi)
    } else {
        locate::solve(label, h, ends, at, phi)
    };
    curve.periods_locating += curve.periods - periods0;
    let p = found?;
    let row = located_row(curve, f, &p, label, settings)?;
    Some((row, p))
}

/// The row of a located point `p` of `label` ([`locate_between`],
/// [`super::corners::end_of_steps`]): its orbit by Newton, kept when it is inside the range and
/// its bifurcation is there to [`LOCATED_TOL`]. Counts it in `curve.located`.
pub(super) fn located_row(
    curve: &mut Curve,
    f: &Forcing,
    p: &OnBranch,
    label: Label,
    settings: &ContSettings,
) -> Option<BranchPoint> {
    let (_, lambda) = curve.unscale(&p.u);
    if lambda < settings.range.0 || lambda > settings.range.1 {
        return None;
    }
    let (fl, orb) = curve.orbit(f, &p.u, p.eval.clone())?;
    // The root is the bifurcation only where its multiplier is there: a fold or a branch
    // point of a smooth map has one at +1, a doubling at -1, a torus a pair on the unit
    // circle. Where the test function changed sign through a jump or a corner (the map not
    // smooth: a sticking phase begins or ends), the point is not located.
    if locate::multiplier_test(label, &orb.multipliers) > LOCATED_TOL {
        return None;
    }
    // A grazing is located where the flight on the smooth side touches the wall: its gap within
    // `LOCATED_TOL` of the half clearance (an impact count that changes with a finite approach
    // speed is a jump of the map, not a grazing).
    if label == Label::GR
        && !crate::orbits::graze::flight_gap(&fl, &orb.s, curve.p)
            .is_some_and(|g| g <= LOCATED_TOL * fl.half_gap())
    {
        return None;
    }
    curve.located += 1;
    Some(BranchPoint {
        located: true,
        ..point(&fl, &orb, label)
    })
}

/// The other branch through a located branch point `at` (tangent `t` of the branch followed):
/// at a branch point the extended Jacobian `[J - I | dF/dlambda]` loses rank, so its null space
/// is two-dimensional; the direction in it orthogonal to `t` is the other branch's. A step of
/// `0.02` in scaled arclength along it, each way, is corrected on the hyperplane normal to it;
/// the first that converges to an impacting orbit is returned (at its own parameter).
pub(super) fn switch_at_branch_point(
    curve: &mut Curve,
    f: &Forcing,
    at: &OnBranch,
    t: &V5,
) -> Option<(Forcing, Orbit)> {
    let ata = at.a.transpose() * at.a;
    let eig = ata.symmetric_eigen();
    let mut order: Vec<usize> = (0..5).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let v = order[..2]
        .iter()
        .map(|&i| {
            let n: V5 = eig.eigenvectors.column(i).into();
            n - t * t.dot(&n)
        })
        .max_by(|x, y| x.norm().total_cmp(&y.norm()))?;
    let v = v / v.norm().max(f64::MIN_POSITIVE);
    for sign in [1.0, -1.0] {
        let dir = v * sign;
        let Some((u, _, e, _)) = curve.correct(&(at.u + dir * 0.02), &dir) else {
            continue;
        };
        if e.impacts == 0 {
            continue;
        }
        if let Some(found) = curve.orbit(f, &u, e) {
            return Some(found);
        }
    }
    None
}

/// How near its critical value (+1, -1, the unit circle) the multiplier of a located point
/// must be ([`locate::multiplier_test`]).
pub const LOCATED_TOL: f64 = 1e-8;
