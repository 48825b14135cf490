//! The ideal case of a harmonic study between the grid's designs: what a jump's bisection asks
//! for at each probe (docs/reduce.md, "Jumps").
//!
//! A probe's design quantity is the curve's peak at that design: the largest design amplitude
//! over the band, and the peak reduction against the linear system's peak over the band. With
//! the attractors the sweep stored, no census runs: at each frequency, the attractors of the
//! grid designs that bracket the probe (the corners of the grid cell it lies in; two for a
//! probe along one axis) that can carry the peak (their design amplitude within [`NEAR_PEAK`]
//! of their design's peak) are *continued* to the probe's design:
//!
//! * an impacting periodic orbit by Newton on `P^p` from its stored section (kept when it
//!   converges to a stable orbit; otherwise the state it leads to is settled as a start is);
//! * the non-impacting family in closed form, where it exists at the probe (where it does not,
//!   its state is settled as below);
//! * a chaotic or quasi-periodic motion (it ran its whole budget at its grid design) by a run
//!   to its first check ([`first_check`]): where it lands on an orbit, that orbit's amplitude;
//!   while it still wanders, the same motion continued, whose amplitude over the design life
//!   (the quantity the grid's peaks are made of; a window maximum is lower) is not measured
//!   here: where the bracketing designs' life amplitudes at that frequency reach above the
//!   probe's exact peak ([`HarmonicIdeal::wandering_level`]), the probe's peak is an estimate and
//!   the probe returns [`UNRESOLVED`] (the bisection stops there);
//! * a motion the census could not tell (`not settled`) by a run from its stored state
//!   ([`settle`]: the census's rule for one start, window and all).
//!
//! Only frequencies where a corner's design quantity reaches [`NEAR_PEAK`] of that corner's
//! peak are probed: the peak of a design between two grid designs sits where theirs are high.
//! The linear system's peak over the band is closed form at every frequency. A dataset without
//! stored attractors, or a study with `design_peak = "from_rest"`, runs the whole curve at the
//! probe instead (the run from the initial state at every frequency, and the census when the
//! design quantity needs it), and so does a study of several units (each frequency's census of
//! several units, [`crate::orbits::several`], then the race for the design lives along the
//! probe's curve for its peak: the continuation covers one unit). Probes are deterministic: the
//! same probe gives the same bits.

use rayon::prelude::*;

use super::analysis::{Plan, Shard, line_key};
use super::curve::{Curve, CurvePoint};
use super::design::design_study;
use crate::orbits::attractors::{AttractorRow, SteadyKind};
use crate::orbits::census::{CensusSettings, Landing, Settled, first_check, settle};
use crate::orbits::map::Forcing;
use crate::orbits::race::Serves;
use crate::orbits::response::orbit_from_section;
use crate::orbits::several::{UnitsRun, census_run_units, race_runs};
use crate::orbits::shoot::{Newton, non_impacting};
use crate::orbits::{CENSUS_WINDOW, HANDOVER, forced_run};
use crate::reduce::common::jumps::{IdealCase, UNRESOLVED};
use crate::sim::harmonic::DesignPeak;
use crate::sim::{Harmonic, HarmonicRecord, NoProbe, Outcome};
use crate::study::{CensusKind, Study};

/// The share of a corner's peak above which a frequency is probed.
pub const NEAR_PEAK: f64 = 0.7;

/// The ideal case of a harmonic study at any design (jump location): `[peak amplitude, peak
/// reduction]`; `None` when a run does not end `ok` or the design is not valid (out of range,
/// or resonance without damping). A design probed twice (the bisections of the peak amplitude
/// and of PR along one line share their first midpoints) is computed once.
pub struct HarmonicIdeal<'a> {
    study: &'a Study,
    /// The design axes' keys and values, in design-grid order.
    keys: Vec<String>,
    grid: Vec<Vec<f64>>,
    /// The ideal curves, by design, with their stored attractors.
    curves: &'a [Curve],
    /// The census's design point for probes between the grid's points (they are no grid
    /// point; one fixed identity keeps them deterministic).
    probe_point: u64,
    /// Designs computed so far, by the bits of their axis values (with what earlier shards of
    /// the analysis computed).
    seen: std::sync::Mutex<std::collections::HashMap<Vec<u64>, Option<[f64; 2]>>>,
    /// The probes computed here, in the order they were asked for.
    computed: std::sync::Mutex<Vec<Vec<u64>>>,
    /// As one shard of the analysis: only the probes of its lines.
    shard: Option<Shard>,
}

