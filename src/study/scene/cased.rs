//! The tables of a scene whose runs are each design point's cases (`[perturb]`, `[noise]`):
//! free decay and harmonic. [`study`] validates them in turn, in the order the messages have
//! always come in; a scene adds its own checks at their places through [`CasedScene`].

use std::path::Path;

use super::raw::RawStudy;
use crate::error::InputError;
use crate::model::System;
use crate::sim::{Scene, SolverSettings};
use crate::study::axis::Axis;
use crate::study::context::Cx;
use crate::study::header::{RawHeader, header};
use crate::study::perturb::{self, Case};
use crate::study::run::{self, DEFAULT_CHUNK_RUNS, RunRules};
use crate::study::sweep::{self, SceneAxes};
use crate::study::validated::Study;
use crate::study::{noise, ranking, reliability, system, zones};

/// What a scene whose runs are cases adds to the tables it shares with the other: its
/// validated `[scene]`, its sweepable keys and its cross-checks. Each default is free decay's.
pub(super) trait CasedScene {
    /// The validated scene.
    fn scene(&self) -> Scene;

    /// Refuses `[study]` keys that do not belong to the scene (checked before `[study]` is read).
    fn check_header(&self, _cx: &Cx, _h: &RawHeader) -> Result<(), InputError> {
        Ok(())
    }

    /// The scene's own keys that `[sweep]` may sweep besides the system's.
    fn sweep_keys(&self) -> SceneAxes<'static> {
        SceneAxes::NONE
    }

    /// Puts the axes in the order the plan walks them (file order unless the scene says).
    fn order_axes(&self, _axes: &mut Vec<Axis>) {}

    /// Refuses a solver the scene cannot use.
    fn check_solver(&self, _cx: &Cx, _solver: &SolverSettings) -> Result<(), InputError> {
        Ok(())
    }

    /// What the scene asks of `[run]`, given the system and the axes.
    fn run_rules<'a>(&self, _system: &System, _axes: &'a [Axis]) -> RunRules<'a> {
        RunRules {
            aim: DEFAULT_CHUNK_RUNS,
            realizations: false,
            no_audit: None,
            curve: None,
        }
    }

    /// Checks every run of the plan (each design point, each case) once the tables are known.
    fn check_runs(
        &self,
        _cx: &Cx,
        _system: &System,
        _axes: &[Axis],
        _cases: &[Case],
    ) -> Result<(), InputError> {
        Ok(())
    }
}

/// Each table of a study of `scene` in turn (`[scene]` itself already validated into it).
pub(super) fn study(
    cx: &Cx,
    raw: &RawStudy,
    path: &Path,
    text: &str,
    scene: &impl CasedScene,
) -> Result<Study, InputError> {
    let h = &raw.study;
    if raw.hazard.is_some() {
        return Err(InputError::new(format!(
            "{}: [hazard]: a seismic hazard curve belongs to the random and record scenes with an \
             intensity measure ([scene] kind = \"random\" or \"record\", intensity = \"pga\" \
             or \"sa\")",
            cx.file
        )));
    }
    scene.check_header(cx, h)?;
    let request = header(cx, h)?;
    let system = system::system(cx, &raw.system)?;
    let mut axes = sweep::axes(cx, &raw.sweep, &raw.system, &scene.sweep_keys())?;
    scene.order_axes(&mut axes);
    let noise = noise::noise(cx, raw.noise.as_ref())?;
    let cases = perturb::cases(cx, raw.perturb.as_ref(), &axes, &system, noise.as_ref())?;
    system::check_tables(cx, &raw.system, &system, &axes, &cases)?;
    let solver = solver_of(cx, raw, scene)?;
    let reliability = reliability::reliability(cx, &raw.reliability)?;
    let zones = zones::zones(cx, &raw.zones, &axes)?;
    let ranking = ranking::ranking(cx, &raw.ranking)?;
    let run = run::run(
        cx,
        &raw.run,
        cases.len() as u64,
        &scene.run_rules(&system, &axes),
    )?;
    scene.check_runs(cx, &system, &axes, &cases)?;
    Ok(Study {
        path: path.to_path_buf(),
        source: text.to_string(),
        name: h.name.clone(),
        seed: h.seed.unwrap_or(0),
        request,
        scene: scene.scene(),
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

/// `[solver]`, checked against the scene.
fn solver_of(
    cx: &Cx,
    raw: &RawStudy,
    scene: &impl CasedScene,
) -> Result<SolverSettings, InputError> {
    let solver = crate::study::solver::solver(cx, &raw.solver)?;
    scene.check_solver(cx, &solver)?;
    Ok(solver)
}
