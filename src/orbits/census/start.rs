//! One start of the census, from its initial state to where it ends (the module doc of
//! [`super`], "Starts" and "Each start"): the seeded starts' states, the transient rule with
//! Newton's hand-over, the first check and the tangent-map probe of a start that wanders, its
//! budget and measuring window, and the stable orbits found in its close returns.

use super::cloud::{Cloud, chaos_probe};
use super::motion::{CensusSettings, Origin, ProbeResult, Wandering};
use crate::orbits::map::{Forcing, Section, eval};
use crate::orbits::shoot::{
    Newton, Orbit, Stability, Termination, non_impacting, orbit_at, same_orbit, solve,
};
use crate::sim::Outcome;
use crate::sim::noise::mix64;
use crate::sim::{Drive, Harmonic, HarmonicRecord, NoProbe, Request, simulate_harmonic};

/// Longest period looked for.
pub(super) const MAX_PERIOD: usize = 8;

/// Start `k`'s uniform number `j` in `[0, 1)`.
pub(super) fn uniform(c: &CensusSettings, k: u32, j: u32) -> f64 {
    let z = mix64(c.seed ^ mix64(c.point ^ mix64(0xCE_5005 + 8 * u64::from(k) + u64::from(j))));
    (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Start `k >= 1` (module doc).
pub fn start(f: &Forcing, c: &CensusSettings, k: u32, x_ref: f64) -> Section {
    let w = f.omega;
    let a = 2.0 * x_ref * uniform(c, k, 1).sqrt();
    let th = std::f64::consts::TAU * uniform(c, k, 2);
    let (x, v) = (a * th.cos(), -w * a * th.sin());
    let z = f.half_gap() * (2.0 * uniform(c, k, 3) - 1.0);
    let rel = 2.0 * w * x_ref * (2.0 * uniform(c, k, 4) - 1.0);
    [x, v, z, v + rel]
}

/// Where one start ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Landing {
    Orbit(Orbit),
    NonPeriodic {
        amplitude: f64,
        impacts_per_period: f64,
        wandering: Box<Wandering>,
    },
}

/// A start between its first check and its end (module doc, "Starts that wander").
#[derive(Clone, Debug)]
pub(super) struct Wanderer {
    pub(super) origin: Origin,
    /// Census starts it stands for (1, or 0 for a seed).
    pub(super) starts: u32,
    /// Where it is, what it has run, its probe and cloud so far.
    pub(super) state: Section,
    pub(super) periods: u64,
    pub(super) probe: ProbeResult,
    pub(super) cloud: Cloud,
}

/// Where a start settled: its attractor, the forcing periods simulated, and the section state
/// it ended in (a periodic orbit's own section, or where the measuring window ended), from
/// which the next frequency of a sweep starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Settled {
    pub landing: Landing,
    pub periods: u64,
    pub end: Section,
}

/// A start after its first check: landed, or wandering.
pub(super) enum Early {
    Landed(Settled),
    Wandering(Wanderer),
}

/// Runs one start from `s0` to its attractor (module doc, "Each start"), wandering included:
/// what a sweep from frequency to frequency, or a probe between designs, runs for one start.
pub fn settle(f: &Forcing, s0: &Section, c: &CensusSettings, newton: &Newton) -> Settled {
    match begin(f, s0, c, newton, Origin::Start(0), 1, c.max_periods) {
        Early::Landed(st) => st,
        Early::Wandering(w) => conclude(f, w, c.max_periods, c, newton),
    }
}

/// A start from `s0` up to its first check only ([`FIRST_CHECK`] periods, then the probe):
/// where it lands (a periodic orbit, the non-impacting family, a failed run), or `None` while
/// it still wanders. What a probe between designs runs for a chaotic attractor continued from
/// a neighbouring design: as a seed joins a chaotic attractor that ran its whole budget, it
/// does not run a budget of its own.
pub fn first_check(
    f: &Forcing,
    s0: &Section,
    c: &CensusSettings,
    newton: &Newton,
) -> Option<Settled> {
    match begin(f, s0, c, newton, Origin::Start(0), 1, c.max_periods) {
        Early::Landed(st) => Some(st),
        Early::Wandering(_) => None,
    }
}

