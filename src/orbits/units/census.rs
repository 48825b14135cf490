//! The census of periodic steady states of several units at one frequency point: seeded starts
//! in the cavities, a transient, Newton on `P^p` ([`super::shoot`]), distinct orbits merged.
//!
//! # Starts
//! Start 0 is the given section state (the system's initial state: every unit at `(y0, w0)`,
//! in step). Start `k >= 1` is drawn from the seed, the design point and `k` (SplitMix64: the
//! same on any thread count) over a box scaled by `X = max(A_0, d/2)`, `A_0` the largest `|x|`
//! start 0 saw in its last period:
//!
//! * main mass: `x = a cos(theta)`, `x' = -omega a sin(theta)`, `a = 2 X sqrt(u1)`,
//!   `theta = 2 pi u2` (uniform over the disc of radius `2 X` in the `(x, x'/omega)` plane);
//! * unit `i`, each drawn on its own: `z_i = (d_i/2)(2 u - 1)` anywhere in its cavity,
//!   `y_i' - x'` uniform in `[-2 omega X, 2 omega X]`.
//!
//! # Each start
//! The start runs one forcing period at a time. After each, for the smallest `p` in `1..=8`
//! whose last two `p`-step differences of the section ([`super::map::distance`]) are both at
//! most [`UnitsCensusSettings::handover`] times the scale `L` ([`super::map::scale`]), Newton on
//! `P^p` takes over from the latest section. A converged, impacting, stable orbit ends the start;
//! otherwise the hand-over tolerance is divided by 1000 and the transient goes on. A start
//! whose last 16 periods made no impact has reached the non-impacting family (counted, not
//! listed); one that reaches its budget of [`UnitsCensusSettings::max_periods`] periods first
//! did not settle (a motion that is not periodic, or a slow transient). Such starts are grouped
//! into motions by where they wander over their last
//! [`crate::orbits::tolerances::CENSUS_WINDOW`] periods ([`super::motion`]: a second look of
//! [`crate::orbits::census::SECOND_LOOK`] periods where the windows disagree); each motion keeps
//! the largest `|x|` of its starts over those windows (exact, the map's own amplitude each
//! period; a lower bound of what it reaches), the states its starts ended in (from which the
//! race measures it over the design life, [`crate::orbits::race::race_units`]) and its largest
//! Lyapunov exponent from two trajectories through its first state over
//! [`super::lyapunov::PERIODS`] periods ([`super::lyapunov`]), which tells it chaotic,
//! quasi-periodic or not settled as one unit's census does.
//!
//! # Merging
//! Two orbits are one when their periods agree and the section of one lies within `1e-6 L` of
//! one of the other's `p` sections ([`super::shoot::same_orbit`]). Basin share = starts that
//! reached the orbit / starts.

use super::lyapunov::{self, two_trajectory};
use super::map::{complete, dim, distance, eval, half_gaps, initial, scale};
use super::motion::{UnitsCloud, UnitsMotion, join};
use super::shoot::{UnitsOrbit, orbit_at, same_orbit, solve};
use crate::numeric::mix64;
use crate::orbits::map::Forcing;
use crate::orbits::shoot::{Newton, Stability, Termination};
use crate::sim::Outcome;

/// Largest period looked for.
const MAX_PERIOD: usize = 8;
/// Periods without impact after which a start has reached the non-impacting family.
const QUIET: u64 = 16;
/// Periods over which a start that does not settle is measured (its last ones).
const WINDOW: usize = crate::orbits::tolerances::CENSUS_WINDOW as usize;

/// The census's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitsCensusSettings {
    /// Starts, `>= 1` (start 0 from the given state).
    pub starts: u32,
    /// Forcing periods each start may run before it counts as not settled.
    pub max_periods: u64,
    /// Relative `p`-step difference at which a start is handed to Newton (default `1e-3`).
    pub handover: f64,
    /// The study seed and the design point: they fix the starts.
    pub seed: u64,
    pub point: u64,
}

impl Default for UnitsCensusSettings {
    fn default() -> Self {
        UnitsCensusSettings {
            starts: 8,
            max_periods: 2000,
            handover: crate::orbits::tolerances::HANDOVER,
            seed: 0,
            point: 0,
        }
    }
}

/// One distinct periodic orbit the census found.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsAttractor {
    pub orbit: UnitsOrbit,
    /// Starts that reached it.
    pub starts: u32,
    /// The first start that reached it.
    pub first: u32,
    /// Newton's iterations for that first start.
    pub iterations: u32,
}

