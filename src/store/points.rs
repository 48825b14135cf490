//! The points tables: the sweep's runs, one Parquet part file per chunk.
//!
//! A run directory `OUT/<name>/` holds `points/part-NNNNNN.parquet`, one file per chunk (chunk
//! `k` → `part-{k:06}.parquet`), rows in `point_id` order. Every part starts with the run's
//! identity and system, `point_id point case ideal dm dd noise_seed`, the system
//! `mass_main mass_inner K C d e x0 v0 y0 w0` (after `dm`, `dd`) and `solver tol`; the rest
//! is the scene's record ([`StoredRecord`]), so each scene has its own table (SI units; every
//! column in `docs/schema.md`):
//!
//! * free decay ([`Record`], table `points`): `h rtol atol`, `outcome`, the observables
//!   `x1 t1 x2 t2 xmax di`, the counts `impacts sticks steps` and
//!   `energy_impact energy_viscous t_stop`;
//! * the harmonic scene ([`HarmonicRecord`], table `forced_points`): the inputs `F0 omega r`,
//!   `outcome`, `amplitude impacts_per_period period amplitude_linear attenuation`, the
//!   transient and window `n_trans converged n_meas`, the window's energies
//!   `energy_force energy_viscous energy_impact`, the whole run's `impacts sticks steps t_stop`,
//!   and the attractor census at that frequency, `starts attractors amplitude_worst
//!   worst_period worst_impacts_per_period worst_basin_share rest_amplitude rest_period
//!   census_periods` ([`Steady`]);
//! * the random and record scenes ([`RealizationRecord`], table `random_points`, in
//!   [`super::random`]): the load's swept keys `S0 omega_g zeta_g omega_f zeta_f scale`, `outcome`,
//!   `amplitude t_peak rms_x rms_acc first_passage_time`, `impacts sticks energy_impact`,
//!   `samples t_stop steps`.
//!
//! `solver` and `outcome` are dictionary-encoded; `noise_seed` is null without noise;
//! observables are NaN when the outcome says so. A part's key-value metadata adds the study text
//! (`impactsweep.study`) to the version keys, and `impactsweep.table` says which table it holds.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, anyhow, bail};
use arrow_array::types::Int8Type;
use arrow_array::{
    Array, ArrayRef, BooleanArray, DictionaryArray, Float64Array, Int8Array, RecordBatch,
    StringArray, UInt32Array, UInt64Array,
};
use arrow_schema::{DataType, Schema, SchemaRef};

use super::manifest::{AttractorsEntry, WritingEntry};
use super::schema::{META_STUDY, META_TABLE, META_UNITS, TableKind, column_name};
use crate::model::{SYSTEM_KEYS, System, UNIT_KEYS, UnitTable};
use crate::sim::harmonic::Steady;
use crate::sim::random::RealizationRecord;
use crate::sim::{HarmonicRecord, Outcome, Record, SolverSettings, State};

/// The `f64` observable columns of a [`Record`], in schema order.
const OBSERVABLES: [&str; 6] = ["x1", "t1", "x2", "t2", "xmax", "di"];
const COUNTS: [&str; 3] = ["impacts", "sticks", "steps"];
const ENERGIES: [&str; 3] = ["energy_impact", "energy_viscous", "t_stop"];
/// Dictionary-encoded columns.
const DICTIONARY: [&str; 2] = ["outcome", "solver"];

/// One stored run, as the reducer reads it back: its identity, its system and its scene's record
/// (`R` = [`Record`] for free decay, [`HarmonicRecord`] for the harmonic scene).
#[derive(Clone, Debug, PartialEq)]
pub struct RunRow<R = Record> {
    pub point_id: u64,
    pub point: u64,
    pub case: u32,
    pub ideal: bool,
    pub dm: f64,
    pub dd: f64,
    pub noise_seed: Option<u64>,
    pub system: System,
    /// The solver's name: borrowed when simulated (no allocation per run), owned when read back.
    pub solver: Cow<'static, str>,
    pub tol: f64,
    /// The record; a free-decay record's `peaks` holds at most `(x1, t1), (x2, t2)` when read
    /// back, a forced record's `end` state is not stored (NaN when read back).
    pub record: R,
}

