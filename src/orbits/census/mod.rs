//! The attractor census of one frequency point: seeded starts, each run to its attractor, a
//! periodic one handed over to Newton as soon as the motion approaches it, distinct attractors
//! merged, each with its basin share.
//!
//! # Starts
//! Start 0 is the study's initial state. Start `k >= 1` is drawn from the study seed, the
//! design point and `k` (SplitMix64, so the same study gives the same starts on any thread
//! count) over a box scaled by `X = max(A_0, d/2)`, `A_0` the amplitude reached from start 0:
//!
//! * main mass: `x = a cos(theta)`, `x' = -omega a sin(theta)`, `a = 2 X sqrt(u1)` (uniform over
//!   the disc of radius `2 X` in the `(x, x'/omega)` plane), `theta = 2 pi u2`;
//! * inner mass: `z = y - x = (d/2)(2 u3 - 1)` anywhere in the clearance, `y' - x'` uniform in
//!   `[-2 omega X, 2 omega X]`.
//!
//! # Each start
//! The start runs the sweep's transient rule (docs/scenes.md: the `p`-step differences of the
//! section contract geometrically, `p` in `1..=8`), stopped as soon as the predicted distance
//! to the periodic orbit is below `1e-3` [`CensusSettings::handover`] of the scale, then 16
//! periods in which the sections repeating to the hand-over tolerance give the period `p`.
//! Newton on `P^p` takes over from there; a converged, stable, impacting orbit ends the start.
//! A start that reaches the end of its budget first is handed to Newton the same way when its
//! last 16 sections repeat to the hand-over tolerance (a weakly stable orbit, approached slowly).
//! A start that made no impact in those 16 periods, with the inner mass at rest relative to the
//! cavity (`|y'| <= 1e-12 omega X`), has reached the non-impacting family.
//!
//! # Starts that wander: chaos, and transient chaos
//! A start that has not converged after [`FIRST_CHECK`] periods is probed for [`PROBE`] periods
//! with the tangent map (its largest Lyapunov exponent, `cloud::ChaosProbe`). Near resonance many
//! starts first wander chaotically and only then settle on a periodic orbit (transient chaos:
//! measured on the showcase, lifetimes of 200 to 1400 periods with an exponent near 1 per
//! period all along), so a positive exponent does not end a start by itself. Instead the
//! census defers its wandering starts and resolves them by cloud ([`Cloud`]: where in the
//! section they wander):
//!
//! * of the wanderers in one cloud, one (the first) runs on for the rest of the
//!   [`CensusSettings::max_periods`] budget;
//! * when it escapes to a periodic orbit, the cloud was transient: every other member runs on
//!   for its own budget too (each may leave by another door);
//! * when it does not, the cloud is a chaotic attractor within the budget: the others are that
//!   attractor without running further, and its statistics are measured once.
//!
//! So a chaotic attractor costs one budget, not one per start, and transient chaos costs what
//! it always did. A start that reaches nothing within the budget is measured over
//! [`CensusSettings::window`] more periods: its amplitude is the largest `|x|` over that
//! window, a lower bound of what the motion can reach (a longer window can only raise it).
//!
//! # Merging
//! Two periodic attractors are one when their periods agree and the section of one lies within
//! `1e-6 X` of one of the other's `p` sections; all non-impacting starts are one attractor (the
//! family); two motions that are not periodic are one when their clouds are ([`Cloud::same`]).
//! A chaotic motion's 200-period cloud is a sample, and the rule fails now and then for two
//! samples of one motion: so two that ran their whole budgets and whose windows differ get a
//! second look, [`SECOND_LOOK`] periods from each one's last state, and are one when those
//! clouds are. (Before, on the frequency-response showcase 267 motions shared their point and
//! case with an earlier one; new 200-period clouds from their states made 141 of them the
//! same as the earlier, and each had had its own design life measured.) The merged attractor
//! keeps the larger window maximum, and the other's state joins its life measurement.
//! Basin share = starts that reached the attractor / starts.

mod cloud;
mod motion;
mod start;

pub use cloud::{CHAOS_FLOOR, Cloud, SECOND_LOOK, same_moments};
use cloud::{chaos_probe, long_cloud};
pub use motion::{CensusSettings, Origin, ProbeResult, Wandering};
pub use start::{
    CLOSE_RETURN, CLOSE_RETURN_TRIES, FIRST_CHECK, JOIN_AFTER, Landing, PROBE, Settled,
    close_returns, first_check, settle, start,
};
use start::{Early, Wanderer, begin, conclude, land, section_of, transient};

