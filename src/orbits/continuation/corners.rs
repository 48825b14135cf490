//! Where the map is not smooth: a corner of a branch (an impact on the section, a grazing)
//! passed or located from its smooth side, an impact's approach speed vanishing (the orbit
//! joins the non-impacting family), and the end of a branch at the swept range.

use super::branch::{BranchPoint, ContSettings, Curve, End, V5, point, tangent};
use super::located::located_row;
use crate::orbits::label::Label;
use crate::orbits::locate::{self, OnBranch};
use crate::orbits::map::{Forcing, eval};
use crate::sim::Outcome;

/// The end of a branch whose steps failed down to the smallest: where the map one step past
/// the last point (at the last predictor `u_pred`) has another impact count than the last
/// point's orbit, the branch ran into a grazing it cannot pass (`grazing_end`). The grazing is
/// then located between the last point and the predictor from the smooth side
/// ([`locate::solve_grazing`]: a trial that fails or has another impact count is past it) and
/// is the branch's last row, `GR`; where that fails the last point is labelled `GR`. Otherwise
/// `step_too_small`.
pub(super) fn end_of_steps(
    curve: &mut Curve,
    f: &Forcing,
    here: &OnBranch,
    u_pred: &V5,
    settings: &ContSettings,
    mut pts: Vec<BranchPoint>,
) -> (Vec<BranchPoint>, End) {
    let (s, lambda) = curve.unscale(u_pred);
    let e = eval(&curve.param.at(f, lambda), &s, curve.p, false);
    curve.periods += curve.p;
    if e.outcome != Outcome::Ok || e.impacts == here.eval.impacts {
        if vanishing_end(curve, f, here, &(u_pred - here.u), settings, &mut pts) {
            return (pts, End::GrazingEnd);
        }
        return (pts, End::StepTooSmall);
    }
    let step = u_pred - here.u;
    let h = step.norm();
    let t = step / h;
    let left = here.eval.impacts;
    let periods0 = curve.periods;
    let found = locate::solve_grazing(
        h,
        (1.0, -1.0),
        -1.0,
        |sigma| {
            let (u, a, eval, _) = curve.correct(&(here.u + t * sigma), &t)?;
            Some(OnBranch { u, a, eval })
        },
        |p| if p.eval.impacts == left { 1.0 } else { -1.0 },
    );
    curve.periods_locating += curve.periods - periods0;
    match found.and_then(|p| located_row(curve, f, &p, Label::GR, settings)) {
        Some(row) => pts.push(row),
        None if vanishing_end(curve, f, here, &t, settings, &mut pts) => {}
        None => {
            if let Some(last) = pts.last_mut()
                && last.label == Label::None
            {
                last.label = Label::GR;
            }
        }
    }
    (pts, End::GrazingEnd)
}

/// Where the steps failed with an impact's approach speed near zero (below
/// [`VANISHING_SPEED`]` omega d/2` at `here`), the point ahead (along `dir`) where it vanishes
/// ([`speed_vanishing`]) as the branch's last row. Whether there was one.
pub(super) fn vanishing_end(
    curve: &mut Curve,
    f: &Forcing,
    here: &OnBranch,
    dir: &V5,
    settings: &ContSettings,
    pts: &mut Vec<BranchPoint>,
) -> bool {
    let l = f.half_gap();
    if here.eval.min_impact_speed >= VANISHING_SPEED * here_speed_scale(curve, f, &here.u) {
        return false;
    }
    let Some(found) = speed_vanishing(curve, f, &here.u, dir, CORNER_REACH, settings.range) else {
        return false;
    };
    clear_approach(pts, &found.row, l);
    pts.push(found.row);
    true
}

