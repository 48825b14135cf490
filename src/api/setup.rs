//! One run of one system given as `KEY=VALUE` settings (the `impactsweep simulate --set` keys,
//! the Python binding's keyword arguments): the setup, its run with or without a trace, and
//! its record as JSON. Shared by the command line (`app/simulate.rs`) and the Python
//! binding, so both give the same bits and the same errors.

use super::realization::{self, RandomSetup};
use crate::error::InputError;
use crate::model::{SYSTEM_KEYS, System, UNIT_KEYS};
use crate::sim::{
    self, Drive, Harmonic, HarmonicRecord, Probe, Record, Request, Scene, SceneRecord, SolverKind,
    SolverSettings, State,
};

/// A fully resolved single run.
#[derive(Clone, Debug)]
pub struct Setup {
    pub system: System,
    pub solver: SolverSettings,
    pub request: Request,
    /// Free decay (default), the harmonic scene (`--set scene=harmonic`), or the random or
    /// record scene (`--set scene=random`, `scene=record`: then [`Setup::random`] holds it).
    pub scene: Scene,
    /// `--set scene=random` or `scene=record`: the one-point study the keys describe and the
    /// realization to run ([`RandomSetup`]); `system`, `solver`, `request` and `scene` are
    /// its design's. `None` in the free and harmonic scenes.
    pub random: Option<Box<RandomSetup>>,
}

impl Default for Setup {
    fn default() -> Self {
        Setup {
            system: System::TABLE_I,
            solver: SolverSettings::default(),
            request: Request::default(),
            scene: Scene::Free,
            random: None,
        }
    }
}

fn all_keys() -> String {
    let mut keys: Vec<&str> = SYSTEM_KEYS.to_vec();
    keys.extend(UNIT_KEYS);
    keys.extend(SolverSettings::KEYS);
    keys.push("t_end");
    keys.push("scene");
    keys.extend(Harmonic::KEYS);
    keys.join(" ")
}

/// The scenes `--set scene=` names.
fn scene_names() -> String {
    let mut names = Scene::NAMES.to_vec();
    names.extend(realization::KINDS);
    names.join(", ")
}

/// The scene the last `scene=` of `sets` names, if it is the random or record scene.
fn random_kind(sets: &[String]) -> Option<&'static str> {
    let last = sets
        .iter()
        .filter_map(|item| item.split_once('='))
        .filter(|(k, _)| k.trim() == "scene")
        .map(|(_, v)| v.trim())
        .next_back()?;
    realization::KINDS.into_iter().find(|k| *k == last)
}

/// The harmonic scene's `--set` keys as given, checked together once all are read.
#[derive(Default)]
struct HarmonicKeys {
    scene: Option<String>,
    harmonic: Harmonic,
    /// Every forced key given, as `KEY=VALUE`, in order.
    given: Vec<String>,
    omega: Option<String>,
    r: Option<String>,
    /// Free-decay-only keys given (`peaks`, `t_end`).
    free_only: Vec<String>,
}

impl Setup {
    /// Applies `KEY=VALUE` settings; the error names the key, the value and what is allowed.
    /// With `scene=random` or `scene=record` among them the setup is the one-point study of
    /// these keys alone ([`RandomSetup::from_sets`]: a study's defaults, not this setup's).
    pub fn apply(&mut self, sets: &[String]) -> Result<(), InputError> {
        if let Some(kind) = random_kind(sets) {
            let r = RandomSetup::from_sets(kind, sets)?;
            self.system = r.system();
            self.solver = r.study.solver;
            self.request = r.study.request;
            self.scene = Scene::Random(r.scene());
            self.random = Some(Box::new(r));
            return Ok(());
        }
        self.random = None;
        let mut forced = HarmonicKeys::default();
        if let Some(&h) = self.scene.harmonic() {
            forced.scene = Some("harmonic".into());
            forced.harmonic = h;
        }
        for item in sets {
            self.apply_one(item, &mut forced)?;
        }
        self.settle_scene(forced)?;
        self.validate()
    }

