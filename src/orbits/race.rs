//! Life amplitudes only where they can change the decision: a race over one curve's steady
//! states that are not periodic (docs/scenes.md, "The amplitude over a design life").
//!
//! A curve serves two decisions: its design quantity, the largest design amplitude over its
//! frequencies and their attractors (the **peak**), and at each frequency whether the damper
//! helps (the frequency's design amplitude below the main mass's linear amplitude there,
//! [`crate::model::System::linear_amplitude`]: the band and share where it helps). A periodic
//! orbit's amplitude is exact; a motion that is not periodic has an amplitude over the design
//! life that only a long measurement estimates ([`super::life`]: its 90 % interval narrows from
//! about ±50 % after 2,000 periods to ±5 % after some 10^5 to 10^6 on the slowest tails). So:
//!
//! 1. **Estimate** every one from [`LifeSettings::first`] periods, with its 90 % interval. (No
//!    motion is screened out by its window maximum: on the showcase a motion's life amplitude
//!    reached 2.3 times its 200-period window maximum.)
//! 2. **The peak.** Its interval is `[lower, upper]`: the largest periodic amplitude and lower
//!    end of an interval, and the largest periodic amplitude and upper end. While it is wider
//!    than the tolerance (`upper - lower > 2 tol peak`), the motion with the highest upper end
//!    that could still carry the peak (upper end above `lower`) is measured again (its window
//!    doubled). The motion with the largest estimate, the **leader**, may be measured up to its
//!    cap (`life_max_periods`), also when a periodic orbit is higher than every estimate (short
//!    measurements of a slow tail run low, and a leader that could only be the orbit would have
//!    let the orbit carry a peak that brute force puts 3 % above it); the others only up to a
//!    sixteenth of the cap ([`SCREEN`]): a motion
//!    that is not the leader cannot settle the peak by itself, and refining every motion of a
//!    chaotic plateau to the tolerance costs several times the rest of a study (measured on the
//!    bundled frequency-response study: 1.4 * 10^8 periods against 4 * 10^7 with the screen; a
//!    screened motion whose estimate overtakes the leader's becomes the leader and goes on).
//!    A leader whose last window met the tolerance is measured again while it could carry
//!    the peak, even where the peak's interval is already narrow enough: a measurement settles
//!    only when three successive windows meet the tolerance ([`LifeRun::settled`]).
//! 3. **Where the damper helps.** Then each motion whose interval holds the linear amplitude at
//!    its frequency is measured again until it no longer does, meets the tolerance or reaches
//!    the screen.
//! 4. **As smooth as the physics near the peak** ([`dip`]). A frequency's value is its largest
//!    estimate. Where it lies more than the tolerance below the lower end of a neighbouring
//!    frequency's value that is at the peak (`value < (1 - tol) lo`, the neighbour's value within
//!    the tolerance of the peak's lower end), and no periodic orbit at the frequency reaches that,
//!    its motion is measured again, past the screen up to the cap, until it no longer does or is
//!    settled. A short measurement of a slow tail reads low, and its interval misses above more
//!    often than its 90 % says: on the chaotic band of `scripts/band_smoothness.sh` the motions
//!    such frequencies stopped on read 0.60 to 0.92 cm where brute force gives about 0.98 cm,
//!    after 2,000 to 64,000 periods. A frequency far below the peak keeps its estimate and its
//!    interval: it decides nothing.
//!
//! 5. **The whole curve, when asked** (`[scene] life_curve = "whole"`, [`LifeCurve::Whole`];
//!    [`whole_curve`]). Last, at every frequency each motion that could still carry the
//!    frequency's value (its upper end above the frequency's largest lower end and periodic
//!    amplitude) is measured, past the screen up to the cap, until it no longer could or is
//!    settled: the values the charts draw between the decisions are then measured as long as
//!    the peak's, at several times the race's periods (`results/life_curve.md`: on the chaotic
//!    band of m = 20 g, d = 20 mm, r = 0.94 ... 1.02, over 20 study seeds).
//!
//! Steps 3 to 5 run on a curve that is drawn and read frequency by frequency (the ideal
//! case's, [`Serves::Curve`]); a perturbed case's curve serves its peak alone
//! ([`Serves::Peak`]).
//!
//! Deterministic: the motions are measured from their stored states, their first estimates side
//! by side, then one at a time in an order the rule fixes (each measurement's chains run in
//! parallel). A scene with `nonperiodic_peak = "window"` ([`NonPeriodicPeak::Window`]) takes no
//! part: its motions keep their census window's maximum.
//!
//! A curve of several units races the same way ([`race_units`]): each frequency's starts that did
//! not settle make one motion, measured by the map of several units ([`PeriodMap`]).

