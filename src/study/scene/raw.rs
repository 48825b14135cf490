//! The raw form of a study file: `#[serde(deny_unknown_fields)]` structs that mirror the TOML
//! and refuse unknown keys and wrong types ([`RawStudy`]), each table's own raw struct living
//! in the table's module; `[scene]`'s is here ([`RawScene`]): one table holds the keys of every
//! scene, and each scene's parser takes its own and refuses the others'.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;
use toml::de::DeTable;

use crate::error::InputError;
use crate::sim::{Harmonic, Scene};
use crate::study::axis::RawAxis;
use crate::study::context::Cx;
use crate::study::hazard::RawHazard;
use crate::study::header::RawHeader;
use crate::study::noise::RawNoise;
use crate::study::perturb::RawPerturb;
use crate::study::ranking::RawRanking;
use crate::study::reliability::RawReliability;
use crate::study::run::RawRun;
use crate::study::solver::RawSolver;
use crate::study::system::RawSystem;
use crate::study::toml_error::{serde_error, syntax_error};
use crate::study::zones::RawZones;

/// A study file as written: every table, each refusing unknown keys.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStudy {
    pub(super) study: RawHeader,
    pub(super) scene: Option<RawScene>,
    #[serde(default)]
    pub(super) system: RawSystem,
    #[serde(default)]
    pub(super) sweep: BTreeMap<String, RawAxis>,
    pub(super) perturb: Option<RawPerturb>,
    pub(super) noise: Option<RawNoise>,
    #[serde(default)]
    pub(super) solver: RawSolver,
    #[serde(default)]
    pub(super) reliability: RawReliability,
    #[serde(default)]
    pub(super) zones: RawZones,
    #[serde(default)]
    pub(super) ranking: RawRanking,
    #[serde(default)]
    pub(super) run: RawRun,
    pub(super) hazard: Option<RawHazard>,
}

/// Parses study text (TOML syntax, then the raw form) and hands it to `validate`.
pub(super) fn with_raw<T>(
    path: &Path,
    text: &str,
    validate: impl FnOnce(&Cx, &RawStudy) -> Result<T, InputError>,
) -> Result<T, InputError> {
    let file = path.display().to_string();
    let doc = DeTable::parse(text).map_err(|e| syntax_error(&file, text, &e))?;
    let raw: RawStudy =
        toml::from_str(text).map_err(|e| serde_error(&file, text, doc.get_ref(), &e))?;
    let cx = Cx::new(file, text, doc.get_ref());
    validate(&cx, &raw)
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub(super) struct RawScene {
    kind: Option<String>,
    pub(super) F0: Option<f64>,
    pub(super) omega: Option<f64>,
    pub(super) r: Option<f64>,
    pub(super) n_trans: Option<u64>,
    pub(super) n_trans_max: Option<u64>,
    pub(super) n_meas: Option<u64>,
    pub(super) trans_tol: Option<f64>,
    pub(super) period_tol: Option<f64>,
    pub(super) starts: Option<u32>,
    pub(super) design_peak: Option<String>,
    pub(super) nonperiodic_peak: Option<String>,
    pub(super) design_life: Option<f64>,
    pub(super) life_quantile: Option<f64>,
    pub(super) life_tol: Option<f64>,
    pub(super) life_max_periods: Option<u64>,
    pub(super) life_curve: Option<String>,
    // The random and record scenes ([`super::random_load`]).
    pub(super) input: Option<String>,
    pub(super) spectrum: Option<String>,
    pub(super) S0: Option<f64>,
    pub(super) omega_g: Option<f64>,
    pub(super) zeta_g: Option<f64>,
    pub(super) omega_f: Option<f64>,
    pub(super) zeta_f: Option<f64>,
    pub(super) dt: Option<f64>,
    pub(super) duration: Option<f64>,
    pub(super) envelope: Option<RawEnvelope>,
    pub(super) realizations: Option<u64>,
    pub(super) threshold: Option<f64>,
    pub(super) record: Option<String>,
    /// A suite: a list of files or a folder ([`super::random_load`] reads it).
    pub(super) records: Option<toml::Value>,
    pub(super) scale: Option<f64>,
    pub(super) design_intensity: Option<f64>,
    pub(super) intensity: Option<String>,
    pub(super) T: Option<f64>,
    pub(super) ida_tol: Option<f64>,
    pub(super) ida_max: Option<f64>,
    pub(super) drift_ratio: Option<f64>,
    pub(super) storey_height: Option<f64>,
    pub(super) yield_coefficient: Option<f64>,
}

/// The scene kinds of [`super::random`] (the other kinds are [`Scene::NAMES`]).
pub(super) const RANDOM_KINDS: [&str; 2] = ["random", "record"];

/// The keys of `[scene]` that belong to the random scene only, to the record scene only, and to
/// both.
pub(super) const RANDOM_ONLY: [&str; 8] = [
    "spectrum", "S0", "omega_g", "zeta_g", "omega_f", "zeta_f", "dt", "envelope",
];
pub(super) const RECORD_ONLY: [&str; 3] = ["record", "records", "scale"];
pub(super) const RANDOM_SHARED: [&str; 12] = [
    "input",
    "duration",
    "realizations",
    "threshold",
    "design_intensity",
    "intensity",
    "T",
    "ida_tol",
    "ida_max",
    "drift_ratio",
    "storey_height",
    "yield_coefficient",
];

/// `[scene] envelope = { t1, t2, c }` (s, s, 1/s).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawEnvelope {
    pub(super) t1: f64,
    pub(super) t2: f64,
    pub(super) c: f64,
}

