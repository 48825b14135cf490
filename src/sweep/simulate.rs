//! What one chunk's runs are (the pipeline's *simulate* step, between the plan and the store):
//! each run of a free-decay study on its own, and for a harmonic study with a census each
//! frequency-response curve (a design and the cases that share its system) as one task, its
//! runs from the initial state and its census in frequency order ([`crate::orbits::curve`]),
//! with the attractors it found; for a harmonic study of several units each curve too, each
//! run with its own census of several units and the race for the design lives along the curve
//! ([`crate::orbits::several`]). Pure: the same plan and chunk give the same rows and bits on
//! any thread count.

use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::orbits::attractors::{AttractorRow, RunId};
use crate::orbits::curve::{CurveFrequency, curve_census, fill_steady, from_rest};
use crate::orbits::forced_run;
use crate::orbits::race::Serves;
use crate::orbits::several::{UnitsRun, census_run_units, forced_run_units, race_runs};
use crate::plan::{Plan, RunSpec};
use crate::sim::{Harmonic, HarmonicRecord, NoProbe, Record, simulate};
use crate::store::{RunRow, StoredRecord};
use crate::study::CensusKind;

/// A scene's record as the engine simulates and stores it: [`Record`] for free decay,
/// [`HarmonicRecord`] for the harmonic scene. The engine picks it from the study's scene.
pub trait SceneRun: StoredRecord + Send + Sync {
    /// Simulates one run of the plan.
    fn simulate(plan: &Plan, run: &RunSpec) -> Self;

    /// Simulates chunk `k` (in parallel, on the current rayon pool): its rows in `point_id`
    /// order, and the attractors of its runs when the scene takes a census. By default each run
    /// on its own ([`SceneRun::simulate`]).
    fn simulate_chunk(plan: &Plan, k: u64, progress: Option<&ProgressBar>) -> ChunkRows<Self> {
        ChunkRows {
            rows: simulate_chunk(plan, k, progress),
            attractors: None,
        }
    }
}

/// A simulated chunk: its runs, and their attractors (a harmonic study with a census).
pub struct ChunkRows<R> {
    pub rows: Vec<RunRow<R>>,
    pub attractors: Option<Vec<AttractorRow>>,
}

impl SceneRun for Record {
    fn simulate(plan: &Plan, run: &RunSpec) -> Self {
        simulate_run(plan, run)
    }
}

impl SceneRun for HarmonicRecord {
    fn simulate(plan: &Plan, run: &RunSpec) -> Self {
        simulate_forced_run(plan, run)
    }

    /// By the study's census ([`CensusKind`]): one unit's, each frequency-response curve (a
    /// design and a case group) as one task ([`simulate_curve`]); several units', each curve (a
    /// design and a case) as one task ([`simulate_units_curve`]); none, each run on its own.
    fn simulate_chunk(plan: &Plan, k: u64, progress: Option<&ProgressBar>) -> ChunkRows<Self> {
        match plan.study.census_kind() {
            CensusKind::None => ChunkRows {
                rows: simulate_chunk(plan, k, progress),
                attractors: None,
            },
            CensusKind::Units => simulate_units_chunk(plan, k, progress),
            CensusKind::OneUnit => simulate_curves_chunk(plan, k, progress),
        }
    }
}

/// Chunk `k` of a study with the one-unit census: each frequency-response curve (a design and
/// a case group) as one task ([`simulate_curve`]), in parallel.
fn simulate_curves_chunk(
    plan: &Plan,
    k: u64,
    progress: Option<&ProgressBar>,
) -> ChunkRows<HarmonicRecord> {
    let n_f = plan.study.curve_points();
    let points = plan.chunk_points(k);
    let designs: Vec<u64> = (points.start / n_f..points.end.div_ceil(n_f)).collect();
    let tasks: Vec<(u64, Vec<u32>)> = designs
        .into_iter()
        .flat_map(|design| {
            same_system_cases(plan, design)
                .into_iter()
                .map(move |cases| (design, cases))
        })
        .collect();
    let done: Vec<(Vec<RunRow<HarmonicRecord>>, Vec<AttractorRow>)> = tasks
        .into_par_iter()
        .map(|(design, cases)| {
            let out = simulate_curve(plan, design, &cases);
            if let Some(pb) = progress {
                pb.inc(out.0.len() as u64);
            }
            out
        })
        .collect();
    gathered(done)
}

/// A chunk from its curves' rows and attractors: the rows in `point_id` order, each run's
/// attractors in census order.
fn gathered(
    done: Vec<(Vec<RunRow<HarmonicRecord>>, Vec<AttractorRow>)>,
) -> ChunkRows<HarmonicRecord> {
    let mut rows = Vec::with_capacity(done.iter().map(|d| d.0.len()).sum());
    let mut attractors = Vec::new();
    for (r, a) in done {
        rows.extend(r);
        attractors.extend(a);
    }
    rows.sort_by_key(|r| r.point_id);
    // Stable: each run's attractors stay in their census order.
    attractors.sort_by_key(|a| a.run.point_id);
    ChunkRows {
        rows,
        attractors: Some(attractors),
    }
}

