//! The random and record scenes' runs (docs/scenes.md, model.md §13): the *simulate* step of a
//! random or record study, beside [`super::simulate`]'s free-decay and harmonic runs.
//!
//! A run is a realization `c` of design point `p` ([`crate::plan`]): its load is drawn as it
//! runs from [`Plan::load_stream`] (study seed and `c`: the same load at every design point),
//! never stored; a record's samples are
//! the study's, shared. A design point's setup ([`RandomRun::new`]: its oscillators, its
//! propagator over `dt`, its quadratic forms) is prepared once per chunk and shared by its
//! realizations, which run in parallel on the current rayon pool, up to
//! [`crate::sim::random::LANES`] of one design point side by side ([`RandomRun::run_blocks`]:
//! each record the run alone's, bit for bit). Pure: the same plan and chunk
//! give the same rows and bits on any thread count, chunk size or shard split.

use indicatif::ProgressBar;
use rayon::prelude::*;

use super::simulate::{ChunkRows, SceneRun, row_of};
use crate::plan::{Plan, RunSpec};
use crate::sim::random::{
    GivenNormals, IntensitySpec, LANES, LoadBlock, OwnIntensity, RandomRecord, RandomRun,
    RandomScene, RealizationRecord, ida,
};
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
        // Up to `LANES` realizations of one design point at a time, run side by side
        // (`RandomRun::run_blocks`: each record the run alone's, bit for bit).
        let ids: Vec<u64> = plan.chunk_runs(k).collect();
        let groups: Vec<&[u64]> = ids
            .chunk_by(|a, b| a / n == b / n)
            .flat_map(|same| same.chunks(LANES))
            .collect();
        let rows = groups
            .into_par_iter()
            .flat_map_iter(|group| {
                let p = group[0] / n;
                let runs: Vec<RunSpec> = group
                    .iter()
                    .map(|id| plan.run(p, (id % n) as u32))
                    .collect();
                let records = match setups.get((p - points.start) as usize) {
                    Some((first, scene, setup)) => {
                        debug_assert!(runs.iter().all(|run| run.system == first.system));
                        realizations(plan, &runs, scene, setup)
                    }
                    None => runs.iter().map(|run| Self::simulate(plan, run)).collect(),
                };
                let rows: Vec<RunRow<Self>> = runs
                    .iter()
                    .zip(records)
                    .map(|(run, record)| row_of(plan, run, record))
                    .collect();
                if let Some(pb) = progress {
                    pb.inc(rows.len() as u64);
                }
                rows
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

/// [`realization`] of each of `runs` (realizations of one design point), run side by side
/// ([`motion_rows`]): the same records, bit for bit.
fn realizations(
    plan: &Plan,
    runs: &[RunSpec],
    scene: &RandomScene,
    setup: &RandomRun,
) -> Vec<RealizationRecord> {
    let blocks: Vec<LoadBlock> = runs
        .iter()
        .map(|run| setup.load(plan.load_stream(run)))
        .collect();
    let capacity = design_stripe(plan, scene);
    motion_rows(setup, &plan.study.request, scene, &blocks, capacity)
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
    let record = setup.run_block(req, block, gain, probe);
    let capacity = search(scene, &spec, capacity, own, (gain, &record))
        .map(|search| search.finish(|g| setup.amplitude_block(req, block, g)));
    stripe_row(scene, (own, gain), record, capacity)
}

/// [`motion_row`] of each motion of `blocks` with no probe, their runs side by side
/// ([`RandomRun::run_blocks`]), and their capacity searches' trials too, a round of trials at a
/// time ([`ida::Search`], [`RandomRun::amplitude_blocks`]): the same records, bit for bit.
pub fn motion_rows(
    setup: &RandomRun,
    req: &Request,
    scene: &RandomScene,
    blocks: &[LoadBlock],
    capacity: bool,
) -> Vec<RealizationRecord> {
    let Some(spec) = scene.intensity else {
        let runs: Vec<(&LoadBlock, f64)> = blocks.iter().map(|b| (b, 1.0)).collect();
        return setup
            .run_blocks(req, &runs)
            .into_iter()
            .map(|record| RealizationRecord::new(scene, record))
            .collect();
    };
    let stripes: Vec<(OwnIntensity, f64)> = blocks
        .iter()
        .map(|b| setup.at_stripe(&spec, scene.im, b))
        .collect();
    let runs: Vec<(&LoadBlock, f64)> = blocks.iter().zip(&stripes).map(|(b, s)| (b, s.1)).collect();
    let records = setup.run_blocks(req, &runs);
    let mut searches: Vec<Option<ida::Search>> = stripes
        .iter()
        .zip(&records)
        .map(|(&(own, gain), record)| search(scene, &spec, capacity, own, (gain, record)))
        .collect();
    let mut capacities: Vec<Option<ida::Capacity>> = vec![None; blocks.len()];
    loop {
        // Every search's next trial, run side by side.
        let mut asked = Vec::new();
        for (i, slot) in searches.iter_mut().enumerate() {
            let Some(search) = slot else { continue };
            match search.ask() {
                ida::Next::Run(gain) => asked.push((i, gain)),
                ida::Next::Done(c) => {
                    capacities[i] = Some(c);
                    *slot = None;
                }
            }
        }
        if asked.is_empty() {
            break;
        }
        let trials: Vec<(&LoadBlock, f64)> = asked.iter().map(|&(i, g)| (&blocks[i], g)).collect();
        let amplitudes = setup.amplitude_blocks(req, &trials);
        for (&(i, _), a) in asked.iter().zip(amplitudes) {
            if let Some(search) = &mut searches[i] {
                search.tell(a);
            }
        }
    }
    stripes
        .into_iter()
        .zip(records)
        .zip(capacities)
        .map(|((stripe, record), capacity)| stripe_row(scene, stripe, record, capacity))
        .collect()
}

/// The capacity search of a motion of own intensity `own` first run at `gain` (`record`), where
/// `capacity` and the scene has a threshold: the search [`motion_row`] runs.
fn search(
    scene: &RandomScene,
    spec: &IntensitySpec,
    capacity: bool,
    own: OwnIntensity,
    (gain, record): (f64, &RandomRecord),
) -> Option<ida::Search> {
    let i0 = own.of(spec.measure);
    let b = scene.threshold.filter(|_| capacity && i0 > 0.0)?;
    let amplitude = if record.outcome == Outcome::Ok {
        record.amplitude
    } else {
        f64::NAN
    };
    Some(ida::Search::new(
        i0,
        b,
        (gain, amplitude),
        spec.ida_tol,
        spec.ida_max,
    ))
}

/// The row of a motion run at its stripe (`(own, gain)`, [`RandomRun::at_stripe`]): `record`
/// its run there, `capacity` its capacity where it was searched.
fn stripe_row(
    scene: &RandomScene,
    (own, gain): (OwnIntensity, f64),
    record: RandomRecord,
    capacity: Option<ida::Capacity>,
) -> RealizationRecord {
    let mut row = RealizationRecord::new(scene, record);
    row.own = Some(own);
    row.load[5] = Some(gain);
    row.capacity = capacity;
    row
}
