//! Locating a bifurcation between two consecutive continuation points
//! ([`super::continuation`]): the sign change of its test function is bracketed by the two
//! points and solved on the branch.
//!
//! # On the branch
//! A trial point at arclength `sigma` in `(0, h)` from the earlier point `u` (with tangent `t`)
//! is the corrector's point from the predictor `u + sigma t` on the hyperplane through it normal
//! to `t` (the step that found the later point used `sigma = h`). So every trial is a point of
//! the branch, to the corrector's tolerance, and `sigma` moves monotonically along it.
//!
//! # Test functions (docs/model.md, §12)
//! With `J` the exact Jacobian of `P^p` at the trial point and `t_lambda` the parameter component
//! of the unit tangent there (oriented along the earlier point's):
//! * `SN`, a fold: `t_lambda = 0`;
//! * `BP`, a branch point (a real multiplier through `+1` where the branch does not fold, as
//!   where the symmetric two-impact orbit meets its asymmetric pair): `det(J - I) = 0`;
//! * `PD`, a period doubling: `det(J + I) = 0`;
//! * `NS`, a Neimark–Sacker point (a complex pair through the unit circle; a torus is born):
//!   `|mu| - 1 = 0` for the complex pair of modulus nearest 1;
//! * `GR` and `NI`, grazing (the impact count changes: a new contact appears at zero speed, or
//!   an impact's approach speed reaches zero; `NI`, the impacts end): the map is not smooth
//!   there, so the impact count itself is the (discontinuous) test function. A grazing is solved
//!   from the smooth side ([`solve_grazing`]): the located row is the orbit without the contact,
//!   whose flight touches the wall ([`super::graze`]); `NI` keeps the side with the impacts.
//!
//! The smooth ones are solved by the Illinois variant of regula falsi, the grazings by
//! bisection, until the bracket in `sigma` (scaled arclength: `r / r_0` moves by at most as
//! much) is below [`SIGMA_TOL`]. Each trial is one corrector solve: a few evaluations of `P^p`.

use nalgebra::{Matrix4, SMatrix, SVector};

use super::label::Label;
use super::map::MapEval;
use super::shoot::multipliers;

type V5 = SVector<f64, 5>;

/// The bracket in scaled arclength below which a located point is taken: with `|t| = 1` the
/// parameter moves by at most `SIGMA_TOL * lambda_0`, well under `1e-8` in `r` or `F0 / F0_0`.
pub const SIGMA_TOL: f64 = 1e-11;
/// A located root's test function, relative to its larger value at the two bracketing points.
pub const ROOT_TOL: f64 = 1e-6;
/// Most trials for one located point.
const MAX_TRIALS: u32 = 80;

/// A point of the branch found by the corrector: scaled unknowns, the `4 x 5` Jacobian of the
/// extended system and the map's evaluation there.
#[derive(Clone, Debug)]
pub struct OnBranch {
    pub u: V5,
    pub a: SMatrix<f64, 4, 5>,
    pub eval: MapEval,
}

/// The value of `label`'s test function at `p` (module doc); `tangent` gives the unit tangent
/// at a point from its Jacobian (oriented along the earlier point's). NaN where it is not
/// defined (no Jacobian; no complex pair for `NS`).
pub fn test_function(
    label: Label,
    p: &OnBranch,
    tangent: &dyn Fn(&SMatrix<f64, 4, 5>) -> Option<V5>,
    impacts_left: u64,
) -> f64 {
    let j = || p.eval.jacobian.map(|m| Matrix4::from_fn(|r, c| m[r][c]));
    match label {
        Label::SN => tangent(&p.a).map_or(f64::NAN, |t| t[4]),
        Label::BP => j().map_or(f64::NAN, |m| (m - Matrix4::identity()).determinant()),
        Label::PD => j().map_or(f64::NAN, |m| (m + Matrix4::identity()).determinant()),
        Label::NS => p
            .eval
            .jacobian
            .map_or(f64::NAN, |m| ns_value(&multipliers(&m))),
        Label::GR | Label::NI => {
            if p.eval.impacts == impacts_left {
                1.0
            } else {
                -1.0
            }
        }
        Label::None => f64::NAN,
    }
}

