//! Study files: TOML → validated [`Study`].
//!
//! CONTRACT (shared by the sweep engine and the reducer): the types below are the validated
//! form; later stages never see an unvalidated value. The TOML format is documented in
//! `docs/study.md`. Parsing follows ripgrep's low/high args: `#[serde(deny_unknown_fields)]` raw
//! structs mirror the TOML, one conversion validates units, ranges and cross-field rules.
//!
//! [`Study::parse`] reads the text (`toml_error.rs` turns a syntax or type error into
//! `file:line:col` or `file: [table].key = value: ...`), then hands each table to its own file,
//! which holds the table's raw struct, its validated type and its messages: `[study]` here,
//! `scene.rs`, `system.rs`, `sweep.rs`, `noise.rs`, `perturb.rs` (with the cross-checks over every design
//! point's extremes), `solver.rs`, `reliability.rs`, `zones.rs`, `ranking.rs`, `run.rs`.
//!
//! A study of the random or record scene (`[scene] kind = "random"` or `"record"`) is validated
//! into a [`RandomStudy`] (`random.rs`, the record file in `record.rs`), which [`Study::load`]
//! turns into a [`Study`] of [`Scene::Random`] whose cases are its realizations
//! ([`Study::realizations`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::de::DeTable;

use toml_error::{serde_error, snippet, syntax_error};

use crate::error::InputError;
use crate::model::{RangeError, System, fmt_value};
use crate::sim::random::RandomScene;
use crate::sim::{NoiseSettings, Request, Scene, SolverKind, SolverSettings};
use crate::stats::hazard::SiteHazard;

mod axis;
mod hazard;
mod noise;
mod perturb;
mod random;
mod ranking;
mod record;
mod reliability;
mod run;
mod scene;
mod solver;
mod sweep;
mod system;
mod toml_error;
mod zones;

pub use axis::Axis;
pub use hazard::HAZARD_COPY;
pub use perturb::Case;
pub use random::{DEFAULT_DT, DEFAULT_REALIZATIONS, INTENSITY_KEYS};
pub use ranking::{DiSource, Ranking, VERIFY_PERIODS};
pub use record::{EVEN_TOL, RECORD_COPY, RECORD_COPY_PARQUET, SUITE_COPY, record_copy};
pub use reliability::{Reliability, SafetyForm};
pub use run::{DEFAULT_CHUNK_RUNS, RunSettings, whole_curves};
pub use scene::frequency_axis;
pub use zones::{DeclaredZone, Zones};

/// A validated study.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// The file it was read from.
    pub path: PathBuf,
    /// The TOML text as read (stored next to the dataset and in Parquet metadata).
    pub source: String,
    /// `[study].name`: names the output directory `DIR/<name>/`. `[A-Za-z0-9_.-]+`.
    pub name: String,
    /// `[study].seed`: root of every random stream (noise, bootstrap, audit choice). Default 0.
    pub seed: u64,
    /// What each run must produce (`[study].outputs` / `peaks` / `t_end`): sets the horizon.
    pub request: Request,
    /// `[scene]`: free decay (the default) or the harmonic scene with its fixed settings; the
    /// swept `F0`, `omega` or `r` of a design point come from the plan.
    pub scene: Scene,
    /// `[system]`: base parameters, Table I defaults when absent.
    pub system: System,
    /// `[sweep]`: the swept axes in file order; the design grid is their Cartesian product,
    /// the last axis varying fastest. In a harmonic study the frequency axis (`omega` or `r`)
    /// is moved last, wherever the file has it, so that consecutive design points form one
    /// frequency-response curve.
    pub axes: Vec<Axis>,
    /// `[perturb]`: per design point, the cases to run; `cases[0]` is always the ideal case
    /// (`dm = dd = 0`, no noise) and is marked `ideal`; a listed case equal to it is dropped,
    /// other repeated cases are kept (the paper's Table II repeats one).
    pub cases: Vec<Case>,
    /// `[noise]`: off when absent.
    pub noise: Option<NoiseSettings>,
    /// `[solver]`.
    pub solver: SolverSettings,
    /// `[reliability]`, read by the reducer.
    pub reliability: Reliability,
    /// `[zones]`, read by the reducer.
    pub zones: Zones,
    /// `[ranking]`, read by the reducer.
    pub ranking: Ranking,
    /// `[run]`: engine settings.
    pub run: RunSettings,
    /// A random or record study ([`Scene::Random`]): its runs per design point, the
    /// realizations `0..realizations` (`cases` is empty). 0 in the other scenes, whose runs
    /// are `cases`.
    pub realizations: u64,
    /// A random or record study with a swept intensity: `[scene].design_intensity`, the swept
    /// value its designs are ranked at (one of the axis's values); `None` for the middle one.
    pub design_intensity: Option<f64>,
    /// `[hazard]`: the site's hazard curve of a random or record study with an intensity
    /// measure ([`crate::stats::hazard`]).
    pub hazard: Option<SiteHazard>,
}

