//! A frequency-response curve as one unit of work: the runs of one design and case at every
//! swept frequency, in frequency order, each frequency's attractor census seeded with the
//! attractors its neighbours found.
//!
//! # Order
//! For each frequency (in the curve's own order) the run from the study's initial state comes
//! first ([`simulate_harmonic`], with the run's noise), then the census:
//!
//! 1. **Up.** In increasing frequency, each frequency runs its own seeded starts
//!    ([`Census::run_starts`]), then continues every attractor of the next lower frequency to
//!    its own ([`Census::seed`]: Newton on a periodic orbit, a run from its state otherwise).
//! 2. **Down.** In decreasing frequency, each frequency continues every attractor of the next
//!    higher frequency (as it stands after both passes) to its own.
//!
//! The up pass contains the transient sweep up the band (each frequency started where the
//! previous one settled) and the down pass the sweep down it: inside a hysteresis loop the two
//! sweeps stay on the two branches of the loop. A frequency's census therefore holds what its
//! own starts reach, plus what its neighbours' attractors become when the frequency moves by
//! one step: the census can only find more than its starts alone, never less, and a branch
//! that one start reached anywhere along the curve is followed to every frequency where it
//! stays stable. Basin shares remain those of the frequency's own starts (a continued
//! attractor that no start reached has share 0).
//!
//! Pure: the same inputs give the same bits, whatever runs beside it.

use super::census::{Census, CensusSettings, Origin};
use super::map::{Forcing, Section};
use super::race::Serves;
use super::shoot::Newton;
use super::{CENSUS_WINDOW, HANDOVER, steady_of};
use crate::model::System;
use crate::sim::noise::NoiseStream;
use crate::sim::{
    Harmonic, HarmonicRecord, NoProbe, NoiseSettings, Outcome, Request, SolverSettings,
    simulate_harmonic,
};

/// One frequency of a curve: its scene, the census's identity for its starts (the design
/// point) and its run's noise stream, if any.
pub struct CurveFrequency {
    pub scene: Harmonic,
    pub point: u64,
    pub noise: Option<NoiseStream>,
}

/// What a curve's runs found: per frequency (in the input order) the record of the run from
/// the initial state (its `steady` summary filled from the census) and the census.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveRun {
    pub records: Vec<HarmonicRecord>,
    pub censuses: Vec<Option<Census>>,
}

/// Runs one curve (module doc): the system `sys` (one design and case) at each of `freqs`.
/// A frequency whose run from the initial state does not end `ok`, or a scene with
/// `starts = 0`, has no census (`None`) and takes no part in the passes.
pub fn run_curve(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    noise: Option<&NoiseSettings>,
    seed: u64,
    freqs: Vec<CurveFrequency>,
) -> CurveRun {
    let targets: Vec<(Harmonic, u64)> = freqs.iter().map(|f| (f.scene, f.point)).collect();
    let mut records = from_rest(sys, settings, req, noise, freqs);
    let censuses = curve_census(sys, settings, seed, &targets, &records, Serves::Curve);
    fill_steady(&mut records, &censuses);
    CurveRun { records, censuses }
}

/// The run from the study's initial state at each frequency, with its noise: the records
/// without their census.
pub fn from_rest(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    noise: Option<&NoiseSettings>,
    freqs: Vec<CurveFrequency>,
) -> Vec<HarmonicRecord> {
    freqs
        .into_iter()
        .map(|fq| {
            let mut stream = fq.noise;
            match (noise, stream.as_mut()) {
                (Some(ns), Some(st)) => {
                    simulate_harmonic(sys, settings, req, &fq.scene, Some((ns, st)), &mut NoProbe)
                }
                _ => simulate_harmonic(sys, settings, req, &fq.scene, None, &mut NoProbe),
            }
        })
        .collect()
}

/// The census of every frequency of a curve (module doc), then the race for the life
/// amplitudes of its motions that are not periodic ([`super::race`]), each frequency's `(scene,
/// design point)` in `targets`, from the records of its runs from the initial state (start 0 goes on
/// from where each ended). The noise of those runs is a measurement noise that does not move
/// the system, so the census depends on the system, the scenes and the points only: the cases
/// of a design that differ only in their noise share it. `serves`: what the curve's values are
/// for (the ideal case's curve, or a perturbed case's peak alone: [`Serves`]).
pub fn curve_census(
    sys: &System,
    settings: &SolverSettings,
    seed: u64,
    targets: &[(Harmonic, u64)],
    records: &[HarmonicRecord],
    serves: Serves,
) -> Vec<Option<Census>> {
    let points = curve_points(sys, settings, seed, targets, records);
    let mut censuses = census_passes(&points);
    super::race::race(&race_points(&points, targets), &mut censuses, serves);
    censuses
}

