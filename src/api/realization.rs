//! One realization at hand (issue 67 item 9): a random or record design given as `KEY=VALUE`
//! settings (`impactsweep simulate --set scene=random --set S0=... --set realization=C`, the
//! Python binding's batch), turned into the one-point study those keys describe and run as
//! that study's sweep runs it ([`crate::sweep::random::one_realization`]): the same defaults
//! and checks as a study file (firm soil's filters, 20 s, `dt = 0.005` s, the structure at
//! rest), and the same bits as the sweep's row of that design and realization.
//!
//! The keys are those of a random or record study (docs/scenes.md) under their study names:
//! the load's `[scene]` keys, the system's, the solver's (`solver` is `[solver] kind`), a
//! stripe `im` (g, the study's `[sweep] im = [im]`: one stripe, the design stripe), and the
//! run's own `realization` (0 to 9999999, default 0; a record's only realization is 0) and
//! `seed` (the study seed, 0 to 2^64 - 1, default 0). `envelope=t1,t2,c` (s, s, 1/s) is the
//! study's `envelope = { t1, t2, c }`. A key given twice takes its last value.

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::InputError;
use crate::model::{SYSTEM_KEYS, System, UNIT_KEYS};
use crate::plan::Plan;
use crate::sim::random::{Excitation, RandomScene, RealizationRecord};
use crate::sim::{Harmonic, SolverSettings, State};
use crate::study::Study;

/// The scenes a realization at hand runs (`--set scene=random`, `--set scene=record`).
pub const KINDS: [&str; 2] = ["random", "record"];

/// The `[scene]` keys of the random scene, in the order of docs/scenes.md (a stripe `im`
/// besides, [`scene_keys`]).
pub const RANDOM_KEYS: [&str; 18] = [
    "input",
    "spectrum",
    "S0",
    "omega_g",
    "zeta_g",
    "omega_f",
    "zeta_f",
    "dt",
    "duration",
    "envelope",
    "threshold",
    "drift_ratio",
    "storey_height",
    "yield_coefficient",
    "intensity",
    "T",
    "ida_tol",
    "ida_max",
];

/// The `[scene]` keys of the record scene.
pub const RECORD_KEYS: [&str; 12] = [
    "input",
    "record",
    "scale",
    "duration",
    "threshold",
    "drift_ratio",
    "storey_height",
    "yield_coefficient",
    "intensity",
    "T",
    "ida_tol",
    "ida_max",
];

/// The run's own keys: the realization and the study seed.
pub const RUN_KEYS: [&str; 2] = ["realization", "seed"];

/// Keys whose value is a word or a path, not a number.
const WORDS: [&str; 5] = ["input", "spectrum", "record", "intensity", "solver"];

/// The largest realization: a study holds at most 10^7 per design point.
pub const MAX_REALIZATION: u32 = 9_999_999;

/// The solver keys of a random or record setup: `simulate --set`'s but `peaks` (a free-decay
/// key: a random run lasts its duration).
fn solver_keys() -> impl Iterator<Item = &'static str> {
    SolverSettings::KEYS.into_iter().filter(|k| *k != "peaks")
}

/// What messages call the one-point study's file; [`set_error`] takes it off.
const FILE: &str = "--set";

/// A random or record design and one of its realizations, from `KEY=VALUE` settings.
#[derive(Clone, Debug, PartialEq)]
pub struct RandomSetup {
    /// The one-point study the keys describe: its design point 0, `realization + 1`
    /// realizations (a record: 1), `[study] seed` the given seed.
    pub study: Study,
    /// The realization run: its load is the stream of the study seed and this number, the
    /// same at every design ([`crate::plan`]).
    pub realization: u32,
    /// The keys given (each once, the last value kept), in the order first given.
    pub given: Vec<String>,
}

