//! How near an orbit's inner mass comes to a wall in free flight: the test function of a
//! grazing (docs/model.md §12).
//!
//! At a grazing an orbit's impact sequence changes: a flight of the inner mass touches a wall
//! with zero relative speed (a new contact appears; or, seen from the other side, an impact's
//! approach speed reaches zero). On the side without that contact the map is smooth and the
//! flight passes the wall at a distance
//!
//! ```text
//! gap = d/2 - max |z(t)|,   z = y - x,   over the local extrema of z inside every free flight
//! ```
//!
//! that goes to zero, linearly in the parameter, at the grazing; on the other side the contact is
//! an impact whose approach speed grows like the square root of the distance (the map's
//! derivatives like its inverse), which is why the corrector converges on the smooth side. A
//! located grazing is the orbit on the smooth side whose gap is within `1e-8 d/2` of zero.
//!
//! Between events the main mass moves in closed form ([`crate::sim::harmonic`]) and the inner
//! mass at constant velocity, so each flight is scanned like the closed-form orbit's
//! ([`super::analytic`]): a grid of 8 points per radian of the fastest rate, each local extremum
//! refined by golden-section search.

use super::analytic::local_extremes_at;
use super::map::{Forcing, Section};
use crate::sim::harmonic::motion::Forced;
use crate::sim::harmonic::simulate_harmonic;
use crate::sim::{Outcome, Probe, Request, State, Wall};

/// Grid points per radian of the fastest rate of the motion when scanning a flight: extrema of
/// `z` are at least `pi / rate` apart, so 8 points per radian bracket each.
const POINTS_PER_RADIAN: f64 = 8.0;
/// Golden-section steps refining an extremum: the bracket (a grid cell) shrinks by
/// `0.618^40 ~ 4e-9`, the value's error by its square (`1e-17` of the cell's variation).
const GOLDEN_STEPS: usize = 40;

/// The events that bound the free flights: an impact (free after it unless a sticking phase
/// begins at the same instant) and a separation (free after it).
#[derive(Default)]
struct Flights {
    /// `(t, state after, free after)`.
    starts: Vec<(f64, State, bool)>,
    /// Every impact: `(t, state before)`.
    impacts: Vec<(f64, State)>,
}

impl Probe for Flights {
    fn impact(&mut self, t: f64, _wall: Wall, before: &State, after: &State) {
        self.starts.push((t, *after, true));
        self.impacts.push((t, *before));
    }
    fn stick(&mut self, t: f64, _wall: Wall, state: &State) {
        // The impact at the same instant closed a chatter: stuck, not free, after it.
        if let Some(last) = self.starts.last_mut()
            && last.0 == t
        {
            last.2 = false;
        } else {
            self.starts.push((t, *state, false));
        }
    }
    fn separate(&mut self, t: f64, _wall: Wall, state: &State) {
        self.starts.push((t, *state, true));
    }
}

/// The smallest gap (m) between the inner mass and a wall at a local extremum of `z = y - x`
/// inside a free flight, over `p` forcing periods from section state `s` (the flights cut by
/// `t = 0` and `t = p T` included). `+inf` when no flight has an interior extremum; `None` when
/// the run does not end `ok`. Negative values cannot occur for a simulated motion (it would
/// have hit the wall).
pub fn flight_gap(f: &Forcing, s: &Section, p: u64) -> Option<f64> {
    scan(f, s, p).map(|(gap, _)| gap.gap)
}

/// Where a flight comes nearest a wall over `p` forcing periods from section state `s`
/// ([`flight_gap`]): the gap there (m), the instant `t` in `[0, p T]` (s) and the wall's sign
/// (`+1` the right wall `z = +d/2`, `-1` the left). At a grazing this is the contact that
/// becomes an impact on the far side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    pub gap: f64,
    pub t: f64,
    pub wall: f64,
}

