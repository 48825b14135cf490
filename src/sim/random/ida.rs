//! A motion's capacity by incremental dynamic analysis (Vamvatsikos and Cornell 2002; model.md
//! §13, docs/scenes.md): the smallest intensity at which `max |x|` passes the limit `b` when
//! the motion is scaled.
//!
//! # Method
//! One motion (a realization's load, or a record) of own intensity `I0` (g, at scale 1) is run
//! at gains `s`; it *passes* at `s` when its `max |x| > b`. The search keeps `hi`, the smallest
//! gain found passing, and `lo`, the largest gain found not passing below `hi`, and ends when
//! `hi / lo <= 1 + tol`; the capacity is `sqrt(lo hi) I0` (g), within a relative `tol / 2` of
//! the first passage's gain when the response is monotone in the gain between them.
//! * **Bracketing** from the first run `(s0, a0)`: the next gain is the linear structure's
//!   answer `s0 b / a0`, 2 % beyond it (up when `a0 <= b`, down when it passed), held within a
//!   factor `[1.05, 16]` of `s0`; then again from the newest end until both ends exist.
//! * **Closing**: false position on `ln a` against `ln s` between the ends, the trial placed a
//!   `tol / 2` beyond the estimate on the side of the end that moved last, so that a near-linear
//!   response closes the bracket in two runs; after two trials that moved the same end, a
//!   geometric bisection. Every trial lies inside the bracket by at least `tol / 4`.
//! * **Where the response is not monotone** (a motion that passes at one gain and not at a
//!   larger one, the "resurrection" of IDA curves), the search keeps the smallest passing gain
//!   it found and says so ([`Capacity::resurrected`]); gains below the bracket it never tried
//!   may still pass. With an impact damper they often do, in narrow windows that a finer scan
//!   keeps finding lower down (`results/ida_scan.md`: the first passage of the seismic
//!   showcase's 4-cm design moves from 0.86 to 0.73 of the capacity as a scan's step goes from
//!   2 to 0.025 %), so there the capacity is the crossing this search meets, not a converged
//!   first passage; the stripes' own share that passes needs no capacity, and the decision
//!   rests on it (`crate::reduce::random::risk`).
//! * **Censored**: a motion that does not pass at `ida_max / I0` (the study's largest intensity)
//!   has capacity above `ida_max` ([`Capacity::censored`], `capacity` = `ida_max`).
//! * A run that does not end `ok` (its amplitude NaN) ends the search: capacity NaN.
//!
//! At most [`MAX_RUNS`] runs a motion, the first included; a search that reaches it reports
//! the bracket it has (`capacity` its geometric middle, within a wider tolerance).

use serde::Serialize;

/// Most runs of one motion's capacity search, the first included.
pub const MAX_RUNS: u32 = 20;

/// A run of the search: its gain and its amplitude (m).
type Trial = (f64, f64);

/// One motion's capacity (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Capacity {
    /// The intensity (g) at which `max |x|` first passes the limit: the geometric middle of
    /// the final bracket; `ida_max` when censored; NaN when a run failed.
    pub capacity: f64,
    /// The motion did not pass the limit at the largest intensity tried.
    pub censored: bool,
    /// It passed at a gain and not at a larger one (the smallest passing gain is kept).
    pub resurrected: bool,
    /// Runs the search took, the first included.
    pub runs: u32,
}

/// The capacity (g) of a motion of own intensity `own` (g, > 0) against the limit `b`, from a
/// first run at gain `s0` whose amplitude was `a0` (module doc). `amplitude(s)` runs the
/// motion at gain `s` and returns its `max |x|` (NaN for a run that did not end `ok`).
pub fn capacity(
    own: f64,
    b: f64,
    first: (f64, f64),
    tol: f64,
    ida_max: f64,
    amplitude: impl FnMut(f64) -> f64,
) -> Capacity {
    Search::new(own, b, first, tol, ida_max).finish(amplitude)
}

/// What a [`Search`] asks for next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Next {
    /// A run of the motion at this gain; its amplitude goes to [`Search::tell`].
    Run(f64),
    /// The search is over.
    Done(Capacity),
}

