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
//! # Ends
//! Every branch ends with a named reason ([`End`]): `range` (it left the swept interval),
//! `no_impacts`, `step_too_small`, `max_points` ([`ContSettings::max_points`]), `simulator`,
//! `grazing_end` (the steps failed where, one step past the last point, the orbit's impact count
//! changes: the map is not smooth there, and often not continuous, so the branch cannot pass; or
//! every impact's approach speed vanished at once, where the orbit joins the non-impacting
//! family), `closed` (back on a point it went through), or
//! `grazing`: the corrector came back along the branch it came from (nearer the point before
//! than half a step), which happens at a corner of the branch where an impact grazes and the
//! map is not smooth; the last point is labelled `GR` rather than taken for a fold.
//! Nothing loops forever: each step is a bounded number of map evaluations.

use nalgebra::{SMatrix, SVector};

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

/// A label of a continuation point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Label {
    None,
    SN,
    /// A branch point: a real multiplier through `+1` where the branch does not fold.
    BP,
    PD,
    /// Neimark–Sacker: a complex pair of multipliers through the unit circle.
    NS,
    GR,
    NI,
}

impl Label {
    pub fn name(self) -> &'static str {
        match self {
            Label::None => "",
            Label::SN => "SN",
            Label::BP => "BP",
            Label::PD => "PD",
            Label::NS => "NS",
            Label::GR => "GR",
            Label::NI => "NI",
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
    let mut sides: Vec<(Vec<BranchPoint>, End)> = Vec::new();
    for dir in [-1.0, 1.0] {
        if sides.first().is_some_and(|(_, end)| *end == End::Closed) {
            // The first side went round the whole curve (or into a loop it follows once).
            sides.push((Vec::new(), End::Closed));
            continue;
        }
        let (pts, end) = side(&mut curve, f, orbit, dir, settings, &mut switches);
        sides.push((pts, end));
    }
    let (mut down, end_down) = sides.remove(0);
    let (up, end_up) = sides.remove(0);
    down.reverse();
    down.push(start);
    down.extend(up);
    let branch = Branch {
        points: down,
        ends: (end_down, end_up),
        periods: curve.periods,
        located: curve.located,
        periods_locating: curve.periods_locating,
    };
    (branch, switches)
}

/// The points on one side of the start (`dir` = the sign of the first step in `lambda`).
fn side(
    curve: &mut Curve,
    f: &Forcing,
    orbit: &Orbit,
    dir: f64,
    settings: &ContSettings,
    switches: &mut Vec<(Forcing, Orbit)>,
) -> (Vec<BranchPoint>, End) {
    let u = curve.to_u(&orbit.s, curve.param.get(f));
    let Some((_, a, e)) = curve.residual(&u) else {
        return (Vec::new(), End::Simulator);
    };
    let Some(t) = tangent(&a, &V5::new(0.0, 0.0, 0.0, 0.0, dir)) else {
        return (Vec::new(), End::StepTooSmall);
    };
    let mut walk = Walk {
        pts: Vec::new(),
        u,
        t,
        here: OnBranch { u, a, eval: e },
        prev_orbit: orbit.clone(),
        h: settings.h0,
        doubled: false,
        switched: 0,
        u_before: None,
        crossed: false,
        trail: Vec::new(),
    };
    while walk.pts.len() < settings.max_points {
        let u_pred = walk.u + walk.t * walk.h;
        let step = match curve.correct(&u_pred, &walk.t) {
            None => walk.shorten(curve, f, &u_pred, settings),
            Some((u_new, a_new, state_eval, iters)) => {
                let next = OnBranch {
                    u: u_new,
                    a: a_new,
                    eval: state_eval,
                };
                walk.advance(curve, f, next, iters, settings, switches)
            }
        };
        if let Some(end) = step {
            return (walk.pts, end);
        }
    }
    (walk.pts, End::MaxPoints)
}

/// One side of a branch being followed ([`side`]): its points so far and where it stands.
struct Walk {
    pts: Vec<BranchPoint>,
    /// The current point (scaled unknowns), the unit tangent there, and its extended Jacobian
    /// and map evaluation (the left end of the bracket when a label is located).
    u: V5,
    t: V5,
    here: OnBranch,
    /// The orbit at the current point (its multipliers against the next point's).
    prev_orbit: Orbit,
    /// The step length.
    h: f64,
    /// A period doubling on this side already gave its doubled branch.
    doubled: bool,
    /// Branch points switched at on this side.
    switched: u32,
    /// The point before `u`, to see the branch fold back onto itself.
    u_before: Option<V5>,
    /// The last step went past a corner ([`past_corner`]).
    crossed: bool,
    /// The points so far and their tangents, to see the branch close on itself.
    trail: Vec<(V5, V5)>,
}

impl Walk {
    /// The corrector failed from `u_pred`: the step is halved; below the smallest step the
    /// branch has a corner (an impact on the section, a grazing), passed once per corner (the
    /// flag is cleared by the next ordinary step), or its end there. `Some` when the side ends.
    fn shorten(
        &mut self,
        curve: &mut Curve,
        f: &Forcing,
        u_pred: &V5,
        settings: &ContSettings,
    ) -> Option<End> {
        self.h *= 0.5;
        if self.h >= settings.h_min {
            return None;
        }
        // Every impact vanishing at once: the branch ends there ([`speed_vanishing`]).
        let slow =
            self.here.eval.min_impact_speed < VANISHING_SPEED * here_speed_scale(curve, f, &self.u);
        if slow
            && let Some(found) =
                speed_vanishing(curve, f, &self.u, &self.t, CORNER_REACH, settings.range)
            && found.all
        {
            clear_approach(&mut self.pts, &found.row, f.half_gap());
            self.pts.push(found.row);
            return Some(End::GrazingEnd);
        }
        if !self.crossed
            && let Some(jump) = past_corner(curve, f, &self.u, &self.t)
        {
            if jump.2.eval.impacts != self.here.eval.impacts
                && let Some(last) = self.pts.last_mut()
                && last.label == Label::None
            {
                last.label = Label::GR;
            }
            (self.u, self.t, self.here) = jump;
            self.u_before = None;
            self.h = settings.h0;
            self.crossed = true;
            return None;
        }
        let pts = std::mem::take(&mut self.pts);
        let (pts, end) = end_of_steps(curve, f, &self.here, u_pred, settings, pts);
        self.pts = pts;
        Some(end)
    }

