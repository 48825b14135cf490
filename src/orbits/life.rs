//! The largest amplitude of a motion that is not periodic over a design life (docs/model.md,
//! "The amplitude over a design life"): the motion is run period by period from states on it
//! (its chains), its per-period maxima `z_k = max |x|` over period `k` are collected, and the
//! peaks-over-threshold estimate of [`crate::stats::extremes`] gives the quantile of the
//! largest of `N` periods with its 90 % interval. The window grows (doubling) until the
//! interval's half-width is within the tolerance of the estimate at three successive windows
//! ([`SETTLE_WINDOWS`]), or a cap is reached ([`LifeRun::settled`]). The
//! chains run in parallel (each is a pure function of its start, so the result does not depend
//! on the threads).
//!
//! The tail's shape is kept in `[-1/2, 0]` ([`crate::stats::extremes::Life::bounded`]): the
//! largest excursion of the main mass is bounded (the force's work over a period is bounded and
//! the damper and the impacts only dissipate), and below -1/2 the likelihood is not regular.
//!
//! Clusters of exceedances are separated by `run` periods below the threshold: three times the
//! motion's Lyapunov time `1 / lambda_1` (the time over which it forgets where it was; about 3
//! periods on the showcase's chaotic motions, `lambda_1` near 1 per forcing period), clamped to
//! `[2, 50]` (50 when the exponent is not positive: a slowly mixing motion).
//!
//! Only the per-period maxima above the estimate's thresholds enter it (the periods below only
//! count), and its thresholds rise as the sample grows (a fixed number of the highest cluster
//! maxima). So after the first window, which locates every extremum, the motion runs with a
//! floor under the next estimate's thresholds ([`floor_for`]: the threshold of the largest count
//! of cluster maxima the next window's fits take, read from the periods so far, and never above
//! the last estimate's lowest threshold): extrema of `x` below it are not located
//! ([`eval_above`]; watching `x'` for its zeros is about half of a chaotic motion's steps). A
//! period whose maximum is below the floor keeps a value below it. After each estimate the run
//! checks that its thresholds are all at or above the floor (so every value a fit used is exact;
//! which cluster maximum is a threshold is chosen above a lower base quantile, where values kept
//! below the floor can join or part clusters: docs/scenes.md);
//! when one is not, the whole measurement is run again without a floor, from the same states.

use super::map::{Forcing, Section, eval, eval_above, periods_above};
use crate::sim::Outcome;
use crate::stats::extremes::{Life, LifeEstimate, floor_for, life_pot};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the life estimate of one motion asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LifeSettings {
    /// The design life in forcing periods, `N`.
    pub n_life: f64,
    /// The quantile of the largest amplitude over the life (0.5: its median).
    pub quantile: f64,
    /// The interval's half-width, relative to the estimate, at which the window stops growing.
    pub tol: f64,
    /// The first window (periods), and the cap on the window.
    pub first: u64,
    pub cap: u64,
}

/// One forcing period of a motion at a time: what a [`LifeRun`] measures. One unit's
/// stroboscopic map ([`Forcing`], whose extrema below a floor need not be located) and that of
/// several units ([`super::units::map::UnitsMap`], every extremum located) implement it.
pub trait PeriodMap: Send + Sync {
    /// A section state, the main mass's displacement `x` (m) first.
    type State: Clone + Send + Sync + AsMut<[f64]>;
    /// Whether [`PeriodMap::period`] may leave the extrema below its floor unlocated; a map
    /// that does not is measured without a floor (module doc).
    const FLOORS: bool;
    /// One period from `s`: `max |x|` over it (m; exact when at least `floor`, some value
    /// below `floor` otherwise) and the section it ends on; `None` when the simulator stopped
    /// (an outcome other than `ok`).
    fn period(&self, s: &Self::State, floor: f64) -> Option<(f64, Self::State)>;
    /// `n` periods of [`PeriodMap::period`] one after another from `s`: each one's `max |x|`
    /// pushed to `z`, `s` moved to the last one's end; `false` when the simulator stopped (the
    /// periods before kept, `s` where the failing one started). The bits of `n` calls; a map may
    /// run them at less cost.
    fn periods(&self, s: &mut Self::State, floor: f64, n: u64, z: &mut Vec<f64>) -> bool {
        for _ in 0..n {
            let Some((amplitude, end)) = self.period(s, floor) else {
                return false;
            };
            z.push(amplitude);
            *s = end;
        }
        true
    }
    /// `p` periods from `s`: the section they end on; `None` when the simulator stopped.
    fn run(&self, s: &Self::State, p: u64) -> Option<Self::State>;
}

