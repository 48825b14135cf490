//! The decision verified (docs/scenes.md, "The decision verified"): the designs that decide a
//! harmonic study's ranking get their peak motions measured directly, and are ranked on that.
//!
//! A motion that is not periodic carries an estimate of its largest amplitude over the design
//! life, from the periods the sweep's race spent on it (a few thousand for a motion that does
//! not lead its curve, up to `life_max_periods` for one that does,
//! [`crate::orbits::race`]). Before the ranking is final:
//!
//! 1. **Which designs decide.** The best-ranked design of the ranking as the sweep measured it,
//!    and every design whose ideal-case peak interval (its 90 % interval; a periodic peak's is
//!    one point) overlaps the best design's: those whose order the estimates cannot settle.
//!    None when fewer than two designs rank: there is no order to decide.
//! 2. **Their peaks measured directly.** For each of their cases, the motions that are not
//!    periodic are taken in decreasing order of their estimate when one could still carry the
//!    case's peak (the upper end of its interval above the largest periodic amplitude and every
//!    value measured directly so far: a short measurement of a slow tail runs low), at most
//!    [`MOST`] per case. A motion whose estimate already rests on at
//!    least `verify_periods` periods (a race leader that grew to `life_max_periods`) is a direct
//!    measurement as it stands and is taken as it is; every other one is run again from its stored state on
//!    [`DIRECT_CHAINS`](crate::orbits::life::DIRECT_CHAINS) independent chains for
//!    `[ranking] verify_periods` periods in all (default 1,024,000, at least 10^6;
//!    [`crate::study::Ranking::verify_periods`]) and its design-life amplitude estimated from them
//!    ([`crate::orbits::life::measure_directly_above`]), its window doubling; it stops early once
//!    its interval lies wholly below the case's peak so far (it cannot carry the peak), so the
//!    motion that carries a case's peak always rests on the whole `verify_periods`. The case's
//!    peak becomes the largest of its periodic amplitudes, the direct values and the estimates
//!    not measured again.
//! 3. **Ranked on them.** The design's runs are reduced again with the new peaks, then the
//!    study is ranked ([`crate::reduce::common::Reducer::replace`]). The report shows each
//!    direct value beside the estimate, the periods it rests on, and the ranks it moved.
//!
//! Deterministic: every direct measurement is a pure function of the stored state, and the
//! designs and motions are chosen from the ranking and the stored estimates alone.

use rayon::prelude::*;

use crate::model::System;
use crate::orbits::attractors::AttractorRow;
use crate::orbits::life::{LifeSettings, LifeSummary, measure_directly_above};
use crate::orbits::map::{Forcing, Section};
use crate::orbits::race::FIRST;
use crate::orbits::units::map::UnitsMap;
use crate::sim::SolverSettings;
use crate::stats::extremes::LifeEstimate;
use crate::store::table::{Column, Table};

/// The most motions measured directly per case.
pub const MOST: usize = 3;

/// A motion that is not periodic, kept from the stored attractors for a verification: where
/// it is, a state on it (with several units, the whole state in `units`; empty for one unit),
/// its largest Lyapunov exponent (per forcing period; NaN when not measured) and its estimate
/// (m) with the 90 % interval and the periods it rests on.
#[derive(Clone, Debug, PartialEq)]
pub struct Contender {
    pub design: u64,
    pub case: u32,
    pub r: f64,
    pub omega: f64,
    pub f0: f64,
    pub section: Section,
    pub units: Vec<f64>,
    pub lambda: f64,
    pub amplitude: f64,
    pub lo: f64,
    pub hi: f64,
    pub measured: u64,
}