/// [`capacity`]'s search one trial at a time, for callers that run several motions' trials
/// together (the sweep's realizations side by side): the same trials and the same capacity.
#[derive(Clone, Debug)]
pub struct Search {
    own: f64,
    b: f64,
    tol: f64,
    ida_max: f64,
    s_max: f64,
    tried: Vec<Trial>,
    streak: u32,
    prev_hi: Option<bool>,
    /// The gain [`Search::ask`] asked for, until its amplitude is told.
    pending: Option<f64>,
}

impl Search {
    /// The search of [`capacity`] (the same arguments, without the runs).
    pub fn new(own: f64, b: f64, (s0, a0): (f64, f64), tol: f64, ida_max: f64) -> Search {
        Search {
            own,
            b,
            tol,
            ida_max,
            s_max: ida_max / own,
            tried: vec![(s0, a0)],
            streak: 0,
            prev_hi: None,
            pending: None,
        }
    }

    /// The next run's gain, or the capacity (module doc).
    pub fn ask(&mut self) -> Next {
        let (b, tol, own) = (self.b, self.tol, self.own);
        let tried = &self.tried;
        if tried.iter().any(|t| t.1.is_nan()) {
            return Next::Done(done(f64::NAN, false, tried, b));
        }
        let (lo, hi) = ends(tried, b);
        let trial = match (lo, hi) {
            (Some((l, _)), Some((h, _))) if h / l <= 1.0 + tol => {
                return Next::Done(done((l * h).sqrt() * own, false, tried, b));
            }
            (Some((l, al)), Some((h, ah))) => {
                // The end the newest run moved, and how many runs in a row moved it.
                let moved_hi = tried.last().is_some_and(|t| t.1 > b);
                self.streak = if self.prev_hi == Some(moved_hi) {
                    self.streak + 1
                } else {
                    1
                };
                self.prev_hi = Some(moved_hi);
                let pad = (tol / 4.0).ln_1p();
                let (x0, x1) = (l.ln(), h.ln());
                if self.streak >= 3 || x1 - x0 <= 4.0 * pad || al <= 0.0 {
                    (0.5 * (x0 + x1)).exp()
                } else {
                    let (y0, y1) = (al.ln() - b.ln(), ah.ln() - b.ln());
                    let x = x0 + y0 / (y0 - y1) * (x1 - x0);
                    let half = (tol / 2.0).ln_1p();
                    let x = if moved_hi { x - half } else { x + half };
                    x.clamp(x0 + pad, x1 - pad).exp()
                }
            }
            (Some((l, al)), None) => {
                if l >= self.s_max * (1.0 - 1e-12) {
                    return Next::Done(done(self.ida_max, true, tried, b));
                }
                let guess = if al > 0.0 { b / al * 1.02 } else { 4.0 };
                (l * guess.clamp(1.05, 16.0)).min(self.s_max)
            }
            (None, Some((h, ah))) => h * (b / ah / 1.02).clamp(1.0 / 16.0, 1.0 / 1.05),
            (None, None) => unreachable!("the first run is one of the ends"),
        };
        if tried.len() as u32 >= MAX_RUNS {
            return Next::Done(match (lo, hi) {
                (Some((l, _)), Some((h, _))) => done((l * h).sqrt() * own, false, tried, b),
                (Some(_), None) => done(self.ida_max, true, tried, b),
                _ => done(f64::NAN, false, tried, b),
            });
        }
        self.pending = Some(trial);
        Next::Run(trial)
    }

    /// The search to its end, `amplitude(s)` running the motion at each gain `s` it asks for
    /// ([`capacity`]).
    pub fn finish(mut self, mut amplitude: impl FnMut(f64) -> f64) -> Capacity {
        loop {
            match self.ask() {
                Next::Run(s) => self.tell(amplitude(s)),
                Next::Done(c) => return c,
            }
        }
    }

    /// The amplitude (m; NaN for a run that did not end `ok`) of the run [`Search::ask`] asked
    /// for.
    ///
    /// # Panics
    /// When no run was asked for (a `tell` not after [`Next::Run`]): a caller's mistake.
    pub fn tell(&mut self, amplitude: f64) {
        let s = self
            .pending
            .take()
            .expect("Search::tell follows a Next::Run of Search::ask");
        self.tried.push((s, amplitude));
    }
}