impl<'a> HarmonicIdeal<'a> {
    /// `curves`: the study's ideal curves in design order ([`super::HarmonicSummary`]);
    /// `plan`: what earlier shards computed, and this run's shard.
    pub fn new(study: &'a Study, curves: &'a [Curve], plan: &Plan) -> Self {
        let design = design_study(study);
        HarmonicIdeal {
            study,
            keys: design.axes.iter().map(|a| a.key.clone()).collect(),
            grid: design.axes.iter().map(|a| a.values.clone()).collect(),
            curves,
            probe_point: u64::MAX,
            seen: std::sync::Mutex::new(plan.prior.probes.clone()),
            computed: Default::default(),
            shard: plan.shard,
        }
    }

    /// The probes computed here (not taken from earlier shards), sorted by their values' bits:
    /// what a shard of the analysis stores.
    pub fn computed(&self) -> Vec<(Vec<u64>, Option<[f64; 2]>)> {
        let keys = self.computed.lock().map(|k| k.clone()).unwrap_or_default();
        let seen = self.seen.lock().map(|m| m.clone()).unwrap_or_default();
        let mut out: Vec<(Vec<u64>, Option<[f64; 2]>)> = keys
            .into_iter()
            .filter_map(|k| seen.get(&k).map(|v| (k, *v)))
            .collect();
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }

    /// The system and harmonic scene of the design with axis values `values`; `None` when
    /// invalid.
    fn design(&self, values: &[f64]) -> Option<(crate::model::System, Harmonic)> {
        let mut sys = self.study.system;
        let mut scene = self.study.scene.clone();
        for (key, v) in self.keys.iter().zip(values) {
            if !sys.set(key, *v) {
                scene.set(key, *v);
            }
        }
        sys.validate().ok()?;
        Some((sys, *scene.harmonic()?))
    }

    /// The band's scenes: `h` at each swept frequency (one, when the study sweeps none).
    fn band(&self, sys: &crate::model::System, h: Harmonic) -> Option<Vec<Harmonic>> {
        let out: Vec<Harmonic> = match self.study.frequency_axis() {
            Some(a) => a
                .values
                .iter()
                .map(|&v| {
                    let mut x = h;
                    x.set(&a.key, v);
                    x
                })
                .collect(),
            None => vec![h],
        };
        out.iter().all(|x| x.validate(sys).is_ok()).then_some(out)
    }

    /// The grid designs at the corners of the grid cell holding `values` (a value on a grid
    /// line contributes that line only), as design indices.
    fn corners(&self, values: &[f64]) -> Vec<u64> {
        let mut out = vec![0u64];
        for (axis, &v) in self.grid.iter().zip(values) {
            let n = axis.len() as u64;
            let i = axis.iter().position(|&g| g >= v).unwrap_or(axis.len() - 1);
            let idx: Vec<u64> = if axis[i] == v || i == 0 {
                vec![i as u64]
            } else {
                vec![i as u64 - 1, i as u64]
            };
            out = out
                .iter()
                .flat_map(|&d| idx.iter().map(move |&j| d * n + j))
                .collect();
        }
        out
    }

    /// The probe's `[peak amplitude, peak reduction]` from its corners' stored attractors.
    fn continued(&self, values: &[f64], corners: &[&Curve]) -> Option<[f64; 2]> {
        let (sys, h) = self.design(values)?;
        let band = self.band(&sys, h)?;
        let newton = Newton::default();
        let (mut peak, mut linear, mut unresolved) = (f64::NAN, f64::NAN, f64::NAN);
        for (i, scene) in band.iter().enumerate() {
            let f = Forcing {
                sys,
                F0: scene.F0,
                omega: scene.omega(&sys),
                settings: self.study.solver,
            };
            linear = linear.max(f.amplitude_linear());
            let near = corners.iter().any(|c| {
                let (p, _) = c.peak();
                c.points
                    .get(i)
                    .is_some_and(|q| q.design >= NEAR_PEAK * p || !p.is_finite())
            });
            if !near {
                continue;
            }
            let c = CensusSettings {
                starts: 1,
                max_periods: scene.n_trans_max,
                handover: HANDOVER,
                window: CENSUS_WINDOW,
                seed: self.study.seed,
                point: self.probe_point,
                spent0: 0,
            };
            let mut wanders = false;
            for c0 in corners {
                let point = c0.design * band.len() as u64 + i as u64;
                let (p, _) = c0.peak();
                for a in c0.attractors.iter().flatten() {
                    if a.run.point == point && (a.amplitude >= NEAR_PEAK * p || !p.is_finite()) {
                        match continue_to(&f, a, &c, &newton)? {
                            Continued::Exact(amp) => peak = peak.max(amp),
                            Continued::Wanders => wanders = true,
                        }
                    }
                }
            }
            if wanders {
                unresolved = unresolved.max(Self::wandering_level(corners, i));
            }
        }
        // A chaotic motion that may carry the peak: the peak is an estimate here.
        if unresolved.is_finite() && (peak.is_nan() || peak < unresolved) {
            return Some([UNRESOLVED; 2]);
        }
        Some([peak, 1.0 - peak / linear])
    }

