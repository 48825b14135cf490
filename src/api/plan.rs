//! The sizing of a study (`impactsweep plan STUDY.toml`, the Python binding's `plan`): its size, where its dataset would
//! go, and an estimate of run time and disk size.
//!
//! The time estimate comes from a short timed sample: up to [`SAMPLE_RUNS`] runs spread over
//! the plan by a golden-ratio sequence of run indices, out of step with its axes (same
//! systems, cases and noise as the real sweep), simulated on one thread;
//! the mean time per run is scaled by the total and divided by the threads a `run` would use,
//! but a harmonic study takes at least one curve's time: a curve is one task of the sweep. A
//! harmonic study with a census times its race of the design lives apart and counts it once a
//! curve ([`Sample::race_seconds`]), a perturbed case's curve at its race for the peak alone
//! ([`Sample::peak_seconds`]); with `life_curve = "whole"` the ideal curves' extra race
//! scales with their frequencies instead ([`Sample::whole_seconds`]).
//! It measures the binary it runs in, so a debug build predicts a debug build.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use crate::orbits::census::Kind;
use crate::orbits::curve;
use crate::orbits::race::{Serves, race};
use crate::orbits::several::{NO_RUN, UnitsRun, census_run_units, race_runs};
use crate::plan::Plan;
use crate::reduce::harmonic::verify::MOST;
use crate::reduce::random::design_study;
use crate::reduce::random::subset::{MAX_SUBSET_RUNS, SUBSET_BELOW};
use crate::report::text::{count, thousands};
use crate::sim::harmonic::LifeCurve;
use crate::sim::{self, Drive, Harmonic, NoProbe, Scene};
use crate::study::{CensusKind, Study, num as fmt_value};

/// Runs simulated by the timed sample.
pub const SAMPLE_RUNS: u64 = 200;

/// Runs simulated by the timed sample of a harmonic study of several units with a census:
/// each takes its census of several units (about 0.2 s of CPU a run on
/// configs/multi-unit.toml, up to 1 s with 8 units), so fewer than [`SAMPLE_RUNS`].
pub const UNITS_SAMPLE_RUNS: u64 = 16;

/// Rough Parquet size of one run (bytes). Measured: 88.4 bytes per run for a 200,000-run
/// noise-free e × m × d sweep (one case per point, 4 part files, 17.7 MB) written by the sweep
/// engine's store. Most of it is the 9 Float64 observables that change on every run
/// (`x1 t1 x2 t2 xmax di energy_impact energy_viscous t_stop`), whose mantissas barely compress;
/// ids, parameters and counts dictionary/RLE-encode to a few bytes. Rounded up to 90; an
/// estimate, not a promise (other grids compress differently).
pub const BYTES_PER_RUN: u64 = 90;

/// Rough Parquet size of one run of a harmonic study (bytes): the forced table's Float64
/// outputs (`amplitude impacts_per_period amplitude_linear attenuation energy_* t_stop`, and
/// `omega r` along the frequency axis). Measured: 69 bytes per run for a one-case 3 x 3 x 81
/// study (729 runs, one part file), 38 for `configs/frequency-response.toml` (five cases,
/// whose runs off the impact band are identical and compress); rounded up to 70.
pub const BYTES_PER_FORCED_RUN: u64 = 70;

/// Bytes of Parquet per run of a random or record study: eight Float64 observables that change
/// on every realization (`amplitude t_peak rms_x rms_acc first_passage_time energy_impact
/// t_stop` and the counts) beside ids and the design's values that compress to a few bytes;
/// an estimate like the others, not measured on a large study yet.
pub const BYTES_PER_RANDOM_RUN: u64 = 80;

/// Rough Parquet size of one row of a harmonic study's `attractors` table (bytes): one steady
/// state that a run's census found, 33 columns of which the section state, amplitudes, exponent
/// and life statistics are floats that barely compress. Measured: 89.1 bytes per row for
/// `configs/frequency-response.toml` with `life_max_periods = 2000` (8,009 rows, 713,758
/// bytes, one part file; 2.2 rows per run): its attractors take about twice its points.
/// Rounded up to 90.
pub const BYTES_PER_STEADY_STATE: u64 = 90;

/// A timed sample: runs simulated and seconds taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub runs: u64,
    pub seconds: f64,
    /// The steady states the sample's censuses found (the rows it would add to the
    /// `attractors` table; 0 without a census).
    pub steady_states: u64,
    /// The part of `seconds` the race of the design lives took ([`crate::orbits::race`]; 0
    /// without a census): a curve's race, whose chains run on every thread, and whose cost
    /// follows the curve's peak (its leader grows to `life_max_periods`), not its frequencies.
    pub race_seconds: f64,
    /// The periods that race measured.
    pub race_periods: u64,
    /// A perturbed case's curve's race, which serves its peak alone ([`Serves::Peak`]), timed
    /// on the same censuses as `race_seconds` (not part of `seconds`); 0 without perturbed
    /// cases or a census, when each curve counts at `race_seconds`.
    pub peak_seconds: f64,
    /// With `life_curve = "whole"`: the same sample's race with the whole curve measured (step 5
    /// of [`crate::orbits::race`]), whose cost beyond `race_seconds` follows the frequencies; 0
    /// otherwise.
    pub whole_seconds: f64,
}

/// Frequencies of the middle design's ideal curve that the timed sample of a harmonic study
/// with a census runs ([`time_sample`]).
pub const SAMPLE_FREQUENCIES: u64 = 9;

