//! A periodic orbit in impact coordinates: the forcing phases of its impacts and the state just
//! after its first impact are the unknowns, its impact sequence (which wall, in which order) is
//! fixed. Used where an impact's approach speed goes to zero (docs/model.md §12, "Corners: an
//! impact velocity vanishing").
//!
//! # Why
//! On the Poincaré section the map's derivatives grow like `1/u` as an impact's approach speed
//! `u` goes to zero (the impact instant moves like `dt = -(dy - dx) / u`), and Newton's basin
//! shrinks like `u^2 / |x''|`: continuation on the section creeps toward the parameter where the
//! speed vanishes and stops short of it. With the impact instants as unknowns the flights have
//! prescribed ends, every flight is in closed form, and the equations are smooth in the unknowns
//! and the parameter through `u = 0` (on the other side `u < 0`: a virtual orbit whose inner
//! mass would fly through the wall). Masri and Caughey's closed form ([`super::analytic`]) is this
//! system for the symmetric two-impact orbit with its symmetry built in.
//!
//! # The system
//! An orbit of `p` forcing periods with `n` impacts at phases `phi_1 < ... < phi_n` (`omega t`,
//! in `[0, 2 pi p)`) on the walls `s_k = +-1` (`z = y - x = s_k d/2`), and the state
//! `(x_1, x'_1, y'_1)` just after the first (`y_1 = x_1 + s_1 d/2`). Flight `k` runs from `phi_k`
//! to `phi_{k+1}` (`phi_{n+1} = phi_1 + 2 pi p`): the main mass in closed form
//! ([`crate::sim::harmonic::motion::Forced`]), the inner mass at constant velocity; each flight
//! ends on its wall and the impact law (eq. 3–4) gives the next start:
//!
//! ```text
//! z(phi_{k+1}-) - s_{k+1} d/2 = 0                          k = 1 .. n
//! (x, x', y') after the impact at phi_1 + 2 pi p  -  (x_1, x'_1, y'_1) = 0
//! ```
//!
//! `n + 3` equations in `n + 3` unknowns. Impact `k`'s approach speed is
//! `u_k = s_k (y' - x')` just before it. Where `u_j` vanishes is one more unknown, the
//! continuation parameter `lambda`, and one more equation, `u_j = 0`. Both are solved by Newton
//! with a central-difference Jacobian (the residual is closed-form: `n` flights), in the scaled
//! units of continuation (`x / L`, `x' / (wn L)`, phases in rad, `lambda / lambda_0`, `L = d/2`).
//!
//! # Ranges
//! Orbits whose every event is an impact (no sticking phase), `p >= 1`, `n >= 1`; any valid
//! system and forcing. A solution is returned only when it is an orbit of the simulator's
//! kind: phases in order, every other impact approaching its wall (`u_k > -1e-9 wn d/2`: others may vanish with it,
//! by a symmetry), and every flight
//! inside the clearance (`|z| <= d/2 (1 + 1e-9)` at the flight's local extrema).

use nalgebra::{DMatrix, DVector};

use super::analytic::local_extremes;
use super::map::{Forcing, Section};
use crate::sim::harmonic::motion::Forced;
use crate::sim::harmonic::simulate_harmonic;
use crate::sim::phase::impact;
use crate::sim::{Outcome, Probe, Request, State, Wall};

/// Newton iterations at most.
const MAX_ITERATIONS: usize = 40;
/// Converged when the scaled residual's norm is below this.
const TOLERANCE: f64 = 1e-12;
/// Central-difference step of the scaled unknowns.
const FD_STEP: f64 = 1e-7;
/// An impact's approach speed counts as zero down to `-1e-9 wn d/2` (rounding).
const SPEED_FLOOR: f64 = 1e-9;
/// Grid points per radian of the fastest rate when a flight is checked against the walls.
const POINTS_PER_RADIAN: f64 = 8.0;
/// Golden-section steps refining a flight's extremum.
const GOLDEN_STEPS: usize = 40;

/// An orbit's impacts over its `p` periods, from one simulation: phases and walls.
#[derive(Default)]
struct Impacts {
    /// `(t, wall sign)`.
    hits: Vec<(f64, f64)>,
    sticks: usize,
}