/// The branch's point at the end of the range that the step from `u` to `u_new` left: the
/// corrector at the bound itself, from the chord's point there. `None` where it does not
/// converge (the branch then ends at its last point inside).
pub(super) fn at_range_end(
    curve: &mut Curve,
    f: &Forcing,
    u: &V5,
    u_new: &V5,
    settings: &ContSettings,
) -> Option<BranchPoint> {
    let (_, l0) = curve.unscale(u);
    let (_, l1) = curve.unscale(u_new);
    let bound = l1.clamp(settings.range.0, settings.range.1);
    // From a point on the bound itself (a branch started at the range's end) the point at the
    // bound is that point again: no new row (issue 45, item 2).
    if l1 == l0 || (l0 - bound).abs() <= 1e-12 * bound.abs() {
        return None;
    }
    let mut from = u + (u_new - u) * ((bound - l0) / (l1 - l0));
    from[4] = bound / curve.lambda0;
    let (u_b, _, eval, _) = curve.correct(&from, &V5::new(0.0, 0.0, 0.0, 0.0, 1.0))?;
    if eval.impacts == 0 {
        return None;
    }
    let (fl, orb) = curve.orbit(f, &u_b, eval)?;
    Some(point(&fl, &orb, Label::None))
}

/// How near the section (in forcing periods) an impact of the orbit must be for the branch to
/// be followed across it in the other representation ([`past_corner`]).
pub(super) const SECTION_IMPACT_PERIODS: f64 = 1e-3;

/// The steps in the scaled parameter tried past a corner, smallest first.
pub(super) const CORNER_NUDGES: [f64; 6] = [1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4];

/// How far (scaled) the point found past a corner may lie from where it was looked for: farther
/// is another branch.
pub(super) const CORNER_REACH: f64 = 0.05;

/// The branch at `u` (tangent `t`), where its steps failed, continued past the corner a little
/// further on in the parameter (the steps [`CORNER_NUDGES`], each a corrector solve at a fixed
/// parameter), from two starts in turn:
///
/// * **an impact on the section.** The section state is taken at `t = 0 mod T`. Where an impact
///   of the orbit moves through that instant as the parameter changes, the fixed point jumps
///   from the state just before the impact to the state just after it (or back): the orbit is
///   continuous, its section coordinates are not, and the steps shrink into the jump. When the
///   inner mass at `u` is within [`SECTION_IMPACT_PERIODS`] of a period from a wall (at its
///   relative speed), the start is the same state in the other representation: the impact law
///   (eq. 3–4) forward if the inner mass approaches the wall, inverted (`e > 0`) if it leaves it;
/// * **a grazing.** The state at `u` itself: past a grazing the orbit has another impact
///   sequence, and the simulator finds it (the map's Jacobian grows like the inverse square root
///   of the distance to the grazing, so the predictor-corrector cannot step into it).
///
/// Returns the point found, its tangent (oriented as `t` is in the parameter) and its map
/// evaluation; `None` when neither start leads on.
pub(super) fn past_corner(
    curve: &mut Curve,
    f: &Forcing,
    u: &V5,
    t: &V5,
) -> Option<(V5, V5, OnBranch)> {
    let (s, lambda) = curve.unscale(u);
    let fl = curve.param.at(f, lambda);
    let (big_m, m, e) = (fl.sys.M, fl.sys.m, fl.sys.e);
    let l = fl.half_gap();
    let rel = s[3] - s[1];
    let wall = s[2].signum();
    let mut starts = Vec::with_capacity(2);
    if l - s[2].abs() <= rel.abs() * SECTION_IMPACT_PERIODS * fl.period() {
        if rel * wall > 0.0 {
            // Approaching the wall: the state just after the impact.
            let (v, w) = crate::sim::phase::impact(big_m, m, e, s[1], s[3]);
            starts.push([s[0], v, wall * l, w]);
        } else if e > 0.0 {
            // Leaving it: the state just before, `rel- = -rel+ / e` with the momentum kept.
            let rel_before = -rel / e;
            let v = (big_m * s[1] + m * s[3] - m * rel_before) / (big_m + m);
            starts.push([s[0], v, wall * l, v + rel_before]);
        }
    }
    starts.push(s);
    let along = V5::new(0.0, 0.0, 0.0, 0.0, t[4].signum());
    for start in starts {
        for nudge in CORNER_NUDGES {
            let from = curve.to_u(&start, lambda) + along * nudge;
            if let Some((u_new, a, eval, _)) = curve.correct(&from, &along)
                && (u_new - from).norm() <= CORNER_REACH
                && let Some(t_new) = tangent(&a, &along)
            {
                return Some((u_new, t_new, OnBranch { u: u_new, a, eval }));
            }
        }
    }
    None
}