/// Simulates up to [`SAMPLE_RUNS`] runs spread evenly over the plan, on this thread. A
/// harmonic study with a census instead runs up to [`SAMPLE_FREQUENCIES`] frequencies, evenly
/// spread, of its middle design's ideal curve as the sweep runs a curve (from rest, the census
/// up and down, the race of the design life): there the runs from rest are a few percent of
/// the cost (on configs/frequency-response.toml a sample of them alone predicted 3.0 s for a
/// 109 s sweep). Its frequencies lie further apart than the curve's, so each census inherits
/// less from its neighbour: rather an overestimate. A harmonic study of several units runs up
/// to [`UNITS_SAMPLE_RUNS`] runs evenly spread, each with its census of several units, as the
/// sweep runs them.
pub fn time_sample(study: &Study) -> Sample {
    let plan = Plan::new(study);
    if study.census() {
        return time_curve(study, &plan);
    }
    let units = study.census_kind() == CensusKind::Units;
    let total = plan.n_runs();
    let n = total.min(if units {
        UNITS_SAMPLE_RUNS
    } else {
        SAMPLE_RUNS
    });
    let n_cases = plan.n_cases();
    let start = Instant::now();
    let mut steady_states = 0u64;
    for j in 0..n {
        let r = sample_index(j, n, total);
        let run = plan.run(r / n_cases, (r % n_cases) as u32);
        if units {
            // The run as the sweep runs it, with its census of several units (its race is
            // timed on a curve below).
            let out = census_run_units(
                &run.system,
                &study.solver,
                &study.request,
                &run.scene.harmonic_or_default(),
                None,
                &mut NoProbe,
                study.seed,
                run.point,
            );
            steady_states += out.rows(NO_RUN).len() as u64;
            continue;
        }
        let mut stream = plan.noise_stream(&run);
        let noise = match (&study.noise, stream.as_mut()) {
            (Some(ns), Some(s)) => Some((ns, s)),
            _ => None,
        };
        let rec = sim::simulate_scene(
            &run.system,
            &study.solver,
            &study.request,
            &run.scene,
            noise,
            &mut NoProbe,
        );
        std::hint::black_box(rec);
    }
    let seconds = start.elapsed().as_secs_f64();
    let (race_seconds, race_periods, whole_seconds) = if units {
        time_units_race(study, &plan)
    } else {
        (0.0, 0, 0.0)
    };
    Sample {
        runs: n,
        seconds: seconds + race_seconds,
        steady_states,
        race_seconds,
        race_periods,
        peak_seconds: 0.0,
        whole_seconds,
    }
}

/// The race of the design lives of a study of several units, timed on up to
/// [`SAMPLE_FREQUENCIES`] frequencies of its middle design's ideal curve as the sweep races a
/// curve ([`race_runs`], each frequency's census of several units run first, not timed): its
/// seconds, the periods it measured, and with `life_curve = "whole"` the seconds of the same
/// race with the whole curve measured (0 otherwise).
fn time_units_race(study: &Study, plan: &Plan) -> (f64, u64, f64) {
    let runs = sample_curve(study, plan);
    let scenes: Vec<Harmonic> = runs.iter().map(|r| r.scene.harmonic_or_default()).collect();
    let mut outs: Vec<UnitsRun> = runs
        .iter()
        .zip(&scenes)
        .map(|(run, h)| {
            census_run_units(
                &run.system,
                &study.solver,
                &study.request,
                h,
                None,
                &mut NoProbe,
                study.seed,
                run.point,
            )
        })
        .collect();
    let whole = scenes.iter().any(|h| h.life_curve == LifeCurve::Whole);
    let (seconds, whole_seconds) = time_races(&mut outs, whole, |outs, curve| {
        let scenes: Vec<Harmonic> = scenes.iter().map(|h| with_life_curve(h, curve)).collect();
        race_runs(outs, &scenes, Serves::Curve);
    });
    let periods = outs
        .iter()
        .filter_map(|o| o.census.as_ref())
        .flat_map(|c| &c.2.motions)
        .filter_map(|m| m.life.map(|l| l.measured))
        .sum();
    (seconds, periods, whole_seconds)
}

/// The sample's race timed as the study asks: with the whole curve first on a copy of `x`
/// (`race(copy, LifeCurve::Whole)`, when `whole`), then with the decisions alone on `x` itself,
/// which the sample keeps. The seconds of the decisions' race, and of the whole curve's (0
/// without it).
fn time_races<T: Clone>(x: &mut T, whole: bool, race: impl Fn(&mut T, LifeCurve)) -> (f64, f64) {
    let whole_seconds = if whole {
        let mut copy = x.clone();
        let start = Instant::now();
        race(&mut copy, LifeCurve::Whole);
        start.elapsed().as_secs_f64()
    } else {
        0.0
    };
    let start = Instant::now();
    race(x, LifeCurve::Decisions);
    (start.elapsed().as_secs_f64(), whole_seconds)
}

/// `h` with its `life_curve` set to `curve`.
fn with_life_curve(h: &Harmonic, curve: LifeCurve) -> Harmonic {
    Harmonic {
        life_curve: curve,
        ..*h
    }
}

