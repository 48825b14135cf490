//! The timing harness and the rows of the trade-off table: what a solver setting costs (median
//! time per run) and how wrong it is (against the reference).
//!
//! Every setting first runs the set once untimed (its records, and the warm-up); then rounds
//! time every setting once each over the whole set, interleaved so that load from other
//! processes falls on all settings alike, until [`Timing`] is satisfied; the time per run of a
//! setting is the median over the rounds, divided by the number of runs. Both wall time and the
//! thread's CPU time are kept; CPU time ranks and charts the settings, since on a shared machine
//! wall time also counts the time other processes held the core.

use std::time::Instant;

use super::errors::{Comparison, Observed, compare};
use super::reference::Reference;
use crate::numeric::median;
use crate::sim::{self, NoProbe, Record, SolverKind, SolverSettings};

pub use crate::store::tradeoff::Row;

impl Row {
    /// Meets the DI goal with no changed outcome.
    pub fn meets_goal(&self) -> bool {
        self.changed_outcome == 0 && self.di.max < super::DI_GOAL
    }

    /// A row from what a comparison found, time not yet measured (NaN, `reps` 0).
    pub fn new(solver: String, setting: String, knob: &str, value: f64, c: &Comparison) -> Row {
        Row {
            solver,
            setting,
            knob: knob.into(),
            value,
            atol: f64::NAN,
            time_per_run: f64::NAN,
            cpu_per_run: f64::NAN,
            reps: 0,
            steps_per_run: f64::NAN,
            xmax: c.xmax,
            t1: c.t1,
            di: c.di,
            impacts: c.impacts,
            changed_outcome: c.changed_outcome,
            changed_impacts: c.changed_impacts,
            unfinished: c.unfinished,
            runs: c.runs,
            cheapest: false,
        }
    }

    /// The row of one setting from its records (time not yet measured).
    pub fn of_records(
        truth: &[Record],
        settings: &SolverSettings,
        setting: &str,
        records: &[Record],
    ) -> Row {
        let got: Vec<Observed> = records.iter().map(Observed::from).collect();
        let mut row = Row::new(
            settings.kind.name().into(),
            setting.into(),
            settings.kind.knob(),
            settings.knob_value(),
            &compare(truth, &got),
        );
        if settings.kind == SolverKind::Dopri5 {
            row.atol = settings.atol;
        }
        row.steps_per_run =
            records.iter().map(|r| r.steps as f64).sum::<f64>() / records.len().max(1) as f64;
        row
    }
}

/// CPU time of the calling thread (s); wall time where the platform has no thread clock.
fn thread_cpu(wall0: Instant) -> f64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec through a valid pointer.
        if unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) } == 0 {
            return ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9;
        }
    }
    wall0.elapsed().as_secs_f64()
}

/// One timed pass over the whole set: (wall, thread CPU) seconds per run.
fn time_pass(reference: &Reference, settings: &SolverSettings) -> (f64, f64) {
    let origin = Instant::now();
    let c0 = thread_cpu(origin);
    let t0 = Instant::now();
    for s in &reference.systems {
        std::hint::black_box(sim::simulate(
            std::hint::black_box(s),
            settings,
            &reference.request,
            None,
            &mut NoProbe,
        ));
    }
    let wall = t0.elapsed().as_secs_f64();
    let cpu = thread_cpu(origin) - c0;
    let n = reference.systems.len().max(1) as f64;
    (wall / n, cpu / n)
}

/// How long to time.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    /// At least this many timed passes of the whole set per setting.
    pub min_reps: u32,
    /// Keep adding rounds until this much wall time has passed (s).
    pub min_seconds: f64,
    /// At most this many rounds.
    pub max_reps: u32,
}

impl Timing {
    /// The default run: at least 7 rounds and 6 s.
    pub const FULL: Timing = Timing {
        min_reps: 7,
        min_seconds: 6.0,
        max_reps: 200,
    };
    /// `--quick`: at least 5 rounds and 0.5 s.
    pub const QUICK: Timing = Timing {
        min_reps: 5,
        min_seconds: 0.5,
        max_reps: 50,
    };
    /// `plan`'s quote: at least 5 rounds and 20 ms.
    pub const QUOTE: Timing = Timing {
        min_reps: 5,
        min_seconds: 0.02,
        max_reps: 50,
    };
}

/// Measures every setting against the reference records (see the module doc).
pub fn measure_all(
    reference: &Reference,
    truth: &[Record],
    settings: &[(SolverSettings, String)],
    timing: Timing,
) -> Vec<Row> {
    let mut rows: Vec<Row> = settings
        .iter()
        .map(|(s, label)| Row::of_records(truth, s, label, &reference.run(s)))
        .collect();
    let mut times: Vec<Vec<(f64, f64)>> = vec![Vec::new(); settings.len()];
    let start = Instant::now();
    let mut rounds = 0;
    while rounds < timing.max_reps
        && (rounds < timing.min_reps || start.elapsed().as_secs_f64() < timing.min_seconds)
    {
        for (k, (s, _)) in settings.iter().enumerate() {
            times[k].push(time_pass(reference, s));
        }
        rounds += 1;
    }
    for (row, t) in rows.iter_mut().zip(times) {
        row.reps = t.len() as u32;
        let wall: Vec<f64> = t.iter().map(|p| p.0).collect();
        let cpu: Vec<f64> = t.iter().map(|p| p.1).collect();
        row.time_per_run = median(&wall);
        row.cpu_per_run = median(&cpu);
    }
    rows
}