/// An impact whose approach speed falls below this fraction of `omega d/2` is followed to its
/// zero in impact coordinates ([`speed_vanishing`]).
pub(super) const VANISHING_SPEED: f64 = 0.05;

/// `omega d/2` at the point `u` (m/s).
pub(super) fn here_speed_scale(curve: &Curve, f: &Forcing, u: &V5) -> f64 {
    let (_, lambda) = curve.unscale(u);
    let fl = curve.param.at(f, lambda);
    fl.omega * fl.half_gap()
}

/// A located point where an impact's approach speed vanishes: its row and whether every impact
/// of the orbit vanishes there.
pub(super) struct Vanishing {
    pub(super) row: BranchPoint,
    pub(super) all: bool,
}

/// The point ahead of `u` (the parameter moving as `t`'s parameter component does, at most
/// `reach` in the scaled parameter, inside `range`) where the orbit's slowest impact reaches its
/// wall with zero approach speed, solved in impact coordinates ([`crate::orbits::sequence`]: on the
/// section the map's derivatives grow like the inverse of that speed and the corrector cannot
/// get there). Its row is labelled `GR`, located; its multipliers are `NaN`: the impact law's
/// saltation divides by the approach speed, and the multipliers of the orbits before it grow
/// without bound (so the row is not stable).
pub(super) fn speed_vanishing(
    curve: &mut Curve,
    f: &Forcing,
    u: &V5,
    t: &V5,
    reach: f64,
    range: (f64, f64),
) -> Option<Vanishing> {
    use crate::orbits::sequence::{ImpactOrbit, speed_zero};
    let (s, lambda) = curve.unscale(u);
    let fl = curve.param.at(f, lambda);
    let orbit = ImpactOrbit::from_section(&fl, &s, curve.p)?;
    curve.periods += curve.p;
    let speeds = orbit.speeds(&fl);
    let j = (0..speeds.len()).min_by(|&a, &b| speeds[a].total_cmp(&speeds[b]))?;
    let param = curve.param;
    let (fz, oz, sz, sp) = speed_zero(&|x| param.at(f, x), lambda, &orbit, j)?;
    let lz = param.get(&fz);
    let ahead = (lz - lambda) * t[4].signum();
    if !(ahead > 0.0 && ahead <= reach * curve.lambda0 && lz >= range.0 && lz <= range.1) {
        return None;
    }
    let e = eval(&fz, &sz, curve.p, false);
    curve.periods += curve.p;
    if e.outcome != Outcome::Ok {
        return None;
    }
    curve.located += 1;
    let floor = 1e-9 * fz.sys.omega() * fz.half_gap();
    let row = BranchPoint {
        r: fz.ratio(),
        omega: fz.omega,
        F0: fz.F0,
        s: sz,
        period: curve.p as u32,
        amplitude: e.amplitude,
        impacts: oz.walls.len() as u64,
        multiplier_max: f64::NAN,
        multipliers: [(f64::NAN, f64::NAN); 4],
        min_impact_speed: sp[j].abs(),
        stable: false,
        label: Label::GR,
        located: true,
    };
    Some(Vanishing {
        row,
        all: sp.iter().all(|v| v.abs() <= floor),
    })
}

/// Clears the unlocated `GR` labels on the points just before a located vanishing impact
/// `row` ([`speed_vanishing`]): the approach of its slow impact (`half_gap` is `d/2`).
pub(super) fn clear_approach(pts: &mut [BranchPoint], row: &BranchPoint, half_gap: f64) {
    let slow = VANISHING_SPEED * half_gap;
    let approach = pts.iter_mut().rev().take_while(|p| {
        !p.located && p.impacts == row.impacts && p.min_impact_speed < slow * p.omega
    });
    for p in approach {
        if p.label == Label::GR {
            p.label = Label::None;
        }
    }
}
