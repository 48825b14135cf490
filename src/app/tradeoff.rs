//! `impactsweep tradeoff`: what each solver setting costs and how wrong it is (issue 5).
//!
//! On a reference set of runs (a study's design points, ideal case; by default the paper's
//! Table I system for `e = 0.45, 0.46, ..., 0.95`), every solver runs over a ladder of its
//! accuracy knob:
//!
//! | solver | knob | ladder |
//! |---|---|---|
//! | `exact` | `tol` | `1e-4, 1e-6, ..., 1e-12` |
//! | `rk4` | `h` | `T/50, T/100, ..., T/6400` (`T` the undamped period) |
//! | `dopri5` | `rtol` | `1e-3, 1e-4, ..., 1e-11`, with `atol = rtol * A` (`A = |x0| + |v0| / omega`, the amplitude scale) |
//!
//! For each setting: the median wall time per run (single thread; every setting first runs the
//! set once untimed, then rounds time each setting once over the whole set, interleaved so that
//! load from other processes falls on all alike, at least seven rounds and six seconds; the
//! median over the rounds, divided by the number of runs; both wall time and the thread's CPU
//! time are kept, and CPU time ranks and charts the settings since on a shared machine wall time
//! also counts the time other processes held the core), and the error against `exact` at `tol = 1e-14`
//! (its tightest): max and median relative error in `xmax`, `t1`, `DI` and the impact count, and
//! how many runs changed outcome or impact count. Runs whose outcome differs from the reference
//! are counted, not averaged (their observables may be NaN).
//!
//! The result is printed, written to `OUT/tradeoff.parquet` (via [`crate::store_tradeoff`]),
//! `OUT/tradeoff.md` and a log-log chart `OUT/tradeoff.svg`/`.png` (via
//! [`crate::report::tradeoff_chart`]). The SciPy peer (`scripts/peer_scipy.py`) joins the table and
//! chart when its JSON is found (`--peer FILE`, or `OUT/peer_scipy.json`).
//!
//! [`quote`] gives the `plan` command the measured cost and error of one setting.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;

use crate::model::System;
use crate::sim::{self, NoProbe, Outcome, Record, Request, SolverKind, SolverSettings};

/// `impactsweep tradeoff [STUDY.toml] [--out DIR]`.
#[derive(Clone, Debug, Default)]
pub struct TradeoffArgs {
    pub study: Option<PathBuf>,
    pub out: PathBuf,
    pub quick: bool,
    /// The SciPy peer's JSON (default: `OUT/peer_scipy.json` when present).
    pub peer: Option<PathBuf>,
}

/// DI error under which a setting is "good enough" (0.1 %).
pub const DI_GOAL: f64 = 1e-3;

/// Tightest `exact` tolerance: the reference.
pub const REFERENCE_TOL: f64 = 1e-14;

/// At most this many reference runs from a study (evenly spaced design points).
pub const MAX_STUDY_POINTS: usize = 64;

/// The reference set: systems run with one request.
#[derive(Clone, Debug)]
pub struct Reference {
    /// What the set is, for the table's heading.
    pub label: String,
    pub systems: Vec<System>,
    pub request: Request,
    /// Settings other than the knobs (caps, chatter tolerance), shared by every setting.
    pub base: SolverSettings,
}

impl Reference {
    /// The paper's Table I system for `e = 0.45 + 0.01 i`, `i = 0..=50` (computed from the index).
    pub fn paper() -> Reference {
        Reference::paper_step(1)
    }

    /// The paper set, every `stride`-th `e` of it.
    pub fn paper_step(stride: usize) -> Reference {
        let systems = (0..=50)
            .step_by(stride.max(1))
            .map(|i| System {
                e: 0.45 + 0.01 * i as f64,
                ..System::TABLE_I
            })
            .collect();
        Reference {
            label: "Table I system, e = 0.45..0.95".into(),
            systems,
            request: Request::default(),
            base: SolverSettings::default(),
        }
    }

    /// A study's design points (ideal case), at most [`MAX_STUDY_POINTS`] of them evenly spaced.
    pub fn study(study: &crate::study::Study) -> Reference {
        let plan = crate::plan::Plan::new(study);
        let n = plan.n_points();
        let take = (n as usize).min(MAX_STUDY_POINTS) as u64;
        let systems = (0..take)
            .map(|i| {
                let p = if take <= 1 {
                    0
                } else {
                    i * (n - 1) / (take - 1)
                };
                plan.point_system(p)
            })
            .collect();
        Reference {
            label: format!("study {}: {take} of {n} design points", study.name),
            systems,
            request: Request {
                trace_dt: None,
                ..study.request
            },
            base: study.solver,
        }
    }

