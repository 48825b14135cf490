//! The load of `[scene] kind = "random"` and `kind = "record"` (docs/scenes.md, docs/model.md
//! §13): the structure under a random load generated per realization, or under a recorded
//! accelerogram or force history. The keys live in `[scene]` beside the harmonic scene's
//! ([`RawScene`]); this module validates them into a [`RandomScene`] and the number of
//! realizations, reads the record ([`crate::study::record`]) and checks one swept value of a
//! scene key ([`check_key`]). The study around the load is [`super::random`]'s.
//!
//! | key | scene | unit | default | range |
//! |---|---|---|---|---|
//! | `input` | both | | `"base"` (a record: its column) | `"base"` (ground acceleration) or `"force"` |
//! | `spectrum` | random | | required | `"white"`, `"kanai-tajimi"`, `"clough-penzien"` |
//! | `S0` | random | (m/s^2)^2 or N^2 per rad/s | required; with stripes (`intensity` and `[sweep] im`) 0.005, which scales out | `(0, 1e12]`, sweepable |
//! | `omega_g`, `zeta_g` | random (Kanai–Tajimi, Clough–Penzien) | rad/s, 1 | firm soil: `5 pi`, 0.6 | `[1e-3, 1e5]`, `[1e-3, 10]`, sweepable |
//! | `omega_f`, `zeta_f` | random (Clough–Penzien) | rad/s, 1 | `pi / 2`, 0.6 | the same |
//! | `dt` | random | s | 0.005 | `[1e-6, 1]` |
//! | `duration` | both | s | 20 (a record: its own) | `(0, 1e6]`, at most `1e8` samples |
//! | `envelope = { t1, t2, c }` | random | s, s, 1/s | none | `0 <= t1 <= t2`, `c >= 0` |
//! | `realizations` | random | | 1000 | `[1, 10^7]` (a record: 1; a suite: its records) |
//! | `threshold` | both | m | none | `> 0` |
//! | `drift_ratio`, `storey_height` | both | 1, m | none | both `> 0`: the limit `b = drift_ratio storey_height` instead of `threshold` |
//! | `yield_coefficient` | both | 1 | none | `> 0`: the limit at first yield, `b = C_y M g / K`, instead of `threshold` |
//! | `intensity` | both | | none | `"pga"` or `"sa"` (ground acceleration only): stripes (`[sweep] im`, g), capacities, hazard |
//! | `T` | both, with `intensity = "sa"` | s | the structure's `2 pi sqrt(M / K)` | `[max(0.01, 8 dt), 100]` |
//! | `ida_tol`, `ida_max` | both, with `intensity` | 1, g | 0.01, 10 | `[1e-6, 0.5]`, `(0, 1000]` |
//! | `record` | record | path | required (or `records`) | CSV or Parquet relative to the study file (in a run directory, its copy `record.csv` or `record.parquet` when the path does not resolve there) |
//! | `records` | record | paths or a folder | instead of `record` | a suite: a list of record files, or a folder whose `.csv` and `.parquet` files are taken by name; realization `c` runs record `c`, each at its own `dt` and length (in a run directory, the copies in `records/`) |
//! | `scale` | record | 1 | 1 | `> 0`, sweepable |

use std::collections::BTreeMap;
use std::path::Path;

use super::raw::{RANDOM_ONLY, RECORD_ONLY, RawScene};
use crate::error::InputError;
use crate::model::RangeError;
use crate::sim::random::intensity::{DEFAULT_IDA_MAX, DEFAULT_IDA_TOL};
use crate::sim::random::{
    Envelope, Excitation, Input, IntensitySpec, Measure, RandomLoad, RandomScene, Recorded,
    Spectrum, Suite, SuiteRecord,
};
use crate::study::axis::{Axis, RawAxis};
use crate::study::context::{Cx, num, range_value};
use crate::study::record;