impl Probe for Impacts {
    fn impact(&mut self, t: f64, wall: Wall, _before: &State, _after: &State) {
        self.hits.push((t, wall.sign()));
    }
    fn stick(&mut self, _t: f64, _wall: Wall, _at: &State) {
        self.sticks += 1;
    }
}

/// An orbit of `p` periods with its impacts as unknowns (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct ImpactOrbit {
    /// Forcing periods of the orbit.
    pub p: u64,
    /// Each impact's wall, `+1` right (`z = +d/2`), `-1` left, in order.
    pub walls: Vec<f64>,
    /// Each impact's forcing phase `omega t` (rad), increasing, the first in `[0, 2 pi p)`.
    pub phases: Vec<f64>,
    /// `(x, x', y')` just after the first impact (m, m/s, m/s).
    pub after: [f64; 3],
}

/// What one evaluation of the system gives besides its residual.
struct Flown {
    /// The scaled residual (`n + 3`).
    residual: Vec<f64>,
    /// Each impact's approach speed `u_k` (m/s), signed (module doc).
    speeds: Vec<f64>,
    /// The state at the section (`t = 0 mod p T`), `(x, x', z, y')`.
    section: Section,
    /// Every flight's local extrema of `z` within the clearance (to `1e-9` of it); checked only
    /// when asked for ([`ImpactOrbit::fly`]), `true` otherwise.
    inside: bool,
    /// `(x, x', y')` just after each impact, in order (m, m/s, m/s).
    afters: Vec<[f64; 3]>,
}

impl ImpactOrbit {
    /// The orbit through section state `s` at `f` (a fixed point of `P^p`, as continuation has
    /// it): its impacts recorded by one simulation over `p` periods. `None` when the run fails,
    /// has no impact or a sticking phase.
    pub fn from_section(f: &Forcing, s: &Section, p: u64) -> Option<ImpactOrbit> {
        let sys = f.started(s);
        let mut rec = Impacts::default();
        let out = simulate_harmonic(
            &sys,
            &f.settings,
            &Request::default(),
            &f.scene(p),
            None,
            &mut rec,
        );
        if out.outcome != Outcome::Ok || rec.hits.is_empty() || rec.sticks > 0 {
            return None;
        }
        let t1 = rec.hits[0].0;
        // The state just after the first impact: the simulation again, up to it.
        let start = State {
            x: sys.x0,
            v: sys.v0,
            y: sys.y0,
            w: sys.w0,
        };
        let forced = Forced::new(f.sys.M, f.sys.K, f.sys.C, f.F0, f.omega);
        let (h0, g0) = forced.free_start(0.0, start.x, start.v);
        let jet = forced.jet(0.0, h0, g0, t1);
        let (v, w) = impact(f.sys.M, f.sys.m, f.sys.e, jet.v, start.w);
        Some(ImpactOrbit {
            p,
            walls: rec.hits.iter().map(|h| h.1).collect(),
            phases: rec.hits.iter().map(|h| h.0 * f.omega).collect(),
            after: [jet.x, v, w],
        })
    }

    /// Each impact's approach speed `u_k` (m/s) at `f`, in order: positive approaching the wall.
    pub fn speeds(&self, f: &Forcing) -> Vec<f64> {
        self.fly(f, false).speeds
    }

    /// The scaled unknowns: phases, `x_1 / L`, `x'_1 / (wn L)`, `y'_1 / (wn L)`.
    fn to_unknowns(&self, l: f64, wn: f64) -> Vec<f64> {
        let mut u = self.phases.clone();
        u.extend([
            self.after[0] / l,
            self.after[1] / (wn * l),
            self.after[2] / (wn * l),
        ]);
        u
    }

    fn with_unknowns(&self, u: &[f64], l: f64, wn: f64) -> ImpactOrbit {
        let n = self.walls.len();
        ImpactOrbit {
            p: self.p,
            walls: self.walls.clone(),
            phases: u[..n].to_vec(),
            after: [u[n] * l, u[n + 1] * wn * l, u[n + 2] * wn * l],
        }
    }

