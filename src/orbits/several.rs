//! One run of a harmonic study of several damper units as the sweep runs it (model.md §14,
//! issue 68): the run from the study's initial state, then the census of periodic steady states
//! of several units at the same frequency ([`super::units::census`]), and its rows
//! ([`AttractorRow::of_units_census`]) summed up in the record ([`steady_of_rows`]).
//!
//! # Start 0
//! The census's start 0 is the state the run from rest reached at the end of its window
//! (`t_stop`, a section time): `(x, x', y_1 - x, y_1', ..., y_N - x, y_N')`, every unit's own
//! state, not the noise-free initial state. So the attractor the run settles on is always among
//! the census's candidates, and the worst steady amplitude is never below the run's own
//! measured amplitude (the floor of [`AttractorRow::of_units_census`]).
//!
//! # The design life
//! Each motion of the census that is not periodic (its starts that did not settle, told apart
//! by where they wander: [`super::units::motion`]) is measured over the design life by the race
//! of the run's curve ([`race_units`], [`race_runs`]; a run on its own is a curve of one point),
//! its clusters of exceedances spaced by its Lyapunov exponent from two trajectories
//! ([`super::units::lyapunov`]): its amplitude is the estimate, never below the census's windows.
//!
//! # What it does not do
//! No continuation between the frequencies: each run's census stands on its own.

use super::attractors::{AttractorRow, RunId, RunWindow, steady_of_rows};
use super::map::Forcing;
use super::race::{Serves, race_units};
use super::units::census::{UnitsCensus, UnitsCensusSettings, census_units};
use crate::model::System;
use crate::sim::harmonic::simulate_harmonic_ends;
use crate::sim::noise::NoiseStream;
use crate::sim::{
    Harmonic, HarmonicRecord, NoiseSettings, Outcome, Probe, Request, SolverSettings,
};

/// A run of several units with its census.
#[derive(Clone, Debug)]
pub struct UnitsRun {
    /// The run from the initial state, its `steady` summary filled from the census.
    pub record: HarmonicRecord,
    /// The census's forcing, its start 0 (the run's end state, `2 + 2N` components) and the
    /// census; `None` when the run did not end `ok` or `starts = 0`.
    pub census: Option<(Forcing, Vec<f64>, UnitsCensus)>,
}

impl UnitsRun {
    /// The census's attractor rows for the run `run` (empty without a census).
    pub fn rows(&self, run: RunId) -> Vec<AttractorRow> {
        let Some((f, s0, c)) = &self.census else {
            return Vec::new();
        };
        let own = RunWindow {
            amplitude: self.record.amplitude,
            n_meas: self.record.n_meas,
        };
        AttractorRow::of_units_census(run, f, c, s0, own)
    }
}

/// The section state of the run's end (module doc, *Start 0*) from its record and every unit's
/// `(y, w)` at the end; a massless damper's units at zero, as [`super::units::map::eval`] keeps
/// them.
pub fn end_section(sys: &System, rec: &HarmonicRecord, units: &[(f64, f64)]) -> Vec<f64> {
    let (x, v) = (rec.end.x, rec.end.v);
    let mut s = vec![x, v];
    for &(y, w) in units {
        if sys.m == 0.0 {
            s.extend([0.0, 0.0]);
        } else {
            s.extend([y - x, w]);
        }
    }
    s
}

/// One run of several units (module doc): the run from the study's initial state (with its
/// noise, a measurement noise that does not move the system), then `scene.starts` starts of the
/// census from its end state, seeded by `seed` and the design point `point` (the noise-free
/// census: [`UnitsCensusSettings`]), each start's budget `scene.n_trans_max` periods, then the
/// design life of its motion that is not periodic (the race of a curve of one point,
/// [`race_units`]). With one unit the map is one unit's, bit for bit ([`super::units`]). Pure.
#[allow(clippy::too_many_arguments)]
pub fn forced_run_units<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
    seed: u64,
    point: u64,
) -> UnitsRun {
    let mut run = census_run_units(sys, settings, req, scene, noise, probe, seed, point);
    race_runs(std::slice::from_mut(&mut run), &[*scene], Serves::Curve);
    run
}

/// [`forced_run_units`] before the race: the run and its census, the record's `steady` summary
/// not yet filled (what a curve's runs are before [`race_runs`]).
#[allow(clippy::too_many_arguments)]
pub fn census_run_units<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
    seed: u64,
    point: u64,
) -> UnitsRun {
    let (record, units) = simulate_harmonic_ends(sys, settings, req, scene, noise, probe);
    if record.outcome != Outcome::Ok || scene.starts == 0 {
        return UnitsRun {
            record,
            census: None,
        };
    }
    let f = Forcing {
        sys: *sys,
        F0: scene.F0,
        omega: record.omega,
        settings: *settings,
    };
    let s0 = end_section(sys, &record, &units);
    let c = census_units(
        &f,
        &s0,
        &UnitsCensusSettings {
            starts: scene.starts,
            max_periods: scene.n_trans_max,
            handover: super::tolerances::HANDOVER,
            seed,
            point,
        },
    );
    UnitsRun {
        record,
        census: Some((f, s0, c)),
    }
}

/// The race for the design lives over the runs of one curve ([`race_units`]: one design and
/// case, `scenes[i]` run `i`'s scene, in any order of frequency), then each record's `steady`
/// summary from its rows. `serves`: what the curve's values are for ([`Serves`]).
pub fn race_runs(runs: &mut [UnitsRun], scenes: &[Harmonic], serves: Serves) {
    let points: Vec<Option<(Forcing, Harmonic)>> = runs
        .iter()
        .zip(scenes)
        .map(|(r, h)| r.census.as_ref().map(|(f, _, _)| (f.clone(), *h)))
        .collect();
    let mut censuses: Vec<Option<UnitsCensus>> = runs
        .iter_mut()
        .map(|r| r.census.as_mut().map(|c| std::mem::take(&mut c.2)))
        .collect();
    race_units(&points, &mut censuses, serves);
    for (run, c) in runs.iter_mut().zip(censuses) {
        if let (Some(slot), Some(c)) = (run.census.as_mut(), c) {
            slot.2 = c;
        }
        let rows = run.rows(NO_RUN);
        if let Some((_, _, c)) = &run.census {
            run.record.steady = steady_of_rows(&rows, c.starts, c.periods);
        }
    }
}

/// The run identity of rows made only for a record's summary or a count.
pub const NO_RUN: RunId = RunId {
    point_id: 0,
    point: 0,
    case: 0,
    ideal: true,
    r: f64::NAN,
    omega: f64::NAN,
    F0: f64::NAN,
};
