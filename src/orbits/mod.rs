//! Steady states of the forced scene (pure; no I/O): the stroboscopic map with its exact
//! Jacobian ([`map`]), periodic orbits by shooting with their Floquet multipliers ([`shoot`]),
//! continuation along the frequency or the force ([`continuation`]) and the attractor census of
//! one frequency point ([`census`]); Masri and Caughey's symmetric period-1 orbit in closed
//! form ([`analytic`]), which the shooting is tested against.

pub mod analytic;
pub mod attractors;
pub mod census;
pub mod continuation;
pub mod curve;
pub mod graze;
pub mod label;
pub mod life;
pub mod locate;
pub mod lyapunov;
pub mod map;
pub mod race;
pub mod response;
pub mod sequence;
pub mod several;
pub mod shoot;
pub mod tolerances;
pub mod twopar;
pub mod units;
pub mod units_response;

use crate::model::System;
use crate::sim::harmonic::Steady;
use crate::sim::noise::NoiseStream;
use crate::sim::{
    Harmonic, HarmonicRecord, NoiseSettings, Outcome, Probe, Request, SolverSettings,
    simulate_harmonic,
};

pub use tolerances::{CENSUS_WINDOW, HANDOVER};

/// One run of the harmonic scene as a sweep runs it: the run from the study's initial state
/// ([`simulate_harmonic`], with its noise), then the attractor census of `scene.starts` starts
/// at the same frequency ([`census::census`], noise-free: the noise is a measurement noise and
/// does not move the system) with the life amplitudes of its motions that are not periodic
/// ([`race`]). `seed` and `point` fix the census's starts. A system of several units takes the
/// census of several units instead ([`several::forced_run_units`], its record). Pure.
#[allow(clippy::too_many_arguments)]
pub fn forced_run<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
    seed: u64,
    point: u64,
) -> HarmonicRecord {
    if sys.unit_count() > 1 {
        return several::forced_run_units(sys, settings, req, scene, noise, probe, seed, point)
            .record;
    }
    let mut rec = simulate_harmonic(sys, settings, req, scene, noise, probe);
    if rec.outcome != Outcome::Ok || scene.starts == 0 {
        return rec;
    }
    let f = map::Forcing {
        sys: *sys,
        F0: scene.F0,
        omega: rec.omega,
        settings: *settings,
    };
    // Start 0 goes on from where the run from the initial state ended (a section time): the
    // same trajectory, without running its transient again.
    let s0 = [rec.end.x, rec.end.v, rec.end.y - rec.end.x, rec.end.w];
    let c = census::census(
        &f,
        &s0,
        &census::CensusSettings {
            starts: scene.starts,
            max_periods: scene.n_trans_max,
            handover: HANDOVER,
            window: CENSUS_WINDOW,
            seed,
            point,
            // The run from the initial state is start 0's transient so far.
            spent0: if rec.converged { 0 } else { rec.n_trans },
        },
    );
    // The life amplitudes of its motions that are not periodic, where they can change its
    // worst amplitude (a curve of one point: [`race`]).
    let mut cs = [Some(c)];
    race::race(&[Some((f, *scene))], &mut cs, race::Serves::Curve);
    if let Some(c) = &cs[0] {
        rec.steady = steady_of(c);
    }
    rec
}

/// The census's summary for a run's record: [`attractors::steady_of_rows`] of its rows.
pub fn steady_of(c: &census::Census) -> Steady {
    let run = attractors::RunId {
        point_id: 0,
        point: 0,
        case: 0,
        ideal: true,
        r: f64::NAN,
        omega: f64::NAN,
        F0: f64::NAN,
    };
    let rows = attractors::AttractorRow::of_census(run, c, f64::NAN);
    attractors::steady_of_rows(&rows, c.starts, c.periods)
}