use super::map::{Forcing, Section};
use super::shoot::{Newton, Orbit, Stability, Termination, orbit_at, same_orbit, solve};
use crate::sim::Outcome;

/// What kind of steady state an attractor is.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// A periodic orbit (impacting, or the non-impacting family), exact.
    Periodic(Box<Orbit>),
    /// A motion that is not periodic (within the periods the start was given).
    NonPeriodic(Box<Wandering>),
}

/// Most runs a life measurement uses for one attractor (its own section and the states of
/// starts that joined it).
pub const CHAINS: usize = 8;

/// One distinct attractor at a frequency point.
#[derive(Clone, Debug, PartialEq)]
pub struct Attractor {
    pub kind: Kind,
    /// Orbit period in forcing periods; 0 when not periodic.
    pub period: u32,
    /// The design amplitude (m): `max |x|` of a periodic orbit, exact; of a motion that is not
    /// periodic, its largest amplitude over the design life when measured, else its window's.
    pub amplitude: f64,
    /// `max |x|` over the census's measuring window (m); the amplitude of a periodic orbit.
    pub window_amplitude: f64,
    /// Impacts per forcing period (over whole orbit periods, or over the window).
    pub impacts_per_period: f64,
    /// Census starts that reached it (seeds from a neighbouring frequency are not counted).
    pub starts: u32,
    /// How it was first reached.
    pub origin: Origin,
    /// A section state on it: a periodic orbit's own section, or where the measuring window of a
    /// motion that is not periodic ended (a state on the attractor, from which a neighbouring
    /// frequency's census, continuation or a longer measurement can start).
    pub section: Section,
}

/// The census of one frequency point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Census {
    /// Distinct attractors, in the order they were first reached (start 0's first).
    pub attractors: Vec<Attractor>,
    /// Starts run.
    pub starts: u32,
    /// Forcing periods simulated in all (transients, probes, Newton's maps, windows).
    pub periods: u64,
}

impl Census {
    /// The attractor with the largest amplitude (the worst steady state); ties go to the first.
    pub fn worst(&self) -> Option<&Attractor> {
        self.attractors
            .iter()
            .reduce(|a, b| if b.amplitude > a.amplitude { b } else { a })
    }

    /// Basin share of attractor `i`.
    pub fn share(&self, i: usize) -> f64 {
        self.attractors[i].starts as f64 / self.starts as f64
    }
}

/// Runs the census at one frequency point from `s0` (the study's initial section): starts
/// `0..c.starts`.
pub fn census(f: &Forcing, s0: &Section, c: &CensusSettings) -> Census {
    let mut out = Census::default();
    out.run_starts(f, s0, c, &Newton::default());
    out
}

impl Census {
    /// Runs the census's own starts at `f` (module doc, "Starts"), start 0 from `s0`. Start 0
    /// runs to its end first (its amplitude scales the other starts' box); the others are
    /// resolved by cloud, with start 0's attractor among those they can join.
    pub fn run_starts(&mut self, f: &Forcing, s0: &Section, c: &CensusSettings, newton: &Newton) {
        let budget0 = c
            .max_periods
            .saturating_sub(c.spent0)
            .max(FIRST_CHECK + PROBE + 1);
        let st = match begin(f, s0, c, newton, Origin::Start(0), 1, budget0) {
            Early::Landed(st) => st,
            Early::Wandering(w) => conclude(f, w, budget0, c, newton),
        };
        self.periods += st.periods;
        self.starts += 1;
        let first = attractor(st, Origin::Start(0), 1);
        let x_ref = if first.amplitude.is_finite() {
            f.half_gap().max(first.amplitude)
        } else {
            f.half_gap()
        };
        self.merge(f, first);
        let mut wanderers = Vec::new();
        for k in 1..c.starts.max(1) {
            let s = start(f, c, k, x_ref);
            self.starts += 1;
            match begin(f, &s, c, newton, Origin::Start(k), 1, c.max_periods) {
                Early::Landed(st) => {
                    self.periods += st.periods;
                    self.merge(f, attractor(st, Origin::Start(k), 1));
                }
                Early::Wandering(w) => {
                    self.periods += w.periods;
                    wanderers.push(w);
                }
            }
        }
        self.resolve(f, wanderers, c, newton);
    }

