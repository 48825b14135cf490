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
//! Between two consecutive points ([`classify`]):
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

use nalgebra::{SMatrix, SVector};

mod corners;
mod located;
mod through;
mod walk;

use corners::*;
pub use located::LOCATED_TOL;
use located::*;
use through::*;
use walk::*;

pub use super::label::Label;
use super::locate::{self, OnBranch, complex_outside, ns_value, test_function};
use super::map::{Forcing, MapEval, Section, eval};
use super::shoot::{Newton, Orbit, Stability, Termination, multipliers, orbit_at, solve};
use crate::sim::Outcome;

/// The continuation parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// The frequency ratio `r`.
    Ratio,
    /// The force amplitude `F0` (N).
    Force,
}

impl Param {
    /// The parameter's value at `f`.
    pub fn get(self, f: &Forcing) -> f64 {
        match self {
            Param::Ratio => f.ratio(),
            Param::Force => f.F0,
        }
    }

    /// `f` with the parameter set to `value`.
    pub fn at(self, f: &Forcing, value: f64) -> Forcing {
        match self {
            Param::Ratio => f.at_ratio(value),
            Param::Force => f.at_force(value),
        }
    }
}

/// Why a branch ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    Range,
    NoImpacts,
    StepTooSmall,
    MaxPoints,
    Simulator,
    /// The corrector came back along the branch: a corner of the branch (grazing).
    Grazing,
    /// The steps failed where, just past the last point, the orbit's impact sequence changes
    /// (an impact appears or vanishes): the branch cannot be continued past that grazing.
    GrazingEnd,
    /// The branch came back to its start: a closed curve (an isola), followed once.
    Closed,
}

impl End {
    pub fn name(self) -> &'static str {
        match self {
            End::Range => "range",
            End::NoImpacts => "no_impacts",
            End::StepTooSmall => "step_too_small",
            End::MaxPoints => "max_points",
            End::Simulator => "simulator",
            End::Grazing => "grazing",
            End::GrazingEnd => "grazing_end",
            End::Closed => "closed",
        }
    }
}

/// What the motion becomes where a branch ends at a grazing that no periodic orbit continues
/// past ([`End::GrazingEnd`]; [`through`]): a run from the grazing orbit a little past it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GrazingOutcome {
    /// A motion that is not periodic (chaos through the square-root singularity of the
    /// discontinuity map, or not settled within the run).
    Chaos,
    /// A periodic attractor: another branch's orbit, or the non-impacting family.
    Jump,
    /// Neither is known: the run failed.
    None,
}

impl GrazingOutcome {
    pub fn name(self) -> &'static str {
        match self {
            GrazingOutcome::Chaos => "chaos",
            GrazingOutcome::Jump => "jump",
            GrazingOutcome::None => "none",
        }
    }
}

/// One point of a branch.
#[derive(Clone, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct BranchPoint {
    /// The system at this point (its `omega`, `F0`).
    pub r: f64,
    pub omega: f64,
    pub F0: f64,
    pub s: Section,
    pub period: u32,
    pub amplitude: f64,
    pub impacts: u64,
    pub multiplier_max: f64,
    /// The Floquet multipliers `(re, im)`, by decreasing modulus (NaN past the fourth).
    pub multipliers: [(f64, f64); 4],
    /// The smallest approach speed of an impact over the orbit (m/s): near zero it grazes.
    pub min_impact_speed: f64,
    pub stable: bool,
    pub label: Label,
    /// The point is a located bifurcation: its label's test function solved on the branch.
    pub located: bool,
}

impl BranchPoint {
    /// The continuation parameter's value at this point.
    pub fn value(&self, param: Param) -> f64 {
        match param {
            Param::Ratio => self.r,
            Param::Force => self.F0,
        }
    }

    pub fn impacts_per_period(&self) -> f64 {
        self.impacts as f64 / self.period as f64
    }
}

/// A followed branch: its points in parameter order along the curve, and how each end ended.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    pub points: Vec<BranchPoint>,
    /// The ends (first point's side, last point's side).
    pub ends: (End, End),
    /// At an end [`End::GrazingEnd`], what the motion becomes past it (`None` at other ends).
    pub outcomes: (Option<GrazingOutcome>, Option<GrazingOutcome>),
    /// Forcing periods simulated to follow it (locating its labels included).
    pub periods: u64,
    /// Labels located on it ([`super::locate`]), and the forcing periods that took.
    pub located: u32,
    pub periods_locating: u64,
}

/// Continuation settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContSettings {
    /// The swept interval of the parameter.
    pub range: (f64, f64),
    /// First step, and bounds of the step, in scaled arclength.
    pub h0: f64,
    pub h_min: f64,
    pub h_max: f64,
    /// Most points on one side of the start.
    pub max_points: usize,
    /// Follow doubled branches at PD points and the other branch at branch points (`BP`).
    pub switch_pd: bool,
}

type V5 = SVector<f64, 5>;
type M5 = SMatrix<f64, 5, 5>;

struct Curve<'a> {
    base: &'a Forcing,
    param: Param,
    p: u64,
    lambda0: f64,
    l: f64,
    wn: f64,
    periods: u64,
    located: u32,
    periods_locating: u64,
}