use super::census::{Census, Kind};
use super::life::{LifeRun, LifeSettings, MIN_CHAINS, PeriodMap, topped_up};
use super::map::Forcing;
use super::units::census::{RestLanding, UnitsCensus};
use super::units::map::UnitsMap;
use crate::sim::Harmonic;
use crate::sim::harmonic::{LifeCurve, NonPeriodicPeak};
use crate::stats::extremes::LifeEstimate;
use rayon::prelude::*;

/// Periods of a motion's first life estimate.
pub const FIRST: u64 = 2000;

/// The life settings of a scene at forcing `f`: its design life in forcing periods.
pub fn settings(f: &Forcing, h: &Harmonic) -> LifeSettings {
    LifeSettings {
        n_life: h.design_life / f.period(),
        quantile: h.life_quantile,
        tol: h.life_tol,
        first: FIRST.min(h.life_max_periods),
        cap: h.life_max_periods,
    }
}

/// A motion in the race: where it is (frequency and attractor index), its forcing, the linear
/// amplitude there (m), settings, exponent and measurement.
struct Runner<M: PeriodMap> {
    at: (usize, usize),
    f: M,
    linear: f64,
    s: LifeSettings,
    lambda: f64,
    run: LifeRun<M::State>,
    active: bool,
}

/// What the race's rule sees of a motion: its estimate, periods measured, whether it can be
/// measured further (not failed, not settled, not at its cap), whether its last window met the
/// tolerance ([`LifeRun::meets`]), the linear amplitude at its frequency (m) and that
/// frequency's place in the curve (by forcing frequency, from 0).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    estimate: Option<LifeEstimate>,
    periods: u64,
    active: bool,
    meets: bool,
    linear: f64,
    freq: usize,
}

impl Entry {
    /// The motion's interval, unbounded before its first estimate.
    fn interval(&self) -> (f64, f64) {
        self.estimate
            .map_or((f64::NEG_INFINITY, f64::INFINITY), |e| (e.lo, e.hi))
    }
}

/// The share of the cap a motion is measured to unless it leads the curve (module doc).
pub const SCREEN: u64 = 16;