impl Contender {
    /// The contender of a stored attractor that is not periodic and has a design-life estimate
    /// (`None` for a periodic one, and for a motion whose estimate could not be made: its
    /// maxima show no tail to fit, so a longer run of it would not either).
    pub fn of(a: &AttractorRow, design: u64) -> Option<Contender> {
        let estimated = a.life_lo.is_finite() && a.life_hi.is_finite();
        (!a.kind.periodic() && estimated).then_some(Contender {
            design,
            case: a.run.case,
            r: a.run.r,
            omega: a.run.omega,
            f0: a.run.F0,
            section: a.section,
            units: a.section_units.clone(),
            lambda: a.lyapunov,
            amplitude: a.amplitude,
            lo: a.life_lo,
            hi: a.life_hi,
            measured: a.measured_periods,
        })
    }
}

/// What one case keeps for a verification while the parts stream in: the largest amplitude it
/// takes as it is (m: of its periodic orbits, and of motions with no design-life estimate), its
/// [`MOST`] highest motions that are not periodic, and the largest design amplitude of the
/// others (m; `-inf` when none), so memory stays bounded per case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseTop {
    pub periodic: f64,
    pub top: Vec<Contender>,
    pub rest: f64,
}

impl Default for CaseTop {
    fn default() -> Self {
        CaseTop {
            periodic: f64::NEG_INFINITY,
            top: Vec::new(),
            rest: f64::NEG_INFINITY,
        }
    }
}

impl CaseTop {
    /// Takes in one stored attractor of the case.
    pub fn add(&mut self, a: &AttractorRow, design: u64) {
        match Contender::of(a, design) {
            None => self.periodic = self.periodic.max(a.amplitude),
            Some(c) => self.push(c),
        }
    }

    /// Takes in a motion that is not periodic: the [`MOST`] highest stay (ties to the lower
    /// frequency), the others leave their amplitude in `rest`.
    pub fn push(&mut self, c: Contender) {
        self.top.push(c);
        self.top.sort_by(|x, y| {
            y.amplitude
                .total_cmp(&x.amplitude)
                .then(x.r.total_cmp(&y.r))
        });
        if self.top.len() > MOST
            && let Some(dropped) = self.top.pop()
        {
            self.rest = self.rest.max(dropped.amplitude);
        }
    }
}

/// One direct measurement beside the estimate it checks.
#[derive(Clone, Debug, PartialEq)]
pub struct Verified {
    pub motion: Contender,
    /// The design-life amplitude from the direct measurement and its 90 % interval (m), the
    /// periods it rests on, and the largest amplitude seen over them (m); `None` when the
    /// simulator stopped a chain, and when the motion was not run again.
    pub direct: Option<LifeSummary>,
    /// The motion was not run again: its estimate already rests on at least the verification's
    /// periods (the sweep's race grew it that far), so it is a direct measurement as it is.
    pub as_raced: bool,
}

impl Verified {
    /// The motion's design amplitude after the verification (m): the direct estimate (at least
    /// the largest amplitude seen), or the estimate when it was taken as raced or the direct
    /// measurement failed.
    pub fn value(&self) -> f64 {
        self.direct
            .and_then(|d| d.estimate.map(|e| e.amplitude.max(d.window_max)))
            .unwrap_or(self.motion.amplitude)
    }
}

/// A case's peak after its verification.
#[derive(Clone, Debug, PartialEq)]
pub struct CasePeak {
    pub design: u64,
    pub case: u32,
    /// The peak before and after (m).
    pub before: f64,
    pub after: f64,
    /// Whether the peak after rests on a periodic orbit or a direct measurement (not on an
    /// estimate that rests on fewer periods than the verification's).
    pub supported: bool,
    pub verified: Vec<Verified>,
    /// The verification's round that measured it (from 1: [`Verification::designs`]).
    pub round: usize,
}

/// A reduction's verification: the deciding designs, each verified case's peak, and the ranking
/// before it (design and rank, best first); empty when the reduction verifies nothing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Verification {
    /// Periods of each direct measurement (`[ranking] verify_periods`).
    pub periods: u64,
    /// The designs verified, in design order, and the rounds they took (the first round's
    /// designs decide the ranking as the sweep measured it; a later round's, the ranking the
    /// rounds before moved).
    pub designs: Vec<u64>,
    pub rounds: usize,
    pub peaks: Vec<CasePeak>,
    pub ranks_before: Vec<(u64, u64)>,
}

