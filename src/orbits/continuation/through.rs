//! Through a grazing (issue 45): where a branch's steps end at a grazing (`grazing_end`), the
//! orbit with the changed impact sequence is looked for on the far side, seeded from the
//! grazing orbit, and the branch goes on along it; where none is within reach, the branch ends
//! there and a short run from the grazing orbit says what the motion becomes.
//!
//! # The orbit past a grazing
//! At a grazing the impact sequence changes (di Bernardo, Budd, Champneys and Kowalczyk,
//! *Piecewise-smooth Dynamical Systems*, 2008, ch. 6–7; Nordmark 1991):
//! * **a contact is added.** A flight of the inner mass touches a wall (`gap = 0`,
//!   [`crate::orbits::graze::nearest_contact`]). Past it that touch is an impact whose approach
//!   speed `u` grows from zero. In impact coordinates ([`crate::orbits::sequence`]) the orbit
//!   with the contact as one more impact is smooth in `u`, and `lambda(u)` is smooth too; so the
//!   orbit is solved at a given contact speed, `u = 0.3 omega d/2` (else `0.1`, `0.05`), with
//!   the parameter an unknown ([`crate::orbits::sequence::speed_at`]). Its parameter lies past
//!   the grazing where the orbit persists, or back before it where the two meet in a nonsmooth
//!   fold (the branch then turns back with the new contact): either way the branch goes on;
//! * **an impact vanishes.** An impact's approach speed reaches zero
//!   ([`crate::orbits::sequence::speed_zero`]); there the orbit without that impact is the same
//!   orbit, and it is solved without it at a parameter a little past the zero, then before it
//!   ([`crate::orbits::sequence::solve_at`]: the orbit must stay inside the clearance, which
//!   picks the side). Where every impact vanishes at once the orbit joins the non-impacting
//!   family (a branch of its own), and the branch ends there.
//!
//! The orbit found is solved again on the section by Newton, and the walk goes on from it with
//! the unit tangent of its branch oriented away from the grazing orbit (in the scaled unknowns
//! `u`, the direction `u - u_grazing`). It is kept where its parameter is within [`REACH`] of
//! the grazing's (relative), inside the swept range, and it has the impact count asked for.
//!
//! # Where no orbit continues the branch
//! A run from the grazing orbit's section state at the parameter [`BEYOND`] past the grazing
//! (relative, along the branch's last direction), with the census's rules for one start
//! ([`crate::orbits::census::settle`], a budget of [`RUN_PERIODS`] forcing periods) says which
//! case it is: `chaos` (a motion that is not periodic), `jump` (a periodic attractor, another
//! branch's or the non-impacting family) or `none` (the run failed).

use super::branch::{BranchPoint, ContSettings, Curve, GrazingOutcome, V5, point, tangent};
use crate::orbits::census::{CensusSettings, Landing, settle};
use crate::orbits::graze::nearest_contact;
use crate::orbits::label::Label;
use crate::orbits::locate::OnBranch;
use crate::orbits::map::{Forcing, Section};
use crate::orbits::sequence::{ImpactOrbit, solve_at, speed_at, speed_zero};
use crate::orbits::shoot::{Newton, Orbit, Termination, orbit_at, solve};

/// How far past a grazing (relative to its parameter) the orbit with the changed sequence may
/// lie: farther is not this branch's continuation.
pub(super) const REACH: f64 = 0.05;

/// The new contact's approach speeds tried, in units of `omega d/2`: above
/// [`super::corners::VANISHING_SPEED`] so that the walk does not take it for an impact
/// vanishing, small enough to stay near the grazing. The corrector's basin on the section
/// shrinks like the square of the slowest impact's speed (the map's derivatives grow like its
/// inverse): from `0.1` the
/// steps creep away from the grazing (hundreds of points on the design-map showcase), from
/// `0.3` they do not.
pub(super) const CONTACT_SPEEDS: [f64; 3] = [0.3, 0.1, 0.05];

/// A flight nearer a wall than this (relative to `d/2`) is the grazing contact to add.
pub(super) const CONTACT_GAP: f64 = 1e-3;

/// An impact slower than this (in units of `omega d/2`) is the one vanishing at the grazing.
pub(super) const VANISHED_SPEED: f64 = 1e-3;

/// The parameter steps (relative) at which the orbit without the vanished impact is solved,
/// each past the zero first, then before it.
pub(super) const REMOVAL_STEPS: [f64; 3] = [1e-3, 1e-4, 1e-2];

