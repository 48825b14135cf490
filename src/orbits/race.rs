//! Life amplitudes only where they can change the decision: a race over one curve's steady
//! states that are not periodic (docs/scenes.md, "The amplitude over a design life").
//!
//! A curve's design quantity is the largest design amplitude over its frequencies and their
//! attractors. A periodic orbit's amplitude is exact; a motion that is not periodic has an
//! amplitude over the design life that only a long measurement estimates
//! ([`super::life`], 10^3 to 10^5 periods each). So:
//!
//! 1. **Estimate** every one from [`LifeSettings::first`] periods, with its 90 % interval. (No
//!    motion is screened out by its window maximum: on the showcase a motion's life amplitude
//!    reached 2.3 times its 200-period window maximum, and a screen at half the curve's largest
//!    window maximum lost the peak of two of its nine designs; BENCHMARKS.md.)
//! 2. **Race.** The leader's lower bound is the largest of the periodic amplitudes and the
//!    estimates' lower ends. A motion is refined (its window doubled) while it has neither met
//!    the tolerance nor its cap and its interval's upper end, times a factor that shrinks as the
//!    measurement grows ([`DROPS`]: a short sample's interval misses rare excursions), reaches
//!    the leader's lower bound. The race ends when none is left. The leader itself is refined
//!    to the tolerance.
//!
//! Deterministic: the motions are measured from their stored states, in curve order. A scene
//! with `nonperiodic_peak = "window"` ([`NonPeriodicPeak::Window`]) takes no part: its motions
//! keep their census window's maximum.

use super::census::{Census, Kind};
use super::life::{LifeRun, LifeSettings};
use super::map::Forcing;
use crate::sim::Harmonic;
use crate::sim::forced::NonPeriodicPeak;

/// Periods of a motion's first life estimate.
pub const FIRST: u64 = 2000;

/// When a motion may leave the race: from `periods` on, when its interval's upper end times
/// `factor` is below the leader's lower bound (the last row that applies). A short sample's
/// interval misses rare excursions: on the showcase a motion's first 4,000 periods showed a
/// bounded tail, 0.65 cm [0.64, 0.74], and the next 4,000 a rarer, larger excursion that moved
/// it to 1.14 cm [0.81, 1.44]. Measured on the showcase's 45 curves (every motion that is not
/// periodic measured as the race does until its tolerance or its 20,000-period cap;
/// `examples/race_drop.rs`, `results/race_drop.md`), the final life amplitude reached at most
/// 2.36 times the upper end after 2,000 periods, and 1.89, 2.00 and 1.15 times after 4,000,
/// 8,000 and 16,000. Two measurements of other runs of the same motions had 2.36, 2.12, 1.61
/// and 1.09 (the frequencies computed as `0.8 + 0.005 i`, which differ from the study's grid in
/// the last bits) and 2.51, 1.60, 1.63 and 1.59 (the exact event finder before the life's
/// floor, `5c7683b`): the largest ratio is a rare excursion's, and it moves with the sample.
/// Each factor is about a fifth above the largest of the three. (The rule before `6bd18b6`, the
/// upper end itself below the leader after 8,000 periods, could drop a motion whose life
/// amplitude was 1.6 times that upper end; the rule of `6bd18b6`, factor 2 from 4,000 periods
/// on, one 2.1 times; the rule of `77b65ba`, factor 2 from 8,000 on, one 2.0 times.)
pub const DROPS: [(u64, f64); 4] = [(2000, 3.0), (4000, 2.5), (8000, 2.4), (16000, 2.0)];

/// Whether a motion measured for `periods` with upper end `hi` may leave the race against the
/// leader's lower bound `leader` ([`DROPS`]).
fn may_drop(periods: u64, hi: f64, leader: f64) -> bool {
    DROPS
        .iter()
        .rev()
        .find(|(n, _)| periods >= *n)
        .is_some_and(|&(_, factor)| hi * factor < leader)
}

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

/// A motion in the race: where it is (frequency and attractor index), its forcing, settings,
/// exponent and measurement.
struct Runner {
    at: (usize, usize),
    f: Forcing,
    s: LifeSettings,
    lambda: f64,
    run: LifeRun,
    active: bool,
}

/// Runs the race over a curve (module doc): `points[i]` is frequency `i`'s forcing and scene
/// (`None` where it has no census); the life estimates land in each motion's
/// [`super::census::Wandering::life`] and its design amplitude becomes the estimate.
pub fn race(points: &[Option<(Forcing, Harmonic)>], censuses: &mut [Option<Census>]) {
    race_with(points, censuses, false);
}

/// What the race saves, for the benchmarks: every motion that is not periodic measured to the
/// tolerance (or its cap), none stopped by the leader.
pub fn refine_all(points: &[Option<(Forcing, Harmonic)>], censuses: &mut [Option<Census>]) {
    race_with(points, censuses, true);
}

fn race_with(points: &[Option<(Forcing, Harmonic)>], censuses: &mut [Option<Census>], all: bool) {
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
    for r in &mut runners {
        r.active = r.run.grow(&r.f, &r.s, r.lambda);
    }
    loop {
        let periodic = censuses
            .iter()
            .flatten()
            .flat_map(|c| &c.attractors)
            .filter(|a| matches!(a.kind, Kind::Periodic(_)))
            .map(|a| a.amplitude)
            .fold(f64::NEG_INFINITY, f64::max);
        let leader = runners
            .iter()
            .filter_map(|r| r.run.estimate.map(|e| e.lo))
            .fold(periodic, f64::max);
        let mut any = false;
        for r in &mut runners {
            let reaches = all
                || r.run
                    .estimate
                    .is_none_or(|e| !may_drop(r.run.periods(), e.hi, leader));
            if r.active && reaches {
                r.active = r.run.grow(&r.f, &r.s, r.lambda);
                any = true;
            }
        }
        if !any {
            break;
        }
    }
    for r in runners {
        let Some(c) = censuses[r.at.0].as_mut() else {
            continue;
        };
        let a = &mut c.attractors[r.at.1];
        let summary = r.run.summary();
        if let Some(e) = summary.estimate {
            a.amplitude = e.amplitude.max(a.window_amplitude);
        }
        if let Kind::NonPeriodic(w) = &mut a.kind {
            w.life = Some(summary);
        }
    }
}
