//! `impactsweep._impactsweep`: the Python binding of the impactsweep library (PyO3, one abi3
//! module). Every function here calls the library the command line calls (the same `Setup`
//! for `simulate`, the same `Study`, plan, sweep engine, store schema and reducer); the Python
//! layer (`impactsweep/__init__.py`) turns its arguments into what these take.
//!
//! Errors: bad input (`InputError` anywhere in the chain) raises `ValueError` with the text the
//! command line prints after `error: `; an interrupted sweep raises `KeyboardInterrupt`; any
//! other failure `RuntimeError`. Long calls release the GIL and look for Ctrl-C every
//! [`POLL`], so `KeyboardInterrupt` stops them within a second.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use arrow_pyarrow::ToPyArrow;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use rayon::prelude::*;

use impactsweep::api::json::insert_system;
use impactsweep::api::random_batch::RandomBatch;
use impactsweep::api::realization::RandomSetup;
use impactsweep::api::setup::{Setup, forced_json, record_json, trace_scene};
use impactsweep::error::{InputError, Interrupted};
use impactsweep::model::SYSTEM_KEYS;
use impactsweep::plan::{Plan, RunSpec};
use impactsweep::sim::random::{
    Excitation, GivenNormals, LoadBlock, Normals, RandomRun, RandomScene, RealizationRecord,
    RealizationStream,
};
use impactsweep::sim::{
    Harmonic, HarmonicRecord, NoProbe, Record, Scene, SceneRecord, SolverSettings,
};
use impactsweep::store::RunRow;
use impactsweep::study::{LoadOptions, Study};
use impactsweep::sweep::{self, SceneRun, SweepOptions};

/// How often a long call looks for Ctrl-C.
const POLL: Duration = Duration::from_millis(20);

/// An error of the library as a Python exception (see the module doc).
/// Whether a batch's rows carry several damper units anywhere: its table then has the `units`
/// and `d_spread` columns, as a study's does.
fn several<R>(rows: &[impactsweep::store::RunRow<R>]) -> bool {
    rows.iter()
        .any(|r| r.system.units != 1.0 || r.system.d_spread != 0.0)
}

fn py_err(err: anyhow::Error) -> PyErr {
    let msg = format!("{err:#}");
    if err
        .chain()
        .any(|e| e.downcast_ref::<Interrupted>().is_some())
    {
        PyKeyboardInterrupt::new_err(msg)
    } else if err
        .chain()
        .any(|e| e.downcast_ref::<InputError>().is_some())
    {
        PyValueError::new_err(msg)
    } else {
        PyRuntimeError::new_err(msg)
    }
}

fn input_err(err: InputError) -> PyErr {
    PyValueError::new_err(err.0)
}

/// A JSON value as Python objects: objects become dicts (in the record's key order), null
/// None, numbers int or float (the same `f64` bits the JSON text round-trips to).
fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => {
            if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| json_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// The setup of `impactsweep simulate --set KEY=VALUE ...`.
fn setup(sets: &[String]) -> PyResult<Setup> {
    let mut s = Setup::default();
    s.apply(sets).map_err(input_err)?;
    Ok(s)
}

/// The record `impactsweep simulate --set ... --json` prints, as a dict.
#[pyfunction]
fn simulate<'py>(py: Python<'py>, sets: Vec<String>) -> PyResult<Bound<'py, PyAny>> {
    let s = setup(&sets)?;
    if let Some(r) = &s.random {
        let (row, _) = py.detach(|| r.run(None)).map_err(input_err)?;
        return json_to_py(py, &r.json(&row));
    }
    let json = match s.run_scene(&mut NoProbe) {
        SceneRecord::Free(rec) => record_json(&s, &rec),
        SceneRecord::Harmonic(rec) => forced_json(&s, &rec),
        SceneRecord::Random(rec) => serde_json::to_value(&rec).unwrap_or_default(),
    };
    json_to_py(py, &json)
}

/// The name a random or record setup's study text goes by; [`random_err`] takes it off the
/// messages.
const RANDOM_FILE: &str = "simulate";

/// A study's message about the keys of `simulate(scene="random")` as the keyword arguments
/// name them: without the file (the Python layer wrote the text) and without the table
/// (`[scene].S0 = -1: ...` reads `S0 = -1: ...`, `[sweep].im` reads `im`, `[solver].kind` reads
/// `solver`).
fn random_err(err: InputError) -> PyErr {
    let msg = err.0;
    let msg = msg
        .strip_prefix(&format!("{RANDOM_FILE}: "))
        .unwrap_or(&msg)
        .replace("[solver].kind", "solver");
    let mut msg = msg.as_str().to_owned();
    for table in ["[scene].", "[system].", "[solver].", "[sweep]."] {
        msg = msg.replace(table, "");
    }
    PyValueError::new_err(msg)
}

/// The one design of a random or record setup: the study text the Python layer writes for
/// `simulate(scene="random", ...)`'s keys, parsed and checked as a study file is (so the same
/// defaults: the structure at rest), and its scene prepared.
struct RandomDesign {
    study: Study,
    system: impactsweep::model::System,
    scene: RandomScene,
    run: RandomRun,
}

impl RandomDesign {
    fn parse(text: &str) -> PyResult<RandomDesign> {
        let study = Study::parse(Path::new(RANDOM_FILE), text).map_err(random_err)?;
        // Design point 0: the study's scene with its one stripe `im` set.
        let (system, scene) = Plan::new(&study).point(0);
        let Scene::Random(scene) = scene else {
            return Err(PyValueError::new_err(
                "scene: the random or record scene's setup has no [scene] kind (a bug: please \
                 report it)",
            ));
        };
        let run = RandomRun::new(&system, &study.solver, &scene);
        Ok(RandomDesign {
            study,
            system,
            scene,
            run,
        })
    }

