//! `[scene] kind = "random"` and `kind = "record"` (docs/scenes.md): a study whose runs are
//! each design point's realizations of a random load or the records of a suite. Its load is
//! validated by [`super::random_load`]; the other tables are the shared ones, with the keys of
//! the other scenes refused (`[study]`'s horizon, `[perturb]`, `[noise]`, the harmonic keys) and
//! `[hazard]` read when the scene has an intensity measure. [`RandomStudy`] is the validated
//! form, which [`Study::load`](crate::study::Study::load) turns into a [`Study`] of
//! [`Scene::Random`].

use std::path::{Path, PathBuf};

use super::random_load;
use super::raw::{RANDOM_KINDS, RawScene, RawStudy, with_raw};
use crate::error::InputError;
use crate::model::System;
use crate::sim::random::RandomScene;
use crate::sim::{Request, Scene, SolverKind, SolverSettings};
use crate::stats::hazard::SiteHazard;
use crate::study::axis::Axis;
use crate::study::context::Cx;
use crate::study::header::header;
use crate::study::ranking::{self, Ranking};
use crate::study::reliability::{self, Reliability};
use crate::study::run::{self, DEFAULT_CHUNK_RUNS, RunRules, RunSettings};
use crate::study::size::{LoadOptions, MAX_RUNS};
use crate::study::sweep::{self, SceneAxes};
use crate::study::validated::Study;
use crate::study::zones::{self, Zones};
use crate::study::{hazard, solver, system};

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
        let study = with_raw(path, text, |cx, raw| study(cx, raw, path, text))?;
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
pub(super) fn study(
    cx: &Cx,
    raw: &RawStudy,
    path: &Path,
    text: &str,
) -> Result<RandomStudy, InputError> {
    let h = &raw.study;
    let default = RawScene::default();
    let raw_scene = raw.scene.as_ref().unwrap_or(&default);
    let kind = raw_scene.kind(cx)?;
    if !RANDOM_KINDS.contains(&kind) {
        return Err(cx.err(
            "[scene].kind",
            format!("{kind:?}"),
            "a random study needs [scene] kind = \"random\" or \"record\" (the free and \
             harmonic scenes load as a Study)",
        ));
    }
    header(cx, h)?;
    refuse_other_scenes(cx, raw, raw_scene, kind)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let (mut scene, realizations) = random_load::scene(cx, kind, raw_scene, &raw.sweep, dir)?;
    // A random study starts at rest: the initial state defaults to 0.
    let at_rest = System {
        x0: 0.0,
        v0: 0.0,
        y0: 0.0,
        w0: 0.0,
        ..System::TABLE_I
    };
    let system = system::system_on(cx, &raw.system, at_rest)?;
    let swept: Vec<&str> = raw.sweep.keys().map(String::as_str).collect();
    random_load::limit(cx, raw_scene, &system, &swept, &mut scene)?;
    random_load::intensity(cx, raw_scene, &system, &swept, &mut scene)?;
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
    let keys = random_load::axes_of(&scene);
    let scene_axes = SceneAxes {
        keys: &keys,
        check: random_load::check_key,
        listed: true,
        units: true,
    };
    let axes = sweep::axes(cx, &raw.sweep, &raw.system, &scene_axes)?;
    system::check_tables(cx, &raw.system, &system, &axes, &[])?;
    let solver = exact_solver(cx, raw)?;
    let design_intensity = random_load::design_intensity(cx, raw_scene.design_intensity, &axes)?;
    let rules = RunRules {
        aim: DEFAULT_CHUNK_RUNS,
        realizations: true,
        no_audit: None,
        curve: None,
    };
    let run = run::run(cx, &raw.run, realizations, &rules)?;
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

/// Refuses what belongs to the other scenes: the free-decay keys, the harmonic scene's keys,
/// perturbed cases and measurement noise.
fn refuse_other_scenes(
    cx: &Cx,
    raw: &RawStudy,
    raw_scene: &RawScene,
    kind: &str,
) -> Result<(), InputError> {
    raw.study.refuse_free_keys(cx, NOT_RANDOM)?;
    if let Some(key) = raw_scene.harmonic_given().first() {
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
    Ok(())
}

/// The study's solver, which must be `exact`, without an accuracy audit (it re-runs
/// free-decay runs).
fn exact_solver(cx: &Cx, raw: &RawStudy) -> Result<SolverSettings, InputError> {
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
    Ok(solver)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::sim::random::{Excitation, Input, Spectrum};
    use crate::study::RandomStudy;

    fn parse(body: &str) -> Result<RandomStudy, String> {
        RandomStudy::parse(
            Path::new("r.toml"),
            &format!("[study]\nname = \"r\"\n{body}"),
        )
        .map_err(|e| e.to_string())
    }

    #[test]
    fn a_kanai_tajimi_study_is_validated_with_its_defaults() {
        let s = parse(
            "[scene]\nkind = \"random\"\nspectrum = \"kanai-tajimi\"\nS0 = 0.01\nomega_g = 15.6\n\
             zeta_g = 0.6\nduration = 20\nthreshold = 0.02\nenvelope = { t1 = 2, t2 = 10, c = 0.3 }\n\
             [sweep]\nm = [0.01, 0.02]\n",
        )
        .unwrap();
        assert_eq!(s.realizations, 1000);
        assert_eq!(s.scene.dt, 0.005);
        assert_eq!(s.scene.input, Input::Base);
        assert_eq!(s.n_points(), 2);
        // The structure starts at rest.
        assert_eq!(
            (s.system.x0, s.system.v0, s.system.y0, s.system.w0),
            (0.0, 0.0, 0.0, 0.0)
        );
        let Excitation::Random(r) = &s.scene.excitation else {
            panic!()
        };
        assert_eq!(
            r.spectrum,
            Spectrum::KanaiTajimi {
                omega_g: 15.6,
                zeta_g: 0.6
            }
        );
        assert!(r.envelope.is_some());
    }

    #[test]
    fn stripes_need_no_s0_and_a_load_at_its_own_level_does() {
        let stripes = parse(
            "[scene]\nkind = \"random\"\nspectrum = \"clough-penzien\"\nintensity = \"sa\"\n\
             threshold = 0.02\n[sweep]\nim = [0.1, 0.2]\n",
        )
        .unwrap();
        let Excitation::Random(r) = &stripes.scene.excitation else {
            panic!()
        };
        assert_eq!(r.S0, crate::study::scene::random_load::STRIPES_S0);
        // Without stripes the motions run at their own level, which the study must give.
        let own = parse(
            "[scene]\nkind = \"random\"\nspectrum = \"clough-penzien\"\nintensity = \"sa\"\n\
             threshold = 0.02\n[sweep]\nm = [0.1, 0.2]\n",
        )
        .unwrap_err();
        assert!(own.contains("[scene].S0: missing"), "{own}");
        // Stripes without an intensity measure are named first (not the S0 they would excuse).
        let bare = parse("[scene]\nkind = \"random\"\nspectrum = \"white\"\n[sweep]\nim = [0.3]\n")
            .unwrap_err();
        assert!(
            bare.contains(
                "[sweep].im = [0.3]: stripes (g) scale each motion to its own intensity \
                 measure; give [scene] intensity = \"pga\" or \"sa\""
            ),
            "{bare}"
        );
    }

    #[test]
    fn a_swept_intensity_lands_on_each_point() {
        let s = parse(
            "[scene]\nkind = \"random\"\nspectrum = \"white\"\nduration = 5\n[sweep]\n\
             S0 = [0.001, 0.01, 0.1]\nd = [0.01, 0.02]\n",
        )
        .unwrap();
        assert_eq!(s.n_points(), 6);
        let (sys, scene) = s.point(3);
        assert_eq!(sys.d, 0.02);
        let Excitation::Random(r) = &scene.excitation else {
            panic!()
        };
        assert_eq!(r.S0, 0.01);
    }
}
