//! Study files: TOML → validated [`Study`].
//!
//! CONTRACT (shared by the sweep engine and the reducer): the types below are the validated
//! form; later stages never see an unvalidated value. The TOML format is documented in
//! `docs/study.md`. Parsing follows ripgrep's low/high args: `#[serde(deny_unknown_fields)]` raw
//! structs mirror the TOML, one conversion validates units, ranges and cross-field rules.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::error::InputError;
use crate::model::{RangeError, SYSTEM_KEYS, System, fmt_value};
use crate::sim::{NoiseSettings, Request, SolverKind, SolverSettings};

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
    /// `[system]`: base parameters, Table I defaults when absent.
    pub system: System,
    /// `[sweep]`: the swept axes in file order; the design grid is their Cartesian product,
    /// the last axis varying fastest.
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
    /// Mean strength (Pa), `> 0`. The paper does not state it, so there is no default: without
    /// `strength_mean` and `strength_sd` both hold NaN ([`Reliability::has_strength`] is false)
    /// and the reducer reports reliability as unavailable.
    pub strength_mean: f64,
    /// Standard deviation of strength (Pa), `>= 0`; given together with `strength_mean`.
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

/// The default size guard: a study with more runs than this is refused unless the caller
/// passes `allow_large` (`--allow-large` on the command line). 10^7 runs is about ten minutes
/// of noise-free two-peak runs on two cores and about a gigabyte of Parquet.
pub const MAX_RUNS: u64 = 10_000_000;

/// Hard limit on the length of one axis (its values are held in memory: 80 MB at this size).
/// Not lifted by `allow_large`.
pub const MAX_AXIS_VALUES: u64 = 10_000_000;

/// Runs per chunk aimed at when `[run].chunk_points` is absent.
pub const DEFAULT_CHUNK_RUNS: u64 = 65_536;

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

impl Reliability {
    /// Whether the study gave a strength distribution (`strength_mean`, `strength_sd`). Without
    /// one both hold NaN and the reducer reports reliability as unavailable.
    pub fn has_strength(&self) -> bool {
        self.strength_mean.is_finite() && self.strength_sd.is_finite()
    }
}

impl Default for Reliability {
    fn default() -> Self {
        Reliability {
            E: 200e9,
            r: 3.4e-3,
            L: 0.5,
            strength_mean: f64::NAN,
            strength_sd: f64::NAN,
            safety_form: SafetyForm::Exact,
            bootstrap: 2000,
            confidence: 0.95,
        }
    }
}

impl Default for Zones {
    fn default() -> Self {
        Zones {
            jump_k: 6.0,
            r_min: 0.98,
            di_strong: None,
            declared: Vec::new(),
        }
    }
}

impl Default for Ranking {
    fn default() -> Self {
        Ranking {
            wf1: 0.5,
            wf2: 0.5,
            di_source: DiSource::Ideal,
        }
    }
}

impl Case {
    /// The unperturbed, noise-free case (always `cases[0]`).
    pub const IDEAL: Case = Case {
        dm: 0.0,
        dd: 0.0,
        noise_seed: None,
        ideal: true,
    };
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
        let study = parse_unchecked(path, text)?;
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
            self.cases.len(),
            if self.cases.len() == 1 { "" } else { "s" },
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

    /// Total runs: points × cases. Saturates at `u64::MAX`.
    pub fn n_runs(&self) -> u64 {
        self.n_points().saturating_mul(self.cases.len() as u64)
    }

    /// The axis of a system key, if it is swept.
    pub fn axis(&self, key: &str) -> Option<&Axis> {
        self.axes.iter().find(|a| a.key == key)
    }
}

// ---------------------------------------------------------------------------------------------
// Raw form: mirrors the TOML, refuses unknown keys and wrong types.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    study: RawHeader,
    #[serde(default)]
    system: RawSystem,
    #[serde(default)]
    sweep: BTreeMap<String, RawAxis>,
    perturb: Option<RawPerturb>,
    noise: Option<RawNoise>,
    #[serde(default)]
    solver: RawSolver,
    #[serde(default)]
    reliability: RawReliability,
    #[serde(default)]
    zones: RawZones,
    #[serde(default)]
    ranking: RawRanking,
    #[serde(default)]
    run: RawRun,
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

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct RawSystem {
    M: Option<f64>,
    m: Option<f64>,
    K: Option<f64>,
    C: Option<f64>,
    d: Option<f64>,
    e: Option<f64>,
    x0: Option<f64>,
    v0: Option<f64>,
    y0: Option<f64>,
    w0: Option<f64>,
}