/// The unit tangent of the branch where the extended Jacobian is `a`, oriented along `prev`:
/// the null vector of `a` with `prev . t > 0`.
fn tangent(a: &SMatrix<f64, 4, 5>, prev: &V5) -> Option<V5> {
    let mut m = M5::zeros();
    m.fixed_view_mut::<4, 5>(0, 0).copy_from(a);
    m.set_row(4, &prev.transpose());
    let rhs = V5::new(0.0, 0.0, 0.0, 0.0, 1.0);
    let t = m.lu().solve(&rhs)?;
    let n = t.norm();
    (n.is_finite() && n > 0.0).then(|| t / n)
}

impl Curve<'_> {
    fn to_u(&self, s: &Section, lambda: f64) -> V5 {
        V5::new(
            s[0] / self.l,
            s[1] / (self.wn * self.l),
            s[2] / self.l,
            s[3] / (self.wn * self.l),
            lambda / self.lambda0,
        )
    }

    fn unscale(&self, u: &V5) -> (Section, f64) {
        (
            [
                u[0] * self.l,
                u[1] * self.wn * self.l,
                u[2] * self.l,
                u[3] * self.wn * self.l,
            ],
            u[4] * self.lambda0,
        )
    }

    /// `F(u)` scaled, its `4 x 5` Jacobian `[J - I | dF/dlambda]` (both exact, from one
    /// evaluation of the map) and that evaluation.
    fn residual(&mut self, u: &V5) -> Option<(SVector<f64, 4>, SMatrix<f64, 4, 5>, MapEval)> {
        let (s, lambda) = self.unscale(u);
        let f = self.param.at(self.base, lambda);
        let e = eval(&f, &s, self.p, true);
        self.periods += self.p;
        if e.outcome != Outcome::Ok {
            return None;
        }
        let jac = e.jacobian?;
        let dp = e.d_param?;
        let d_lambda = match self.param {
            // omega = r wn.
            Param::Ratio => dp.omega.map(|v| v * self.wn),
            Param::Force => dp.force,
        };
        let (a_l, b_l) = (1.0 / self.l, 1.0 / (self.wn * self.l));
        let sc = [a_l, b_l, a_l, b_l];
        let g = SVector::<f64, 4>::from_fn(|r, _| (e.end[r] - s[r]) * sc[r]);
        let mut a = SMatrix::<f64, 4, 5>::zeros();
        for r in 0..4 {
            for c in 0..4 {
                // d(scaled row) / d(scaled col) = sc[r] J[r][c] / sc[c].
                let id = if r == c { 1.0 } else { 0.0 };
                a[(r, c)] = sc[r] * (jac[r][c] - id) / sc[c];
            }
            a[(r, 4)] = sc[r] * d_lambda[r] * self.lambda0;
        }
        Some((g, a, e))
    }

    /// The orbit at the branch point `u` whose map evaluation is `eval`: the system at its
    /// parameter and the orbit's stability by Newton from there (`None` where it fails).
    fn orbit(&self, f: &Forcing, u: &V5, eval: MapEval) -> Option<(Forcing, Orbit)> {
        let (s, lambda) = self.unscale(u);
        let fl = self.param.at(f, lambda);
        let state = super::shoot::NewtonState {
            s,
            residual: 0.0,
            iterations: 0,
            last: eval,
        };
        let orb = orbit_at(&fl, self.p, &state, &Newton::default())?;
        Some((fl, orb))
    }

    /// Newton on `(F(u), t . (u - u_pred)) = 0` from `u_pred`: one map evaluation per
    /// iteration. Returns the point, its Jacobian, the map's evaluation there and the
    /// iterations taken.
    fn correct(&mut self, u_pred: &V5, t: &V5) -> Option<(V5, SMatrix<f64, 4, 5>, MapEval, u32)> {
        let mut u = *u_pred;
        for it in 0..8u32 {
            let (g, a, e) = self.residual(&u)?;
            if g.norm() <= 1e-9 {
                return Some((u, a, e, it));
            }
            let mut m = M5::zeros();
            m.fixed_view_mut::<4, 5>(0, 0).copy_from(&a);
            m.set_row(4, &t.transpose());
            let mut rhs = V5::zeros();
            rhs.fixed_rows_mut::<4>(0).copy_from(&(-g));
            rhs[4] = -t.dot(&(u - u_pred));
            let du = m.lu().solve(&rhs)?;
            if !du.iter().all(|v| v.is_finite()) || du.norm() > 0.5 {
                return None;
            }
            u += du;
            // The inner mass stays in the clearance.
            u[2] = u[2].clamp(-1.0, 1.0);
        }
        None
    }
}

/// The orbit's point on a branch.
fn point(f: &Forcing, orbit: &Orbit, label: Label) -> BranchPoint {
    BranchPoint {
        r: f.ratio(),
        omega: f.omega,
        F0: f.F0,
        s: orbit.s,
        period: orbit.period,
        amplitude: orbit.amplitude,
        impacts: orbit.impacts,
        multiplier_max: orbit.multiplier_max(),
        multipliers: std::array::from_fn(|i| {
            orbit
                .multipliers
                .get(i)
                .copied()
                .unwrap_or((f64::NAN, f64::NAN))
        }),
        min_impact_speed: orbit.min_impact_speed,
        stable: orbit.stability == Stability::Stable,
        label,
        located: false,
    }
}

/// Real multipliers below `-1`.
fn below_minus_one(orbit: &Orbit) -> usize {
    orbit
        .multipliers
        .iter()
        .filter(|&&(re, im)| im.abs() <= 1e-9 * re.abs().max(1.0) && re < -1.0)
        .count()
}

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
    use super::*;

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