    /// The flights of the orbit at `f` (module doc); with `check_walls`, each flight's local
    /// extrema of `z` are checked against the clearance (a grid of 8 points per radian of the
    /// fastest rate, each extremum refined by golden-section search).
    fn fly(&self, f: &Forcing, check_walls: bool) -> Flown {
        let (big_m, m, e) = (f.sys.M, f.sys.m, f.sys.e);
        let forced = Forced::new(big_m, f.sys.K, f.sys.C, f.F0, f.omega);
        let l = f.half_gap();
        let wn = f.sys.omega();
        let n = self.walls.len();
        let span = std::f64::consts::TAU * self.p as f64;
        let [x1, v1, w1] = self.after;
        let mut a = State {
            x: x1,
            v: v1,
            y: x1 + self.walls[0] * l,
            w: w1,
        };
        let mut residual = Vec::with_capacity(n + 3);
        let mut speeds = Vec::with_capacity(n);
        let mut section = [f64::NAN; 4];
        let mut afters = vec![[f64::NAN; 3]; n];
        let mut inside = true;
        let rate = f.omega.max(wn).max(f.sys.C / big_m);
        for k in 0..n {
            let phi_a = self.phases[k];
            let phi_b = self.phases.get(k + 1).map_or(self.phases[0] + span, |&p| p);
            let (t_a, t_b) = (phi_a / f.omega, phi_b / f.omega);
            let (h0, g0) = forced.free_start(t_a, a.x, a.v);
            let jet = forced.jet(t_a, h0, g0, t_b);
            let y = a.y + a.w * (t_b - t_a);
            if check_walls && inside {
                let len = t_b - t_a;
                let z = |s: f64| a.y + a.w * s - forced.jet(t_a, h0, g0, t_a + s).x;
                let cells = ((POINTS_PER_RADIAN * len * rate).ceil() as usize).clamp(16, 1 << 16);
                inside = local_extremes(&z, [a.w - a.v, a.w - jet.v], len, cells, GOLDEN_STEPS)
                    .iter()
                    .all(|&(val, _)| val.abs() <= l * (1.0 + 1e-9));
            }
            let wall = self.walls[(k + 1) % n];
            residual.push((y - jet.x - wall * l) / l);
            speeds.push(wall * (a.w - jet.v));
            // The section instant `p T` lies in the flight across phase `2 pi p`: the last one,
            // unless a contact added past the section ends it before that
            // ([`ImpactOrbit::with_contact`]).
            let across = phi_a <= span && span < phi_b;
            if across || (k + 1 == n && section[0].is_nan()) {
                let t_s = span / f.omega;
                let at = forced.jet(t_a, h0, g0, t_s);
                let y_s = a.y + a.w * (t_s - t_a);
                section = [at.x, at.v, y_s - at.x, a.w];
            }
            let (v, w) = impact(big_m, m, e, jet.v, a.w);
            afters[(k + 1) % n] = [jet.x, v, w];
            a = State {
                x: jet.x,
                v,
                y: jet.x + wall * l,
                w,
            };
        }
        residual.extend([(a.x - x1) / l, (a.v - v1) / (wn * l), (a.w - w1) / (wn * l)]);
        // Speeds were recorded at the end of each flight: impact k + 1; rotate so that
        // `speeds[k]` is impact k's.
        speeds.rotate_right(1);
        Flown {
            residual,
            speeds,
            section,
            inside,
            afters,
        }
    }

    /// The same orbit with one more impact: a contact at the instant `t` (s, in `[0, p T)`) on
    /// `wall` (`+1` right, `-1` left), where a flight touches that wall at a grazing (its
    /// approach speed zero there, so the orbit is unchanged). The first impact stays the first:
    /// a contact before it is placed one orbit period later, in the flight through the section.
    /// Returns the orbit and the contact's index in it.
    pub fn with_contact(&self, f: &Forcing, t: f64, wall: f64) -> (ImpactOrbit, usize) {
        let span = std::f64::consts::TAU * self.p as f64;
        let mut phi = f.omega * t;
        if self.phases.first().is_some_and(|&first| phi <= first) {
            phi += span;
        }
        let k = self.phases.partition_point(|&q| q < phi);
        let mut out = self.clone();
        out.phases.insert(k, phi);
        out.walls.insert(k, wall);
        (out, k)
    }

    /// The same orbit without impact `j` (one whose approach speed is zero at `f`, so the orbit
    /// is unchanged); `None` when it is the only impact. Without the first impact the second is
    /// the first, with the state just after it.
    pub fn without(&self, f: &Forcing, j: usize) -> Option<ImpactOrbit> {
        let n = self.walls.len();
        if n < 2 || j >= n {
            return None;
        }
        let mut out = self.clone();
        if j == 0 {
            out.after = self.fly(f, false).afters[1];
        }
        out.phases.remove(j);
        out.walls.remove(j);
        Some(out)
    }