/// Default realizations per design point.
pub const DEFAULT_REALIZATIONS: u64 = 1000;

/// `S0` where a study with stripes (an intensity measure and `[sweep] im`) gives none
/// ((m/s^2)^2 or N^2 per rad/s, the seismic showcase's): every motion is scaled to its stripe,
/// so the load's own level scales out of every result but the motions' unscaled `pga` and `sa`.
pub const STRIPES_S0: f64 = 0.005;

/// Default sample interval of a random load (s): 200 samples per second, the rate of many
/// strong-motion records.
pub const DEFAULT_DT: f64 = 0.005;

/// The keys that are an intensity (model.md §13): a random load's `S0`, a record's `scale`, a
/// stripe's intensity measure `im` (g). A study sweeping one ranks its designs at one of its
/// values, the design intensity.
pub const INTENSITY_KEYS: [&str; 3] = ["S0", "scale", "im"];

/// `[scene].design_intensity`: the swept intensity value the designs are ranked at. Allowed
/// only with a swept `S0` or `scale`, and only as one of its swept values (matched to a
/// relative 1e-9, the value stored as the axis holds it).
pub(super) fn design_intensity(
    cx: &Cx,
    given: Option<f64>,
    axes: &[Axis],
) -> Result<Option<f64>, InputError> {
    let Some(v) = given else {
        return Ok(None);
    };
    let Some(axis) = axes
        .iter()
        .find(|a| INTENSITY_KEYS.contains(&a.key.as_str()))
    else {
        return Err(cx.err(
            "[scene].design_intensity",
            num(v),
            "needs a swept intensity: sweep S0 (a random load) or scale (a record) in [sweep]",
        ));
    };
    match axis
        .values
        .iter()
        .find(|&&x| (x - v).abs() <= 1e-9 * x.abs().max(v.abs()))
    {
        Some(&x) => Ok(Some(x)),
        None => Err(cx.err(
            "[scene].design_intensity",
            num(v),
            format!(
                "must be one of the swept {} values: {}",
                axis.key,
                axis.values
                    .iter()
                    .map(|&x| num(x))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// Checks one value of a swept scene key on its own (`S0`, `omega_g`, `zeta_g`, `omega_f`,
/// `zeta_f`, `scale`).
pub(super) fn check_key(key: &str, v: f64) -> Result<(), RangeError> {
    if key == "im" {
        return if v.is_finite() && (1e-6..=1e3).contains(&v) {
            Ok(())
        } else {
            Err(RangeError::new(
                "im",
                v,
                "a stripe's intensity (g) must be in [1e-6, 1000]",
            ))
        };
    }
    let mut s = RandomScene {
        input: Input::Base,
        excitation: Excitation::Random(RandomLoad {
            spectrum: Spectrum::CloughPenzien {
                omega_g: 1.0,
                zeta_g: 1.0,
                omega_f: 1.0,
                zeta_f: 1.0,
            },
            S0: 1.0,
            envelope: None,
        }),
        dt: DEFAULT_DT,
        duration: 1.0,
        threshold: None,
        intensity: None,
        im: None,
    };
    if key == "scale" {
        s.excitation = Excitation::Record(Recorded {
            values: vec![0.0, 0.0].into(),
            scale: 1.0,
        });
    }
    s.set(key, v);
    s.validate()
}

/// The scene keys a study of `scene` may sweep.
pub(super) fn axes_of(scene: &RandomScene) -> Vec<&'static str> {
    if scene.intensity.is_some() {
        // Stripes are in the intensity measure; the load's own level is fixed.
        return match &scene.excitation {
            Excitation::Record(_) | Excitation::Suite(_) => vec!["im"],
            Excitation::Random(r) => match r.spectrum {
                Spectrum::White => vec!["im"],
                Spectrum::KanaiTajimi { .. } => vec!["im", "omega_g", "zeta_g"],
                Spectrum::CloughPenzien { .. } => {
                    vec!["im", "omega_g", "zeta_g", "omega_f", "zeta_f"]
                }
            },
        };
    }
    match &scene.excitation {
        Excitation::Record(_) | Excitation::Suite(_) => vec!["scale"],
        Excitation::Random(r) => match r.spectrum {
            Spectrum::White => vec!["S0"],
            Spectrum::KanaiTajimi { .. } => vec!["S0", "omega_g", "zeta_g"],
            Spectrum::CloughPenzien { .. } => {
                vec!["S0", "omega_g", "zeta_g", "omega_f", "zeta_f"]
            }
        },
    }
}

/// The validated random or record scene of `kind` and its realizations per design point. Keys
/// swept in `[sweep]` hold 1 here (the plan sets them per point; their range is checked on the
/// axis). `dir` is the study file's folder (a record's path is relative to it).
pub(super) fn scene(
    cx: &Cx,
    kind: &str,
    raw: &RawScene,
    sweep: &BTreeMap<String, RawAxis>,
    dir: &Path,
) -> Result<(RandomScene, u64), InputError> {
    let (other, other_kind) = if kind == "random" {
        (&RECORD_ONLY[..], "record")
    } else {
        (&RANDOM_ONLY[..], "random")
    };
    for key in other {
        if raw.has(key) {
            return Err(cx.err(
                &format!("[scene].{key}"),
                cx.source("scene", key),
                format!("{key} belongs to the {other_kind} scene; this study's kind is {kind:?}"),
            ));
        }
    }
    for key in crate::sim::random::RandomScene::AXES {
        if raw.has(key) && sweep.contains_key(key) {
            return Err(cx.err(
                &format!("[scene].{key}"),
                cx.source("scene", key),
                format!("{key} is also swept in [sweep]; a key is either fixed or swept, not both"),
            ));
        }
    }
    let value = |key: &str| -> Result<f64, InputError> {
        match raw.number(key) {
            Some(v) => Ok(v),
            None if sweep.contains_key(key) => Ok(1.0),
            // Firm soil's filters and a strong motion's length serve where a study gives none
            // (the report states them).
            None if kind == "random" && default_of(key).is_some() => {
                Ok(default_of(key).unwrap_or(f64::NAN))
            }
            None => Err(missing(
                cx,
                key,
                &format!(
                    "the {kind} scene needs {} (fixed here or swept in [sweep])",
                    if key == "S0" { S0_WHAT } else { key }
                ),
            )),
        }
    };
    let input = match &raw.input {
        Some(s) => Some(Input::parse(s).ok_or_else(|| {
            cx.err(
                "[scene].input",
                format!("{s:?}"),
                "unknown input; allowed: base (ground acceleration, displacements relative to the \
                 ground), force (a force on the main mass)",
            )
        })?),
        None => None,
    };
    if sweep.contains_key("im") && raw.intensity.is_none() {
        // Before the load's own keys: at a stripe a random load's S0 may be left out.
        return Err(cx.err(
            "[sweep].im",
            cx.source("sweep", "im"),
            "stripes (g) scale each motion to its own intensity measure; give [scene] intensity \
             = \"pga\" or \"sa\"",
        ));
    }
    let (scene, realizations) = if kind == "random" {
        // With stripes (an intensity measure and `[sweep] im`) every motion is scaled to its
        // stripe, so the load's own level scales out.
        let stripes = raw.intensity.is_some() && sweep.contains_key("im");
        random(cx, raw, input.unwrap_or(Input::Base), stripes, &value)?
    } else {
        recorded(cx, raw, input, &value, dir)?
    };
    scene
        .validate()
        .map_err(|e| cx.err(&format!("[scene].{}", e.key), range_value(&e), e.allowed))?;
    Ok((scene, realizations))
}

/// The default of a random load's key a study may leave out: firm soil's Kanai–Tajimi filter
/// (`omega_g = 5 pi` rad/s, `zeta_g = 0.6`), the Clough–Penzien high-pass filter at a tenth of
/// it (`omega_f = pi / 2` rad/s, `zeta_f = 0.6`), and 20 s of load.
pub fn default_of(key: &str) -> Option<f64> {
    Some(match key {
        "omega_g" => 5.0 * std::f64::consts::PI,
        "zeta_g" => 0.6,
        "omega_f" => 0.5 * std::f64::consts::PI,
        "zeta_f" => 0.6,
        "duration" => 20.0,
        _ => return None,
    })
}

/// What `S0` is and the values it takes ([`crate::sim::random::RandomLoad::validate`]).
const S0_WHAT: &str = "S0, the load's two-sided spectral density per rad/s, in (0, 1e12] \
                       ((m/s^2)^2 for a base input, N^2 for a force)";

/// A key of `[scene]` the scene needs and the study lacks.
fn missing(cx: &Cx, key: &str, why: &str) -> InputError {
    InputError::new(format!("{}: [scene].{key}: missing; {why}", cx.file))
}

/// The random scene's keys.
fn random(
    cx: &Cx,
    raw: &RawScene,
    input: Input,
    stripes: bool,
    value: &dyn Fn(&str) -> Result<f64, InputError>,
) -> Result<(RandomScene, u64), InputError> {
    // S0 may be left out where stripes scale every motion (its default then scales out).
    let s0 = || match raw.number("S0") {
        None if stripes => Ok(STRIPES_S0),
        _ => value("S0"),
    };
    let Some(name) = &raw.spectrum else {
        // A study that gives neither hears of both at once, with an example.
        let and_s0 = if s0().is_err() {
            format!(
                "; and {S0_WHAT} (fixed here or swept in [sweep]): for example spectrum = \
                 \"kanai-tajimi\" and S0 = 1e-3"
            )
        } else {
            String::new()
        };
        return Err(missing(
            cx,
            "spectrum",
            &format!(
                "the random scene needs a spectrum; allowed: {}{and_s0}",
                Spectrum::NAMES.join(", ")
            ),
        ));
    };
    let spectrum = match name.as_str() {
        "white" => Spectrum::White,
        "kanai-tajimi" => Spectrum::KanaiTajimi {
            omega_g: value("omega_g")?,
            zeta_g: value("zeta_g")?,
        },
        "clough-penzien" => Spectrum::CloughPenzien {
            omega_g: value("omega_g")?,
            zeta_g: value("zeta_g")?,
            omega_f: value("omega_f")?,
            zeta_f: value("zeta_f")?,
        },
        _ => {
            return Err(cx.err(
                "[scene].spectrum",
                format!("{name:?}"),
                format!("unknown spectrum; allowed: {}", Spectrum::NAMES.join(", ")),
            ));
        }
    };
    // A filter key the spectrum does not have.
    let used: &[&str] = match spectrum {
        Spectrum::White => &[],
        Spectrum::KanaiTajimi { .. } => &["omega_g", "zeta_g"],
        Spectrum::CloughPenzien { .. } => &["omega_g", "zeta_g", "omega_f", "zeta_f"],
    };
    for key in ["omega_g", "zeta_g", "omega_f", "zeta_f"] {
        if raw.has(key) && !used.contains(&key) {
            return Err(cx.err(
                &format!("[scene].{key}"),
                cx.source("scene", key),
                format!(
                    "spectrum = {name:?} has no {key}; omega_g and zeta_g belong to kanai-tajimi \
                     and clough-penzien, omega_f and zeta_f to clough-penzien"
                ),
            ));
        }
    }
    let realizations = raw.realizations.unwrap_or(DEFAULT_REALIZATIONS);
    if !(1..=10_000_000).contains(&realizations) {
        return Err(cx.err(
            "[scene].realizations",
            realizations,
            "must be a whole number in [1, 10000000]",
        ));
    }
    let scene = RandomScene {
        input,
        excitation: Excitation::Random(RandomLoad {
            spectrum,
            S0: s0()?,
            envelope: raw.envelope.as_ref().map(|e| Envelope {
                t1: e.t1,
                t2: e.t2,
                c: e.c,
            }),
        }),
        dt: raw.dt.unwrap_or(DEFAULT_DT),
        duration: value("duration")?,
        threshold: raw.threshold,
        intensity: None,
        im: None,
    };
    Ok((scene, realizations))
}

/// The record scene's keys and its file.
fn recorded(
    cx: &Cx,
    raw: &RawScene,
    input: Option<Input>,
    value: &dyn Fn(&str) -> Result<f64, InputError>,
    dir: &Path,
) -> Result<(RandomScene, u64), InputError> {
    if let Some(records) = &raw.records {
        if raw.record.is_some() {
            return Err(cx.err(
                "[scene].records",
                cx.source("scene", "records"),
                "give one record (record = \"path\") or a suite (records = [...] or a folder), \
                 not both",
            ));
        }
        return suite(cx, raw, input, value, dir, records);
    }
    let Some(shown) = &raw.record else {
        return Err(missing(
            cx,
            "record",
            "the record scene needs record = \"path\" (CSV, columns t and a or t and F, relative \
             to the study file), or a suite: records = [\"a.csv\", ...] or records = \"folder\"",
        ));
    };
    if let Some(n) = raw.realizations
        && n != 1
    {
        return Err(cx.err(
            "[scene].realizations",
            n,
            "a record is one load: realizations must be 1 (sweep scale for intensities; a suite \
             of records is records = [...])",
        ));
    }
    let mut path = dir.join(shown);
    let copy = dir.join(record::record_copy(shown));
    if !path.exists() && copy.exists() {
        path = copy;
    }
    let file = record::read(cx, shown, &path)?;
    if let Some(i) = input
        && i != file.input
    {
        let column = if file.input == Input::Base { "a" } else { "F" };
        return Err(cx.err(
            "[scene].input",
            format!("{:?}", i.name()),
            format!(
                "the record {shown:?} holds column {column}, a {}; give input = {:?} or leave \
                 input out",
                if file.input == Input::Base {
                    "ground acceleration"
                } else {
                    "force"
                },
                file.input.name()
            ),
        ));
    }
    let length = (file.values.len() - 1) as f64 * file.dt;
    let duration = raw.number("duration").unwrap_or(length);
    let scale = if raw.has("scale") {
        value("scale")?
    } else {
        1.0
    };
    let scene = RandomScene {
        input: file.input,
        excitation: Excitation::Record(Recorded {
            values: file.values,
            scale,
        }),
        dt: file.dt,
        duration,
        threshold: raw.threshold,
        intensity: None,
        im: None,
    };
    if !(file.dt >= 1e-6 && file.dt <= 1.0) {
        return Err(cx.err(
            "[scene].record",
            format!("{shown:?}"),
            format!(
                "the record's sample interval is {} s; allowed: [1e-6, 1] s",
                num(file.dt)
            ),
        ));
    }
    Ok((scene, 1))
}

/// A suite of records (`[scene] records`): each file read and checked as one record (the error
/// names the file), all of one input; realization `c` runs record `c`, each at its own `dt` and
/// length (or the study's `duration`). The scene's own `dt` and `duration` are the suite's
/// finest and longest (what its checks bound).
fn suite(
    cx: &Cx,
    raw: &RawScene,
    input: Option<Input>,
    value: &dyn Fn(&str) -> Result<f64, InputError>,
    dir: &Path,
    records: &toml::Value,
) -> Result<(RandomScene, u64), InputError> {
    let list: Option<Vec<String>> = records
        .as_array()
        .and_then(|a| a.iter().map(|v| v.as_str().map(str::to_string)).collect());
    let source = match (records.as_str(), &list) {
        (Some(f), _) => record::SuiteSource::Folder(f),
        (None, Some(l)) => record::SuiteSource::List(l),
        _ => {
            return Err(cx.err(
                "[scene].records",
                cx.source("scene", "records"),
                "allowed: a list of record files ([\"a.csv\", \"b.csv\"], relative to the study \
                 file) or a folder of them (\"suite\")",
            ));
        }
    };
    let files = record::suite_files(&source, dir)
        .map_err(|(value, why)| cx.err("[scene].records", value, why))?;
    let n = files.len() as u64;
    if let Some(r) = raw.realizations
        && r != n
    {
        return Err(cx.err(
            "[scene].realizations",
            r,
            format!(
                "a suite's realizations are its records: {n} here; leave realizations out or \
                 give {n}"
            ),
        ));
    }
    let at = "[scene].records";
    let mut suite: Vec<SuiteRecord> = Vec::with_capacity(files.len());
    let mut first_input = input;
    for (name, path) in &files {
        let file = record::read_at(cx, at, name, path)?;
        match first_input {
            Some(i) if i != file.input => {
                return Err(cx.err(
                    at,
                    format!("{name:?}"),
                    format!(
                        "this record is a {}, the suite's {}; a suite's records share one input \
                         (columns t,a or t,F)",
                        file.input.name(),
                        i.name()
                    ),
                ));
            }
            _ => first_input = Some(file.input),
        }
        if !(file.dt >= 1e-6 && file.dt <= 1.0) {
            return Err(cx.err(
                at,
                format!("{name:?}"),
                format!(
                    "the record's sample interval is {} s; allowed: [1e-6, 1] s",
                    num(file.dt)
                ),
            ));
        }
        let length = (file.values.len() - 1) as f64 * file.dt;
        suite.push(SuiteRecord {
            name: name.clone(),
            dt: file.dt,
            duration: raw.number("duration").unwrap_or(length),
            values: file.values,
        });
    }
    let scale = if raw.has("scale") {
        value("scale")?
    } else {
        1.0
    };
    let dt = suite.iter().map(|r| r.dt).fold(f64::INFINITY, f64::min);
    let duration = suite.iter().map(|r| r.duration).fold(0.0, f64::max);
    let scene = RandomScene {
        input: first_input.unwrap_or(Input::Base),
        excitation: Excitation::Suite(Suite {
            records: suite.into(),
            scale,
        }),
        dt,
        duration,
        threshold: raw.threshold,
        intensity: None,
        im: None,
    };
    Ok((scene, n))
}

/// The limit of `|x|` as a structure states it: `threshold` (m), or a drift ratio times the
/// storey height (`drift_ratio`, `storey_height` in m: `b = ratio h`), or first yield at a
/// base-shear coefficient (`yield_coefficient` `C_y`: the linear structure's base shear
/// `K b = C_y M g`, `b = C_y M g / K`, with `M` and `K` not swept). At most one form.
pub(super) fn limit(
    cx: &Cx,
    raw: &RawScene,
    system: &crate::model::System,
    swept: &[&str],
    scene: &mut RandomScene,
) -> Result<(), InputError> {
    let given: Vec<&str> = ["threshold", "drift_ratio", "yield_coefficient"]
        .into_iter()
        .filter(|k| raw.has(k))
        .collect();
    if given.len() > 1 {
        return Err(cx.err(
            &format!("[scene].{}", given[1]),
            cx.source("scene", given[1]),
            format!(
                "the limit is given once: threshold (m), drift_ratio with storey_height, or \
                 yield_coefficient; this study also gives {}",
                given[0]
            ),
        ));
    }
    let positive = |key: &str, v: f64, what: &str| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(cx.err(
                &format!("[scene].{key}"),
                num(v),
                format!("{what} must be > 0"),
            ))
        }
    };
    if let Some(h) = raw.number("storey_height")
        && raw.number("drift_ratio").is_none()
    {
        return Err(cx.err(
            "[scene].storey_height",
            num(h),
            "a storey height sets the limit with a drift_ratio (b = drift_ratio * storey_height); \
             give drift_ratio too",
        ));
    }
    if let Some(r) = raw.number("drift_ratio") {
        let r = positive(
            "drift_ratio",
            r,
            "the drift ratio (drift over storey height)",
        )?;
        let Some(h) = raw.number("storey_height") else {
            return Err(missing(
                cx,
                "storey_height",
                "a drift_ratio limit needs the storey height (m): b = drift_ratio * storey_height",
            ));
        };
        let h = positive("storey_height", h, "the storey height (m)")?;
        scene.threshold = Some(r * h);
    }
    if let Some(c) = raw.number("yield_coefficient") {
        let c = positive(
            "yield_coefficient",
            c,
            "the base-shear coefficient at first yield",
        )?;
        if swept.contains(&"M") || swept.contains(&"K") {
            return Err(cx.err(
                "[scene].yield_coefficient",
                num(c),
                "first yield at C_y M g / K needs M and K fixed; this study sweeps one of them \
                 (give threshold in m instead)",
            ));
        }
        scene.threshold = Some(c * system.M * crate::sim::random::intensity::G / system.K);
    }
    Ok(())
}

/// `[scene] intensity` (with `T`, `ida_tol`, `ida_max`) onto `scene`: the intensity measure
/// of the stripes, capacities and hazard. `T` defaults to the structure's own period
/// `2 pi sqrt(M / K)` of `system`, which must then not be swept (`swept`: the swept keys).
pub(super) fn intensity(
    cx: &Cx,
    raw: &RawScene,
    system: &crate::model::System,
    swept: &[&str],
    scene: &mut RandomScene,
) -> Result<(), InputError> {
    let Some(name) = &raw.intensity else {
        for key in ["T", "ida_tol", "ida_max"] {
            if raw.has(key) {
                return Err(cx.err(
                    &format!("[scene].{key}"),
                    cx.source("scene", key),
                    format!(
                        "{key} belongs to an intensity measure: give [scene] intensity = \"pga\" \
                         or \"sa\""
                    ),
                ));
            }
        }
        return Ok(());
    };
    let Some(measure) = Measure::parse(name) else {
        return Err(cx.err(
            "[scene].intensity",
            format!("{name:?}"),
            format!(
                "unknown intensity measure; allowed: {} (peak ground acceleration, or the \
                 spectral acceleration at T with 5 % damping, both in g)",
                Measure::NAMES.join(", ")
            ),
        ));
    };
    for key in ["S0", "scale"] {
        if swept.contains(&key) {
            return Err(cx.err(
                &format!("[sweep].{key}"),
                cx.source("sweep", key),
                format!(
                    "with an intensity measure the stripes are [sweep] im = [...] (in g, each \
                     motion scaled to it); {key} fixes the load's own level"
                ),
            ));
        }
    }
    let period = match raw.number("T") {
        Some(t) => t,
        None if swept.contains(&"M") || swept.contains(&"K") => {
            return Err(missing(
                cx,
                "T",
                "Sa's period defaults to the structure's 2 pi sqrt(M / K), which this study \
                 sweeps; give T (s)",
            ));
        }
        None => system.period(),
    };
    scene.intensity = Some(IntensitySpec {
        measure,
        period,
        ida_tol: raw.number("ida_tol").unwrap_or(DEFAULT_IDA_TOL),
        ida_max: raw.number("ida_max").unwrap_or(DEFAULT_IDA_MAX),
    });
    let mut probe = scene.clone();
    probe.im = None;
    probe.validate().map_err(|e| {
        let value = cx.source("scene", &e.key);
        cx.err(&format!("[scene].{}", e.key), value, e.allowed)
    })
}