/// The `j`-th of `n` run indices of the timed sample over `total` runs: all of them when
/// `n == total`, else the golden-ratio sequence `floor(frac(0.5 + j phi) total)`, spread evenly
/// and never in step with the plan's axes (an even stride of `total / n` runs falls on the same
/// frequency and case at every step whenever it is a multiple of a curve's runs: on
/// configs/multi-unit.toml every sampled run lay at r = 0.85, far from resonance).
fn sample_index(j: u64, n: u64, total: u64) -> u64 {
    if n >= total {
        return j;
    }
    const PHI: f64 = 0.618_033_988_749_894_9;
    let u = (0.5 + j as f64 * PHI).fract();
    ((u * total as f64) as u64).min(total - 1)
}

/// Up to [`SAMPLE_FREQUENCIES`] runs, evenly spread, of the middle design's ideal curve: the
/// curve a harmonic study's timed sample runs.
fn sample_curve(study: &Study, plan: &Plan) -> Vec<crate::plan::RunSpec> {
    let n_f = study.curve_points();
    let design = plan.n_points() / n_f / 2;
    let n = n_f.min(SAMPLE_FREQUENCIES);
    (0..n)
        .map(|j| {
            let i = if n > 1 { j * (n_f - 1) / (n - 1) } else { 0 };
            plan.run(design * n_f + i, 0)
        })
        .collect()
}

/// The timed sample of a harmonic study with a census ([`time_sample`]).
fn time_curve(study: &Study, plan: &Plan) -> Sample {
    let runs = sample_curve(study, plan);
    let freqs: Vec<_> = runs.iter().map(|run| plan.curve_frequency(run)).collect();
    let targets: Vec<_> = freqs.iter().map(|f| (f.scene, f.point)).collect();
    // `run_curve`'s steps, the race timed apart.
    let sys = &runs[0].system;
    let start = Instant::now();
    let records = curve::from_rest(
        sys,
        &study.solver,
        &study.request,
        study.noise.as_ref(),
        freqs,
    );
    let points = curve::curve_points(sys, &study.solver, study.seed, &targets, &records);
    let mut censuses = curve::census_passes(&points);
    let race_points = curve::race_points(&points, &targets);
    let whole = race_points
        .iter()
        .flatten()
        .any(|(_, h)| h.life_curve == LifeCurve::Whole);
    // A perturbed case's curve races for its peak alone: timed on a copy of the same censuses.
    let peak_seconds = if plan.n_cases() > 1 {
        let mut copy = censuses.clone();
        let start = Instant::now();
        race(&race_points, &mut copy, Serves::Peak);
        start.elapsed().as_secs_f64()
    } else {
        0.0
    };
    // The ideal case's race, every rule.
    let (race_seconds, whole_seconds) = time_races(&mut censuses, whole, |censuses, curve| {
        let points: Vec<_> = race_points
            .iter()
            .map(|p| p.clone().map(|(f, h)| (f, with_life_curve(&h, curve))))
            .collect();
        race(&points, censuses, Serves::Curve);
    });
    let seconds = start.elapsed().as_secs_f64() - whole_seconds - peak_seconds;
    let found = censuses.iter().flatten().flat_map(|c| &c.attractors);
    let steady_states = found.clone().count() as u64;
    let race_periods = found
        .filter_map(|a| match &a.kind {
            Kind::NonPeriodic(w) => w.life.map(|l| l.measured),
            Kind::Periodic(_) => None,
        })
        .sum();
    Sample {
        runs: runs.len() as u64,
        seconds,
        steady_states,
        race_seconds,
        race_periods,
        peak_seconds,
        whole_seconds,
    }
}

/// The plan as text.
pub fn describe(study: &Study, out: &Path, threads: usize, sample: Option<Sample>) -> String {
    let plan = Plan::new(study);
    let mut s = String::new();
    let w = &mut s;
    let _ = writeln!(
        w,
        "study:          {} ({})",
        study.name,
        study.path.display()
    );
    describe_axes(w, study);
    let n_cases = plan.n_cases();
    let noisy = study
        .cases
        .iter()
        .filter(|c| c.noise_seed.is_some())
        .count();
    let perturbed = study
        .cases
        .iter()
        .filter(|c| c.dm != 0.0 || c.dd != 0.0)
        .count();
    let _ = writeln!(w, "design points:  {}", plan.n_points());
    if let Some(r) = study.scene.random() {
        let what = if r.suite().is_empty() {
            "realizations (the same loads at every design point)"
        } else {
            "records of the suite, one per run (the same at every design point)"
        };
        let _ = writeln!(w, "cases/point:    {n_cases} {what}");
    } else {
        let _ = writeln!(
            w,
            "cases/point:    {n_cases} (1 ideal, {perturbed} perturbed, {noisy} with noise)"
        );
    }
    let _ = writeln!(w, "total runs:     {}", plan.n_runs());
    describe_noise(w, study);
    match &study.scene {
        Scene::Harmonic(h) => describe_harmonic(w, study, h),
        Scene::Random(r) => describe_random(w, r, |k| study.axis(k).is_some()),
        Scene::Free => describe_free(w, study),
    }
    describe_chunks(w, study, &plan);
    if let Some(warning) = tiny_parts(&plan) {
        let _ = writeln!(w, "warning:        {warning}");
    }
    let _ = writeln!(w, "output:         {}/", out.join(&study.name).display());
    if let Some(sm) = sample
        && sm.runs > 0
    {
        describe_time(w, study, &plan, threads, sm);
        describe_subset(w, study, sm.seconds / sm.runs as f64, threads);
    }
    describe_disk(w, study, &plan, sample);
    s
}