    /// The corrector found `next` (in `iters` iterations): the side ends there (closed on
    /// itself, at a corner it came back from, past the swept range, out of impacts), or its
    /// point is labelled, located and added, and the walk moves on to it. `Some` when the side
    /// ends.
    fn advance(
        &mut self,
        curve: &mut Curve,
        f: &Forcing,
        next: OnBranch,
        iters: u32,
        settings: &ContSettings,
        switches: &mut Vec<(Forcing, Orbit)>,
    ) -> Option<End> {
        self.crossed = false;
        let u_new = next.u;
        if let Some(end) = self.ends_before(curve, f, &next, settings) {
            return Some(end);
        }
        let Some(t_new) = tangent(&next.a, &self.t) else {
            return Some(End::StepTooSmall);
        };
        let (s, lambda) = curve.unscale(&u_new);
        let fl = curve.param.at(f, lambda);
        let state = super::shoot::NewtonState {
            s,
            residual: 0.0,
            iterations: 0,
            last: next.eval.clone(),
        };
        let newton = Newton::default();
        let Some(orb) = orbit_at(&fl, curve.p, &state, &newton) else {
            return Some(End::NoImpacts);
        };
        let label = self.label(curve, f, &fl, &orb, &next, &t_new, settings, switches);
        let falling = orb.min_impact_speed < self.prev_orbit.min_impact_speed;
        let vanishing =
            falling && orb.min_impact_speed < VANISHING_SPEED * fl.omega * fl.half_gap();
        self.pts.push(point(&fl, &orb, label));
        self.prev_orbit = orb;
        self.trail.push((self.u, self.t));
        self.u_before = Some(self.u);
        self.u = u_new;
        self.t = t_new;
        self.here = next;
        if iters <= 3 {
            self.h = (self.h * 1.5).min(settings.h_max);
        }
        // An impact's approach speed falling to zero within the next step, located in impact
        // coordinates (continuation on the section cannot reach it). Where every impact vanishes
        // at once the orbit joins the non-impacting family and the branch ends; where one of
        // several does, the grazing is passed or located from its smooth side as any other
        // ([`past_corner`], [`end_of_steps`]).
        if vanishing
            && let Some(found) =
                speed_vanishing(curve, f, &self.u, &self.t, 2.0 * self.h, settings.range)
            && found.all
        {
            clear_approach(&mut self.pts, &found.row, f.half_gap());
            self.pts.push(found.row);
            return Some(End::GrazingEnd);
        }
        None
    }