/// A start from `s0` up to its first check ([`FIRST_CHECK`] periods, then the probe), with a
/// budget of `budget` periods in all.
pub(super) fn begin(
    f: &Forcing,
    s0: &Section,
    c: &CensusSettings,
    newton: &Newton,
    origin: Origin,
    starts: u32,
    budget: u64,
) -> Early {
    let budget = budget.max(1);
    let first = budget.min(FIRST_CHECK);
    let (rec, periods) = transient(f, s0, c, first);
    if rec.outcome != Outcome::Ok {
        return Early::Landed(failed(periods, *s0));
    }
    let s = section_of(&rec);
    if rec.converged || budget <= first {
        return Early::Landed(land(f, &rec, &s, c, newton, periods, None));
    }
    let probe = chaos_probe(f, &s, PROBE);
    let periods = periods + probe.periods;
    if !probe.ok {
        return Early::Landed(failed(periods, s));
    }
    Early::Wandering(Wanderer {
        origin,
        starts,
        state: probe.end,
        periods,
        probe: ProbeResult {
            lambda: probe.lambda,
            se: probe.se,
            periods: probe.periods,
        },
        cloud: probe.cloud,
    })
}

/// A wandering start run on until `budget` periods in all: the transient rule, then Newton or
/// the measuring window.
pub(super) fn conclude(
    f: &Forcing,
    w: Wanderer,
    budget: u64,
    c: &CensusSettings,
    newton: &Newton,
) -> Settled {
    let left = budget.max(1).saturating_sub(w.periods).max(1);
    let (rec, p) = transient(f, &w.state, c, left);
    let periods = w.periods + p;
    if rec.outcome != Outcome::Ok {
        return failed(periods, w.state);
    }
    let s = section_of(&rec);
    land(f, &rec, &s, c, newton, periods, Some((w.probe, w.cloud)))
}

/// Where a transient run `rec` (ending at section `s`, `periods` simulated) leads: the
/// non-impacting family, a stable periodic orbit by Newton, or the measuring window. `probe`:
/// what a wandering start's probe found.
///
/// Newton is tried whenever the run's last `2 * MAX_PERIOD` sections repeat with some period
/// to the hand-over tolerance, also when the run ended at its budget before its transient test
/// was met: a start that wandered first and then approaches a weakly stable orbit (a
/// multiplier near 1, so the test needs hundreds of periods more) is on that orbit, not a motion
/// that is not periodic. (Until this was so, the showcase had about 40 such starts counted as
/// chaotic or not settled attractors with exactly their orbit's amplitude, each with a design
/// life measured for it.)
pub(super) fn land(
    f: &Forcing,
    rec: &HarmonicRecord,
    s: &Section,
    c: &CensusSettings,
    newton: &Newton,
    mut periods: u64,
    probe: Option<(ProbeResult, Cloud)>,
) -> Settled {
    let x_scale = f.half_gap().max(rec.amplitude);
    // `m = 0`: the main mass alone, linear, whose one steady state is the non-impacting orbit
    // wherever the transient has got to (a massless inner mass cannot act on it).
    let alone = f.sys.m == 0.0;
    if rec.impacts_per_period == 0.0
        && (alone || s[3].abs() <= 1e-12 * f.omega * x_scale)
        && let Some(o) = non_impacting(f, s[0] + s[2])
    {
        // The sweep goes on from where the motion is (the family's section places the inner
        // mass by convention).
        return Settled {
            landing: Landing::Orbit(o),
            periods,
            end: *s,
        };
    }
    if rec.period >= 1 {
        let p = u64::from(rec.period);
        let (term, state) = solve(f, p, s, newton);
        if let Some(st) = &state {
            periods += u64::from(st.iterations + 1) * p;
        }
        if let (Termination::Converged { .. }, Some(st)) = (term, state)
            && let Some(o) = orbit_at(f, p, &st, newton)
            && o.stability == Stability::Stable
        {
            let end = o.s;
            return Settled {
                landing: Landing::Orbit(o),
                periods,
                end,
            };
        }
    }
    measure(f, s, c, periods, probe, !rec.converged)
}

/// A start that is not periodic, measured over [`CensusSettings::window`] periods from `s`
/// (`periods` simulated before); `exhausted`: it ran its whole budget without converging.
pub(super) fn measure(
    f: &Forcing,
    s: &Section,
    c: &CensusSettings,
    periods: u64,
    probe: Option<(ProbeResult, Cloud)>,
    exhausted: bool,
) -> Settled {
    let n = c.window.max(1);
    let mut cloud = Cloud::new(f);
    let mut sections = Vec::with_capacity(n as usize + 1);
    sections.push(*s);
    let (mut amplitude, mut impacts) = (0.0_f64, 0u64);
    for _ in 0..n {
        let w = eval(f, sections.last().unwrap_or(s), 1, false);
        if w.outcome != Outcome::Ok {
            return failed(periods + n, *s);
        }
        amplitude = amplitude.max(w.amplitude);
        impacts += w.impacts;
        cloud.add(&w.end);
        sections.push(w.end);
    }
    let (embedded, newton_periods) = if exhausted {
        close_returns(f, &sections)
    } else {
        (Vec::new(), 0)
    };
    let end = *sections.last().unwrap_or(s);
    Settled {
        landing: Landing::NonPeriodic {
            amplitude,
            impacts_per_period: impacts as f64 / n as f64,
            wandering: Box::new(Wandering {
                cloud,
                probe: probe.map(|p| p.0),
                exhausted,
                embedded,
                life: None,
                chains: Vec::new(),
            }),
        },
        periods: periods + n + newton_periods,
        end,
    }
}