/// The swept axes, one line each with its range and number of values.
fn describe_axes(w: &mut String, study: &Study) {
    if study.axes.is_empty() {
        let _ = writeln!(w, "axes:           none (one design point)");
    }
    for (i, a) in study.axes.iter().enumerate() {
        let label = if i == 0 { "axes:" } else { "" };
        let n = a.values.len();
        let range = if n == 1 {
            fmt_value(a.values[0])
        } else {
            format!(
                "{} .. {}",
                fmt_value(a.values[0]),
                fmt_value(a.values[n - 1])
            )
        };
        let _ = writeln!(
            w,
            "{label:<16}{} = {range} ({})",
            a.key,
            count(n as u64, "value", "values")
        );
    }
}

/// The measurement noise, on (its power, sample time and deviation per sample) or off.
fn describe_noise(w: &mut String, study: &Study) {
    match &study.noise {
        Some(ns) => {
            let sd = (ns.power / ns.sample_time).sqrt();
            let _ = writeln!(
                w,
                "noise:          on: power {} m^2 s, sample time {} s (sd {:.3e} m per sample)",
                fmt_value(ns.power),
                fmt_value(ns.sample_time),
                sd
            );
        }
        None => {
            let _ = writeln!(w, "noise:          off");
        }
    }
}

/// How the runs are cut into chunks: realizations of a design point, or design points.
fn describe_chunks(w: &mut String, study: &Study, plan: &Plan) {
    if plan.blocks() > 1 {
        let _ = writeln!(
            w,
            "chunks:         {} of up to {} realizations ({} per design point, \
             [run].chunk_realizations)",
            plan.n_chunks(),
            plan.chunk_cases(),
            plan.blocks()
        );
    } else {
        let _ = writeln!(
            w,
            "chunks:         {} of up to {} design points",
            plan.n_chunks(),
            study.run.chunk_points
        );
    }
}

/// The time estimate from the timed sample `sm`: its time per run scaled by the runs over the
/// threads, and at least one curve's time for a harmonic study (a curve is one task). A harmonic
/// study with a census scales its census so, and its race (`sm.race_seconds`, on every thread)
/// by the curves: a curve's race grows its leader to `life_max_periods` however many
/// frequencies it has (on configs/frequency-response.toml scaling the whole sample by the
/// frequencies predicted 7 min for a 108 s run). The reduction's verification is estimated
/// apart, from the race's speed per period.
fn describe_time(w: &mut String, study: &Study, plan: &Plan, threads: usize, sm: Sample) {
    let threads = threads.max(1);
    let census = (sm.seconds - sm.race_seconds).max(0.0);
    let per_run = census / sm.runs as f64;
    let curve = study.curve_points();
    let harmonic = study.scene.harmonic().is_some();
    let curves = if harmonic && curve > 0 {
        plan.n_runs() / curve
    } else {
        0
    };
    // With the whole curve measured, each ideal curve (one a design) adds the sample's extra
    // race in proportion to its frequencies.
    let designs = plan.n_points() / curve.max(1);
    // The race's sample is up to SAMPLE_FREQUENCIES frequencies of one ideal curve.
    let sampled = curve.min(SAMPLE_FREQUENCIES);
    let whole_extra = if sm.whole_seconds > 0.0 && sampled > 0 {
        (sm.whole_seconds - sm.race_seconds).max(0.0) * curve as f64 / sampled as f64
    } else {
        0.0
    };
    // Each design's ideal curve races with every rule, a perturbed case's for its peak alone.
    let perturbed = curves.saturating_sub(designs);
    let peak = if sm.peak_seconds > 0.0 {
        sm.peak_seconds
    } else {
        sm.race_seconds
    };
    let mut total = per_run * plan.n_runs() as f64 / threads as f64
        + sm.race_seconds * (curves - perturbed) as f64
        + peak * perturbed as f64
        + whole_extra * designs as f64;
    // A harmonic study's curve (one design and case over its frequencies) is one task: the
    // run takes at least one curve's time, however many threads there are.
    let mut bound = String::new();
    if harmonic && curve > 1 {
        let one = per_run * curve as f64 + sm.race_seconds + whole_extra;
        if one > total {
            total = one;
            bound = format!(
                "; a curve is one task, so its {} at most {}",
                count(curves, "curve keeps", "curves keep"),
                count(curves, "thread busy", "threads busy")
            );
        }
    }
    let what = match study.census_kind() {
        CensusKind::OneUnit => {
            format!(
                "census {:.1} ms a frequency over a sample of {} of one design's curve, its race \
             of the design lives {} over {} periods, counted once a curve{}",
                per_run * 1e3,
                count(sm.runs, "frequency", "frequencies"),
                fmt_duration(sm.race_seconds),
                thousands(sm.race_periods),
                peak_words(sm.peak_seconds, perturbed)
            ) + &whole_words(whole_extra)
        }
        CensusKind::Units => {
            format!(
                "{:.1} ms a run with its census of several units over a sample of {}, the race of \
             the design lives {} over {} periods on a sample of one design's curve, counted once \
             a curve",
                per_run * 1e3,
                count(sm.runs, "run", "runs"),
                fmt_duration(sm.race_seconds),
                thousands(sm.race_periods)
            ) + &whole_words(whole_extra)
        }
        CensusKind::None => format!(
            "{:.1} us/run over a sample of {}",
            per_run * 1e6,
            count(sm.runs, "run", "runs")
        ),
    };
    let _ = writeln!(
        w,
        "time estimate:  {} on {threads} thread{} ({what}{bound})",
        fmt_duration(total),
        if threads == 1 { "" } else { "s" },
    );
    // Verified when two designs or more rank (a design is a curve's frequencies).
    if study.census() && sm.race_periods > 0 && study.ranking.verify_periods > 0 && designs > 1 {
        let per_case = sm.race_seconds / sm.race_periods as f64
            * study.ranking.verify_periods as f64
            * MOST as f64;
        let _ = writeln!(
            w,
            "verification:   `reduce` measures the motions that could carry a peak of the designs \
             that decide the ranking, at most {} a case over {} periods: up to about {} a case \
             of each such design at the race's speed",
            MOST,
            thousands(study.ranking.verify_periods),
            fmt_duration(per_case)
        );
    }
}