/// `|mu| - 1` for the complex pair of the multipliers `mu` whose modulus is nearest 1; NaN
/// without a complex pair.
pub fn ns_value(mu: &[(f64, f64)]) -> f64 {
    mu.iter()
        .filter(|(re, im)| im.abs() > 1e-9 * re.abs().max(1.0))
        .map(|(re, im)| re.hypot(*im) - 1.0)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(f64::NAN)
}

/// How far the multipliers `mu` are from `label`'s bifurcation: the distance of the nearest
/// real multiplier from +1 (`SN`, `BP`) or -1 (`PD`), or of the modulus of the nearest complex
/// pair from 1 (`NS`); 0 for the grazings (their test is the impact count), infinite when no
/// multiplier of the kind exists.
pub fn multiplier_test(label: Label, mu: &[(f64, f64)]) -> f64 {
    let complex = |m: &&(f64, f64)| m.1.abs() > 1e-9 * m.0.abs().max(1.0);
    let real = |target: f64| {
        mu.iter()
            .filter(|m| !complex(m))
            .map(|m| (m.0 - target).abs())
            .fold(f64::INFINITY, f64::min)
    };
    match label {
        Label::SN | Label::BP => real(1.0),
        Label::PD => real(-1.0),
        Label::NS => mu
            .iter()
            .filter(complex)
            .map(|m| (m.0.hypot(m.1) - 1.0).abs())
            .fold(f64::INFINITY, f64::min),
        Label::GR | Label::NI | Label::None => 0.0,
    }
}

/// Complex multipliers among `mu` outside the unit circle (a change of this count between two
/// points is a Neimark–Sacker crossing).
pub fn complex_outside(mu: &[(f64, f64)]) -> usize {
    mu.iter()
        .filter(|(re, im)| im.abs() > 1e-9 * re.abs().max(1.0) && re.hypot(*im) > 1.0)
        .count()
}