/// The motion the race measures next (module doc), or `None` when it is over: `periodic` is the
/// largest periodic amplitude of the curve, `tol` and `cap` the scene's `life_tol` and
/// `life_max_periods`; `all` refines every motion to its tolerance; `help`: step 3 runs (where the
/// damper helps, [`Serves::Curve`]).
fn next(
    motions: &[Entry],
    periodic: f64,
    tol: f64,
    cap: u64,
    all: bool,
    help: bool,
) -> Option<usize> {
    if all {
        return motions.iter().position(|m| m.active);
    }
    let lower = peak_lower(motions, periodic);
    let upper = motions
        .iter()
        .map(|m| m.interval().1)
        .fold(periodic, f64::max);
    // The leader is the motion with the largest estimate even where a periodic orbit is
    // higher: while the peak's interval is open, it is the one most likely to overtake that
    // orbit, and a leader that could only be the periodic orbit would leave every motion at
    // its screen, however far above the orbit its interval reaches.
    let (leader, best) = motions
        .iter()
        .enumerate()
        .filter_map(|(i, m)| m.estimate.map(|e| (Some(i), e.amplitude)))
        .fold(
            (None, f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        );
    let peak = best.max(periodic);
    let open = |i: usize, m: &Entry| m.active && (Some(i) == leader || m.periods < cap / SCREEN);
    if upper - lower > 2.0 * tol * peak {
        let carrier = motions
            .iter()
            .enumerate()
            .filter(|&(i, m)| open(i, m) && m.interval().1 > lower)
            .max_by(|a, b| a.1.interval().1.total_cmp(&b.1.interval().1))
            .map(|(i, _)| i);
        if carrier.is_some() {
            return carrier;
        }
    }
    // A leader whose last window met the tolerance, and that could carry the peak, is measured
    // again: the next windows must meet it too ([`LifeRun::settled`]), though the peak's
    // interval may already be narrow enough.
    if let Some(l) = leader
        && open(l, &motions[l])
        && motions[l].meets
        && motions[l].interval().1 > lower
    {
        return Some(l);
    }
    if !help {
        return None;
    }
    motions.iter().enumerate().position(|(i, m)| {
        let (lo, hi) = m.interval();
        open(i, m) && lo <= m.linear && m.linear <= hi
    })
}

/// The lower end of a curve's peak: the largest periodic amplitude `periodic` and lower end of
/// an interval.
fn peak_lower(motions: &[Entry], periodic: f64) -> f64 {
    motions
        .iter()
        .map(|m| m.interval().0)
        .fold(periodic, f64::max)
}

/// Step 4 of the race (module doc): the motion that carries a frequency's value where that
/// value lies more than `tol` below the lower end of a neighbouring frequency's value at the
/// peak (at or above `(1 - tol) lower`, `lower` the peak's lower end), or `None`.
/// `periodic_at[q]` is the largest periodic amplitude at the curve's `q`-th frequency (`-inf`
/// without one).
///
/// On the chaotic band of `scripts/band_smoothness.sh` (80 study seeds) this rule keeps every
/// seed's neighbouring frequencies within brute force's step plus their stated error, and 79
/// of 80 within brute force's step plus 5 % (71 of 80 without it).
/// On the bundled frequency-response study the race measures 9.6 * 10^6 periods with it and
/// 7.7 * 10^6 without; counting every neighbour instead of those at the peak, 3.5 * 10^7 (and
/// 1.34 * 10^7 counting those whose interval reaches the peak): most dips lie well below their
/// design's peak and decide nothing (BENCHMARKS.md, "Stop 62").
fn dip(motions: &[Entry], periodic_at: &[f64], lower: f64, tol: f64) -> Option<usize> {
    // Each frequency's value: the motion with its largest estimate.
    let mut top: Vec<Option<(usize, LifeEstimate)>> = vec![None; periodic_at.len()];
    for (i, m) in motions.iter().enumerate() {
        if let Some(e) = m.estimate
            && top[m.freq].is_none_or(|(_, b)| e.amplitude > b.amplitude)
        {
            top[m.freq] = Some((i, e));
        }
    }
    (0..top.len()).find_map(|q| {
        let (i, e) = top[q]?;
        let floor = [q.wrapping_sub(1), q + 1]
            .iter()
            .filter_map(|&k| top.get(k).copied().flatten())
            .filter(|(_, n)| n.amplitude >= (1.0 - tol) * lower)
            .map(|(_, n)| (1.0 - tol) * n.lo)
            .fold(f64::NEG_INFINITY, f64::max);
        (motions[i].active && e.amplitude < floor && periodic_at[q] < floor).then_some(i)
    })
}

/// Step 5 of the race (module doc), on a curve whose study asks for the whole curve: the
/// motion with the highest upper end among those that could still carry their frequency's
/// value (measurable, upper end above the largest lower end and the largest periodic amplitude
/// `periodic_at` at their frequency), or `None` when every frequency's value is settled, capped
/// or carried by a periodic orbit. A motion without an estimate yet has no upper bound.
fn whole_curve(motions: &[Entry], periodic_at: &[f64]) -> Option<usize> {
    let mut lower = periodic_at.to_vec();
    for m in motions {
        lower[m.freq] = lower[m.freq].max(m.interval().0);
    }
    motions
        .iter()
        .enumerate()
        .filter(|(_, m)| m.active && m.interval().1 > lower[m.freq])
        .max_by(|a, b| a.1.interval().1.total_cmp(&b.1.interval().1))
        .map(|(i, _)| i)
}

/// What a curve's values serve, and so which of the race's rules run on it (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Serves {
    /// The curve itself: the ideal case's, which the report draws and reads frequency by
    /// frequency (where the damper helps) besides its peak. Every rule runs.
    Curve,
    /// Its peak alone: a perturbed case's curve, one sample of its design's stress (the summary's
    /// band, shares and charts are the ideal curve's). Steps 1 and 2 run; step 3 (where the
    /// damper helps) and step 4 (a dip beside the peak) decide nothing on it. On the bundled
    /// frequency-response study, with them left out on the perturbed cases the whole summary
    /// (every design's peaks over its cases, ranks, reliabilities) came out bit for bit the same;
    /// step 4 alone had measured 13 of the race's 58 million periods there (BENCHMARKS.md,
    /// "Stop 64").
    Peak,
}

/// Runs the race over a curve (module doc): `points[i]` is frequency `i`'s forcing and scene
/// (`None` where it has no census), `serves` what its values are for; the life estimates land
/// in each motion's [`super::census::Wandering::life`] and its design amplitude becomes the
/// estimate.
pub fn race(
    points: &[Option<(Forcing, Harmonic)>],
    censuses: &mut [Option<Census>],
    serves: Serves,
) {
    race_with(points, censuses, false, serves);
}