    /// The load's samples of one run ([`RandomRun::load`]): realization `realization` of study
    /// seed `seed`, or the standard normals `normals` (f64 bytes, checked) in its place; with
    /// the stream it names (`None` for normals or a record).
    fn block(
        &self,
        py: Python<'_>,
        seed: u64,
        realization: u64,
        normals: Option<Bound<'_, PyBytes>>,
    ) -> PyResult<(LoadBlock, Option<(u64, u64)>)> {
        Ok(match normals {
            Some(bytes) => {
                let u = f64s(bytes.as_bytes());
                check_normals(self, &u)?;
                (py.detach(|| self.run.load(GivenNormals::new(&u))), None)
            }
            None => {
                let stream = RealizationStream::new(seed, 0, realization);
                (
                    py.detach(|| self.run.load(stream)),
                    self.scene.draws_normals().then_some((seed, realization)),
                )
            }
        })
    }

    /// The record of one run as a JSON object: the run's observables, then what it ran (the
    /// scene, the stream or `null` for normals handed in or a record, `n_normals`, the system,
    /// the solver and the scene's settings under its name).
    fn json(&self, row: &RealizationRecord, stream: Option<(u64, u64)>) -> serde_json::Value {
        let mut map = match serde_json::to_value(&row.record) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        };
        if self.scene.intensity.is_some() {
            insert_stripe(&mut map, row);
        }
        let kind = if self.scene.draws_normals() {
            "random"
        } else {
            "record"
        };
        map.insert("scene".into(), kind.into());
        let (seed, realization) = match stream {
            Some((s, r)) => (s.into(), r.into()),
            None => (serde_json::Value::Null, serde_json::Value::Null),
        };
        map.insert("seed".into(), seed);
        map.insert("realization".into(), realization);
        map.insert("n_normals".into(), self.run.n_normals().into());
        insert_system(&mut map, &self.system, &self.study.solver);
        map.insert(kind.into(), self.scene_json());
        serde_json::Value::Object(map)
    }

    /// The scene's settings under the study file's keys (`input dt duration threshold`, a random
    /// load's `spectrum S0`, its filter's keys and `envelope`; a record's `scale` and
    /// `record_samples`, the samples it holds).
    fn scene_json(&self) -> serde_json::Value {
        let num =
            |v: f64| serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, Into::into);
        let sc = &self.scene;
        let mut m = serde_json::Map::new();
        m.insert("input".into(), sc.input.name().into());
        match &sc.excitation {
            Excitation::Random(r) => {
                m.insert("spectrum".into(), r.spectrum.name().into());
                for k in RandomScene::AXES {
                    if let Some(v) = sc.get(k) {
                        m.insert(k.into(), num(v));
                    }
                }
                let envelope = r.envelope.map_or(
                    serde_json::Value::Null,
                    |e| serde_json::json!({"t1": num(e.t1), "t2": num(e.t2), "c": num(e.c)}),
                );
                m.insert("envelope".into(), envelope);
            }
            Excitation::Record(r) => {
                m.insert("scale".into(), num(r.scale));
                m.insert("record_samples".into(), r.values.len().into());
            }
            Excitation::Suite(s) => {
                m.insert("scale".into(), num(s.scale));
                let names: Vec<serde_json::Value> =
                    s.records.iter().map(|r| r.name.clone().into()).collect();
                m.insert("records".into(), names.into());
            }
        }
        m.insert("dt".into(), num(sc.dt));
        m.insert("duration".into(), num(sc.duration));
        m.insert(
            "threshold".into(),
            sc.threshold.map_or(serde_json::Value::Null, num),
        );
        if let Some(spec) = sc.intensity {
            m.insert("intensity".into(), spec.measure.name().into());
            m.insert("T".into(), num(spec.period));
            m.insert("ida_tol".into(), num(spec.ida_tol));
            m.insert("ida_max".into(), num(spec.ida_max));
        }
        serde_json::Value::Object(m)
    }
}

/// A run under an intensity measure: the motion's own `pga` and `sa` (g, at scale 1), the
/// `scale` it ran at (`im / own`) and its capacity (`capacity` g, `capacity_censored`,
/// `capacity_resurrected`, `capacity_runs`; null where not searched), under the names of the
/// `random_points` table (docs/schema.md).
fn insert_stripe(map: &mut serde_json::Map<String, serde_json::Value>, row: &RealizationRecord) {
    let num = |v: f64| serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, Into::into);
    let opt = |v: Option<f64>| v.map_or(serde_json::Value::Null, num);
    map.insert("pga".into(), opt(row.own.map(|o| o.pga)));
    map.insert("sa".into(), opt(row.own.map(|o| o.sa)));
    map.insert("scale".into(), opt(row.load[5]));
    let c = row.capacity;
    map.insert("capacity".into(), opt(c.map(|c| c.capacity)));
    let flag = |f: Option<bool>| f.map_or(serde_json::Value::Null, Into::into);
    map.insert("capacity_censored".into(), flag(c.map(|c| c.censored)));
    map.insert(
        "capacity_resurrected".into(),
        flag(c.map(|c| c.resurrected)),
    );
    map.insert(
        "capacity_runs".into(),
        c.map_or(serde_json::Value::Null, |c| c.runs.into()),
    );
}

