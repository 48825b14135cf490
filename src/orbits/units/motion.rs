//! The motions of several units that are not periodic, told apart (docs/model.md §14): the
//! census's starts that did not settle on a periodic orbit, grouped by where they wander.
//!
//! Near resonance a census of several units often holds more than one such motion at one
//! frequency: on the multi-unit showcase (two units, clearances 5 and 15 mm, r = 0.94) start 0
//! wanders with one unit floating still in its cavity and the structure below 0.43 cm, while the
//! three seeded starts share a chaotic motion of both units reaching 0.82 cm. Pooled, the race
//! measured the larger and a restart from the first stored state the smaller. So each motion is
//! kept apart, with its own starts, window, states, exponent and design life.
//!
//! # When two starts are one motion
//! As one unit's census ([`crate::orbits::census`], "Merging"): each start's cloud, the mean and
//! spread of every section coordinate over its last
//! [`crate::orbits::tolerances::CENSUS_WINDOW`] periods in scaled units (`x / L`,
//! `x' / (wn L)`, `z_i / L`, `y_i' / (wn L)`, `L = d/2`), and the rule of
//! [`crate::orbits::census::same_moments`]. A 200-period cloud of a slowly mixing chaotic motion
//! is a coarse sample (on the showcase's point above, the structure's mean differed by 0.135 L
//! between two starts of one motion, against a spread of 0.17 L), so a start whose cloud matches
//! no motion gets a second look: a cloud over [`SECOND_LOOK`] periods from its end state,
//! compared with the same from each motion's first state (computed once per motion); it joins
//! the first motion whose second look matches. The rule never joins two motions whose spreads
//! differ by a factor 2 or whose means lie apart by half a spread in any coordinate, so a unit
//! floating still (spread 0) is never one motion with that unit impacting.
//!
//! Starts whose simulation stopped (an outcome not `ok`) are one motion with no state.

use super::map::eval;
use crate::orbits::census::{ProbeResult, SECOND_LOOK, same_moments};
use crate::orbits::life::LifeSummary;
use crate::orbits::map::Forcing;
use crate::sim::Outcome;

/// Where a motion of several units wanders in the section: the sums of every coordinate and of
/// its square in scaled units (module doc) over the sections added.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UnitsCloud {
    n: u64,
    sum: Vec<f64>,
    sum2: Vec<f64>,
    scale: Vec<f64>,
}

impl UnitsCloud {
    /// An empty cloud for section states of `f` (`2 + 2N` components).
    pub fn new(f: &Forcing) -> UnitsCloud {
        let l = f.half_gap();
        let wl = f.sys.omega() * l;
        let n = 2 + 2 * super::map::unit_count(f);
        UnitsCloud {
            n: 0,
            sum: vec![0.0; n],
            sum2: vec![0.0; n],
            scale: (0..n)
                .map(|k| if k % 2 == 0 { 1.0 / l } else { 1.0 / wl })
                .collect(),
        }
    }

    /// Adds one section state.
    pub fn add(&mut self, s: &[f64]) {
        self.n += 1;
        for (k, x) in s.iter().enumerate().take(self.sum.len()) {
            let v = x * self.scale[k];
            self.sum[k] += v;
            self.sum2[k] += v * v;
        }
    }

    /// Each coordinate's mean and standard deviation.
    fn moments(&self) -> Vec<(f64, f64)> {
        let n = self.n.max(1) as f64;
        self.sum
            .iter()
            .zip(&self.sum2)
            .map(|(s, s2)| {
                let mean = s / n;
                (mean, (s2 / n - mean * mean).max(0.0).sqrt())
            })
            .collect()
    }

    /// Whether two clouds are one motion ([`same_moments`]); empty clouds never are.
    pub fn same(&self, other: &UnitsCloud) -> bool {
        self.n > 0 && other.n > 0 && same_moments(&self.moments(), &other.moments())
    }
}