/// The default size guard: a study with more runs than this is refused unless the caller
/// passes `allow_large` (`--allow-large` on the command line). 10^7 runs is about ten minutes
/// of noise-free two-peak runs on two cores and about a gigabyte of Parquet.
pub const MAX_RUNS: u64 = 10_000_000;

/// Hard limit on the length of one axis (its values are held in memory: 80 MB at this size).
/// Not lifted by `allow_large`.
pub const MAX_AXIS_VALUES: u64 = 10_000_000;

/// The outputs a study may ask for in `[study].outputs`, with the number of positive
/// half-cycle maxima each needs (the horizon follows from the largest). `xmax` is the larger of
/// the first two maxima (model.md §3), so it needs two.
pub const OUTPUTS: [(&str, usize); 10] = [
    ("x1", 1),
    ("t1", 1),
    ("x2", 2),
    ("t2", 2),
    ("xmax", 2),
    ("di", 2),
    ("impacts", 1),
    ("sticks", 1),
    ("energy_impact", 1),
    ("energy_viscous", 1),
];

/// Options of [`Study::load_with`] and [`Study::parse_with`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Accept a study beyond the size guard [`MAX_RUNS`].
    pub allow_large: bool,
}

impl Study {
    /// Reads and validates a study file with the default size guard ([`MAX_RUNS`]). Errors
    /// name the file, the key, the value and the allowed range; TOML syntax errors give line
    /// and column.
    pub fn load(path: &Path) -> Result<Study, InputError> {
        Study::load_with(path, LoadOptions::default())
    }