    /// Whether the orbit at `f` is one the simulator would run: phases increasing within one
    /// orbit, every impact but `except` approaching its wall, every flight inside the clearance.
    fn admissible(&self, f: &Forcing, flown: &Flown, except: usize) -> bool {
        let span = std::f64::consts::TAU * self.p as f64;
        let n = self.walls.len();
        let ordered = self.phases.windows(2).all(|w| w[0] < w[1])
            && self.phases[n - 1] < self.phases[0] + span;
        // Others may vanish with it (by a symmetry): to rounding, scaled.
        let floor = -SPEED_FLOOR * f.sys.omega() * f.half_gap();
        let approaching = flown
            .speeds
            .iter()
            .enumerate()
            .all(|(k, &u)| k == except || u > floor);
        ordered && approaching && flown.inside
    }
}

/// Where impact `j`'s approach speed vanishes, continuing in the parameter `lambda` from the
/// orbit `orbit` at `lambda_start`: `at(lambda)` is the forcing at a value of the parameter
/// (`lambda_start` its value at `orbit`'s). Returns the forcing and the orbit there, its section
/// state and every impact's approach speed (`u_j` zero to rounding); `None` when Newton does not
/// converge or the solution is not admissible (module doc).
pub fn speed_zero(
    at: &impl Fn(f64) -> Forcing,
    lambda_start: f64,
    orbit: &ImpactOrbit,
    j: usize,
) -> Option<(Forcing, ImpactOrbit, Section, Vec<f64>)> {
    speed_at(at, lambda_start, orbit, j, 0.0)
}

/// Where impact `j`'s approach speed is `target` (m/s, `>= 0`), the parameter `lambda` an
/// unknown as in [`speed_zero`] (which is this with `target = 0`). Past a grazing, the orbit with
/// the new contact is found this way ([`ImpactOrbit::with_contact`], the contact's speed the
/// target): along that orbit's family the contact's speed is a smooth function of the
/// parameter's, so the family is reached at a given speed, on whichever side of the grazing it
/// lies (di Bernardo et al. 2008, §7.3: it persists on the far side, or turns back in a
/// nonsmooth fold).
pub fn speed_at(
    at: &impl Fn(f64) -> Forcing,
    lambda_start: f64,
    orbit: &ImpactOrbit,
    j: usize,
    target: f64,
) -> Option<(Forcing, ImpactOrbit, Section, Vec<f64>)> {
    let f0 = at(lambda_start);
    let (l, wn) = (f0.half_gap(), f0.sys.omega());
    let n = orbit.walls.len();
    if j >= n {
        return None;
    }
    let dim = n + 4;
    let mut u0 = orbit.to_unknowns(l, wn);
    u0.push(1.0);
    let residual = |u: &[f64]| -> Option<Vec<f64>> {
        let f = at(u[dim - 1] * lambda_start);
        let o = orbit.with_unknowns(&u[..dim - 1], l, wn);
        let flown = o.fly(&f, false);
        let mut r = flown.residual;
        r.push((flown.speeds[j] - target) / (wn * l));
        r.iter().all(|v| v.is_finite()).then_some(r)
    };
    let u = newton(u0, &residual)?;
    let f = at(u[dim - 1] * lambda_start);
    let o = orbit.with_unknowns(&u[..dim - 1], l, wn);
    let flown = o.fly(&f, true);
    if !o.admissible(&f, &flown, j) {
        return None;
    }
    Some((f, o, flown.section, flown.speeds))
}

/// The orbit with `orbit`'s impact sequence at `f` (the parameter fixed), by Newton from
/// `orbit`: the orbit, its section state and every impact's approach speed; `None` when Newton
/// does not converge or the orbit is not admissible (every impact approaching its wall, every
/// flight inside the clearance).
pub fn solve_at(f: &Forcing, orbit: &ImpactOrbit) -> Option<(ImpactOrbit, Section, Vec<f64>)> {
    let (l, wn) = (f.half_gap(), f.sys.omega());
    let residual = |u: &[f64]| -> Option<Vec<f64>> {
        let r = orbit.with_unknowns(u, l, wn).fly(f, false).residual;
        r.iter().all(|v| v.is_finite()).then_some(r)
    };
    let u = newton(orbit.to_unknowns(l, wn), &residual)?;
    let o = orbit.with_unknowns(&u, l, wn);
    let flown = o.fly(f, true);
    if !o.admissible(f, &flown, usize::MAX) {
        return None;
    }
    Some((o, flown.section, flown.speeds))
}

