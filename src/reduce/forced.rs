//! The harmonic scene's reduction (model.md §8, docs/reduce.md): every design's
//! frequency-response curve becomes one row of the reducer's grid.
//!
//! A **design** is a design point without its frequency: the study's grid with the frequency
//! axis (`r` or `omega`, always the last, [`crate::study`]) taken out ([`design_study`]). The
//! part files hold whole curves (a chunk is a whole number of them), so the reduction streams:
//! [`ForcedReducer::push`] turns each design's runs into
//!
//! * one reducer [`Run`] per case: its response is the case's **peak amplitude** over the swept
//!   band (the largest `amplitude` of its runs, the classic design target, [`PEAK_AMPLITUDE`]);
//!   its damping quantity is the **peak reduction** `PR = 1 - peak amplitude / peak of
//!   amplitude_linear` over the same band ([`PEAK_REDUCTION`], dimensionless: 0.9 means the
//!   damper removes 90 % of the linear system's resonance peak; negative when it makes the
//!   peak worse). A case with a run that did not end `ok` takes that run's outcome (its peak is
//!   unknown), so the reducer counts it as failed;
//! * the ideal case's [`Curve`] (kept for the charts, the report and the band columns: where
//!   the peak is, the band where the damper helps, how much of the band is periodic).
//!
//! The reducer ([`super::Reducer`]) then does over the designs what it does over free-decay
//! design points: stress, R and the safety factor from the peak amplitudes of the cases (each
//! case's peak is a sample), perfectibility from R and PR, zones, jumps (located with the ideal
//! case's curve continued to each probe from its grid neighbours' attractors,
//! [`super::probe::ForcedIdeal`]), sensitivity and the robust recommendation.

use super::table::{Column, Table};
use super::{Damping, Options, PointStats, Reducer, Response, Run, Summary};
use crate::orbits::attractors::AttractorRow;
use crate::sim::forced::{DesignPeak, NonPeriodicPeak};
use crate::sim::{ForcedRecord, Outcome, Scene};
use crate::store::RunRow;
use crate::study::{Study, frequency_axis};

/// The response of a harmonic study: the largest steady amplitude over the swept band.
pub const PEAK_AMPLITUDE: Response = Response {
    name: "peak_amplitude",
    unit: "m",
    description: "largest steady amplitude over the frequency band",
};

/// The damping quantity of a harmonic study: `1 - peak amplitude / the linear system's peak
/// over the band`.
pub const PEAK_REDUCTION: Damping = Damping {
    name: "peak_reduction",
    symbol: "PR",
    title: "Peak reduction",
    unit: "1",
    description: "peak reduction, 1 - peak amplitude / the linear system's peak over the band",
};

/// The study's `[scene].design_peak` (the worst steady state unless it says otherwise).
pub fn design_peak(study: &Study) -> DesignPeak {
    match study.scene {
        Scene::Harmonic(h) => h.design_peak,
        Scene::Free => DesignPeak::Worst,
    }
}

/// The study of the designs: the harmonic study without its frequency axis.
pub fn design_study(study: &Study) -> Study {
    let mut s = study.clone();
    if let Some(i) = frequency_axis(&s.axes) {
        s.axes.remove(i);
    }
    s
}

/// The reducer's options for a harmonic study: the design study's own, with the peak
/// amplitude as the response and the peak reduction as the damping quantity.
pub fn options(design: &Study) -> Options {
    Options {
        response: PEAK_AMPLITUDE,
        damping: PEAK_REDUCTION,
        ..Options::from_study(design)
    }
}

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
    /// per forcing period and its basin share (NaN without census).
    pub design_period: u32,
    pub design_impacts: f64,
    pub design_share: f64,
    /// Distinct attractors the census found (0 without census).
    pub attractors: u32,
}

