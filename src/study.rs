//! Study files: TOML → validated [`Study`].
//!
//! CONTRACT (shared by the sweep engine and the reducer): the types below are the validated
//! form; later stages never see an unvalidated value. The TOML format is documented in
//! `docs/study.md`. Parsing follows ripgrep's low/high args: `#[serde(deny_unknown_fields)]` raw
//! structs mirror the TOML, one conversion validates units, ranges and cross-field rules.

use std::path::{Path, PathBuf};

use crate::error::InputError;
use crate::model::System;
use crate::sim::{NoiseSettings, Request, SolverSettings};

/// A validated study.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// The file it was read from.
    pub path: PathBuf,
    /// The TOML text as read (stored next to the dataset and in Parquet metadata).
    pub source: String,
    /// `[study].name`: names the output directory `DIR/<name>/`. `[A-Za-z0-9_.-]+`.
    pub name: String,
    /// `[study].seed`: root of every random stream (noise, bootstrap, audit choice).
    pub seed: u64,
    /// What each run must produce (`[study].outputs` / `peaks` / `t_end`): sets the horizon.
    pub request: Request,
    /// `[system]`: base parameters, Table I defaults when absent.
    pub system: System,
    /// `[sweep]`: the swept axes in file order; the design grid is their Cartesian product,
    /// the last axis varying fastest.
    pub axes: Vec<Axis>,
    /// `[perturb]`: per design point, the cases to run; `cases[0]` is always the ideal case
    /// (`dm = dd = 0`, no noise) and is marked `ideal`.
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
}

/// One swept axis: a system key and its values (computed from an integer index, never
/// accumulated).
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub key: String,
    pub values: Vec<f64>,
}

/// One perturbation/noise case of a design point (model.md §4, the paper's Table II).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// Change of the inner mass `m` (kg).
    pub dm: f64,
    /// Change of the clearance `d` (m).
    pub dd: f64,
    /// Noise seed; `None` means no noise for this case.
    pub noise_seed: Option<u64>,
    /// The unperturbed, noise-free case.
    pub ideal: bool,
}

/// Which relation turns reliability into a safety factor (model.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SafetyForm {
    /// Shigley's exact lognormal relation (default).
    Exact,
    /// The paper's small-`C_n` form.
    Paper,
}

/// `[reliability]`: stress model and strength distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct Reliability {
    /// Young's modulus (Pa). Default 200e9.
    pub E: f64,
    /// Radius of the cantilever's circular section (m). Default 3.4e-3.
    pub r: f64,
    /// Cantilever length (m). Default 0.5.
    pub L: f64,
    /// Mean strength (Pa); required (the paper does not state it).
    pub strength_mean: f64,
    /// Standard deviation of strength (Pa); required.
    pub strength_sd: f64,
    /// Safety-factor relation. Default exact.
    pub safety_form: SafetyForm,
    /// Bootstrap resamples for the confidence interval of R. Default 2000.
    pub bootstrap: usize,
    /// Confidence level of that interval. Default 0.95.
    pub confidence: f64,
}

/// Where a design point's DI comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiSource {
    /// The ideal case (default).
    Ideal,
    /// The mean over the cases.
    Mean,
}

/// `[zones]`: automatic zone finding and declared overrides.
#[derive(Clone, Debug, PartialEq)]
pub struct Zones {
    /// Jump threshold: a first difference larger than `jump_k` robust standard deviations
    /// (MAD × 1.4826) of the first differences is a jump. Default 6.
    pub jump_k: f64,
    /// Reliability at or above which a point is "reliable". Default 0.98.
    pub r_min: f64,
    /// DI at or above which damping is "strong" (m/s); default: the median DI of the sweep.
    pub di_strong: Option<f64>,
    /// Zones declared in the study; when non-empty they replace the automatic ones.
    pub declared: Vec<DeclaredZone>,
}

/// A zone declared in the study: a name and a range of one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct DeclaredZone {
    pub name: String,
    pub axis: String,
    pub from: f64,
    pub to: f64,
}

/// `[ranking]`: perfectibility weights (eq. 11).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ranking {
    /// Weight of reliability. Default 0.5.
    pub wf1: f64,
    /// Weight of DI. Default 0.5.
    pub wf2: f64,
    pub di_source: DiSource,
}

/// `[run]`: engine settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    /// Design points per Parquet part file (each chunk holds whole design points).
    /// Default: enough points for about 65536 runs.
    pub chunk_points: u64,
    /// Accuracy audit: points re-run with `exact` at tight tolerance. Default 0 until the
    /// fidelity issue lands.
    pub audit: u64,
}

impl Study {
    /// Reads and validates a study file. Errors name the file, the key, the value and the
    /// allowed range; TOML syntax errors give line and column.
    pub fn load(path: &Path) -> Result<Study, InputError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            InputError::new(format!(
                "{}: cannot read the study file: {e}",
                path.display()
            ))
        })?;
        Study::parse(path, &text)
    }

    /// Parses and validates study text; `path` is used in messages.
    pub fn parse(path: &Path, _text: &str) -> Result<Study, InputError> {
        Err(InputError::new(format!(
            "{}: study files are not implemented yet",
            path.display()
        )))
    }

    /// Number of design points (product of the axis lengths; 1 without axes).
    pub fn n_points(&self) -> u64 {
        self.axes.iter().map(|a| a.values.len() as u64).product()
    }

    /// Total runs: points × cases.
    pub fn n_runs(&self) -> u64 {
        self.n_points() * self.cases.len() as u64
    }
}