/// What the race saves, for the benchmarks: every motion that is not periodic measured to the
/// tolerance (or its cap), none stopped by the leader.
pub fn refine_all(points: &[Option<(Forcing, Harmonic)>], censuses: &mut [Option<Census>]) {
    race_with(points, censuses, true, Serves::Curve);
}

/// One step of a runner's measurement ([`LifeRun::grow`]); whether it may go on. A motion with
/// no estimate after its second window (`2 first` periods) whose maxima repeat
/// ([`LifeRun::repeats`]: a transient that reached a periodic orbit) stops there: longer runs of
/// the same maxima would not show a tail (on a newcomer's study of the structure without a
/// damper such motions grew to the screen, 64,000 periods each, for nothing). One whose maxima
/// are irregular goes on: a chaotic transient still approaching its attractor has its largest
/// values in a few long build-ups, too few clusters to fit, until it arrives (at the bundled
/// study's m = 10 g, d = 20 mm, r = 0.935 the census's motion reached 0.899 cm in 4,000 periods
/// without an estimate, and its attractor 0.91 cm).
fn grow<M: PeriodMap>(r: &mut Runner<M>) -> bool {
    let more = r.run.grow(&r.f, &r.s, r.lambda);
    more && (r.run.estimate.is_some() || r.run.periods() < 2 * r.s.first || !r.run.repeats())
}

/// One measurement of `r` ([`grow`]), which stays active while it can grow; no rule measures an
/// inactive motion again, so its per-period maxima go ([`LifeRun::retire`]).
fn advance<M: PeriodMap>(r: &mut Runner<M>) {
    r.active = grow(r);
    if !r.active {
        r.run.retire();
    }
}