/// The cloud of the motion from `s` over `n` periods of the map of several units; `None` when
/// a period's map stopped.
pub fn long_cloud(f: &Forcing, s: &[f64], n: u64) -> Option<UnitsCloud> {
    let mut cloud = UnitsCloud::new(f);
    let mut state = s.to_vec();
    for _ in 0..n {
        let e = eval(f, &state, 1);
        if e.outcome != Outcome::Ok {
            return None;
        }
        state = e.end;
        cloud.add(&state);
    }
    Some(cloud)
}

/// One motion that is not periodic, as the census found it (module doc).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UnitsMotion {
    /// Starts that ended on it.
    pub starts: u32,
    /// The first of them.
    pub first: u32,
    /// The largest `|x|` over the last [`crate::orbits::tolerances::CENSUS_WINDOW`] periods of
    /// each of its starts (m): a lower bound of what it reaches.
    pub window: f64,
    /// Where each of its starts ended, in start order (`2 + 2N` components): the states the
    /// race measures it from ([`crate::orbits::race::race_units`]); empty for starts whose
    /// simulation stopped.
    pub states: Vec<Vec<f64>>,
    /// Its first start's cloud over its last window; `None` for starts whose simulation stopped.
    pub cloud: Option<UnitsCloud>,
    /// Its second look from its first state (module doc), once computed.
    pub look: Option<UnitsCloud>,
    /// Its largest Lyapunov exponent from two trajectories through its first state
    /// ([`super::lyapunov`]); `None` without a state or when the simulator stopped.
    pub probe: Option<ProbeResult>,
    /// Its design life (the race), when the scene asks for it; `None` before the race.
    pub life: Option<LifeSummary>,
}

/// Adds start `k`, ended at `end` with its window `cloud` (`None`: its simulation stopped)
/// and window amplitude `window`, to the motion it belongs to in `motions` (module doc), or as a
/// new one. Returns the motion's index and the forcing periods the second looks simulated.
pub fn join(
    f: &Forcing,
    motions: &mut Vec<UnitsMotion>,
    k: u32,
    end: Option<(Vec<f64>, UnitsCloud)>,
    window: f64,
) -> (usize, u64) {
    let mut periods = 0;
    let (at, state, cloud, look) = match end {
        None => (
            motions.iter().position(|m| m.cloud.is_none()),
            None,
            None,
            None,
        ),
        Some((s, cloud)) => {
            let direct = motions
                .iter()
                .position(|m| m.cloud.as_ref().is_some_and(|c| c.same(&cloud)));
            let (at, look) = match direct {
                Some(i) => (Some(i), None),
                None => {
                    periods += SECOND_LOOK;
                    // An empty cloud where the look stopped: it matches nothing.
                    let look = long_cloud(f, &s, SECOND_LOOK).unwrap_or_default();
                    (second_look(f, motions, &look, &mut periods), Some(look))
                }
            };
            (at, Some(s), Some(cloud), look)
        }
    };
    match at {
        Some(i) => {
            let m = &mut motions[i];
            m.starts += 1;
            m.window = m.window.max(window);
            m.states.extend(state);
            (i, periods)
        }
        None => {
            motions.push(UnitsMotion {
                starts: 1,
                first: k,
                window,
                states: state.into_iter().collect(),
                cloud,
                look,
                ..UnitsMotion::default()
            });
            (motions.len() - 1, periods)
        }
    }
}

/// The first motion of `motions` (with a state) whose second look matches `look`, computing
/// each one's once (its periods added to `periods`).
fn second_look(
    f: &Forcing,
    motions: &mut [UnitsMotion],
    look: &UnitsCloud,
    periods: &mut u64,
) -> Option<usize> {
    for (i, m) in motions.iter_mut().enumerate() {
        let Some(first) = m.states.first() else {
            continue;
        };
        if m.look.is_none() {
            *periods += SECOND_LOOK;
            m.look = Some(long_cloud(f, first, SECOND_LOOK).unwrap_or_default());
        }
        if m.look.as_ref().is_some_and(|c| c.same(look)) {
            return Some(i);
        }
    }
    None
}