/// A scene's record as the points table stores it: its table, its columns after `solver tol`,
/// and how to read them back.
pub trait StoredRecord: Sized {
    /// The table the parts hold (`impactsweep.table`).
    const TABLE: TableKind;
    /// How the run ended.
    fn outcome(&self) -> Outcome;
    /// The columns after `tol`: name, type, nullable.
    fn fields() -> Vec<(&'static str, DataType, bool)>;
    /// Those columns for `rows`, in [`StoredRecord::fields`] order.
    fn arrays(rows: &[RunRow<Self>], settings: &SolverSettings) -> Result<Vec<ArrayRef>>;
    /// The records of a batch, one per row.
    fn read(batch: &RecordBatch) -> Result<Vec<Self>>;
}

pub(super) fn dict_type() -> DataType {
    DataType::Dictionary(Box::new(DataType::Int8), Box::new(DataType::Utf8))
}

/// The Arrow schema of a free-decay part file (the columns above, in that order, with their
/// units).
pub fn schema() -> SchemaRef {
    schema_of::<Record>(false)
}

/// The Arrow schema of the parts of `R`'s table; `units`: a study of several damper units,
/// whose parts carry the [`UNIT_KEYS`] columns after the system's (a study of one unit has
/// exactly the columns it had before they existed).
pub fn schema_of<R: StoredRecord>(units: bool) -> SchemaRef {
    let t = R::TABLE;
    let mut cols: Vec<(&str, DataType, bool)> = vec![
        ("point_id", DataType::UInt64, false),
        ("point", DataType::UInt64, false),
        ("case", DataType::UInt32, false),
        ("ideal", DataType::Boolean, false),
        ("dm", DataType::Float64, false),
        ("dd", DataType::Float64, false),
        ("noise_seed", DataType::UInt64, true),
    ];
    for key in SYSTEM_KEYS {
        cols.push((column_name(key), DataType::Float64, false));
    }
    if units {
        for key in UNIT_KEYS {
            cols.push((column_name(key), DataType::Float64, false));
        }
    }
    cols.push(("solver", dict_type(), false));
    cols.push(("tol", DataType::Float64, false));
    cols.extend(R::fields());
    let fields = cols
        .into_iter()
        .map(|(name, dt, nullable)| {
            super::field(t, name, dt, nullable).expect("every points column has a unit")
        })
        .collect::<Vec<_>>();
    Arc::new(Schema::new(fields))
}

/// The file of chunk `k` in a run directory.
pub fn part_path(run_dir: &Path, k: u64) -> PathBuf {
    run_dir.join("points").join(format!("part-{k:06}.parquet"))
}

/// The chunk id of a part file name (`part-000012.parquet` → 12).
pub fn part_chunk(path: &Path) -> Option<u64> {
    let name = path.file_name()?.to_str()?;
    let digits = name.strip_prefix("part-")?.strip_suffix(".parquet")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The finished part files of a run directory, in chunk order (temporary files excluded).
pub fn part_files(run_dir: &Path) -> Result<Vec<PathBuf>> {
    let dir = run_dir.join("points");
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut parts = Vec::new();
    for entry in std::fs::read_dir(&dir).with_context(|| format!("listing {}", dir.display()))? {
        let path = entry
            .with_context(|| format!("listing {}", dir.display()))?
            .path();
        if let Some(k) = part_chunk(&path) {
            parts.push((k, path));
        }
    }
    parts.sort();
    Ok(parts.into_iter().map(|(_, p)| p).collect())
}

/// What [`write_part`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartInfo {
    pub rows: u64,
    /// The file's checksum (16 hex digits) by the algorithm asked for.
    pub checksum: String,
    pub bytes: u64,
    /// The chunk's attractors part, when it has one.
    pub attractors: Option<AttractorsEntry>,
}

impl PartInfo {
    /// The record of chunk `k`'s part files about to be renamed into place (the journal's
    /// `writing` line), as [`write_part`] wrote them.
    pub fn writing(&self, k: u64) -> WritingEntry {
        WritingEntry {
            chunk: k,
            checksum: self.checksum.clone(),
            attractors: self.attractors.as_ref().map(|a| a.checksum.clone()),
        }
    }
}

/// Encodes rows as one part file (see [`super::encode`]; `outcome` and `solver`
/// dictionary-encoded, the study text and `extra` in the metadata).
///
/// `settings` fills the free-decay table's `h`, `rtol`, `atol` columns (one study, one solver
/// setting; [`RunRow`] carries `solver` and `tol` only).
pub fn encode_part<R: StoredRecord>(
    rows: &[RunRow<R>],
    study_toml: &str,
    settings: &SolverSettings,
    units: bool,
    extra: &[(&str, &str)],
) -> Result<Vec<u8>> {
    let batch = to_batch(rows, settings, units)?;
    let mut meta = vec![(META_STUDY.to_string(), study_toml.to_string())];
    if let Some(table) = rows.first().and_then(|r| r.system.table) {
        meta.push((META_UNITS.to_string(), serde_json::to_string(&table)?));
    }
    meta.extend(extra.iter().map(|(k, v)| (k.to_string(), v.to_string())));
    super::encode(
        R::TABLE,
        &batch,
        &super::WriteOptions {
            dictionary: &DICTIONARY,
            extra: meta,
        },
    )
}

/// Writes chunk `k`'s rows into the run directory `dir` atomically (each file to its temporary
/// name, then renamed; not synced: the sweep engine syncs its file system about once a second)
/// and returns their `checksum`. With `attractors` (a harmonic study with a census), the chunk
/// also has an attractors part and the points part says so ([`super::attractors`]).
///
/// Both files are written under their temporary names first; then `record` is given their
/// checksums, before either is renamed (the sweep engine journals them, so that a part renamed
/// but never recorded as finished is held to the checksum it was written with,
/// [`crate::sweep::verify`]); then the attractors part is renamed and the points part last, so
/// it stays the chunk's commit marker. An error from `record` renames nothing.
#[allow(clippy::too_many_arguments)]
pub fn write_part<R: StoredRecord>(
    dir: &Path,
    k: u64,
    rows: &[RunRow<R>],
    attractors: Option<&[crate::orbits::attractors::AttractorRow]>,
    study_toml: &str,
    settings: &SolverSettings,
    units: bool,
    checksum: super::Checksum,
    record: impl FnOnce(&PartInfo) -> Result<()>,
) -> Result<PartInfo> {
    let side = match attractors {
        Some(a) => {
            let path = super::attractors::attractors_part_path(dir, k);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent)
                    .with_context(|| format!("creating {}", parent.display()))?;
            }
            let bytes = super::attractors::encode_part(a, study_toml, units)?;
            let entry = AttractorsEntry {
                rows: a.len() as u64,
                checksum: checksum.hex(&bytes),
            };
            let tmp = super::write_tmp(&path, &bytes, super::Durability::Later)?;
            Some((entry, tmp, path))
        }
        None => None,
    };
    let marker = [(super::attractors::META_ATTRACTORS, "1")];
    let extra: &[(&str, &str)] = if side.is_some() { &marker } else { &[] };
    let bytes = encode_part(rows, study_toml, settings, units, extra)?;
    let path = part_path(dir, k);
    let tmp = super::write_tmp(&path, &bytes, super::Durability::Later)?;
    let info = PartInfo {
        rows: rows.len() as u64,
        checksum: checksum.hex(&bytes),
        bytes: bytes.len() as u64,
        attractors: side.as_ref().map(|s| s.0.clone()),
    };
    record(&info)?;
    if let Some((_, side_tmp, side_path)) = &side {
        super::rename_into_place(side_tmp, side_path)?;
    }
    super::rename_into_place(&tmp, &path)?;
    Ok(info)
}