impl Verification {
    /// The rank a design had before the verification.
    pub fn rank_before(&self, design: u64) -> Option<u64> {
        self.ranks_before
            .iter()
            .find(|r| r.0 == design)
            .map(|r| r.1)
    }

    /// The direct measurements of a design's case, in the order they ran.
    pub fn of(&self, design: u64, case: u32) -> Option<&CasePeak> {
        self.peaks
            .iter()
            .find(|p| p.design == design && p.case == case)
    }
}

/// The scene's life question: design life `design_life` (s) at quantile `quantile`, measured
/// directly over `periods` forcing periods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LifeQuestion {
    pub design_life: f64,
    pub quantile: f64,
    pub periods: u64,
}

/// A motion's identity across processes: its design, case, and the bits of its frequency ratio
/// and estimate (m). What a shard's stored direct measurement is found by ([`Measured`]).
pub type MotionKey = (u64, u32, u64, u64);

impl Contender {
    /// The motion's [`MotionKey`].
    pub fn key(&self) -> MotionKey {
        (
            self.design,
            self.case,
            self.r.to_bits(),
            self.amplitude.to_bits(),
        )
    }
}

/// Direct measurements an analysis shard made (`reduce --shard`), by motion: the final
/// reduction takes them instead of running them again (`None`: the measurement failed).
pub type Measured = std::collections::HashMap<MotionKey, Option<LifeSummary>>;

/// Verifies one case (module doc, step 2): `sys` is the case's system, `settings` the study's
/// solver, `before` the case's peak as the sweep measured it; a motion `measured` already holds
/// (an analysis shard's) is taken from it, the others are measured here.
pub fn verify_case(
    (design, case): (u64, u32),
    top: &CaseTop,
    sys: &System,
    settings: &SolverSettings,
    life: LifeQuestion,
    before: f64,
    measured: &Measured,
) -> CasePeak {
    let mut best = top.periodic;
    let mut verified = Vec::new();
    // The motions of `top` not taken: their estimates stay in the case's peak.
    let mut unmeasured = top.rest;
    for c in &top.top {
        // Its interval's upper end, not its estimate: a short measurement of a slow tail runs
        // low, and on the bundled study such estimates sat below an impact-free orbit while
        // their motions, measured directly, carried the peak 3 % above it.
        if c.hi <= best {
            unmeasured = unmeasured.max(c.amplitude);
            continue;
        }
        if c.measured >= life.periods {
            best = best.max(c.amplitude);
            verified.push(Verified {
                motion: c.clone(),
                direct: None,
                as_raced: true,
            });
            continue;
        }
        let direct = match measured.get(&c.key()) {
            Some(d) => *d,
            None => measure(c, sys, settings, life, best),
        };
        let v = Verified {
            motion: c.clone(),
            direct,
            as_raced: false,
        };
        best = best.max(v.value());
        verified.push(v);
    }
    let failed = verified.iter().any(|v| !v.as_raced && v.direct.is_none());
    CasePeak {
        design,
        case,
        before,
        after: if verified.is_empty() {
            before
        } else {
            best.max(unmeasured)
        },
        supported: !failed && unmeasured <= best,
        verified,
        round: 1,
    }
}

/// Motion `c` of a case with system `sys` measured directly over `life.periods` periods, or
/// fewer once its interval lies below `bar`, the case's peak so far
/// ([`measure_directly_above`]); a motion of several units by their map ([`UnitsMap`]) from its
/// whole state.
fn measure(
    c: &Contender,
    sys: &System,
    settings: &SolverSettings,
    life: LifeQuestion,
    bar: f64,
) -> Option<LifeSummary> {
    let f = Forcing {
        sys: *sys,
        F0: c.f0,
        omega: c.omega,
        settings: *settings,
    };
    let s = LifeSettings {
        n_life: life.design_life / f.period(),
        quantile: life.quantile,
        tol: 0.0,
        first: FIRST,
        cap: life.periods,
    };
    if c.units.is_empty() {
        measure_directly_above(&f, &c.section, c.lambda, &s, life.periods, bar)
    } else {
        measure_directly_above(&UnitsMap(f), &c.units, c.lambda, &s, life.periods, bar)
    }
}