/// The flight's extremum nearest a wall ([`Nearest`]); `None` when the run does not end `ok` or
/// no flight has an interior extremum.
pub fn nearest_contact(f: &Forcing, s: &Section, p: u64) -> Option<Nearest> {
    scan(f, s, p)
        .map(|(gap, _)| gap)
        .filter(|g| g.gap.is_finite())
}

/// The grazing test function of the motion from `s` over `p` periods (m), signed and continuous
/// through a grazing: of the flights' gaps ([`flight_gap`], `>= 0`) and of every impact's depth
/// `-u^2 / (2 |x''|)` (`u` the approach speed, `x''` the main mass's acceleration there: how far
/// the inner mass's path would have gone past the wall, `< 0`), the one nearest zero. On the
/// side of a grazing without the contact it is the gap, on the other the new impact's depth; both
/// go to zero linearly in the distance to the grazing. `None` when the run does not end `ok`.
pub fn grazing_value(f: &Forcing, s: &Section, p: u64) -> Option<f64> {
    let (gap, depth) = scan(f, s, p)?;
    let gap = gap.gap;
    Some(if gap <= -depth { gap } else { depth })
}

/// The smallest flight gap, where it is, and the impact depth nearest zero (`-inf` without
/// impacts).
fn scan(f: &Forcing, s: &Section, p: u64) -> Option<(Nearest, f64)> {
    let sys = f.started(s);
    let mut flights = Flights::default();
    let out = simulate_harmonic(
        &sys,
        &f.settings,
        &Request::default(),
        &f.scene(p),
        None,
        &mut flights,
    );
    if out.outcome != Outcome::Ok {
        return None;
    }
    let (big_m, k, c) = (f.sys.M, f.sys.K, f.sys.C);
    let forced = Forced::new(big_m, k, c, f.F0, f.omega);
    let l = f.half_gap();
    let rate = f.omega.max(f.sys.omega()).max(c / big_m);
    let start = State {
        x: sys.x0,
        v: sys.v0,
        y: sys.y0,
        w: sys.w0,
    };
    // The first flight starts at t = 0, free unless the inner mass starts stuck on a wall
    // (on it and moving with the main mass).
    let free_at_start = !((start.y - start.x).abs() >= l && start.w == start.v);
    let mut segments = vec![(0.0, start, free_at_start)];
    segments.extend(flights.starts.iter().copied());
    let t_end = out.t_stop;
    let mut gap = Nearest {
        gap: f64::INFINITY,
        t: f64::NAN,
        wall: f64::NAN,
    };
    for (i, &(t_a, a, free)) in segments.iter().enumerate() {
        let t_b = segments.get(i + 1).map_or(t_end, |seg| seg.0);
        let len = t_b - t_a;
        if !free || len <= 0.0 {
            continue;
        }
        let (h0, g0) = forced.free_start(t_a, a.x, a.v);
        let z = |s: f64| a.y + a.w * s - forced.jet(t_a, h0, g0, t_a + s).x;
        let v_end = forced.jet(t_a, h0, g0, t_b).v;
        let n = ((POINTS_PER_RADIAN * len * rate).ceil() as usize).clamp(16, 1 << 16);
        let slopes = [a.w - a.v, a.w - v_end];
        for (v, sign, at) in local_extremes_at(&z, slopes, len, n, GOLDEN_STEPS) {
            // A maximum approaches the right wall, a minimum the left one.
            let g = l - sign * v;
            if g < gap.gap {
                gap = Nearest {
                    gap: g,
                    t: t_a + at,
                    wall: sign,
                };
            }
        }
    }
    let mut depth = f64::NEG_INFINITY;
    for &(t, b) in &flights.impacts {
        let acc = (f.F0 * (f.omega * t).cos() - k * b.x - c * b.v) / big_m;
        let u = b.w - b.v;
        if acc != 0.0 {
            depth = depth.max(-u * u / (2.0 * acc.abs()));
        }
    }
    Some((gap, depth))
}