/// Distance, relative to `d/2`, within which a section that returns after `p` periods is
/// handed to Newton ([`close_returns`]).
pub const CLOSE_RETURN: f64 = 0.1;

/// Most Newton searches [`close_returns`] makes from one window (measured on the showcase: the
/// stable orbits of its chaotic windows were found within 50 tries).
pub const CLOSE_RETURN_TRIES: usize = 64;

/// The stable impacting periodic orbits found by Newton on `P^p` (`p` = 1 to 4) from every
/// close return of a wandering motion's sections (`|s_{k+p} - s_k| < CLOSE_RETURN d/2`; the
/// close-returns method of Lathrop and Kostelich), distinct, and the periods Newton simulated.
/// A chaotic set is threaded with periodic orbits, almost all unstable; a stable one among
/// them, or beside it, is an attractor that starts reach only by a rare escape (transient
/// chaos), which Newton from the cloud finds in a few tries.
pub fn close_returns(f: &Forcing, sections: &[Section]) -> (Vec<Orbit>, u64) {
    let newton = Newton::default();
    let tol = CLOSE_RETURN * f.half_gap();
    let mut found: Vec<Orbit> = Vec::new();
    let mut periods = 0;
    let mut tries = 0;
    for p in 1..=4usize {
        for k in 0..sections.len().saturating_sub(p) {
            if tries >= CLOSE_RETURN_TRIES
                || crate::orbits::shoot::distance(f, &sections[k + p], &sections[k]) >= tol
            {
                continue;
            }
            tries += 1;
            let pp = p as u64;
            let (term, state) = solve(f, pp, &sections[k], &newton);
            if let Some(st) = &state {
                periods += u64::from(st.iterations + 1) * pp;
            }
            if let (Termination::Converged { .. }, Some(st)) = (term, state)
                && let Some(o) = orbit_at(f, pp, &st, &newton)
                && o.stability == Stability::Stable
                && !found
                    .iter()
                    .any(|q| q.period == o.period && same_orbit(f, &q.s, &o.s, u64::from(o.period)))
            {
                found.push(o);
            }
        }
    }
    (found, periods)
}

pub(super) fn failed(periods: u64, end: Section) -> Settled {
    Settled {
        landing: Landing::NonPeriodic {
            amplitude: f64::NAN,
            impacts_per_period: f64::NAN,
            wandering: Box::new(Wandering {
                cloud: Cloud::default(),
                probe: None,
                exhausted: false,
                embedded: Vec::new(),
                life: None,
                chains: Vec::new(),
            }),
        },
        periods,
        end,
    }
}

/// Periods of the transient rule before a start that has not converged is probed for chaos.
pub const FIRST_CHECK: u64 = 100;

/// Periods of that probe (the tangent map's exponent over them).
pub const PROBE: u64 = 64;

/// Periods in all after which a member of a cloud whose first wanderer ran its whole budget
/// joins that attractor (module doc).
pub const JOIN_AFTER: u64 = FIRST_CHECK + PROBE;

/// The sweep's transient rule from `s` for at most `max` periods, stopped at the hand-over
/// tolerance, then `2 * MAX_PERIOD` periods that give the period approached. Returns the run and
/// the periods it simulated.
pub(super) fn transient(
    f: &Forcing,
    s: &Section,
    c: &CensusSettings,
    max: u64,
) -> (HarmonicRecord, u64) {
    let scene = Harmonic {
        F0: f.F0,
        drive: Drive::Omega(f.omega),
        n_trans: None,
        n_trans_max: max.max(1),
        n_meas: 2 * MAX_PERIOD as u64,
        trans_tol: c.handover * 1e-3,
        period_tol: c.handover,
        energies: false,
        ..Harmonic::default()
    };
    let sys = f.started(s);
    let rec = simulate_harmonic(
        &sys,
        &f.settings,
        &Request::default(),
        &scene,
        None,
        &mut NoProbe,
    );
    let periods = rec.n_trans + rec.n_meas;
    (rec, periods)
}

pub(super) fn section_of(rec: &HarmonicRecord) -> Section {
    [rec.end.x, rec.end.v, rec.end.y - rec.end.x, rec.end.w]
}