/// A random study's reduction by default estimates `p_f` by subset simulation for each design
/// whose realizations passed the threshold fewer than [`SUBSET_BELOW`] times (at the design
/// intensity): at most [`MAX_SUBSET_RUNS`] runs a design, which can outnumber the sweep's own.
/// Its bound in runs and in time at the sample's cost per run (`per_run`, s), on `threads`.
/// Nothing for a record suite (it draws no normals) or without a threshold.
fn describe_subset(w: &mut String, study: &Study, per_run: f64, threads: usize) {
    let Some(r) = study.scene.random() else {
        return;
    };
    if r.threshold.is_none() || !r.draws_normals() {
        return;
    }
    let designs: usize = design_study(study)
        .axes
        .iter()
        .map(|a| a.values.len())
        .product();
    let most = designs * MAX_SUBSET_RUNS;
    let _ = writeln!(
        w,
        "subset:         `reduce` estimates p_f by subset simulation for each design whose \
         realizations pass the threshold fewer than {SUBSET_BELOW} times at the design \
         intensity: up to {} runs a design, {} for {}, about {} on {} at the sample's cost \
         (`reduce --subset 0`: none)",
        thousands(MAX_SUBSET_RUNS as u64),
        count(most as u64, "run", "runs"),
        count(designs as u64, "design", "designs"),
        fmt_duration(most as f64 * per_run / threads.max(1) as f64),
        count(threads.max(1) as u64, "thread", "threads")
    );
}

/// The time estimate's words for a perturbed case's race (its peak alone), empty without one.
fn peak_words(peak: f64, perturbed: u64) -> String {
    if peak > 0.0 && perturbed > 0 {
        format!(
            " ({} when it serves a perturbed case's peak alone)",
            fmt_duration(peak)
        )
    } else {
        String::new()
    }
}

/// The time estimate's words for the whole curve's extra race (`life_curve = "whole"`), empty
/// without it.
fn whole_words(extra: f64) -> String {
    if extra > 0.0 {
        format!(
            "; the whole curve measured (`life_curve = \"whole\"`) adds {} a design's ideal curve",
            fmt_duration(extra)
        )
    } else {
        String::new()
    }
}

/// The disk estimate: the points at a rough size per run ([`BYTES_PER_RUN`],
/// [`BYTES_PER_FORCED_RUN`]) and per part file ([`PART_OVERHEAD_BYTES`], one per chunk); a
/// harmonic study with a census adds its `attractors` table (a part file per chunk too), at
/// [`BYTES_PER_STEADY_STATE`] per steady state and as many per run as the timed sample's
/// censuses found.
fn describe_disk(w: &mut String, study: &Study, plan: &Plan, sample: Option<Sample>) {
    let runs = plan.n_runs();
    let parts = plan.n_chunks().saturating_mul(PART_OVERHEAD_BYTES);
    let census = study.census_kind() != CensusKind::None;
    let per_run = match study.scene {
        Scene::Free => BYTES_PER_RUN,
        Scene::Harmonic(_) => BYTES_PER_FORCED_RUN,
        Scene::Random(_) => BYTES_PER_RANDOM_RUN,
    };
    let points = runs.saturating_mul(per_run).saturating_add(parts);
    let what = format!(
        "rough: about {per_run} bytes of Parquet per run and {} per part file",
        fmt_bytes(PART_OVERHEAD_BYTES)
    );
    let states = sample
        .filter(|sm| census && sm.runs > 0)
        .map(|sm| sm.steady_states as f64 / sm.runs as f64);
    let _ = match (census, states) {
        (true, Some(k)) => {
            let rows = (runs as f64 * k) as u64;
            let table = rows
                .saturating_mul(BYTES_PER_STEADY_STATE)
                .saturating_add(parts);
            writeln!(
                w,
                "disk estimate:  {} ({what}; the attractors table about \
                 {BYTES_PER_STEADY_STATE} bytes per steady state, {k:.1} per run in the timed \
                 sample)",
                fmt_bytes(points.saturating_add(table))
            )
        }
        (true, None) => writeln!(
            w,
            "disk estimate:  {} ({what}; the attractors table not counted)",
            fmt_bytes(points)
        ),
        (false, _) => writeln!(w, "disk estimate:  {} ({what})", fmt_bytes(points)),
    };
}