/// A Float64 column of `rows`.
pub(super) fn f64col<R>(rows: &[RunRow<R>], f: impl Fn(&RunRow<R>) -> f64) -> ArrayRef {
    Arc::new(Float64Array::from_iter_values(rows.iter().map(f)))
}

/// A UInt64 column of `rows`.
pub(super) fn u64col<R>(rows: &[RunRow<R>], f: impl Fn(&RunRow<R>) -> u64) -> ArrayRef {
    Arc::new(UInt64Array::from_iter_values(rows.iter().map(f)))
}

/// A dictionary column of `rows`: `names` and each row's key into them.
fn dict<R>(rows: &[RunRow<R>], names: &[&str], f: impl Fn(&RunRow<R>) -> i8) -> Result<ArrayRef> {
    let keys = Int8Array::from_iter_values(rows.iter().map(f));
    let values: ArrayRef = Arc::new(StringArray::from(names.to_vec()));
    Ok(Arc::new(DictionaryArray::<Int8Type>::try_new(
        keys, values,
    )?))
}

/// The outcome column: the dictionary is every outcome in [`Outcome::ALL`] order, so keys are
/// stable across files.
pub(super) fn outcome_col<R: StoredRecord>(rows: &[RunRow<R>]) -> Result<ArrayRef> {
    let outcomes: Vec<&str> = Outcome::ALL.iter().map(|o| o.name()).collect();
    dict(rows, &outcomes, |r| {
        Outcome::ALL
            .iter()
            .position(|o| *o == r.record.outcome())
            .unwrap_or(0) as i8
    })
}

/// The accessor of system key `key` ([`System::get`] without a string comparison per row: a
/// part of 65,536 rows compared 655,360 key names); NaN for a key that is not a system key.
fn system_field(key: &str) -> fn(&System) -> f64 {
    match key {
        "M" => |s| s.M,
        "m" => |s| s.m,
        "K" => |s| s.K,
        "C" => |s| s.C,
        "d" => |s| s.d,
        "e" => |s| s.e,
        "x0" => |s| s.x0,
        "v0" => |s| s.v0,
        "y0" => |s| s.y0,
        "w0" => |s| s.w0,
        _ => |_| f64::NAN,
    }
}

