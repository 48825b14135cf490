//! Continuation of periodic orbits along the frequency ratio `r` or the force amplitude `F0`:
//! pseudo-arclength predictor–corrector on `F(s, lambda) = P^p(s; lambda) - s = 0`, with
//! adaptive steps, located bifurcation labels and switches to the doubled branch at a period
//! doubling and to the other branch at a branch point.
//!
//! # Predictor–corrector
//! Unknowns `u = (s, lambda)` in scaled coordinates (`x / L`, `x' / (wn L)`, `z / L`,
//! `y' / (wn L)`, `lambda / lambda_0`; `L = d/2`). The tangent `t` spans the null space of
//! `[J - I | dF/dlambda]` (`J` the exact monodromy matrix of [`super::map`], `dF/dlambda` its
//! exact derivative in `omega` or `F0`, from the same evaluation), oriented like the previous
//! one. The predictor is `u + h t`; the corrector is Newton on `(F(u), t . (u - u_pred)) = 0`,
//! which crosses folds where `lambda` turns back. Each corrector iteration is one evaluation of
//! the map; the evaluation that confirms a point also gives its multipliers and the next
//! tangent. A step that converges in at most 3 iterations
//! grows `h` by 1.5 (up to [`ContSettings::h_max`]); a failed one halves it, and below
//! [`ContSettings::h_min`] the branch ends (`step_too_small`).
//!
//! # Labels
//! Between two consecutive points ([`walk::classify`]):
//! * `SN`, a fold: the tangent's `lambda` component changes sign (and the orbit's minimal period
//!   does not: on `P^{2p}` a change of period is where the doubled branch crosses, a `PD`);
//! * `GR`, grazing: the number of impacts per orbit changes (an impact velocity reached zero, or
//!   a new contact), or an impact's approach speed falls below `1e-3 omega d/2`. An approach
//!   speed falling toward zero is followed there in impact coordinates ([`super::sequence`]),
//!   where the section's map is not smooth enough for the corrector, and the orbit with the
//!   zero-speed impact is the located `GR` row (multipliers `NaN`: they grow without bound);
//! * `PD`, period doubling: a real multiplier crosses `-1` (the count of real multipliers
//!   below `-1` changes); the doubled branch is then followed from the eigenvector (Newton on
//!   `P^{2p}`), once per branch;
//! * `BP`, a branch point: a real multiplier crosses `+1` without a fold (`det(J - I)` changes
//!   sign, the tangent's `lambda` component does not); once located, the other branch through
//!   it is followed from the null direction of the extended Jacobian orthogonal to the tangent
//!   (once per branch);
//! * `NS`, Neimark–Sacker: the count of complex multipliers outside the unit circle changes;
//! * `NI`: the orbit's impacts end (the branch joins the non-impacting family, and ends there).
//!
//! Each is then solved on the branch between the two points ([`super::locate`]; docs/model.md,
//! §12) and inserted as its own row (`located`); the point past it stays, unlabelled. Where it
//! cannot be solved (the map is not smooth there) a `BP` or `NS` is dropped and the others stay
//! on the point past the change.
//!
//! At a located grazing where the steps fail, the orbit with the changed impact sequence (the
//! grazing contact added, or the vanishing impact removed) is solved past it, seeded from the
//! grazing orbit, and the branch goes on along it ([`through`]): its impact count changes there
//! and the `GR` row stays.
//!
//! # Ends
//! Every branch ends with a named reason ([`End`]): `range` (it left the swept interval),
//! `no_impacts`, `step_too_small`, `max_points` ([`ContSettings::max_points`]), `simulator`,
//! `grazing_end` (the steps failed where, one step past the last point, the orbit's impact count
//! changes, and no orbit with the changed impact sequence continues the branch past that
//! grazing ([`through`]); or every impact's approach speed vanished at once, where the orbit
//! joins the non-impacting family; the branch's [`GrazingOutcome`] says what the motion becomes
//! there), `closed` (back on a point it went through), or
//! `grazing`: the corrector came back along the branch it came from (nearer the point before
//! than half a step), which happens at a corner of the branch where an impact grazes and the
//! map is not smooth; the last point is labelled `GR` rather than taken for a fold.
//! Nothing loops forever: each step is a bounded number of map evaluations.