    /// Whether the side ends at `next` before a point is added there: back on a point it went
    /// through (a closed curve, followed once), going back the way it came (a corner, not a
    /// fold), past the swept range, or out of impacts (where they end, located).
    fn ends_before(
        &mut self,
        curve: &mut Curve,
        f: &Forcing,
        next: &OnBranch,
        settings: &ContSettings,
    ) -> Option<End> {
        let (u, u_new) = (self.u, next.u);
        let trail = &self.trail;
        if trail.len() > 4
            && trail[..trail.len() - 4]
                .iter()
                .any(|(w, tw)| tw.dot(&self.t) > 0.9 && passes(w, &u, &u_new))
        {
            // Back on a point it went through, the same way: a closed curve (an isola, or a
            // loop the branch ran into) is followed once.
            return Some(End::Closed);
        }
        if self.u_before.is_some_and(|b| retraces(&b, &u, &u_new)) {
            // The corrector found the branch it came along: the branch has a corner here (a
            // grazing, where the map is not smooth), not a fold.
            if let Some(last) = self.pts.last_mut() {
                last.label = Label::GR;
            }
            return Some(End::Grazing);
        }
        let (_, lambda) = curve.unscale(&u_new);
        if lambda < settings.range.0 || lambda > settings.range.1 {
            self.pts
                .extend(at_range_end(curve, f, &u, &u_new, settings));
            return Some(End::Range);
        }
        if next.eval.impacts == 0 {
            // Where the impacts end, located; failing that, on the last impacting point.
            let (here, t, h) = (&self.here, &self.t, self.h);
            match locate_between(curve, f, here, next, t, h, Label::NI, settings) {
                Some((p, _)) => self.pts.push(p),
                None => {
                    if let Some(last) = self.pts.last_mut() {
                        last.label = Label::NI;
                    }
                }
            }
            return Some(End::NoImpacts);
        }
        None
    }