/// The keys of `kind` besides the system's and the solver's (the scene's, `im`, the run's).
pub fn scene_keys(kind: &str) -> Vec<&'static str> {
    let mut keys: Vec<&str> = if kind == "record" {
        RECORD_KEYS.to_vec()
    } else {
        RANDOM_KEYS.to_vec()
    };
    keys.push("im");
    keys.extend(RUN_KEYS);
    keys
}

/// Every key a setup of `kind` takes, for messages.
fn allowed(kind: &str) -> String {
    let mut keys = vec!["scene"];
    keys.extend(scene_keys(kind));
    keys.extend(SYSTEM_KEYS);
    keys.extend(UNIT_KEYS);
    keys.extend(solver_keys());
    keys.join(" ")
}

/// Why a key is not one of `kind`'s.
fn not_a_key(kind: &str, key: &str) -> &'static str {
    let other = if kind == "record" {
        &RANDOM_KEYS[..]
    } else {
        &RECORD_KEYS[..]
    };
    if other.contains(&key) {
        if kind == "record" {
            "a key of the random scene"
        } else {
            "a key of the record scene"
        }
    } else if Harmonic::KEYS.contains(&key) {
        "a key of the harmonic scene"
    } else if key == "t_end" || key == "peaks" {
        "a free-decay key (a random or record run lasts its duration)"
    } else {
        "unknown key"
    }
}

/// One value as the study file holds it: a TOML string, integer or float (shortest round
/// trip), checked as `--set` reads it.
fn toml_value(key: &str, raw: &str) -> Result<String, InputError> {
    if WORDS.contains(&key) {
        return Ok(serde_json::to_string(raw).unwrap_or_default());
    }
    if key == "envelope" {
        let parts: Vec<&str> = raw.split(',').map(str::trim).collect();
        let nums: Vec<f64> = parts.iter().filter_map(|p| p.parse().ok()).collect();
        if parts.len() != 3 || nums.len() != 3 {
            return Err(InputError::new(format!(
                "--set envelope={raw}: expected t1,t2,c (rise end s, decay start s, decay rate \
                 1/s), e.g. envelope=2,10,0.3"
            )));
        }
        return Ok(format!(
            "{{ t1 = {}, t2 = {}, c = {} }}",
            float(nums[0]),
            float(nums[1]),
            float(nums[2])
        ));
    }
    let value: f64 = raw
        .parse()
        .map_err(|_| InputError::new(format!("--set {key}={raw}: '{raw}' is not a number")))?;
    if key == "max_impacts" || key == "max_steps" {
        if value.fract() == 0.0 && (0.0..=9.0e15).contains(&value) {
            return Ok(format!("{}", value as u64));
        }
        return Err(InputError::new(format!(
            "--set {key}={raw}: must be a whole number >= 0"
        )));
    }
    Ok(float(value))
}

/// A float in TOML: a whole number as an integer (`3`, as messages then show it), else Rust's
/// shortest round-trip digits, `nan` and `inf` as TOML spells them.
fn float(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 && !(v == 0.0 && v.is_sign_negative()) {
        format!("{}", v as i64)
    } else if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{v:?}")
    }
}

/// A whole number in `[0, max]` from `--set key=raw`.
fn whole(key: &str, raw: &str, max: u64, range: &str) -> Result<u64, InputError> {
    raw.parse::<u64>()
        .ok()
        .filter(|&v| v <= max)
        .ok_or_else(|| {
            InputError::new(format!(
                "--set {key}={raw}: must be a whole number in {range}"
            ))
        })
}

/// A study's message as `--set` states it: `--set: [scene].S0 = -1: ...` reads
/// `--set S0 = -1: ...` (as the other scenes' range errors read), `[solver].kind` reads
/// `solver`, the stripe `[sweep].im = [0.3]` reads `im = 0.3`.
fn set_error(err: InputError) -> InputError {
    let msg = err.0;
    let Some(rest) = msg.strip_prefix(&format!("{FILE}: ")) else {
        return InputError::new(msg);
    };
    let mut rest = rest.replace("[solver].kind", "solver");
    for table in ["[scene].", "[system].", "[solver].", "[sweep].", "[study]."] {
        if let Some(r) = rest.strip_prefix(table) {
            rest = r.to_string();
        }
    }
    if let Some(r) = rest.strip_prefix("im = [")
        && let Some((v, tail)) = r.split_once(']')
    {
        rest = format!("im = {v}{tail}");
    }
    InputError::new(format!("{FILE} {rest}"))
}