fn race_with(
    points: &[Option<(Forcing, Harmonic)>],
    censuses: &mut [Option<Census>],
    all: bool,
    serves: Serves,
) {
    let mut runners = Vec::new();
    for (i, (p, c)) in points.iter().zip(censuses.iter()).enumerate() {
        let (Some((f, h)), Some(c)) = (p, c) else {
            continue;
        };
        // `nonperiodic_peak = "window"`: the window's maximum stays the design amplitude.
        if h.nonperiodic_peak == NonPeriodicPeak::Window {
            continue;
        }
        for (j, a) in c.attractors.iter().enumerate() {
            if let Kind::NonPeriodic(w) = &a.kind
                && a.window_amplitude.is_finite()
            {
                runners.push(Runner {
                    at: (i, j),
                    f: f.clone(),
                    linear: f.sys.linear_amplitude(f.F0, f.ratio()),
                    s: settings(f, h),
                    lambda: w.probe.map_or(f64::NAN, |p| p.lambda),
                    run: LifeRun::chains(
                        std::iter::once(a.section)
                            .chain(w.chains.iter().copied())
                            .collect(),
                    ),
                    active: true,
                });
            }
        }
    }
    let omega = omegas(points);
    let periodic_at: Vec<f64> = censuses
        .iter()
        .map(|c| {
            c.iter()
                .flat_map(|c| &c.attractors)
                .filter(|a| matches!(a.kind, Kind::Periodic(_)))
                .map(|a| a.amplitude)
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect();
    contest(
        &mut runners,
        &omega,
        &periodic_at,
        all,
        whole(points, serves),
        serves,
    );
    // Motions that turned out to be transients onto a periodic orbit the census holds at their
    // point, removed after every result is written (their indices stay valid until then).
    let mut landed: Vec<(usize, usize, usize)> = Vec::new();
    for r in runners {
        let Some(c) = censuses[r.at.0].as_mut() else {
            continue;
        };
        let summary = r.run.summary();
        if summary.estimate.is_none()
            && r.run.repeats()
            && let Some(k) = orbit_reached(c, r.run.last_max())
        {
            landed.push((r.at.0, r.at.1, k));
        }
        let a = &mut c.attractors[r.at.1];
        // Without an estimate, the largest value measured (a lower bound of the life's).
        a.amplitude = summary
            .estimate
            .map_or(summary.window_max, |e| e.amplitude)
            .max(a.window_amplitude);
        if let Kind::NonPeriodic(w) = &mut a.kind {
            w.life = Some(summary);
        }
    }
    // Starts join their orbits first (indices as found), then removals from the highest index.
    for &(i, j, k) in &landed {
        if let Some(c) = censuses[i].as_mut() {
            let starts = c.attractors[j].starts;
            c.attractors[k].starts += starts;
        }
    }
    landed.sort_unstable_by(|a, b| b.cmp(a));
    for (i, j, _) in landed {
        if let Some(c) = censuses[i].as_mut() {
            c.attractors.remove(j);
        }
    }
}

/// The race over a curve of several units' censuses (module doc; model.md §14): at each
/// frequency each motion of the census that is not periodic ([`UnitsCensus::motions`]) with its
/// starts' end states as its chains, measured period by period by the map of several units
/// ([`UnitsMap`]: every extremum located, no floor), clusters of exceedances separated by
/// [`super::life::cluster_run`] of the motion's exponent ([`super::units::motion::UnitsMotion::probe`]; 50 periods,
/// that of a slowly mixing motion, without one). Its summary lands in [`super::units::motion::UnitsMotion::life`]. A
/// motion whose maxima came to repeat at a periodic orbit's amplitude (a slow transient) is that
/// orbit: its starts join it.
pub fn race_units(
    points: &[Option<(Forcing, Harmonic)>],
    censuses: &mut [Option<UnitsCensus>],
    serves: Serves,
) {
    let mut runners = Vec::new();
    for (i, (p, c)) in points.iter().zip(censuses.iter()).enumerate() {
        let (Some((f, h)), Some(c)) = (p, c) else {
            continue;
        };
        if h.nonperiodic_peak == NonPeriodicPeak::Window {
            continue;
        }
        for (j, m) in c.motions.iter().enumerate() {
            if m.states.is_empty() {
                continue;
            }
            runners.push(Runner {
                at: (i, j),
                f: UnitsMap(f.clone()),
                linear: f.sys.linear_amplitude(f.F0, f.ratio()),
                s: settings(f, h),
                lambda: m.probe.map_or(f64::NAN, |p| p.lambda),
                run: LifeRun::chains(m.states.clone()),
                active: true,
            });
        }
    }
    let omega = omegas(points);
    let periodic_at: Vec<f64> = points
        .iter()
        .zip(censuses.iter())
        .map(|(p, c)| match (p, c) {
            (Some((f, _)), Some(c)) => units_periodic(f, c),
            _ => f64::NEG_INFINITY,
        })
        .collect();
    contest(
        &mut runners,
        &omega,
        &periodic_at,
        false,
        whole(points, serves),
        serves,
    );
    // Motions that turned out to be transients onto a periodic orbit of their census, removed
    // after every result is written (their indices stay valid until then).
    let mut landed: Vec<(usize, usize, usize)> = Vec::new();
    for r in runners {
        let Some(c) = censuses[r.at.0].as_mut() else {
            continue;
        };
        let summary = r.run.summary();
        let top = r.run.last_max();
        let reached = c
            .attractors
            .iter()
            .position(|a| (a.orbit.amplitude - top).abs() <= 1e-6 * a.orbit.amplitude);
        match reached {
            Some(k) if summary.estimate.is_none() && r.run.repeats() => {
                landed.push((r.at.0, r.at.1, k));
            }
            _ => c.motions[r.at.1].life = Some(summary),
        }
    }
    landed.sort_unstable_by(|a, b| b.cmp(a));
    for (i, j, k) in landed {
        if let Some(c) = censuses[i].as_mut() {
            let m = c.motions.remove(j);
            c.attractors[k].starts += m.starts;
            c.rest = match c.rest {
                RestLanding::Motion(r) if r == j => RestLanding::Orbit(k),
                RestLanding::Motion(r) if r > j => RestLanding::Motion(r - 1),
                rest => rest,
            };
        }
    }
}

/// Whether step 5 (the whole curve) runs: on a curve the report draws ([`Serves::Curve`]) of a
/// study that asks for it (`life_curve = "whole"`, a study-wide key).
fn whole(points: &[Option<(Forcing, Harmonic)>], serves: Serves) -> bool {
    serves == Serves::Curve
        && points
            .iter()
            .flatten()
            .any(|(_, h)| h.life_curve == LifeCurve::Whole)
}

/// Each frequency's forcing frequency (rad/s; NaN where it has no census).
fn omegas(points: &[Option<(Forcing, Harmonic)>]) -> Vec<f64> {
    points
        .iter()
        .map(|p| p.as_ref().map_or(f64::NAN, |p| p.0.omega))
        .collect()
}

/// The largest periodic amplitude of a census of several units at `f` (m): its impacting
/// orbits' and, when starts reached it, the non-impacting family's (the structure's forced
/// response alone); `-inf` without either.
fn units_periodic(f: &Forcing, c: &UnitsCensus) -> f64 {
    let neutral = if c.non_impacting > 0 {
        super::attractors::neutral_amplitude(f)
    } else {
        f64::NEG_INFINITY
    };
    c.attractors
        .iter()
        .map(|a| a.orbit.amplitude)
        .fold(neutral, f64::max)
}

/// The race itself (module doc) over `runners`, the motions of a curve whose frequency `i` has
/// forcing frequency `omega[i]` (rad/s; NaN where it has no census) and largest periodic
/// amplitude `periodic[i]` (m; `-inf` without one): each motion's first estimate, then one
/// measurement at a time as the rule picks them (`whole`: step 5 too). What one unit's census
/// and that of several units share ([`race`], [`race_units`]).
fn contest<M: PeriodMap>(
    runners: &mut [Runner<M>],
    omega: &[f64],
    periodic: &[f64],
    all: bool,
    whole: bool,
    serves: Serves,
) {
    // Every motion's first estimate: each a pure function of its own states, so they run side by
    // side (a motion of one or three chains alone would leave a core idle).
    // A motion of fewer states than MIN_CHAINS gets nudged copies first (`topped_up`).
    runners.par_iter_mut().for_each(|r| {
        if r.run.starts.len() < MIN_CHAINS {
            r.run = LifeRun::chains(topped_up(&r.f, std::mem::take(&mut r.run.starts)));
        }
        advance(r);
    });
    // The curve's frequencies in order of forcing frequency: each one's place, and its largest
    // periodic amplitude.
    let mut order: Vec<usize> = (0..omega.len()).collect();
    order.sort_by(|&a, &b| omega[a].total_cmp(&omega[b]));
    let mut place = vec![0; omega.len()];
    for (q, &i) in order.iter().enumerate() {
        place[i] = q;
    }
    let periodic_at: Vec<f64> = order.iter().map(|&i| periodic[i]).collect();
    let periodic = periodic_at
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let (tol, cap) = runners.first().map_or((0.0, 0), |r| (r.s.tol, r.s.cap));
    loop {
        let entries: Vec<Entry> = runners
            .iter()
            .map(|r| Entry {
                estimate: r.run.estimate,
                periods: r.run.periods(),
                active: r.active,
                meets: r.run.meets(&r.s),
                linear: r.linear,
                freq: place[r.at.0],
            })
            .collect();
        let curve = serves == Serves::Curve;
        let found = next(&entries, periodic, tol, cap, all, curve)
            .or_else(|| {
                curve
                    .then(|| dip(&entries, &periodic_at, peak_lower(&entries, periodic), tol))
                    .flatten()
            })
            .or_else(|| whole.then(|| whole_curve(&entries, &periodic_at)).flatten());
        let Some(i) = found else {
            break;
        };
        advance(&mut runners[i]);
    }
}

/// The periodic attractor of census `c` whose amplitude is `top`, the largest of a motion's last
/// per-period maxima after they began to repeat (to 1e-6 relative): a start that was still
/// approaching that orbit when the census's budget ended (a multiplier near 1) and reached it
/// during its life measurement. It is that orbit, and its starts join the orbit's basin. (On
/// the bundled study one such start at r = 0.94 measured 4,000 periods whose maxima repeated
/// at the census's period-4 orbit's amplitude, 5.6e-6 relative above it in its window.)
fn orbit_reached(c: &Census, top: f64) -> Option<usize> {
    c.attractors.iter().position(|a| {
        matches!(a.kind, Kind::Periodic(_)) && (a.amplitude - top).abs() <= 1e-6 * a.amplitude
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion with estimate `a` in `[lo, hi]` (m) after `periods`, the linear amplitude at its
    /// frequency 1 mm.
    fn motion(a: f64, lo: f64, hi: f64, periods: u64) -> Entry {
        Entry {
            estimate: Some(LifeEstimate {
                amplitude: a,
                lo,
                hi,
                threshold: 0.0,
                sigma: 0.0,
                xi: 0.0,
                xi_se: 0.0,
                end_point: f64::NAN,
                exceedances: 0,
                measured: periods,
                lowest_threshold: 0.0,
            }),
            periods,
            active: true,
            meets: 0.5 * (hi - lo) <= 0.05 * a,
            linear: 1e-3,
            freq: 0,
        }
    }

    #[test]
    fn the_motion_that_could_carry_the_peak_highest_is_measured_first() {
        let ms = [
            motion(9e-3, 7e-3, 12e-3, 16_000),
            motion(8e-3, 6e-3, 14e-3, 16_000),
        ];
        // The peak is in [7, 14] mm: the second reaches highest.
        assert_eq!(next(&ms, 0.0, 0.05, 1 << 20, false, true), Some(1));
        // A periodic orbit of 15 mm carries the peak exactly: nothing can change it.
        assert_eq!(next(&ms, 15e-3, 0.05, 1 << 20, false, true), None);
    }

    #[test]
    fn only_the_leader_is_measured_past_the_screen() {
        let cap = 1 << 20;
        let screened = cap / SCREEN;
        // The second reaches highest but has had its screen; the leader (the larger estimate)
        // goes on.
        let ms = [
            motion(9e-3, 7e-3, 12e-3, 2000),
            motion(8e-3, 6e-3, 14e-3, screened),
        ];
        assert_eq!(next(&ms, 0.0, 0.05, cap, false, true), Some(0));
        // Once the leader is within the tolerance and the other screened, the race is over,
        // though the peak's interval is still wider.
        let ms = [
            motion(9e-3, 8.8e-3, 9.2e-3, 2000),
            motion(8e-3, 6e-3, 14e-3, screened),
        ];
        let mut ms = ms;
        ms[0].active = false;
        assert_eq!(next(&ms, 0.0, 0.05, cap, false, true), None);
    }

    /// The showcase's m = 20 g, d = 20 mm with the simulator of `39736dd`: an impact-free orbit of
    /// 0.974 cm at r = 1.01 above every chaotic estimate (0.94 to 0.967 cm after their screens,
    /// low as short measurements of a slow tail are), their intervals reaching 1.1 to 1.6 cm.
    /// The peak is open: the largest estimate goes on past its screen (at 1,024,000 periods
    /// such a motion measures 1.00 cm, brute force's value).
    #[test]
    fn a_periodic_orbit_above_the_estimates_leaves_the_largest_to_go_on() {
        let cap = 1 << 20;
        let screened = cap / SCREEN;
        let ms = [
            motion(9.56e-3, 9.41e-3, 13.8e-3, screened),
            motion(9.67e-3, 9.57e-3, 11.1e-3, screened),
            motion(9.41e-3, 9.14e-3, 15.9e-3, screened),
        ];
        assert_eq!(next(&ms, 9.74e-3, 0.05, cap, false, true), Some(1));
        // Once the leader has settled and the others have had their screens, the race is over.
        let mut ms = ms;
        ms[1] = motion(9.67e-3, 9.5e-3, 9.9e-3, 4 * screened);
        ms[1].active = false;
        assert_eq!(next(&ms, 9.74e-3, 0.05, cap, false, true), None);
    }

    #[test]
    fn a_peak_within_the_tolerance_leaves_the_help_decision() {
        // The peak is settled ([9.8, 10.2] mm, its leader's two last windows within the
        // tolerance); the other motion's interval holds the linear amplitude at its frequency
        // (1 mm): it is measured.
        let mut ms = [
            motion(10e-3, 9.8e-3, 10.2e-3, 4000),
            motion(1.1e-3, 0.8e-3, 1.6e-3, 2000),
        ];
        ms[0].active = false;
        assert_eq!(next(&ms, 0.0, 0.05, 1 << 20, false, true), Some(1));
        // Not on a curve that serves its peak alone (a perturbed case's: `Serves::Peak`).
        assert_eq!(next(&ms, 0.0, 0.05, 1 << 20, false, false), None);
        // Not once its interval clears it.
        ms[1] = motion(1.3e-3, 1.1e-3, 1.6e-3, 4000);
        assert_eq!(next(&ms, 0.0, 0.05, 1 << 20, false, true), None);
    }

    /// The stopping rule asks successive windows to meet the tolerance
    /// ([`super::life::SETTLE_WINDOWS`]): a leader whose first window within it narrows the
    /// peak's interval enough is still measured while it could carry the peak, and not when a
    /// periodic orbit above its interval carries it.
    #[test]
    fn a_leader_within_the_tolerance_once_is_measured_once_more() {
        let ms = [motion(10e-3, 9.8e-3, 10.2e-3, 128_000)];
        assert_eq!(next(&ms, 0.0, 0.05, 1 << 20, false, true), Some(0));
        assert_eq!(next(&ms, 10.5e-3, 0.05, 1 << 20, false, true), None);
        // Settled (not active): the race is over.
        let mut ms = ms;
        ms[0].active = false;
        assert_eq!(next(&ms, 0.0, 0.05, 1 << 20, false, true), None);
    }

    /// `m` at the curve's `q`-th frequency.
    fn at(m: Entry, q: usize) -> Entry {
        Entry { freq: q, ..m }
    }

    /// Step 5: the motion reaching highest among those that could still carry their
    /// frequency's value is measured first, then the next; one under a periodic orbit or under
    /// a neighbour's lower end at its own frequency never is.
    #[test]
    fn the_whole_curve_measures_every_value_that_is_not_known() {
        let mut ms = [
            at(motion(5e-3, 4.5e-3, 9e-3, 2000), 0),
            // Under frequency 1's periodic orbit of 1 cm.
            at(motion(7e-3, 6e-3, 8e-3, 2000), 1),
            at(motion(7e-3, 6.8e-3, 7.5e-3, 64_000), 2),
            at(motion(5e-3, 4.5e-3, 6.9e-3, 2000), 2),
            // Under its frequency's lower end (6.8 mm).
            at(motion(5e-3, 4.5e-3, 6.7e-3, 2000), 2),
        ];
        let periodic_at = [f64::NEG_INFINITY, 1e-2, f64::NEG_INFINITY];
        let mut order = Vec::new();
        while let Some(i) = whole_curve(&ms, &periodic_at) {
            order.push(i);
            ms[i].active = false;
        }
        assert_eq!(order, [0, 2, 3]);
    }

    /// A curve of three frequencies: `first` at the first, `second` at the next, and at the
    /// third a leader at its cap, 9.891 mm [9.766, 10.188] (the band's seed 7 at r = 1.00); the
    /// second and the leader measured no further.
    fn beside_the_leader(first: Entry, second: Entry) -> [Entry; 3] {
        let mut ms = [
            at(first, 0),
            at(second, 1),
            at(motion(9.891e-3, 9.766e-3, 10.188e-3, 1 << 20), 2),
        ];
        ms[1].active = false;
        ms[2].active = false;
        ms
    }

    /// Study seed 7 of the band (`scripts/band_smoothness.sh`) before step 4: at r = 0.99 a
    /// motion measured 8,000 periods gave 0.764 cm [0.721, 0.975], its upper end just below the
    /// lower end of the peak's interval (0.977 cm), and the race stopped it there; measured on,
    /// it gave 0.971 cm, as its neighbour at r = 0.995 did (0.971 cm after 512,000 periods; the
    /// interval here is illustrative). It cannot carry the peak, but it lies more than the
    /// tolerance below a neighbour at the peak: it is measured on.
    #[test]
    fn a_frequency_well_below_a_neighbour_at_the_peak_is_measured_on() {
        let cap = 1 << 20;
        let mut ms = beside_the_leader(
            motion(7.637e-3, 7.206e-3, 9.75e-3, 8000),
            motion(9.711e-3, 9.6e-3, 9.85e-3, 512_000),
        );
        let none = [f64::NEG_INFINITY; 3];
        let lower = peak_lower(&ms, f64::NEG_INFINITY);
        assert_eq!(next(&ms, f64::NEG_INFINITY, 0.05, cap, false, true), None);
        assert_eq!(dip(&ms, &none, lower, 0.05), Some(0));
        // Also past its screen (seed 46: 0.885 cm after 64,000 periods beside 0.984 cm).
        ms[0] = at(motion(8.849e-3, 8.2e-3, 10.4e-3, cap / SCREEN), 0);
        assert_eq!(dip(&ms, &none, lower, 0.05), Some(0));
        // Not within the tolerance of it (0.95 * 9.6 mm = 9.12 mm)...
        ms[0] = at(motion(9.2e-3, 8.2e-3, 10.4e-3, 8000), 0);
        assert_eq!(dip(&ms, &none, lower, 0.05), None);
        // ...nor where a periodic orbit at its frequency reaches the neighbour's lower end...
        ms[0] = at(motion(7.637e-3, 7.206e-3, 9.75e-3, 8000), 0);
        let orbit = [9.2e-3, f64::NEG_INFINITY, f64::NEG_INFINITY];
        assert_eq!(dip(&ms, &orbit, lower, 0.05), None);
        // ...nor once it is settled or capped.
        ms[0].active = false;
        assert_eq!(dip(&ms, &none, lower, 0.05), None);
    }

    /// Far below the peak a frequency keeps its estimate however far it lies below its
    /// neighbour: neither can change a decision.
    #[test]
    fn a_frequency_below_a_neighbour_far_from_the_peak_decides_nothing() {
        let ms = beside_the_leader(
            motion(3e-3, 2e-3, 6e-3, 2000),
            motion(6e-3, 5.9e-3, 6.2e-3, 256_000),
        );
        let none = [f64::NEG_INFINITY; 3];
        let lower = peak_lower(&ms, f64::NEG_INFINITY);
        assert_eq!(dip(&ms, &none, lower, 0.05), None);
        // The same neighbour, were it at the peak: measured on.
        assert_eq!(dip(&ms, &none, 6e-3, 0.05), Some(0));
    }
}