/// The rows as one Arrow batch of `R`'s table ([`schema_of`]): what a part file holds, and what
/// the Python package's `simulate_batch` returns.
pub fn to_batch<R: StoredRecord>(
    rows: &[RunRow<R>],
    settings: &SolverSettings,
    units: bool,
) -> Result<RecordBatch> {
    let mut cols: Vec<ArrayRef> = vec![
        u64col(rows, |r| r.point_id),
        u64col(rows, |r| r.point),
        Arc::new(UInt32Array::from_iter_values(rows.iter().map(|r| r.case))),
        Arc::new(BooleanArray::from_iter(rows.iter().map(|r| Some(r.ideal)))),
        f64col(rows, |r| r.dm),
        f64col(rows, |r| r.dd),
        Arc::new(UInt64Array::from_iter(rows.iter().map(|r| r.noise_seed))),
    ];
    for key in SYSTEM_KEYS {
        let field = system_field(key);
        cols.push(f64col(rows, |r| field(&r.system)));
    }
    if units {
        cols.push(f64col(rows, |r| r.system.units));
        cols.push(f64col(rows, |r| r.system.d_spread));
    }
    // The dictionary of solver names: those present, in first-seen order (deterministic).
    let mut solvers: Vec<&str> = Vec::new();
    for r in rows {
        if !solvers.contains(&&*r.solver) {
            solvers.push(&r.solver);
        }
    }
    if solvers.len() > i8::MAX as usize {
        bail!("too many solver names in one part ({})", solvers.len());
    }
    cols.push(dict(rows, &solvers, |r| {
        solvers.iter().position(|s| *s == r.solver).unwrap_or(0) as i8
    })?);
    cols.push(f64col(rows, |r| r.tol));
    cols.extend(R::arrays(rows, settings)?);
    Ok(RecordBatch::try_new(schema_of::<R>(units), cols)?)
}

impl StoredRecord for Record {
    const TABLE: TableKind = TableKind::Points;

    fn outcome(&self) -> Outcome {
        self.outcome
    }

    fn fields() -> Vec<(&'static str, DataType, bool)> {
        let mut cols: Vec<(&str, DataType, bool)> = Vec::new();
        for key in ["h", "rtol", "atol"] {
            cols.push((key, DataType::Float64, false));
        }
        cols.push(("outcome", dict_type(), false));
        for key in OBSERVABLES {
            cols.push((key, DataType::Float64, false));
        }
        for key in COUNTS {
            cols.push((key, DataType::UInt64, false));
        }
        for key in ENERGIES {
            cols.push((key, DataType::Float64, false));
        }
        cols
    }

    fn arrays(rows: &[RunRow<Self>], settings: &SolverSettings) -> Result<Vec<ArrayRef>> {
        let mut cols = Vec::new();
        for v in [settings.h, settings.rtol, settings.atol] {
            cols.push(f64col(rows, |_| v));
        }
        cols.push(outcome_col(rows)?);
        cols.push(f64col(rows, |r| r.record.x1));
        cols.push(f64col(rows, |r| r.record.t1));
        cols.push(f64col(rows, |r| r.record.x2));
        cols.push(f64col(rows, |r| r.record.t2));
        cols.push(f64col(rows, |r| r.record.xmax));
        cols.push(f64col(rows, |r| r.record.di));
        cols.push(u64col(rows, |r| r.record.impacts));
        cols.push(u64col(rows, |r| r.record.sticks));
        cols.push(u64col(rows, |r| r.record.steps));
        cols.push(f64col(rows, |r| r.record.energy_impact));
        cols.push(f64col(rows, |r| r.record.energy_viscous));
        cols.push(f64col(rows, |r| r.record.t_stop));
        Ok(cols)
    }

    fn read(batch: &RecordBatch) -> Result<Vec<Self>> {
        let u64s = |n| column::<UInt64Array>(batch, n);
        let f64s = |n| column::<Float64Array>(batch, n);
        let outcome = outcomes(batch)?;
        let obs: Vec<&Float64Array> = OBSERVABLES.iter().map(|k| f64s(k)).collect::<Result<_>>()?;
        let counts: Vec<&UInt64Array> = COUNTS.iter().map(|k| u64s(k)).collect::<Result<_>>()?;
        let en: Vec<&Float64Array> = ENERGIES.iter().map(|k| f64s(k)).collect::<Result<_>>()?;
        let mut out = Vec::with_capacity(batch.num_rows());
        for (i, outcome) in outcome.into_iter().enumerate() {
            let (x1, t1, x2, t2) = (
                obs[0].value(i),
                obs[1].value(i),
                obs[2].value(i),
                obs[3].value(i),
            );
            let peaks = [(x1, t1), (x2, t2)]
                .into_iter()
                .filter(|(x, t)| !x.is_nan() && !t.is_nan())
                .collect();
            out.push(Record {
                outcome,
                peaks,
                x1,
                t1,
                x2,
                t2,
                xmax: obs[4].value(i),
                di: obs[5].value(i),
                impacts: counts[0].value(i),
                sticks: counts[1].value(i),
                // Not stored: the runs table keeps the total (a simultaneous impact once).
                unit_impacts: Vec::new(),
                steps: counts[2].value(i),
                energy_impact: en[0].value(i),
                energy_viscous: en[1].value(i),
                t_stop: en[2].value(i),
            });
        }
        Ok(out)
    }
}

/// The `f64` outputs of a [`HarmonicRecord`] after `outcome`, in schema order (then `period`).
const FORCED_OUTPUTS: [&str; 2] = ["amplitude", "impacts_per_period"];
/// The window's energies of a [`HarmonicRecord`].
const FORCED_ENERGIES: [&str; 3] = ["energy_force", "energy_viscous", "energy_impact"];