    /// Applies one `KEY=VALUE` setting; the harmonic scene's keys and the free-decay-only keys
    /// are gathered in `forced` for [`Self::settle_scene`].
    fn apply_one(&mut self, item: &str, forced: &mut HarmonicKeys) -> Result<(), InputError> {
        let Some((key, raw)) = item.split_once('=') else {
            return Err(InputError::new(format!(
                "--set {item}: expected KEY=VALUE, with KEY one of: {}",
                all_keys()
            )));
        };
        let (key, raw) = (key.trim(), raw.trim());
        if key == "scene" {
            if !Scene::NAMES.contains(&raw) && !realization::KINDS.contains(&raw) {
                return Err(InputError::new(format!(
                    "--set scene={raw}: unknown scene; allowed: {}",
                    scene_names()
                )));
            }
            forced.scene = Some(raw.to_string());
            return Ok(());
        }
        if key == "solver" {
            self.solver.kind = SolverKind::parse(raw).ok_or_else(|| {
                let names: Vec<&str> = SolverKind::ALL.iter().map(|k| k.name()).collect();
                InputError::new(format!(
                    "--set solver={raw}: unknown solver; allowed: {}",
                    names.join(", ")
                ))
            })?;
            return Ok(());
        }
        let known = SYSTEM_KEYS.contains(&key)
            || UNIT_KEYS.contains(&key)
            || SolverSettings::KEYS.contains(&key)
            || Harmonic::KEYS.contains(&key)
            || key == "t_end";
        if !known {
            for kind in realization::KINDS {
                if realization::scene_keys(kind).contains(&key) {
                    return Err(InputError::new(format!(
                        "--set {key}={raw}: a key of the {kind} scene; add --set scene={kind}"
                    )));
                }
            }
            return Err(InputError::new(format!(
                "--set {key}={raw}: unknown key '{key}'; allowed keys: {}",
                all_keys()
            )));
        }
        self.set_value(key, raw, forced)
    }

    /// Sets a known numeric key `key` to `raw` (a solver setting, a harmonic scene's key, a
    /// free-decay horizon key or a system value).
    fn set_value(
        &mut self,
        key: &str,
        raw: &str,
        forced: &mut HarmonicKeys,
    ) -> Result<(), InputError> {
        let value: f64 = raw
            .parse()
            .map_err(|_| InputError::new(format!("--set {key}={raw}: '{raw}' is not a number")))?;
        let integer = |v: f64| -> Result<u64, InputError> {
            if v.fract() == 0.0 && (0.0..=9.0e15).contains(&v) {
                Ok(v as u64)
            } else {
                Err(InputError::new(format!(
                    "--set {key}={raw}: must be a whole number >= 0"
                )))
            }
        };
        match key {
            "tol" => self.solver.tol = value,
            "h" => self.solver.h = value,
            "rtol" => self.solver.rtol = value,
            "atol" => self.solver.atol = value,
            "chatter_tol" => self.solver.chatter_tol = value,
            "max_impacts" => self.solver.max_impacts = integer(value)?,
            "max_steps" => self.solver.max_steps = integer(value)?,
            "t_max_periods" => self.solver.t_max_periods = value,
            "peaks" => {
                self.request.peaks = integer(value)? as usize;
                forced.free_only.push(format!("{key}={raw}"));
            }
            "t_end" => {
                self.request.t_end = Some(value);
                forced.free_only.push(format!("{key}={raw}"));
            }
            "F0" | "omega" | "r" | "n_trans" | "n_trans_max" | "n_meas" | "trans_tol"
            | "period_tol" | "starts" | "design_life" | "life_quantile" | "life_tol"
            | "life_max_periods" => {
                let h = &mut forced.harmonic;
                match key {
                    "F0" => h.F0 = value,
                    "omega" => {
                        h.drive = Drive::Omega(value);
                        forced.omega = Some(raw.to_string());
                    }
                    "r" => {
                        h.drive = Drive::Ratio(value);
                        forced.r = Some(raw.to_string());
                    }
                    "n_trans" => h.n_trans = Some(integer(value)?),
                    "n_trans_max" => h.n_trans_max = integer(value)?,
                    "n_meas" => h.n_meas = integer(value)?,
                    "trans_tol" => h.trans_tol = value,
                    "starts" => h.starts = integer(value)? as u32,
                    "design_life" => h.design_life = value,
                    "life_quantile" => h.life_quantile = value,
                    "life_tol" => h.life_tol = value,
                    "life_max_periods" => h.life_max_periods = integer(value)?,
                    _ => h.period_tol = value,
                }
                forced.given.push(format!("{key}={raw}"));
            }
            _ => {
                self.system.set(key, value);
            }
        }
        Ok(())
    }

