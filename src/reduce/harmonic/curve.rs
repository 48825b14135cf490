//! A design's frequency-response curve (its ideal case at every swept frequency, [`Curve`]): the
//! design peak and where it is, the linear system's peak, the band where the damper helps, the
//! steady states the census found at each frequency.

use crate::orbits::attractors::AttractorRow;
use crate::sim::harmonic::DesignPeak;
use crate::sim::{HarmonicRecord, Outcome};

/// One run of a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// Frequency ratio and frequency (rad/s).
    pub r: f64,
    pub omega: f64,
    pub outcome: Outcome,
    /// `amplitude`, `amplitude_linear` (m), `impacts_per_period`, `period`, `converged`, as
    /// stored (from the study's initial state); `attenuation` is the design quantity's,
    /// `design / amplitude_linear` (the stored from-rest value with `design_peak = "from_rest"`
    /// or without census), so the band where the damper helps is judged on the same steady
    /// state as the peak.
    pub amplitude: f64,
    pub linear: f64,
    pub attenuation: f64,
    pub impacts_per_period: f64,
    pub period: u32,
    pub converged: bool,
    /// The design quantity at this frequency (m): the worst steady amplitude of the census
    /// (`design_peak = "worst"`), or `amplitude` (`"from_rest"`, or a run without census).
    pub design: f64,
    /// The period of the steady state that carries `design` (0: not periodic), its impacts
    /// per forcing period and its basin share (NaN without census): the share of the census's
    /// starts that reached it, its mirror image's included once the curve holds its attractors
    /// ([`Curve::count_mirror_images`]).
    pub design_period: u32,
    pub design_impacts: f64,
    pub design_share: f64,
    /// Distinct attractors the census found (0 without census).
    pub attractors: u32,
}

impl CurvePoint {
    /// The point of a stored run; `peak` says which steady state is the design quantity.
    pub fn of(rec: &HarmonicRecord, peak: DesignPeak) -> CurvePoint {
        let st = &rec.steady;
        let worst = peak == DesignPeak::Worst && st.starts > 0;
        CurvePoint {
            design: if worst {
                st.amplitude_worst
            } else {
                rec.amplitude
            },
            design_period: if worst { st.worst_period } else { rec.period },
            design_impacts: if worst {
                st.worst_impacts_per_period
            } else {
                rec.impacts_per_period
            },
            design_share: if worst {
                st.worst_basin_share
            } else {
                f64::NAN
            },
            attractors: st.attractors,
            r: rec.r,
            omega: rec.omega,
            outcome: rec.outcome,
            amplitude: rec.amplitude,
            linear: rec.amplitude_linear,
            // The design quantity's attenuation: with the census, the worst steady state's.
            attenuation: if worst {
                st.amplitude_worst / rec.amplitude_linear
            } else {
                rec.attenuation
            },
            impacts_per_period: rec.impacts_per_period,
            period: rec.period,
            converged: rec.converged,
        }
    }

    fn ok(&self) -> bool {
        self.outcome == Outcome::Ok
    }

    /// The damper helps at this frequency: `attenuation < 1 - HELP_TOL` (an ok run).
    pub fn helps(&self) -> bool {
        self.ok() && self.attenuation < 1.0 - HELP_TOL
    }
}

/// The damper helps where `attenuation < 1 - HELP_TOL`: a motion that never reaches the walls
/// has `attenuation = 1` only to the simulator's accuracy (1e-9 relative, tests/forced.rs), and
/// must not count as helping.
pub const HELP_TOL: f64 = 1e-6;

/// The band around the linear system's resonance where the damper helps (`attenuation < 1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HelpBand {
    /// Its limits in `r`: where the attenuation crosses 1 (linear between the swept
    /// frequencies), or the end of the swept band when it still helps there (`*_edge`).
    pub from: f64,
    pub to: f64,
    pub from_edge: bool,
    pub to_edge: bool,
}

/// The frequency-response curve of one design's ideal case, in frequency order.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// The design (a point of the design grid).
    pub design: u64,
    pub points: Vec<CurvePoint>,
    /// The ideal case's system (with its initial state) and force amplitude (N): what the
    /// steady-state analysis of the curve starts from ([`super::steady`]).
    pub system: crate::model::System,
    pub f0: f64,
    /// The ideal case's attractors at every frequency, as the sweep stored them (the
    /// `attractors` table); `None` for a dataset written before the sweep stored them.
    pub attractors: Option<Vec<AttractorRow>>,
}