/// One run of the random or record scene: the setup of study text `text` (its one design),
/// realization `realization` of study seed `seed` (the stream the sweep's row of that
/// realization draws, [`Plan::load_stream`]), or the standard normals `normals` (f64 bytes,
/// native endian, exactly `n_normals` of them) in its place. Under an intensity measure the
/// motion runs at the study's stripe `im` (`[sweep] im = [im]`) as the sweep runs it
/// ([`sweep::random::motion_row`]), with its capacity where `capacity` and a threshold.
/// Returns the record as a dict.
#[pyfunction]
#[pyo3(signature = (text, seed, realization, normals=None, capacity=true))]
fn simulate_random<'py>(
    py: Python<'py>,
    text: &str,
    seed: u64,
    realization: u64,
    normals: Option<Bound<'py, PyBytes>>,
    capacity: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let d = RandomDesign::parse(text)?;
    let req = d.study.request;
    let (block, stream) = d.block(py, seed, realization, normals)?;
    let row = py.detach(|| {
        sweep::random::motion_row(&d.run, &req, &d.scene, (&block, capacity), &mut NoProbe)
    });
    json_to_py(py, &d.json(&row, stream))
}

/// The most rows a random or record trace holds (`duration / dt`): 10^7 rows are 400 MB.
const MAX_TRACE_ROWS: f64 = 1e7;

/// One run of the random or record scene with its waveform: the motion of
/// [`simulate_random`] (the same stream or normals, at the same stripe), its state every `dt`
/// seconds and at every impact. Returns `(record, samples, impacts, load)`: the record as
/// `simulate_random` returns it without the capacity search (`capacity` null), the samples as
/// bytes of `t x v y w` rows, the impact times, and the load's samples at the stripe's scale
/// (`t_k = k dt` of the load; m/s^2 or N), all f64 bytes, native endian.
#[pyfunction]
#[pyo3(signature = (text, seed, realization, normals, dt))]
#[allow(clippy::type_complexity)]
fn trace_random<'py>(
    py: Python<'py>,
    text: &str,
    seed: u64,
    realization: u64,
    normals: Option<Bound<'py, PyBytes>>,
    dt: f64,
) -> PyResult<(
    Bound<'py, PyAny>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
)> {
    let d = RandomDesign::parse(text)?;
    let req = d.study.request;
    let traced = impactsweep::sim::Request {
        trace_dt: Some(dt),
        ..req
    };
    traced
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let rows = d.scene.duration / dt;
    if rows > MAX_TRACE_ROWS {
        let fmt = impactsweep::model::fmt_value;
        return Err(PyValueError::new_err(format!(
            "dt={}: the trace of a {} s run would hold {} rows; allowed at most 1e7 (dt >= \
             duration / 1e7 = {} s)",
            fmt(dt),
            fmt(d.scene.duration),
            fmt(rows.round()),
            fmt(d.scene.duration / MAX_TRACE_ROWS)
        )));
    }
    let (block, stream) = d.block(py, seed, realization, normals)?;
    // The record and its impact times from the run as the sweep takes it; the trace from a
    // second run at its scale (a traced run takes every interval through the event loop).
    let mut times = ImpactTimes::default();
    let row = py
        .detach(|| sweep::random::motion_row(&d.run, &req, &d.scene, (&block, false), &mut times));
    let gain = row.load[5]
        .filter(|_| d.scene.intensity.is_some())
        .unwrap_or(1.0);
    let mut probe = impactsweep::sim::TraceProbe::default();
    py.detach(|| d.run.run_block(&traced, &block, gain, &mut probe));
    let load: Vec<f64> = block.values().iter().map(|a| a * gain).collect();
    Ok((
        json_to_py(py, &d.json(&row, stream))?,
        PyBytes::new(py, &trace_rows(&probe.rows)),
        PyBytes::new(py, &f64_bytes(&times.times)),
        PyBytes::new(py, &f64_bytes(&load)),
    ))
}

/// Normals handed in: a random load's, exactly `n_normals` of them, every one finite.
fn check_normals(d: &RandomDesign, u: &[f64]) -> PyResult<()> {
    if !d.scene.draws_normals() {
        return Err(PyValueError::new_err(
            "normals: a record's load draws no normals; leave normals out",
        ));
    }
    let n = d.run.n_normals();
    if u.len() != n {
        return Err(PyValueError::new_err(format!(
            "normals: {} values; this load draws n_normals = {n} standard normals ({} load \
             intervals of dt: one normal per sample for white noise, one per interval through a \
             filter)",
            u.len(),
            d.run.segments()
        )));
    }
    if let Some((i, v)) = u.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "normals[{i}] = {v}: a standard normal must be finite"
        )));
    }
    Ok(())
}

/// The standard normals one run of the random setup `text` draws (0 for a record).
#[pyfunction]
fn random_n_normals(text: &str) -> PyResult<usize> {
    Ok(RandomDesign::parse(text)?.run.n_normals())
}

/// The first `n` standard normals of realization `realization`'s load stream under study seed
/// `seed` (f64 bytes, native endian): what its run draws, in order.
#[pyfunction]
fn realization_normals<'py>(
    py: Python<'py>,
    seed: u64,
    realization: u64,
    n: usize,
) -> PyResult<Bound<'py, PyBytes>> {
    if n > MAX_NORMALS {
        return Err(PyValueError::new_err(format!(
            "n={n}: allowed 0 ..= {MAX_NORMALS} (a run draws at most one normal per load sample)"
        )));
    }
    let mut s = RealizationStream::new(seed, 0, realization);
    let bytes: Vec<u8> = (0..n).flat_map(|_| s.next_normal().to_ne_bytes()).collect();
    Ok(PyBytes::new(py, &bytes))
}