/// The free-decay lines: the solver's accuracy on the study's own design points and each run's
/// horizon.
fn describe_free(w: &mut String, study: &Study) {
    let sv = &study.solver;
    let _ = writeln!(
        w,
        "solver:         {} ({} {}, chatter_tol {}, max_impacts {}, max_steps {}, t_max_periods {})",
        sv.kind.name(),
        sv.kind.knob(),
        fmt_value(sv.knob_value()),
        fmt_value(sv.chatter_tol),
        sv.max_impacts,
        sv.max_steps,
        fmt_value(sv.t_max_periods)
    );
    // What the chosen setting costs and how wrong it is, measured now on the study's own design
    // points against `exact` at its tightest tolerance (issue 5).
    let reference = crate::accuracy::Reference::study(study);
    let q = crate::accuracy::quote_on(&reference, sv);
    let _ = writeln!(
        w,
        "accuracy:       {} = {}: max relative error against exact (tol 1e-14) DI {:.1e}, xmax {:.1e}, t1 {:.1e}; {} of {} runs changed impact count",
        sv.kind.knob(),
        fmt_value(sv.knob_value()),
        q.di_err,
        q.xmax_err,
        q.t1_err,
        q.changed_impacts,
        q.runs
    );
    let _ = writeln!(
        w,
        "                ({}; {:.1} us CPU per noise-free run)",
        reference.label,
        q.cpu_per_run * 1e6
    );
    let horizon = match study.request.t_end {
        Some(t) => format!("to t = {} s", fmt_value(t)),
        None => format!("to the end of positive half-cycle {}", study.request.peaks),
    };
    let _ = writeln!(w, "each run:       {horizon}");
}

/// The random and record scenes' lines: the load, its sampling and duration, the threshold;
/// `swept(key)`: whether the study sweeps a scene key (its value here is a placeholder).
fn describe_random(w: &mut String, r: &sim::random::RandomScene, swept: impl Fn(&str) -> bool) {
    use sim::random::Excitation;
    let value = |key: &str, v: f64| {
        if swept(key) {
            "swept".to_string()
        } else {
            fmt_value(v)
        }
    };
    let load = match &r.excitation {
        Excitation::Random(l) => format!(
            "{} noise, S0 = {} (two-sided, per rad/s){}",
            l.spectrum.name(),
            value("S0", l.S0),
            if l.envelope.is_some() {
                ", with an envelope"
            } else {
                ""
            }
        ),
        Excitation::Record(rec) => format!(
            "a record of {} samples, scale {}",
            rec.values.len(),
            value("scale", rec.scale)
        ),
        Excitation::Suite(s) => format!(
            "a suite of {} records, {} samples in all, scale {}",
            s.records.len(),
            s.records.iter().map(|r| r.values.len()).sum::<usize>(),
            value("scale", s.scale)
        ),
    };
    let _ = writeln!(w, "load:           {} ({load})", r.input.name());
    let suite = r.suite();
    if suite.is_empty() {
        let _ = writeln!(
            w,
            "each run:       {} s in samples of {} s ({} samples), solver exact",
            fmt_value(r.duration),
            fmt_value(r.dt),
            r.segments()
        );
    } else {
        let span = |f: &dyn Fn(&sim::random::SuiteRecord) -> f64| {
            let lo = suite.iter().map(f).fold(f64::INFINITY, f64::min);
            let hi = suite.iter().map(f).fold(0.0, f64::max);
            if lo == hi {
                fmt_value(lo)
            } else {
                format!("{} to {}", fmt_value(lo), fmt_value(hi))
            }
        };
        let _ = writeln!(
            w,
            "each run:       its record: {} s in samples of {} s, solver exact",
            span(&|x| x.duration),
            span(&|x| x.dt),
        );
    }
    let _ = writeln!(
        w,
        "threshold:      {}",
        r.threshold
            .map_or("none (no first passage, no p_f)".to_string(), |b| format!(
                "|x| > {} m",
                fmt_value(b)
            ))
    );
}

/// The harmonic scene's lines: the force, the frequency band (fixed or swept) and each run's
/// transient and window.
fn describe_harmonic(w: &mut String, study: &Study, h: &sim::Harmonic) {
    let swept = |key: &str| study.axis(key).is_some();
    let force = if swept("F0") {
        "F0 swept".to_string()
    } else {
        format!("F0 = {} N", fmt_value(h.F0))
    };
    let freq = match (h.drive, study.frequency_axis()) {
        (_, Some(a)) => format!("{} swept (each curve: {} values)", a.key, a.values.len()),
        (Drive::Omega(w), None) => format!("omega = {} rad/s", fmt_value(w)),
        (Drive::Ratio(r), None) => format!("r = {}", fmt_value(r)),
    };
    let _ = writeln!(
        w,
        "scene:          harmonic: F0 cos(omega t) on the main mass; {force}, {freq}"
    );
    let _ = writeln!(
        w,
        "solver:         exact (tol {}, chatter_tol {}, max_impacts {}, max_steps {})",
        fmt_value(study.solver.tol),
        fmt_value(study.solver.chatter_tol),
        study.solver.max_impacts,
        study.solver.max_steps
    );
    let transient = match h.n_trans {
        Some(n) => format!("{n} forcing periods"),
        None => format!(
            "until the Poincare section converges (trans_tol {}), at most {} forcing periods",
            fmt_value(h.trans_tol),
            h.n_trans_max
        ),
    };
    let _ = writeln!(
        w,
        "each run:       transient {transient}, then {} periods measured (period_tol {})",
        h.n_meas,
        fmt_value(h.period_tol)
    );
}

/// Runs per part file under which `plan` calls the part files tiny (with [`TINY_MIN_CHUNKS`]
/// chunks or more): below it a part's fixed cost, [`PART_OVERHEAD_BYTES`] of schema and metadata
/// and a file to create, rename and record, is a tenth of the part or more.
pub const TINY_PART_RUNS: u64 = 1000;
/// Chunks from which tiny parts are worth a warning (fewer tiny files cost little).
pub const TINY_MIN_CHUNKS: u64 = 100;
/// The fixed size of a part file: its footer (the schema with every column's unit, statistics)
/// and the study text. Measured: 10.8 kB for a 2-run part of a 9-line study.
pub const PART_OVERHEAD_BYTES: u64 = 10_600;