impl PeriodMap for Forcing {
    type State = Section;
    const FLOORS: bool = true;

    fn period(&self, s: &Section, floor: f64) -> Option<(f64, Section)> {
        let e = eval_above(self, s, 1, floor);
        (e.outcome == Outcome::Ok).then_some((e.amplitude, e.end))
    }

    fn periods(&self, s: &mut Section, floor: f64, n: u64, z: &mut Vec<f64>) -> bool {
        periods_above(self, s, n, floor, |amplitude| z.push(amplitude))
    }

    fn run(&self, s: &Section, p: u64) -> Option<Section> {
        let e = eval(self, s, p, false);
        (e.outcome == Outcome::Ok).then_some(e.end)
    }
}

/// One motion's measurement so far, over one or more chains (runs from different states on
/// the same attractor: a chaotic motion that lingers in one part of its attractor for a while
/// is sampled more evenly by several runs than by one of the same total length). Resumable:
/// more periods give the bits of longer runs.
#[derive(Clone, Debug, PartialEq)]
pub struct LifeRun<S = Section> {
    /// Each chain's per-period maxima and where it is now.
    pub chains: Vec<(Vec<f64>, S)>,
    /// The simulator stopped a chain (its outcome was not `ok`).
    pub failed: bool,
    /// The estimate from the periods measured (when one could be made).
    pub estimate: Option<LifeEstimate>,
    /// The window reached [`LifeSettings::cap`] before the interval met the tolerance.
    pub capped: bool,
    /// Extrema below this `|x|` are not located in the periods run next (m; 0: all are).
    pub floor: f64,
    /// The chains' first states (a measurement whose floor did not hold runs again from them).
    pub starts: Vec<S>,
    /// Every window locates every extremum ([`LifeRun::without_floor`]).
    pub exact: bool,
    /// How many windows in a row before the last met the tolerance ([`LifeRun::settled`]).
    pub met_before: u32,
    /// The per-period maxima [`LifeRun::retire`] let go: how many, and the largest (NaN: none).
    pub retired: (u64, f64),
}

impl<S: Clone + Send + Sync> LifeRun<S> {
    /// A measurement of one chain starting at `state`.
    pub fn new(state: S) -> LifeRun<S> {
        LifeRun::chains(vec![state])
    }

    /// A measurement of one chain per state (at least one).
    pub fn chains(states: Vec<S>) -> LifeRun<S> {
        LifeRun {
            chains: states.iter().map(|s| (Vec::new(), s.clone())).collect(),
            failed: false,
            estimate: None,
            capped: false,
            floor: 0.0,
            starts: states,
            exact: false,
            met_before: 0,
            retired: (0, f64::NAN),
        }
    }

    /// The same measurement locating every extremum in every window (no floor, module doc): the
    /// per-period maxima are all exact, at the cost of the steps the floor saves.
    pub fn without_floor(mut self) -> LifeRun<S> {
        self.exact = true;
        self
    }

    /// Periods measured over all chains.
    pub fn periods(&self) -> u64 {
        self.retired.0 + self.chains.iter().map(|c| c.0.len() as u64).sum::<u64>()
    }

    /// Lets go of the per-period maxima of a measurement that will not grow again, but for each
    /// chain's last [`REPEAT_WINDOW`] ([`LifeRun::repeats`], [`LifeRun::last_max`]): its
    /// estimate, periods and largest value stay ([`LifeRun::summary`]). A race holds many
    /// measurements at once (a curve's every motion with `life_curve = "whole"`, each up to
    /// `life_max_periods` values): those that are over take no more memory than a few kB each.
    pub fn retire(&mut self) {
        for (z, _) in &mut self.chains {
            let keep = z.len().saturating_sub(REPEAT_WINDOW);
            let top = z[..keep].iter().copied().fold(self.retired.1, f64::max);
            self.retired = (self.retired.0 + keep as u64, top);
            z.drain(..keep);
            z.shrink_to_fit();
        }
    }