    /// Continues `from`, an attractor of a neighbouring frequency of the same curve, to `f`:
    /// a periodic orbit by Newton on `P^p` from its section (kept when it converges to a stable
    /// orbit), anything else (a motion that is not periodic, an orbit that lost its stability or
    /// that Newton cannot reach) as a start from its section. A seed that wanders in the cloud
    /// of a chaotic attractor already found here joins it without running its budget. What it
    /// lands on joins the census (a new attractor, or merged into a known one) without counting
    /// as a start: basin shares stay those of the census's own starts.
    pub fn seed(
        &mut self,
        f: &Forcing,
        from: &Attractor,
        origin: Origin,
        c: &CensusSettings,
        newton: &Newton,
    ) {
        if let Kind::Periodic(o) = &from.kind
            && o.impacts > 0
        {
            let p = u64::from(o.period);
            let (term, state) = solve(f, p, &o.s, newton);
            if let Some(st) = &state {
                self.periods += u64::from(st.iterations + 1) * p;
            }
            if let (Termination::Converged { .. }, Some(st)) = (term, state)
                && let Some(orbit) = orbit_at(f, p, &st, newton)
                && orbit.stability == Stability::Stable
            {
                let end = orbit.s;
                let landing = Settled {
                    landing: Landing::Orbit(orbit),
                    periods: 0,
                    end,
                };
                self.merge(f, attractor(landing, origin, 0));
                return;
            }
        }
        // A motion that was not periodic there is probed first: when it wanders in the cloud of
        // a chaotic attractor found here, it is that attractor (no transient to run).
        if matches!(from.kind, Kind::NonPeriodic(_)) && self.has_exhausted_cloud() {
            let probe = chaos_probe(f, &from.section, PROBE);
            self.periods += probe.periods;
            if probe.ok
                && let Some(i) = self.exhausted_cloud(&probe.cloud)
            {
                let _ = i;
                return;
            }
        }
        match begin(f, &from.section, c, newton, origin, 0, c.max_periods) {
            Early::Landed(st) => {
                self.periods += st.periods;
                self.merge(f, attractor(st, origin, 0));
            }
            Early::Wandering(w) => {
                self.periods += w.periods;
                self.resolve(f, vec![w], c, newton);
            }
        }
    }

    /// Whether a motion that is not periodic here ran a whole budget (a chaotic attractor).
    fn has_exhausted_cloud(&self) -> bool {
        self.attractors
            .iter()
            .any(|a| matches!(&a.kind, Kind::NonPeriodic(x) if x.exhausted))
    }

    /// The attractor whose whole-budget cloud `cloud` is, if any.
    fn exhausted_cloud(&self, cloud: &Cloud) -> Option<usize> {
        self.attractors.iter().position(
            |a| matches!(&a.kind, Kind::NonPeriodic(x) if x.exhausted && x.cloud.same(cloud)),
        )
    }

    /// Resolves wandering starts by cloud (module doc, "Starts that wander").
    fn resolve(
        &mut self,
        f: &Forcing,
        wanderers: Vec<Wanderer>,
        c: &CensusSettings,
        newton: &Newton,
    ) {
        let mut groups: Vec<Vec<Wanderer>> = Vec::new();
        for w in wanderers {
            // A chaotic attractor this census already ran a whole budget on: the wanderer runs
            // to JOIN_AFTER periods, then joins it unless it escaped.
            if let Some(i) = self.exhausted_cloud(&w.cloud) {
                self.join_or_land(f, i, w, c, newton);
                continue;
            }
            match groups.iter_mut().find(|g| g[0].cloud.same(&w.cloud)) {
                Some(g) => g.push(w),
                None => groups.push(vec![w]),
            }
        }
        for group in groups {
            let mut members = group.into_iter();
            let Some(first) = members.next() else {
                continue;
            };
            let st = conclude(f, first.clone(), c.max_periods, c, newton);
            self.periods += st.periods - first.periods;
            let exhausted = matches!(&st.landing, Landing::NonPeriodic { wandering, .. } if wandering.exhausted);
            let index = self.merge(f, attractor(st, first.origin, first.starts));
            for w in members {
                if exhausted {
                    self.join_or_land(f, index, w, c, newton);
                } else {
                    // The cloud proved transient: each member runs its own budget.
                    let st = conclude(f, w.clone(), c.max_periods, c, newton);
                    self.periods += st.periods - w.periods;
                    self.merge(f, attractor(st, w.origin, w.starts));
                }
            }
        }
    }