/// Chunk `k` of a study of several units: each frequency-response curve (a design and a case)
/// as one task ([`simulate_units_curve`]), in parallel; the rows in `point_id` order, each
/// run's attractors in census order.
fn simulate_units_chunk(
    plan: &Plan,
    k: u64,
    progress: Option<&ProgressBar>,
) -> ChunkRows<HarmonicRecord> {
    let n_f = plan.study.curve_points();
    let points = plan.chunk_points(k);
    let n_cases = plan.n_cases() as u32;
    let tasks: Vec<(u64, u32)> = (points.start / n_f..points.end.div_ceil(n_f))
        .flat_map(|design| (0..n_cases).map(move |case| (design, case)))
        .collect();
    let done: Vec<(Vec<RunRow<HarmonicRecord>>, Vec<AttractorRow>)> = tasks
        .into_par_iter()
        .map(|(design, case)| {
            let out = simulate_units_curve(plan, design, case);
            if let Some(pb) = progress {
                pb.inc(out.0.len() as u64);
            }
            out
        })
        .collect();
    gathered(done)
}

/// The frequency-response curve of a study of several units at design `design` and case
/// `case`, as one task: each frequency's run with its census ([`census_run_units`], in
/// parallel), then the race for the design lives over the curve ([`race_runs`]: the ideal
/// case's curve is drawn and read frequency by frequency, a perturbed case's serves its peak).
/// Returns the rows and their attractors.
pub fn simulate_units_curve(
    plan: &Plan,
    design: u64,
    case: u32,
) -> (Vec<RunRow<HarmonicRecord>>, Vec<AttractorRow>) {
    let n_f = plan.study.curve_points();
    let runs: Vec<RunSpec> = (design * n_f..(design + 1) * n_f)
        .map(|p| plan.run(p, case))
        .collect();
    let study = plan.study;
    let mut outs: Vec<UnitsRun> = runs
        .par_iter()
        .map(|run| {
            let mut stream = plan.noise_stream(run);
            census_run_units(
                &run.system,
                &study.solver,
                &study.request,
                &harmonic_scene(run),
                study.noise.as_ref().zip(stream.as_mut()),
                &mut NoProbe,
                study.seed,
                run.point,
            )
        })
        .collect();
    let scenes: Vec<Harmonic> = runs.iter().map(harmonic_scene).collect();
    let serves = if runs.first().is_some_and(|r| r.spec.ideal) {
        Serves::Curve
    } else {
        Serves::Peak
    };
    race_runs(&mut outs, &scenes, serves);
    let mut rows = Vec::with_capacity(runs.len());
    let mut attractors = Vec::new();
    for (run, out) in runs.iter().zip(outs) {
        attractors.extend(out.rows(run_id(run, &out.record)));
        rows.push(row_of(plan, run, out.record));
    }
    (rows, attractors)
}

/// The run `run` of a study of several units with its census ([`forced_run_units`]: the
/// study seed and the design point fix its starts).
fn units_run(plan: &Plan, run: &RunSpec) -> UnitsRun {
    let study = plan.study;
    let mut stream = plan.noise_stream(run);
    forced_run_units(
        &run.system,
        &study.solver,
        &study.request,
        &harmonic_scene(run),
        study.noise.as_ref().zip(stream.as_mut()),
        &mut NoProbe,
        study.seed,
        run.point,
    )
}

/// The attractor rows' key of `run`, simulated as `rec`.
fn run_id(run: &RunSpec, rec: &HarmonicRecord) -> RunId {
    RunId {
        point_id: run.point_id,
        point: run.point,
        case: run.case,
        ideal: run.spec.ideal,
        r: rec.r,
        omega: rec.omega,
        F0: rec.F0,
    }
}

/// The run's harmonic scene: the study's, with the design point's `F0`, `omega` or `r`; the
/// default harmonic scene if the study is a free-decay one.
fn harmonic_scene(run: &RunSpec) -> Harmonic {
    run.scene.harmonic_or_default()
}

/// The cases of design `design` grouped by their system (a case that differs from another only
/// in its noise has the same system, and so the same census), in case order.
fn same_system_cases(plan: &Plan, design: u64) -> Vec<Vec<u32>> {
    let n_f = plan.study.curve_points();
    let mut groups: Vec<(Vec<u64>, Vec<u32>)> = Vec::new();
    for c in 0..plan.n_cases() as u32 {
        let sys = plan.run(design * n_f, c).system;
        let key: Vec<u64> = crate::model::SYSTEM_KEYS
            .iter()
            .map(|k| sys.get(k).unwrap_or(f64::NAN).to_bits())
            .collect();
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push(c),
            None => groups.push((key, vec![c])),
        }
    }
    groups.into_iter().map(|g| g.1).collect()
}