/// Most normals [`realization_normals`] gives: a run's most load samples, and one.
const MAX_NORMALS: usize = impactsweep::sim::random::MAX_SAMPLES as usize + 1;

/// `f64`s from native-endian bytes (a NumPy float64 buffer).
fn f64s(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|b| f64::from_ne_bytes(b.try_into().unwrap_or([0; 8])))
        .collect()
}

/// Runs `f` on a scoped thread with the GIL released, looking for Ctrl-C every [`POLL`]: on
/// one, `on_interrupt` is called (it must make `f` end soon), the thread joined, and the
/// signal's error (`KeyboardInterrupt`) returned.
fn interruptible<T: Send>(
    py: Python<'_>,
    on_interrupt: impl Fn(),
    f: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let finished = (Mutex::new(false), Condvar::new());
    let finished = &finished;
    std::thread::scope(|scope| {
        let handle = scope.spawn(move || {
            let out = f();
            *finished.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
            finished.1.notify_all();
            out
        });
        loop {
            // Wakes as soon as `f` is done, else every POLL to look for Ctrl-C.
            let done = py.detach(|| {
                let guard = finished.0.lock().unwrap_or_else(|e| e.into_inner());
                let (guard, _) = finished
                    .1
                    .wait_timeout_while(guard, POLL, |done| !*done)
                    .unwrap_or_else(|e| e.into_inner());
                *guard
            });
            if done {
                break;
            }
            if let Err(e) = py.check_signals() {
                on_interrupt();
                let _ = py.detach(|| handle.join());
                return Err(e);
            }
        }
        py.detach(|| handle.join())
            .map_err(|_| PyRuntimeError::new_err("a worker panicked (a bug: please report it)"))
    })
}

/// Batches of up to this many rows run on the calling thread (GIL released) without a watcher
/// thread: a few milliseconds at most, and no thread to start for the one-point calls that
/// FORM or an optimiser make.
const INLINE_ROWS: usize = 64;

/// One run per row: `names[j]` takes `columns[j][i]` in row `i`, over the setup of `sets`.
/// Returns a pyarrow RecordBatch with the columns of the scene's points table. With
/// `scene=random` or `scene=record` among `sets` a row is one realization (the `realization`
/// column, else the setup's) of the one-point study of the keys and the row's values, under
/// study seed `seed` ([`impactsweep::api::random_batch`]): the `random_points` table.
///
/// `normals` (random scene only; f64 bytes, native endian, `n_rows` rows of `n_normals`
/// standard normals): row `i` runs on its row of normals in place of a realization's stream.
/// `capacity` (random and record scenes): whether a row at its stripe with a threshold searches
/// the motion's capacity ([`RandomBatch::run`]).
#[pyfunction]
#[pyo3(signature = (sets, names, columns, n_rows, threads=None, seed=0, normals=None, capacity=true))]
#[allow(clippy::too_many_arguments)]
fn simulate_batch<'py>(
    py: Python<'py>,
    sets: Vec<String>,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
    n_rows: usize,
    threads: Option<usize>,
    seed: u64,
    normals: Option<Bound<'py, PyBytes>>,
    capacity: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let base = setup(&sets)?;
    let study = batch_study(&base, seed)?;
    let cols: Vec<Vec<f64>> = columns.iter().map(|b| f64s(b.as_bytes())).collect();
    if base.random.is_none() {
        check_columns(&base, &names, &cols, n_rows)?;
    }
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads=0: must be at least 1"));
    }
    let inputs = Inputs {
        base: &base,
        names: &names,
        cols: &cols,
        n: n_rows,
    };
    // A pool of `threads`, else rayon's global pool (every core, started once per process).
    let pool = match threads {
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("starting the thread pool: {e}")))?,
        ),
        None => None,
    };
    let settings = base.solver;
    let batch = match base.scene {
        Scene::Free => {
            let rows = run_rows::<Record>(py, pool.as_ref(), &inputs, &study)?
                .map_err(PyValueError::new_err)?;
            impactsweep::store::points::to_batch(&rows, &settings, several(&rows))
        }
        Scene::Harmonic(_) => {
            let rows = run_rows::<HarmonicRecord>(py, pool.as_ref(), &inputs, &study)?
                .map_err(PyValueError::new_err)?;
            impactsweep::store::points::to_batch(&rows, &settings, several(&rows))
        }
        Scene::Random(_) => {
            let Some(r) = base.random.as_deref() else {
                return Err(PyValueError::new_err(
                    "scene: a random setup without its study (a bug: please report it)",
                ));
            };
            let normals = normals.map(|b| f64s(b.as_bytes()));
            let rows = random_rows(
                py,
                pool.as_ref(),
                r,
                seed,
                (&names, &cols, n_rows),
                (normals.as_deref(), capacity),
            )?;
            impactsweep::store::points::to_batch(&rows, &r.study.solver, false)
        }
    }
    .map_err(py_err)?;
    batch.to_pyarrow(py)
}