/// Solves `label`'s test function between `sigma = 0` (value `phi0`) and `sigma = h` (value
/// `phi1`, of the other sign): `at(sigma)` corrects the trial point. Returns the located point
/// (for a grazing, the end of the final bracket with more impacts; otherwise the trial with the
/// smallest test function), or `None` when the test function is undefined at a trial, when the
/// sign changed through a jump rather than a root ([`ROOT_TOL`]), or (for a grazing) when the
/// corrector stops converging before the bracket is down to [`SIGMA_TOL`].
pub fn solve(
    label: Label,
    h: f64,
    (phi0, phi1): (f64, f64),
    mut at: impl FnMut(f64) -> Option<OnBranch>,
    phi: impl Fn(&OnBranch) -> f64,
) -> Option<OnBranch> {
    if phi0 * phi1 >= 0.0 || !(phi0 * phi1).is_finite() {
        return None;
    }
    let smooth = !matches!(label, Label::GR | Label::NI);
    let (mut a, mut fa, mut pa) = (0.0, phi0, None::<OnBranch>);
    let (mut b, mut fb, mut pb) = (h, phi1, None::<OnBranch>);
    // Which end the last two trials replaced (Illinois: halve the other end's value when the
    // same end moves twice).
    let mut side = 0i8;
    let mut best: Option<(f64, OnBranch)> = None;
    for _ in 0..MAX_TRIALS {
        if b - a <= SIGMA_TOL {
            break;
        }
        let s = if smooth {
            let s = (a * fb - b * fa) / (fb - fa);
            // Keep the trial strictly inside, away from the ends.
            let margin = 1e-3 * (b - a);
            s.clamp(a + margin, b - margin)
        } else {
            0.5 * (a + b)
        };
        // Where the corrector fails at the trial (at a branch point its system is singular,
        // and slow to converge next to it), a trial halfway to either end instead.
        let (s, p) = match [s, 0.5 * (a + s), 0.5 * (s + b)]
            .into_iter()
            .find_map(|s| at(s).map(|p| (s, p)))
        {
            Some(found) => found,
            // No trial converges any more: what the trials so far found decides.
            None => break,
        };
        let fs = phi(&p);
        if !fs.is_finite() {
            return None;
        }
        if best.as_ref().is_none_or(|(fb, _)| fs.abs() < *fb) {
            best = Some((fs.abs(), p.clone()));
        }
        if fs == 0.0 {
            return Some(p);
        }
        if fs.signum() == fa.signum() {
            (a, fa, pa) = (s, fs, Some(p));
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb, pb) = (s, fs, Some(p));
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    if smooth {
        // The trial with the smallest test function; a root only where the function is small
        // against its values at the two points (a sign change through a jump, where the
        // monodromy matrix is discontinuous, is not a root). Next to a branch point the
        // corrector may land on either branch through it, so the bracket can stall before its
        // tolerance while a trial has already solved the function: that trial stands.
        let (fp, p) = best?;
        (fp <= ROOT_TOL * phi0.abs().max(phi1.abs())).then_some(p)
    } else if b - a > SIGMA_TOL {
        None
    } else {
        // The grazing orbit: the side with more impacts.
        match (pa, pb) {
            (Some(x), Some(y)) => Some(if x.eval.impacts >= y.eval.impacts {
                x
            } else {
                y
            }),
            (x, y) => x.or(y),
        }
    }
}

/// Solves a grazing (`GR`) between `sigma = 0` and `sigma = h` by bisection on the impact count
/// (`phi` is `+1` or `-1`; `phi0`, `phi1` its values at the ends). `rough` is `phi`'s value on
/// the side with more impacts, where the grazing contact is an impact: the map's derivatives grow
/// like the inverse square root of the distance there, so a trial whose corrector fails counts
/// as that side. Returns the last trial on the other, smooth side once the bracket is below
/// [`SIGMA_TOL`]: the orbit whose flight passes the wall at a gap that shrinks with the bracket
/// ([`super::graze`]). `None` when no trial landed on the smooth side or the bracket stalls.
pub fn solve_grazing(
    h: f64,
    (phi0, phi1): (f64, f64),
    rough: f64,
    mut at: impl FnMut(f64) -> Option<OnBranch>,
    phi: impl Fn(&OnBranch) -> f64,
) -> Option<OnBranch> {
    if phi0 * phi1 >= 0.0 || !(phi0 * phi1).is_finite() {
        return None;
    }
    let (mut a, mut fa) = (0.0, phi0);
    let mut b = h;
    let mut smooth: Option<OnBranch> = None;
    for _ in 0..MAX_TRIALS {
        if b - a <= SIGMA_TOL {
            break;
        }
        let s = 0.5 * (a + b);
        let (fs, p) = match at(s) {
            Some(p) => (phi(&p), Some(p)),
            None => (rough, None),
        };
        if fs != rough {
            smooth = p.or(smooth);
        }
        if fs.signum() == fa.signum() {
            (a, fa) = (s, fs);
        } else {
            b = s;
        }
    }
    if b - a > SIGMA_TOL {
        return None;
    }
    smooth
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Illinois iteration solves a smooth function to the bracket tolerance, and bisection
    /// a sign step.
    #[test]
    fn a_sign_change_is_solved_to_the_tolerance() {
        let dummy = |s: f64| OnBranch {
            u: V5::new(0.0, 0.0, 0.0, 0.0, s),
            a: SMatrix::zeros(),
            eval: MapEval {
                outcome: crate::sim::Outcome::Ok,
                end: [0.0; 4],
                jacobian: None,
                d_param: None,
                amplitude: 0.0,
                impacts: 1,
                sticks: 0,
                min_impact_speed: 1.0,
            },
        };
        let root = 0.012_345_678_9;
        let f = |p: &OnBranch| (p.u[4] - root) * (1.0 + 30.0 * p.u[4]);
        let p = solve(
            Label::PD,
            0.05,
            (f(&dummy(0.0)), f(&dummy(0.05))),
            |s| Some(dummy(s)),
            f,
        )
        .unwrap();
        assert!((p.u[4] - root).abs() < 1e-11, "{}", p.u[4]);
        let step = |p: &OnBranch| if p.u[4] < root { 1.0 } else { -1.0 };
        let p = solve(Label::GR, 0.05, (1.0, -1.0), |s| Some(dummy(s)), step).unwrap();
        assert!((p.u[4] - root).abs() < 2e-11, "{}", p.u[4]);
    }
}