/// A warning when the study's part files will be tiny (see [`TINY_PART_RUNS`]).
pub fn tiny_parts(plan: &Plan) -> Option<String> {
    let runs_per_part = plan.chunk_runs(0).end;
    if plan.n_chunks() < TINY_MIN_CHUNKS || runs_per_part >= TINY_PART_RUNS {
        return None;
    }
    let suggest = TINY_PART_RUNS.div_ceil(plan.n_cases().max(1));
    Some(format!(
        "{} part files of {runs_per_part} runs (about {}, of which {} is each file's fixed \
         schema and metadata): tiny files slow the sweep and every reader that opens them all. \
         Set [run].chunk_points to {suggest} or more, or leave it out (about {} runs per part)",
        plan.n_chunks(),
        fmt_bytes(runs_per_part * BYTES_PER_RUN + PART_OVERHEAD_BYTES),
        fmt_bytes(PART_OVERHEAD_BYTES),
        crate::study::DEFAULT_CHUNK_RUNS
    ))
}

/// `1.2 s`, `3 min 20 s`, `2 h 05 min`.
pub fn fmt_duration(secs: f64) -> String {
    if secs < 1.0 {
        format!("{:.0} ms", secs * 1e3)
    } else if secs < 60.0 {
        format!("{secs:.1} s")
    } else if secs < 3600.0 {
        format!("{} min {:02} s", (secs / 60.0) as u64, (secs % 60.0) as u64)
    } else {
        format!(
            "{} h {:02} min",
            (secs / 3600.0) as u64,
            ((secs % 3600.0) / 60.0) as u64
        )
    }
}