/// The frequency-response curves of a harmonic study's design `design` for `cases` (cases with
/// one system), as one task: each case's runs at every frequency from the initial state (with
/// its noise), and one census along the curve ([`curve_census`]: in frequency order, each
/// frequency seeded with its neighbours' attractors), which every case of the group shares.
/// Returns the rows and their attractors (every case's).
pub fn simulate_curve(
    plan: &Plan,
    design: u64,
    cases: &[u32],
) -> (Vec<RunRow<HarmonicRecord>>, Vec<AttractorRow>) {
    let study = plan.study;
    let n_f = study.curve_points();
    let mut censuses = None;
    // The cases share one census: it serves the ideal curve when one of them is the ideal case,
    // else the perturbed cases' peaks alone.
    let serves = if cases.iter().any(|&c| plan.run(design * n_f, c).spec.ideal) {
        Serves::Curve
    } else {
        Serves::Peak
    };
    let mut rows = Vec::with_capacity(cases.len() * n_f as usize);
    let mut attractors = Vec::new();
    for &case in cases {
        let runs: Vec<RunSpec> = (design * n_f..(design + 1) * n_f)
            .map(|p| plan.run(p, case))
            .collect();
        let freqs: Vec<CurveFrequency> = runs.iter().map(|run| plan.curve_frequency(run)).collect();
        let targets: Vec<(Harmonic, u64)> = freqs.iter().map(|f| (f.scene, f.point)).collect();
        let sys = runs[0].system;
        let mut records = from_rest(
            &sys,
            &study.solver,
            &study.request,
            study.noise.as_ref(),
            freqs,
        );
        let cs = censuses.get_or_insert_with(|| {
            curve_census(&sys, &study.solver, study.seed, &targets, &records, serves)
        });
        fill_steady(&mut records, cs);
        for ((run, record), census) in runs.iter().zip(records).zip(cs.iter()) {
            if let Some(c) = census {
                attractors.extend(AttractorRow::of_census(
                    run_id(run, &record),
                    c,
                    std::f64::consts::TAU / record.omega,
                ));
            }
            rows.push(row_of(plan, run, record));
        }
    }
    (rows, attractors)
}

/// Simulates one run: the study's solver and request, the run's noise stream when its case has
/// noise (no random number is drawn otherwise).
pub fn simulate_run(plan: &Plan, run: &RunSpec) -> Record {
    let study = plan.study;
    match (study.noise.as_ref(), plan.noise_stream(run)) {
        (Some(ns), Some(mut stream)) => simulate(
            &run.system,
            &study.solver,
            &study.request,
            Some((ns, &mut stream)),
            &mut NoProbe,
        ),
        _ => simulate(
            &run.system,
            &study.solver,
            &study.request,
            None,
            &mut NoProbe,
        ),
    }
}

/// Simulates one run of a harmonic study ([`forced_run`]: from the study's initial state, then
/// the attractor census seeded by the study seed and the design point): the run's scene (the study's, with the design point's
/// `F0`, `omega` or `r`; the default harmonic scene if the study is a free-decay one), the study's
/// solver, the run's noise stream when its case has noise. The study has validated the scene
/// for every run ([`Harmonic::validate`]).
pub fn simulate_forced_run(plan: &Plan, run: &RunSpec) -> HarmonicRecord {
    let study = plan.study;
    let mut scene = harmonic_scene(run);
    match study.census_kind() {
        CensusKind::None => scene.starts = 0,
        CensusKind::OneUnit => {}
        // Every design of a study of several units, its one-unit ones too, takes the census of
        // several units: every design's steady states are found alike.
        CensusKind::Units => return units_run(plan, run).record,
    }
    let mut stream = plan.noise_stream(run);
    forced_run(
        &run.system,
        &study.solver,
        &study.request,
        &scene,
        study.noise.as_ref().zip(stream.as_mut()),
        &mut NoProbe,
        study.seed,
        run.point,
    )
}

/// The stored row of a run.
pub fn run_row<R: SceneRun>(plan: &Plan, run: &RunSpec) -> RunRow<R> {
    row_of(plan, run, R::simulate(plan, run))
}

/// The stored row of `run` with its simulated `record`.
pub(super) fn row_of<R>(plan: &Plan, run: &RunSpec, record: R) -> RunRow<R> {
    RunRow {
        point_id: run.point_id,
        point: run.point,
        case: run.case,
        ideal: run.spec.ideal,
        dm: run.spec.dm,
        dd: run.spec.dd,
        noise_seed: run.spec.noise_seed,
        system: run.system,
        solver: plan.study.solver.kind.name().into(),
        tol: plan.study.solver.tol,
        record,
    }
}

/// Simulates chunk `k` (in parallel over its runs, on the current rayon pool), in `point_id`
/// order.
pub fn simulate_chunk<R: SceneRun>(
    plan: &Plan,
    k: u64,
    progress: Option<&ProgressBar>,
) -> Vec<RunRow<R>> {
    let points = plan.chunk_points(k);
    let n_cases = plan.n_cases();
    (points.start * n_cases..points.end * n_cases)
        .into_par_iter()
        .map(|id| {
            let run = plan.run(id / n_cases, (id % n_cases) as u32);
            let row = run_row(plan, &run);
            if let Some(pb) = progress {
                pb.inc(1);
            }
            row
        })
        .collect()
}