impl StoredRecord for HarmonicRecord {
    const TABLE: TableKind = TableKind::HarmonicPoints;

    fn outcome(&self) -> Outcome {
        self.outcome
    }

    fn fields() -> Vec<(&'static str, DataType, bool)> {
        let f = |name| (name, DataType::Float64, false);
        let u = |name| (name, DataType::UInt64, false);
        let mut cols = vec![f("F0"), f("omega"), f("r"), ("outcome", dict_type(), false)];
        cols.extend(FORCED_OUTPUTS.map(f));
        cols.push(("period", DataType::UInt32, false));
        cols.push(f("amplitude_linear"));
        cols.push(f("attenuation"));
        cols.push(u("n_trans"));
        cols.push(("converged", DataType::Boolean, false));
        cols.push(u("n_meas"));
        cols.extend(FORCED_ENERGIES.map(f));
        cols.extend(COUNTS.map(u));
        cols.push(f("t_stop"));
        cols.push(("starts", DataType::UInt32, false));
        cols.push(("attractors", DataType::UInt32, false));
        cols.push(f("amplitude_worst"));
        cols.push(("worst_period", DataType::UInt32, false));
        cols.push(f("worst_impacts_per_period"));
        cols.push(f("worst_basin_share"));
        cols.push(f("rest_amplitude"));
        cols.push(("rest_period", DataType::UInt32, false));
        cols.push(u("census_periods"));
        cols.push(("worst_kind", DataType::Utf8, false));
        cols.extend(WORST_LIFE.map(f));
        cols
    }

    fn arrays(rows: &[RunRow<Self>], _settings: &SolverSettings) -> Result<Vec<ArrayRef>> {
        let mut cols = vec![
            f64col(rows, |r| r.record.F0),
            f64col(rows, |r| r.record.omega),
            f64col(rows, |r| r.record.r),
            outcome_col(rows)?,
            f64col(rows, |r| r.record.amplitude),
            f64col(rows, |r| r.record.impacts_per_period),
            Arc::new(UInt32Array::from_iter_values(
                rows.iter().map(|r| r.record.period),
            )),
            f64col(rows, |r| r.record.amplitude_linear),
            f64col(rows, |r| r.record.attenuation),
            u64col(rows, |r| r.record.n_trans),
            Arc::new(BooleanArray::from_iter(
                rows.iter().map(|r| Some(r.record.converged)),
            )),
            u64col(rows, |r| r.record.n_meas),
            f64col(rows, |r| r.record.energy_force),
            f64col(rows, |r| r.record.energy_viscous),
            f64col(rows, |r| r.record.energy_impact),
            u64col(rows, |r| r.record.impacts),
            u64col(rows, |r| r.record.sticks),
            u64col(rows, |r| r.record.steps),
        ];
        cols.push(f64col(rows, |r| r.record.t_stop));
        let u32col = |g: fn(&Steady) -> u32| -> ArrayRef {
            Arc::new(UInt32Array::from_iter_values(
                rows.iter().map(|r| g(&r.record.steady)),
            ))
        };
        cols.push(u32col(|s| s.starts));
        cols.push(u32col(|s| s.attractors));
        cols.push(f64col(rows, |r| r.record.steady.amplitude_worst));
        cols.push(u32col(|s| s.worst_period));
        cols.push(f64col(rows, |r| r.record.steady.worst_impacts_per_period));
        cols.push(f64col(rows, |r| r.record.steady.worst_basin_share));
        cols.push(f64col(rows, |r| r.record.steady.rest_amplitude));
        cols.push(u32col(|s| s.rest_period));
        cols.push(u64col(rows, |r| r.record.steady.census_periods));
        cols.push(Arc::new(StringArray::from_iter_values(
            rows.iter().map(|r| r.record.steady.worst_kind),
        )));
        cols.push(f64col(rows, |r| r.record.steady.worst_lyapunov));
        cols.push(f64col(rows, |r| r.record.steady.worst_window_amplitude));
        cols.push(f64col(rows, |r| r.record.steady.worst_life_lo));
        cols.push(f64col(rows, |r| r.record.steady.worst_life_hi));
        Ok(cols)
    }

