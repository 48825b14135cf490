//! Continuation of a periodic orbit of several units along the frequency ratio `r`
//! (docs/model.md §14): pseudo-arclength predictor–corrector on
//! `F(q, r) = P^p(q; r) - q = 0` in the reduced section ([`super::shoot`]: the units in step at
//! the start stay in step), with the bifurcations between points labelled.
//!
//! # Predictor–corrector
//! Unknowns `u = (q, r)`, `q` the reduced state in scaled coordinates (`x / L`, `x' / (wn L)`,
//! the same for each group; `L = d/2`). The extended Jacobian is `[J - I | dF/dr]`, `J` the
//! reduced monodromy matrix ([`super::shoot::monodromy`]: exact where impacts come one unit at a
//! time, central differences of the exact map elsewhere) and `dF/dr` by central differences in
//! `r` (step `1e-7 r`). The tangent `t` spans its null space (the bordered system with the
//! previous tangent), oriented like the previous one. The predictor is `u + h t`; the corrector
//! is Newton on `(F(u), t . (u - u_pred)) = 0`, which crosses folds where `r` turns back, to a
//! residual of `1e-10 L` (the shooting's tolerance) within [`MAX_CORRECTIONS`] iterations. A
//! step that converges within 3 iterations grows `h` by 1.5 (up to `h_max`); a failed one halves
//! it, and so does one whose point lies off the tangent's way (the step `u_new - u` at more than
//! 60° from `t`, [`MIN_STEP_COSINE`]: the corrector went back along the branch, or across to
//! another, from a long prediction near a sharp turn). Below `h_min` the orbit is shot directly a little further along `r` (`1e-4 r`, then
//! `1e-3 r`: past a point where the map is not smooth but the orbit goes on, as where an event
//! of the period map changes order) and the walk goes on from there with `h0`; when that fails
//! too, the branch ends (`step_too_small`, or `grazing_end` below).
//!
//! # Units at rest
//! A group of units that makes no impact over the orbit (at rest in its cavity while the others
//! rattle: its row of the monodromy matrix is free, [`super::shoot::free_mask`]) may rest
//! anywhere its cavity lets it: the orbits make a family, `J - I` is singular along it and the
//! corrector could not converge. Such a group is held where the orbit followed has it, relative
//! to the ground (`y = z + x` at the first point, `y' = 0`): its coordinates leave the unknowns,
//! its `z = y - x` moves with the structure. Where it starts to impact, the impacts change and
//! the branch ends there (`grazing_end`).
//!
//! # Labels
//! Between two consecutive points; `SN`, `PD`, `NS` and `BP` are located between them
//! ([`LOCATED`]): the bracket is bisected, each midpoint of the chord corrected onto the branch
//! orthogonally to the chord, to [`LOCATE_TOL`] in the scaled arclength; the located point is a
//! row of its own, kept where its multiplier lies within [`LOCATED_MULTIPLIER_TOL`] of the
//! bifurcation's value. Where that fails (a corrector does not converge, another change shows in
//! the bracket, or the bracket narrows onto a jump of the multipliers, where the map is not
//! smooth though the impacts stay) and for `GR`, the label sits on the point past the change:
//! * `SN`, a fold: the tangent's `r` component changes sign and `det(J - I)` with it (a real
//!   multiplier crosses 1). Where `r` turns back without that, the walk met a point where the
//!   map is not smooth though the impacts per orbit stay (an impact's order changes) and went
//!   back along the half it came: the branch ends at the last point before it
//!   (`step_too_small`);
//! * `PD`: the count of real multipliers below `-1` changes;
//! * `NS`: the count of complex multipliers outside the unit circle changes;
//! * `BP`: the sign of `det(J - I)` (the product of `mu - 1` over the multipliers) changes
//!   without a fold;
//! * `GR`: the impacts per orbit change (an impact grazes); the branch ends there
//!   (`grazing_end`): the map is not smooth across it. Where the steps fail down to `h_min`
//!   and the impacts change just past the last point, the branch ends `grazing_end` too
//!   (one unit's continuation goes on along the changed impact sequence; this one does not).
//!
//! The multipliers are those the census reports ([`super::shoot::orbit_at`]: the relative modes
//! of units in step and the free modes of a group at rest are set apart). Every branch ends with
//! a named reason ([`End`]): `range`, `no_impacts`, `step_too_small`, `max_points`, `simulator`,
//! `grazing_end`, `closed` (the step passed through a point it went through, the same way: a
//! closed curve is followed once, and the other side is empty). Each step is a bounded number of map evaluations. Pure.