    /// Runs `n` more periods in all, shared out evenly over the chains (the first chains take
    /// the remainder), locating the extrema from [`LifeRun::floor`] up. A chain whose simulator
    /// stops (an outcome other than `ok`) fails the run.
    ///
    /// The chains run in parallel, [`SEGMENT`] periods at a time in turn (a FIFO of segments,
    /// each chain's next queued behind the others'), so they advance together and the threads
    /// finish a window within one segment of each other: run each to its end, the chains' costs
    /// differ (their impacts do) and one core waited up to a chain's time at every window. Each
    /// chain is still one sequence of periods, so the values do not depend on the threads.
    pub fn extend<M: PeriodMap<State = S>>(&mut self, f: &M, n: u64) {
        if self.failed {
            return;
        }
        let floor = self.floor;
        let k = self.chains.len().max(1) as u64;
        let failed = AtomicBool::new(false);
        rayon::scope_fifo(|scope| {
            for (i, chain) in self.chains.iter_mut().enumerate() {
                let m = n / k + u64::from((i as u64) < n % k);
                chain.0.reserve(m as usize);
                let failed = &failed;
                scope.spawn_fifo(move |scope| segment(scope, f, floor, chain, m, failed));
            }
        });
        self.failed = failed.into_inner();
    }

    /// Whether the per-period maxima the estimate uses are exact: its lowest threshold is at or
    /// above the floor (a period below the floor keeps a value below it).
    pub fn floor_holds(&self) -> bool {
        self.floor <= 0.0
            || self
                .estimate
                .is_none_or(|e| e.lowest_threshold >= self.floor)
    }

    /// Whether the maxima repeat: every chain's last [`REPEAT_WINDOW`] per-period maxima take at
    /// most [`REPEAT_VALUES`] distinct values (relative `1e-9`): a periodic orbit reached, or a
    /// motion that repeats itself. An irregular motion (a chaotic transient still approaching its
    /// attractor, whose largest values come in a few long build-ups) does not.
    pub fn repeats(&self) -> bool {
        self.chains.iter().all(|(z, _)| {
            let mut last = z[z.len().saturating_sub(REPEAT_WINDOW)..].to_vec();
            last.sort_by(f64::total_cmp);
            last.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
            last.len() <= REPEAT_VALUES
        })
    }

    /// The largest of every chain's last [`REPEAT_WINDOW`] per-period maxima.
    pub fn last_max(&self) -> f64 {
        self.chains
            .iter()
            .flat_map(|(z, _)| z[z.len().saturating_sub(REPEAT_WINDOW)..].iter().copied())
            .fold(f64::NAN, f64::max)
    }

    /// The largest amplitude over the periods measured.
    pub fn window_max(&self) -> f64 {
        self.chains
            .iter()
            .flat_map(|c| c.0.iter().copied())
            .fold(self.retired.1, f64::max)
    }

    /// Every chain's per-period maxima so far.
    fn maxima(&self) -> Vec<&[f64]> {
        self.chains.iter().map(|c| c.0.as_slice()).collect()
    }

    /// Estimates from the periods measured so far ([`life_pot`]), clusters separated by
    /// [`cluster_run`] of the motion's exponent `lambda` (per forcing period).
    pub fn estimate(&mut self, s: &LifeSettings, lambda: f64) -> Option<LifeEstimate> {
        self.estimate = life_pot(
            &self.maxima(),
            cluster_run(lambda),
            // The main mass's excursion is bounded (module doc).
            Life::bounded(s.n_life, s.quantile),
        );
        self.estimate
    }

    /// Whether the last window's estimate meets the tolerance (its interval's half-width within
    /// `tol` of the estimate).
    pub fn meets(&self, s: &LifeSettings) -> bool {
        self.estimate.is_some_and(|e| e.rel_halfwidth() <= s.tol)
    }