/// The rows of a random or record batch (module doc of [`impactsweep::api::random_batch`]) on
/// `pool` (or the global one), every row checked before the first runs, stopped by Ctrl-C.
fn random_rows(
    py: Python<'_>,
    pool: Option<&rayon::ThreadPool>,
    setup: &RandomSetup,
    seed: u64,
    (names, cols, n): (&[String], &[Vec<f64>], usize),
    (normals, capacity): (Option<&[f64]>, bool),
) -> PyResult<Vec<RunRow<RealizationRecord>>> {
    if setup.has("seed") {
        return Err(PyValueError::new_err(format!(
            "seed={}: the study seed of a batch is its seed argument; leave seed out of the keys",
            setup.study.seed
        )));
    }
    let mut setup = setup.clone();
    setup.study.seed = seed;
    let setup = &setup;
    let batch = RandomBatch::new(setup, names, cols, n).map_err(PyValueError::new_err)?;
    let per_row = match normals {
        Some(u) => Some(check_batch_normals(setup, &batch, names, u, n)?),
        None => None,
    };
    let stop = AtomicBool::new(false);
    let all = || -> Result<Vec<RunRow<RealizationRecord>>, String> {
        if let Some(msg) = (0..n)
            .into_par_iter()
            .find_map_first(|i| batch.row(i).err())
        {
            return Err(msg);
        }
        Ok((0..n)
            .into_par_iter()
            .filter_map(|i| {
                if stop.load(Ordering::Relaxed) {
                    return None;
                }
                let (study, case) = batch.row(i).ok()?;
                let u = normals.zip(per_row).map(|(u, k)| &u[i * k..][..k]);
                Some(RandomBatch::run(i, &study, case, u, capacity))
            })
            .collect())
    };
    let work = || match pool {
        Some(p) => p.install(all),
        None => all(),
    };
    let rows = if n <= INLINE_ROWS {
        py.detach(work)
    } else {
        interruptible(py, || stop.store(true, Ordering::SeqCst), work)?
    };
    rows.map_err(PyValueError::new_err)
}

/// Normals handed to a batch: a random load's (not a record's), without a realization to name
/// the stream they replace, `n` rows of `n_normals`, every one finite. Returns `n_normals`.
fn check_batch_normals(
    setup: &RandomSetup,
    batch: &RandomBatch,
    names: &[String],
    u: &[f64],
    n: usize,
) -> PyResult<usize> {
    if !setup.scene().draws_normals() {
        return Err(PyValueError::new_err(
            "normals: a record's load draws no normals; leave normals out",
        ));
    }
    if setup.has("realization") || names.iter().any(|k| k == "realization") {
        return Err(PyValueError::new_err(
            "normals: given with realization; the normals replace the stream it names",
        ));
    }
    let k = batch.n_normals();
    if u.len() != n * k {
        return Err(PyValueError::new_err(format!(
            "normals: {} values for {n} rows; this load draws n_normals = {k} standard normals \
             a run (one row of normals per row of the batch)",
            u.len()
        )));
    }
    if let Some((i, v)) = u.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "normals[{}, {}] = {v}: a standard normal must be finite",
            i / k.max(1),
            i % k.max(1)
        )));
    }
    Ok(k)
}

/// The batch's rows: `base` with row `i` of the input columns.
struct Inputs<'a> {
    base: &'a Setup,
    names: &'a [String],
    cols: &'a [Vec<f64>],
    n: usize,
}

impl Inputs<'_> {
    /// The setup of row `i`, validated; the error names the row, the key, the value and what is
    /// allowed.
    fn row(&self, i: usize) -> Result<Setup, String> {
        let mut s = self.base.clone();
        for (name, col) in self.names.iter().zip(self.cols) {
            let v = col[i];
            if !s.system.set(name, v) {
                s.scene.set(name, v);
            }
        }
        s.validate().map_err(|e| {
            let msg = e.0.strip_prefix("--set ").unwrap_or(&e.0);
            format!("row {i}: {msg}")
        })?;
        Ok(s)
    }
}

/// The rows of the batch on `pool` (or the global one), stopped by Ctrl-C: every row validated
/// first (`Err`: the first bad row's message), then run.
fn run_rows<R: SceneRun>(
    py: Python<'_>,
    pool: Option<&rayon::ThreadPool>,
    inputs: &Inputs<'_>,
    study: &Study,
) -> PyResult<Result<Vec<RunRow<R>>, String>> {
    let stop = AtomicBool::new(false);
    let all = || -> Result<Vec<RunRow<R>>, String> {
        if let Some(msg) = (0..inputs.n)
            .into_par_iter()
            .find_map_first(|i| inputs.row(i).err())
        {
            return Err(msg);
        }
        Ok(batch_rows::<R>(inputs, study, &stop))
    };
    let work = || match pool {
        Some(p) => p.install(all),
        None => all(),
    };
    if inputs.n <= INLINE_ROWS {
        return Ok(py.detach(work));
    }
    interruptible(py, || stop.store(true, Ordering::SeqCst), work)
}

/// The input columns: known keys of the setup's scene, each once, each `n_rows` long.
fn check_columns(base: &Setup, names: &[String], cols: &[Vec<f64>], n: usize) -> PyResult<()> {
    let harmonic = matches!(base.scene, Scene::Harmonic(_));
    for (j, name) in names.iter().enumerate() {
        let scene_key = Harmonic::AXES.contains(&name.as_str());
        if !SYSTEM_KEYS.contains(&name.as_str()) && !scene_key {
            let mut allowed: Vec<&str> = SYSTEM_KEYS.to_vec();
            allowed.extend(Harmonic::AXES);
            return Err(PyValueError::new_err(format!(
                "input column '{name}': unknown key; allowed: {}",
                allowed.join(" ")
            )));
        }
        if scene_key && !harmonic {
            return Err(PyValueError::new_err(format!(
                "input column '{name}': a key of the harmonic scene; add scene=\"harmonic\""
            )));
        }
        if names[..j].contains(name) {
            return Err(PyValueError::new_err(format!(
                "input column '{name}': given twice"
            )));
        }
        if cols[j].len() != n {
            return Err(PyValueError::new_err(format!(
                "input column '{name}': {} values for {n} rows",
                cols[j].len()
            )));
        }
    }
    if names.iter().any(|n| n == "omega") && names.iter().any(|n| n == "r") {
        return Err(PyValueError::new_err(
            "input columns 'omega' and 'r': give the forcing frequency once, as omega (rad/s) \
             or as r = omega / sqrt(K/M)",
        ));
    }
    Ok(())
}