/// Whether two attractors at one frequency are a periodic orbit and its mirror image. The
/// cavity is symmetric, so `x -> -x` half a forcing period later maps a motion onto another; an
/// asymmetric orbit and its image are two attractors with the same period, amplitude and
/// multipliers (equal here to 1e-9 relative), and a jump between them changes nothing the
/// design quantity measures.
pub fn mirror_images(a: &AttractorRow, b: &AttractorRow) -> bool {
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
    a.kind.periodic()
        && b.kind.periodic()
        && a.period == b.period
        && same(a.amplitude, b.amplitude)
        && (same(a.multiplier_max, b.multiplier_max)
            || (a.multiplier_max.is_nan() && b.multiplier_max.is_nan()))
}

impl Curve {
    /// The design peak: the largest design quantity ([`CurvePoint::design`]) over the band and
    /// the `r` where it is; NaN when a run of the curve did not end `ok` (the peak could be
    /// there).
    pub fn peak(&self) -> (f64, f64) {
        self.max_of(|p| p.design)
    }

    /// The largest amplitude reached from the study's initial state over the band, and its `r`.
    pub fn peak_from_rest(&self) -> (f64, f64) {
        self.max_of(|p| p.amplitude)
    }

    /// The point of the band that carries the design peak.
    pub fn peak_point(&self) -> Option<&CurvePoint> {
        let (_, r) = self.peak();
        self.points.iter().find(|p| p.r == r)
    }

    /// Whether the steady state carrying the peak is periodic (period 1 to 8). When it is not
    /// (chaotic, quasi-periodic, or a transient that did not converge), the peak is the largest
    /// excursion of a wandering motion over its window: a lower bound of what the motion can
    /// reach, and indicative only. `false` when the curve has no peak.
    pub fn peak_periodic(&self) -> bool {
        self.peak_point().is_some_and(|p| p.design_period >= 1)
    }

    /// The stored attractor that carries the design peak (ideal case): at the peak's frequency,
    /// the attractor whose design amplitude is the peak. `None` without stored attractors.
    pub fn peak_attractor(&self) -> Option<&AttractorRow> {
        let (_, r) = self.peak();
        self.design_attractor(self.points.iter().position(|p| p.r == r)?)
    }

    /// The peak as an interval `[lo, hi]` (m): one point when a periodic orbit carries it, the
    /// 90 % interval of a life estimate (its lower end at most the amplitude), `[amplitude,
    /// inf)` for a motion the race did not estimate; `None` without a stored attractor at the
    /// peak.
    pub fn peak_interval(&self) -> Option<(f64, f64)> {
        let a = self.peak_attractor()?;
        Some(if a.kind.periodic() {
            (a.amplitude, a.amplitude)
        } else if a.life_lo.is_finite() {
            (a.life_lo.min(a.amplitude), a.life_hi)
        } else {
            (a.amplitude, f64::INFINITY)
        })
    }

    /// Takes in a direct measurement of one of its motions ([`super::verify`]): the stored
    /// attractor's design amplitude and life columns become the direct measurement's, and the
    /// point's design quantity (and its attenuation) the largest of its attractors again.
    pub fn take_verified(&mut self, v: &super::verify::Verified) {
        let Some(i) = self.points.iter().position(|p| p.r == v.motion.r) else {
            return;
        };
        let Some((d, e)) = v.direct.and_then(|d| Some((d, d.estimate?))) else {
            return;
        };
        let at = self.design * self.points.len() as u64 + i as u64;
        let Some(rows) = self.attractors.as_mut() else {
            return;
        };
        if let Some(a) = rows
            .iter_mut()
            .find(|a| a.run.point == at && !a.kind.periodic() && a.amplitude == v.motion.amplitude)
        {
            a.amplitude = v.value();
            a.life_amplitude = e.amplitude;
            a.life_lo = e.lo;
            a.life_hi = e.hi;
            a.life_capped = false;
            a.tail_shape = e.xi;
            a.tail_end = e.end_point;
            a.exceedances = e.exceedances;
            a.measured_periods = d.measured;
        }
        let top = rows
            .iter()
            .filter(|a| a.run.point == at)
            .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
            .map(|a| (a.amplitude, a.period, a.impacts_per_period, a.basin_share));
        if let (Some((amp, period, impacts, share)), Some(p)) = (top, self.points.get_mut(i)) {
            p.design = amp;
            p.attenuation = amp / p.linear;
            p.design_period = period;
            p.design_impacts = impacts;
            p.design_share = share;
        }
        if let Some(share) = self.design_share_at(i) {
            self.points[i].design_share = share;
        }
    }