    /// The label of the point `orb` at `fl` (the corrector's `next`, tangent `t_new` there),
    /// located between the current point and it where it can be: a located label is a row of
    /// its own (pushed here) and the point past it is plain. A period doubling hands over its
    /// doubled branch (once per side), a located branch point its other branch (at most
    /// [`MAX_SWITCHES_PER_SIDE`]).
    #[allow(clippy::too_many_arguments)]
    fn label(
        &mut self,
        curve: &mut Curve,
        f: &Forcing,
        fl: &Forcing,
        orb: &Orbit,
        next: &OnBranch,
        t_new: &V5,
        settings: &ContSettings,
        switches: &mut Vec<(Forcing, Orbit)>,
    ) -> Label {
        let (label, locatable) = classify(&self.prev_orbit, orb, &self.t, t_new, fl);
        if label == Label::PD
            && locatable
            && !self.doubled
            && let Some(d) = doubled_orbit(fl, orb, &Newton::default())
        {
            switches.push((fl.clone(), d));
            self.doubled = true;
        }
        if !locatable {
            return label;
        }
        match locate_between(curve, f, &self.here, next, &self.t, self.h, label, settings) {
            Some((p, at)) => {
                let branch_point = p.label == Label::BP;
                self.pts.push(p);
                // At a branch point the other branch (the asymmetric pair of a symmetric
                // orbit) is followed too, at up to `MAX_SWITCHES_PER_SIDE` of them.
                if branch_point
                    && self.switched < MAX_SWITCHES_PER_SIDE
                    && let Some(o) = switch_at_branch_point(curve, f, &at, &self.t)
                {
                    switches.push(o);
                    self.switched += 1;
                }
                Label::None
            }
            // A multiplier that jumped across +1 or the unit circle (the monodromy matrix is
            // discontinuous where a sticking phase begins or ends) is not a branch point or a
            // torus: no label. The others stay on the point past the change.
            None if matches!(label, Label::BP | Label::NS) => Label::None,
            None => label,
        }
    }
}

/// The label between two consecutive points of a branch (`prev` then `orb`, tangents `t` then
/// `t_new`, the later one at `f`), and whether it can be located on the branch:
/// * the orbit's minimal period changes: `PD` (on `P^{2p}` the branch of period `p` and the
///   doubled one cross at the doubling; not located);
/// * the tangent's parameter component changes sign: `SN`;
/// * the impact count changes: `GR`;
/// * a real multiplier crosses `-1`: `PD`; `+1` (without a fold): `BP`;
/// * a complex pair crosses the unit circle: `NS`;
/// * an impact's approach speed is below `1e-3 omega d/2` (a graze on its way, the count not
///   yet changed): `GR`, not located.
fn classify(prev: &Orbit, orb: &Orbit, t: &V5, t_new: &V5, f: &Forcing) -> (Label, bool) {
    let det = |m: &super::map::Mat4, sign: f64| {
        (nalgebra::Matrix4::from_fn(|r, c| m[r][c]) - nalgebra::Matrix4::identity() * sign)
            .determinant()
    };
    let same_p = orb.period == prev.period;
    if !same_p {
        (Label::PD, false)
    } else if t_new[4].signum() != t[4].signum() {
        (Label::SN, true)
    } else if orb.impacts != prev.impacts {
        (Label::GR, true)
    } else if below_minus_one(orb) != below_minus_one(prev) {
        (Label::PD, true)
    } else if det(&orb.monodromy, 1.0).signum() != det(&prev.monodromy, 1.0).signum() {
        (Label::BP, true)
    } else if complex_outside(&orb.multipliers) != complex_outside(&prev.multipliers)
        && ns_value(&orb.multipliers).is_finite()
        && ns_value(&prev.multipliers).is_finite()
    {
        (Label::NS, true)
    } else if orb.min_impact_speed < 1e-3 * f.omega * f.half_gap() {
        (Label::GR, false)
    } else {
        (Label::None, false)
    }
}

/// `label` located between the points `here` and `next` (the step from `here` along `t` of
/// length `h` found `next`), as a branch point at the located parameter ([`super::locate`]);
/// `None` when it cannot be solved there or falls outside the swept range.
#[allow(clippy::too_many_arguments)]
fn locate_between(
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

/// The row of a located point `p` of `label` ([`locate_between`], [`end_of_steps`]): its orbit
/// by Newton, kept when it is inside the range and its bifurcation is there to
/// [`LOCATED_TOL`]. Counts it in `curve.located`.
fn located_row(
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
        && !super::graze::flight_gap(&fl, &orb.s, curve.p)
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
fn switch_at_branch_point(
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

/// The end of a branch whose steps failed down to the smallest: where the map one step past
/// the last point (at the last predictor `u_pred`) has another impact count than the last
/// point's orbit, the branch ran into a grazing it cannot pass (`grazing_end`). The grazing is
/// then located between the last point and the predictor from the smooth side
/// ([`locate::solve_grazing`]: a trial that fails or has another impact count is past it) and
/// is the branch's last row, `GR`; where that fails the last point is labelled `GR`. Otherwise
/// `step_too_small`.
fn end_of_steps(
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
fn vanishing_end(
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

/// Branch points on one side of a branch's start where the other branch is followed too (the
/// symmetric orbit loses its stability to the asymmetric pair below resonance and regains it
/// above).
const MAX_SWITCHES_PER_SIDE: u32 = 2;

/// The branch's point at the end of the range that the step from `u` to `u_new` left: the
/// corrector at the bound itself, from the chord's point there. `None` where it does not
/// converge (the branch then ends at its last point inside).
fn at_range_end(
    curve: &mut Curve,
    f: &Forcing,
    u: &V5,
    u_new: &V5,
    settings: &ContSettings,
) -> Option<BranchPoint> {
    let (_, l0) = curve.unscale(u);
    let (_, l1) = curve.unscale(u_new);
    let bound = l1.clamp(settings.range.0, settings.range.1);
    if l1 == l0 {
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
const SECTION_IMPACT_PERIODS: f64 = 1e-3;

/// The steps in the scaled parameter tried past a corner, smallest first.
const CORNER_NUDGES: [f64; 6] = [1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4];

/// How far (scaled) the point found past a corner may lie from where it was looked for: farther
/// is another branch.
const CORNER_REACH: f64 = 0.05;

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
fn past_corner(curve: &mut Curve, f: &Forcing, u: &V5, t: &V5) -> Option<(V5, V5, OnBranch)> {
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
const VANISHING_SPEED: f64 = 0.05;

/// `omega d/2` at the point `u` (m/s).
fn here_speed_scale(curve: &Curve, f: &Forcing, u: &V5) -> f64 {
    let (_, lambda) = curve.unscale(u);
    let fl = curve.param.at(f, lambda);
    fl.omega * fl.half_gap()
}

/// A located point where an impact's approach speed vanishes: its row and whether every impact
/// of the orbit vanishes there.
struct Vanishing {
    row: BranchPoint,
    all: bool,
}

/// The point ahead of `u` (the parameter moving as `t`'s parameter component does, at most
/// `reach` in the scaled parameter, inside `range`) where the orbit's slowest impact reaches its
/// wall with zero approach speed, solved in impact coordinates ([`super::sequence`]: on the
/// section the map's derivatives grow like the inverse of that speed and the corrector cannot
/// get there). Its row is labelled `GR`, located; its multipliers are `NaN`: the impact law's
/// saltation divides by the approach speed, and the multipliers of the orbits before it grow
/// without bound (so the row is not stable).
fn speed_vanishing(
    curve: &mut Curve,
    f: &Forcing,
    u: &V5,
    t: &V5,
    reach: f64,
    range: (f64, f64),
) -> Option<Vanishing> {
    use super::sequence::{ImpactOrbit, speed_zero};
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
fn clear_approach(pts: &mut [BranchPoint], row: &BranchPoint, half_gap: f64) {
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

/// Whether the step from `now` to `next` passes through `start`: `start` lies within 5 % of the
/// step's length (plus the corrector's tolerance) of the chord between them.
fn passes(start: &V5, now: &V5, next: &V5) -> bool {
    let chord = next - now;
    let len2 = chord.norm_squared();
    if len2 == 0.0 {
        return false;
    }
    let along = ((start - now).dot(&chord) / len2).clamp(0.0, 1.0);
    (now + chord * along - start).norm() <= 0.05 * len2.sqrt() + 1e-8
}

/// Whether `next` goes back along the branch through `before` and `now`: it is nearer `before`
/// than half the distance from `before` to `now`.
fn retraces(before: &V5, now: &V5, next: &V5) -> bool {
    (next - before).norm() < 0.5 * (now - before).norm()
}

/// The period-`2p` orbit born at a period doubling of `orb`: Newton on `P^{2p}` from the fixed
/// point pushed along the eigenvector of the multiplier near `-1`, both ways.
fn doubled_orbit(f: &Forcing, orb: &Orbit, newton: &Newton) -> Option<Orbit> {
    let m = nalgebra::Matrix4::from_fn(|r, c| orb.monodromy[r][c]);
    let (lam, _) = orb
        .multipliers
        .iter()
        .filter(|(re, im)| *re < 0.0 && im.abs() < 1e-9)
        .min_by(|a, b| (a.0 + 1.0).abs().total_cmp(&(b.0 + 1.0).abs()))?;
    let a = m - nalgebra::Matrix4::identity() * *lam;
    // The eigenvector: the null vector of `M - lambda I` by SVD.
    let svd = a.svd(false, true);
    let vt = svd.v_t?;
    let k = (0..4).min_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]))?;
    let v = vt.row(k);
    let l = f.half_gap();
    let norm = v.norm();
    let p2 = 2 * u64::from(orb.period);
    for sign in [1.0, -1.0] {
        let s: Section = std::array::from_fn(|i| orb.s[i] + sign * 1e-2 * l * v[i] / norm);
        if let (Termination::Converged { .. }, Some(st)) = solve(f, p2, &s, newton)
            && let Some(o) = orbit_at(f, p2, &st, newton)
            && u64::from(o.period) == p2
        {
            return Some(o);
        }
    }
    let _ = multipliers;
    None
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