/// The designs that decide the ranking (module doc, step 1): the best-ranked design of `ranks`
/// (best first) and every design whose peak interval overlaps its own; `interval(d)` is design
/// `d`'s ideal-case peak interval (m), `None` when unknown. None when fewer than two designs
/// rank: one design has no order to decide, and its peak keeps the race's estimate (a
/// one-frequency study of a chaotic point runs in about a second where a verification would
/// add 10^6 periods, some 3 s of one core).
pub fn deciding(ranks: &[(u64, u64)], interval: impl Fn(u64) -> Option<(f64, f64)>) -> Vec<u64> {
    let [(best, _), _, ..] = *ranks else {
        return Vec::new();
    };
    let Some((lo, hi)) = interval(best) else {
        return vec![best];
    };
    let mut out: Vec<u64> = ranks
        .iter()
        .map(|&(d, _)| d)
        .filter(|&d| d == best || interval(d).is_some_and(|(l, h)| l <= hi && lo <= h))
        .collect();
    out.sort_unstable();
    out
}

/// A case to verify: its design and case, what it kept, its system and its peak before (m).
pub type CaseToVerify<'a> = ((u64, u32), &'a CaseTop, System, f64);

/// Verifies every case of the deciding designs in parallel; the results in the input's order.
/// `measured`: what analysis shards measured already.
pub fn verify_all(
    cases: &[CaseToVerify],
    settings: &SolverSettings,
    life: LifeQuestion,
    measured: &Measured,
) -> Vec<CasePeak> {
    cases
        .par_iter()
        .map(|(at, top, sys, before)| verify_case(*at, top, sys, settings, life, *before, measured))
        .collect()
}

/// The cases of `cases` an analysis shard verifies: the `k`-th (in the deterministic order the
/// reduction lists them) falls to shard `k % count`.
pub fn share<T>(cases: &[T], index: u64, count: u64) -> impl Iterator<Item = &T> {
    cases
        .iter()
        .enumerate()
        .filter(move |(k, _)| *k as u64 % count.max(1) == index)
        .map(|(_, c)| c)
}