/// The census of one frequency point.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsCensus {
    /// Distinct stable impacting orbits, in the order first reached.
    pub attractors: Vec<UnitsAttractor>,
    /// Starts run.
    pub starts: u32,
    /// Starts that reached the non-impacting family.
    pub non_impacting: u32,
    /// The motions that are not periodic: the starts that reached no periodic orbit within
    /// their budget (or whose simulation stopped), grouped by where they wander
    /// ([`super::motion`]), in the order first reached.
    pub motions: Vec<UnitsMotion>,
    /// Forcing periods simulated in all: the transients, Newton's maps counted as `2 dim + 1`
    /// maps an iteration (an upper bound: units in step have fewer columns), the motions'
    /// second looks and exponents.
    pub periods: u64,
    /// Where start 0 (the given state) ended.
    pub rest: RestLanding,
}

/// Where start 0 of a census ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RestLanding {
    /// On attractor `i` of [`UnitsCensus::attractors`].
    Orbit(usize),
    /// On the non-impacting family.
    NonImpacting,
    /// On motion `i` of [`UnitsCensus::motions`] (it did not settle within its budget).
    Motion(usize),
    /// No census was run.
    #[default]
    Unsettled,
}

impl Default for UnitsCensus {
    fn default() -> Self {
        UnitsCensus {
            attractors: Vec::new(),
            starts: 0,
            non_impacting: 0,
            motions: Vec::new(),
            periods: 0,
            rest: RestLanding::Unsettled,
        }
    }
}

impl UnitsCensus {
    /// Basin share of attractor `i`.
    pub fn share(&self, i: usize) -> f64 {
        self.attractors[i].starts as f64 / self.starts.max(1) as f64
    }

    /// Starts that did not settle on a periodic orbit (every motion's).
    pub fn unsettled(&self) -> u32 {
        self.motions.iter().map(|m| m.starts).sum()
    }

    /// The orbit with the largest amplitude.
    pub fn worst(&self) -> Option<&UnitsAttractor> {
        self.attractors.iter().reduce(|a, b| {
            if b.orbit.amplitude > a.orbit.amplitude {
                b
            } else {
                a
            }
        })
    }
}

/// Where one start ended.
enum Landing {
    Orbit(Box<UnitsOrbit>, u32),
    Quiet,
    /// The budget ran out (with the state it ended on and its cloud over its last window) or
    /// the simulation stopped (`None`).
    Unsettled(Option<(Vec<f64>, UnitsCloud)>),
}

