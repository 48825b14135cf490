//! What a branch is (its points, its ends, the parameter it follows and the settings) and the
//! curve the predictor–corrector walks in scaled coordinates (the module doc of [`super`]): its
//! residual and exact Jacobian, the tangent, the corrector, and a branch point from an orbit.

use nalgebra::{SMatrix, SVector};

use crate::orbits::label::Label;
use crate::orbits::map::{Forcing, MapEval, Section, eval};
use crate::orbits::shoot::{Newton, NewtonState, Orbit, Stability, orbit_at};
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
/// past ([`End::GrazingEnd`]; [`super::through`]): a run from the grazing orbit a little past it.
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
    /// Labels located on it ([`crate::orbits::locate`]), and the forcing periods that took.
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

pub(super) type V5 = SVector<f64, 5>;
type M5 = SMatrix<f64, 5, 5>;

pub(super) struct Curve<'a> {
    pub(super) base: &'a Forcing,
    pub(super) param: Param,
    pub(super) p: u64,
    pub(super) lambda0: f64,
    pub(super) l: f64,
    pub(super) wn: f64,
    pub(super) periods: u64,
    pub(super) located: u32,
    pub(super) periods_locating: u64,
}

/// The unit tangent of the branch where the extended Jacobian is `a`, oriented along `prev`:
/// the null vector of `a` with `prev . t > 0`.
pub(super) fn tangent(a: &SMatrix<f64, 4, 5>, prev: &V5) -> Option<V5> {
    let mut m = M5::zeros();
    m.fixed_view_mut::<4, 5>(0, 0).copy_from(a);
    m.set_row(4, &prev.transpose());
    let rhs = V5::new(0.0, 0.0, 0.0, 0.0, 1.0);
    let t = m.lu().solve(&rhs)?;
    let n = t.norm();
    (n.is_finite() && n > 0.0).then(|| t / n)
}

impl Curve<'_> {
    pub(super) fn to_u(&self, s: &Section, lambda: f64) -> V5 {
        V5::new(
            s[0] / self.l,
            s[1] / (self.wn * self.l),
            s[2] / self.l,
            s[3] / (self.wn * self.l),
            lambda / self.lambda0,
        )
    }

    pub(super) fn unscale(&self, u: &V5) -> (Section, f64) {
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
    pub(super) fn residual(
        &mut self,
        u: &V5,
    ) -> Option<(SVector<f64, 4>, SMatrix<f64, 4, 5>, MapEval)> {
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
    pub(super) fn orbit(&self, f: &Forcing, u: &V5, eval: MapEval) -> Option<(Forcing, Orbit)> {
        let (s, lambda) = self.unscale(u);
        let fl = self.param.at(f, lambda);
        let state = NewtonState {
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
    pub(super) fn correct(
        &mut self,
        u_pred: &V5,
        t: &V5,
    ) -> Option<(V5, SMatrix<f64, 4, 5>, MapEval, u32)> {
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
pub(super) fn point(f: &Forcing, orbit: &Orbit, label: Label) -> BranchPoint {
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
pub(super) fn below_minus_one(orbit: &Orbit) -> usize {
    orbit
        .multipliers
        .iter()
        .filter(|&&(re, im)| im.abs() <= 1e-9 * re.abs().max(1.0) && re < -1.0)
        .count()
}
