//! The frequency-response showcase's curves for the race examples (`race_cost`, `race_drop`),
//! built as the sweep builds them: `configs/frequency-response.toml` read and expanded by the
//! study and the plan (its frequency grid, seed, design points and cases), each curve's run
//! from the initial state, then the census passes. (Until `race_cost` went through the plan it
//! computed the frequencies as `0.8 + 0.005 i`, which differs from the study's grid in the last
//! bits at some frequencies: its chaotic peaks differed from the showcase's by up to 14 %.)

use impactsweep::orbits::census::{Census, CensusSettings};
use impactsweep::orbits::curve::{
    CurveFrequency, census_passes, curve_points, from_rest, race_points,
};
use impactsweep::orbits::map::{Forcing, Section};
use impactsweep::plan::Plan;
use impactsweep::sim::Harmonic;
use impactsweep::study::Study;
use std::path::Path;

/// One curve's censuses (both passes, before any life is measured) and its race points.
#[allow(dead_code)]
pub struct ShowcaseCurve {
    pub censuses: Vec<Option<Census>>,
    pub race_points: Vec<Option<(Forcing, Harmonic)>>,
}

/// The showcase study, as the sweep reads it.
pub fn study() -> Study {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/frequency-response.toml");
    Study::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The designs of `study`: its design points over its frequencies (nine for the showcase).
pub fn designs(study: &Study) -> u64 {
    study.n_points() / study.curve_points()
}

/// The curve of design `design` (below [`designs`]; its points are `design * n_f + i` over the
/// study's `n_f` frequencies) in case `case` (0: the ideal case), as the sweep builds it from
/// its runs from the initial state: each frequency's forcing, census settings and start 0
/// (`None`: no census there), and its scene and design point.
pub fn showcase_points(
    study: &Study,
    design: u64,
    case: u32,
) -> (Vec<Option<CurvePoint>>, Vec<(Harmonic, u64)>) {
    let plan = Plan::new(study);
    let n_f = study.curve_points();
    let runs: Vec<_> = (design * n_f..(design + 1) * n_f)
        .map(|p| plan.run(p, case))
        .collect();
    let freqs: Vec<CurveFrequency> = runs.iter().map(|r| plan.curve_frequency(r)).collect();
    let targets: Vec<(Harmonic, u64)> = freqs.iter().map(|f| (f.scene, f.point)).collect();
    let sys = runs[0].system;
    let records = from_rest(
        &sys,
        &study.solver,
        &study.request,
        study.noise.as_ref(),
        freqs,
    );
    let points = curve_points(&sys, &study.solver, study.seed, &targets, &records);
    (points, targets)
}

/// One frequency of a curve for the census: its forcing, census settings and start 0.
pub type CurvePoint = (Forcing, CensusSettings, Section);

/// The curve of design `design` in case `case` ([`showcase_points`]): its censuses (both
/// passes, before any life is measured) and race points.
#[allow(dead_code)]
pub fn showcase_curve(study: &Study, design: u64, case: u32) -> ShowcaseCurve {
    let (points, targets) = showcase_points(study, design, case);
    ShowcaseCurve {
        censuses: census_passes(&points),
        race_points: race_points(&points, &targets),
    }
}