    /// [`Study::load`] with options (`allow_large`).
    pub fn load_with(path: &Path, opts: LoadOptions) -> Result<Study, InputError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            InputError::new(format!(
                "{}: cannot read the study file: {e}",
                path.display()
            ))
        })?;
        Study::parse_with(path, &text, opts)
    }

    /// Parses and validates study text with the default size guard; `path` is used in
    /// messages.
    pub fn parse(path: &Path, text: &str) -> Result<Study, InputError> {
        Study::parse_with(path, text, LoadOptions::default())
    }

    /// [`Study::parse`] with options (`allow_large`).
    pub fn parse_with(path: &Path, text: &str, opts: LoadOptions) -> Result<Study, InputError> {
        let study = from_text(path, text)?;
        study.check_size(opts.allow_large)?;
        Ok(study)
    }

    /// The size guard: more than [`MAX_RUNS`] runs is refused unless `allow_large`.
    pub fn check_size(&self, allow_large: bool) -> Result<(), InputError> {
        let runs = self.n_runs();
        if allow_large || runs <= MAX_RUNS {
            return Ok(());
        }
        Err(InputError::new(format!(
            "{}: [sweep] = {} runs ({} design points x {} case{}): more than the size guard of {} \
             runs; pass --allow-large to run it anyway",
            self.path.display(),
            runs,
            self.n_points(),
            self.n_cases(),
            if self.n_cases() == 1 { "" } else { "s" },
            MAX_RUNS
        )))
    }

    /// Number of design points (product of the axis lengths; 1 without axes). Saturates at
    /// `u64::MAX`.
    pub fn n_points(&self) -> u64 {
        self.axes
            .iter()
            .fold(1u64, |n, a| n.saturating_mul(a.values.len() as u64))
    }

    /// Runs per design point: its cases, or a random study's realizations.
    pub fn n_cases(&self) -> u64 {
        match self.scene {
            Scene::Random(_) => self.realizations,
            Scene::Free | Scene::Harmonic(_) => self.cases.len() as u64,
        }
    }

    /// Total runs: points × cases. Saturates at `u64::MAX`.
    pub fn n_runs(&self) -> u64 {
        self.n_points().saturating_mul(self.n_cases())
    }

    /// The axis of a system key, if it is swept.
    pub fn axis(&self, key: &str) -> Option<&Axis> {
        self.axes.iter().find(|a| a.key == key)
    }

    /// The swept frequency axis of a harmonic study (`omega` or `r`; always the last axis).
    pub fn frequency_axis(&self) -> Option<&Axis> {
        match self.scene {
            Scene::Harmonic(_) => frequency_axis(&self.axes).map(|i| &self.axes[i]),
            Scene::Free | Scene::Random(_) => None,
        }
    }

    /// The files a record study reads and their copies in a run directory, relative to it:
    /// `[scene] record` (relative to the study file, or the run directory's copy
    /// [`RECORD_COPY`]), or each record of a suite (`[scene] records`, copied into
    /// [`SUITE_COPY`]` /` under its file name). Empty for any other study.
    pub fn record_files(&self) -> Vec<(PathBuf, PathBuf)> {
        let Scene::Random(r) = &self.scene else {
            return Vec::new();
        };
        if r.draws_normals() {
            return Vec::new();
        }
        let Ok(doc) = self.source.parse::<toml::Table>() else {
            return Vec::new();
        };
        let dir = self.path.parent().unwrap_or(Path::new("."));
        let scene = doc.get("scene");
        if let Some(shown) = scene.and_then(|s| s.get("record")).and_then(|v| v.as_str()) {
            let copy = PathBuf::from(record::record_copy(shown));
            let path = dir.join(shown);
            return vec![(if path.exists() { path } else { dir.join(&copy) }, copy)];
        }
        let Some(records) = scene.and_then(|s| s.get("records")) else {
            return Vec::new();
        };
        let source = match records {
            toml::Value::String(f) => record::SuiteSource::Folder(f),
            toml::Value::Array(a) => {
                let list: Vec<String> = a
                    .iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect();
                return self.suite_copies(&record::SuiteSource::List(&list), dir);
            }
            _ => return Vec::new(),
        };
        self.suite_copies(&source, dir)
    }

    /// A suite's files and their copies ([`Study::record_files`]).
    fn suite_copies(
        &self,
        source: &record::SuiteSource<'_>,
        dir: &Path,
    ) -> Vec<(PathBuf, PathBuf)> {
        record::suite_files(source, dir)
            .map(|files| {
                files
                    .into_iter()
                    .map(|(name, path)| (path, Path::new(SUITE_COPY).join(name)))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The swept intensity the designs are ranked at (`S0`, `scale` or a stripe's `im`):
    /// `[scene].design_intensity`, or else the middle swept value (the lower middle one for an
    /// even count); `None` without an intensity axis.
    pub fn design_intensity_value(&self) -> Option<f64> {
        let axis = self
            .axes
            .iter()
            .find(|a| INTENSITY_KEYS.contains(&a.key.as_str()))?;
        Some(
            self.design_intensity
                .unwrap_or(axis.values[(axis.values.len() - 1) / 2]),
        )
    }

    /// The file a study's hazard table is read from (`[hazard] table` relative to the study
    /// file, or the run directory's copy [`hazard::HAZARD_COPY`]); `None` without one.
    pub fn hazard_path(&self) -> Option<PathBuf> {
        let doc: toml::Table = self.source.parse().ok()?;
        let shown = doc.get("hazard")?.get("table")?.as_str()?;
        let dir = self.path.parent().unwrap_or(Path::new("."));
        Some(hazard::table_path(dir, shown))
    }

    /// Design points per frequency-response curve: the length of the frequency axis of a
    /// harmonic study, 1 otherwise. Chunks hold whole curves.
    pub fn curve_points(&self) -> u64 {
        self.frequency_axis().map_or(1, |a| a.values.len() as u64)
    }
}

// ---------------------------------------------------------------------------------------------
// Raw form: mirrors the TOML, refuses unknown keys and wrong types. Each table's raw struct and
// its validation live in the table's module.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    study: RawHeader,
    scene: Option<scene::RawScene>,
    #[serde(default)]
    system: system::RawSystem,
    #[serde(default)]
    sweep: BTreeMap<String, axis::RawAxis>,
    perturb: Option<perturb::RawPerturb>,
    noise: Option<noise::RawNoise>,
    #[serde(default)]
    solver: solver::RawSolver,
    #[serde(default)]
    reliability: reliability::RawReliability,
    #[serde(default)]
    zones: zones::RawZones,
    #[serde(default)]
    ranking: ranking::RawRanking,
    #[serde(default)]
    run: run::RawRun,
    hazard: Option<hazard::RawHazard>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawHeader {
    name: String,
    seed: Option<u64>,
    outputs: Option<Vec<String>>,
    peaks: Option<u64>,
    t_end: Option<f64>,
}

// ---------------------------------------------------------------------------------------------
// Validation: raw → Study, one table at a time, in file order of the format.

/// Error builder for one file.
pub(super) struct Cx<'a> {
    file: String,
    text: &'a str,
    doc: &'a DeTable<'a>,
}

impl Cx<'_> {
    pub(super) fn err(
        &self,
        loc: &str,
        value: impl std::fmt::Display,
        allowed: impl std::fmt::Display,
    ) -> InputError {
        InputError::new(format!("{}: {loc} = {value}: {allowed}", self.file))
    }

    /// The source text of `[table].key`, on one line.
    pub(super) fn source(&self, table: &str, key: &str) -> String {
        self.doc
            .get(table)
            .and_then(|t| t.get_ref().as_table())
            .and_then(|t| t.get(key))
            .map(|v| snippet(self.text, &v.span()))
            .unwrap_or_default()
    }

    /// The position of a key in the file (for file order of `[sweep]`).
    pub(super) fn key_pos(&self, table: &str, key: &str) -> usize {
        self.doc
            .get(table)
            .and_then(|t| t.get_ref().as_table())
            .and_then(|t| t.get_key_value(key))
            .map(|(k, _)| k.span().start)
            .unwrap_or(usize::MAX)
    }
}

/// A number as a user would write it: shortest round-trip digits, in exponent form when very
/// small or very large (`5e-10`, not `0.0000000005`).
pub fn num(v: f64) -> String {
    fmt_value(v)
}

/// A [`RangeError`]'s value in the same form.
pub(super) fn range_value(e: &RangeError) -> String {
    e.value.parse::<f64>().map_or_else(|_| e.value.clone(), num)
}

/// Parses study text (TOML syntax, then the raw form) and hands it to `validate`.
fn with_raw<T>(
    path: &Path,
    text: &str,
    validate: impl FnOnce(&Cx, &RawStudy) -> Result<T, InputError>,
) -> Result<T, InputError> {
    let file = path.display().to_string();
    let doc = DeTable::parse(text).map_err(|e| syntax_error(&file, text, &e))?;
    let raw: RawStudy =
        toml::from_str(text).map_err(|e| serde_error(&file, text, doc.get_ref(), &e))?;
    let cx = Cx {
        file,
        text,
        doc: doc.get_ref(),
    };
    validate(&cx, &raw)
}

/// Parses and validates study text (no size guard): TOML syntax, then the raw form, then each
/// table in turn; the first error found is returned. A random or record study is validated as
/// a [`RandomStudy`] and becomes a [`Study`] of [`Scene::Random`].
fn from_text(path: &Path, text: &str) -> Result<Study, InputError> {
    with_raw(path, text, |cx, raw| {
        let random = match raw.scene.as_ref() {
            Some(s) => scene::RANDOM_KINDS.contains(&s.kind(cx)?),
            None => false,
        };
        if random {
            random_study(cx, raw, path, text).map(Study::from)
        } else {
            validate(cx, raw, path, text)
        }
    })
}

/// Each table of a free or harmonic study in turn.
fn validate(cx: &Cx, raw: &RawStudy, path: &Path, text: &str) -> Result<Study, InputError> {
    let h = &raw.study;
    let scene = scene::scene(cx, raw.scene.as_ref(), &raw.sweep)?;
    if raw.hazard.is_some() {
        return Err(InputError::new(format!(
            "{}: [hazard]: a seismic hazard curve belongs to the random and record scenes with an \
             intensity measure ([scene] kind = \"random\" or \"record\", intensity = \"pga\" \
             or \"sa\")",
            cx.file
        )));
    }
    if let Scene::Harmonic(_) = scene {
        free_only(cx, h)?;
    }
    let request = header(cx, h)?;
    let system = system::system(cx, &raw.system)?;
    let mut axes = sweep::axes(cx, &raw.sweep, &raw.system, &scene)?;
    if let Some(i) = scene::frequency_axis(&axes) {
        let f = axes.remove(i);
        axes.push(f);
    }
    let noise = noise::noise(cx, raw.noise.as_ref())?;
    let cases = perturb::cases(cx, raw.perturb.as_ref(), &axes, &system, noise.as_ref())?;
    let solver = solver::solver(cx, &raw.solver)?;
    if let Scene::Harmonic(_) = scene {
        scene::check_solver(cx, &solver)?;
    }
    let reliability = reliability::reliability(cx, &raw.reliability)?;
    let zones = zones::zones(cx, &raw.zones, &axes)?;
    let ranking = ranking::ranking(cx, &raw.ranking)?;
    let curve = match scene {
        Scene::Harmonic(_) => scene::frequency_axis(&axes).map(|i| &axes[i]),
        Scene::Free | Scene::Random(_) => None,
    };
    let run = run::run(cx, &raw.run, cases.len() as u64, &scene, curve)?;
    scene::check_runs(cx, &scene, &system, &axes, &cases)?;
    Ok(Study {
        path: path.to_path_buf(),
        source: text.to_string(),
        name: h.name.clone(),
        seed: h.seed.unwrap_or(0),
        request,
        scene,
        system,
        axes,
        cases,
        noise,
        solver,
        reliability,
        zones,
        ranking,
        run,
        realizations: 0,
        design_intensity: None,
        hazard: None,
    })
}

/// A validated study of the random or record scene (`[scene] kind = "random"` or `"record"`,
/// docs/scenes.md): the load, the realizations per design point and the tables a random study
/// shares with the others. [`Study::load`] reads it as a [`Study`] of [`Scene::Random`]
/// (`Study::from`), which the sweep and the reducer run. The structure starts at rest unless `[system]` says
/// otherwise (`x0`, `v0`, `y0`, `w0` default to 0 here, not to Table I's `v0 = 2 m/s`).
#[derive(Clone, Debug, PartialEq)]
pub struct RandomStudy {
    /// The file it was read from, and its text.
    pub path: PathBuf,
    pub source: String,
    /// `[study].name` and `[study].seed` (the root of every realization's stream).
    pub name: String,
    pub seed: u64,
    /// `[scene]`: the load (keys swept in `[sweep]` hold a placeholder; [`RandomStudy::point`]
    /// sets them).
    pub scene: RandomScene,
    /// `[scene].realizations`: runs per design point (1 for a record).
    pub realizations: u64,
    /// `[scene].design_intensity`: the swept `S0` or `scale` the designs are ranked at (one of
    /// its swept values; `None`: the middle one).
    pub design_intensity: Option<f64>,
    pub system: System,
    /// `[sweep]`: system keys and the scene's `S0`, `omega_g`, `zeta_g`, `omega_f`, `zeta_f` or
    /// `scale`, in file order, the last varying fastest.
    pub axes: Vec<Axis>,
    pub solver: SolverSettings,
    pub reliability: Reliability,
    pub zones: Zones,
    pub ranking: Ranking,
    pub run: RunSettings,
    /// `[hazard]`: the site's hazard curve (a study with an intensity measure).
    pub hazard: Option<SiteHazard>,
}

impl RandomStudy {
    /// Reads and validates a random or record study with the default size guard; a record file
    /// is read too.
    pub fn load(path: &Path) -> Result<RandomStudy, InputError> {
        RandomStudy::load_with(path, LoadOptions::default())
    }

    /// [`RandomStudy::load`] with options (`allow_large`).
    pub fn load_with(path: &Path, opts: LoadOptions) -> Result<RandomStudy, InputError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            InputError::new(format!(
                "{}: cannot read the study file: {e}",
                path.display()
            ))
        })?;
        RandomStudy::parse_with(path, &text, opts)
    }

    /// Parses and validates study text; `path` names it in messages and locates a record.
    pub fn parse(path: &Path, text: &str) -> Result<RandomStudy, InputError> {
        RandomStudy::parse_with(path, text, LoadOptions::default())
    }

    /// [`RandomStudy::parse`] with options (`allow_large`).
    pub fn parse_with(
        path: &Path,
        text: &str,
        opts: LoadOptions,
    ) -> Result<RandomStudy, InputError> {
        let study = with_raw(path, text, |cx, raw| random_study(cx, raw, path, text))?;
        let runs = study.n_runs();
        if opts.allow_large || runs <= MAX_RUNS {
            return Ok(study);
        }
        Err(InputError::new(format!(
            "{}: [sweep] = {runs} runs ({} design points x {} realizations): more than the size \
             guard of {MAX_RUNS} runs; pass --allow-large to run it anyway",
            path.display(),
            study.n_points(),
            study.realizations
        )))
    }

    /// Design points: the product of the axis lengths (1 without axes). Saturates.
    pub fn n_points(&self) -> u64 {
        self.axes
            .iter()
            .fold(1u64, |n, a| n.saturating_mul(a.values.len() as u64))
    }

    /// Runs: points x realizations. Saturates.
    pub fn n_runs(&self) -> u64 {
        self.n_points().saturating_mul(self.realizations)
    }

    /// The system and the scene of design point `p` (mixed radix over the axes, the last
    /// fastest): each axis value lands on its system key or on the scene's.
    pub fn point(&self, p: u64) -> (System, RandomScene) {
        let mut sys = self.system;
        let mut scene = self.scene.clone();
        let mut rest = p;
        let mut values = vec![0.0; self.axes.len()];
        for (i, axis) in self.axes.iter().enumerate().rev() {
            let n = axis.values.len() as u64;
            values[i] = axis.values[(rest % n) as usize];
            rest /= n;
        }
        for (axis, v) in self.axes.iter().zip(values) {
            if !sys.set(&axis.key, v) {
                scene.set(&axis.key, v);
            }
        }
        (sys, scene)
    }
}