    /// Decides the scene from the keys given: the forced keys need `scene=harmonic`, `omega`
    /// and `r` exclude each other, and the free-decay horizon keys do not apply to it.
    fn settle_scene(&mut self, forced: HarmonicKeys) -> Result<(), InputError> {
        if let (Some(w), Some(r)) = (&forced.omega, &forced.r) {
            return Err(InputError::new(format!(
                "--set omega={w} and --set r={r}: give the forcing frequency once, as omega \
                 (rad/s) or as r = omega / sqrt(K/M)"
            )));
        }
        match forced.scene.as_deref() {
            Some("harmonic") => {
                if let Some(item) = forced.free_only.first() {
                    return Err(InputError::new(format!(
                        "--set {item}: a free-decay key; the harmonic scene runs n_trans + \
                         n_meas forcing periods"
                    )));
                }
                self.scene = Scene::Harmonic(forced.harmonic);
            }
            _ => {
                if let Some(item) = forced.given.first() {
                    return Err(InputError::new(format!(
                        "--set {item}: a key of the harmonic scene; add --set scene=harmonic"
                    )));
                }
                self.scene = Scene::Free;
            }
        }
        Ok(())
    }

    pub fn validate(&self) -> Result<(), InputError> {
        let wrap = |e: crate::model::RangeError| InputError::new(format!("--set {e}"));
        self.system.validate().map_err(wrap)?;
        self.solver.validate().map_err(wrap)?;
        self.request.validate().map_err(wrap)?;
        if let Some(h) = self.scene.harmonic() {
            h.validate(&self.system).map_err(wrap)?;
            if self.solver.kind != SolverKind::Exact {
                return Err(InputError::new(format!(
                    "--set solver={}: the harmonic scene is solved in closed form only; allowed: \
                     exact",
                    self.solver.kind.name()
                )));
            }
        }
        Ok(())
    }

    /// Runs the free-decay simulation without noise.
    pub fn run<P: Probe>(&self, probe: &mut P) -> Record {
        sim::simulate(&self.system, &self.solver, &self.request, None, probe)
    }

    /// Runs the setup's scene without noise.
    pub fn run_scene<P: Probe>(&self, probe: &mut P) -> SceneRecord {
        match &self.scene {
            // The census's starts are those of study seed 0, design point 0.
            Scene::Harmonic(h) => SceneRecord::Harmonic(crate::orbits::forced_run(
                &self.system,
                &self.solver,
                &self.request,
                h,
                None,
                probe,
                0,
                0,
            )),
            Scene::Free | Scene::Random(_) => sim::simulate_scene(
                &self.system,
                &self.solver,
                &self.request,
                &self.scene,
                None,
                probe,
            ),
        }
    }
}

pub use crate::sim::TraceProbe;

/// Simulates with a trace sampled every `dt` (plus every impact) up to `t_end`.
pub fn trace(setup: &Setup, dt: f64, t_end: Option<f64>) -> (Record, Vec<(f64, State)>) {
    let mut s = setup.clone();
    s.request.trace_dt = Some(dt);
    if t_end.is_some() {
        s.request.t_end = t_end;
    }
    let mut probe = TraceProbe::default();
    let rec = s.run(&mut probe);
    (rec, probe.rows)
}

/// The setup's scene with a trace sampled every `dt` (plus every impact) over the whole run.
pub fn trace_scene(setup: &Setup, dt: f64) -> (SceneRecord, Vec<(f64, State)>) {
    let mut s = setup.clone();
    s.request.trace_dt = Some(dt);
    let mut probe = TraceProbe::default();
    let rec = s.run_scene(&mut probe);
    (rec, probe.rows)
}