/// Measures one setting (see [`measure_all`]).
pub fn measure(
    reference: &Reference,
    truth: &[Record],
    settings: &SolverSettings,
    setting: &str,
    timing: Timing,
) -> Row {
    measure_all(
        reference,
        truth,
        &[(*settings, setting.to_string())],
        timing,
    )
    .remove(0)
}

/// Marks, per solver, the cheapest row (by CPU time) meeting [`super::DI_GOAL`].
pub fn mark_cheapest(rows: &mut [Row]) {
    let mut names: Vec<String> = rows.iter().map(|r| r.solver.clone()).collect();
    names.dedup();
    for name in names {
        let best = rows
            .iter()
            .enumerate()
            .filter(|(_, r)| r.solver == name && r.meets_goal())
            .min_by(|a, b| a.1.cpu_per_run.total_cmp(&b.1.cpu_per_run))
            .map(|(i, _)| i);
        if let Some(i) = best {
            rows[i].cheapest = true;
        }
    }
}

/// The measured cost and error of one setting (for `plan`).
#[derive(Clone, Debug, PartialEq)]
pub struct Quote {
    /// Median wall time per run on this machine (s).
    pub time_per_run: f64,
    /// Median CPU time per run (s).
    pub cpu_per_run: f64,
    /// Max relative errors against `exact` at `tol = 1e-14`.
    pub xmax_err: f64,
    pub t1_err: f64,
    pub di_err: f64,
    /// Runs (of `runs`) whose outcome or impact count changed.
    pub changed_outcome: u64,
    pub changed_impacts: u64,
    pub runs: u64,
}

impl std::fmt::Display for Quote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} CPU per run; max relative error xmax {}, t1 {}, DI {}; {} of {} runs changed outcome, {} impact count",
            fmt_time(self.cpu_per_run),
            fmt_err(self.xmax_err),
            fmt_err(self.t1_err),
            fmt_err(self.di_err),
            self.changed_outcome,
            self.runs,
            self.changed_impacts
        )
    }
}

/// A quick live measurement of `settings` on the paper set (every fifth `e`, 11 runs), for
/// `plan` to quote what the study's chosen solver setting costs and how wrong it is.
/// Takes a few milliseconds for any setting in the tradeoff ladder.
pub fn quote(settings: &SolverSettings) -> Quote {
    let reference = Reference {
        base: *settings,
        ..Reference::paper_step(5)
    };
    quote_on(&reference, settings)
}

/// [`quote`] on any reference set (for instance [`Reference::study`]).
pub fn quote_on(reference: &Reference, settings: &SolverSettings) -> Quote {
    let truth = reference.truth();
    let row = measure(reference, &truth, settings, "", Timing::QUOTE);
    Quote {
        time_per_run: row.time_per_run,
        cpu_per_run: row.cpu_per_run,
        xmax_err: row.xmax.max,
        t1_err: row.t1.max,
        di_err: row.di.max,
        changed_outcome: row.changed_outcome,
        changed_impacts: row.changed_impacts,
        runs: row.runs,
    }
}

/// A time in s, µs or ms.
pub fn fmt_time(t: f64) -> String {
    if !t.is_finite() {
        "-".into()
    } else if t < 1e-3 {
        format!("{:.2} µs", t * 1e6)
    } else if t < 1.0 {
        format!("{:.2} ms", t * 1e3)
    } else {
        format!("{t:.2} s")
    }
}

/// A relative error in scientific notation (`-` when not available).
pub fn fmt_err(e: f64) -> String {
    if e.is_nan() {
        "-".into()
    } else if e == 0.0 {
        "0".into()
    } else {
        format!("{e:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::super::errors::compare;
    use super::*;

    #[test]
    fn compare_counts_changes_and_skips_failed_runs() {
        let truth = Reference::paper_step(25).truth();
        assert_eq!(truth.len(), 3);
        let mut got: Vec<Observed> = truth.iter().map(Observed::from).collect();
        got[0].xmax *= 1.01;
        got[1].impacts += 1;
        got[2].finished = false;
        let c = compare(&truth, &got);
        assert!((c.xmax.max - 0.01).abs() < 1e-12, "{:?}", c.xmax);
        assert_eq!(c.di.max, 0.0);
        assert!(c.impacts.max > 0.0);
        assert_eq!(
            (c.changed_outcome, c.changed_impacts, c.unfinished),
            (1, 1, 1)
        );
    }

    #[test]
    fn cheapest_is_the_fastest_meeting_the_goal() {
        let truth = Reference::paper_step(25).truth();
        let reference = Reference::paper_step(25);
        let mut rows: Vec<Row> = [1e-4, 1e-8]
            .iter()
            .map(|&tol| {
                let s = SolverSettings {
                    tol,
                    ..SolverSettings::default()
                };
                measure(&reference, &truth, &s, "t", Timing::QUICK)
            })
            .collect();
        rows[0].cpu_per_run = 2.0;
        rows[1].cpu_per_run = 1.0;
        mark_cheapest(&mut rows);
        assert!(rows[1].cheapest && !rows[0].cheapest);
    }
}