    /// Whether the measurement may stop: the last [`SETTLE_WINDOWS`] windows' estimates all meet
    /// the tolerance.
    pub fn settled(&self, s: &LifeSettings) -> bool {
        self.met_before + 1 >= SETTLE_WINDOWS && self.meets(s)
    }

    /// One step of refinement: the window grows (to `first`, then doubling, at most to `cap`)
    /// and the estimate is made again. Returns whether another step could follow (not failed,
    /// not within the tolerance, not at the cap); at the cap without meeting the tolerance the
    /// run is `capped`.
    pub fn grow<M: PeriodMap<State = S>>(&mut self, f: &M, s: &LifeSettings, lambda: f64) -> bool {
        let have = self.periods();
        let want = window_after(have, s);
        self.met_before = if self.meets(s) {
            self.met_before + 1
        } else {
            0
        };
        if want > have {
            self.extend(f, want - have);
        }
        if self.failed {
            return false;
        }
        self.estimate(s, lambda);
        if !self.floor_holds() {
            // Run again without a floor (module doc).
            self.chains = self
                .starts
                .iter()
                .map(|s| (Vec::new(), s.clone()))
                .collect();
            self.floor = 0.0;
            self.extend(f, want);
            if self.failed {
                return false;
            }
            self.estimate(s, lambda);
        }
        if !self.exact
            && M::FLOORS
            && let Some(e) = self.estimate
        {
            // The floor for the next window (`floor_for`), never above this estimate's thresholds.
            let next = window_after(self.periods(), s) as usize;
            let below =
                floor_for(&self.maxima(), cluster_run(lambda), next).unwrap_or(f64::NEG_INFINITY);
            self.floor = self.floor.max(below.min(e.lowest_threshold));
        }
        self.capped = !self.settled(s) && self.periods() >= s.cap;
        !self.settled(s) && !self.capped
    }

    /// Grows until the measurement is [`settled`](LifeRun::settled) or the cap is reached.
    pub fn refine<M: PeriodMap<State = S>>(&mut self, f: &M, s: &LifeSettings, lambda: f64) {
        while self.grow(f, s, lambda) {}
    }

    /// What the census keeps of the measurement.
    pub fn summary(&self) -> LifeSummary {
        LifeSummary {
            estimate: self.estimate,
            measured: self.periods(),
            capped: self.capped,
            window_max: self.window_max(),
        }
    }
}

/// The window after `have` periods: `first`, then doubling, at most `cap`.
fn window_after(have: u64, s: &LifeSettings) -> u64 {
    if have < s.first {
        s.first
    } else {
        (2 * have).min(s.cap)
    }
}

/// Periods a chain of [`LifeRun::extend`] runs before the next chain's turn: about 10 ms of a
/// chaotic motion, a small fraction of a window's time per thread.
pub const SEGMENT: u64 = 2000;

/// How many successive windows must meet the tolerance before a measurement stops
/// ([`LifeRun::settled`]). One window's interval can meet it while the fit still sees only the
/// lower part of a slowly approached bound or of a rarely visited part of the attractor (a short
/// measurement of such a tail runs low, and its interval is then too narrow). Emulating the race
/// on the same samples of the validation's ten points, seeds 1-40, three horizons (1,200
/// estimates; `examples/life_lab.rs`, `results/life_stops_least.md`): stopping at the first
/// window within 5 % left 35 estimates that stopped early more than 5 % off (down to -10.7 %);
/// at the second, 8 (down to -9.5 %, m = 15 g, d = 15 mm, e = 0.75, r = 1); at the third, none
/// (three more are off at the cap whatever the rule), for twice the periods of the motions that
/// stop early (the tightest tail 4,000 -> 8,000) and none more where the cap is reached.
pub const SETTLE_WINDOWS: u32 = 3;