/// The one-case, noise-free study a batch's rows are the runs of: the base setup's solver,
/// request and scene, the study seed `seed` (it seeds whatever a run draws from its study seed
/// and design point), no axes. Row `i` is its design point `i`.
fn batch_study(base: &Setup, seed: u64) -> PyResult<Study> {
    let mut study =
        Study::parse(Path::new("batch.toml"), "[study]\nname = \"batch\"\n").map_err(input_err)?;
    study.seed = seed;
    study.solver = base.solver;
    study.request = base.request;
    study.scene = base.scene.clone();
    study.system = base.system;
    Ok(study)
}

/// The rows of the batch, in input order, on the current rayon pool: row `i` is simulated by
/// the sweep engine's own per-run function ([`sweep::run_row`]) as run `i` of [`batch_study`]
/// (`point_id = point = i`, the ideal case). Once `stop` is set the remaining runs are skipped
/// (the result is then discarded).
fn batch_rows<R: SceneRun>(
    inputs: &Inputs<'_>,
    study: &Study,
    stop: &AtomicBool,
) -> Vec<RunRow<R>> {
    let plan = Plan::new(study);
    let spec = study.cases[0];
    (0..inputs.n)
        .into_par_iter()
        .filter_map(|i| {
            if stop.load(Ordering::Relaxed) {
                return None;
            }
            let s = inputs.row(i).ok()?;
            let run = RunSpec {
                point_id: i as u64,
                point: i as u64,
                case: 0,
                system: s.system,
                scene: s.scene,
                spec,
            };
            Some(sweep::run_row::<R>(&plan, &run))
        })
        .collect()
}

/// A run with a trace sampled every `dt` and at every impact: `(record, samples, impacts)`,
/// the samples as bytes of `t x v y w` rows (f64, native endian), the impact times as f64
/// bytes.
#[pyfunction]
#[pyo3(signature = (sets, dt, t_end=None))]
fn trace<'py>(
    py: Python<'py>,
    sets: Vec<String>,
    dt: f64,
    t_end: Option<f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
    let mut s = setup(&sets)?;
    if s.random.is_some() {
        return Err(PyValueError::new_err(
            "trace: a random or record setup (a bug: the Python layer sends it to trace_random)",
        ));
    }
    if let Some(t) = t_end {
        if matches!(s.scene, Scene::Harmonic(_)) {
            return Err(PyValueError::new_err(format!(
                "t_end={t}: a free-decay option; the harmonic scene runs n_trans + n_meas forcing \
                 periods"
            )));
        }
        s.request.t_end = Some(t);
    }
    let check = impactsweep::sim::Request {
        trace_dt: Some(dt),
        ..s.request
    };
    check
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let (rec, rows) = py.detach(|| trace_scene(&s, dt));
    let json = match &rec {
        SceneRecord::Free(r) => record_json(&s, r),
        SceneRecord::Harmonic(r) => forced_json(&s, r),
        SceneRecord::Random(r) => serde_json::to_value(r).unwrap_or_default(),
    };
    // Impact rows are the trace's rows that are not on the dt grid: the probe records them
    // with the state just before; the Python layer gets their times from a second pass.
    let mut probe = ImpactTimes::default();
    let mut s2 = s.clone();
    s2.request.trace_dt = None;
    py.detach(|| s2.run_scene(&mut probe));
    Ok((
        json_to_py(py, &json)?,
        PyBytes::new(py, &trace_rows(&rows)),
        PyBytes::new(py, &f64_bytes(&probe.times)),
    ))
}

/// A trace's rows as bytes of `t x v y w` rows (f64, native endian).
fn trace_rows(rows: &[(f64, impactsweep::sim::State)]) -> Vec<u8> {
    let mut out = Vec::with_capacity(rows.len() * 40);
    for (t, st) in rows {
        for v in [*t, st.x, st.v, st.y, st.w] {
            out.extend_from_slice(&v.to_ne_bytes());
        }
    }
    out
}

/// Values as f64 bytes, native endian.
fn f64_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_ne_bytes()).collect()
}

/// The per-period maxima of `|x|` of the harmonic setup's motion from its initial state: `burn`
/// forcing periods dropped, then `periods` recorded (f64 bytes, native endian).
#[pyfunction]
#[pyo3(signature = (sets, periods, burn))]
fn period_maxima<'py>(
    py: Python<'py>,
    sets: Vec<String>,
    periods: u64,
    burn: u64,
) -> PyResult<Bound<'py, PyBytes>> {
    let s = setup(&sets)?;
    let Scene::Harmonic(h) = s.scene else {
        return Err(PyValueError::new_err(
            "period_maxima: a harmonic-scene function; add scene=\"harmonic\"",
        ));
    };
    if periods == 0 || periods > 100_000_000 {
        return Err(PyValueError::new_err(format!(
            "periods={periods}: allowed 1 ..= 1e8"
        )));
    }
    let sys = s.system;
    let f = impactsweep::orbits::map::Forcing {
        sys,
        F0: h.F0,
        omega: h.omega(&sys),
        settings: s.solver,
    };
    let s0 = [sys.x0, sys.v0, sys.y0 - sys.x0, sys.w0];
    let z = py
        .detach(|| impactsweep::orbits::life::period_maxima(&f, &s0, burn, periods))
        .ok_or_else(|| {
            PyRuntimeError::new_err(
                "period_maxima: the simulator stopped (event_cap, step_cap or non_finite)",
            )
        })?;
    Ok(PyBytes::new(py, &f64_bytes(&z)))
}

