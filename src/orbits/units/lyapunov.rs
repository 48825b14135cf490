//! The largest Lyapunov exponent of a motion of several units, from two trajectories
//! (Benettin's first method; docs/model.md §14).
//!
//! One unit's exponent comes from the exact tangent map ([`crate::orbits::lyapunov`]). The map of
//! several units has an exact Jacobian only where impacts come one unit at a time, and central
//! differences cost `2 (2 + 2N)` maps a period, so here a second trajectory is run beside the
//! motion, `delta_0 = 1e-8 L` away in the section norm ([`super::map::distance`], `L = d/2`
//! the system's half clearance): each forcing period both go through the exact map `P`, the growth
//! `delta_1 / delta_0` is logged, and the second is put back at `delta_0` along the separation
//! (`b <- a + (b - a) delta_0 / delta_1`), so the separation turns towards the most unstable
//! direction and stays linear. The first [`BURN`] periods are not counted (the turning);
//! `lambda_1` is the mean of the logs over [`PERIODS`] periods, its standard error by batch means
//! over 8 batches ([`crate::orbits::lyapunov::batch_means`]).
//!
//! `delta_0` is small against every scale of the motion (`1e-8` of a clearance) and well above
//! rounding (`1e-16` relative of the state), so a period straddles a grazing only on a
//! vanishing share of periods; the test in `tests/units_orbits.rs` checks the estimate against
//! one unit's exact tangent map on a chaotic point.
//!
//! Units: per forcing period. Pure.

use super::map::{complete, distance, eval};
use crate::orbits::census::ProbeResult;
use crate::orbits::lyapunov::batch_means;
use crate::orbits::map::Forcing;
use crate::sim::Outcome;

/// Forcing periods counted (8 batches of 64).
pub const PERIODS: u64 = 512;
/// Periods run first, not counted.
pub const BURN: u64 = 16;
/// The separation, relative to the system's half clearance `d/2`.
pub const SEPARATION: f64 = 1e-8;

/// The exponent of the motion through section state `s` (`2 + 2N` components) over `n` counted
/// periods after [`BURN`] ([`PERIODS`] in the census), per forcing period, with its standard
/// error and the periods counted; `None` when the simulator stopped either trajectory (its
/// outcome not `ok`).
pub fn two_trajectory(f: &Forcing, s: &[f64], n: u64) -> Option<ProbeResult> {
    let mut a = complete(f, s);
    let delta = SEPARATION * f.half_gap();
    let wn = f.sys.omega();
    // The first separation along (1, 1, ...) in the section norm's scaled coordinates:
    // positions (even indices) in m, velocities (odd) in m/s scaled by wn.
    let step = delta / (a.len() as f64).sqrt();
    let nudged = |a: &[f64]| -> Vec<f64> {
        a.iter()
            .enumerate()
            .map(|(k, v)| v + if k % 2 == 0 { step } else { step * wn })
            .collect()
    };
    let mut b = nudged(&a);
    let mut logs = Vec::with_capacity(n as usize);
    for k in 0..BURN + n {
        let (ea, eb) = (eval(f, &a, 1), eval(f, &b, 1));
        if ea.outcome != Outcome::Ok || eb.outcome != Outcome::Ok {
            return None;
        }
        let grown = distance(f, &ea.end, &eb.end);
        a = ea.end;
        if !(grown.is_finite() && grown > 0.0) {
            // Both landed on the same state (units pressed on a wall together): start the
            // separation again along the first direction; the period is not counted.
            b = nudged(&a);
            continue;
        }
        if k >= BURN {
            logs.push((grown / delta).ln());
        }
        let back = delta / grown;
        b = a
            .iter()
            .zip(&eb.end)
            .map(|(x, y)| x + (y - x) * back)
            .collect();
    }
    let (lambda, se) = batch_means(&logs, 8);
    Some(ProbeResult {
        lambda,
        se,
        periods: logs.len() as u64,
    })
}