/// The contact's slower speeds (units of `omega d/2`) at which its family is tabulated between
/// the grazing and the point the walk goes on from: the walk starts at the first of
/// [`CONTACT_SPEEDS`] that solves, up to a few per cent of the parameter past the grazing.
pub(super) const FILL_SPEEDS: [f64; 4] = [0.02, 0.05, 0.1, 0.2];

/// Where a branch that ends at a grazing is run from, past the grazing (relative).
pub(super) const BEYOND: f64 = 1e-3;

/// The budget of that run, in forcing periods: the census's default start budget.
pub(super) const RUN_PERIODS: u64 = 2000;

/// An orbit solved in impact coordinates: its forcing and section state.
type Solved = (Forcing, Section);

/// The point the walk goes on from past a grazing: scaled unknowns, the unit tangent, the
/// extended Jacobian and map evaluation there, the orbit and its forcing.
pub(super) struct Resumed {
    pub(super) u: V5,
    pub(super) t: V5,
    pub(super) here: OnBranch,
    pub(super) orbit: Orbit,
    pub(super) f: Forcing,
    /// Points of the same orbit family between the grazing and this one, in that order.
    pub(super) fill: Vec<BranchPoint>,
}

/// The orbit past the grazing `row` (the branch's last row, travelling in the parameter as
/// `dir`), with a contact added or an impact removed (module doc); `None` when neither is
/// within reach.
pub(super) fn through_grazing(
    curve: &mut Curve,
    f: &Forcing,
    row: &BranchPoint,
    dir: f64,
    settings: &ContSettings,
) -> Option<Resumed> {
    let lambda = row.value(curve.param);
    let fg = curve.param.at(f, lambda);
    let io = ImpactOrbit::from_section(&fg, &row.s, curve.p)?;
    curve.periods += curve.p;
    let n = io.walls.len() as u64;
    let slow = VANISHED_SPEED * fg.omega * fg.half_gap();
    if io.speeds(&fg).iter().all(|&u| u <= slow) {
        // Every impact vanishes at once: the orbit joins the non-impacting family.
        return None;
    }
    let mut found = None;
    if let Some((fz, sz, fill)) = contact_added(curve, f, &fg, row, &io) {
        found = resume(curve, row, &fz, &sz, n + 1, settings).map(|mut next| {
            next.fill = fill_points(curve, &fill, &next.orbit);
            next
        });
    }
    if found.is_none() && row.min_impact_speed <= slow {
        found = impact_removed(curve, f, row, &io, dir, settings);
    }
    found
}

/// The orbit with the grazing contact of `row` (at `fg`) as one more impact, at the first of
/// [`CONTACT_SPEEDS`] where it solves: its forcing and section state, and the same orbit's
/// family at the slower speeds of [`FILL_SPEEDS`] where they solve (slowest first).
fn contact_added(
    curve: &mut Curve,
    f: &Forcing,
    fg: &Forcing,
    row: &BranchPoint,
    io: &ImpactOrbit,
) -> Option<(Forcing, Section, Vec<Solved>)> {
    let near = nearest_contact(fg, &row.s, curve.p)?;
    curve.periods += curve.p;
    if near.gap > CONTACT_GAP * fg.half_gap() {
        return None;
    }
    let (with, j) = io.with_contact(fg, near.t, near.wall);
    let param = curve.param;
    let lambda = row.value(param);
    let scale = fg.omega * fg.half_gap();
    let at = |speed: f64| {
        let (fz, _, sz, _) = speed_at(&|x| param.at(f, x), lambda, &with, j, speed * scale)?;
        Some((fz, sz))
    };
    let (speed, (fz, sz)) = CONTACT_SPEEDS
        .iter()
        .find_map(|&speed| at(speed).map(|found| (speed, found)))?;
    let fill = FILL_SPEEDS
        .iter()
        .filter(|&&u| u < speed)
        .filter_map(|&u| at(u))
        .collect();
    Some((fz, sz, fill))
}