    fn read(batch: &RecordBatch) -> Result<Vec<Self>> {
        let u64s = |n| column::<UInt64Array>(batch, n);
        let f64s = |n| column::<Float64Array>(batch, n);
        let outcome = outcomes(batch)?;
        let (f0, omega, r) = (f64s("F0")?, f64s("omega")?, f64s("r")?);
        let (amplitude, per_period) = (f64s("amplitude")?, f64s("impacts_per_period")?);
        let period: &UInt32Array = column(batch, "period")?;
        let (linear, attenuation) = (f64s("amplitude_linear")?, f64s("attenuation")?);
        let (n_trans, n_meas) = (u64s("n_trans")?, u64s("n_meas")?);
        let converged: &BooleanArray = column(batch, "converged")?;
        let en: Vec<&Float64Array> = FORCED_ENERGIES
            .iter()
            .map(|k| f64s(k))
            .collect::<Result<_>>()?;
        let counts: Vec<&UInt64Array> = COUNTS.iter().map(|k| u64s(k)).collect::<Result<_>>()?;
        let t_stop = f64s("t_stop")?;
        let steady = read_steady(batch)?;
        let nan = f64::NAN;
        let mut out = Vec::with_capacity(batch.num_rows());
        for (i, outcome) in outcome.into_iter().enumerate() {
            out.push(HarmonicRecord {
                steady: steady.as_ref().map_or(Steady::NONE, |st| st(i)),
                outcome,
                F0: f0.value(i),
                omega: omega.value(i),
                r: r.value(i),
                amplitude: amplitude.value(i),
                impacts_per_period: per_period.value(i),
                period: period.value(i),
                amplitude_linear: linear.value(i),
                attenuation: attenuation.value(i),
                n_trans: n_trans.value(i),
                converged: converged.value(i),
                n_meas: n_meas.value(i),
                energy_force: en[0].value(i),
                energy_viscous: en[1].value(i),
                energy_impact: en[2].value(i),
                end: State {
                    x: nan,
                    v: nan,
                    y: nan,
                    w: nan,
                },
                impacts: counts[0].value(i),
                sticks: counts[1].value(i),
                steps: counts[2].value(i),
                t_stop: t_stop.value(i),
            });
        }
        Ok(out)
    }
}

/// The census columns of a forced part, as a function of the row; `None` for a part written
/// before the census (it reduces as `design_peak = "from_rest"`).
#[allow(clippy::type_complexity)]
fn read_steady(batch: &RecordBatch) -> Result<Option<Box<dyn Fn(usize) -> Steady + '_>>> {
    if batch.schema().index_of("amplitude_worst").is_err() {
        return Ok(None);
    }
    let u32s = |n| column::<UInt32Array>(batch, n);
    let f64s = |n| column::<Float64Array>(batch, n);
    let (starts, attractors, worst_period) =
        (u32s("starts")?, u32s("attractors")?, u32s("worst_period")?);
    let (worst, ipp, share) = (
        f64s("amplitude_worst")?,
        f64s("worst_impacts_per_period")?,
        f64s("worst_basin_share")?,
    );
    let (rest, rest_period) = (f64s("rest_amplitude")?, u32s("rest_period")?);
    let periods = column::<UInt64Array>(batch, "census_periods")?;
    // The worst attractor's kind and life columns (issue 22); absent from older parts.
    let life = if batch.schema().index_of("worst_kind").is_ok() {
        let kind = column::<StringArray>(batch, "worst_kind")?;
        let cols = WORST_LIFE
            .iter()
            .map(|n| f64s(n))
            .collect::<Result<Vec<_>>>()?;
        Some((kind, cols))
    } else {
        None
    };
    let life_of = move |i: usize| -> (&'static str, [f64; 4]) {
        match &life {
            Some((kind, cols)) => (
                crate::orbits::attractors::SteadyKind::parse(kind.value(i))
                    .map_or("", |k| k.name()),
                [0, 1, 2, 3].map(|j| cols[j].value(i)),
            ),
            None => ("", [f64::NAN; 4]),
        }
    };
    Ok(Some(Box::new(move |i| {
        let (worst_kind, [lyapunov, window, lo, hi]) = life_of(i);
        Steady {
            starts: starts.value(i),
            attractors: attractors.value(i),
            amplitude_worst: worst.value(i),
            worst_period: worst_period.value(i),
            worst_impacts_per_period: ipp.value(i),
            worst_basin_share: share.value(i),
            rest_amplitude: rest.value(i),
            rest_period: rest_period.value(i),
            census_periods: periods.value(i),
            worst_kind,
            worst_lyapunov: lyapunov,
            worst_window_amplitude: window,
            worst_life_lo: lo,
            worst_life_hi: hi,
        }
    })))
}

/// The worst attractor's Float64 columns after `worst_kind` ([`Steady`]).
const WORST_LIFE: [&str; 4] = [
    "worst_lyapunov",
    "worst_window_amplitude",
    "worst_life_lo",
    "worst_life_hi",
];

/// The number of rows of a part file, from its footer (cheap; fails on a damaged file).
pub fn part_rows(path: &Path) -> Result<u64> {
    let builder = super::open(path)?;
    Ok(builder.metadata().file_metadata().num_rows() as u64)
}

/// The key-value metadata of a part file.
pub fn part_metadata(path: &Path) -> Result<BTreeMap<String, String>> {
    Ok(super::metadata_of(&super::open(path)?))
}