/// Up to [`SEGMENT`] of the `left` periods still due on `chain`, then its next segment queued
/// behind the other chains' ([`LifeRun::extend`]); a stop of the simulator sets `failed` and ends
/// the chain.
fn segment<'s, M: PeriodMap>(
    scope: &rayon::ScopeFifo<'s>,
    f: &'s M,
    floor: f64,
    chain: &'s mut (Vec<f64>, M::State),
    left: u64,
    failed: &'s AtomicBool,
) {
    let now = left.min(SEGMENT);
    let (z, state) = chain;
    if !f.periods(state, floor, now, z) {
        failed.store(true, Ordering::Relaxed);
        return;
    }
    if left > now {
        scope.spawn_fifo(move |scope| segment(scope, f, floor, chain, left - now, failed));
    }
}

/// What the census keeps of a life measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LifeSummary {
    pub estimate: Option<LifeEstimate>,
    /// Periods measured.
    pub measured: u64,
    pub capped: bool,
    /// The largest per-period maximum over the periods measured.
    pub window_max: f64,
}

/// The last per-period maxima of a chain [`LifeRun::repeats`] looks at.
pub const REPEAT_WINDOW: usize = 256;

/// The most distinct values among them of a chain that repeats ([`LifeRun::repeats`]).
pub const REPEAT_VALUES: usize = 32;

/// Periods below the threshold that separate clusters of exceedances (module doc).
pub fn cluster_run(lambda: f64) -> usize {
    let n = 3.0 / lambda;
    if n.is_finite() && n > 0.0 {
        n.round().clamp(2.0, 50.0) as usize
    } else {
        50
    }
}

/// The per-period maxima of `|x|` of the motion from section `s` under `f`: `burn` periods
/// dropped (its transient), then `n` recorded; `None` when the simulator stopped (its outcome
/// was not `ok`). What [`LifeRun`] measures, for a caller with its own statistics.
pub fn period_maxima<M: PeriodMap>(f: &M, s: &M::State, burn: u64, n: u64) -> Option<Vec<f64>> {
    let mut state = s.clone();
    if burn > 0 {
        state = f.run(&state, burn)?;
    }
    let mut run = LifeRun::new(state);
    run.extend(f, n);
    (!run.failed).then(|| run.chains.swap_remove(0).0)
}

/// Chains of a direct measurement ([`measure_directly`]).
pub const DIRECT_CHAINS: usize = 16;

/// Periods each chain of a direct measurement runs before it is measured: the nudge of its
/// start grows by `e^(lambda_1 n)`, past the attractor's size within some 30 periods on the
/// motions measured (`lambda_1` about 1 per period), so the chains are independent.
pub const DIRECT_BURN: u64 = 200;

/// A state on the motion through `section` for chain `i` of a measurement: the main mass moved
/// by `i` nm, then [`DIRECT_BURN`] periods run (chain 0 is the section itself run on); `None`
/// when the simulator stopped.
fn nudged<M: PeriodMap>(f: &M, section: &M::State, i: usize) -> Option<M::State> {
    let mut start = section.clone();
    start.as_mut()[0] += i as f64 * 1e-9;
    f.run(&start, DIRECT_BURN)
}

/// The fewest chains a race's motion is measured on ([`topped_up`]).
pub const MIN_CHAINS: usize = 4;

/// The states of a motion's measurement, `states` (its own section first, then the census
/// starts that joined it) topped up to [`MIN_CHAINS`] with nudged copies of the first (chains
/// `1, 2, ...` of [`nudged`]; one whose simulator stopped is left out). A motion that only one
/// or two of a census's starts reached would otherwise run its measurement on one or two
/// threads: at the bundled study's m = 10 g, d = 20 mm, r = 0.935 (a one-frequency study of
/// 16 starts) the motion that led its race was one start's, measured 256,000 to 512,000
/// periods on one core. The copies' burn is not measured; the count does not depend on the
/// threads, so neither do the values.
pub fn topped_up<M: PeriodMap>(f: &M, states: Vec<M::State>) -> Vec<M::State> {
    let Some(first) = states.first().cloned() else {
        return states;
    };
    let missing = MIN_CHAINS.saturating_sub(states.len());
    let copies: Vec<Option<M::State>> = (1..=missing)
        .into_par_iter()
        .map(|i| nudged(f, &first, i))
        .collect();
    states
        .into_iter()
        .chain(copies.into_iter().flatten())
        .collect()
}

