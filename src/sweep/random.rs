//! The random and record scenes' runs (docs/scenes.md, model.md §13): the *simulate* step of a
//! random or record study, beside [`super::simulate`]'s free-decay and harmonic runs.
//!
//! A run is a realization `c` of design point `p` ([`crate::plan`]): its load is drawn as it
//! runs from [`Plan::load_stream`] (study seed and `c`: the same load at every design point),
//! never stored; a record's samples are
//! the study's, shared. A design point's setup ([`RandomRun::new`]: its oscillators, its
//! propagator over `dt`, its quadratic forms) is prepared once per chunk and shared by its
//! realizations, which run in parallel on the current rayon pool. Pure: the same plan and chunk
//! give the same rows and bits on any thread count, chunk size or shard split.

use indicatif::ProgressBar;
use rayon::prelude::*;

use super::simulate::{ChunkRows, SceneRun, row_of};
use crate::plan::{Plan, RunSpec};
use crate::sim::random::{GivenNormals, LoadBlock, RandomRun, RandomScene, RealizationRecord, ida};
use crate::sim::{NoProbe, Outcome, Probe, Request, Scene};
use crate::store::RunRow;

impl SceneRun for RealizationRecord {
    fn simulate(plan: &Plan, run: &RunSpec) -> Self {
        let scene = random_scene(&run.scene, run.case);
        let setup = RandomRun::new(&run.system, &plan.study.solver, &scene);
        realization(plan, run, &scene, &setup)
    }

    /// Each design point of the chunk set up once ([`RandomRun::new`]), then its realizations
    /// (all, or the chunk's block of them, [`Plan::chunk_runs`]) in parallel, in `point_id`
    /// order. A suite's records differ in `dt` and length: each run sets up its own.
    fn simulate_chunk(plan: &Plan, k: u64, progress: Option<&ProgressBar>) -> ChunkRows<Self> {
        let points = plan.chunk_points(k);
        let n = plan.n_cases();
        let suite = plan
            .study
            .scene
            .random()
            .is_some_and(|r| !r.suite().is_empty());
        let setups: Vec<(RunSpec, RandomScene, RandomRun)> = points
            .clone()
            .filter(|_| !suite)
            .map(|p| {
                let first = plan.run(p, 0);
                let scene = random_scene(&first.scene, 0);
                let setup = RandomRun::new(&first.system, &plan.study.solver, &scene);
                (first, scene, setup)
            })
            .collect();
        let rows = plan
            .chunk_runs(k)
            .into_par_iter()
            .map(|id| {
                let (p, c) = (id / n, (id % n) as u32);
                let run = plan.run(p, c);
                let record = match setups.get((p - points.start) as usize) {
                    Some((first, scene, setup)) => {
                        debug_assert_eq!(run.system, first.system);
                        realization(plan, &run, scene, setup)
                    }
                    None => Self::simulate(plan, &run),
                };
                let row = row_of(plan, &run, record);
                if let Some(pb) = progress {
                    pb.inc(1);
                }
                row
            })
            .collect::<Vec<RunRow<Self>>>();
        ChunkRows {
            rows,
            attractors: None,
        }
    }
}

/// The random scene of realization `case` of a run (the design point's values set by the
/// plan; a suite's record `case`, [`RandomScene::for_case`]); a run of another scene never
/// reaches here (the engine picks the record type from the study's scene), and would get the
/// placeholder of [`RandomScene::placeholder`].
fn random_scene(scene: &Scene, case: u32) -> RandomScene {
    scene
        .random()
        .map_or_else(RandomScene::placeholder, |r| r.for_case(case).into_owned())
}

/// One realization of a random or record study, as the sweep stores it (the same bits as its
/// row): realization `case` of design point `point`, with `trace` a sampled trace of the run at
/// the stripe's scale every `trace` seconds (plus every impact). `None` for a point or a
/// realization out of the plan, or a study of another scene.
pub fn one_realization(
    plan: &Plan,
    point: u64,
    case: u32,
    trace: Option<f64>,
) -> Option<(RealizationRecord, Vec<(f64, crate::sim::State)>)> {
    plan.study.scene.random()?;
    if point >= plan.n_points() || u64::from(case) >= plan.n_cases() {
        return None;
    }
    let run = plan.run(point, case);
    let scene = random_scene(&run.scene, case);
    let setup = RandomRun::new(&run.system, &plan.study.solver, &scene);
    let row = realization(plan, &run, &scene, &setup);
    let mut probe = crate::sim::TraceProbe::default();
    if let Some(dt) = trace {
        let req = crate::sim::Request {
            trace_dt: Some(dt),
            ..plan.study.request
        };
        let gain = row.load[5]
            .filter(|_| scene.intensity.is_some())
            .unwrap_or(1.0);
        setup.run_scaled(&req, plan.load_stream(&run), gain, &mut probe);
    }
    Some((row, probe.rows))
}