/// A number for JSON: NaN and infinities become null.
fn num(v: f64) -> serde_json::Value {
    serde_json::Number::from_f64(v)
        .map(serde_json::Value::Number)
        .unwrap_or(serde_json::Value::Null)
}

/// The system and the solver settings, as every record's JSON carries them.
fn insert_setup(map: &mut serde_json::Map<String, serde_json::Value>, setup: &Setup) {
    super::json::insert_system(map, &setup.system, &setup.solver);
}

/// The record as one JSON object (SI units; NaN becomes null).
pub fn record_json(setup: &Setup, rec: &Record) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    map.insert("outcome".into(), rec.outcome.name().into());
    for (k, v) in [
        ("x1", rec.x1),
        ("t1", rec.t1),
        ("x2", rec.x2),
        ("t2", rec.t2),
        ("xmax", rec.xmax),
        ("di", rec.di),
        ("energy_impact", rec.energy_impact),
        ("energy_viscous", rec.energy_viscous),
        ("t_stop", rec.t_stop),
    ] {
        map.insert(k.into(), num(v));
    }
    map.insert("impacts".into(), rec.impacts.into());
    map.insert("sticks".into(), rec.sticks.into());
    map.insert("steps".into(), rec.steps.into());
    map.insert(
        "peaks".into(),
        rec.peaks
            .iter()
            .map(|(x, t)| serde_json::json!({"x": num(*x), "t": num(*t)}))
            .collect::<Vec<_>>()
            .into(),
    );
    insert_setup(&mut map, setup);
    serde_json::Value::Object(map)
}

/// A forced record as one JSON object: the forced keys, the usual counts, `outcome`, the
/// system, the solver and the scene (SI units; NaN becomes null).
pub fn forced_json(setup: &Setup, rec: &HarmonicRecord) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    map.insert("outcome".into(), rec.outcome.name().into());
    map.insert("scene".into(), "harmonic".into());
    for (k, v) in [
        ("F0", rec.F0),
        ("omega", rec.omega),
        ("r", rec.r),
        ("amplitude", rec.amplitude),
        ("impacts_per_period", rec.impacts_per_period),
        ("amplitude_linear", rec.amplitude_linear),
        ("attenuation", rec.attenuation),
        ("energy_force", rec.energy_force),
        ("energy_impact", rec.energy_impact),
        ("energy_viscous", rec.energy_viscous),
        ("t_stop", rec.t_stop),
    ] {
        map.insert(k.into(), num(v));
    }
    map.insert("period".into(), rec.period.into());
    let st = &rec.steady;
    for (k, v) in [
        ("amplitude_worst", st.amplitude_worst),
        ("worst_impacts_per_period", st.worst_impacts_per_period),
        ("worst_basin_share", st.worst_basin_share),
        ("rest_amplitude", st.rest_amplitude),
    ] {
        map.insert(k.into(), num(v));
    }
    map.insert("starts".into(), st.starts.into());
    map.insert("attractors".into(), st.attractors.into());
    map.insert("worst_period".into(), st.worst_period.into());
    map.insert("rest_period".into(), st.rest_period.into());
    map.insert("census_periods".into(), st.census_periods.into());
    map.insert("worst_kind".into(), st.worst_kind.into());
    for (k, v) in [
        ("worst_lyapunov", st.worst_lyapunov),
        ("worst_window_amplitude", st.worst_window_amplitude),
        ("worst_life_lo", st.worst_life_lo),
        ("worst_life_hi", st.worst_life_hi),
    ] {
        map.insert(k.into(), num(v));
    }
    map.insert("n_trans".into(), rec.n_trans.into());
    map.insert("converged".into(), rec.converged.into());
    map.insert("impacts".into(), rec.impacts.into());
    map.insert("sticks".into(), rec.sticks.into());
    map.insert("steps".into(), rec.steps.into());
    map.insert(
        "end".into(),
        serde_json::json!({
            "x": num(rec.end.x),
            "v": num(rec.end.v),
            "y": num(rec.end.y),
            "w": num(rec.end.w),
        }),
    );
    insert_setup(&mut map, setup);
    map.insert(
        "harmonic".into(),
        serde_json::to_value(&setup.scene).unwrap_or_default(),
    );
    serde_json::Value::Object(map)
}