use nalgebra::{DMatrix, DVector};

use super::map::{UnitsEval, distance, eval, expand, groups, reduce};
use super::shoot::{UnitsNewton, UnitsOrbit, free_mask, monodromy, orbit_at};
use crate::orbits::continuation::{End, passes};
use crate::orbits::label::Label;
use crate::orbits::map::Forcing;
use crate::orbits::shoot::Newton;
use crate::sim::Outcome;

/// Corrector iterations per step.
pub const MAX_CORRECTIONS: u32 = 6;

/// The labels located between two points (module doc, "Labels"); a grazing (`GR`) is not.
pub const LOCATED: [Label; 4] = [Label::SN, Label::PD, Label::NS, Label::BP];

/// Bisections of a located point at most, and the width (in the scaled arclength) of the
/// bracket it stops at.
pub const LOCATE_STEPS: u32 = 40;
pub const LOCATE_TOL: f64 = 1e-8;

/// The smallest cosine between a step (from the last point to the corrected one) and the
/// tangent it was predicted along: a step further off the tangent is refused and halved
/// (module doc).
pub const MIN_STEP_COSINE: f64 = 0.5;

/// The settings of a continuation of several units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitsContSettings {
    /// The interval of `r` followed.
    pub range: (f64, f64),
    /// First, smallest and largest step in the scaled arclength.
    pub h0: f64,
    pub h_min: f64,
    pub h_max: f64,
    /// Most points each way.
    pub max_points: usize,
}

/// One point of a branch: the orbit at `r` and its label.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsBranchPoint {
    pub r: f64,
    pub orbit: UnitsOrbit,
    pub label: Label,
    /// The point is its label's located point (module doc, "Labels"); a label on a point that
    /// is not located sits on the first point past the change.
    pub located: bool,
}

/// A branch in the order of the curve (`r` may turn back at folds), its ends (the low side's
/// first) and the forcing periods it simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsBranch {
    pub points: Vec<UnitsBranchPoint>,
    pub ends: (End, End),
    pub periods: u64,
}

/// The curve walked: the forcing at the start, the period, the groups and the scales.
struct Walk<'a> {
    base: &'a Forcing,
    p: u64,
    groups: Vec<Vec<usize>>,
    /// The coordinates of the reduced state that are unknowns: the structure's and those of
    /// every group that impacts over the orbit.
    active: Vec<usize>,
    /// The groups at rest in their cavities over the orbit (no impact), each with its position
    /// relative to the ground `y` (m), held: `z = y - x`, `y' = 0` (module doc, "Units at rest").
    held: Vec<(usize, f64)>,
    n: usize,
    l: f64,
    wn: f64,
    periods: u64,
}

/// A converged point with its tangent and the corrector's iterations.
struct Solved {
    u: DVector<f64>,
    ext: DMatrix<f64>,
    orbit: UnitsOrbit,
    iterations: u32,
}

