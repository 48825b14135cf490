//! The validated [`Study`]: what every later stage reads (the sweep engine, the reducer, the
//! report), and its sizes and files. `study/scene/` builds it, one parser per scene;
//! [`Study::load`](super::Study::load) is the entry point.

use std::path::{Path, PathBuf};

use super::axis::Axis;
use super::hazard;
use super::perturb::Case;
use super::ranking::Ranking;
use super::record::{self, SUITE_COPY};
use super::reliability::Reliability;
use super::run::RunSettings;
use super::size::MAX_RUNS;
use super::zones::Zones;
use crate::error::InputError;
use crate::model::System;
use crate::sim::{NoiseSettings, Request, Scene, SolverSettings};
use crate::stats::hazard::SiteHazard;

/// Which census of periodic steady states a harmonic study's runs take
/// ([`Study::census_kind`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CensusKind {
    /// None: a free-decay or random study, or `starts = 0`.
    None,
    /// One unit's census along each frequency-response curve ([`crate::orbits::curve`]), its
    /// motions that are not periodic measured over the design life ([`crate::orbits::race`]).
    OneUnit,
    /// A study of several units (`units` or `d_spread` anywhere, [`Study::several_units`]):
    /// every run's own census of several units from its end state
    /// ([`crate::orbits::several`]), for its one-unit designs too, so that every design's
    /// steady states are found alike, its motions that are not periodic measured over the
    /// design life along each curve ([`crate::orbits::race::race_units`]).
    Units,
}

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

impl Study {
    /// Which census of periodic steady states the runs of this study take, decided once here
    /// for every stage (the sweep matches it, the reducer and the plan read it).
    pub fn census_kind(&self) -> CensusKind {
        match self.scene {
            Scene::Harmonic(h) if h.starts > 0 && self.several_units() => CensusKind::Units,
            Scene::Harmonic(h) if h.starts > 0 => CensusKind::OneUnit,
            _ => CensusKind::None,
        }
    }

    /// A harmonic study whose runs take the one-unit census (model.md §10): `starts` given, one
    /// damper unit. Its attractors are followed along branches, raced for their design lives and
    /// continued to the jumps' probes, which cover one unit ([`CensusKind::OneUnit`]).
    pub fn census(&self) -> bool {
        self.census_kind() == CensusKind::OneUnit
    }

    /// Several damper units anywhere in the study (model.md §14): `[system]` or `[sweep]` sets
    /// `units` or `d_spread`. Its tables then carry those columns.
    pub fn several_units(&self) -> bool {
        self.system.units != 1.0
            || self.system.d_spread != 0.0
            || self
                .axes
                .iter()
                .any(|a| crate::model::UNIT_KEYS.contains(&a.key.as_str()))
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

    /// The files a record study reads and their copies in a run directory, relative to it:
    /// `[scene] record` (relative to the study file, or the run directory's copy
    /// [`record::RECORD_COPY`]), or each record of a suite (`[scene] records`, copied into
    /// [`SUITE_COPY`]` /` under its file name). Empty for any other study.
    pub fn record_files(&self) -> Vec<(PathBuf, PathBuf)> {
        let Some(r) = self.scene.random() else {
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

    /// The file a study's hazard table is read from (`[hazard] table` relative to the study
    /// file, or the run directory's copy [`hazard::HAZARD_COPY`]); `None` without one.
    pub fn hazard_path(&self) -> Option<PathBuf> {
        let doc: toml::Table = self.source.parse().ok()?;
        let shown = doc.get("hazard")?.get("table")?.as_str()?;
        let dir = self.path.parent().unwrap_or(Path::new("."));
        Some(hazard::table_path(dir, shown))
    }
}
