//! Bifurcation curves in two parameters: a located fold, period doubling, Neimark–Sacker point
//! or grazing of a branch along `r` ([`super::locate`]) followed in `(r, p)`, `p` a
//! design axis (`m`, `d`, `e`, `C` or `F0`), by continuation of the minimally extended system
//! (docs/model.md, §12):
//!
//! ```text
//! P^q(s; r, p) - s = 0      (4 equations: the orbit)
//! phi(s; r, p)     = 0      (1 equation: the bifurcation's test function)
//! ```
//!
//! in the six unknowns `y = (s, r, p)` (scaled: `x / L`, `x' / (wn L)`, `z / L`, `y' / (wn L)`,
//! `r / r_0`, `p / p_0`, `L` the seed's half clearance), `phi` = `det(J - I)` for `SN`,
//! `det(J + I)` for `PD`, `|mu| - 1` of the complex pair nearest the unit circle for `NS`, the
//! signed grazing value relative to the half clearance for `GR` ([`super::graze::grazing_value`]:
//! a flight's gap to the wall on one side, the new impact's depth on the other). A grazing's
//! Newton steps stall at the kink of the map there (about `1e-9` scaled); its point is taken
//! on the smooth side once its residuals are within [`GRAZING_TOL`]. The
//! orbit's rows of the Jacobian are exact in `s` and `r` (the map's monodromy matrix and its
//! derivative in `omega`), forward differences in `p` (exact in `F0`); the test function's row is
//! forward differences throughout. Pseudo-arclength steps as in [`super::continuation`]; at each
//! value of `at_values` (a study's grid values of `p`) the curve's point is solved for exactly
//! (`p` fixed, Newton in `(s, r)`). A curve ends where it leaves the `p` or `r` range, where the
//! orbit's impact count changes (a grazing: the map is not smooth there; not for a grazing's own
//! curve), at a failed step below the smallest, where it creeps ([`STALL_POINTS`]), or after
//! [`MAX_POINTS`].

use nalgebra::{DMatrix, DVector, Matrix4};

use super::label::Label;
use super::locate::ns_value;
use super::map::{Forcing, MapEval, Section, eval};
use crate::sim::Outcome;

/// A grazing curve's point is taken when its scaled residuals (the orbit's and the grazing
/// value's relative to `d/2`) are within this: the tolerance of the continuation's corrector.
const GRAZING_TOL: f64 = 1e-9;

/// Most points of one curve on each side of its seed.
pub const MAX_POINTS: usize = 400;

/// A side whose last [`STALL_POINTS`] points advanced less than [`STALL_ARC`] in the scaled
/// coordinates (relative `r` and `p`, the section over `d/2`) is creeping: its corrector keeps
/// failing and halving the step, which then grows back by 1.3 and fails again. It ends there
/// instead of spending [`MAX_POINTS`] on a stretch that one ordinary step would cover (on a
/// 100-design forced study a fold's curve crept 800 points over 0.1 % of `m`).
pub const STALL_POINTS: usize = 100;
pub const STALL_ARC: f64 = 0.01;

/// The design axis a bifurcation is followed in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Inner mass `m` (kg).
    M,
    /// Clearance `d` (m).
    D,
    /// Coefficient of restitution `e`.
    E,
    /// Damping coefficient `C` (N s/m).
    C,
    /// Force amplitude `F0` (N).
    F0,
}

impl Axis {
    /// The axis of a study key (`m`, `d`, `e`, `C`, `F0`); `None` for any other.
    pub fn of_key(key: &str) -> Option<Axis> {
        Some(match key {
            "m" => Axis::M,
            "d" => Axis::D,
            "e" => Axis::E,
            "C" => Axis::C,
            "F0" => Axis::F0,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Axis::M => "m",
            Axis::D => "d",
            Axis::E => "e",
            Axis::C => "C",
            Axis::F0 => "F0",
        }
    }

    /// The axis's value at `f`.
    pub fn get(self, f: &Forcing) -> f64 {
        match self {
            Axis::M => f.sys.m,
            Axis::D => f.sys.d,
            Axis::E => f.sys.e,
            Axis::C => f.sys.C,
            Axis::F0 => f.F0,
        }
    }

    /// `f` with the axis set to `v`.
    pub fn at(self, f: &Forcing, v: f64) -> Forcing {
        let mut g = f.clone();
        match self {
            Axis::M => g.sys.m = v,
            Axis::D => g.sys.d = v,
            Axis::E => g.sys.e = v,
            Axis::C => g.sys.C = v,
            Axis::F0 => g.F0 = v,
        }
        g
    }
}

/// One point of a bifurcation curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// The design axis's value and the frequency ratio.
    pub p: f64,
    pub r: f64,
    /// The orbit's section state, amplitude (m), period (forcing periods) and impacts per
    /// forcing period.
    pub s: Section,
    pub amplitude: f64,
    pub period: u32,
    pub impacts_per_period: f64,
    /// The point is at one of the requested values of `p` exactly.
    pub at_value: bool,
}