    /// The stored attractor that carries the design quantity of the curve's `i`-th point: the
    /// attractor at that frequency whose design amplitude is [`CurvePoint::design`]. `None`
    /// without stored attractors.
    pub fn design_attractor(&self, i: usize) -> Option<&AttractorRow> {
        let design = self.points.get(i)?.design;
        self.attractors_at(i).find(|a| a.amplitude == design)
    }

    /// The stored attractors (ideal case) at the curve's `i`-th point; none without stored
    /// attractors.
    pub fn attractors_at(&self, i: usize) -> impl Iterator<Item = &AttractorRow> {
        let point = self.design * self.points.len() as u64 + i as u64;
        self.attractors
            .iter()
            .flatten()
            .filter(move |a| a.run.point == point)
    }

    /// The steady states at the curve's `i`-th point that differ in what the design sees: the
    /// stored attractors, a periodic orbit and its mirror image counted once
    /// ([`mirror_images`]).
    pub fn distinct_states_at(&self, i: usize) -> usize {
        let mut kept: Vec<&AttractorRow> = Vec::new();
        for a in self.attractors_at(i) {
            if !kept.iter().any(|k| mirror_images(k, a)) {
                kept.push(a);
            }
        }
        kept.len()
    }

    /// The basin share of the steady state carrying the design quantity at the curve's `i`-th
    /// point: its attractor's share plus its mirror image's ([`mirror_images`]), which the
    /// census counts as two attractors of its own. `None` without a stored attractor there.
    pub fn design_share_at(&self, i: usize) -> Option<f64> {
        let carrier = self.design_attractor(i)?;
        Some(
            self.attractors_at(i)
                .filter(|a| std::ptr::eq(*a, carrier) || mirror_images(a, carrier))
                .map(|a| a.basin_share)
                .sum(),
        )
    }

    /// Counts each point's design share over the steady state, not the attractor: a periodic
    /// orbit carrying the design quantity and its mirror image are reached from their starts
    /// together (the run's stored `worst_basin_share` is one attractor's). Points without a
    /// stored attractor keep the run's, and points without a share (`design_peak =
    /// "from_rest"`, whose design quantity is the run's own) keep none.
    pub fn count_mirror_images(&mut self) {
        for i in 0..self.points.len() {
            if !self.points[i].design_share.is_finite() {
                continue;
            }
            if let Some(share) = self.design_share_at(i) {
                self.points[i].design_share = share;
            }
        }
    }

    /// The bands of `r` (first and last grid frequency of each run of neighbours) where the
    /// census found two or more steady states that differ in what the design sees
    /// ([`Curve::distinct_states_at`]): a jump between them is possible there. Empty without
    /// stored attractors.
    pub fn coexistence_bands(&self) -> Vec<(f64, f64)> {
        let mut bands: Vec<(f64, f64)> = Vec::new();
        let mut open = false;
        for (i, p) in self.points.iter().enumerate() {
            let states = self.distinct_states_at(i);
            match (states >= 2, open, bands.last_mut()) {
                (true, true, Some(b)) => b.1 = p.r,
                (true, _, _) => bands.push((p.r, p.r)),
                _ => {}
            }
            open = states >= 2;
        }
        bands
    }

    /// The linear system's steady amplitude (m) at frequency ratio `r`, in closed form: the
    /// main mass without the inner one, `F0 / K / sqrt((1 - r^2)^2 + (2 zeta r)^2)`.
    pub fn linear_at(&self, r: f64) -> f64 {
        self.system.linear_amplitude(self.f0, r)
    }

    /// `(r, amplitude)` of the linear system on `n + 1` evenly spaced ratios from `r0` to `r1`:
    /// a smooth line between the swept frequencies, for the charts.
    pub fn linear_line(&self, r0: f64, r1: f64, n: usize) -> Vec<(f64, f64)> {
        (0..=n)
            .map(|i| {
                let r = r0 + (r1 - r0) * i as f64 / n.max(1) as f64;
                (r, self.linear_at(r))
            })
            .collect()
    }

    /// The linear system's largest amplitude over the band and its `r`.
    pub fn linear_peak(&self) -> (f64, f64) {
        let mut best = (f64::NAN, f64::NAN);
        for p in &self.points {
            if best.0.is_nan() || p.linear > best.0 {
                best = (p.linear, p.r);
            }
        }
        best
    }