/// The point ids (in file order) and the outcome counts of a part file of either scene's table
/// (`impactsweep.table` says which), every record read: what a part's check needs
/// ([`crate::sweep::verify`]).
pub fn read_ids_outcomes(path: &Path) -> Result<(Vec<u64>, BTreeMap<String, u64>)> {
    fn of<R: StoredRecord>(rows: Vec<RunRow<R>>) -> (Vec<u64>, BTreeMap<String, u64>) {
        let mut counts = BTreeMap::new();
        for r in &rows {
            *counts
                .entry(r.record.outcome().name().to_string())
                .or_default() += 1;
        }
        (rows.iter().map(|r| r.point_id).collect(), counts)
    }
    let meta = part_metadata(path)?;
    let table = meta.get(META_TABLE).map(String::as_str);
    Ok(if table == Some(TableKind::HarmonicPoints.name()) {
        of(read_rows::<HarmonicRecord>(path)?)
    } else if table == Some(TableKind::RandomPoints.name()) {
        of(read_rows::<RealizationRecord>(path)?)
    } else {
        of(read_rows::<Record>(path)?)
    })
}

/// Reads a free-decay part file back into rows, in file order ([`read_rows`]).
pub fn read_part(path: &Path) -> Result<Vec<RunRow>> {
    read_rows(path)
}

/// Reads a part file of `R`'s table back into rows, in file order. A part of another schema
/// version, or of another scene's table, is refused with a message that says what it holds.
pub fn read_rows<R: StoredRecord>(path: &Path) -> Result<Vec<RunRow<R>>> {
    let builder = super::open(path)?;
    let meta = super::metadata_of(&builder);
    super::check_version(path, &meta)?;
    if let Some(table) = meta.get(META_TABLE)
        && table != R::TABLE.name()
    {
        return Err(crate::error::InputError::new(format!(
            "{}: holds the {table} table, not {} (a part of another scene's study; see \
             docs/schema.md)",
            path.display(),
            R::TABLE.name()
        ))
        .into());
    }
    let table: Option<UnitTable> = meta
        .get(META_UNITS)
        .map(|json| serde_json::from_str(json))
        .transpose()
        .with_context(|| format!("reading {} of {}", META_UNITS, path.display()))?;
    let mut rows = Vec::new();
    for batch in super::read_batches(path, builder)? {
        read_batch(&batch, &mut rows).with_context(|| format!("reading {}", path.display()))?;
    }
    if table.is_some() {
        for row in &mut rows {
            row.system.table = table;
        }
    }
    Ok(rows)
}