/// Each frequency's forcing, census settings and start 0 for [`census_passes`] (`None` where
/// its run failed or the scene takes no census): the first half of [`curve_census`].
pub fn curve_points(
    sys: &System,
    settings: &SolverSettings,
    seed: u64,
    targets: &[(Harmonic, u64)],
    records: &[HarmonicRecord],
) -> Vec<Option<(Forcing, CensusSettings, Section)>> {
    targets
        .iter()
        .zip(records)
        .map(|(&(scene, point), rec)| {
            (rec.outcome == Outcome::Ok && scene.starts > 0).then(|| {
                let f = Forcing {
                    sys: *sys,
                    F0: scene.F0,
                    omega: rec.omega,
                    settings: *settings,
                };
                let c = CensusSettings {
                    starts: scene.starts,
                    max_periods: scene.n_trans_max,
                    handover: HANDOVER,
                    window: CENSUS_WINDOW,
                    seed,
                    point,
                    // The run from the initial state is start 0's transient so far.
                    spent0: if rec.converged { 0 } else { rec.n_trans },
                };
                // Start 0 goes on from where the run from the initial state ended (a section
                // time).
                let s0: Section = [rec.end.x, rec.end.v, rec.end.y - rec.end.x, rec.end.w];
                (f, c, s0)
            })
        })
        .collect()
}

/// What the race of [`super::race`] needs of each frequency: its forcing and scene.
pub fn race_points(
    points: &[Option<(Forcing, CensusSettings, Section)>],
    targets: &[(Harmonic, u64)],
) -> Vec<Option<(Forcing, Harmonic)>> {
    points
        .iter()
        .zip(targets)
        .map(|(p, (scene, _))| p.as_ref().map(|(f, _, _)| (f.clone(), *scene)))
        .collect()
}

/// Each record's census summary ([`steady_of`]) from its census.
pub fn fill_steady(records: &mut [HarmonicRecord], censuses: &[Option<Census>]) {
    for (rec, c) in records.iter_mut().zip(censuses) {
        if let Some(c) = c {
            rec.steady = steady_of(c);
        }
    }
}

/// The census of every point of a curve by the up and down passes (module doc): `points[i]` is
/// the forcing of point `i`, its census settings and its start 0 (`None`: no census there).
/// The passes go in increasing `omega`, then `F0` (a curve along the force), then input order.
pub fn census_passes(points: &[Option<(Forcing, CensusSettings, Section)>]) -> Vec<Option<Census>> {
    census_passes_with(points, |_, _| {})
}

/// [`census_passes`] with `also(i, census)` called at point `i` of the up pass after its own
/// starts, before the attractors of the point below are continued to it: what is known at that
/// point from elsewhere may join its census there (`examples/shared_census.rs` seeds a
/// perturbed case with the ideal case's attractors).
pub fn census_passes_with(
    points: &[Option<(Forcing, CensusSettings, Section)>],
    also: impl Fn(usize, &mut Census),
) -> Vec<Option<Census>> {
    let forcings = points;
    let newton = Newton::default();
    let mut order: Vec<usize> = (0..forcings.len())
        .filter(|&i| forcings[i].is_some())
        .collect();
    order.sort_by(|&a, &b| {
        let key = |i: usize| {
            forcings[i]
                .as_ref()
                .map_or((f64::NAN, f64::NAN), |x| (x.0.omega, x.0.F0))
        };
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0)
            .then(ka.1.total_cmp(&kb.1))
            .then(a.cmp(&b))
    });
    let mut out: Vec<Option<Census>> = vec![None; forcings.len()];
    let mut prev: Option<usize> = None;
    for &i in &order {
        let Some((f, c, s0)) = &forcings[i] else {
            continue;
        };
        let mut census = Census::default();
        census.run_starts(f, s0, c, &newton);
        also(i, &mut census);
        if let Some(j) = prev
            && let Some(below) = &out[j]
        {
            for a in below.attractors.clone() {
                census.seed(f, &a, Origin::Up, c, &newton);
            }
        }
        out[i] = Some(census);
        prev = Some(i);
    }
    for w in order.windows(2).rev() {
        let (i, above) = (w[0], w[1]);
        let (Some((f, c, _)), Some(from)) = (&forcings[i], out[above].clone()) else {
            continue;
        };
        if let Some(census) = out[i].as_mut() {
            for a in &from.attractors {
                census.seed(f, a, Origin::Down, c, &newton);
            }
        }
    }
    out
}