impl RandomSetup {
    /// The setup of `sets` with `scene=kind` (`random` or `record`) among them; the error
    /// names the key, the value and what is allowed. A record's path is relative to the
    /// current directory.
    pub fn from_sets(kind: &str, sets: &[String]) -> Result<RandomSetup, InputError> {
        // Each key once, its last value, in the order first given.
        let mut given: Vec<String> = Vec::new();
        let mut values: BTreeMap<String, String> = BTreeMap::new();
        for item in sets {
            let Some((key, raw)) = item.split_once('=') else {
                return Err(InputError::new(format!(
                    "--set {item}: expected KEY=VALUE, with KEY one of: {}",
                    allowed(kind)
                )));
            };
            let (key, raw) = (key.trim(), raw.trim());
            if key == "scene" {
                continue;
            }
            let known = scene_keys(kind).contains(&key)
                || SYSTEM_KEYS.contains(&key)
                || UNIT_KEYS.contains(&key)
                || solver_keys().any(|k| k == key);
            if !known {
                return Err(InputError::new(format!(
                    "--set {key}={raw}: {} for scene={kind}; allowed keys: {}",
                    not_a_key(kind, key),
                    allowed(kind)
                )));
            }
            if values.insert(key.to_string(), raw.to_string()).is_none() {
                given.push(key.to_string());
            }
        }
        let seed = match values.get("seed") {
            Some(raw) => whole("seed", raw, u64::MAX, "[0, 18446744073709551615]")?,
            None => 0,
        };
        let realization = match values.get("realization") {
            Some(raw) if kind == "record" => whole(
                "realization",
                raw,
                0,
                "[0, 0]: a record is one load, its realization 0",
            )? as u32,
            Some(raw) => whole(
                "realization",
                raw,
                u64::from(MAX_REALIZATION),
                "[0, 9999999]",
            )? as u32,
            None => 0,
        };
        // At a stripe `S0` scales out and may be left to its default (the study's rule).
        let needed: &[&str] = if kind == "record" {
            &["record"]
        } else if values.contains_key("im") {
            &["spectrum"]
        } else {
            &["spectrum", "S0"]
        };
        for key in needed {
            if !values.contains_key(*key) {
                return Err(InputError::new(format!(
                    "--set scene={kind}: needs --set {key}=...; {}",
                    match *key {
                        "record" =>
                            "a CSV or Parquet file with columns t,a or t,F (the path \
                                     relative to the current directory)",
                        "spectrum" => "allowed: white, kanai-tajimi, clough-penzien",
                        _ => "the two-sided spectral density, (m/s^2)^2 or N^2 per rad/s",
                    }
                )));
            }
        }
        if let Some(im) = values.get("im")
            && !values.contains_key("intensity")
        {
            return Err(InputError::new(format!(
                "--set im={im}: a stripe (g) scales each motion to its own intensity measure; \
                 add --set intensity=pga or intensity=sa"
            )));
        }
        let text = study_text(kind, &values, seed, realization)?;
        let study = Study::parse(Path::new(FILE), &text).map_err(set_error)?;
        Ok(RandomSetup {
            study,
            realization,
            given,
        })
    }

    /// The design's system (the structure at rest unless the keys say otherwise).
    pub fn system(&self) -> System {
        Plan::new(&self.study).point_system(0)
    }

    /// The design's scene, with its stripe `im` when given.
    pub fn scene(&self) -> RandomScene {
        Plan::new(&self.study)
            .point(0)
            .1
            .random()
            .cloned()
            .unwrap_or_else(RandomScene::placeholder)
    }