/// Realization `run.case` of `run.point` on its design point's `setup`: its load's samples
/// drawn once ([`RandomRun::load`]) and run as [`motion_row`] runs them, the capacity searched
/// at the design stripe (every point without stripes).
fn realization(
    plan: &Plan,
    run: &RunSpec,
    scene: &RandomScene,
    setup: &RandomRun,
) -> RealizationRecord {
    let block = setup.load(plan.load_stream(run));
    let capacity = design_stripe(plan, scene);
    motion_row(
        setup,
        &plan.study.request,
        scene,
        (&block, capacity),
        &mut NoProbe,
    )
}

/// Whether `scene` (a design point's) lies at the study's design stripe, where a motion's
/// capacity is searched: every point of a study without stripes.
fn design_stripe(plan: &Plan, scene: &RandomScene) -> bool {
    scene.im.is_none() || scene.im == plan.study.design_intensity_value()
}

/// The stored row of realization `run` alone (Python's `simulate_batch` runs one a row): its
/// load drawn from its stream, or from the standard normals `normals` handed in
/// ([`RandomRun::n_normals`] of them) in place of it, run as [`motion_row`] runs it, the
/// capacity searched at the design stripe where `capacity`. With the stream and `capacity`,
/// the sweep's row bit for bit; on the normals the stream draws, the same.
pub fn realization_row(
    plan: &Plan,
    run: &RunSpec,
    normals: Option<&[f64]>,
    capacity: bool,
) -> RunRow<RealizationRecord> {
    let scene = random_scene(&run.scene, run.case);
    let setup = RandomRun::new(&run.system, &plan.study.solver, &scene);
    let block = match normals {
        Some(u) => setup.load(GivenNormals::new(u)),
        None => setup.load(plan.load_stream(run)),
    };
    let capacity = capacity && design_stripe(plan, &scene);
    let req = &plan.study.request;
    let record = motion_row(&setup, req, &scene, (&block, capacity), &mut NoProbe);
    row_of(plan, run, record)
}

/// The row of one motion, its load's samples `block` at scale 1 ([`RandomRun::load`]), on a
/// design point's `setup`: what the sweep stores for a realization, and what Python's
/// `simulate(scene="random", normals=...)` runs on the normals it is handed.
///
/// Without an intensity measure, the run of `block` (the same bits as [`RandomRun::run`] on
/// the normals that made it). Under one: the motion's own PGA and Sa first (one pass over the
/// samples), the run at the stripe's gain `im / own` (1 without a stripe,
/// [`RandomRun::at_stripe`]), and where `capacity` and the scene has a threshold, the motion's
/// capacity by incremental dynamic analysis ([`crate::sim::random::ida`]), each trial a run of
/// the same motion at another gain. `probe` observes the run the record comes from (not the
/// capacity search's).
pub fn motion_row<P: Probe>(
    setup: &RandomRun,
    req: &Request,
    scene: &RandomScene,
    (block, capacity): (&LoadBlock, bool),
    probe: &mut P,
) -> RealizationRecord {
    let Some(spec) = scene.intensity else {
        let record = setup.run_block(req, block, 1.0, probe);
        return RealizationRecord::new(scene, record);
    };
    let (own, gain) = setup.at_stripe(&spec, scene.im, block);
    let i0 = own.of(spec.measure);
    let record = setup.run_block(req, block, gain, probe);
    let amplitude = |r: &crate::sim::random::RandomRecord| {
        if r.outcome == Outcome::Ok {
            r.amplitude
        } else {
            f64::NAN
        }
    };
    let capacity = match scene.threshold {
        Some(b) if capacity && i0 > 0.0 => Some(ida::capacity(
            i0,
            b,
            (gain, amplitude(&record)),
            spec.ida_tol,
            spec.ida_max,
            |s| setup.amplitude_block(req, block, s),
        )),
        _ => None,
    };
    let mut row = RealizationRecord::new(scene, record);
    row.own = Some(own);
    row.load[5] = Some(gain);
    row.capacity = capacity;
    row
}