/// A motion measured directly from a state on it (`section`): [`DIRECT_CHAINS`] chains, chain
/// `i` from the state with its main mass moved by `i` nm and run [`DIRECT_BURN`] periods, then
/// `periods` periods in all (the window doubling from `periods / 64` as in [`LifeRun::grow`], so
/// its floor applies), and the design-life estimate of `s` from all of them. What the
/// harmonic reduction's verification runs on the motions that decide a ranking
/// (`crate::reduce::harmonic::verify`); `None` when a chain's simulator stopped.
pub fn measure_directly<M: PeriodMap>(
    f: &M,
    section: &M::State,
    lambda: f64,
    s: &LifeSettings,
    periods: u64,
) -> Option<LifeSummary> {
    measure_directly_above(f, section, lambda, s, periods, f64::NEG_INFINITY)
}

/// [`measure_directly`], stopped early once the estimate's interval lies wholly below `bar`
/// (m): a motion that can no longer reach a case's peak need not be measured to the end (its
/// summary says how many periods it rests on). One whose interval still reaches `bar` runs
/// all `periods`. Deterministic: the windows and the test are those of `periods` and `bar`.
pub fn measure_directly_above<M: PeriodMap>(
    f: &M,
    section: &M::State,
    lambda: f64,
    s: &LifeSettings,
    periods: u64,
    bar: f64,
) -> Option<LifeSummary> {
    let starts: Vec<Option<M::State>> = (0..DIRECT_CHAINS)
        .into_par_iter()
        .map(|i| nudged(f, section, i))
        .collect();
    let starts: Option<Vec<M::State>> = starts.into_iter().collect();
    let settings = LifeSettings {
        tol: 0.0,
        first: (periods / 64).max(1),
        cap: periods,
        ..*s
    };
    let mut run = LifeRun::chains(starts?);
    while run.grow(f, &settings, lambda) {
        if run.estimate.is_some_and(|e| e.hi < bar) {
            break;
        }
    }
    (!run.failed).then(|| run.summary())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run_of(chains: Vec<Vec<f64>>) -> LifeRun {
        let mut run = LifeRun::chains(vec![[0.0; 4]; chains.len()]);
        for (c, z) in run.chains.iter_mut().zip(chains) {
            c.0 = z;
        }
        run
    }

    /// A retired measurement says what it said before: its periods, largest value, summary, and
    /// its last maxima (whether they repeat, and their largest), from a few kB.
    #[test]
    fn a_retired_measurement_keeps_its_summary() {
        let long: Vec<f64> = (0..5000).map(|i| ((i * 7919) % 1013) as f64).collect();
        let short: Vec<f64> = (0..100).map(|i| (i % 3) as f64).collect();
        let mut run = run_of(vec![long, short]);
        let before = (run.summary(), run.repeats(), run.last_max());
        run.retire();
        assert_eq!((run.summary(), run.repeats(), run.last_max()), before);
        assert_eq!(run.periods(), 5100);
        assert_eq!(run.chains[0].0.len(), REPEAT_WINDOW);
        assert_eq!(run.chains[1].0.len(), 100);
        // Retired twice: nothing more goes.
        run.retire();
        assert_eq!(run.summary(), before.0);
    }

    /// A motion of one state gets [`MIN_CHAINS`] chains: its own state first, then nudged copies
    /// run on to other states of the same motion, the same bits on every call; a motion of
    /// enough states keeps them as they are.
    #[test]
    fn a_motion_of_one_state_is_topped_up_to_the_fewest_chains() {
        // The reference point m = 20 g, d = 20 mm, r = 1.01: chaotic.
        let f = crate::orbits::map::tests::table_i(0.02, 0.02, 0.9, 0.1, 0.1, 1.01);
        let on = eval(&f, &[0.003, 0.05, 0.0, 0.0], 500, false).end;
        let states = topped_up(&f, vec![on]);
        assert_eq!(states.len(), MIN_CHAINS);
        assert_eq!(states[0], on);
        for (i, a) in states.iter().enumerate() {
            for b in &states[i + 1..] {
                // Apart by more than the nudge's growth would leave without chaos.
                assert!((a[0] - b[0]).abs() > 1e-6, "{a:?} {b:?}");
            }
        }
        assert_eq!(topped_up(&f, vec![on]), states);
        let four = vec![on; MIN_CHAINS];
        assert_eq!(topped_up(&f, four.clone()), four);
    }

    /// The map of several units with one unit is one unit's map (model.md §14): the per-period
    /// maxima a measurement takes through it equal, bit for bit, those of one unit's map
    /// without a floor, on a chaotic motion, where any difference grows.
    #[test]
    fn one_unit_measured_through_the_map_of_several_units_gives_the_same_maxima() {
        let f = crate::orbits::map::tests::table_i(0.02, 0.02, 0.9, 0.1, 0.1, 1.01);
        let on = eval(&f, &[0.003, 0.05, 0.0, 0.0], 500, false).end;
        let one = period_maxima(&f, &on, 0, 400).unwrap();
        let units = crate::orbits::units::map::UnitsMap(f.clone());
        let several = period_maxima(&units, &on.to_vec(), 0, 400).unwrap();
        assert_eq!(one.len(), 400);
        assert_eq!(one, several);
    }

    /// Independent per-period maxima of a bounded law, `z = 1e-2 (1 - sqrt(u) / 2)` with `u`
    /// uniform (the tail's shape -1/2, at the bound the estimate allows), drawn from a counter in
    /// the state: a motion whose every window is well measured.
    struct Bounded;

    impl PeriodMap for Bounded {
        type State = Section;
        const FLOORS: bool = false;

        fn period(&self, s: &Section, _floor: f64) -> Option<(f64, Section)> {
            let mut h = (s[1] as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
            h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            let u = ((h ^ (h >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
            Some((1e-2 * (1.0 - 0.5 * u.sqrt()), [0.0, s[1] + 1.0, 0.0, 0.0]))
        }

        fn run(&self, s: &Section, p: u64) -> Option<Section> {
            Some([0.0, s[1] + p as f64, 0.0, 0.0])
        }
    }

    /// The measurement stops at the first window that is the [`SETTLE_WINDOWS`]-th in a row whose
    /// interval meets the tolerance, not at the first or second (issue 69: a short sample of a
    /// rarely visited tail can meet it twice and still run low).
    #[test]
    fn a_measurement_stops_at_the_third_window_in_a_row_within_the_tolerance() {
        let s = LifeSettings {
            n_life: 1e6,
            quantile: 0.5,
            tol: 0.05,
            first: 2000,
            cap: 1 << 20,
        };
        let mut run = LifeRun::chains((0..4).map(|i| [0.0, 1e12 * i as f64, 0.0, 0.0]).collect());
        let mut met = Vec::new();
        while run.grow(&Bounded, &s, 1.0) {
            met.push(run.meets(&s));
            assert!(!run.settled(&s), "{met:?}");
        }
        met.push(run.meets(&s));
        assert_eq!(SETTLE_WINDOWS, 3);
        // Every window meets the tolerance: the rule before would have stopped at 4,000 periods.
        assert_eq!(met, [true; 3], "{:?}", run.estimate);
        assert!(run.settled(&s) && !run.capped);
        assert_eq!(run.periods(), 8000);
    }

    /// A periodic orbit reached (a cycle of 3 values, rounding noise at 1e-12 relative) repeats;
    /// an irregular motion, or one chain of it among repeating ones, does not.
    #[test]
    fn maxima_repeat_on_a_periodic_orbit_and_not_on_an_irregular_motion() {
        let cycle: Vec<f64> = (0..4000)
            .map(|i| [1e-2, 1.1e-2, 0.9e-2][i % 3] * (1.0 + 1e-12 * (i % 7) as f64))
            .collect();
        let irregular: Vec<f64> = (0..4000)
            .map(|i| 1e-2 * (1.0 + 0.1 * ((i as f64) * 0.618_033_988_7).fract()))
            .collect();
        assert!(run_of(vec![cycle.clone(), cycle.clone()]).repeats());
        assert!(!run_of(vec![irregular.clone()]).repeats());
        assert!(!run_of(vec![cycle, irregular]).repeats());
    }
}
