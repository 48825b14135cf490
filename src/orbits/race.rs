//! Life amplitudes only where they can change the decision: a race over one curve's steady
//! states that are not periodic (docs/scenes.md, "The amplitude over a design life").
//!
//! A curve serves two decisions: its design quantity, the largest design amplitude over its
//! frequencies and their attractors, and at each frequency whether the damper helps (the
//! frequency's design amplitude below the main mass's linear amplitude there,
//! [`crate::model::System::linear_amplitude`]: the band and share where it helps). A periodic
//! orbit's amplitude is exact; a motion that is not periodic has an amplitude over the design
//! life that only a long measurement estimates ([`super::life`], 10^3 to 10^5 periods each).
//! So:
//!
//! 1. **Estimate** every one from [`LifeSettings::first`] periods, with its 90 % interval. (No
//!    motion is screened out by its window maximum: on the showcase a motion's life amplitude
//!    reached 2.3 times its 200-period window maximum, and a screen at half the curve's largest
//!    window maximum lost the peak of two of its nine designs; BENCHMARKS.md.)
//! 2. **Race.** The leader's lower bound is the largest of the periodic amplitudes and the
//!    estimates' lower ends. A motion is refined (its window doubled) while it has neither met
//!    the tolerance nor its cap and its interval, widened by a factor `k` that shrinks as the
//!    measurement grows (`[lo / k, hi k]`, [`DROPS`]: a short sample's interval misses rare
//!    excursions), either reaches the leader's lower bound or holds the linear amplitude at its
//!    frequency. The race ends when none is left. The leader itself is refined to the
//!    tolerance.
//!
//! Deterministic: the motions are measured from their stored states, in curve order. A scene
//! with `nonperiodic_peak = "window"` ([`NonPeriodicPeak::Window`]) takes no part: its motions
//! keep their census window's maximum.

use super::census::{Census, Kind};
use super::life::{LifeRun, LifeSettings};
use super::map::Forcing;
use crate::sim::Harmonic;
use crate::sim::forced::NonPeriodicPeak;
use crate::stats::extremes::LifeEstimate;

/// Periods of a motion's first life estimate.
pub const FIRST: u64 = 2000;

/// The drop factor `k` from `periods` on (the last row that applies): a motion leaves the race
/// when its interval widened by it, `[lo / k, hi k]`, is below the leader's lower bound and
/// does not hold the linear amplitude at its frequency ([`may_drop`]). A short sample's
/// interval misses rare excursions: on the showcase a motion's first 4,000 periods showed a
/// bounded tail, 0.65 cm [0.64, 0.74], and the next 4,000 a rarer, larger excursion that moved
/// it to 1.14 cm [0.81, 1.44].
///
/// The factors are read from the distribution of the ratio of a motion's final life amplitude
/// to its interval's ends after `periods`, measured on the showcase's 45 curves with every
/// motion that is not periodic refined until its tolerance or its cap (`examples/race_drop.rs`,
/// `results/race_drop.md`), and checked on the decisions they serve:
/// - to the upper end, its 99.5th percentile was 1.55, 1.38, 1.15 and 1.02 after 2,000, 4,000,
///   8,000 and 16,000 periods (2,492 to 1,918 motions), and 1.51, 1.40, 1.27 and 1.04 with
///   another seed (other starts, other motions; `results/race_drop_seed7.md`). Each factor is
///   about a fifth above the larger of the two. To the lower end, its 0.5th percentile was
///   0.82, 0.89, 0.96 and 1.00 (0.87, 0.89, 0.91 and 1.00 with the other seed), well above
///   `1 / k`;
/// - its largest value was 2.36, 2.12, 2.00 and 1.15 (1.25 to 2.12 with the other seed): a rare
///   excursion's, and it moves with the sample. About 1 in 700 to 900 ratios lies outside
///   `[1 / k, k]`: such a motion can leave the race with a life amplitude other than refining
///   would give;
/// - what matters is whether a decision moves: on both seeds' 45 curves and the design map's 5
///   (`results/race_drop_design_map.md`) the race gives every design peak that refining every
///   motion gives (the same bits) and the same help decision at every frequency, at 52 % of
///   those periods. The factors of `c3daf45` (3, 2.5, 2.4 and 2, a fifth above the largest
///   ratio, with the upper end only) took 67 %, and the help decision rested on first
///   estimates.
///
/// (The rule before `6bd18b6`, the upper end itself below the leader after 8,000 periods,
/// could drop a motion whose life amplitude was 1.6 times that upper end.)
pub const DROPS: [(u64, f64); 4] = [(2000, 1.85), (4000, 1.65), (8000, 1.5), (16000, 1.25)];

/// Whether a motion measured for `periods` with estimate `e` may leave the race (module doc):
/// its interval widened by the factor of [`DROPS`], `[lo / k, hi k]`, lies below the leader's
/// lower bound `leader` and does not hold `linear`, the linear amplitude at its frequency
/// (whether the damper helps there does not rest on it).
fn may_drop(periods: u64, e: &LifeEstimate, leader: f64, linear: f64) -> bool {
    drop_factor(periods)
        .is_some_and(|k| e.hi * k < leader && !(e.lo / k <= linear && linear <= e.hi * k))
}

/// The drop factor `k` of a motion measured for `periods` (the last row of [`DROPS`] that
/// applies; `None` before the first).
pub fn drop_factor(periods: u64) -> Option<f64> {
    DROPS
        .iter()
        .rev()
        .find(|(n, _)| periods >= *n)
        .map(|&(_, k)| k)
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

/// A motion in the race: where it is (frequency and attractor index), its forcing, the linear
/// amplitude there (m), settings, exponent and measurement.
struct Runner {
    at: (usize, usize),
    f: Forcing,
    linear: f64,
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
                    .is_none_or(|e| !may_drop(r.run.periods(), &e, leader, r.linear));
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

#[cfg(test)]
mod tests {
    use super::*;

    /// An estimate with interval `[lo, hi]` (the rest does not enter the rule).
    fn estimate(lo: f64, hi: f64) -> LifeEstimate {
        LifeEstimate {
            amplitude: 0.5 * (lo + hi),
            lo,
            hi,
            threshold: 0.0,
            sigma: 0.0,
            xi: 0.0,
            xi_se: 0.0,
            end_point: f64::NAN,
            exceedances: 0,
            measured: 0,
        }
    }

    #[test]
    fn a_motion_leaves_the_race_only_when_neither_decision_rests_on_it() {
        // After 2,000 periods k = 1.85: [3, 4] mm widens to [1.62, 7.4] mm.
        let e = estimate(3e-3, 4e-3);
        // Below a 10 mm leader and a 1 mm linear amplitude: it decides nothing.
        assert!(may_drop(2000, &e, 10e-3, 1e-3));
        // Its widened interval reaches a 7 mm leader: it could carry the peak.
        assert!(!may_drop(2000, &e, 7e-3, 1e-3));
        // It holds a 2 mm linear amplitude at its frequency (whether the damper helps there),
        // though its interval does not: it stays.
        assert!(!may_drop(2000, &e, 10e-3, 2e-3));
        // From 16,000 periods on k = 1.25: [2.4, 5] mm, which no longer holds 2 mm.
        assert!(may_drop(16000, &e, 10e-3, 2e-3));
        // Before its first estimate's periods no rule applies.
        assert!(!may_drop(1000, &e, 10e-3, 1e-3));
    }
}