    /// The largest life amplitude of a motion that is not periodic at frequency `i` over the
    /// bracketing grid designs: what a chaotic motion that still wanders at the probe may
    /// reach there (its own amplitude over the design life is not measured at the probe: that
    /// costs the race's 8,000 periods or more per motion).
    fn wandering_level(corners: &[&Curve], i: usize) -> f64 {
        corners
            .iter()
            .flat_map(|c| c.attractors_at(i))
            .filter(|a| !matches!(a.kind, SteadyKind::Periodic | SteadyKind::Neutral))
            .map(|a| a.amplitude)
            .fold(f64::NAN, f64::max)
    }

    /// The probe's whole curve run afresh (no stored attractors, or `from_rest`).
    fn simulated(&self, values: &[f64]) -> Option<[f64; 2]> {
        let s = self.study;
        let (sys, h) = self.design(values)?;
        let scenes: Vec<Harmonic> = self
            .band(&sys, h)?
            .into_iter()
            .map(|mut scene| {
                if scene.design_peak == DesignPeak::FromRest {
                    scene.starts = 0;
                }
                scene
            })
            .collect();
        let records: Vec<HarmonicRecord> = match s.census_kind() {
            // Several units: each frequency's own census of several units, then the race along
            // the probe's curve for its peak, as the sweep's perturbed cases.
            CensusKind::Units => {
                let mut runs: Vec<UnitsRun> = scenes
                    .par_iter()
                    .map(|scene| {
                        census_run_units(
                            &sys,
                            &s.solver,
                            &s.request,
                            scene,
                            None,
                            &mut NoProbe,
                            s.seed,
                            self.probe_point,
                        )
                    })
                    .collect();
                race_runs(&mut runs, &scenes, Serves::Peak);
                runs.into_iter().map(|r| r.record).collect()
            }
            CensusKind::None | CensusKind::OneUnit => scenes
                .iter()
                .map(|scene| {
                    forced_run(
                        &sys,
                        &s.solver,
                        &s.request,
                        scene,
                        None,
                        &mut NoProbe,
                        s.seed,
                        self.probe_point,
                    )
                })
                .collect(),
        };
        let (mut peak, mut linear) = (f64::NAN, f64::NAN);
        for rec in &records {
            if rec.outcome != Outcome::Ok {
                return None;
            }
            peak = peak.max(CurvePoint::of(rec, h.design_peak).design);
            linear = linear.max(rec.amplitude_linear);
        }
        Some([peak, 1.0 - peak / linear])
    }

    fn compute(&self, values: &[f64]) -> Option<[f64; 2]> {
        let (_, h) = self.design(values)?;
        let corners: Option<Vec<&Curve>> = self
            .corners(values)
            .into_iter()
            .map(|d| {
                let c = self.curves.binary_search_by_key(&d, |c| c.design).ok()?;
                let c = &self.curves[c];
                c.attractors.is_some().then_some(c)
            })
            .collect();
        match corners {
            // A grid design itself (a bisection's midpoint can fall on one): its own curve's
            // peak, from its census and life estimates, as the grid's quantities are.
            Some(cs)
                if h.design_peak == DesignPeak::Worst && cs.len() == 1 && self.on_grid(values) =>
            {
                let (peak, _) = cs[0].peak();
                let (linear, _) = cs[0].linear_peak();
                Some([peak, 1.0 - peak / linear])
            }
            // The continuation of stored attractors covers one unit: a study of several units
            // runs the probe's curve with its census.
            Some(cs)
                if h.design_peak == DesignPeak::Worst
                    && !cs.is_empty()
                    && self.study.census_kind() != CensusKind::Units =>
            {
                self.continued(values, &cs)
            }
            _ => self.simulated(values),
        }
    }