/// A followed bifurcation curve, its points in order of arclength.
#[derive(Clone, Debug, PartialEq)]
pub struct BifurcationCurve {
    pub label: Label,
    pub axis: Axis,
    pub points: Vec<CurvePoint>,
    /// Forcing periods simulated.
    pub periods: u64,
}

type V6 = DVector<f64>;

struct System2<'a> {
    base: &'a Forcing,
    label: Label,
    axis: Axis,
    q: u64,
    l: f64,
    wn: f64,
    r0: f64,
    p0: f64,
    periods: u64,
}

impl System2<'_> {
    fn unscale(&self, y: &V6) -> (Section, f64, f64) {
        (
            [
                y[0] * self.l,
                y[1] * self.wn * self.l,
                y[2] * self.l,
                y[3] * self.wn * self.l,
            ],
            y[4] * self.r0,
            y[5] * self.p0,
        )
    }

    fn forcing(&self, r: f64, p: f64) -> Forcing {
        self.axis.at(self.base, p).at_ratio(r)
    }

    fn eval(&mut self, y: &V6) -> Option<MapEval> {
        let (s, r, p) = self.unscale(y);
        if !(r > 0.0 && p > 0.0) {
            return None;
        }
        let e = eval(&self.forcing(r, p), &s, self.q, true);
        self.periods += self.q;
        (e.outcome == Outcome::Ok && e.jacobian.is_some()).then_some(e)
    }

    /// The test function at `y`, whose evaluation is `e`. A grazing's is the signed grazing
    /// value relative to the half clearance ([`super::graze::grazing_value`]: one more run).
    fn phi(&mut self, y: &V6, e: &MapEval) -> f64 {
        if self.label == Label::GR {
            let (s, r, p) = self.unscale(y);
            let f = self.forcing(r, p);
            self.periods += self.q;
            return super::graze::grazing_value(&f, &s, self.q).map_or(f64::NAN, |g| g / self.l);
        }
        let Some(j) = e.jacobian else {
            return f64::NAN;
        };
        let m = Matrix4::from_fn(|r, c| j[r][c]);
        match self.label {
            Label::SN | Label::BP => (m - Matrix4::identity()).determinant(),
            Label::PD => (m + Matrix4::identity()).determinant(),
            Label::NS => ns_value(&super::shoot::multipliers(&j)),
            _ => f64::NAN,
        }
    }

    /// The scaled orbit residual `P^q(s) - s`.
    fn orbit_residual(&self, y: &V6, e: &MapEval) -> [f64; 4] {
        let (s, _, _) = self.unscale(y);
        let sc = self.scales();
        std::array::from_fn(|i| (e.end[i] - s[i]) * sc[i])
    }

    fn scales(&self) -> [f64; 4] {
        let (a, b) = (1.0 / self.l, 1.0 / (self.wn * self.l));
        [a, b, a, b]
    }

    /// `G(y)` (5) and its `5 x 6` Jacobian, with the evaluation at `y`.
    fn system(&mut self, y: &V6) -> Option<(DVector<f64>, DMatrix<f64>, MapEval)> {
        let e = self.eval(y)?;
        let res = self.orbit_residual(y, &e);
        let phi0 = self.phi(y, &e);
        if !phi0.is_finite() {
            return None;
        }
        let sc = self.scales();
        let j = e.jacobian?;
        let dp = e.d_param?;
        let mut a = DMatrix::zeros(5, 6);
        for r in 0..4 {
            for c in 0..4 {
                let id = if r == c { 1.0 } else { 0.0 };
                a[(r, c)] = sc[r] * (j[r][c] - id) / sc[c];
            }
            // omega = r wn: d/d(r / r0) = wn r0 d/domega.
            a[(r, 4)] = sc[r] * dp.omega[r] * self.wn * self.r0;
        }
        // The p column: exact in F0, forward differences otherwise.
        let dp_col: [f64; 4] = if self.axis == Axis::F0 {
            std::array::from_fn(|r| sc[r] * dp.force[r] * self.p0)
        } else {
            let h = 1e-6;
            let mut y1 = y.clone();
            y1[5] += h;
            let e1 = self.eval(&y1)?;
            std::array::from_fn(|r| sc[r] * (e1.end[r] - e.end[r]) / h)
        };
        for (r, v) in dp_col.iter().enumerate() {
            a[(r, 5)] = *v;
        }
        // The test function's row by forward differences (a grazing's needs no map evaluation:
        // its test function is a run of its own).
        let h = 1e-7;
        for c in 0..6 {
            let mut y1 = y.clone();
            y1[c] += h;
            let phi1 = if self.label == Label::GR {
                self.phi(&y1, &e)
            } else {
                let e1 = self.eval(&y1)?;
                self.phi(&y1, &e1)
            };
            if !phi1.is_finite() {
                return None;
            }
            a[(4, c)] = (phi1 - phi0) / h;
        }
        let g = DVector::from_iterator(5, res.iter().copied().chain(std::iter::once(phi0)));
        Some((g, a, e))
    }

    /// The unit null vector of `a` oriented along `prev`.
    fn tangent(a: &DMatrix<f64>, prev: &V6) -> Option<V6> {
        let mut m = DMatrix::zeros(6, 6);
        m.view_mut((0, 0), (5, 6)).copy_from(a);
        m.set_row(5, &prev.transpose());
        let mut rhs = DVector::zeros(6);
        rhs[5] = 1.0;
        let t = m.lu().solve(&rhs)?;
        let n = t.norm();
        (n.is_finite() && n > 0.0).then(|| t / n)
    }

    /// Newton on `(G(y), t . (y - y_pred)) = 0`; or, with `fixed_p`, on `G(y) = 0` with `p`
    /// held.
    fn correct(&mut self, y_pred: &V6, t: Option<&V6>) -> Option<(V6, DMatrix<f64>, MapEval)> {
        let mut y = y_pred.clone();
        for _ in 0..10 {
            let (g, a, e) = self.system(&y)?;
            // A grazing's Newton steps cross the grazing, where the map is not smooth: they
            // stall at the size of that kink (about 1e-9 scaled). The point on the smooth side
            // whose residuals are within the continuation corrector's tolerance stands.
            if self.label == Label::GR && g.norm() <= GRAZING_TOL {
                return Some((y, a, e));
            }
            let mut m = DMatrix::zeros(6, 6);
            m.view_mut((0, 0), (5, 6)).copy_from(&a);
            let mut rhs = DVector::zeros(6);
            rhs.rows_mut(0, 5).copy_from(&(-&g));
            match t {
                Some(t) => {
                    m.set_row(5, &t.transpose());
                    rhs[5] = -t.dot(&(&y - y_pred));
                }
                None => m[(5, 5)] = 1.0,
            }
            let dy = m.lu().solve(&rhs)?;
            if !dy.iter().all(|v| v.is_finite()) || dy.norm() > 0.2 {
                return None;
            }
            y += &dy;
            if dy.norm() <= 1e-11 {
                return Some((y, a, e));
            }
        }
        None
    }

    fn point(&self, y: &V6, e: &MapEval, at_value: bool) -> CurvePoint {
        let (s, r, p) = self.unscale(y);
        CurvePoint {
            p,
            r,
            s,
            amplitude: e.amplitude,
            period: self.q as u32,
            impacts_per_period: e.impacts as f64 / self.q as f64,
            at_value,
        }
    }
}