    /// Median undamped period of the set (s).
    pub fn period(&self) -> f64 {
        median(self.systems.iter().map(|s| s.period()).collect())
    }

    /// Median amplitude scale `|x0| + |v0| / omega` of the set (m).
    pub fn amplitude(&self) -> f64 {
        median(
            self.systems
                .iter()
                .map(|s| s.x0.abs() + s.v0.abs() / s.omega())
                .collect(),
        )
    }

    /// Runs every system with `settings`.
    pub fn run(&self, settings: &SolverSettings) -> Vec<Record> {
        self.systems
            .iter()
            .map(|s| sim::simulate(s, settings, &self.request, None, &mut NoProbe))
            .collect()
    }

    /// The reference records: `exact` at its tightest tolerance.
    pub fn truth(&self) -> Vec<Record> {
        self.run(&SolverSettings {
            kind: SolverKind::Exact,
            tol: REFERENCE_TOL,
            ..self.base
        })
    }
}

/// The knob ladder of every solver (`quick`: a shorter one).
pub fn ladder(reference: &Reference, quick: bool) -> Vec<(SolverSettings, String)> {
    let base = reference.base;
    let period = reference.period();
    let amp = reference.amplitude();
    let mut out = Vec::new();
    let tols: &[i32] = if quick {
        &[4, 8, 12]
    } else {
        &[4, 6, 8, 10, 12]
    };
    for &k in tols {
        let tol = 10f64.powi(-k);
        out.push((
            SolverSettings {
                kind: SolverKind::Exact,
                tol,
                ..base
            },
            format!("tol = 1e-{k}"),
        ));
    }
    let divs: &[u32] = if quick {
        &[50, 200, 800, 3200]
    } else {
        &[50, 100, 200, 400, 800, 1600, 3200, 6400]
    };
    for &n in divs {
        out.push((
            SolverSettings {
                kind: SolverKind::Rk4,
                h: period / f64::from(n),
                ..base
            },
            format!("h = T/{n}"),
        ));
    }
    let rtols: &[i32] = if quick {
        &[3, 6, 9]
    } else {
        &[3, 4, 5, 6, 7, 8, 9, 10, 11]
    };
    for &k in rtols {
        let rtol = 10f64.powi(-k);
        out.push((
            SolverSettings {
                kind: SolverKind::Dopri5,
                rtol,
                atol: rtol * amp,
                ..base
            },
            format!("rtol = 1e-{k}"),
        ));
    }
    out
}

/// Max and median of a set of relative errors (NaN when the set is empty).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrStat {
    pub max: f64,
    pub median: f64,
}

impl ErrStat {
    fn of(mut v: Vec<f64>) -> ErrStat {
        if v.is_empty() {
            return ErrStat {
                max: f64::NAN,
                median: f64::NAN,
            };
        }
        v.sort_by(f64::total_cmp);
        ErrStat {
            max: v[v.len() - 1],
            median: median_sorted(&v),
        }
    }
}

/// One row of the table: a solver at one knob setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// `exact`, `rk4`, `dopri5`, or a peer (`scipy-RK45`, `scipy-DOP853`).
    pub solver: String,
    /// The knob as a person reads it (`h = T/400`).
    pub setting: String,
    /// Knob name and value (`tol`, `h` in s, `rtol`).
    pub knob: String,
    pub value: f64,
    /// `dopri5`'s (and the peer's) absolute tolerance, NaN otherwise.
    pub atol: f64,
    /// Median wall time per run (s).
    pub time_per_run: f64,
    /// Median CPU time of the timing thread per run (s): what ranks and charts the settings,
    /// because on a shared machine it does not count the time other processes held the core.
    pub cpu_per_run: f64,
    /// Timed repetitions of the whole set.
    pub reps: u32,
    /// Mean solver steps per run (NaN for the peer).
    pub steps_per_run: f64,
    pub xmax: ErrStat,
    pub t1: ErrStat,
    pub di: ErrStat,
    pub impacts: ErrStat,
    /// Runs whose outcome differs from the reference's.
    pub changed_outcome: u64,
    /// Runs whose impact count differs from the reference's.
    pub changed_impacts: u64,
    /// Runs the solver could not finish (the peer's chatter guard).
    pub unfinished: u64,
    pub runs: u64,
    /// The cheapest setting of its solver with max DI error under [`DI_GOAL`].
    pub cheapest: bool,
}