impl From<RandomStudy> for Study {
    /// The random study as the sweep and the reducer take any study: its scene
    /// [`Scene::Random`], no cases (its runs are the realizations, [`Study::n_cases`]), no
    /// measurement noise, the default request (a random run lasts its scene's duration).
    fn from(r: RandomStudy) -> Study {
        Study {
            path: r.path,
            source: r.source,
            name: r.name,
            seed: r.seed,
            request: Request::default(),
            scene: Scene::Random(r.scene),
            system: r.system,
            axes: r.axes,
            cases: Vec::new(),
            noise: None,
            solver: r.solver,
            reliability: r.reliability,
            zones: r.zones,
            ranking: r.ranking,
            run: r.run,
            realizations: r.realizations,
            design_intensity: r.design_intensity,
            hazard: r.hazard,
        }
    }
}

/// Study keys of other scenes refused in a random or record study, with what to do instead.
const NOT_RANDOM: [(&str, &str); 3] = [
    (
        "outputs",
        "a random or record run records all its outputs (docs/scenes.md); leave [study].outputs \
         out",
    ),
    (
        "peaks",
        "peaks belong to the free-decay scene; a random or record run lasts [scene].duration",
    ),
    (
        "t_end",
        "t_end belongs to the free-decay scene; a random or record run lasts [scene].duration",
    ),
];

