//! The low-`p_f` route of the random scene's reduction (model.md §13): a design whose
//! realizations passed the threshold fewer than [`SUBSET_BELOW`] times, where Monte Carlo's
//! estimate rests on too few failures, gets `p_f` by subset simulation
//! ([`crate::stats::subset`], Au and Beck 2001) over its realization's white-noise samples as
//! standard normals: the same simulator, the normals handed in as a slice
//! ([`GivenNormals`]), the response `max |x|` (NaN, i.e. not failing, for a run that did not
//! end `ok`). Seeded by the study seed alone, the same seed at every design point (common random
//! numbers, as the sweep's realizations: identical designs get identical estimates and two
//! designs are compared on correlated samples), so the same bits on any thread
//! count. Asked for by `reduce --subset N` (`N` samples per level); a record has no normals to
//! sample and keeps Monte Carlo.
//!
//! Its interval is a lognormal one on the method's coefficient of variation with fully
//! correlated levels (`cov_upper`, the conservative bound):
//! `p exp(-+1.96 sigma)`, `sigma^2 = ln(1 + cov_upper^2)`, the upper end at most 1.

use crate::numeric::mix64;
use crate::plan::Plan;
use crate::sim::random::{GivenNormals, RandomRun};
use crate::sim::{NoProbe, Outcome, Scene};
use crate::stats::fragility::Z95;
use crate::stats::subset::{SubsetOutcome, SubsetSettings, subset_simulation};
use crate::study::Study;

/// Exceedances below which a design's `p_f` is estimated by subset simulation as well: Monte
/// Carlo's coefficient of variation `sqrt((1 - p) / (n p))` is then above about 0.3.
pub const SUBSET_BELOW: u64 = 10;

/// Samples per level by default (Au and Beck's choice): about 1,000 runs per decade of `p_f`.
pub const DEFAULT_SUBSET_N: usize = 1000;

/// Runs at most per design by default: with [`DEFAULT_SUBSET_N`] per level, 11 levels
/// (`p_f` down to about 1e-11), and never fewer than 6 levels (1e-6) for another `n`.
pub const MAX_SUBSET_RUNS: usize = 10_000;

/// A subset simulation's estimate of a design point's `p_f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubsetPf {
    pub p_f: f64,
    /// Its coefficient of variation with uncorrelated levels, and with fully correlated ones.
    pub cov: f64,
    pub cov_upper: f64,
    /// The interval (module doc).
    pub lo: f64,
    pub hi: f64,
    /// Levels run and responses evaluated.
    pub levels: u64,
    pub runs: u64,
    /// Whether the last level reached the threshold.
    pub converged: bool,
}

/// `p_f = P(max |x| > b)` of design point `point` of `study` by subset simulation with `n`
/// samples per level; `None` for a record (no normals) or settings subset simulation refuses
/// (`n` a multiple of 10, at least 100).
pub fn subset_pf(study: &Study, point: u64, b: f64, n: usize) -> Option<SubsetPf> {
    let (sys, scene) = Plan::new(study).point(point);
    let Scene::Random(scene) = scene else {
        return None;
    };
    if !scene.draws_normals() {
        return None;
    }
    let setup = RandomRun::new(&sys, &study.solver, &scene);
    // Each level after the first adds n (1 - p0) runs.
    let per_level = (n - n / 10).max(1);
    let settings = SubsetSettings {
        n,
        seed: mix64(study.seed ^ 0x5B5E_75B5),
        max_levels: (1 + MAX_SUBSET_RUNS.saturating_sub(n) / per_level).clamp(6, 20),
        ..SubsetSettings::default()
    };
    let r = subset_simulation(setup.n_normals(), b, &settings, |u| {
        let rec = setup.run(&study.request, GivenNormals::new(u), &mut NoProbe);
        if rec.outcome == Outcome::Ok {
            rec.amplitude
        } else {
            f64::NAN
        }
    });
    if r.outcome == SubsetOutcome::Invalid {
        return None;
    }
    let sigma = (1.0 + r.cov_upper * r.cov_upper).ln().sqrt();
    Some(SubsetPf {
        p_f: r.p_f,
        cov: r.cov,
        cov_upper: r.cov_upper,
        lo: r.p_f * (-Z95 * sigma).exp(),
        hi: (r.p_f * (Z95 * sigma).exp()).min(1.0),
        levels: r.levels.len() as u64,
        runs: r.evaluations,
        converged: r.outcome == SubsetOutcome::Converged,
    })
}
