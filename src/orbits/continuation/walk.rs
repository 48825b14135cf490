//! One side of a branch, step by step (the module doc of [`super`]): predictor and corrector,
//! each new point's label ([`classify`]) located where it can be, the branches handed over at a
//! period doubling and a branch point, and the side's end (closed on itself, back the way it
//! came, past the swept range, out of impacts, at a grazing, out of steps).

use super::branch::{
    BranchPoint, ContSettings, Curve, End, GrazingOutcome, V5, below_minus_one, point, tangent,
};
use super::corners::{
    CORNER_REACH, VANISHING_SPEED, at_range_end, clear_approach, end_of_steps, here_speed_scale,
    past_corner, speed_vanishing,
};
use super::located::{locate_between, switch_at_branch_point};
use super::through::{outcome_beyond, through_grazing};
use crate::orbits::label::Label;
use crate::orbits::locate::{OnBranch, complex_outside, ns_value};
use crate::orbits::map::{Forcing, Section};
use crate::orbits::shoot::{Newton, Orbit, Termination, multipliers, orbit_at, solve};

/// The points on one side of the start (`dir` = the sign of the first step in `lambda`), how the
/// side ended and, at a grazing it ends at, what the motion becomes there.
pub(super) fn side(
    curve: &mut Curve,
    f: &Forcing,
    orbit: &Orbit,
    dir: f64,
    settings: &ContSettings,
    switches: &mut Vec<(Forcing, Orbit)>,
) -> (Vec<BranchPoint>, End, Option<GrazingOutcome>) {
    let u = curve.to_u(&orbit.s, curve.param.get(f));
    let Some((_, a, e)) = curve.residual(&u) else {
        return (Vec::new(), End::Simulator, None);
    };
    let Some(t) = tangent(&a, &V5::new(0.0, 0.0, 0.0, 0.0, dir)) else {
        return (Vec::new(), End::StepTooSmall, None);
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
        passed: Vec::new(),
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
        match step {
            Some(End::GrazingEnd) if walk.through(curve, f, settings) => {}
            Some(End::GrazingEnd) => {
                let outcome = walk.outcome(curve, f);
                return (walk.pts, End::GrazingEnd, Some(outcome));
            }
            Some(end) => return (walk.pts, end, None),
            None => {}
        }
    }
    (walk.pts, End::MaxPoints, None)
}

/// Most grazings one side of a branch is continued through ([`super::through`]).
pub(super) const MAX_PASSES: usize = 8;

/// One side of a branch being followed ([`side`]): its points so far and where it stands.
pub(super) struct Walk {
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
    /// The parameter values of the grazings passed ([`super::through`]): each is passed once.
    passed: Vec<f64>,
}

impl Walk {
    /// The side ended at a grazing (its last row): the orbit with the changed impact sequence
    /// past it ([`super::through::through_grazing`]) is the next point, and the walk goes on from it.
    /// Whether it does (at most [`MAX_PASSES`] times a side, once per grazing).
    fn through(&mut self, curve: &mut Curve, f: &Forcing, settings: &ContSettings) -> bool {
        let Some(row) = self.pts.last().cloned() else {
            return false;
        };
        let lambda = row.value(curve.param);
        let again = self
            .passed
            .iter()
            .any(|&p| (p - lambda).abs() <= 1e-6 * lambda.abs());
        if row.label != Label::GR || again || self.passed.len() >= MAX_PASSES {
            return false;
        }
        let Some(next) = through_grazing(curve, f, &row, self.t[4], settings) else {
            return false;
        };
        self.passed.push(lambda);
        self.pts.extend(next.fill);
        self.pts.push(point(&next.f, &next.orbit, Label::None));
        self.prev_orbit = next.orbit;
        self.trail.push((self.u, self.t));
        self.u_before = None;
        (self.u, self.t, self.here) = (next.u, next.t, next.here);
        self.h = settings.h0;
        self.crossed = false;
        true
    }

    /// What the motion becomes past the grazing where the side ends: a run from its last row
    /// (the grazing orbit) a little past it ([`super::through::outcome_beyond`]).
    fn outcome(&self, curve: &mut Curve, f: &Forcing) -> GrazingOutcome {
        let (s, lambda) = match self.pts.last() {
            Some(row) => (row.s, row.value(curve.param)),
            None => curve.unscale(&self.u),
        };
        outcome_beyond(curve, f, &s, lambda, self.t[4])
    }

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
        let state = crate::orbits::shoot::NewtonState {
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
            && trail[..trail.len() - 4].iter().any(|(w, tw)| {
                tw.dot(&self.t) > 0.9 && passes(w.as_slice(), u.as_slice(), u_new.as_slice())
            })
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
pub(super) fn classify(
    prev: &Orbit,
    orb: &Orbit,
    t: &V5,
    t_new: &V5,
    f: &Forcing,
) -> (Label, bool) {
    let det = |m: &crate::orbits::map::Mat4, sign: f64| {
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

/// Branch points on one side of a branch's start where the other branch is followed too (the
/// symmetric orbit loses its stability to the asymmetric pair below resonance and regains it
/// above).
pub(super) const MAX_SWITCHES_PER_SIDE: u32 = 2;

/// Whether the step from `now` to `next` passes through `start` (points of the walk's scaled
/// space, any dimension): `start` lies within 5 % of the step's length (plus the corrector's
/// tolerance) of the chord between them.
pub(crate) fn passes(start: &[f64], now: &[f64], next: &[f64]) -> bool {
    let dot = |a: &mut dyn Iterator<Item = f64>, b: &mut dyn Iterator<Item = f64>| {
        a.zip(b).map(|(x, y)| x * y).sum::<f64>()
    };
    let chord: Vec<f64> = next.iter().zip(now).map(|(b, a)| b - a).collect();
    let len2 = dot(&mut chord.iter().copied(), &mut chord.iter().copied());
    if len2 == 0.0 {
        return false;
    }
    let to_start = start.iter().zip(now).map(|(s, a)| s - a);
    let along = (dot(&mut to_start.clone(), &mut chord.iter().copied()) / len2).clamp(0.0, 1.0);
    let mut closest = now
        .iter()
        .zip(&chord)
        .zip(start)
        .map(|((a, c), s)| a + c * along - s);
    let off = dot(&mut closest.clone(), &mut closest).sqrt();
    off <= 0.05 * len2.sqrt() + 1e-8
}

/// Whether `next` goes back along the branch through `before` and `now`: it is nearer `before`
/// than half the distance from `before` to `now`.
pub(super) fn retraces(before: &V5, now: &V5, next: &V5) -> bool {
    (next - before).norm() < 0.5 * (now - before).norm()
}

/// The period-`2p` orbit born at a period doubling of `orb`: Newton on `P^{2p}` from the fixed
/// point pushed along the eigenvector of the multiplier near `-1`, both ways.
pub(super) fn doubled_orbit(f: &Forcing, orb: &Orbit, newton: &Newton) -> Option<Orbit> {
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