/// The bracket's ends among the runs `tried` (gain, amplitude): the smallest passing gain and
/// the largest gain below it that did not pass.
fn ends(tried: &[Trial], b: f64) -> (Option<Trial>, Option<Trial>) {
    let hi = tried
        .iter()
        .filter(|t| t.1 > b)
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .copied();
    let lo = tried
        .iter()
        .filter(|t| t.1 <= b && hi.is_none_or(|h| t.0 < h.0))
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .copied();
    (lo, hi)
}

fn done(capacity: f64, censored: bool, tried: &[(f64, f64)], b: f64) -> Capacity {
    // Resurrection: a gain above the smallest passing one that did not pass.
    let first = tried
        .iter()
        .filter(|t| t.1 > b)
        .map(|t| t.0)
        .fold(f64::INFINITY, f64::min);
    Capacity {
        capacity,
        censored,
        resurrected: tried.iter().any(|t| t.1 <= b && t.0 > first),
        runs: tried.len() as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_response_gives_the_linear_capacity_in_few_runs() {
        // a(s) = 0.02 s: passes b = 0.05 above s = 2.5; own intensity 0.3 g -> 0.75 g.
        for s0 in [0.1, 1.0, 2.0, 3.0, 50.0] {
            let c = capacity(0.3, 0.05, (s0, 0.02 * s0), 0.01, 10.0, |s| 0.02 * s);
            assert!(!c.censored && !c.resurrected);
            assert!((c.capacity / 0.75 - 1.0).abs() <= 0.005, "{s0}: {c:?}");
            assert!(c.runs <= 6, "{s0}: {c:?}");
        }
    }

    #[test]
    fn a_softening_response_converges_within_the_tolerance() {
        // a(s) = 0.01 s^0.6: passes 0.05 at s = 5^(1/0.6) = 14.62.
        let truth = 5f64.powf(1.0 / 0.6);
        let c = capacity(0.1, 0.05, (1.0, 0.01), 0.01, 10.0, |s| 0.01 * s.powf(0.6));
        assert!((c.capacity / (0.1 * truth) - 1.0).abs() <= 0.005, "{c:?}");
        assert!(c.runs <= MAX_RUNS);
    }

    #[test]
    fn a_motion_that_never_passes_is_censored_at_the_largest_intensity() {
        let c = capacity(0.2, 0.05, (1.0, 0.001), 0.01, 10.0, |s| 0.001 * s.sqrt());
        assert!(c.censored);
        assert_eq!(c.capacity, 10.0);
    }

    #[test]
    fn a_resurrection_keeps_the_first_passage_and_says_so() {
        // Passes on (1, 1.5), falls back on [1.5, 3), passes again from 3; started at 2.
        let a = |s: f64| {
            if (1.0..1.5).contains(&s) || s >= 3.0 {
                0.06
            } else {
                0.04
            }
        };
        let c = capacity(1.0, 0.05, (2.0, a(2.0)), 0.01, 10.0, a);
        // The search starts above the dip: it finds the passage at 3, not the one at 1, unless
        // it tried below; either way the capacity is a passage and is flagged when it saw a
        // gain above a passing one that did not pass.
        let at_3 = (c.capacity / 3.0 - 1.0).abs() <= 0.01;
        let at_1 = (c.capacity - 1.0).abs() <= 0.01;
        assert!(at_1 || at_3, "{c:?}");
        if at_1 {
            assert!(c.resurrected, "{c:?}");
        }
        // Started inside the first passing band: it finds the passage at 1 and, having tried a
        // gain in the dip above it, flags the resurrection.
        let c = capacity(1.0, 0.05, (1.2, a(1.2)), 0.01, 10.0, a);
        assert!((c.capacity - 1.0).abs() <= 0.01, "{c:?}");
    }

    #[test]
    fn a_failed_run_ends_the_search() {
        let c = capacity(1.0, 0.05, (1.0, 0.01), 0.01, 10.0, |_| f64::NAN);
        assert!(c.capacity.is_nan() && c.runs == 2);
    }
}