impl Row {
    /// Meets the DI goal with no changed outcome.
    pub fn meets_goal(&self) -> bool {
        self.changed_outcome == 0 && self.di.max < DI_GOAL
    }
}

/// Observables of one run, as compared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observed {
    pub ok: bool,
    pub finished: bool,
    pub xmax: f64,
    pub t1: f64,
    pub di: f64,
    pub impacts: u64,
}

impl From<&Record> for Observed {
    fn from(r: &Record) -> Self {
        Observed {
            ok: r.outcome == Outcome::Ok,
            finished: true,
            xmax: r.xmax,
            t1: r.t1,
            di: r.di,
            impacts: r.impacts,
        }
    }
}

/// Error statistics of `got` against `truth`, run by run.
pub fn compare(
    truth: &[Record],
    got: &[Observed],
) -> (ErrStat, ErrStat, ErrStat, ErrStat, u64, u64, u64) {
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    let (mut ex, mut et, mut ed, mut ei) = (vec![], vec![], vec![], vec![]);
    let (mut changed_outcome, mut changed_impacts, mut unfinished) = (0, 0, 0);
    for (r, g) in truth.iter().zip(got) {
        if !g.finished {
            unfinished += 1;
        }
        let ref_ok = r.outcome == Outcome::Ok;
        if ref_ok != g.ok || !g.finished {
            changed_outcome += 1;
            if !g.finished {
                continue;
            }
        }
        if r.impacts != g.impacts {
            changed_impacts += 1;
        }
        ei.push(rel(g.impacts as f64, r.impacts.max(1) as f64));
        if ref_ok && g.ok {
            ex.push(rel(g.xmax, r.xmax));
            et.push(rel(g.t1, r.t1));
            ed.push(rel(g.di, r.di));
        }
    }
    (
        ErrStat::of(ex),
        ErrStat::of(et),
        ErrStat::of(ed),
        ErrStat::of(ei),
        changed_outcome,
        changed_impacts,
        unfinished,
    )
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
}