    /// A wanderer in the cloud of attractor `index` (which ran a whole budget without leaving
    /// it): it runs on to [`JOIN_AFTER`] periods; what converges by then lands where it lands,
    /// the rest joins attractor `index` (not measured again).
    fn join_or_land(
        &mut self,
        f: &Forcing,
        index: usize,
        w: Wanderer,
        c: &CensusSettings,
        newton: &Newton,
    ) {
        let left = c
            .max_periods
            .min(JOIN_AFTER)
            .saturating_sub(w.periods)
            .max(1);
        let (rec, p) = transient(f, &w.state, c, left);
        self.periods += p;
        if rec.outcome != Outcome::Ok {
            self.join(index, w.starts, w.state);
            return;
        }
        let s = section_of(&rec);
        if rec.converged {
            let probe = Some((w.probe, w.cloud.clone()));
            let st = land(f, &rec, &s, c, newton, w.periods + p, probe);
            self.periods += st.periods - w.periods - p;
            if matches!(st.landing, Landing::Orbit(_)) {
                self.merge(f, attractor(st, w.origin, w.starts));
                return;
            }
        }
        self.join(index, w.starts, s);
    }

    /// A wanderer (`starts` census starts, now at `state`) joins attractor `index`: its starts
    /// count there, its state is one more chain for the life measurement.
    fn join(&mut self, index: usize, starts: u32, state: Section) {
        let a = &mut self.attractors[index];
        a.starts += starts;
        if let Kind::NonPeriodic(x) = &mut a.kind
            && x.chains.len() + 1 < CHAINS
        {
            x.chains.push(state);
        }
    }

    /// Adds `att` to the census, merged with an equal attractor (module doc), and the stable
    /// orbits found in its close returns; returns its index.
    fn merge(&mut self, f: &Forcing, mut att: Attractor) -> usize {
        let embedded = match &mut att.kind {
            Kind::NonPeriodic(w) => std::mem::take(&mut w.embedded),
            Kind::Periodic(_) => Vec::new(),
        };
        let index = self.merge_one(f, att);
        for o in embedded {
            let found = Settled {
                end: o.s,
                landing: Landing::Orbit(o),
                periods: 0,
            };
            self.merge_one(f, attractor(found, Origin::Recurrence, 0));
        }
        index
    }

    fn merge_one(&mut self, f: &Forcing, att: Attractor) -> usize {
        let found = match self
            .attractors
            .iter()
            .position(|known| same(f, known, &att))
        {
            Some(i) => Some(i),
            None => self.second_look(f, &att),
        };
        let Some(i) = found else {
            self.attractors.push(att);
            return self.attractors.len() - 1;
        };
        let known = &mut self.attractors[i];
        known.starts += att.starts;
        if let Kind::NonPeriodic(x) = &mut known.kind {
            // One more run on a motion that is not periodic, for its life measurement.
            if x.chains.len() + 1 < CHAINS {
                x.chains.push(att.section);
            }
            // Two windows of one motion: the larger maximum is the better lower bound, and
            // its window describes it.
            if att.window_amplitude > known.window_amplitude {
                known.amplitude = att.amplitude;
                known.window_amplitude = att.window_amplitude;
                known.impacts_per_period = att.impacts_per_period;
            }
        }
        i
    }

    /// The known attractor that `att` is on a second look (module doc, "Merging"): both ran
    /// their whole budgets, and their clouds over [`SECOND_LOOK`] periods from their last
    /// states are one. The periods count toward the census.
    fn second_look(&mut self, f: &Forcing, att: &Attractor) -> Option<usize> {
        let exhausted = |a: &Attractor| matches!(&a.kind, Kind::NonPeriodic(w) if w.exhausted);
        if !exhausted(att) {
            return None;
        }
        // `att`'s own cloud, run once at the first candidate.
        let mut ours: Option<Cloud> = None;
        for i in 0..self.attractors.len() {
            if !exhausted(&self.attractors[i]) {
                continue;
            }
            if ours.is_none() {
                ours = Some(long_cloud(f, &att.section, SECOND_LOOK)?);
                self.periods += SECOND_LOOK;
            }
            self.periods += SECOND_LOOK;
            let known = long_cloud(f, &self.attractors[i].section, SECOND_LOOK);
            if known.zip(ours.as_ref()).is_some_and(|(k, o)| k.same(o)) {
                return Some(i);
            }
        }
        None
    }
}