    /// Whether every axis value is one of the grid's.
    fn on_grid(&self, values: &[f64]) -> bool {
        self.grid
            .iter()
            .zip(values)
            .all(|(axis, v)| axis.contains(v))
    }
}

/// What a stored attractor continued to a probe is: an exact amplitude (an orbit, or a motion
/// measured by the census's rule), or a chaotic motion that still wanders.
enum Continued {
    Exact(f64),
    Wanders,
}

/// What stored attractor `a` continues to at `f` (module doc); `None` when the continuation's
/// run does not end `ok`.
fn continue_to(
    f: &Forcing,
    a: &AttractorRow,
    c: &CensusSettings,
    newton: &Newton,
) -> Option<Continued> {
    let exact = |v: Option<f64>| v.map(Continued::Exact);
    match a.kind {
        // Where the walls' motion reaches every placement, the family is gone: its state is
        // settled as a start is.
        SteadyKind::Neutral => match non_impacting(f, a.section[0] + a.section[2]) {
            Some(o) => Some(Continued::Exact(o.amplitude)),
            None => exact(settled(f, a, c, newton)),
        },
        SteadyKind::Periodic => match orbit_from_section(f, &a.section, a.period) {
            Some(o) => Some(Continued::Exact(o.amplitude)),
            None => exact(settled(f, a, c, newton)),
        },
        // A chaotic or quasi-periodic attractor ran its whole budget at its grid design; at the
        // probe it runs to its first check only: where it lands is exact, and while it wanders
        // it is that motion continued, not measured here ([`HarmonicIdeal::wandering_level`]).
        SteadyKind::Chaotic | SteadyKind::QuasiPeriodic => {
            match first_check(f, &a.section, c, newton) {
                Some(st) => exact(landed(st)),
                None => Some(Continued::Wanders),
            }
        }
        SteadyKind::NotSettled => exact(settled(f, a, c, newton)),
    }
}

fn landed(st: Settled) -> Option<f64> {
    match st.landing {
        Landing::Orbit(o) => Some(o.amplitude),
        Landing::NonPeriodic { amplitude, .. } => amplitude.is_finite().then_some(amplitude),
    }
}

fn settled(f: &Forcing, a: &AttractorRow, c: &CensusSettings, newton: &Newton) -> Option<f64> {
    landed(settle(f, &a.section, c, newton))
}

impl IdealCase for HarmonicIdeal<'_> {
    /// A grid design whose peak is carried by a motion that is not periodic: the peak is its
    /// amplitude over the design life, an estimate with a 90 % interval (`life_lo`, `life_hi`;
    /// a motion without a life estimate has only its window maximum, a lower bound). The peak
    /// reduction's interval follows, `1 - [hi, lo] / linear peak`.
    fn interval(&self, values: &[f64]) -> Option<[[f64; 2]; 2]> {
        let &[d] = self.corners(values).as_slice() else {
            return None;
        };
        let c = self.curves.binary_search_by_key(&d, |c| c.design).ok()?;
        let curve = &self.curves[c];
        let a = curve.peak_attractor()?;
        if matches!(a.kind, SteadyKind::Periodic | SteadyKind::Neutral) {
            return None;
        }
        let (lo, hi) = if a.life_lo.is_finite() && a.life_hi.is_finite() {
            (a.life_lo.min(a.amplitude), a.life_hi.max(a.amplitude))
        } else {
            (a.amplitude, f64::INFINITY)
        };
        let (linear, _) = curve.linear_peak();
        Some([[lo, hi], [1.0 - hi / linear, 1.0 - lo / linear]])
    }

    fn at(&self, values: &[f64]) -> Option<[f64; 2]> {
        let key: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
        if let Some(v) = self.seen.lock().ok().and_then(|m| m.get(&key).copied()) {
            return v;
        }
        if let Some(s) = self.shard
            && !s.owns_line(line_key(&self.grid, values))
        {
            // Another shard's line: not computed here (this shard writes no jumps).
            return None;
        }
        let v = self.compute(values);
        if let Ok(mut m) = self.seen.lock() {
            m.insert(key.clone(), v);
        }
        if let Ok(mut c) = self.computed.lock() {
            c.push(key);
        }
        v
    }
}