impl RawScene {
    /// The harmonic scene's keys given, in the order of [`Harmonic::KEYS`].
    pub(super) fn harmonic_given(&self) -> Vec<&'static str> {
        let present = [
            self.F0.is_some(),
            self.omega.is_some(),
            self.r.is_some(),
            self.n_trans.is_some(),
            self.n_trans_max.is_some(),
            self.n_meas.is_some(),
            self.trans_tol.is_some(),
            self.period_tol.is_some(),
            self.starts.is_some(),
            self.design_life.is_some(),
            self.life_quantile.is_some(),
            self.life_tol.is_some(),
            self.life_max_periods.is_some(),
        ];
        let mut keys: Vec<&'static str> = Harmonic::KEYS
            .into_iter()
            .zip(present)
            .filter_map(|(k, p)| p.then_some(k))
            .collect();
        if self.design_peak.is_some() {
            keys.push("design_peak");
        }
        if self.nonperiodic_peak.is_some() {
            keys.push("nonperiodic_peak");
        }
        if self.life_curve.is_some() {
            keys.push("life_curve");
        }
        keys
    }

    /// A sweepable key of the harmonic scene (`F0`, `omega`, `r`) as given.
    pub(super) fn harmonic(&self, key: &str) -> Option<f64> {
        match key {
            "F0" => self.F0,
            "omega" => self.omega,
            "r" => self.r,
            _ => None,
        }
    }

    /// A number-valued key of the random and record scenes.
    pub(super) fn number(&self, key: &str) -> Option<f64> {
        match key {
            "S0" => self.S0,
            "omega_g" => self.omega_g,
            "zeta_g" => self.zeta_g,
            "omega_f" => self.omega_f,
            "zeta_f" => self.zeta_f,
            "dt" => self.dt,
            "duration" => self.duration,
            "threshold" => self.threshold,
            "scale" => self.scale,
            "design_intensity" => self.design_intensity,
            "T" => self.T,
            "ida_tol" => self.ida_tol,
            "ida_max" => self.ida_max,
            "drift_ratio" => self.drift_ratio,
            "storey_height" => self.storey_height,
            "yield_coefficient" => self.yield_coefficient,
            _ => None,
        }
    }

    /// The keys of the random and record scenes given, in the order of [`RANDOM_ONLY`],
    /// [`RECORD_ONLY`], [`RANDOM_SHARED`].
    pub(super) fn random_given(&self) -> Vec<&'static str> {
        RANDOM_ONLY
            .into_iter()
            .chain(RECORD_ONLY)
            .chain(RANDOM_SHARED)
            .filter(|k| self.has(k))
            .collect()
    }

    /// Whether a key of the random and record scenes is given.
    pub(super) fn has(&self, key: &str) -> bool {
        match key {
            "input" => self.input.is_some(),
            "spectrum" => self.spectrum.is_some(),
            "envelope" => self.envelope.is_some(),
            "realizations" => self.realizations.is_some(),
            "record" => self.record.is_some(),
            "records" => self.records.is_some(),
            "intensity" => self.intensity.is_some(),
            _ => self.number(key).is_some(),
        }
    }

    /// Refuses the random and record scenes' keys in a study of another scene.
    pub(super) fn refuse_random_keys(&self, cx: &Cx) -> Result<(), InputError> {
        if let Some(key) = self.random_given().first() {
            return Err(cx.err(
                &format!("[scene].{key}"),
                cx.source("scene", key),
                format!(
                    "{key} belongs to the random and record scenes; set [scene] kind = \"random\" \
                     or \"record\""
                ),
            ));
        }
        Ok(())
    }

    /// The kind as written (`free` when absent), checked against every scene's name.
    pub(super) fn kind(&self, cx: &Cx) -> Result<&str, InputError> {
        let kind = self.kind.as_deref().unwrap_or("free");
        let known = Scene::NAMES.iter().chain(RANDOM_KINDS.iter());
        if !known.clone().any(|k| *k == kind) {
            let names: Vec<&str> = known.copied().collect();
            return Err(cx.err(
                "[scene].kind",
                format!("{kind:?}"),
                format!("unknown scene; allowed: {}", names.join(", ")),
            ));
        }
        Ok(kind)
    }
}