/// The orbits of a contact's family between the grazing and the point the walk goes on from
/// ([`contact_added`]), as branch points: each by Newton on the section from its section state,
/// kept where it has the impacts of the walk's orbit `next`.
fn fill_points(curve: &mut Curve, fill: &[Solved], next: &Orbit) -> Vec<BranchPoint> {
    let newton = Newton::default();
    let mut out = Vec::new();
    for (fl, s) in fill {
        curve.periods += curve.p;
        if let (Termination::Converged { .. }, Some(st)) = solve(fl, curve.p, s, &newton)
            && let Some(orbit) = orbit_at(fl, curve.p, &st, &newton)
            && orbit.impacts == next.impacts
            && orbit.period == next.period
        {
            out.push(point(fl, &orbit, Label::None));
        }
    }
    out
}

/// The orbit without `row`'s vanishing impact, past the parameter where its speed is zero
/// (along `dir`; else before it: module doc), as the walk's next point.
fn impact_removed(
    curve: &mut Curve,
    f: &Forcing,
    row: &BranchPoint,
    io: &ImpactOrbit,
    dir: f64,
    settings: &ContSettings,
) -> Option<Resumed> {
    let param = curve.param;
    let lambda = row.value(param);
    let fg = param.at(f, lambda);
    let speeds = io.speeds(&fg);
    let j = (0..speeds.len()).min_by(|&a, &b| speeds[a].total_cmp(&speeds[b]))?;
    let (fz, oz, _, _) = speed_zero(&|x| param.at(f, x), lambda, io, j)?;
    let without = oz.without(&fz, j)?;
    let n = without.walls.len() as u64;
    let lz = param.get(&fz);
    let ahead = if dir < 0.0 { -1.0 } else { 1.0 };
    for step in REMOVAL_STEPS {
        for sign in [ahead, -ahead] {
            let fl = param.at(f, lz * (1.0 + sign * step));
            curve.periods += curve.p;
            if let Some((_, s, _)) = solve_at(&fl, &without)
                && let Some(r) = resume(curve, row, &fl, &s, n, settings)
            {
                return Some(r);
            }
        }
    }
    None
}

/// The walk's next point from the orbit at `fl` through section state `s`: Newton on the
/// section there, kept when it has `impacts` impacts over the curve's `p` periods, lies within
/// [`REACH`] of the grazing `row` in the parameter and inside the swept range; its tangent is
/// oriented away from the grazing orbit.
fn resume(
    curve: &mut Curve,
    row: &BranchPoint,
    fl: &Forcing,
    s: &Section,
    impacts: u64,
    settings: &ContSettings,
) -> Option<Resumed> {
    let lambda = curve.param.get(fl);
    let lambda_g = row.value(curve.param);
    let inside = lambda >= settings.range.0 && lambda <= settings.range.1;
    if !inside || (lambda - lambda_g).abs() > REACH * lambda_g.abs() {
        return None;
    }
    let newton = Newton::default();
    let (Termination::Converged { .. }, Some(st)) = solve(fl, curve.p, s, &newton) else {
        return None;
    };
    curve.periods += curve.p;
    let orbit = orbit_at(fl, curve.p, &st, &newton)?;
    let u = curve.to_u(&orbit.s, lambda);
    let (_, a, eval) = curve.residual(&u)?;
    if eval.impacts != impacts {
        return None;
    }
    let away = u - curve.to_u(&row.s, lambda_g);
    let t = tangent(&a, &away)?;
    let here = OnBranch { u, a, eval };
    Some(Resumed {
        u,
        t,
        here,
        orbit,
        f: fl.clone(),
        fill: Vec::new(),
    })
}

/// What the motion becomes where a branch ends at the grazing orbit `s` at `lambda` (travelling
/// as `dir`): a run from `s` at [`BEYOND`] past it (module doc).
pub(super) fn outcome_beyond(
    curve: &mut Curve,
    f: &Forcing,
    s: &Section,
    lambda: f64,
    dir: f64,
) -> GrazingOutcome {
    let fl = curve.param.at(f, lambda * (1.0 + dir.signum() * BEYOND));
    let run = CensusSettings {
        starts: 1,
        max_periods: RUN_PERIODS,
        handover: 1e-3,
        window: 200,
        seed: 0,
        point: 0,
        spent0: 0,
    };
    let settled = settle(&fl, s, &run, &Newton::default());
    curve.periods += settled.periods;
    match settled.landing {
        Landing::Orbit(_) => GrazingOutcome::Jump,
        Landing::NonPeriodic { amplitude, .. } if amplitude.is_finite() => GrazingOutcome::Chaos,
        Landing::NonPeriodic { .. } => GrazingOutcome::None,
    }
}