    /// `"random"` or `"record"`.
    pub fn kind(&self) -> &'static str {
        match &self.scene().excitation {
            Excitation::Random(_) => "random",
            Excitation::Record(_) | Excitation::Suite(_) => "record",
        }
    }

    /// Whether a key was given (not defaulted).
    pub fn has(&self, key: &str) -> bool {
        self.given.iter().any(|k| k == key)
    }

    /// The realization as the sweep stores it (the same bits as its row), with `trace` its
    /// displacements every `trace` s (and at every impact) at the stripe's scale.
    pub fn run(
        &self,
        trace: Option<f64>,
    ) -> Result<(RealizationRecord, Vec<(f64, State)>), InputError> {
        crate::sweep::random::one_realization(&Plan::new(&self.study), 0, self.realization, trace)
            .ok_or_else(|| {
                InputError::new(format!(
                    "--set realization={}: outside the setup's realizations (a bug: please \
                     report it)",
                    self.realization
                ))
            })
    }

    /// The row as one JSON object: the row's `load`, `own`, `capacity` and `record` (as
    /// `simulate --study` prints them), then `scene`, `seed`, `realization`, `system` and
    /// `solver` (SI units; NaN becomes null).
    pub fn json(&self, row: &RealizationRecord) -> serde_json::Value {
        let mut map = match serde_json::to_value(row) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        };
        map.insert("scene".into(), self.kind().into());
        map.insert("seed".into(), self.study.seed.into());
        map.insert("realization".into(), self.realization.into());
        super::json::insert_system(&mut map, &self.system(), &self.study.solver);
        serde_json::Value::Object(map)
    }
}