/// A located bifurcation to follow: the system at the point, the orbit's section state and
/// period, and the label (`SN`, `BP`, `PD`, `NS` or `GR`).
#[derive(Clone, Debug)]
pub struct Seed {
    pub f: Forcing,
    pub s: Section,
    pub period: u32,
    pub label: Label,
}

/// Follows the bifurcation `seed` in `(r, axis)` over `p_range` and `r_range`; `at_values` are
/// the values of `axis` where the curve's point is solved for exactly (a study's grid). `None`
/// when the seed does not solve the extended system (a label other than `SN`, `PD`, `NS` and
/// `GR`; or a `BP`, where the orbit's own Jacobian is singular: following it needs the symmetric
/// subspace, not built).
pub fn follow(
    seed: &Seed,
    axis: Axis,
    p_range: (f64, f64),
    r_range: (f64, f64),
    at_values: &[f64],
) -> Option<BifurcationCurve> {
    let Seed {
        f,
        s,
        period,
        label,
    } = seed;
    let (f, label, period) = (f, *label, *period);
    if !matches!(
        label,
        Label::SN | Label::BP | Label::PD | Label::NS | Label::GR
    ) {
        return None;
    }
    let mut sys = System2 {
        base: f,
        label,
        axis,
        q: u64::from(period.max(1)),
        l: f.half_gap(),
        wn: f.sys.omega(),
        r0: f.ratio(),
        p0: axis.get(f),
        periods: 0,
    };
    let sc = sys.scales();
    let y0 = DVector::from_iterator(6, (0..4).map(|i| s[i] * sc[i]).chain([1.0, 1.0]));
    // The seed, polished with p held.
    let (y0, a0, e0) = sys.correct(&y0, None)?;
    let impacts = e0.impacts;
    let mut sides: Vec<Vec<CurvePoint>> = [-1.0, 1.0]
        .into_iter()
        .map(|dir| {
            let side = Side {
                p_range,
                r_range,
                at_values,
                impacts,
            };
            side.follow(&mut sys, &y0, &a0, dir)
        })
        .collect();
    let mut points: Vec<CurvePoint> = sides.remove(0);
    points.reverse();
    points.push(sys.point(&y0, &e0, at_values.contains(&sys.p0)));
    points.extend(sides.remove(0));
    Some(BifurcationCurve {
        label,
        axis,
        points,
        periods: sys.periods,
    })
}