impl<'a> Walk<'a> {
    /// The walk at `f` along orbits like `like` (its period, groups and groups at rest), the
    /// groups at rest held where the state `s` has them.
    fn new(f: &'a Forcing, like: &UnitsOrbit, s: &[f64]) -> Walk<'a> {
        let groups = groups(f, &like.s);
        let (active, held) = unknowns(like, &groups, s);
        Walk {
            base: f,
            p: u64::from(like.period),
            groups,
            active,
            held,
            n: like.s.len() / 2 - 1,
            l: f.half_gap(),
            wn: f.sys.omega(),
            periods: 0,
        }
    }

    fn scale_of(&self, k: usize) -> f64 {
        if k % 2 == 1 { self.wn * self.l } else { self.l }
    }

    /// `u` of a full state `s` at `r`.
    fn u_of(&self, s: &[f64], r: f64) -> DVector<f64> {
        let q = reduce(s, &self.groups);
        let dim = self.active.len();
        DVector::from_fn(dim + 1, |j, _| {
            if j < dim {
                let k = self.active[j];
                q[k] / self.scale_of(k)
            } else {
                r
            }
        })
    }

    /// The full state and `r` of `u`.
    fn state(&self, u: &DVector<f64>) -> (Vec<f64>, f64) {
        let dim = u.len() - 1;
        let mut q = vec![0.0; 2 + 2 * self.groups.len()];
        for (j, &k) in self.active.iter().enumerate() {
            q[k] = u[j] * self.scale_of(k);
        }
        for &(g, y) in &self.held {
            q[2 + 2 * g] = y - q[0];
            q[3 + 2 * g] = 0.0;
        }
        (expand(&q, &self.groups, self.n), u[dim])
    }

    fn eval_at(&mut self, s: &[f64], r: f64) -> UnitsEval {
        self.periods += self.p;
        eval(&self.base.at_ratio(r), s, self.p)
    }

    /// The scaled residual `F(u)`, the extended Jacobian `[J - I | dF/dr]` (scaled) and the map
    /// at `u`; `None` where the map is not differentiable or a run fails.
    fn residual(&mut self, u: &DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>, UnitsEval)> {
        let (s, r) = self.state(u);
        let f = self.base.at_ratio(r);
        let base = self.eval_at(&s, r);
        if base.outcome != Outcome::Ok {
            return None;
        }
        let dim = u.len() - 1;
        let end = reduce(&base.end, &self.groups);
        let q = reduce(&s, &self.groups);
        let res = DVector::from_fn(dim, |i, _| {
            let k = self.active[i];
            (end[k] - q[k]) / self.scale_of(k)
        });
        let (j, _) = monodromy(&f, &s, self.p, &base, &self.groups)?;
        self.periods += 2 * q.len() as u64 * self.p;
        let h = 1e-7 * r;
        let (ep, em) = (self.eval_at(&s, r + h), self.eval_at(&s, r - h));
        if [&ep, &em].iter().any(|e| {
            e.outcome != Outcome::Ok || e.impacts != base.impacts || e.sticks != base.sticks
        }) {
            return None;
        }
        let (rp, rm) = (reduce(&ep.end, &self.groups), reduce(&em.end, &self.groups));
        let mut ext = DMatrix::zeros(dim, dim + 1);
        for (ia, &a) in self.active.iter().enumerate() {
            for (ib, &b) in self.active.iter().enumerate() {
                let id = if a == b { 1.0 } else { 0.0 };
                // A held group's `z = y - x` moves with `x` (column 0).
                let held: f64 = if b == 0 {
                    self.held.iter().map(|&(g, _)| j[(a, 2 + 2 * g)]).sum()
                } else {
                    0.0
                };
                ext[(ia, ib)] = (j[(a, b)] - held - id) * self.scale_of(b) / self.scale_of(a);
            }
            ext[(ia, dim)] = (rp[a] - rm[a]) / (2.0 * h) / self.scale_of(a);
        }
        ext.iter()
            .all(|v| v.is_finite())
            .then_some((res, ext, base))
    }

    /// Why the steps from `u` along `t` failed down to `h_min`: `grazing_end` when, within
    /// `1e-3` of arclength past `u` (at `4 h_min`, `1e-4` and `1e-3`), the map's impacts differ
    /// from `prev`'s (an impact grazes there, where the map is not smooth), else
    /// `step_too_small`.
    fn failed_at(
        &mut self,
        u: &DVector<f64>,
        t: &DVector<f64>,
        h_min: f64,
        prev: &UnitsOrbit,
    ) -> End {
        for h in [4.0 * h_min, 1e-4, 1e-3] {
            let (s, r) = self.state(&(u + t * h));
            let e = self.eval_at(&s, r);
            if e.outcome == Outcome::Ok && e.impacts != prev.impacts {
                return End::GrazingEnd;
            }
        }
        End::StepTooSmall
    }

    /// A hop over a point where the corrector fails though the orbit goes on: Newton shooting
    /// at `r + 1e-4 r` (then `1e-3 r`) in the direction `t` moves `r`, from `u`'s state; the
    /// point found when it keeps `prev`'s period and impacts, with its tangent oriented along
    /// `r`. `None` at a fold (`t` along `r` vanishes) or when neither shot converges.
    fn hop(
        &mut self,
        u: &DVector<f64>,
        t: &DVector<f64>,
        prev: &UnitsOrbit,
        newton: &Newton,
    ) -> Option<Solved> {
        let dim = u.len() - 1;
        let dir = t[dim].signum();
        if t[dim].abs() < 1e-3 {
            return None;
        }
        let (s0, r0) = self.state(u);
        for rel in [1e-4, 1e-3] {
            let r = r0 * (1.0 + dir * rel);
            let f = self.base.at_ratio(r);
            let (end, state) = super::shoot::solve(&f, self.p, &s0, newton);
            self.periods += self.p * u64::from(state.as_ref().map_or(1, |s| s.iterations + 1));
            let (crate::orbits::shoot::Termination::Converged { .. }, Some(state)) = (end, state)
            else {
                continue;
            };
            let Some(orbit) = orbit_at(&f, self.p, &state, newton) else {
                continue;
            };
            if orbit.period != prev.period || orbit.impacts != prev.impacts {
                continue;
            }
            let u = self.u_of(&state.s, r);
            let Some((_, ext, _)) = self.residual(&u) else {
                continue;
            };
            return Some(Solved {
                u,
                ext,
                orbit,
                iterations: 0,
            });
        }
        None
    }

    /// Where `label` happens between the point `ua` (tangent `ta`, orbit `oa`) and the next
    /// point `ub` (module doc, "Labels"): bisection of the bracket, each midpoint of the chord
    /// corrected onto the branch in the hyperplane through it orthogonal to the chord, kept as
    /// the bracket's near end when `label` does not yet happen between the near end and it,
    /// else as its far end; the far end once the bracket is under [`LOCATE_TOL`], with its
    /// orbit, where its multiplier is the bifurcation's ([`at_bifurcation`]). `None` when a
    /// corrector fails, another change shows in the bracket, it does not narrow within
    /// [`LOCATE_STEPS`], or the multipliers jump there.
    fn locate(
        &mut self,
        ua: &DVector<f64>,
        ta: &DVector<f64>,
        oa: &UnitsOrbit,
        ub: &DVector<f64>,
        label: Label,
        newton: &Newton,
    ) -> Option<(DVector<f64>, UnitsOrbit)> {
        let dim = ua.len() - 1;
        let (mut lo, mut lo_t, mut lo_o) = (ua.clone(), ta.clone(), oa.clone());
        let mut hi = ub.clone();
        let mut found = None;
        for _ in 0..LOCATE_STEPS {
            let chord = &hi - &lo;
            if chord.norm() <= LOCATE_TOL {
                return found.filter(|(_, o)| at_bifurcation(o, label));
            }
            let along = &chord / chord.norm();
            let mid = self.correct(&lo + &chord * 0.5, &along, newton)?;
            let tm = Walk::tangent(&mid.ext, &lo_t)?;
            match classify(&lo_o, &mid.orbit, lo_t[dim], tm[dim]) {
                l if l == label => {
                    hi = mid.u.clone();
                    found = Some((mid.u, mid.orbit));
                }
                Label::None => (lo, lo_t, lo_o) = (mid.u, tm, mid.orbit),
                _ => return None,
            }
        }
        None
    }

    /// The unit tangent at a point with extended Jacobian `ext`, oriented like `prev`.
    fn tangent(ext: &DMatrix<f64>, prev: &DVector<f64>) -> Option<DVector<f64>> {
        let dim = ext.nrows();
        let mut m = DMatrix::zeros(dim + 1, dim + 1);
        m.view_mut((0, 0), (dim, dim + 1)).copy_from(ext);
        m.row_mut(dim).copy_from(&prev.transpose());
        let mut rhs = DVector::zeros(dim + 1);
        rhs[dim] = 1.0;
        let t = m.lu().solve(&rhs)?;
        let norm = t.norm();
        (norm.is_finite() && norm > 0.0).then(|| {
            let t = t / norm;
            if t.dot(prev) < 0.0 { -t } else { t }
        })
    }

    /// The corrector from the prediction `pred` along `t`: the converged point, or `None`.
    fn correct(&mut self, pred: DVector<f64>, t: &DVector<f64>, newton: &Newton) -> Option<Solved> {
        let dim = pred.len() - 1;
        let mut u = pred.clone();
        for it in 0..=MAX_CORRECTIONS {
            let (res, ext, base) = self.residual(&u)?;
            if res.norm() <= newton.tol {
                let (s, r) = self.state(&u);
                let state = UnitsNewton {
                    residual: distance(&self.base.at_ratio(r), &base.end, &s),
                    s,
                    iterations: it,
                    last: base,
                };
                let orbit = orbit_at(&self.base.at_ratio(r), self.p, &state, newton)?;
                return Some(Solved {
                    u,
                    ext,
                    orbit,
                    iterations: it,
                });
            }
            if it == MAX_CORRECTIONS {
                break;
            }
            let mut m = DMatrix::zeros(dim + 1, dim + 1);
            m.view_mut((0, 0), (dim, dim + 1)).copy_from(&ext);
            m.row_mut(dim).copy_from(&t.transpose());
            let mut rhs = DVector::zeros(dim + 1);
            rhs.rows_mut(0, dim).copy_from(&(-&res));
            rhs[dim] = -t.dot(&(&u - &pred));
            let delta = m.lu().solve(&rhs)?;
            if delta.iter().any(|v| !v.is_finite()) {
                return None;
            }
            u += delta;
        }
        None
    }
}

/// How near its bifurcation's value a located point's multiplier must lie
/// ([`at_bifurcation`]).
pub const LOCATED_MULTIPLIER_TOL: f64 = 1e-4;

/// Whether `o`, located for `label`, has the multiplier of that bifurcation within
/// [`LOCATED_MULTIPLIER_TOL`]: `-1` for `PD`, `1` for `SN` and `BP`, a complex pair on the unit
/// circle for `NS`. A bracket that narrows onto a jump of the multipliers (where the map is not
/// smooth though the impacts stay) has none there: the change is not that bifurcation's.
fn at_bifurcation(o: &UnitsOrbit, label: Label) -> bool {
    let near = |target: f64| {
        o.multipliers
            .iter()
            .any(|m| (m.0 - target).hypot(m.1) <= LOCATED_MULTIPLIER_TOL)
    };
    match label {
        Label::PD => near(-1.0),
        Label::SN | Label::BP => near(1.0),
        Label::NS => o
            .multipliers
            .iter()
            .any(|m| m.1.abs() > 1e-9 && (m.0.hypot(m.1) - 1.0).abs() <= LOCATED_MULTIPLIER_TOL),
        _ => false,
    }
}

/// Whether multiplier `m = (re, im)` is real (its imaginary part below `1e-9` of its modulus).
fn real(m: &(f64, f64)) -> bool {
    m.1.abs() <= 1e-9 * m.0.hypot(m.1).max(1e-300)
}

/// The sign of `det(J - I)` at `o`: the product of `mu - 1` over its real multipliers (a
/// complex pair's product is positive).
fn det_sign(o: &UnitsOrbit) -> f64 {
    o.multipliers
        .iter()
        .filter(|m| real(m))
        .map(|m| m.0 - 1.0)
        .product::<f64>()
        .signum()
}

/// Whether the walk from `a` to `b` turned back in `r` (tangents' `r` components `ta`, `tb` of
/// opposite signs) without a fold: no real multiplier crossed 1 (`det(J - I)` kept its sign).
/// The walk met a point where the map is not smooth though the impacts per orbit did not
/// change (an impact's order changed), and went back along the half it came (module doc).
fn turned_back(a: &UnitsOrbit, b: &UnitsOrbit, ta: f64, tb: f64) -> bool {
    ta * tb < 0.0 && det_sign(a) == det_sign(b)
}

/// The label between two consecutive orbits `a`, `b` whose tangents' `r` components are `ta`,
/// `tb` (module doc); `GR` where the impacts change.
fn classify(a: &UnitsOrbit, b: &UnitsOrbit, ta: f64, tb: f64) -> Label {
    let below = |o: &UnitsOrbit| {
        o.multipliers
            .iter()
            .filter(|m| real(m) && m.0 < -1.0)
            .count()
    };
    let outside = |o: &UnitsOrbit| {
        o.multipliers
            .iter()
            .filter(|m| !real(m) && m.0.hypot(m.1) > 1.0)
            .count()
    };
    let fold = ta * tb < 0.0;
    if a.impacts != b.impacts {
        Label::GR
    } else if fold {
        Label::SN
    } else if below(a) != below(b) {
        Label::PD
    } else if outside(a) != outside(b) {
        Label::NS
    } else if det_sign(a) != det_sign(b) {
        Label::BP
    } else {
        Label::None
    }
}

/// Follows the branch of `orbit` (a fixed point of `P^p` of several units at `f`) both ways in
/// `r` over `settings.range` (module doc). The branch's first point is `orbit`'s.
pub fn follow_units(f: &Forcing, orbit: &UnitsOrbit, settings: &UnitsContSettings) -> UnitsBranch {
    let newton = Newton::default();
    let mut walk = Walk::new(f, orbit, &orbit.s);
    let r0 = f.ratio();
    let u0 = walk.u_of(&orbit.s, r0);
    let start = UnitsBranchPoint {
        r: r0,
        orbit: orbit.clone(),
        label: Label::None,
        located: false,
    };
    let mut sides: Vec<(Vec<UnitsBranchPoint>, End)> = Vec::new();
    for dir in [-1.0, 1.0] {
        if sides.first().is_some_and(|(_, end)| *end == End::Closed) {
            // The first side went round the whole curve (or into a loop it follows once).
            sides.push((Vec::new(), End::Closed));
            continue;
        }
        sides.push(side(&mut walk, &u0, orbit, dir, settings, &newton));
    }
    let (mut down, end_down) = sides.remove(0);
    let (up, end_up) = sides.remove(0);
    down.reverse();
    down.push(start);
    down.extend(up);
    UnitsBranch {
        points: down,
        ends: (end_down, end_up),
        periods: walk.periods,
    }
}

/// Newton at `f`'s frequency on `P^p(s) - s = 0` from `s` with the groups `like` holds at rest
/// held where `s` has them (module doc, "Units at rest"; shooting on the whole section is
/// singular there): the converged full state, or `None` within 8 iterations. Pure.
pub fn shoot_holding(f: &Forcing, like: &UnitsOrbit, s: &[f64]) -> Option<Vec<f64>> {
    let mut walk = Walk::new(f, like, s);
    let r = f.ratio();
    let mut u = walk.u_of(s, r);
    let dim = u.len() - 1;
    for _ in 0..8 {
        let (res, ext, _) = walk.residual(&u)?;
        if res.norm() <= Newton::default().tol {
            return Some(walk.state(&u).0);
        }
        let delta = ext.columns(0, dim).into_owned().lu().solve(&(-res))?;
        if delta.iter().any(|v| !v.is_finite()) {
            return None;
        }
        for k in 0..dim {
            u[k] += delta[k];
        }
    }
    None
}

/// The unknowns of the walk from `orbit` on `groups`: the reduced coordinates of the structure
/// and of every group that impacts, and each group at rest (no impact over the orbit: its row of
/// the monodromy matrix is free, [`free_mask`]) with its position relative to the ground in the
/// state `s`, held.
fn unknowns(
    orbit: &UnitsOrbit,
    groups: &[Vec<usize>],
    s: &[f64],
) -> (Vec<usize>, Vec<(usize, f64)>) {
    let free = if orbit.monodromy.nrows() == 2 + 2 * groups.len() {
        free_mask(&orbit.monodromy, groups.len())
    } else {
        vec![false; groups.len()]
    };
    let q = reduce(s, groups);
    let mut active = vec![0, 1];
    let mut held = Vec::new();
    for (g, &at_rest) in free.iter().enumerate() {
        if at_rest {
            held.push((g, q[2 + 2 * g] + q[0]));
        } else {
            active.extend([2 + 2 * g, 3 + 2 * g]);
        }
    }
    (active, held)
}

/// One side of the branch from `u0` (the orbit `o0`), `dir` the sign of the first step in `r`.
fn side(
    walk: &mut Walk,
    u0: &DVector<f64>,
    o0: &UnitsOrbit,
    dir: f64,
    s: &UnitsContSettings,
    newton: &Newton,
) -> (Vec<UnitsBranchPoint>, End) {
    let dim = u0.len() - 1;
    let mut seed = DVector::zeros(dim + 1);
    seed[dim] = dir;
    let Some((_, ext, _)) = walk.residual(u0) else {
        return (Vec::new(), End::Simulator);
    };
    let Some(mut t) = Walk::tangent(&ext, &seed) else {
        return (Vec::new(), End::StepTooSmall);
    };
    let (mut u, mut prev) = (u0.clone(), o0.clone());
    let mut h = s.h0;
    let mut out = Vec::new();
    // The points gone through with their tangents, for a closed curve.
    let mut trail: Vec<(DVector<f64>, DVector<f64>)> = vec![(u0.clone(), t.clone())];
    while out.len() < s.max_points {
        let pred = &u + &t * h;
        // A corrector that lands off the tangent's way (back along the branch, or across to
        // another: a long prediction near a sharp turn) has not stepped on.
        let ahead = |n: &Solved| {
            let step = &n.u - &u;
            step.dot(&t) >= MIN_STEP_COSINE * step.norm()
        };
        let next = match walk.correct(pred, &t, newton).filter(ahead) {
            Some(next) => next,
            None if h * 0.5 >= s.h_min => {
                h *= 0.5;
                continue;
            }
            // Past a point where the map is not smooth but the orbit goes on (the corrector's
            // differences straddle an event): shooting a little further along `r`.
            None => match walk.hop(&u, &t, &prev, newton) {
                Some(next) => {
                    h = s.h0.min(s.h_max);
                    next
                }
                None => return (out, walk.failed_at(&u, &t, s.h_min, &prev)),
            },
        };
        if trail.len() > 4
            && trail[..trail.len() - 4].iter().any(|(w, tw)| {
                tw.dot(&t) > 0.9 && passes(w.as_slice(), u.as_slice(), next.u.as_slice())
            })
        {
            // Back on a point it went through, the same way: a closed curve (an isola, or a
            // loop the branch ran into) is followed once.
            return (out, End::Closed);
        }
        let r = next.u[dim];
        if r < s.range.0 || r > s.range.1 {
            return (out, End::Range);
        }
        let Some(tn) = Walk::tangent(&next.ext, &t) else {
            return (out, End::StepTooSmall);
        };
        if turned_back(&prev, &next.orbit, t[dim], tn[dim]) {
            return (out, End::StepTooSmall);
        }
        let mut label = classify(&prev, &next.orbit, t[dim], tn[dim]);
        if LOCATED.contains(&label)
            && let Some((at, orbit)) = walk.locate(&u, &t, &prev, &next.u, label, newton)
        {
            out.push(UnitsBranchPoint {
                r: at[dim],
                orbit,
                label,
                located: true,
            });
            label = Label::None;
        }
        out.push(UnitsBranchPoint {
            r,
            orbit: next.orbit.clone(),
            label,
            located: false,
        });
        if label == Label::GR {
            return (out, End::GrazingEnd);
        }
        if next.iterations <= 3 {
            h = (h * 1.5).min(s.h_max);
        }
        trail.push((next.u.clone(), tn.clone()));
        (u, t, prev) = (next.u, tn, next.orbit);
    }
    (out, End::MaxPoints)
}