/// The peaks-over-threshold estimate of the largest value over `design_periods` periods from
/// per-period maxima (f64 bytes): the dict of its fields, or `None` when no threshold leaves
/// enough clusters.
#[pyfunction]
#[pyo3(signature = (maxima, design_periods, quantile, run, xi_min, xi_max))]
fn life_estimate<'py>(
    py: Python<'py>,
    maxima: Bound<'py, PyBytes>,
    design_periods: f64,
    quantile: f64,
    run: usize,
    xi_min: f64,
    xi_max: f64,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    use impactsweep::stats::extremes::{Life, XI_MAX, life_pot};
    let z = f64s(maxima.as_bytes());
    if !(design_periods.is_finite() && design_periods >= 1.0) {
        return Err(PyValueError::new_err(format!(
            "design_periods={design_periods}: allowed a finite number >= 1"
        )));
    }
    if !(quantile > 0.0 && quantile < 1.0) {
        return Err(PyValueError::new_err(format!(
            "quantile={quantile}: allowed 0 < quantile < 1"
        )));
    }
    if run == 0 {
        return Err(PyValueError::new_err("run=0: allowed at least 1"));
    }
    if !(xi_max.is_finite() && (-XI_MAX..=XI_MAX).contains(&xi_max)) {
        return Err(PyValueError::new_err(format!(
            "xi_max={xi_max}: allowed [-{XI_MAX}, {XI_MAX}]"
        )));
    }
    if !(xi_min.is_finite() && -XI_MAX <= xi_min && xi_min <= xi_max) {
        return Err(PyValueError::new_err(format!(
            "xi_min={xi_min}: allowed [-{XI_MAX}, xi_max={xi_max}]"
        )));
    }
    if let Some(v) = z.iter().find(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!("maxima: {v} is not finite")));
    }
    let life = Life {
        n_life: design_periods,
        q: quantile,
        xi_min,
        xi_max,
    };
    let Some(e) = py.detach(|| life_pot(&[z.as_slice()], run, life)) else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    for (k, v) in [
        ("amplitude", e.amplitude),
        ("lo", e.lo),
        ("hi", e.hi),
        ("threshold", e.threshold),
        ("sigma", e.sigma),
        ("xi", e.xi),
        ("xi_se", e.xi_se),
        ("end_point", e.end_point),
    ] {
        d.set_item(k, v)?;
    }
    d.set_item("exceedances", e.exceedances)?;
    d.set_item("measured", e.measured)?;
    Ok(Some(d))
}

#[derive(Default)]
struct ImpactTimes {
    times: Vec<f64>,
}

impl impactsweep::sim::Probe for ImpactTimes {
    fn impact(
        &mut self,
        t: f64,
        _wall: impactsweep::sim::Wall,
        _before: &impactsweep::sim::State,
        _after: &impactsweep::sim::State,
    ) {
        self.times.push(t);
    }
}

/// A study from its file, or from TOML text (`path` then names it in messages).
fn load_study(path: &str, text: Option<&str>, allow_large: bool) -> PyResult<Study> {
    let opts = LoadOptions { allow_large };
    match text {
        Some(t) => Study::parse_with(Path::new(path), t, opts),
        None => Study::load_with(Path::new(path), opts),
    }
    .map_err(input_err)
}

/// `impactsweep plan`: the study's sizes and the plan's text (with its timed sample).
#[pyfunction]
#[pyo3(signature = (path, text, out, allow_large=false))]
fn plan<'py>(
    py: Python<'py>,
    path: &str,
    text: Option<&str>,
    out: PathBuf,
    allow_large: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let study = load_study(path, text, allow_large)?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let text = py.detach(|| {
        let sample = impactsweep::api::plan::time_sample(&study);
        impactsweep::api::plan::describe(&study, &out, threads, Some(sample))
    });
    let p = Plan::new(&study);
    let d = PyDict::new(py);
    d.set_item("name", &study.name)?;
    d.set_item("scene", study.scene.name())?;
    d.set_item("n_points", p.n_points())?;
    d.set_item("n_cases", p.n_cases())?;
    d.set_item("n_runs", p.n_runs())?;
    d.set_item("n_chunks", p.n_chunks())?;
    let axes = PyDict::new(py);
    for a in &study.axes {
        axes.set_item(&a.key, a.values.clone())?;
    }
    d.set_item("axes", axes)?;
    d.set_item("run_dir", sweep::run_dir(&out, &study))?;
    d.set_item("text", text)?;
    Ok(d)
}