/// The one-point study of the keys `values` (checked names, raw values): each key in its
/// table, `im` as the one stripe `[sweep] im = [im]`, `realization + 1` realizations.
fn study_text(
    kind: &str,
    values: &BTreeMap<String, String>,
    seed: u64,
    realization: u32,
) -> Result<String, InputError> {
    let mut scene = format!("kind = \"{kind}\"\n");
    if kind == "random" {
        scene.push_str(&format!("realizations = {}\n", u64::from(realization) + 1));
    }
    let (mut system, mut solver, mut sweep) = (String::new(), String::new(), String::new());
    for (key, raw) in values {
        if RUN_KEYS.contains(&key.as_str()) {
            continue;
        }
        let v = toml_value(key, raw)?;
        if key == "im" {
            sweep.push_str(&format!("im = [{v}]\n"));
        } else if SYSTEM_KEYS.contains(&key.as_str()) || UNIT_KEYS.contains(&key.as_str()) {
            system.push_str(&format!("{key} = {v}\n"));
        } else if key == "solver" {
            solver.push_str(&format!("kind = {v}\n"));
        } else if SolverSettings::KEYS.contains(&key.as_str()) {
            solver.push_str(&format!("{key} = {v}\n"));
        } else {
            scene.push_str(&format!("{key} = {v}\n"));
        }
    }
    Ok(format!(
        "[study]\nname = \"simulate\"\nseed = {seed}\n[scene]\n{scene}[system]\n{system}\
         [solver]\n{solver}[sweep]\n{sweep}"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sets(items: &[&str]) -> Vec<String> {
        items.iter().map(|s| s.to_string()).collect()
    }

    fn err(items: &[&str]) -> String {
        let kind = if items.contains(&"scene=record") {
            "record"
        } else {
            "random"
        };
        RandomSetup::from_sets(kind, &sets(items))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn a_random_setup_gets_a_studys_defaults() {
        let s = RandomSetup::from_sets(
            "random",
            &sets(&[
                "scene=random",
                "spectrum=clough-penzien",
                "S0=0.01",
                "threshold=0.02",
                "realization=4",
                "seed=9",
                "S0=0.02",
            ]),
        )
        .unwrap();
        assert_eq!(
            (s.realization, s.study.seed, s.study.realizations),
            (4, 9, 5)
        );
        let scene = s.scene();
        assert_eq!(scene.get("S0"), Some(0.02));
        assert_eq!(scene.get("omega_g"), Some(5.0 * std::f64::consts::PI));
        assert_eq!(scene.get("zeta_f"), Some(0.6));
        assert_eq!((scene.dt, scene.duration), (0.005, 20.0));
        assert_eq!(s.system().v0, 0.0);
        assert!(s.has("threshold") && !s.has("duration"));
    }

    #[test]
    fn bad_keys_name_the_key_the_value_and_what_is_allowed() {
        let base = ["scene=random", "spectrum=white", "S0=0.01"];
        let with = |extra: &str| {
            let mut v = base.to_vec();
            v.push(extra);
            err(&v)
        };
        assert_eq!(
            with("S0=-1"),
            "--set S0 = -1: the two-sided spectral density must be in (0, 1e12] ((m/s^2)^2 or \
             N^2 per rad/s)"
        );
        assert!(
            with("spectrum=pink")
                .starts_with("--set spectrum = \"pink\": unknown spectrum; allowed:"),
            "{}",
            with("spectrum=pink")
        );
        assert!(with("F0=1").starts_with(
            "--set F0=1: a key of the harmonic scene for scene=random; allowed keys: scene"
        ));
        assert!(with("scale=2").starts_with("--set scale=2: a key of the record scene"));
        assert_eq!(with("S0=big"), "--set S0=big: 'big' is not a number");
        assert_eq!(
            with("realization=10000000"),
            "--set realization=10000000: must be a whole number in [0, 9999999]"
        );
        assert_eq!(
            with("seed=-1"),
            "--set seed=-1: must be a whole number in [0, 18446744073709551615]"
        );
        assert!(
            with("omega_g=3").starts_with("--set omega_g = 3: spectrum = \"white\" has no omega_g"),
            "{}",
            with("omega_g=3")
        );
        assert!(
            with("im=0.3").starts_with("--set im=0.3: a stripe (g) scales each motion"),
            "{}",
            with("im=0.3")
        );
        let mut stripe = base.to_vec();
        stripe.extend(["intensity=pga", "im=2000"]);
        assert!(
            err(&stripe).starts_with("--set im = 2000: "),
            "{}",
            err(&stripe)
        );
        assert!(with("peaks=3").starts_with("--set peaks=3: a free-decay key"));
        assert!(with("envelope=1,2").starts_with("--set envelope=1,2: expected t1,t2,c"));
        assert!(
            with("solver=rk9").starts_with("--set solver = \"rk9\": unknown solver"),
            "{}",
            with("solver=rk9")
        );
        assert!(
            err(&["scene=random", "S0=0.1"])
                .starts_with("--set scene=random: needs --set spectrum=")
        );
        assert!(err(&["scene=record"]).starts_with("--set scene=record: needs --set record="));
        // At a stripe S0 may be left out (it scales out); elsewhere it is needed.
        let at_stripe = |extra: &[&str]| {
            let mut items = vec!["scene=random", "spectrum=white", "duration=1"];
            items.extend_from_slice(extra);
            RandomSetup::from_sets("random", &sets(&items))
        };
        let striped = at_stripe(&["intensity=pga", "im=0.3"]).expect("S0 defaults at a stripe");
        // The study file's default at stripes (docs/scenes.md, "Inputs").
        assert_eq!(striped.scene().get("S0"), Some(0.005));
        assert!(
            at_stripe(&[])
                .unwrap_err()
                .to_string()
                .starts_with("--set scene=random: needs --set S0=")
        );
        let missing = err(&["scene=record", "record=no/such.csv"]);
        assert!(
            missing.starts_with("--set record = \"no/such.csv\": cannot read the record file"),
            "{missing}"
        );
    }
}