    /// The linear system's largest amplitude over the whole band `[r_first, r_last]`, between
    /// the swept frequencies too, and its `r`: the amplitude is largest at
    /// `r = sqrt(1 - 2 zeta^2)` (0 when `2 zeta^2 >= 1`) and falls away from it, so over the band
    /// at that `r` clamped to the band. [`Curve::linear_peak`] is the largest at the swept
    /// frequencies: below this one when the band's step is coarse against the resonance's width
    /// (`2 zeta` in `r`).
    pub fn linear_peak_between(&self) -> (f64, f64) {
        let (Some(first), Some(last)) = (self.points.first(), self.points.last()) else {
            return (f64::NAN, f64::NAN);
        };
        let (lo, hi) = (first.r.min(last.r), first.r.max(last.r));
        let z = self.system.zeta();
        let r = (1.0 - 2.0 * z * z).max(0.0).sqrt().clamp(lo, hi);
        (self.linear_at(r), r)
    }

    fn max_of(&self, f: impl Fn(&CurvePoint) -> f64) -> (f64, f64) {
        if self.points.iter().any(|p| !p.ok()) {
            return (f64::NAN, f64::NAN);
        }
        let mut best = (f64::NAN, f64::NAN);
        for p in &self.points {
            if best.0.is_nan() || f(p) > best.0 {
                best = (f(p), p.r);
            }
        }
        best
    }

    /// The band where the damper helps: the swept frequencies around the linear system's peak
    /// where it helps ([`CurvePoint::helps`]), its limits interpolated where the attenuation
    /// crosses 1. `None` when the damper does not help at the linear peak.
    pub fn help_band(&self) -> Option<HelpBand> {
        let pts = &self.points;
        let helps = |i: usize| pts[i].helps();
        let (_, r_lin) = self.linear_peak();
        let k = pts.iter().position(|p| p.r == r_lin)?;
        if !helps(k) {
            return None;
        }
        let (mut lo, mut hi) = (k, k);
        while lo > 0 && helps(lo - 1) {
            lo -= 1;
        }
        while hi + 1 < pts.len() && helps(hi + 1) {
            hi += 1;
        }
        // Where the attenuation crosses 1 between an outside and an inside point.
        let cross = |out: usize, inside: usize| {
            let (a, b) = (&pts[out], &pts[inside]);
            if a.ok() && a.attenuation.is_finite() && a.attenuation != b.attenuation {
                let t = (a.attenuation - 1.0) / (a.attenuation - b.attenuation);
                a.r + t.clamp(0.0, 1.0) * (b.r - a.r)
            } else {
                b.r
            }
        };
        Some(HelpBand {
            from: if lo > 0 { cross(lo - 1, lo) } else { pts[0].r },
            to: if hi + 1 < pts.len() {
                cross(hi + 1, hi)
            } else {
                pts[hi].r
            },
            from_edge: lo == 0,
            to_edge: hi + 1 == pts.len(),
        })
    }

    /// The share of the band's frequencies where the damper helps ([`CurvePoint::helps`]).
    pub fn help_share(&self) -> f64 {
        self.share(CurvePoint::helps)
    }

    /// The share of the band's frequencies whose steady state is periodic (`period >= 1`).
    pub fn periodic_share(&self) -> f64 {
        self.share(|p| p.ok() && p.period >= 1)
    }