pub(super) fn column<'a, T: 'static>(batch: &'a RecordBatch, name: &str) -> Result<&'a T> {
    batch
        .column_by_name(name)
        .ok_or_else(|| anyhow!("column `{name}` is missing"))?
        .as_any()
        .downcast_ref::<T>()
        .ok_or_else(|| anyhow!("column `{name}` has an unexpected type"))
}

/// The strings of a dictionary column, one per row.
fn dict_strings(batch: &RecordBatch, name: &str) -> Result<Vec<String>> {
    let dict: &DictionaryArray<Int8Type> = column(batch, name)?;
    let values = dict
        .values()
        .as_any()
        .downcast_ref::<StringArray>()
        .ok_or_else(|| anyhow!("column `{name}`: dictionary values are not strings"))?;
    dict.keys()
        .iter()
        .map(|k| {
            let k = k.ok_or_else(|| anyhow!("column `{name}`: null value"))?;
            Ok(values.value(k as usize).to_string())
        })
        .collect()
}

/// The outcome of every row.
pub(super) fn outcomes(batch: &RecordBatch) -> Result<Vec<Outcome>> {
    dict_strings(batch, "outcome")?
        .into_iter()
        .map(|name| {
            Outcome::ALL
                .into_iter()
                .find(|o| o.name() == name)
                .ok_or_else(|| anyhow!("unknown outcome `{name}`"))
        })
        .collect()
}

fn read_batch<R: StoredRecord>(batch: &RecordBatch, rows: &mut Vec<RunRow<R>>) -> Result<()> {
    let u64s = |n| column::<UInt64Array>(batch, n);
    let f64s = |n| column::<Float64Array>(batch, n);
    let point_id = u64s("point_id")?;
    let point = u64s("point")?;
    let case: &UInt32Array = column(batch, "case")?;
    let ideal: &BooleanArray = column(batch, "ideal")?;
    let dm = f64s("dm")?;
    let dd = f64s("dd")?;
    let noise_seed = u64s("noise_seed")?;
    let sys: Vec<&Float64Array> = SYSTEM_KEYS
        .iter()
        .map(|k| f64s(column_name(k)))
        .collect::<Result<_>>()?;
    // A study of several units has their columns; one of one unit does not.
    let units: Vec<(&str, &Float64Array)> = UNIT_KEYS
        .iter()
        .filter(|k| batch.schema().column_with_name(column_name(k)).is_some())
        .map(|k| Ok((*k, f64s(column_name(k))?)))
        .collect::<Result<_>>()?;
    let solver = dict_strings(batch, "solver")?;
    let tol = f64s("tol")?;
    for (i, record) in R::read(batch)?.into_iter().enumerate() {
        let mut system = System::TABLE_I;
        for (key, col) in SYSTEM_KEYS.iter().zip(&sys) {
            system.set(key, col.value(i));
        }
        for (key, col) in &units {
            system.set(key, col.value(i));
        }
        rows.push(RunRow {
            point_id: point_id.value(i),
            point: point.value(i),
            case: case.value(i),
            ideal: ideal.value(i),
            dm: dm.value(i),
            dd: dd.value(i),
            noise_seed: noise_seed.is_valid(i).then(|| noise_seed.value(i)),
            system,
            solver: Cow::Owned(solver[i].clone()),
            tol: tol.value(i),
            record,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::schema::{META_SCHEMA_VERSION, SCHEMA_VERSION};
    use super::super::{checksum_file, tmp_path};
    use super::*;
    use crate::sim::{NoProbe, Request, SolverSettings, simulate};

    #[test]
    fn system_fields_are_the_system_keys() {
        let mut s = System::TABLE_I;
        for (i, key) in SYSTEM_KEYS.iter().enumerate() {
            assert!(s.set(key, 1.0 + i as f64));
        }
        for key in SYSTEM_KEYS {
            assert_eq!(Some(system_field(key)(&s)), s.get(key), "{key}");
        }
        assert!(system_field("bogus")(&s).is_nan());
    }

    fn rows() -> Vec<RunRow> {
        let settings = SolverSettings::default();
        (0..5u64)
            .map(|p| {
                let mut system = System::TABLE_I;
                system.e = 0.5 + 0.1 * p as f64;
                let record = simulate(&system, &settings, &Request::default(), None, &mut NoProbe);
                RunRow {
                    point_id: p,
                    point: p,
                    case: 0,
                    ideal: p % 2 == 0,
                    dm: 0.0,
                    dd: 0.0,
                    noise_seed: (p % 2 == 1).then_some(p * 7),
                    system,
                    solver: "exact".into(),
                    tol: settings.tol,
                    record,
                }
            })
            .collect()
    }

    /// Peaks beyond the second are not stored, so compare on what the store keeps.
    fn trimmed(mut r: RunRow) -> RunRow {
        r.record.peaks.truncate(2);
        r
    }

    #[test]
    fn write_then_read_gives_the_same_rows_and_bytes_are_deterministic() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("points")).unwrap();
        let path = part_path(dir.path(), 3);
        let rows = rows();
        let info = write_part(
            dir.path(),
            3,
            &rows,
            None,
            "name = 'x'",
            &SolverSettings::default(),
            false,
            super::super::Checksum::DEFAULT,
            |info| {
                // Issue 45: the checksum is known while the part still has its temporary name.
                assert!(!path.exists() && tmp_path(&path).exists());
                assert_eq!(
                    info.checksum,
                    format!("{:016x}", checksum_file(&tmp_path(&path)).unwrap())
                );
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(info.rows, 5);
        assert_eq!(
            info.checksum,
            format!("{:016x}", checksum_file(&path).unwrap())
        );
        assert!(!tmp_path(&path).exists());
        let back = read_part(&path).unwrap();
        let want: Vec<RunRow> = rows.into_iter().map(trimmed).collect();
        assert_eq!(back.len(), want.len());
        for (a, b) in back.iter().zip(&want) {
            // NaN != NaN, so compare the debug text (which shows NaN) and the bits of DI.
            assert_eq!(format!("{a:?}"), format!("{b:?}"));
            assert_eq!(a.record.di.to_bits(), b.record.di.to_bits());
        }
        assert_eq!(part_rows(&path).unwrap(), 5);
        let meta = part_metadata(&path).unwrap();
        assert_eq!(meta[META_STUDY], "name = 'x'");
        assert_eq!(meta[META_SCHEMA_VERSION], SCHEMA_VERSION.to_string());
        assert_eq!(meta[super::super::META_TABLE], "points");
        assert_eq!(
            encode_part(&want, "name = 'x'", &SolverSettings::default(), false, &[]).unwrap(),
            std::fs::read(&path).unwrap()
        );
        assert_eq!(part_files(dir.path()).unwrap(), vec![path]);
    }

    #[test]
    fn schema_matches_the_documented_columns() {
        let names: Vec<String> = schema().fields().iter().map(|f| f.name().clone()).collect();
        let doc = "point_id point case ideal dm dd noise_seed mass_main mass_inner K C d e x0 v0 \
                   y0 w0 solver tol h rtol atol outcome x1 t1 x2 t2 xmax di impacts sticks steps \
                   energy_impact energy_viscous t_stop";
        assert_eq!(names.join(" "), doc);
        assert!(super::super::schema::case_clashes(names.iter().map(String::as_str)).is_empty());
        let schema = schema();
        let units: Vec<&str> = schema
            .fields()
            .iter()
            .map(|f| f.metadata()["unit"].as_str())
            .collect();
        assert_eq!(&units[7..9], ["kg", "kg"]);
    }

    #[test]
    fn part_names_parse() {
        assert_eq!(part_chunk(Path::new("a/part-000012.parquet")), Some(12));
        assert_eq!(part_chunk(Path::new("a/part-000012.parquet.tmp")), None);
        assert_eq!(part_chunk(Path::new("a/part-.parquet")), None);
    }
}