/// The attractor a settled start landed on, reached by `starts` census starts (0 or 1).
fn attractor(st: Settled, origin: Origin, starts: u32) -> Attractor {
    match st.landing {
        Landing::Orbit(o) => Attractor {
            period: o.period,
            amplitude: o.amplitude,
            window_amplitude: o.amplitude,
            impacts_per_period: o.impacts_per_period(),
            section: o.s,
            kind: Kind::Periodic(Box::new(o)),
            starts,
            origin,
        },
        Landing::NonPeriodic {
            amplitude,
            impacts_per_period,
            wandering,
        } => Attractor {
            kind: Kind::NonPeriodic(wandering),
            period: 0,
            amplitude,
            window_amplitude: amplitude,
            impacts_per_period,
            starts,
            origin,
            section: st.end,
        },
    }
}

fn same(f: &Forcing, a: &Attractor, b: &Attractor) -> bool {
    match (&a.kind, &b.kind) {
        (Kind::Periodic(oa), Kind::Periodic(ob)) => {
            if oa.period != ob.period || (oa.impacts == 0) != (ob.impacts == 0) {
                return false;
            }
            if oa.impacts == 0 {
                return true;
            }
            same_orbit(f, &oa.s, &ob.s, u64::from(oa.period))
        }
        (Kind::NonPeriodic(wa), Kind::NonPeriodic(wb)) => wa.cloud.same(&wb.cloud),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::map::eval;
    use crate::orbits::map::tests::table_i as forcing;

    fn settings(starts: u32) -> CensusSettings {
        CensusSettings {
            starts,
            max_periods: 2000,
            handover: 1e-3,
            window: 200,
            seed: 7,
            point: 3,
            spent0: 0,
        }
    }

    /// Issue 16's first row: at r = 0.90 the motion from rest never impacts (0.131 cm), while
    /// other starts reach period-1 orbits at 0.199 and 0.211 cm, 61 % higher. The census finds
    /// them, and the worst is an impacting orbit. The 0.211 cm orbit's basin is small (1 of 24
    /// starts in the brute force): 12 starts met it only by the luck of the draw (none
    /// did once the simulator's last bits changed), 36 meet it once and 48 three times.
    #[test]
    fn census_finds_the_impacting_orbit_the_rest_start_misses() {
        let f = forcing(0.005, 0.005, 0.9, 0.1, 0.1, 0.9);
        let c = census(&f, &[0.0, 0.0, 0.0, 0.0], &settings(48));
        assert_eq!(c.starts, 48);
        let first = &c.attractors[0];
        assert!(matches!(&first.kind, Kind::Periodic(o) if o.impacts == 0));
        assert!(
            (first.amplitude - 0.00131).abs() < 0.00001,
            "{}",
            first.amplitude
        );
        // The brute force found period 1 at 0.199 cm (22 of 24 starts) and at 0.211 cm
        // (1 of 24): both are here, the second (three impacts per period) is the worst.
        let near = |a: f64| {
            c.attractors
                .iter()
                .any(|x| x.period == 1 && (x.amplitude - a).abs() < 2e-5)
        };
        assert!(near(0.00199) && near(0.00211), "{:?}", c.attractors);
        let worst = c.worst().unwrap();
        assert!((worst.amplitude - 0.00211).abs() < 0.00002);
        assert!(worst.amplitude > 1.6 * first.amplitude);
        let shares: f64 = (0..c.attractors.len()).map(|i| c.share(i)).sum();
        assert!((shares - 1.0).abs() < 1e-12);
    }

    /// The showcase's design m = 5 g, d = 5 mm at r = 1.195 has a period-1 orbit with its
    /// largest multiplier at 0.983: a start near it that runs out of periods before the
    /// transient test is met (its sections still drift by more than the test allows, but repeat
    /// to the hand-over tolerance) lands on the orbit; it is not a motion that is not periodic.
    #[test]
    fn a_start_on_a_weakly_stable_orbit_lands_even_at_the_end_of_its_budget() {
        let f = forcing(0.005, 0.005, 0.9, 0.1, 0.1, 1.195);
        let c = census(&f, &[0.0, 0.0, 0.0, 0.0], &settings(8));
        let orbit = c
            .attractors
            .iter()
            .find_map(|a| match &a.kind {
                Kind::Periodic(o) if o.impacts > 0 => Some(o.clone()),
                _ => None,
            })
            .expect("an impacting periodic orbit");
        assert_eq!(orbit.period, 1);
        assert!(orbit.multiplier_max() > 0.97, "{}", orbit.multiplier_max());
        // 1e-5 of the orbit's amplitude off it, and 50 periods: too few for the transient
        // test (1e-6 at a contraction of 0.983 a period), enough to show the period.
        let mut s0 = orbit.s;
        s0[0] += 1e-5 * orbit.amplitude;
        let short = CensusSettings {
            max_periods: 50,
            ..settings(1)
        };
        let settled = settle(&f, &s0, &short, &Newton::default());
        match &settled.landing {
            Landing::Orbit(o) => {
                assert!(same_orbit(&f, &o.s, &orbit.s, 1), "{:?} {:?}", o.s, orbit.s);
                assert!((o.amplitude - orbit.amplitude).abs() <= 1e-9 * orbit.amplitude);
            }
            Landing::NonPeriodic { amplitude, .. } => {
                panic!(
                    "not periodic at {amplitude}, the orbit's amplitude {}",
                    orbit.amplitude
                )
            }
        }
    }

    /// Two windows of one chaotic motion (the second starts `1,000 k` periods further along the
    /// first's trajectory, `k = 1..=20`) whose clouds disagree (here the second's is cut to a
    /// single section, so its spread is 0) are one attractor on the second look when its
    /// 400-period clouds agree: the census then keeps one, with both starts, the larger window
    /// maximum and the other's state as a chain. The clouds' rule is a test on two samples and
    /// on this motion it agrees for 9 of the 20 draws (before and after the simulator's speed
    /// work changed its last bits): at least 5 are asked for, and each merge is checked.
    #[test]
    fn a_second_look_merges_two_windows_of_one_chaotic_motion() {
        // The showcase's m = 5 g, d = 5 mm at r = 0.975: chaotic, every start.
        let f = forcing(0.005, 0.005, 0.9, 0.1, 0.1, 0.975);
        let c = settings(1);
        let newton = Newton::default();
        let on_it = |s0: Section| {
            let st = settle(&f, &s0, &c, &newton);
            assert!(
                matches!(&st.landing, Landing::NonPeriodic { wandering, .. } if wandering.exhausted)
            );
            attractor(st, Origin::Start(0), 1)
        };
        let a = on_it([0.0, 0.0, 0.0, 0.0]);
        let mut merged = 0;
        for k in 1..=20 {
            let later = eval(&f, &a.section, 1000 * k, false).end;
            let mut b = on_it(later);
            if let Kind::NonPeriodic(w) = &mut b.kind {
                let mut cut = Cloud::new(&f);
                cut.add(&b.section);
                w.cloud = cut;
            }
            b.window_amplitude = 2.0 * a.window_amplitude;
            assert!(!same(&f, &a, &b));
            let mut census = Census::default();
            census.merge(&f, a.clone());
            let periods = census.periods;
            let at = census.merge(&f, b.clone());
            assert_eq!(census.periods, periods + 2 * SECOND_LOOK);
            if at != 0 {
                assert_eq!(census.attractors.len(), 2);
                continue;
            }
            merged += 1;
            assert_eq!(census.attractors.len(), 1);
            let one = &census.attractors[0];
            assert_eq!(one.starts, 2);
            assert_eq!(one.window_amplitude, b.window_amplitude);
            assert!(matches!(&one.kind, Kind::NonPeriodic(w) if w.chains == vec![b.section]));
        }
        assert!(merged >= 5, "{merged} of 20 merged");
    }

    #[test]
    fn starts_are_deterministic_and_depend_on_the_point() {
        let f = forcing(0.005, 0.005, 0.9, 0.1, 0.1, 0.9);
        let a = start(&f, &settings(4), 2, 0.003);
        let b = start(&f, &settings(4), 2, 0.003);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        let other = CensusSettings {
            point: 4,
            ..settings(4)
        };
        assert_ne!(a, start(&f, &other, 2, 0.003));
        assert!(a[2].abs() <= f.half_gap());
    }
}