/// Each table of a random or record study in turn.
fn random_study(
    cx: &Cx,
    raw: &RawStudy,
    path: &Path,
    text: &str,
) -> Result<RandomStudy, InputError> {
    let h = &raw.study;
    let default = scene::RawScene::default();
    let raw_scene = raw.scene.as_ref().unwrap_or(&default);
    let kind = raw_scene.kind(cx)?;
    if !scene::RANDOM_KINDS.contains(&kind) {
        return Err(cx.err(
            "[scene].kind",
            format!("{kind:?}"),
            "a random study needs [scene] kind = \"random\" or \"record\" (the free and \
             harmonic scenes load as a Study)",
        ));
    }
    let given = [h.outputs.is_some(), h.peaks.is_some(), h.t_end.is_some()];
    for ((key, why), given) in NOT_RANDOM.into_iter().zip(given) {
        if given {
            return Err(cx.err(&format!("[study].{key}"), cx.source("study", key), why));
        }
    }
    header(cx, h)?;
    if let Some(key) = raw_scene.given().first() {
        return Err(cx.err(
            &format!("[scene].{key}"),
            cx.source("scene", key),
            format!("{key} belongs to the harmonic scene; this study's kind is {kind:?}"),
        ));
    }
    for (table, present, why) in [
        (
            "perturb",
            raw.perturb.is_some(),
            "a random study's cases are its realizations ([scene].realizations); perturbed \
             cases are not supported in it",
        ),
        (
            "noise",
            raw.noise.is_some(),
            "measurement noise belongs to the free and harmonic scenes; a random study's load is \
             its noise",
        ),
    ] {
        if present {
            return Err(InputError::new(format!("{}: [{table}]: {why}", cx.file)));
        }
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let (mut scene, realizations) = random::scene(cx, kind, raw_scene, &raw.sweep, dir)?;
    let mut system = system::system(cx, &raw.system)?;
    for key in ["x0", "v0", "y0", "w0"] {
        if raw.system.get(key).is_none() {
            system.set(key, 0.0);
        }
    }
    let swept: Vec<&str> = raw.sweep.keys().map(String::as_str).collect();
    random::limit(cx, raw_scene, &system, &swept, &mut scene)?;
    random::intensity(cx, raw_scene, &system, &swept, &mut scene)?;
    let hazard = match &raw.hazard {
        Some(_) if scene.intensity.is_none() => {
            return Err(InputError::new(format!(
                "{}: [hazard]: a hazard curve is over an intensity measure in g; give [scene] \
                 intensity = \"pga\" or \"sa\"",
                cx.file
            )));
        }
        Some(h) => Some(hazard::hazard(cx, h, dir)?),
        None => None,
    };
    let keys = random::axes_of(&scene);
    let scene_axes = sweep::SceneAxes {
        keys: &keys,
        check: random::check_key,
        listed: true,
    };
    let axes = sweep::axes_with(cx, &raw.sweep, &raw.system, &scene_axes)?;
    let solver = solver::solver(cx, &raw.solver)?;
    if solver.kind != SolverKind::Exact {
        return Err(cx.err(
            "[solver].kind",
            format!("{:?}", solver.kind.name()),
            "the random and record scenes are solved by exact only",
        ));
    }
    if let Some(a) = raw.run.audit_given()
        && a > 0
    {
        return Err(cx.err(
            "[run].audit",
            a,
            "the accuracy audit re-runs free-decay runs; a random study has none",
        ));
    }
    let design_intensity = random::design_intensity(cx, raw_scene.design_intensity, &axes)?;
    let run = run::run(
        cx,
        &raw.run,
        realizations,
        &Scene::Random(scene.clone()),
        None,
    )?;
    Ok(RandomStudy {
        path: path.to_path_buf(),
        source: text.to_string(),
        name: h.name.clone(),
        seed: h.seed.unwrap_or(0),
        scene,
        realizations,
        design_intensity,
        system,
        axes: axes.clone(),
        solver,
        reliability: reliability::reliability(cx, &raw.reliability)?,
        zones: zones::zones(cx, &raw.zones, &axes)?,
        ranking: ranking::ranking(cx, &raw.ranking)?,
        run,
        hazard,
    })
}

/// Refuses the `[study]` keys of the free-decay scene (`outputs`, `peaks`, `t_end`) in a
/// harmonic study.
fn free_only(cx: &Cx, h: &RawHeader) -> Result<(), InputError> {
    let given = [h.outputs.is_some(), h.peaks.is_some(), h.t_end.is_some()];
    for ((key, why), given) in scene::FREE_ONLY.into_iter().zip(given) {
        if given {
            return Err(cx.err(&format!("[study].{key}"), cx.source("study", key), why));
        }
    }
    Ok(())
}

/// `[study]`: the name (it names the output directory) and what each run must produce (the
/// outputs set the horizon: how many peaks a run needs).
fn header(cx: &Cx, h: &RawHeader) -> Result<Request, InputError> {
    let name_ok = !h.name.is_empty()
        && h.name != "."
        && h.name != ".."
        && h.name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-'));
    if !name_ok {
        return Err(cx.err(
            "[study].name",
            format!("{:?}", h.name),
            "the name must match [A-Za-z0-9_.-]+ and not be . or .. (it names the output directory)",
        ));
    }
    let mut need = 2;
    if let Some(outputs) = &h.outputs {
        if outputs.is_empty() {
            return Err(cx.err("[study].outputs", "[]", "ask for at least one output"));
        }
        need = 1;
        for (i, o) in outputs.iter().enumerate() {
            let Some((_, k)) = OUTPUTS.iter().find(|(n, _)| n == o) else {
                let names: Vec<&str> = OUTPUTS.iter().map(|(n, _)| *n).collect();
                return Err(cx.err(
                    &format!("[study].outputs[{i}]"),
                    format!("{o:?}"),
                    format!("unknown output; allowed: {}", names.join(", ")),
                ));
            };
            need = need.max(*k);
        }
    }
    let mut request = Request {
        peaks: need,
        t_end: h.t_end,
        trace_dt: None,
    };
    if let Some(p) = h.peaks {
        if p < need as u64 {
            return Err(cx.err(
                "[study].peaks",
                p,
                format!("the outputs asked for need peaks >= {need}"),
            ));
        }
        request.peaks = usize::try_from(p).unwrap_or(usize::MAX);
    }
    request
        .validate()
        .map_err(|e| cx.err(&format!("[study].{}", e.key), range_value(&e), e.allowed))?;
    Ok(request)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Study, InputError> {
        Study::parse(Path::new("t.toml"), text)
    }

    fn study(body: &str) -> Study {
        parse(&format!("[study]\nname = \"t\"\n{body}")).unwrap()
    }

    fn err(body: &str) -> String {
        parse(&format!("[study]\nname = \"t\"\n{body}"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn minimal_study_is_table_i_with_one_ideal_case() {
        let s = study("");
        assert_eq!(s.system, System::TABLE_I);
        assert_eq!(s.n_points(), 1);
        assert_eq!(s.cases, vec![Case::IDEAL]);
        assert_eq!(s.request, Request::default());
        assert!(s.noise.is_none());
        assert!(!s.reliability.has_strength());
        assert_eq!(s.run.chunk_points, DEFAULT_CHUNK_RUNS);
        assert_eq!(s.seed, 0);
    }

    #[test]
    fn step_grid_counts_are_pinned() {
        // hyperfine pins 11 values for 0..=1 step 0.1.
        let s = study("[sweep]\ne = { start = 0.0, stop = 1.0, step = 0.1 }\n");
        let v = &s.axes[0].values;
        assert_eq!(v.len(), 11);
        assert_eq!(v[0], 0.0);
        assert_eq!(v[3], 0.3); // 3 * 0.1 = 0.30000000000000004 before rounding
        assert_eq!(v[10], 1.0);
        // The paper's sweep: 51 values, every one the double the user would type.
        let s = study("[sweep]\ne = { start = 0.45, stop = 0.95, step = 0.01 }\n");
        let v = &s.axes[0].values;
        assert_eq!(v.len(), 51);
        for (i, x) in v.iter().enumerate() {
            let typed: f64 = format!("0.{}", 45 + i).parse().unwrap();
            assert_eq!(x.to_bits(), typed.to_bits(), "value {i}");
        }
        // A single value, and a step that does not divide the range.
        let s = study("[sweep]\ne = { start = 0.5, stop = 0.5, step = 0.1 }\n");
        assert_eq!(s.axes[0].values, vec![0.5]);
        assert!(err("[sweep]\ne = { start = 0.0, stop = 1.0, step = 0.3 }\n").contains(
            "[sweep].e.step = 0.3: (stop - start) / step = 3.3333333333333335 is not a whole number"
        ));
    }

    #[test]
    fn linspace_endpoints_are_exact() {
        let s = study("[sweep]\nd = { start = 0.001, stop = 0.0123, num = 7 }\n");
        let v = &s.axes[0].values;
        assert_eq!(v.len(), 7);
        assert_eq!(v[0].to_bits(), 0.001f64.to_bits());
        assert_eq!(v[6].to_bits(), 0.0123f64.to_bits());
        assert!(v.windows(2).all(|w| w[0] < w[1]));
        let s = study("[sweep]\ne = { start = 0.0, stop = 1.0, num = 5 }\n");
        assert_eq!(s.axes[0].values, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        let s = study("[sweep]\ne = { start = 0.3, stop = 0.3, num = 1 }\n");
        assert_eq!(s.axes[0].values, vec![0.3]);
    }

    #[test]
    fn axes_keep_file_order_and_the_grid_is_their_product() {
        let s = study(
            "[sweep]\nm = [0.01, 0.02]\ne = { start = 0.5, stop = 0.9, num = 5 }\nd = [0.01]\n",
        );
        let keys: Vec<&str> = s.axes.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(keys, ["m", "e", "d"]);
        assert_eq!(s.n_points(), 10);
    }

    #[test]
    fn ideal_case_is_first_and_not_duplicated() {
        let s = study(
            "[noise]\npower = 1e-10\nsample_time = 1e-3\n[perturb]\ncases = [\n  { dm = 0.0, dd = 0.0 },\n  { dd = 0.001 },\n  { noise_seed = 7 },\n  {},\n]\n",
        );
        assert_eq!(s.cases.len(), 3);
        assert_eq!(s.cases[0], Case::IDEAL);
        assert!(s.cases[1..].iter().all(|c| !c.ideal));
        assert_eq!(s.cases[1].dd, 0.001);
        assert_eq!(s.cases[2].noise_seed, Some(7));
        // Factorial: 3 x 3 minus the ideal combination, plus the ideal case first.
        let s = study("[perturb]\ndm = [-0.001, 0, 0.001]\ndd = [-0.001, 0.0, 0.001]\n");
        assert_eq!(s.cases.len(), 9);
        assert_eq!(s.cases.iter().filter(|c| c.ideal).count(), 1);
        assert!(s.cases[0].ideal);
        assert_eq!((s.cases[1].dm, s.cases[1].dd), (-0.001, -0.001));
        // With noise seeds no factorial row is ideal.
        let s = study(
            "[noise]\npower = 1e-10\nsample_time = 1e-3\n[perturb]\ndm = [0, 0.001]\nnoise_seeds = [1, 2]\n",
        );
        assert_eq!(s.cases.len(), 5);
        assert_eq!(s.n_runs(), 5);
    }

    #[test]
    fn outputs_set_the_horizon() {
        assert_eq!(study("").request.peaks, 2);
        assert_eq!(study("outputs = [\"x1\", \"impacts\"]\n").request.peaks, 1);
        assert_eq!(study("outputs = [\"x1\"]\npeaks = 5\n").request.peaks, 5);
        assert_eq!(study("t_end = 0.5\n").request.t_end, Some(0.5));
        assert!(
            err("outputs = [\"di\"]\npeaks = 1\n")
                .contains("[study].peaks = 1: the outputs asked for need peaks >= 2")
        );
    }

    #[test]
    fn size_guard_and_allow_large() {
        let text = "[study]\nname = \"big\"\n[sweep]\ne = { start = 0, stop = 1, num = 5000 }\nm = { start = 0, stop = 0.02, num = 2001 }\n";
        let e = parse(text).unwrap_err().to_string();
        assert_eq!(
            e,
            "t.toml: [sweep] = 10005000 runs (10005000 design points x 1 case): more than the size guard of 10000000 runs; pass --allow-large to run it anyway"
        );
        let s = Study::parse_with(Path::new("t.toml"), text, LoadOptions { allow_large: true })
            .unwrap();
        assert_eq!(s.n_runs(), 10_005_000);
        assert!(s.check_size(false).is_err());
    }

    proptest::proptest! {
        /// Whatever value lands on whatever key, parsing answers Ok or an error naming the
        /// file; it never panics.
        #[test]
        fn any_value_on_any_key_never_panics(
            key in proptest::sample::select(vec![
                "[system]\ne", "[system]\nm", "[system]\nd", "[system]\ny0", "seed",
                "peaks", "t_end", "outputs", "[sweep]\ne", "[sweep]\nd", "[sweep]\ny0",
                "[perturb]\ndm", "[perturb]\ndd", "[perturb]\ncases", "[perturb]\nnoise_seeds",
                "[noise]\npower", "[solver]\ntol", "[solver]\nmax_steps", "[reliability]\nE",
                "[reliability]\nstrength_mean", "[zones]\nzone", "[ranking]\nwf1",
                "[run]\nchunk_points", "[bogus]\nx", "[scene]\nkind", "[scene]\nF0",
                "[scene]\nkind = \"harmonic\"\nr", "[scene]\nkind = \"harmonic\"\nn_meas",
                "[scene]\nkind = \"harmonic\"\ntrans_tol",
                "[system]\nC = 0\n[scene]\nkind = \"harmonic\"\n[sweep]\nr",
                "[scene]\nkind = \"harmonic\"\n[sweep]\nomega",
                "[scene]\nkind = \"harmonic\"\n[run]\nchunk_points",
            ]),
            value in proptest::sample::select(vec![
                "nan", "inf", "-inf", "-0.0", "0", "1e308", "-1", "9223372036854775807", "\"x\"",
                "[]", "{}", "[nan]", "[1, 0]", "[0.0, 1e-300]", "{ start = 0, stop = 1e300, step = 1e-300 }",
                "{ start = 0, stop = 1, num = 0 }", "{ start = 1e-3, stop = 1e-3, num = 1 }",
                "{ start = 0, stop = 1, step = nan }", "[{ dm = nan }]", "[{ dd = -1 }]",
                "[{ name = \"a\", axis = \"e\", from = 1, to = 0 }]", "true", "1979-05-27",
            ]),
        ) {
            let text = format!("[study]\nname = \"p\"\n{key} = {value}\n");
            if let Err(e) = Study::parse(Path::new("p.toml"), &text) {
                proptest::prop_assert!(e.to_string().starts_with("p.toml"), "{}", e);
            }
        }
    }
}