/// What one side of a two-parameter curve is followed within ([`follow`]).
struct Side<'a> {
    p_range: (f64, f64),
    r_range: (f64, f64),
    /// Values of the second parameter where a point is solved for exactly.
    at_values: &'a [f64],
    /// The seed's impacts per period (a smooth bifurcation's curve ends where they change).
    impacts: u64,
}

impl Side<'_> {
    /// The points from the seed `y0` (extended Jacobian `a0`) in direction `dir` of the second
    /// parameter, in order away from it: until the corrector fails below the smallest step, the
    /// impacts change (not for a grazing), the curve leaves the ranges or stalls, or
    /// [`MAX_POINTS`].
    fn follow(&self, sys: &mut System2, y0: &V6, a0: &DMatrix<f64>, dir: f64) -> Vec<CurvePoint> {
        let mut prev = DVector::zeros(6);
        prev[5] = dir;
        let mut pts = Vec::new();
        let Some(mut t) = System2::tangent(a0, &prev) else {
            return pts;
        };
        let mut y = y0.clone();
        let mut h = 0.02;
        let mut done = self.at_values.to_vec();
        let mut trail: std::collections::VecDeque<DVector<f64>> = Default::default();
        // The seed's own value is the seed.
        done.retain(|&v| (v - sys.p0).abs() > 1e-12 * v.abs().max(1.0));
        while pts.len() < MAX_POINTS {
            let y_pred = &y + &t * h;
            let Some((y1, a1, e1)) = sys.correct(&y_pred, Some(&t)) else {
                h *= 0.5;
                if h < 1e-6 {
                    break;
                }
                continue;
            };
            // Off a grazing's curve the impact count changes where a smooth bifurcation's
            // orbit meets a grazing; a grazing's own curve may sit on either side of it.
            if e1.impacts != self.impacts && sys.label != Label::GR {
                break;
            }
            let (_, r1, p1) = sys.unscale(&y1);
            at_grid_values(sys, &y, &y1, p1, &mut done, &mut pts);
            let (p_range, r_range) = (self.p_range, self.r_range);
            if p1 < p_range.0 || p1 > p_range.1 || r1 < r_range.0 || r1 > r_range.1 {
                break;
            }
            pts.push(sys.point(&y1, &e1, false));
            trail.push_back(y1.clone());
            if trail.len() > STALL_POINTS
                && let Some(old) = trail.pop_front()
                && (&y1 - old).norm() < STALL_ARC
            {
                break;
            }
            let Some(t1) = System2::tangent(&a1, &t) else {
                break;
            };
            y = y1;
            t = t1;
            h = (h * 1.3).min(0.05);
        }
        pts
    }
}

/// The grid values of `p` in `done` crossed by the step from `y` to `y1` (at `p1`), each solved
/// for exactly (its point pushed onto `pts`) and taken out of `done`.
fn at_grid_values(
    sys: &mut System2,
    y: &V6,
    y1: &V6,
    p1: f64,
    done: &mut Vec<f64>,
    pts: &mut Vec<CurvePoint>,
) {
    let (_, _, p_prev) = sys.unscale(y);
    for v in done.clone() {
        if (v - p_prev) * (v - p1) <= 0.0 && v != p_prev {
            let w = (v - p_prev) / (p1 - p_prev);
            let mut yv = y + (y1 - y) * w;
            yv[5] = v / sys.p0;
            if let Some((yv, _, ev)) = sys.correct(&yv, None) {
                // `p` is the grid value itself (not `v / p0 * p0`).
                pts.push(CurvePoint {
                    p: v,
                    ..sys.point(&yv, &ev, true)
                });
            }
            done.retain(|&x| x != v);
        }
    }
}