mod branch;
mod corners;
mod located;
mod through;
mod walk;
pub(crate) use walk::passes;

pub use branch::{Branch, BranchPoint, ContSettings, End, GrazingOutcome, Param};
use branch::{Curve, point};
pub use located::LOCATED_TOL;
use walk::side;

pub use super::label::Label;
use super::map::Forcing;
use super::shoot::Orbit;

/// Follows the branch of `orbit` (a fixed point of `P^p` at `f`) both ways in `param`; with
/// `settings.switch_pd`, also the doubled branches met at PD points and the other branch at
/// located branch points (`BP`). The first branch returned is `orbit`'s.
pub fn follow(f: &Forcing, orbit: &Orbit, param: Param, settings: &ContSettings) -> Vec<Branch> {
    let mut out = Vec::new();
    let mut pending = vec![(f.clone(), orbit.clone(), settings.switch_pd)];
    while let Some((f, orbit, switch)) = pending.pop() {
        let (branch, switches) = follow_one(&f, &orbit, param, settings);
        out.push(branch);
        if switch {
            for (fd, od) in switches.into_iter().take(4) {
                // A branch switched to does not switch again: bounded work.
                pending.push((fd, od, false));
            }
        }
    }
    out
}

/// One branch both ways; returns it and the orbits to switch to: the doubled ones found at its PD
/// points and the other branch's at its branch points.
fn follow_one(
    f: &Forcing,
    orbit: &Orbit,
    param: Param,
    settings: &ContSettings,
) -> (Branch, Vec<(Forcing, Orbit)>) {
    let mut curve = Curve {
        base: f,
        param,
        p: u64::from(orbit.period),
        lambda0: param.get(f),
        l: f.half_gap(),
        wn: f.sys.omega(),
        periods: 0,
        located: 0,
        periods_locating: 0,
    };
    let mut switches = Vec::new();
    let start = point(f, orbit, Label::None);
    let mut sides: Vec<(Vec<BranchPoint>, End, Option<GrazingOutcome>)> = Vec::new();
    for dir in [-1.0, 1.0] {
        if sides.first().is_some_and(|(_, end, _)| *end == End::Closed) {
            // The first side went round the whole curve (or into a loop it follows once).
            sides.push((Vec::new(), End::Closed, None));
            continue;
        }
        sides.push(side(&mut curve, f, orbit, dir, settings, &mut switches));
    }
    let (mut down, end_down, out_down) = sides.remove(0);
    let (up, end_up, out_up) = sides.remove(0);
    down.reverse();
    down.push(start);
    down.extend(up);
    let branch = Branch {
        points: down,
        ends: (end_down, end_up),
        outcomes: (out_down, out_up),
        periods: curve.periods,
        located: curve.located,
        periods_locating: curve.periods_locating,
    };
    (branch, switches)
}

#[cfg(test)]
mod tests {
    use super::branch::V5;
    use super::walk::retraces;

    /// A step that comes back towards the point before is a retrace; steps along a branch,
    /// through a fold included (the parameter turns, the state goes on), are not.
    #[test]
    fn a_retrace_is_told_from_a_fold() {
        let before = V5::new(0.0, 0.0, 0.0, 0.0, 1.0);
        let now = V5::new(0.1, 0.0, 0.0, 0.0, 1.01);
        // Straight on, and round a fold in lambda.
        assert!(!retraces(&before, &now, &V5::new(0.2, 0.0, 0.0, 0.0, 1.02)));
        assert!(!retraces(&before, &now, &V5::new(0.2, 0.0, 0.0, 0.0, 1.0)));
        // Back onto the way it came.
        assert!(retraces(
            &before,
            &now,
            &V5::new(0.01, 0.0, 0.0, 0.0, 1.001)
        ));
    }
}