/// A uniform number in `[0, 1)` for start `k`, draw `j`.
fn uniform(c: &UnitsCensusSettings, k: u32, j: u64) -> f64 {
    let z = mix64(c.seed ^ mix64(c.point ^ mix64(0x5EED_0068 + 256 * u64::from(k) + j)));
    (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Start `k >= 1` (module doc).
pub fn start(f: &Forcing, c: &UnitsCensusSettings, k: u32, x_ref: f64) -> Vec<f64> {
    let w = f.omega;
    let a = 2.0 * x_ref * uniform(c, k, 1).sqrt();
    let th = std::f64::consts::TAU * uniform(c, k, 2);
    let (x, v) = (a * th.cos(), -w * a * th.sin());
    let mut s = vec![x, v];
    for (i, hd) in half_gaps(f).iter().enumerate() {
        let j = 3 + 2 * i as u64;
        let z = hd * (2.0 * uniform(c, k, j) - 1.0);
        let rel = 2.0 * w * x_ref * (2.0 * uniform(c, k, j + 1) - 1.0);
        s.extend([z, v + rel]);
    }
    s
}

/// The smallest `p` whose last two `p`-step differences are within `tol L` (module doc).
fn repeating(f: &Forcing, h: &[Vec<f64>], tol: f64) -> Option<usize> {
    let n = h.len();
    let last = &h[n - 1];
    let lim = tol * scale(f, last);
    (1..=MAX_PERIOD).find(|&p| {
        n > 2 * p
            && distance(f, last, &h[n - 1 - p]) <= lim
            && distance(f, &h[n - 1 - p], &h[n - 1 - 2 * p]) <= lim
    })
}

/// What one start cost and saw: the periods it ran, the largest `|x|` of its last period and
/// over its last [`crate::orbits::tolerances::CENSUS_WINDOW`] periods (m).
struct Ran {
    periods: u64,
    last: f64,
    window: f64,
}

/// Runs one start from `s` (module doc).
fn run_start(f: &Forcing, s: Vec<f64>, c: &UnitsCensusSettings, newton: &Newton) -> (Landing, Ran) {
    // One map and the `2 (2 + 2G) <= 2 dim` of its Jacobian per Newton iteration.
    let cost = 2 * dim(f) as u64 + 1;
    let mut history = vec![s];
    let (mut periods, mut quiet, mut amp) = (0u64, 0u64, 0.0);
    let mut recent = std::collections::VecDeque::with_capacity(WINDOW);
    // The last window's sections (the start's cloud if it does not settle).
    let mut sections = std::collections::VecDeque::with_capacity(WINDOW);
    let ran = |periods, last, recent: &std::collections::VecDeque<f64>| Ran {
        periods,
        last,
        window: recent.iter().copied().fold(f64::NAN, f64::max),
    };
    let mut tol = c.handover;
    while periods < c.max_periods {
        let now = history.last().cloned().unwrap_or_default();
        let e = eval(f, &now, 1);
        periods += 1;
        if e.outcome != Outcome::Ok {
            return (Landing::Unsettled(None), ran(periods, amp, &recent));
        }
        amp = e.amplitude;
        if recent.len() == WINDOW {
            recent.pop_front();
        }
        recent.push_back(amp);
        quiet = if e.impacts == 0 { quiet + 1 } else { 0 };
        if quiet >= QUIET {
            return (Landing::Quiet, ran(periods, amp, &recent));
        }
        if sections.len() == WINDOW {
            sections.pop_front();
        }
        sections.push_back(e.end.clone());
        history.push(e.end);
        if history.len() > 2 * MAX_PERIOD + 1 {
            history.remove(0);
        }
        let Some(p) = repeating(f, &history, tol) else {
            continue;
        };
        let (term, state) = solve(f, p as u64, &history[history.len() - 1], newton);
        let iterations = state.as_ref().map_or(0, |st| st.iterations);
        periods += u64::from(iterations + 1) * p as u64 * cost;
        if let (Termination::Converged { .. }, Some(st)) = (term, state)
            && let Some(o) = orbit_at(f, p as u64, &st, newton)
            && o.stability == Stability::Stable
        {
            return (
                Landing::Orbit(Box::new(o), iterations),
                ran(periods, amp, &recent),
            );
        }
        tol *= 1e-3;
    }
    let mut cloud = UnitsCloud::new(f);
    for s in &sections {
        cloud.add(s);
    }
    (
        Landing::Unsettled(history.pop().map(|s| (s, cloud))),
        ran(periods, amp, &recent),
    )
}

/// Runs the census at `f` from `s0` (the first start's section state, `2 + 2N` components, read
/// as [`super::map::complete`]s; [`super::map::initial`] for the system's own initial state).
/// Pure.
pub fn census_units(f: &Forcing, s0: &[f64], c: &UnitsCensusSettings) -> UnitsCensus {
    let newton = Newton::default();
    let mut out = UnitsCensus::default();
    let mut x_ref = f.half_gap();
    for k in 0..c.starts.max(1) {
        let s = if k == 0 {
            complete(f, s0)
        } else {
            start(f, c, k, x_ref)
        };
        let (landing, ran) = run_start(f, s, c, &newton);
        if k == 0 && ran.last.is_finite() {
            x_ref = x_ref.max(ran.last);
        }
        out.starts += 1;
        out.periods += ran.periods;
        let rest = match landing {
            Landing::Orbit(o, iterations) => RestLanding::Orbit(out.merge(f, *o, k, iterations)),
            Landing::Quiet => {
                out.non_impacting += 1;
                RestLanding::NonImpacting
            }
            Landing::Unsettled(end) => {
                let (i, looked) = join(f, &mut out.motions, k, end, ran.window);
                out.periods += looked;
                RestLanding::Motion(i)
            }
        };
        if k == 0 {
            out.rest = rest;
        }
    }
    for m in &mut out.motions {
        if let Some(s) = m.states.first() {
            m.probe = two_trajectory(f, s, lyapunov::PERIODS);
            out.periods += 2 * (lyapunov::BURN + lyapunov::PERIODS);
        }
    }
    out
}

/// [`census_units`] from the system's own initial state.
pub fn census_from_rest(f: &Forcing, c: &UnitsCensusSettings) -> UnitsCensus {
    census_units(f, &initial(f), c)
}

impl UnitsCensus {
    /// Adds start `k`'s orbit `o` (a new attractor, or one more start of the same orbit);
    /// returns its index.
    fn merge(&mut self, f: &Forcing, o: UnitsOrbit, k: u32, iterations: u32) -> usize {
        let p = u64::from(o.period);
        if let Some(i) = self
            .attractors
            .iter()
            .position(|a| a.orbit.period == o.period && same_orbit(f, &a.orbit.s, &o.s, p))
        {
            self.attractors[i].starts += 1;
            return i;
        }
        self.attractors.push(UnitsAttractor {
            orbit: o,
            starts: 1,
            first: k,
            iterations,
        });
        self.attractors.len() - 1
    }
}