/// `512 B`, `48.8 kB`, `1.2 GB` (powers of 1000).
pub fn fmt_bytes(b: u64) -> String {
    let units = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut v = b as f64;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < units.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{b} B")
    } else {
        format!("{v:.1} {}", units[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The multi-unit showcase's plan: 16 designs x 31 frequencies x 5 cases, the frequency
    /// fastest. An even stride of 155 runs sampled r = 0.85's ideal case 16 times; the sample
    /// now meets distinct runs, most frequencies' thirds and more than one case.
    #[test]
    fn the_sample_is_not_in_step_with_the_axes() {
        let (total, n) = (2480u64, 16u64);
        let runs: Vec<u64> = (0..n).map(|j| sample_index(j, n, total)).collect();
        let mut distinct = runs.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 16);
        assert!(runs.iter().all(|&r| r < total));
        let freq = |r: u64| (r / 5) % 31;
        for third in 0..3 {
            assert!(runs.iter().any(|&r| freq(r) / 11 == third), "{runs:?}");
        }
        assert!(runs.iter().any(|&r| r % 5 != runs[0] % 5), "{runs:?}");
        // A sample as large as the plan is the plan.
        assert_eq!(
            (0..5).map(|j| sample_index(j, 5, 5)).collect::<Vec<_>>(),
            [0, 1, 2, 3, 4]
        );
    }

    #[test]
    fn durations_and_sizes_read_well() {
        assert_eq!(fmt_duration(1.234), "1.2 s");
        assert_eq!(fmt_duration(0.0123), "12 ms");
        assert_eq!(fmt_duration(200.0), "3 min 20 s");
        assert_eq!(fmt_duration(7500.0), "2 h 05 min");
        assert_eq!(fmt_bytes(512), "512 B");
        assert_eq!(fmt_bytes(48_800), "48.8 kB");
        assert_eq!(fmt_bytes(1_234_000_000), "1.2 GB");
    }

    /// A sample of 4 frequencies: 1 s of census, 2 s of race over 10^6 periods, and the whole
    /// curve's race `whole_seconds` (0: not asked for).
    fn curve_sample(whole_seconds: f64) -> Sample {
        Sample {
            runs: 4,
            seconds: 3.0,
            steady_states: 4,
            race_seconds: 2.0,
            race_periods: 1_000_000,
            peak_seconds: 0.0,
            whole_seconds,
        }
    }

    /// The study of `text` described with `sample` on 2 threads, and its "time estimate:" line.
    fn estimate_line(text: &str, sample: Sample) -> (String, String) {
        let study = Study::parse(Path::new("s.toml"), text).unwrap();
        let out = describe(&study, Path::new("out"), 2, Some(sample));
        let line = out
            .lines()
            .find(|l| l.starts_with("time estimate:"))
            .unwrap()
            .to_string();
        (out, line)
    }

    /// The census scales by the runs over the threads, the race by the curves: 3 designs x 2
    /// cases x 4 frequencies, a sample of 4 frequencies taking 1 s of census and 2 s of race,
    /// is 24 runs x 0.25 s / 2 threads + 6 curves x 2 s = 15 s (scaling the whole sample by
    /// the runs would say 18 s, and 10 times more for a curve of 40 frequencies).
    #[test]
    fn a_harmonic_race_counts_once_a_curve() {
        let text = "[study]\nname = \"s\"\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n\
                    [sweep]\nm = [0.005, 0.01, 0.02]\nr = [0.9, 1.0, 1.1, 1.2]\n\
                    [perturb]\ndm = [0.001]\n";
        let sample = curve_sample(0.0);
        let (out, line) = estimate_line(text, sample);
        assert!(line.starts_with("time estimate:  15.0 s on 2 threads (census 250.0 ms a frequency over a sample of 4 frequencies"), "{line}");
        assert!(
            line.ends_with("2.0 s over 1,000,000 periods, counted once a curve)"),
            "{line}"
        );
        // The verification at that speed: 2 us a period, 1,024,000 periods, 3 motions a case.
        let v = out
            .lines()
            .find(|l| l.starts_with("verification:"))
            .unwrap();
        assert!(
            v.ends_with("up to about 6.1 s a case of each such design at the race's speed"),
            "{v}"
        );
        // One design is not verified: no line.
        let text = "[study]\nname = \"s\"\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n\
                    [sweep]\nr = [0.9, 1.0, 1.1, 1.2]\n";
        let study = Study::parse(Path::new("s.toml"), text).unwrap();
        let out = describe(&study, Path::new("out"), 2, Some(sample));
        assert!(!out.contains("verification:"), "{out}");
    }

    /// A perturbed case's curve counts at its own race, which serves its peak alone: the study
    /// of `a_harmonic_race_counts_once_a_curve` (3 designs x 2 cases) with that race at 0.5 s
    /// is 24 runs x 0.25 s / 2 threads + 3 ideal curves x 2 s + 3 perturbed x 0.5 s = 10.5 s.
    #[test]
    fn a_perturbed_curve_counts_at_its_peaks_race() {
        let text = "[study]\nname = \"s\"\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n\
                    [sweep]\nm = [0.005, 0.01, 0.02]\nr = [0.9, 1.0, 1.1, 1.2]\n\
                    [perturb]\ndm = [0.001]\n";
        let sample = Sample {
            peak_seconds: 0.5,
            ..curve_sample(0.0)
        };
        let (_, line) = estimate_line(text, sample);
        assert!(
            line.starts_with("time estimate:  10.5 s on 2 threads"),
            "{line}"
        );
        assert!(
            line.ends_with(
                "counted once a curve (500 ms when it serves a perturbed case's peak alone))"
            ),
            "{line}"
        );
    }

    /// With the whole curve measured, each ideal curve adds the sample's extra race scaled from
    /// the sampled frequencies to its own: the study above (3 designs, 4 frequencies, all
    /// sampled), its whole race 5 s against the decisions' 2 s, is 15 s + 3 ideal curves x 3 s.
    #[test]
    fn the_whole_curve_adds_its_extra_race_to_each_ideal_curve() {
        let text = "[study]\nname = \"s\"\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n\
                    life_curve = \"whole\"\n[sweep]\nm = [0.005, 0.01, 0.02]\n\
                    r = [0.9, 1.0, 1.1, 1.2]\n[perturb]\ndm = [0.001]\n";
        let (_, line) = estimate_line(text, curve_sample(5.0));
        assert!(
            line.starts_with("time estimate:  24.0 s on 2 threads"),
            "{line}"
        );
        assert!(
            line.ends_with(
                "counted once a curve; the whole curve measured (`life_curve = \"whole\"`) adds 3.0 s a design's ideal curve)"
            ),
            "{line}"
        );
    }

    /// A random study's plan bounds what `reduce`'s subset simulation may add: 10,000 runs a
    /// design at the sample's cost (2 x 3 designs, 100 us a run, 2 threads: 60,000 runs,
    /// 3.0 s); a record suite draws no normals and gets no such line.
    #[test]
    fn a_random_plan_bounds_the_subset_simulation_reduce_may_run() {
        let text = "[study]\nname = \"s\"\n[scene]\nkind = \"random\"\ninput = \"base\"\n\
                    spectrum = \"kanai-tajimi\"\nomega_g = 15.708\nzeta_g = 0.6\nduration = 20\n\
                    threshold = 0.05\nS0 = 1e-3\nrealizations = 200\n[sweep]\nm = [0.0, 0.02]\n\
                    d = [0.01, 0.02, 0.04]\n";
        let sample = Sample {
            runs: 100,
            seconds: 0.01,
            steady_states: 0,
            race_seconds: 0.0,
            race_periods: 0,
            peak_seconds: 0.0,
            whole_seconds: 0.0,
        };
        let (out, _) = estimate_line(text, sample);
        let line = out.lines().find(|l| l.starts_with("subset:")).unwrap();
        assert!(
            line.contains(
                "up to 10,000 runs a design, 60,000 runs for 6 designs, about 3.0 s on 2 threads"
            ),
            "{line}"
        );
        let path = Path::new("configs/seismic-records.toml");
        let study = Study::parse(path, &std::fs::read_to_string(path).unwrap()).unwrap();
        let out = describe(&study, Path::new("out"), 2, Some(sample));
        assert!(!out.contains("subset:"), "{out}");
    }

    #[test]
    fn sample_is_spread_over_the_plan_and_bounded() {
        let text = "[study]\nname = \"s\"\n[sweep]\ne = { start = 0.5, stop = 0.9, num = 300 }\n";
        let study = Study::parse(Path::new("s.toml"), text).unwrap();
        assert_eq!(time_sample(&study).runs, SAMPLE_RUNS);
        let text = "[study]\nname = \"s\"\n[sweep]\ne = [0.5, 0.9]\n";
        let study = Study::parse(Path::new("s.toml"), text).unwrap();
        assert_eq!(time_sample(&study).runs, 2);
    }
}