impl RawSystem {
    fn get(&self, key: &str) -> Option<f64> {
        match key {
            "M" => self.M,
            "m" => self.m,
            "K" => self.K,
            "C" => self.C,
            "d" => self.d,
            "e" => self.e,
            "x0" => self.x0,
            "v0" => self.v0,
            "y0" => self.y0,
            "w0" => self.w0,
            _ => None,
        }
    }
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawAxis {
    List(Vec<f64>),
    Range(RawRange),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRange {
    start: f64,
    stop: f64,
    step: Option<f64>,
    num: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPerturb {
    cases: Option<Vec<RawCase>>,
    dm: Option<Vec<f64>>,
    dd: Option<Vec<f64>>,
    noise_seeds: Option<Vec<u64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCase {
    #[serde(default)]
    dm: f64,
    #[serde(default)]
    dd: f64,
    noise_seed: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawNoise {
    power: f64,
    sample_time: f64,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSolver {
    kind: Option<String>,
    tol: Option<f64>,
    chatter_tol: Option<f64>,
    max_impacts: Option<u64>,
    max_steps: Option<u64>,
    t_max_periods: Option<f64>,
    h: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct RawReliability {
    E: Option<f64>,
    r: Option<f64>,
    L: Option<f64>,
    strength_mean: Option<f64>,
    strength_sd: Option<f64>,
    safety_form: Option<String>,
    bootstrap: Option<u64>,
    confidence: Option<f64>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawZones {
    jump_k: Option<f64>,
    r_min: Option<f64>,
    di_strong: Option<f64>,
    #[serde(default)]
    zone: Vec<RawZone>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawZone {
    name: String,
    axis: String,
    from: f64,
    to: f64,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRanking {
    wf1: Option<f64>,
    wf2: Option<f64>,
    di_source: Option<String>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRun {
    chunk_points: Option<u64>,
    audit: Option<u64>,
}

// ---------------------------------------------------------------------------------------------
// TOML errors → messages that name the file, the key, the value and what is allowed.

/// One step of a key path: a table key or an array index.
enum Seg {
    Key(String),
    Index(usize),
}

/// Renders a key path as `[table].key[2].sub`.
fn render_path(path: &[Seg]) -> String {
    let mut out = String::new();
    for (i, seg) in path.iter().enumerate() {
        match (i, seg) {
            (0, Seg::Key(k)) => out.push_str(&format!("[{k}]")),
            (_, Seg::Key(k)) => out.push_str(&format!(".{k}")),
            (_, Seg::Index(j)) => out.push_str(&format!("[{j}]")),
        }
    }
    out
}

/// 1-based line and column (in characters) of a byte offset.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// The source text of a value, on one line and at most 60 characters.
fn snippet(text: &str, span: &Range<usize>) -> String {
    let raw = text.get(span.clone()).unwrap_or("");
    let one_line: Vec<&str> = raw.split_whitespace().collect();
    let s = one_line.join(" ");
    if s.chars().count() > 60 {
        let cut: String = s.chars().take(57).collect();
        format!("{cut}...")
    } else {
        s
    }
}

fn syntax_error(file: &str, text: &str, err: &toml::de::Error) -> InputError {
    let span = err.span().unwrap_or(0..0);
    let (line, col) = line_col(text, span.start);
    let mut msg = err.message().trim().to_string();
    if msg == "duplicate key" {
        msg = format!("duplicate key '{}'", snippet(text, &span));
    }
    InputError::new(format!("{file}:{line}:{col}: TOML syntax error: {msg}"))
}

struct Hit {
    path: Vec<Seg>,
    value: Range<usize>,
}

/// Finds the deepest key whose key span is `span` or whose value span contains it.
fn locate(table: &DeTable<'_>, span: &Range<usize>, path: &mut Vec<Seg>, best: &mut Option<Hit>) {
    for (k, v) in table.iter() {
        path.push(Seg::Key(k.get_ref().to_string()));
        consider(k.span() == *span, v, span, path, best);
        path.pop();
    }
}

fn consider(
    on_key: bool,
    v: &Spanned<DeValue<'_>>,
    span: &Range<usize>,
    path: &mut Vec<Seg>,
    best: &mut Option<Hit>,
) {
    let vs = v.span();
    let inside = vs.start <= span.start && span.end <= vs.end;
    if on_key || inside {
        let better = match best {
            None => true,
            Some(b) => {
                path.len() > b.path.len()
                    || (path.len() == b.path.len() && vs.len() < b.value.len())
            }
        };
        if better {
            let copy = path
                .iter()
                .map(|s| match s {
                    Seg::Key(k) => Seg::Key(k.clone()),
                    Seg::Index(i) => Seg::Index(*i),
                })
                .collect();
            *best = Some(Hit {
                path: copy,
                value: vs,
            });
        }
    }
    match v.get_ref() {
        DeValue::Table(t) => locate(t, span, path, best),
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                consider(false, item, span, path, best);
                path.pop();
            }
        }
        _ => {}
    }
}

/// Between the first pair of backticks after `prefix`.
fn quoted_after<'m>(msg: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = msg.strip_prefix(prefix)?;
    let rest = rest.strip_prefix('`')?;
    rest.split('`').next()
}

/// serde's "expected ..." in words a user reads.
fn human_expected(exp: &str) -> String {
    let exp = exp.trim();
    match exp {
        "f64" => "must be a number".into(),
        "u64" | "usize" => "must be a whole number >= 0".into(),
        "a string" => "must be a string".into(),
        "a sequence" => "must be a list".into(),
        "a boolean" => "must be true or false".into(),
        _ if exp.starts_with("struct ") || exp == "a map" => "must be a table".into(),
        _ => format!("expected {exp}"),
    }
}

fn serde_error(file: &str, text: &str, doc: &DeTable<'_>, err: &toml::de::Error) -> InputError {
    let msg = err.message().trim();
    let mut best = None;
    if let Some(span) = err.span() {
        locate(doc, &span, &mut Vec::new(), &mut best);
    }
    let (path, value) = match best {
        Some(h) => (h.path, snippet(text, &h.value)),
        None => (Vec::new(), String::new()),
    };
    let loc = render_path(&path);
    let tables = "study, system, sweep, perturb, noise, solver, reliability, zones, ranking, run";
    let out = if let Some(field) = quoted_after(msg, "unknown field ") {
        let allowed = msg
            .split_once(", expected ")
            .map(|(_, e)| {
                e.replace('`', "")
                    .replace(" or ", ", ")
                    .replace("one of ", "")
            })
            .unwrap_or_default();
        if path.len() <= 1 {
            format!("[{field}]: unknown table; allowed tables: {tables}")
        } else {
            format!("{loc} = {value}: unknown key '{field}'; allowed keys: {allowed}")
        }
    } else if let Some(field) = quoted_after(msg, "missing field ") {
        let mut p = path;
        let top = tables.split(", ").any(|t| t == field);
        let (Some(Seg::Key(_)), false) = (p.first(), top) else {
            return InputError::new(format!(
                "{file}: [{field}]: missing table; every study needs [{field}] with at least a name"
            ));
        };
        p.push(Seg::Key(field.to_string()));
        format!("{}: missing; this key is required", render_path(&p))
    } else if msg.starts_with("data did not match any variant of untagged enum RawAxis") {
        format!(
            "{loc} = {value}: an axis is a list of numbers, {{start, stop, step}} or \
             {{start, stop, num}}"
        )
    } else if let Some((_, exp)) = msg
        .strip_prefix("invalid type: ")
        .or_else(|| msg.strip_prefix("invalid value: "))
        .and_then(|m| m.rsplit_once(", expected "))
    {
        format!("{loc} = {value}: {}", human_expected(exp))
    } else if loc.is_empty() {
        msg.to_string()
    } else {
        format!("{loc} = {value}: {msg}")
    };
    InputError::new(format!("{file}: {out}"))
}

// ---------------------------------------------------------------------------------------------
// Validation: raw → Study.

/// Error builder for one file.
struct Cx<'a> {
    file: String,
    text: &'a str,
    doc: &'a DeTable<'a>,
}

impl Cx<'_> {
    fn err(
        &self,
        loc: &str,
        value: impl std::fmt::Display,
        allowed: impl std::fmt::Display,
    ) -> InputError {
        InputError::new(format!("{}: {loc} = {value}: {allowed}", self.file))
    }

    /// The source text of `[table].key`, on one line.
    fn source(&self, table: &str, key: &str) -> String {
        self.doc
            .get(table)
            .and_then(|t| t.get_ref().as_table())
            .and_then(|t| t.get(key))
            .map(|v| snippet(self.text, &v.span()))
            .unwrap_or_default()
    }

    /// The position of a key in the file (for file order of `[sweep]`).
    fn key_pos(&self, table: &str, key: &str) -> usize {
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
fn range_value(e: &RangeError) -> String {
    e.value.parse::<f64>().map_or_else(|_| e.value.clone(), num)
}

/// Rounds to 15 significant digits, so a grid computed as `start + i * step` gives the double
/// the user would type (`0.45 + 3 * 0.01` → `0.48`, not `0.48000000000000004`). Any decimal
/// with at most 15 significant digits is the nearest double to itself, and `start + i * step`
/// is within a few ulps (< 1e-15 relative) of it, so this recovers it; for other values it
/// moves them by less than 5e-16 relative.
fn round15(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    crate::model::round_sig15(v)
}

/// Checks one system key's own range (not the `y0 - x0` constraint, checked separately).
fn check_key(key: &str, v: f64) -> Result<(), RangeError> {
    let mut s = System::TABLE_I;
    s.set(key, v);
    if key == "x0" || key == "y0" {
        s.x0 = v;
        s.y0 = v;
    }
    s.validate()
}

/// The values of one axis.
fn axis_values(cx: &Cx, key: &str, raw: &RawAxis) -> Result<Vec<f64>, InputError> {
    let at = format!("[sweep].{key}");
    let values = match raw {
        RawAxis::List(list) => {
            if list.is_empty() {
                return Err(cx.err(&at, "[]", "an axis needs at least one value"));
            }
            for (i, &v) in list.iter().enumerate() {
                if !v.is_finite() {
                    return Err(cx.err(&format!("{at}[{i}]"), num(v), "must be a finite number"));
                }
                if i > 0 && v <= list[i - 1] {
                    return Err(cx.err(
                        &format!("{at}[{i}]"),
                        num(v),
                        format!(
                            "the values of an axis must be strictly increasing (previous value {})",
                            num(list[i - 1])
                        ),
                    ));
                }
            }
            list.clone()
        }
        RawAxis::Range(r) => {
            for (k, v) in [("start", r.start), ("stop", r.stop)] {
                if !v.is_finite() {
                    return Err(cx.err(&format!("{at}.{k}"), num(v), "must be a finite number"));
                }
            }
            if r.stop < r.start {
                return Err(cx.err(
                    &format!("{at}.stop"),
                    num(r.stop),
                    format!(
                        "the axis is reversed: stop must be >= start = {}",
                        num(r.start)
                    ),
                ));
            }
            match (r.step, r.num) {
                (Some(_), Some(_)) => {
                    return Err(cx.err(
                        &at,
                        cx.source("sweep", key),
                        "give either step or num, not both",
                    ));
                }
                (None, None) => {
                    return Err(cx.err(
                        &at,
                        cx.source("sweep", key),
                        "a range needs a step ({start, stop, step}) or a count ({start, stop, num})",
                    ));
                }
                (Some(step), None) => step_values(cx, &at, r.start, r.stop, step)?,
                (None, Some(n)) => linspace_values(cx, &at, r.start, r.stop, n)?,
            }
        }
    };
    // Only the extremes: every rule on a single key is a range.
    for v in [values[0], values[values.len() - 1]] {
        check_key(key, v).map_err(|e| cx.err(&at, num(v), e.allowed))?;
    }
    Ok(values)
}

/// `start, start + step, ..., stop`: the count is `round((stop - start) / step) + 1` and the
/// last value must land within `1e-9 * step` of `stop`.
fn step_values(
    cx: &Cx,
    at: &str,
    start: f64,
    stop: f64,
    step: f64,
) -> Result<Vec<f64>, InputError> {
    let at_step = format!("{at}.step");
    if !(step.is_finite() && step > 0.0) {
        return Err(cx.err(&at_step, num(step), "the step must be a finite number > 0"));
    }
    let q = (stop - start) / step;
    if q.is_nan() || q + 1.0 > MAX_AXIS_VALUES as f64 {
        return Err(cx.err(
            &at_step,
            num(step),
            format!("the axis would have more than {MAX_AXIS_VALUES} values"),
        ));
    }
    let n = q.round();
    let last = start + n * step;
    if (last - stop).abs() > 1e-9 * step {
        return Err(cx.err(
            &at_step,
            num(step),
            format!(
                "(stop - start) / step = {} is not a whole number; stop must be start + n * step",
                num(q)
            ),
        ));
    }
    let n = n as u64;
    let mut values: Vec<f64> = (0..=n).map(|i| round15(start + i as f64 * step)).collect();
    if let Some(l) = values.last_mut() {
        *l = stop;
    }
    if values.windows(2).any(|w| w[1] <= w[0]) {
        return Err(cx.err(
            &at_step,
            num(step),
            "the step is too small to give distinct values at this magnitude",
        ));
    }
    Ok(values)
}

/// `num` values from `start` to `stop` inclusive, endpoints exact.
fn linspace_values(
    cx: &Cx,
    at: &str,
    start: f64,
    stop: f64,
    n: u64,
) -> Result<Vec<f64>, InputError> {
    let at_num = format!("{at}.num");
    if n == 0 || n > MAX_AXIS_VALUES {
        return Err(cx.err(
            &at_num,
            n,
            format!("num must be a whole number in [1, {MAX_AXIS_VALUES}]"),
        ));
    }
    if n == 1 {
        if start != stop {
            return Err(cx.err(&at_num, n, "num = 1 needs start = stop"));
        }
        return Ok(vec![start]);
    }
    let span = stop - start;
    let last = (n - 1) as f64;
    let mut values: Vec<f64> = (0..n)
        .map(|i| round15(start + span * (i as f64 / last)))
        .collect();
    values[0] = start;
    values[(n - 1) as usize] = stop;
    if values.windows(2).any(|w| w[1] <= w[0]) {
        return Err(cx.err(
            &at_num,
            n,
            "the values would not be distinct: start must be < stop and num not too large",
        ));
    }
    Ok(values)
}

/// A case and where it came from (for messages).
struct SourcedCase {
    case: Case,
    dm_at: String,
    dd_at: String,
    seed_at: String,
}

fn perturb_cases(cx: &Cx, raw: Option<&RawPerturb>) -> Result<Vec<SourcedCase>, InputError> {
    let mut out = vec![SourcedCase {
        case: Case::IDEAL,
        dm_at: String::new(),
        dd_at: String::new(),
        seed_at: String::new(),
    }];
    let Some(p) = raw else { return Ok(out) };
    let factorial = p.dm.is_some() || p.dd.is_some() || p.noise_seeds.is_some();
    let mut rows = Vec::new();
    if let Some(cases) = &p.cases {
        if factorial {
            let k = if p.dm.is_some() {
                "dm"
            } else if p.dd.is_some() {
                "dd"
            } else {
                "noise_seeds"
            };
            return Err(cx.err(
                &format!("[perturb].{k}"),
                cx.source("perturb", k),
                "give either explicit cases or the factorial lists dm, dd, noise_seeds, not both",
            ));
        }
        for (i, c) in cases.iter().enumerate() {
            let at = format!("[perturb].cases[{i}]");
            rows.push(SourcedCase {
                case: Case {
                    dm: c.dm,
                    dd: c.dd,
                    noise_seed: c.noise_seed,
                    ideal: false,
                },
                dm_at: format!("{at}.dm"),
                dd_at: format!("{at}.dd"),
                seed_at: format!("{at}.noise_seed"),
            });
        }
    } else if factorial {
        for (k, empty) in [
            ("dm", p.dm.as_ref().is_some_and(Vec::is_empty)),
            ("dd", p.dd.as_ref().is_some_and(Vec::is_empty)),
            (
                "noise_seeds",
                p.noise_seeds.as_ref().is_some_and(Vec::is_empty),
            ),
        ] {
            if empty {
                return Err(cx.err(
                    &format!("[perturb].{k}"),
                    "[]",
                    "an empty list gives no cases; leave the key out to mean no change",
                ));
            }
        }
        let dms = p.dm.clone().unwrap_or_else(|| vec![0.0]);
        let dds = p.dd.clone().unwrap_or_else(|| vec![0.0]);
        let seeds: Vec<Option<u64>> = match &p.noise_seeds {
            Some(s) => s.iter().map(|&x| Some(x)).collect(),
            None => vec![None],
        };
        for &dm in &dms {
            for &dd in &dds {
                for &seed in &seeds {
                    rows.push(SourcedCase {
                        case: Case {
                            dm,
                            dd,
                            noise_seed: seed,
                            ideal: false,
                        },
                        dm_at: "[perturb].dm".into(),
                        dd_at: "[perturb].dd".into(),
                        seed_at: "[perturb].noise_seeds".into(),
                    });
                }
            }
        }
    }
    for row in rows {
        let c = row.case;
        for (v, at) in [(c.dm, &row.dm_at), (c.dd, &row.dd_at)] {
            if !v.is_finite() {
                return Err(cx.err(at, num(v), "must be a finite number"));
            }
        }
        if c.dm == 0.0 && c.dd == 0.0 && c.noise_seed.is_none() {
            continue; // the ideal case, already cases[0]
        }
        out.push(row);
    }
    Ok(out)
}

fn parse_unchecked(path: &Path, text: &str) -> Result<Study, InputError> {
    let file = path.display().to_string();
    let doc = DeTable::parse(text).map_err(|e| syntax_error(&file, text, &e))?;
    let raw: RawStudy =
        toml::from_str(text).map_err(|e| serde_error(&file, text, doc.get_ref(), &e))?;
    let cx = Cx {
        file,
        text,
        doc: doc.get_ref(),
    };

    // [study]
    let h = &raw.study;
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

    // [system]
    let mut system = System::TABLE_I;
    for key in SYSTEM_KEYS {
        if let Some(v) = raw.system.get(key) {
            check_key(key, v).map_err(|e| cx.err(&format!("[system].{key}"), num(v), e.allowed))?;
            system.set(key, v);
        }
    }

    // [sweep], in file order
    let mut keys: Vec<&String> = raw.sweep.keys().collect();
    keys.sort_by_key(|k| cx.key_pos("sweep", k));
    let mut axes = Vec::new();
    for key in keys {
        let at = format!("[sweep].{key}");
        if !SYSTEM_KEYS.contains(&key.as_str()) {
            return Err(cx.err(
                &at,
                cx.source("sweep", key),
                format!("unknown axis '{key}'; allowed: {}", SYSTEM_KEYS.join(", ")),
            ));
        }
        if let Some(v) = raw.system.get(key) {
            return Err(cx.err(
                &format!("[system].{key}"),
                num(v),
                format!("{key} is also swept in [sweep]; a key is either fixed or swept, not both"),
            ));
        }
        let values = axis_values(&cx, key, &raw.sweep[key])?;
        axes.push(Axis {
            key: key.clone(),
            values,
        });
    }
    let range = |key: &str| -> (f64, f64, String) {
        match axes.iter().find(|a| a.key == key) {
            Some(a) => (
                a.values[0],
                a.values[a.values.len() - 1],
                format!("[sweep].{key}"),
            ),
            None => {
                let v = system.get(key).unwrap_or(f64::NAN);
                (v, v, format!("[system].{key}"))
            }
        }
    };

    // [noise]
    let noise = match &raw.noise {
        None => None,
        Some(n) => {
            let ns = NoiseSettings {
                power: n.power,
                sample_time: n.sample_time,
            };
            ns.validate()
                .map_err(|e| cx.err(&format!("[noise].{}", e.key), range_value(&e), e.allowed))?;
            Some(ns)
        }
    };

    // [perturb] and the cross-checks over every design point's extremes
    let sourced = perturb_cases(&cx, raw.perturb.as_ref())?;
    let (m_lo, _, m_at) = range("m");
    let (d_lo, _, d_at) = range("d");
    let (x_lo, x_hi, _) = range("x0");
    let (y_lo, y_hi, y_at) = range("y0");
    let (gap, y_worst) = if (y_hi - x_lo).abs() >= (y_lo - x_hi).abs() {
        ((y_hi - x_lo).abs(), y_hi)
    } else {
        ((y_lo - x_hi).abs(), y_lo)
    };
    if gap > 0.5 * d_lo {
        return Err(cx.err(
            &y_at,
            num(y_worst),
            format!(
                "the inner mass must start inside the cavity: |y0 - x0| reaches {}, more than \
                 d/2 = {} ({d_at})",
                num(gap),
                num(0.5 * d_lo)
            ),
        ));
    }
    for row in &sourced[1..] {
        let c = row.case;
        if let Some(seed) = c.noise_seed
            && noise.is_none()
        {
            return Err(cx.err(
                &row.seed_at,
                seed,
                "a noise seed needs a [noise] table (power, sample_time)",
            ));
        }
        if m_lo + c.dm < 0.0 {
            return Err(cx.err(
                &row.dm_at,
                num(c.dm),
                format!(
                    "m + dm must be >= 0 at every design point; the smallest m is {} kg ({m_at})",
                    num(m_lo)
                ),
            ));
        }
        if d_lo + c.dd <= 0.0 || (d_lo + c.dd).is_nan() {
            return Err(cx.err(
                &row.dd_at,
                num(c.dd),
                format!(
                    "d + dd must be > 0 at every design point; the smallest d is {} m ({d_at})",
                    num(d_lo)
                ),
            ));
        }
        if gap > 0.5 * (d_lo + c.dd) {
            return Err(cx.err(
                &row.dd_at,
                num(c.dd),
                format!(
                    "the inner mass must start inside the perturbed cavity: |y0 - x0| reaches {}, \
                     more than (d + dd)/2 = {}",
                    num(gap),
                    num(0.5 * (d_lo + c.dd))
                ),
            ));
        }
    }
    let cases: Vec<Case> = sourced.into_iter().map(|s| s.case).collect();

    // [solver]
    let mut solver = SolverSettings::default();
    let rs = &raw.solver;
    if let Some(k) = &rs.kind {
        solver.kind = SolverKind::parse(k).ok_or_else(|| {
            let names: Vec<&str> = SolverKind::ALL.iter().map(|k| k.name()).collect();
            cx.err(
                "[solver].kind",
                format!("{k:?}"),
                format!("unknown solver; allowed: {}", names.join(", ")),
            )
        })?;
    }
    if let Some(v) = rs.tol {
        solver.tol = v;
    }
    if let Some(v) = rs.chatter_tol {
        solver.chatter_tol = v;
    }
    if let Some(v) = rs.max_impacts {
        solver.max_impacts = v;
    }
    if let Some(v) = rs.max_steps {
        solver.max_steps = v;
    }
    if let Some(v) = rs.t_max_periods {
        solver.t_max_periods = v;
    }
    for (v, slot) in [
        (rs.h, &mut solver.h),
        (rs.rtol, &mut solver.rtol),
        (rs.atol, &mut solver.atol),
    ] {
        if let Some(v) = v {
            *slot = v;
        }
    }
    solver
        .validate()
        .map_err(|e| cx.err(&format!("[solver].{}", e.key), range_value(&e), e.allowed))?;

    // [reliability]
    let rr = &raw.reliability;
    let mut reliability = Reliability::default();
    for (key, v, slot) in [
        ("E", rr.E, &mut reliability.E),
        ("r", rr.r, &mut reliability.r),
        ("L", rr.L, &mut reliability.L),
    ] {
        if let Some(v) = v {
            if !(v.is_finite() && v > 0.0) {
                return Err(cx.err(
                    &format!("[reliability].{key}"),
                    num(v),
                    "must be a finite number > 0 (SI units)",
                ));
            }
            *slot = v;
        }
    }
    match (rr.strength_mean, rr.strength_sd) {
        (None, None) => {}
        (Some(mean), Some(sd)) => {
            if !(mean.is_finite() && mean > 0.0) {
                return Err(cx.err(
                    "[reliability].strength_mean",
                    num(mean),
                    "the mean strength must be a finite number > 0 (Pa)",
                ));
            }
            if !(sd.is_finite() && sd >= 0.0) {
                return Err(cx.err(
                    "[reliability].strength_sd",
                    num(sd),
                    "the standard deviation of strength must be a finite number >= 0 (Pa)",
                ));
            }
            reliability.strength_mean = mean;
            reliability.strength_sd = sd;
        }
        (Some(v), None) => {
            return Err(cx.err(
                "[reliability].strength_mean",
                num(v),
                "strength_sd must be given too (both or neither)",
            ));
        }
        (None, Some(v)) => {
            return Err(cx.err(
                "[reliability].strength_sd",
                num(v),
                "strength_mean must be given too (both or neither)",
            ));
        }
    }
    if let Some(s) = &rr.safety_form {
        reliability.safety_form = match s.as_str() {
            "exact" => SafetyForm::Exact,
            "paper" => SafetyForm::Paper,
            _ => {
                return Err(cx.err(
                    "[reliability].safety_form",
                    format!("{s:?}"),
                    "allowed: exact, paper",
                ));
            }
        };
    }
    if let Some(b) = rr.bootstrap {
        if b > 10_000_000 {
            return Err(cx.err(
                "[reliability].bootstrap",
                b,
                "must be a whole number in [0, 10000000] (0 disables the interval)",
            ));
        }
        reliability.bootstrap = b as usize;
    }
    if let Some(c) = rr.confidence {
        if !(c > 0.0 && c < 1.0) {
            return Err(cx.err(
                "[reliability].confidence",
                num(c),
                "the confidence level must be in (0, 1)",
            ));
        }
        reliability.confidence = c;
    }

    // [zones]
    let rz = &raw.zones;
    let mut zones = Zones::default();
    if let Some(k) = rz.jump_k {
        if !(k.is_finite() && k > 0.0) {
            return Err(cx.err("[zones].jump_k", num(k), "must be a finite number > 0"));
        }
        zones.jump_k = k;
    }
    if let Some(r) = rz.r_min {
        if !(0.0..=1.0).contains(&r) {
            return Err(cx.err("[zones].r_min", num(r), "a reliability must be in [0, 1]"));
        }
        zones.r_min = r;
    }
    if let Some(di) = rz.di_strong {
        if !(di.is_finite() && di >= 0.0) {
            return Err(cx.err(
                "[zones].di_strong",
                num(di),
                "must be a finite number >= 0 (m/s)",
            ));
        }
        zones.di_strong = Some(di);
    }
    for (i, z) in rz.zone.iter().enumerate() {
        let at = format!("[zones].zone[{i}]");
        if z.name.trim().is_empty() || rz.zone[..i].iter().any(|o| o.name == z.name) {
            return Err(cx.err(
                &format!("{at}.name"),
                format!("{:?}", z.name),
                "a zone needs a non-empty name, unique in the study",
            ));
        }
        if !axes.iter().any(|a| a.key == z.axis) {
            let swept: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
            return Err(cx.err(
                &format!("{at}.axis"),
                format!("{:?}", z.axis),
                format!(
                    "a zone is a range of a swept axis; swept: {}",
                    if swept.is_empty() {
                        "none".to_string()
                    } else {
                        swept.join(", ")
                    }
                ),
            ));
        }
        if !(z.from.is_finite() && z.to.is_finite() && z.from < z.to) {
            return Err(cx.err(
                &format!("{at}.to"),
                num(z.to),
                format!("must be a finite number > from = {}", num(z.from)),
            ));
        }
        zones.declared.push(DeclaredZone {
            name: z.name.clone(),
            axis: z.axis.clone(),
            from: z.from,
            to: z.to,
        });
    }

    // [ranking]
    let rk = &raw.ranking;
    let (wf1, wf2) = match (rk.wf1, rk.wf2) {
        (None, None) => (0.5, 0.5),
        (Some(a), None) => (a, 1.0 - a),
        (None, Some(b)) => (1.0 - b, b),
        (Some(a), Some(b)) => (a, b),
    };
    for (key, v) in [("wf1", wf1), ("wf2", wf2)] {
        if !(0.0..=1.0).contains(&v) {
            return Err(cx.err(
                &format!("[ranking].{key}"),
                num(v),
                "a weight must be in [0, 1]",
            ));
        }
    }
    if ((wf1 + wf2) - 1.0).abs() > 1e-9 {
        return Err(cx.err(
            "[ranking].wf2",
            num(wf2),
            format!(
                "wf1 + wf2 must be 1 (here {}), so that perfectibility is a percentage",
                num(wf1 + wf2)
            ),
        ));
    }
    let di_source = match rk.di_source.as_deref() {
        None | Some("ideal") => DiSource::Ideal,
        Some("mean") => DiSource::Mean,
        Some(s) => {
            return Err(cx.err(
                "[ranking].di_source",
                format!("{s:?}"),
                "allowed: ideal, mean",
            ));
        }
    };

    // [run]
    let n_cases = cases.len() as u64;
    let mut run = RunSettings {
        chunk_points: (DEFAULT_CHUNK_RUNS / n_cases).max(1),
        audit: 0,
    };
    if let Some(c) = raw.run.chunk_points {
        if c == 0 {
            return Err(cx.err("[run].chunk_points", c, "must be a whole number >= 1"));
        }
        run.chunk_points = c;
    }
    if let Some(a) = raw.run.audit {
        run.audit = a;
    }

    Ok(Study {
        path: path.to_path_buf(),
        source: text.to_string(),
        name: h.name.clone(),
        seed: h.seed.unwrap_or(0),
        request,
        system,
        axes,
        cases,
        noise,
        solver,
        reliability,
        zones,
        ranking: Ranking {
            wf1,
            wf2,
            di_source,
        },
        run,
    })
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

    #[test]
    fn line_and_column_count_characters() {
        assert_eq!(line_col("ab\ncdé\nf", 0), (1, 1));
        assert_eq!(line_col("ab\ncdé\nf", 3), (2, 1));
        assert_eq!(line_col("ab\ncdé\nf", 8), (3, 1));
        assert_eq!(line_col("ab\ncdé\nf", 7), (2, 4));
    }

    #[test]
    fn round15_recovers_typed_decimals() {
        assert_eq!(round15(0.1 + 0.2), 0.3);
        assert_eq!(round15(0.45 + 3.0 * 0.01), 0.48);
        assert_eq!(round15(-2.5e-7), -2.5e-7);
        assert_eq!(round15(0.0), 0.0);
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
                "[run]\nchunk_points", "[bogus]\nx",
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
