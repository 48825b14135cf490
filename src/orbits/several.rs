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
//! # What it does not do
//! A motion that is not periodic carries its largest amplitude over its windows, a lower bound:
//! the design-life measurement and the Lyapunov exponent of such motions cover one unit
//! ([`super::race`]), and a study of several units refuses the design-life keys. No continuation
//! between the frequencies either: each run's census stands on its own.

use super::attractors::{AttractorRow, RunId, RunWindow, steady_of_rows};
use super::map::Forcing;
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
/// census: [`UnitsCensusSettings`]), each start's budget `scene.n_trans_max` periods. With one
/// unit the map is one unit's, bit for bit ([`super::units`]). Pure.
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
    let mut out = UnitsRun {
        record,
        census: Some((f, s0, c)),
    };
    let rows = out.rows(NO_RUN);
    if let Some((_, _, c)) = &out.census {
        out.record.steady = steady_of_rows(&rows, c.starts, c.periods);
    }
    out
}

/// The run identity of rows made only for the record's summary.
const NO_RUN: RunId = RunId {
    point_id: 0,
    point: 0,
    case: 0,
    ideal: true,
    r: f64::NAN,
    omega: f64::NAN,
    F0: f64::NAN,
};