/// Newton on a square system from `u` with a central-difference Jacobian (steps [`FD_STEP`]):
/// at most [`MAX_ITERATIONS`] iterations to a residual norm of [`TOLERANCE`]; `None` when the
/// residual is not finite, the linear solve fails or it does not converge.
fn newton(mut u: Vec<f64>, residual: &dyn Fn(&[f64]) -> Option<Vec<f64>>) -> Option<Vec<f64>> {
    let dim = u.len();
    for _ in 0..MAX_ITERATIONS {
        let r = residual(&u)?;
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm <= TOLERANCE {
            return Some(u);
        }
        let mut jac = DMatrix::zeros(dim, dim);
        for c in 0..dim {
            let (mut up, mut dn) = (u.clone(), u.clone());
            up[c] += FD_STEP;
            dn[c] -= FD_STEP;
            let rp = residual(&up)?;
            let rm = residual(&dn)?;
            for (row, (a, b)) in rp.iter().zip(&rm).enumerate() {
                jac[(row, c)] = (a - b) / (2.0 * FD_STEP);
            }
        }
        let du = jac.lu().solve(&-DVector::from_vec(r))?;
        if !du.iter().all(|v| v.is_finite()) {
            return None;
        }
        for (x, d) in u.iter_mut().zip(du.iter()) {
            *x += d;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::analytic::symmetric_period1;
    use crate::orbits::map::tests::table_i;

    /// A contact added and removed again gives the orbit back, wherever it falls: after the
    /// first impact, or before it (placed one orbit period later, past the section's instant,
    /// so that the section state is still the orbit's).
    #[test]
    fn a_contact_added_and_removed_gives_the_orbit_back() {
        let f = table_i(0.005, 0.005, 0.9, 0.1, 0.1, 0.93);
        let o = symmetric_period1(&f.sys, f.F0, f.omega)
            .into_iter()
            .find(|o| o.admissible)
            .expect("an orbit");
        let io = ImpactOrbit::from_section(&f, &o.section, 1).expect("impacts");
        let t1 = io.phases[0] / f.omega;
        for t in [0.5 * t1, t1 + 0.1 * f.period()] {
            let (with, j) = io.with_contact(&f, t, 1.0);
            assert_eq!(with.walls.len(), 3);
            assert!(with.phases.windows(2).all(|w| w[0] < w[1]), "{with:?}");
            assert_eq!(
                with.without(&f, j).as_ref(),
                Some(&io),
                "contact at t = {t}"
            );
        }
        // A contact before the first impact is placed past the section's instant: the section
        // state is computed in the flight across that instant, the orbit's.
        let (with, _) = io.with_contact(&f, 0.5 * t1, 1.0);
        let (a, b) = (io.fly(&f, false).section, with.fly(&f, false).section);
        assert_eq!(a, b, "the section moved with a contact in the last flight");
    }

    /// The symmetric two-impact orbit in closed form, recorded by the simulator in impact
    /// coordinates, solves the system to rounding, and its approach speeds are the closed
    /// form's `W- - V-` on both walls.
    #[test]
    fn a_simulated_orbit_solves_the_system() {
        let f = table_i(0.005, 0.005, 0.9, 0.1, 0.1, 0.93);
        let o = symmetric_period1(&f.sys, f.F0, f.omega)
            .into_iter()
            .find(|o| o.admissible)
            .expect("an orbit");
        let io = ImpactOrbit::from_section(&f, &o.section, 1).expect("impacts");
        assert_eq!(io.walls.len(), 2);
        let flown = io.fly(&f, false);
        let norm = flown.residual.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(norm < 1e-9, "residual {norm:e}");
        for u in &flown.speeds {
            let want = o.w_before - o.v_before;
            assert!((u - want).abs() < 1e-9 * want, "{u} against {want}");
        }
        for (a, b) in flown.section.iter().zip(o.section) {
            assert!(
                (a - b).abs() < 1e-9 * (1.0 + b.abs()),
                "{:?} against {:?}",
                flown.section,
                o.section
            );
        }
    }
}