/// `impactsweep run` of one study (and `--reduce`): a dict of what it did.
#[pyfunction]
#[pyo3(signature = (path, text, out, resume=false, reduce=false, threads=None, chunk_points=None, allow_large=false, stop_after=None))]
#[allow(clippy::too_many_arguments)]
fn run<'py>(
    py: Python<'py>,
    path: &str,
    text: Option<&str>,
    out: PathBuf,
    resume: bool,
    reduce: bool,
    threads: Option<usize>,
    chunk_points: Option<u64>,
    allow_large: bool,
    stop_after: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let study = load_study(path, text, allow_large)?;
    let opts = SweepOptions {
        threads,
        resume,
        chunk_points,
        stop_after,
        ..SweepOptions::default()
    };
    sweep::clear_stop();
    // On Ctrl-C the engine is asked to stop, as the command's handler does: it writes the
    // chunks in hand and releases its lock, and `resume=True` continues the run.
    let result = interruptible(py, sweep::request_stop, || {
        sweep::run_study(&study, &out, &opts)
    });
    sweep::clear_stop();
    let summary = result?.map_err(py_err)?;
    let dir = summary.dir.clone();
    let d = PyDict::new(py);
    d.set_item("run_dir", &dir)?;
    d.set_item("runs", summary.runs)?;
    d.set_item("chunks_written", summary.chunks_written)?;
    d.set_item("chunks_kept", summary.chunks_kept)?;
    d.set_item("chunks_left", summary.chunks_left)?;
    d.set_item("outcomes", summary.outcomes.clone())?;
    d.set_item("seconds", summary.wall.as_secs_f64())?;
    d.set_item("line", summary.line(&study.name))?;
    if reduce && summary.chunks_left == 0 {
        let line = reduce_dir(
            py,
            &dir,
            Some(impactsweep::reduce::random::subset::DEFAULT_SUBSET_N),
            1,
        )?;
        d.set_item("reduce", line)?;
    }
    Ok(d)
}

fn reduce_dir(
    py: Python<'_>,
    dir: &Path,
    subset: Option<usize>,
    subset_repeats: usize,
) -> PyResult<String> {
    let args = impactsweep::api::reduce::ReduceArgs {
        dir: dir.to_path_buf(),
        subset,
        subset_repeats,
        ..Default::default()
    };
    py.detach(|| impactsweep::api::reduce::reduce_dir(&args))
        .map(|(line, _)| line)
        .map_err(py_err)
}

/// `impactsweep reduce RUN_DIR` (and `--subset N`, 1000 by default, 0 for Monte Carlo alone;
/// `--subset-repeats R`, 1 by default): its summary line.
#[pyfunction]
#[pyo3(signature = (dir, subset=impactsweep::reduce::random::subset::DEFAULT_SUBSET_N, subset_repeats=1))]
fn reduce(py: Python<'_>, dir: PathBuf, subset: usize, subset_repeats: usize) -> PyResult<String> {
    if !(1..=1000).contains(&subset_repeats) {
        return Err(PyValueError::new_err(format!(
            "subset_repeats={subset_repeats}: expected a whole number of independent subset \
             simulations per design in [1, 1000]"
        )));
    }
    // The command line's `--subset N` check (subset simulation's chains of 10 need 10 seeds).
    if subset != 0 && !((100..=1_000_000).contains(&subset) && subset.is_multiple_of(10)) {
        return Err(PyValueError::new_err(format!(
            "subset={subset}: expected 0 (Monte Carlo only) or a whole number of samples per \
             level, a multiple of 10 in [100, 1000000]"
        )));
    }
    reduce_dir(py, &dir, (subset > 0).then_some(subset), subset_repeats)
}

/// `impactsweep status RUN_DIR`, as a dict (with the command's text).
#[pyfunction]
fn status<'py>(py: Python<'py>, dir: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let st = py.detach(|| sweep::status(&dir)).map_err(py_err)?;
    let d = PyDict::new(py);
    d.set_item("complete", st.complete())?;
    d.set_item("n_chunks", st.manifest.n_chunks)?;
    d.set_item("n_runs", st.manifest.n_runs)?;
    d.set_item("runs_done", st.runs_done)?;
    d.set_item("done", st.done.clone())?;
    d.set_item("missing", st.missing.clone())?;
    d.set_item(
        "damaged",
        st.damaged.iter().map(|(k, _)| *k).collect::<Vec<_>>(),
    )?;
    // The math library's fingerprint that wrote the records (None before it was recorded), and
    // this process's (docs/run.md, "Determinism across machines").
    d.set_item("math", st.manifest.math.clone())?;
    d.set_item("math_here", impactsweep::sim::math::fingerprint())?;
    d.set_item("text", st.report(&dir))?;
    Ok(d)
}

/// The system keys and the solver defaults, for the Python layer's docs and checks.
#[pyfunction]
fn keys() -> (Vec<&'static str>, Vec<&'static str>, Vec<&'static str>) {
    (
        SYSTEM_KEYS.to_vec(),
        SolverSettings::KEYS.to_vec(),
        Harmonic::KEYS.to_vec(),
    )
}

#[pymodule]
fn _impactsweep(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_random, m)?)?;
    m.add_function(wrap_pyfunction!(random_n_normals, m)?)?;
    m.add_function(wrap_pyfunction!(realization_normals, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_batch, m)?)?;
    m.add_function(wrap_pyfunction!(trace, m)?)?;
    m.add_function(wrap_pyfunction!(trace_random, m)?)?;
    m.add_function(wrap_pyfunction!(period_maxima, m)?)?;
    m.add_function(wrap_pyfunction!(life_estimate, m)?)?;
    m.add_function(wrap_pyfunction!(plan, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(reduce, m)?)?;
    m.add_function(wrap_pyfunction!(status, m)?)?;
    m.add_function(wrap_pyfunction!(keys, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