/// The `verification` table (docs/schema.md): one row per motion measured directly, its
/// estimate beside its direct value with the periods each rests on, and its case's peak and
/// its design's rank before and after; `rank_after(d)` is design `d`'s rank after.
pub fn table(v: &Verification, rank_after: impl Fn(u64) -> Option<u64>) -> Table {
    let rows: Vec<(&CasePeak, &Verified)> = v
        .peaks
        .iter()
        .flat_map(|p| p.verified.iter().map(move |m| (p, m)))
        .collect();
    let direct = |m: &Verified, f: fn(&LifeSummary) -> f64| m.direct.map_or(f64::NAN, |d| f(&d));
    let estimate = |m: &Verified, f: fn(&LifeEstimate) -> f64, raced: fn(&Contender) -> f64| {
        if m.as_raced {
            return raced(&m.motion);
        }
        m.direct
            .and_then(|d| d.estimate)
            .map_or(f64::NAN, |e| f(&e))
    };
    type Row<'a> = (&'a CasePeak, &'a Verified);
    let mut t = Table::default();
    let f64s = |t: &mut Table, name: &str, f: &dyn Fn(&Row) -> f64| {
        t.push(name, Column::F64(rows.iter().map(f).collect()));
    };
    let u64s = |t: &mut Table, name: &str, f: &dyn Fn(&Row) -> Option<u64>| {
        t.push(name, Column::U64(rows.iter().map(f).collect()));
    };
    let bools = |t: &mut Table, name: &str, f: &dyn Fn(&Row) -> bool| {
        t.push(name, Column::Bool(rows.iter().map(f).collect()));
    };
    u64s(&mut t, "point", &|r| Some(r.0.design));
    u64s(&mut t, "case", &|r| Some(u64::from(r.0.case)));
    f64s(&mut t, "r", &|r| r.1.motion.r);
    f64s(&mut t, "estimate", &|r| r.1.motion.amplitude);
    f64s(&mut t, "estimate_lo", &|r| r.1.motion.lo);
    f64s(&mut t, "estimate_hi", &|r| r.1.motion.hi);
    u64s(&mut t, "estimate_periods", &|r| Some(r.1.motion.measured));
    f64s(&mut t, "direct", &|r| {
        estimate(r.1, |e| e.amplitude, |c| c.amplitude)
    });
    f64s(&mut t, "direct_lo", &|r| estimate(r.1, |e| e.lo, |c| c.lo));
    f64s(&mut t, "direct_hi", &|r| estimate(r.1, |e| e.hi, |c| c.hi));
    u64s(&mut t, "direct_periods", &|r| {
        if r.1.as_raced {
            Some(r.1.motion.measured)
        } else {
            r.1.direct.map(|d| d.measured)
        }
    });
    bools(&mut t, "measured_again", &|r| !r.1.as_raced);
    f64s(&mut t, "largest_seen", &|r| direct(r.1, |d| d.window_max));
    f64s(&mut t, "peak_before", &|r| r.0.before);
    f64s(&mut t, "peak_after", &|r| r.0.after);
    bools(&mut t, "supported", &|r| r.0.supported);
    u64s(&mut t, "round", &|r| Some(r.0.round as u64));
    u64s(&mut t, "rank_before", &|r| v.rank_before(r.0.design));
    u64s(&mut t, "rank_after", &|r| rank_after(r.0.design));
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_deciding_designs_overlap_the_best_ones_interval() {
        let iv = |d: u64| match d {
            0 => Some((1.0, 1.2)),
            1 => Some((1.1, 1.3)),
            2 => Some((1.25, 1.25)),
            _ => None,
        };
        // Design 0 ranks first; 1 overlaps it, 2 (periodic, 1.25) does not, 3 is unknown.
        assert_eq!(deciding(&[(0, 1), (2, 2), (1, 3), (3, 4)], iv), vec![0, 1]);
        assert_eq!(deciding(&[], iv), Vec::<u64>::new());
        // One design has no order to decide.
        assert_eq!(deciding(&[(0, 1)], iv), Vec::<u64>::new());
    }

    fn contender(a: f64) -> Contender {
        Contender {
            design: 0,
            case: 0,
            r: a,
            omega: 1.0,
            f0: 0.1,
            section: [0.0; 4],
            units: Vec::new(),
            lambda: 1.0,
            amplitude: a,
            lo: a,
            hi: a,
            measured: 2000,
        }
    }

    #[test]
    fn the_shards_share_the_cases_each_once() {
        let cases: Vec<u32> = (0..11).collect();
        let mut all: Vec<u32> = (0..3)
            .flat_map(|i| share(&cases, i, 3).copied().collect::<Vec<_>>())
            .collect();
        all.sort_unstable();
        assert_eq!(all, cases);
        assert_eq!(share(&cases, 1, 3).count(), 4);
    }

    #[test]
    fn a_case_keeps_its_highest_motions_and_the_largest_of_the_rest() {
        let mut t = CaseTop::default();
        for a in [1.0, 5.0, 3.0, 4.0, 2.0] {
            t.push(contender(a));
        }
        let kept: Vec<f64> = t.top.iter().map(|c| c.amplitude).collect();
        assert_eq!(kept, vec![5.0, 4.0, 3.0]);
        assert_eq!(t.rest, 2.0);
    }
}