/// Measures every setting against the reference records. Each setting runs once untimed (its
/// records, and the warm-up); then rounds time every setting once each, interleaved, so that
/// load from other processes falls on all settings alike; the time per run of a setting is the
/// median over the rounds.
pub fn measure_all(
    reference: &Reference,
    truth: &[Record],
    settings: &[(SolverSettings, String)],
    timing: Timing,
) -> Vec<Row> {
    let mut rows: Vec<Row> = settings
        .iter()
        .map(|(s, label)| row_of(reference, truth, s, label, &reference.run(s)))
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
        row.time_per_run = median(t.iter().map(|p| p.0).collect());
        row.cpu_per_run = median(t.iter().map(|p| p.1).collect());
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

/// The row of one setting from its records (time not yet measured).
fn row_of(
    reference: &Reference,
    truth: &[Record],
    settings: &SolverSettings,
    setting: &str,
    records: &[Record],
) -> Row {
    let _ = reference;
    let got: Vec<Observed> = records.iter().map(Observed::from).collect();
    let (xmax, t1, di, impacts, changed_outcome, changed_impacts, unfinished) =
        compare(truth, &got);
    let steps = records.iter().map(|r| r.steps as f64).sum::<f64>() / records.len().max(1) as f64;
    Row {
        solver: settings.kind.name().into(),
        setting: setting.into(),
        knob: settings.kind.knob().into(),
        value: settings.knob_value(),
        atol: if settings.kind == SolverKind::Dopri5 {
            settings.atol
        } else {
            f64::NAN
        },
        time_per_run: f64::NAN,
        cpu_per_run: f64::NAN,
        reps: 0,
        steps_per_run: steps,
        xmax,
        t1,
        di,
        impacts,
        changed_outcome,
        changed_impacts,
        unfinished,
        runs: truth.len() as u64,
        cheapest: false,
    }
}

/// Marks, per solver, the cheapest row meeting [`DI_GOAL`].
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
    let timing = Timing {
        min_reps: 5,
        min_seconds: 0.02,
        max_reps: 50,
    };
    let row = measure(reference, &truth, settings, "", timing);
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

/// The SciPy peer's JSON (`scripts/peer_scipy.py --json`).
#[derive(Clone, Debug, serde::Deserialize)]
pub struct PeerFile {
    pub tool: String,
    #[serde(default)]
    pub version: String,
    pub methods: Vec<PeerMethod>,
}

#[derive(Clone, Debug, serde::Deserialize)]
pub struct PeerMethod {
    pub method: String,
    pub rtol: f64,
    pub atol: f64,
    pub time_per_run_s: f64,
    pub cpu_per_run_s: f64,
    pub reps: u32,
    pub runs: Vec<PeerRun>,
}

#[derive(Clone, Debug, serde::Deserialize)]
pub struct PeerRun {
    pub e: f64,
    /// `ok`, `no_second_peak`, or `chatter` (the guard stopped it).
    pub outcome: String,
    pub xmax: Option<f64>,
    pub t1: Option<f64>,
    pub di: Option<f64>,
    pub impacts: u64,
}

/// Peer rows, when the peer ran the same reference set (matched by `e`).
pub fn peer_rows(peer: &PeerFile, reference: &Reference, truth: &[Record]) -> Vec<Row> {
    let mut rows = Vec::new();
    for m in &peer.methods {
        let mut got = Vec::with_capacity(truth.len());
        for sys in &reference.systems {
            let Some(run) = m.runs.iter().find(|r| (r.e - sys.e).abs() < 1e-9) else {
                return Vec::new();
            };
            let nan = |v: Option<f64>| v.unwrap_or(f64::NAN);
            got.push(Observed {
                ok: run.outcome == "ok",
                finished: run.outcome != "chatter",
                xmax: nan(run.xmax),
                t1: nan(run.t1),
                di: nan(run.di),
                impacts: run.impacts,
            });
        }
        let (xmax, t1, di, impacts, changed_outcome, changed_impacts, unfinished) =
            compare(truth, &got);
        rows.push(Row {
            solver: format!("{}-{}", peer.tool, m.method),
            setting: format!("rtol = {:e}", m.rtol),
            knob: "rtol".into(),
            value: m.rtol,
            atol: m.atol,
            time_per_run: m.time_per_run_s,
            cpu_per_run: m.cpu_per_run_s,
            reps: m.reps,
            steps_per_run: f64::NAN,
            xmax,
            t1,
            di,
            impacts,
            changed_outcome,
            changed_impacts,
            unfinished,
            runs: truth.len() as u64,
            cheapest: false,
        });
    }
    rows
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    median_sorted(&v)
}

fn median_sorted(v: &[f64]) -> f64 {
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
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

/// The table as markdown.
pub fn table(reference: &Reference, rows: &[Row]) -> String {
    let mut out = format!(
        "Reference: {} ({} runs), against exact at tol = {REFERENCE_TOL:e}. Errors are relative; \
         max / median over the runs. Times are medians per run over interleaved rounds, single \
         thread; settings are ranked by CPU time.\n\n",
        reference.label,
        reference.systems.len()
    );
    out.push_str("| solver | setting | CPU/run | wall/run | steps/run | xmax err | t1 err | DI err | impacts err | changed outcome | changed impacts | DI < 0.1 % |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let pair = |s: &ErrStat| format!("{} / {}", fmt_err(s.max), fmt_err(s.median));
        let steps = if r.steps_per_run.is_nan() {
            "-".to_string()
        } else {
            format!("{:.0}", r.steps_per_run)
        };
        let goal = if r.cheapest {
            "cheapest"
        } else if r.meets_goal() {
            "yes"
        } else {
            "no"
        };
        let changed = if r.unfinished > 0 {
            format!("{} ({} unfinished)", r.changed_outcome, r.unfinished)
        } else {
            r.changed_outcome.to_string()
        };
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.solver,
            r.setting,
            fmt_time(r.cpu_per_run),
            fmt_time(r.time_per_run),
            steps,
            pair(&r.xmax),
            pair(&r.t1),
            pair(&r.di),
            pair(&r.impacts),
            changed,
            r.changed_impacts,
            goal
        ));
    }
    out.push('\n');
    for r in rows.iter().filter(|r| r.cheapest) {
        out.push_str(&format!(
            "Cheapest {} with DI error under 0.1 %: {} ({} CPU per run, max DI error {}).\n",
            r.solver,
            r.setting,
            fmt_time(r.cpu_per_run),
            fmt_err(r.di.max)
        ));
    }
    let mut solvers: Vec<&str> = rows.iter().map(|r| r.solver.as_str()).collect();
    solvers.dedup();
    for s in solvers {
        if !rows.iter().any(|r| r.solver == s && r.cheapest) {
            out.push_str(&format!(
                "No {s} setting measured keeps the DI error under 0.1 % on every run.\n"
            ));
        }
    }
    out
}