    fn share(&self, f: impl Fn(&CurvePoint) -> bool) -> f64 {
        if self.points.is_empty() {
            return f64::NAN;
        }
        self.points.iter().filter(|p| f(p)).count() as f64 / self.points.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(r: f64, amplitude: f64, linear: f64) -> CurvePoint {
        CurvePoint {
            r,
            omega: r * 63.0,
            outcome: Outcome::Ok,
            amplitude,
            linear,
            attenuation: amplitude / linear,
            impacts_per_period: 2.0,
            period: 1,
            converged: true,
            design: amplitude,
            design_period: 1,
            design_impacts: 2.0,
            design_share: f64::NAN,
            attractors: 0,
        }
    }

    #[test]
    fn the_band_where_the_damper_helps_is_around_the_linear_peak() {
        // Attenuation 2, 1.5, 0.5, 0.25 (linear peak), 0.5, 3: crosses 1 at r = 0.85 and 1.1.
        let c = Curve {
            system: crate::model::System::TABLE_I,
            f0: 1.0,
            attractors: None,
            design: 0,
            points: vec![
                pt(0.7, 2.0, 1.0),
                pt(0.8, 3.0, 2.0),
                pt(0.9, 2.0, 4.0),
                pt(1.0, 2.0, 8.0),
                pt(1.05, 2.0, 4.0),
                pt(1.15, 6.0, 2.0),
            ],
        };
        assert_eq!(c.peak(), (6.0, 1.15));
        assert_eq!(c.linear_peak(), (8.0, 1.0));
        let b = c.help_band().unwrap();
        assert!((b.from - 0.85).abs() < 1e-12, "{b:?}");
        assert!((b.to - 1.07).abs() < 1e-12, "{b:?}");
        assert!(!b.from_edge && !b.to_edge);
        assert_eq!(c.help_share(), 0.5);
        // It helps to the end of the band: the limit is the band's end.
        let c = Curve {
            system: crate::model::System::TABLE_I,
            f0: 1.0,
            attractors: None,
            design: 0,
            points: vec![pt(0.9, 0.5, 4.0), pt(1.0, 1.0, 8.0), pt(1.1, 1.0, 2.0)],
        };
        let b = c.help_band().unwrap();
        assert_eq!(
            (b.from, b.to, b.from_edge, b.to_edge),
            (0.9, 1.1, true, true)
        );
        // It does not help at the linear peak: no band.
        let c = Curve {
            system: crate::model::System::TABLE_I,
            f0: 1.0,
            attractors: None,
            design: 0,
            points: vec![pt(0.9, 0.5, 4.0), pt(1.0, 9.0, 8.0)],
        };
        assert_eq!(c.help_band(), None);
        // A failed run: the peak is unknown.
        let mut c = c;
        c.points[0].outcome = Outcome::StepCap;
        assert!(c.peak().0.is_nan());
        assert_eq!(c.periodic_share(), 0.5);
    }

    #[test]
    fn a_peak_carried_by_an_orbit_and_its_mirror_image_counts_both_basins() {
        use crate::orbits::attractors::SteadyKind::{Chaotic, Periodic};
        // At r = 1.0 an asymmetric orbit (25 % of the starts) and its mirror image (62.5 %, the
        // same amplitude and multiplier to rounding) carry the peak; a lower orbit takes the
        // rest. At r = 1.1 the peak's orbit has a different multiplier than its neighbour: two
        // steady states, its own share alone.
        let mut points = vec![pt(0.9, 1.0, 4.0), pt(1.0, 3.0, 8.0), pt(1.1, 2.0, 2.0)];
        for p in &mut points {
            p.design_share = 0.25; // the run's stored share: one attractor's
        }
        let attractor = crate::reduce::testing::attractor_row;
        let rows = vec![
            attractor(1, Periodic, 3.0, 0.5, 0.25),
            attractor(1, Periodic, 3.0 * (1.0 + 1e-12), 0.5 * (1.0 - 1e-12), 0.625),
            attractor(1, Periodic, 1.0, 0.5, 0.125),
            attractor(2, Periodic, 2.0, 0.5, 0.25),
            attractor(2, Periodic, 2.0, 0.7, 0.75),
            attractor(0, Chaotic, 1.0, f64::NAN, 0.25),
            attractor(0, Chaotic, 1.0, f64::NAN, 0.75),
        ];
        let mut c = Curve {
            system: crate::model::System::TABLE_I,
            f0: 1.0,
            attractors: Some(rows),
            design: 0,
            points,
        };
        assert_eq!(c.distinct_states_at(1), 2);
        assert_eq!(c.distinct_states_at(2), 2);
        // Motions that are not periodic are never one another's image.
        assert_eq!(c.distinct_states_at(0), 2);
        c.count_mirror_images();
        assert_eq!(c.peak_point().unwrap().design_share, 0.875);
        assert_eq!(c.points[2].design_share, 0.25);
        assert_eq!(c.points[0].design_share, 0.25);
        // Without a share (`design_peak = "from_rest"`) none is made up.
        c.points[1].design_share = f64::NAN;
        c.count_mirror_images();
        assert!(c.points[1].design_share.is_nan());
        // Without stored attractors the run's share stands.
        c.attractors = None;
        c.points[1].design_share = 0.25;
        c.count_mirror_images();
        assert_eq!(c.points[1].design_share, 0.25);
    }

    #[test]
    fn a_peak_on_a_wandering_motion_is_flagged() {
        let mut c = Curve {
            system: crate::model::System::TABLE_I,
            f0: 1.0,
            attractors: None,
            design: 0,
            points: vec![pt(0.9, 1.0, 4.0), pt(1.0, 3.0, 8.0), pt(1.1, 2.0, 2.0)],
        };
        assert!(c.peak_periodic());
        // The peak's point did not settle: flagged, whatever the other points do.
        c.points[1].design_period = 0;
        assert!(!c.peak_periodic());
        c.points[1].design_period = 2;
        c.points[0].design_period = 0;
        assert!(c.peak_periodic());
        // No peak (a failed run): not periodic.
        c.points[2].outcome = Outcome::StepCap;
        assert!(!c.peak_periodic());
    }
}