impl CurvePoint {
    /// The point of a stored run; `peak` says which steady state is the design quantity.
    pub fn of(rec: &ForcedRecord, peak: DesignPeak) -> CurvePoint {
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
    /// steady-state analysis of the curve starts from ([`super::orbits`]).
    pub system: crate::model::System,
    pub f0: f64,
    /// The ideal case's attractors at every frequency, as the sweep stored them (the
    /// `attractors` table); `None` for a dataset written before the sweep stored them.
    pub attractors: Option<Vec<AttractorRow>>,
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
    /// stored attractors, a periodic orbit and its mirror image counted once. The cavity is
    /// symmetric, so `x -> -x` half a forcing period later maps a motion onto another; an
    /// asymmetric orbit and its image are two attractors with the same period, amplitude and
    /// multipliers (equal here to 1e-9 relative), and a jump between them changes nothing
    /// the design quantity measures.
    pub fn distinct_states_at(&self, i: usize) -> usize {
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        let mut kept: Vec<&AttractorRow> = Vec::new();
        for a in self.attractors_at(i) {
            let twin = a.kind.periodic()
                && kept.iter().any(|k| {
                    k.kind.periodic()
                        && k.period == a.period
                        && same(k.amplitude, a.amplitude)
                        && (same(k.multiplier_max, a.multiplier_max)
                            || (k.multiplier_max.is_nan() && a.multiplier_max.is_nan()))
                });
            if !twin {
                kept.push(a);
            }
        }
        kept.len()
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

/// What the harmonic reduction adds to the reducer's [`Summary`].
#[derive(Clone, Debug, PartialEq)]
pub struct ForcedSummary {
    /// The frequency axis (`r` or `omega`) and its values; `None` when the study has a single
    /// frequency (then a "curve" is one point).
    pub frequency: Option<(String, Vec<f64>)>,
    /// Every design's ideal-case curve, in design order.
    pub curves: Vec<Curve>,
    /// Simulated runs, and their outcomes in [`Outcome::ALL`] order (the reducer's own counts
    /// are per design and case).
    pub runs: u64,
    pub outcomes: [u64; 6],
    /// Which steady state the design quantity is.
    pub design_peak: DesignPeak,
    /// How the per-design analysis runs (one shard of it, what earlier shards computed).
    pub analysis: super::analysis::Plan,
    /// The design life (s) a motion that is not periodic is measured over, and the quantile of
    /// its largest amplitude that is the design amplitude (`[scene]`).
    pub design_life: f64,
    pub life_quantile: f64,
    /// How a motion that is not periodic gets its design amplitude (`[scene]
    /// nonperiodic_peak`).
    pub nonperiodic_peak: NonPeriodicPeak,
    /// The lines of the grid the bifurcation curves are followed along.
    pub curve_lines: super::bifurcations::CurveLines,
}

impl ForcedSummary {
    /// The design life the motions that are not periodic were measured over (s); NaN when
    /// none was (`nonperiodic_peak = "window"`).
    pub fn measured_life(&self) -> f64 {
        match self.nonperiodic_peak {
            NonPeriodicPeak::Life => self.design_life,
            NonPeriodicPeak::Window => f64::NAN,
        }
    }

    /// The curve of a design, if it is in the dataset.
    pub fn curve(&self, design: u64) -> Option<&Curve> {
        self.curves
            .binary_search_by_key(&design, |c| c.design)
            .ok()
            .map(|i| &self.curves[i])
    }
}

/// The summary columns of a harmonic study beyond the reducer's, for the rows of `points`
/// (designs), from each design's ideal curve: `peak_r` (where its peak is), `linear_peak` and
/// `linear_peak_r` (the linear system's peak over the band), `help_r_from` and `help_r_to` (the
/// band where the damper helps, NaN when it does not help at the linear peak), `help_share` and
/// `periodic_share` (shares of the band's frequencies), `peak_periodic` (the motion at the peak
/// is periodic, [`Curve::peak_periodic`]).
pub fn summary_columns(t: &mut Table, fs: &ForcedSummary, points: &[&PointStats]) {
    let col = |g: &dyn Fn(&Curve) -> f64| {
        Column::F64(
            points
                .iter()
                .map(|p| fs.curve(p.point).map_or(f64::NAN, g))
                .collect(),
        )
    };
    let band = |c: &Curve| c.help_band();
    t.push("peak_r", col(&|c| c.peak().1));
    t.push("peak_from_rest", col(&|c| c.peak_from_rest().0));
    t.push(
        "peak_attractor_period",
        Column::U64(
            points
                .iter()
                .map(|p| {
                    fs.curve(p.point)
                        .and_then(Curve::peak_point)
                        .map(|q| u64::from(q.design_period))
                })
                .collect(),
        ),
    );
    let at_peak = |g: fn(&CurvePoint) -> f64| move |c: &Curve| c.peak_point().map_or(f64::NAN, g);
    t.push(
        "peak_impacts_per_period",
        col(&at_peak(|q| q.design_impacts)),
    );
    t.push("peak_basin_share", col(&at_peak(|q| q.design_share)));
    t.push("linear_peak", col(&|c| c.linear_peak().0));
    t.push("linear_peak_r", col(&|c| c.linear_peak().1));
    t.push(
        "help_r_from",
        col(&|c| band(c).map_or(f64::NAN, |b| b.from)),
    );
    t.push("help_r_to", col(&|c| band(c).map_or(f64::NAN, |b| b.to)));
    t.push("help_share", col(&|c| c.help_share()));
    t.push("periodic_share", col(&|c| c.periodic_share()));
    t.push(
        "peak_periodic",
        Column::Bool(
            points
                .iter()
                .map(|p| fs.curve(p.point).is_some_and(Curve::peak_periodic))
                .collect(),
        ),
    );
    // Issue 22: the steady state carrying the peak, and the design life its amplitude is over.
    let attractor =
        |g: fn(&AttractorRow) -> f64| move |c: &Curve| c.peak_attractor().map_or(f64::NAN, g);
    t.push(
        "peak_kind",
        Column::Str(
            points
                .iter()
                .map(|p| {
                    fs.curve(p.point)
                        .and_then(Curve::peak_attractor)
                        .map_or(String::new(), |a| a.kind.name().to_string())
                })
                .collect(),
        ),
    );
    t.push(
        "peak_window_amplitude",
        col(&attractor(|a| a.window_amplitude)),
    );
    t.push("peak_life_lo", col(&attractor(|a| a.life_lo)));
    t.push("peak_life_hi", col(&attractor(|a| a.life_hi)));
    t.push("peak_lyapunov", col(&attractor(|a| a.lyapunov)));
    t.push(
        "design_life",
        Column::F64(vec![fs.measured_life(); points.len()]),
    );
}

/// The streaming reduction of a harmonic study's parts.
pub struct ForcedReducer<'a> {
    study: &'a Study,
    reducer: Reducer<'a>,
    /// Frequencies per curve and cases per design point.
    n_f: u64,
    n_cases: u64,
    /// Rows of a design whose curve is not complete yet (a chunk that ended inside a curve).
    pending: Vec<RunRow<ForcedRecord>>,
    /// The ideal case's stored attractors, by design.
    attractors: std::collections::BTreeMap<u64, Vec<AttractorRow>>,
    /// Whether the parts came with attractors.
    stored: bool,
    curves: Vec<Curve>,
    runs: u64,
    outcomes: [u64; 6],
    /// Which steady state is the design quantity.
    peak: DesignPeak,
}

impl<'a> ForcedReducer<'a> {
    /// `design` is [`design_study`] of `study`; `options` usually [`options`] of it.
    pub fn new(study: &'a Study, design: &'a Study, options: Options) -> Self {
        ForcedReducer {
            study,
            reducer: Reducer::new(design, options),
            n_f: study.curve_points(),
            n_cases: study.cases.len() as u64,
            pending: Vec::new(),
            attractors: Default::default(),
            stored: false,
            curves: Vec::new(),
            runs: 0,
            outcomes: [0; 6],
            peak: design_peak(study),
        }
    }

    /// Reduces one part's rows (whole curves, in `point_id` order): one reducer run per design
    /// and case, and the ideal case's curve; `attractors` are the part's stored attractors
    /// (`None`: a dataset written before the sweep stored them).
    pub fn push(&mut self, rows: Vec<RunRow<ForcedRecord>>, attractors: Option<Vec<AttractorRow>>) {
        self.stored |= attractors.is_some();
        for a in attractors.into_iter().flatten().filter(|a| a.run.ideal) {
            self.attractors
                .entry(a.run.point / self.n_f)
                .or_default()
                .push(a);
        }
        for r in &rows {
            self.runs += 1;
            self.outcomes[super::outcome_index(r.record.outcome)] += 1;
        }
        let mut rows = rows;
        if !self.pending.is_empty() {
            let mut all = std::mem::take(&mut self.pending);
            all.append(&mut rows);
            rows = all;
        }
        let full = (self.n_f * self.n_cases) as usize;
        let n_f = self.n_f;
        let mut groups: Vec<&[RunRow<ForcedRecord>]> = rows
            .chunk_by(|a, b| a.point / n_f == b.point / n_f)
            .collect();
        // A curve the next part continues waits for it.
        if groups.last().is_some_and(|g| g.len() < full) {
            let last = groups.pop().unwrap_or_default();
            self.pending = last.to_vec();
        }
        let mut runs = Vec::with_capacity(groups.len() * self.n_cases as usize);
        for g in groups {
            self.design(g, &mut runs);
        }
        self.reducer.push(runs);
    }

    /// One design's runs: a reducer run per case, and the ideal case's curve.
    fn design(&mut self, rows: &[RunRow<ForcedRecord>], runs: &mut Vec<Run>) {
        let design = rows[0].point / self.n_f;
        let mut cases: Vec<u32> = rows.iter().map(|r| r.case).collect();
        cases.sort_unstable();
        cases.dedup();
        for c in cases {
            let of_case: Vec<&RunRow<ForcedRecord>> = rows.iter().filter(|r| r.case == c).collect();
            let first = of_case[0];
            let failed = of_case
                .iter()
                .map(|r| r.record.outcome)
                .find(|o| *o != Outcome::Ok);
            let peak = of_case
                .iter()
                .map(|r| CurvePoint::of(&r.record, self.peak).design)
                .fold(f64::NAN, f64::max);
            let linear = of_case
                .iter()
                .map(|r| r.record.amplitude_linear)
                .fold(f64::NAN, f64::max);
            let (response, damping) = match failed {
                None => (peak, 1.0 - peak / linear),
                Some(_) => (f64::NAN, f64::NAN),
            };
            runs.push(Run {
                point: design,
                case: c,
                ideal: first.ideal,
                dm: first.dm,
                dd: first.dd,
                noise_seed: first.noise_seed,
                outcome: failed.unwrap_or(Outcome::Ok),
                response,
                di: damping,
            });
            if first.ideal {
                self.curves.push(Curve {
                    design,
                    system: first.system,
                    f0: first.record.F0,
                    attractors: None,
                    points: of_case
                        .iter()
                        .map(|r| CurvePoint::of(&r.record, self.peak))
                        .collect(),
                });
            }
        }
    }

    /// Everything that needs all the designs (the reducer's [`Reducer::finish_with`], its jumps
    /// located with [`super::probe::ForcedIdeal`]), and the curves.
    ///
    /// `plan` says whether this is one shard of the analysis and what earlier shards computed;
    /// the jump probes computed here are returned with the summaries (what a shard stores).
    pub fn finish(
        mut self,
        plan: &super::analysis::Plan,
    ) -> (Summary, ForcedSummary, super::analysis::Probes) {
        let pending = std::mem::take(&mut self.pending);
        if !pending.is_empty() {
            let mut runs = Vec::new();
            self.design(&pending, &mut runs);
            self.reducer.push(runs);
        }
        self.curves.sort_by_key(|c| c.design);
        self.curves.dedup_by_key(|c| c.design);
        for c in &mut self.curves {
            let rows = self.attractors.remove(&c.design);
            c.attractors = self.stored.then(|| rows.unwrap_or_default());
        }
        let ideal = super::probe::ForcedIdeal::new(self.study, &self.curves, plan);
        let mut summary = self.reducer.finish_with(&ideal);
        let probes = ideal.computed();
        drop(ideal);
        // The outcomes of the simulated runs, not of the designs' cases (the reducer's runs).
        summary.outcome_totals = self.outcomes;
        let frequency = self
            .study
            .frequency_axis()
            .map(|a| (a.key.clone(), a.values.clone()));
        (
            summary,
            ForcedSummary {
                frequency,
                curves: self.curves,
                runs: self.runs,
                outcomes: self.outcomes,
                design_peak: self.peak,
                analysis: plan.clone(),
                design_life: match self.study.scene {
                    Scene::Harmonic(h) => h.design_life,
                    Scene::Free => f64::NAN,
                },
                life_quantile: match self.study.scene {
                    Scene::Harmonic(h) => h.life_quantile,
                    Scene::Free => f64::NAN,
                },
                nonperiodic_peak: match self.study.scene {
                    Scene::Harmonic(h) => h.nonperiodic_peak,
                    Scene::Free => NonPeriodicPeak::Life,
                },
                curve_lines: Default::default(),
            },
            probes,
        )
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