/// One chart series per solver: (time per run, max DI error) along its ladder.
pub fn chart_series(rows: &[Row]) -> Vec<crate::report::tradeoff_chart::Series> {
    let mut out: Vec<crate::report::tradeoff_chart::Series> = Vec::new();
    for r in rows {
        let point = (r.cpu_per_run, r.di.max);
        let peer = !SolverKind::ALL.iter().any(|k| k.name() == r.solver);
        let name = if peer && r.unfinished > 0 {
            format!(
                "{} {} ({} of {} runs unfinished: chatter)",
                r.solver, r.setting, r.unfinished, r.runs
            )
        } else if peer {
            format!("{} {}", r.solver, r.setting)
        } else {
            r.solver.clone()
        };
        match out.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push(point),
            None => out.push(crate::report::tradeoff_chart::Series {
                name,
                points: vec![point],
                peer,
            }),
        }
    }
    out
}

fn load_peer(path: &Path) -> anyhow::Result<PeerFile> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))
}

/// The `tradeoff` command.
pub fn tradeoff(args: &TradeoffArgs) -> anyhow::Result<()> {
    let reference = match &args.study {
        Some(path) => Reference::study(&crate::study::Study::load(path)?),
        None => Reference::paper(),
    };
    let timing = if args.quick {
        Timing::QUICK
    } else {
        Timing::FULL
    };
    let started = Instant::now();
    let truth = reference.truth();
    let mut rows = measure_all(&reference, &truth, &ladder(&reference, args.quick), timing);
    let peer_path = args
        .peer
        .clone()
        .or_else(|| Some(args.out.join("peer_scipy.json")).filter(|p| p.exists()));
    if let Some(path) = &peer_path {
        let peer = load_peer(path)?;
        let extra = peer_rows(&peer, &reference, &truth);
        if extra.is_empty() {
            eprintln!(
                "note: {} does not cover this reference set; the peer is left out",
                path.display()
            );
        }
        rows.extend(extra);
    }
    mark_cheapest(&mut rows);
    let text = table(&reference, &rows);
    print!("{text}");
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let md = args.out.join("tradeoff.md");
    std::fs::write(&md, &text).with_context(|| format!("writing {}", md.display()))?;
    crate::store_tradeoff::write(&args.out.join("tradeoff.parquet"), &rows)?;
    crate::report::tradeoff_chart::draw(
        &chart_series(&rows),
        DI_GOAL,
        (
            "median CPU time per run (s)",
            "max relative error in DI over the runs",
        ),
        &args.out.join("tradeoff"),
    )?;
    println!(
        "wrote {}/tradeoff.{{parquet,md,svg,png}} in {:.1} s",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_reference_has_51_runs_from_the_index() {
        let r = Reference::paper();
        assert_eq!(r.systems.len(), 51);
        assert_eq!(r.systems[0].e, 0.45);
        assert_eq!(r.systems[50].e, 0.45 + 0.01 * 50.0);
        assert_eq!(Reference::paper_step(5).systems.len(), 11);
    }

    #[test]
    fn compare_counts_changes_and_skips_failed_runs() {
        let truth = Reference::paper_step(25).truth();
        assert_eq!(truth.len(), 3);
        let mut got: Vec<Observed> = truth.iter().map(Observed::from).collect();
        got[0].xmax *= 1.01;
        got[1].impacts += 1;
        got[2].finished = false;
        let (x, _, d, i, co, ci, un) = compare(&truth, &got);
        assert!((x.max - 0.01).abs() < 1e-12, "{x:?}");
        assert_eq!(d.max, 0.0);
        assert!(i.max > 0.0);
        assert_eq!((co, ci, un), (1, 1, 1));
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
