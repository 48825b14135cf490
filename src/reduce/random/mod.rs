//! The random and record scenes' reduction (model.md §13, docs/scenes.md): first-passage
//! reliability per design by Monte Carlo over its realizations, the fragility curve when the
//! study sweeps an intensity, and the core's zones, ranking and recommendation on them.
//!
//! # Per design point (the study's grid, intensity included)
//! Over the realizations whose outcome is `ok` (`n` of them; a run that stopped early is
//! counted by the core's `all_ok`/`failed`, never in `p_f`): `k` of them exceed the threshold
//! `b` (`amplitude = max |x| > b`, equivalently a first passage),
//!
//! ```text
//! p_f = k / n,    [p_f_lo, p_f_hi] = Clopper–Pearson at 95 %,    beta = -Phi^-1(p_f),
//! rms_x_mean = mean of rms_x (m),
//! ```
//!
//! the interval exact (conservative) for any `n` ([`crate::stats::binomial`]); `beta` is
//! `+inf` when no realization exceeded (`p_f = 0`: Monte Carlo says only `p_f < p_f_hi`). A
//! study without a threshold has no `p_f` (NaN).
//!
//! # Designs and the design intensity
//! Without an intensity axis (`S0` for a random load, `scale` for a record) a design is a
//! design point. With one, a design is a design point without its intensity ([`design_study`]),
//! and the core ranks the designs at the *design intensity*: `[scene].design_intensity`, one of
//! the swept values, or else the middle value of the swept intensities (the lower middle one for
//! an even count). Each design then gets its fragility
//! curve `P(exceed | IM) = Phi(ln(IM / theta) / beta)` fitted by maximum likelihood on its
//! exceedance counts at every intensity ([`crate::stats::fragility`]).
//!
//! # The core's view
//! Each realization is a [`Run`] of its design: the response ([`AMPLITUDE`]) is its
//! `amplitude`, so the stress route of §5 applies to the peak per realization when the study
//! gives a strength; the damping quantity ([`SURVIVAL`], `p_s`) is 1 when `|x|` stayed within
//! the threshold and 0 when it passed, always averaged over the realizations (`p_s = 1 - p_f`).
//! Without a strength the ranking is by `p_s`, i.e. by `p_f` (rank 1 the lowest), ties to the
//! lower design index. A random load has no ideal case: the jumps between grid designs are
//! found, not located between them ([`NoIdeal`]).
//!
//! # Small p_f
//! With `reduce --subset N`, a design (at the design intensity) whose realizations passed the
//! threshold fewer than [`subset::SUBSET_BELOW`] times gets `p_f` by subset simulation
//! ([`subset`]): its `p_f`, interval and `beta` are then subset simulation's
//! (`p_f_method = subset`, `p_f_cov` its coefficient of variation); `n_exceed` stays the Monte
//! Carlo count, and the ranking stays on the Monte Carlo `p_s`.
//!
//! # Memory
//! The realizations are read one at a time, in case order ([`RandomReducer::push`]): `p_f`
//! from exact counts at any size; the core's statistics exact while a design point's
//! realizations fit [`stream::EXACT_BUDGET`], from running moments and a quantile sketch
//! ([`sketch`]) beyond it ([`stream`]). Memory is then one part file, the budget and a fixed
//! size per design point, whatever the realizations per design.

pub mod point;
pub mod risk;
pub mod sketch;
pub mod stream;
pub mod stripes;
pub mod subset;

use rayon::prelude::*;

use crate::reduce::common::{
    Damping, IdealCase, Options, PointStats, Reducer, Response, Run, Summary,
};
use crate::sim::Outcome;
use crate::sim::random::IntensitySpec;
use crate::sim::random::{RandomScene, RealizationRecord};
use crate::stats::fragility::{self, Counts, FitOutcome, Fragility};
use crate::stats::hazard::{SiteHazard, lambda_f_lognormal};
use crate::store::RunRow;
use crate::store::table::{Column, Table};
use crate::study::{DiSource, Study};
use risk::{DesignRisk, MotionCapacity, design_risk, rank_by_risk};
use stream::{EXACT_BUDGET, PfAcc, PointRuns};
use stripes::{StripesInterval, stripes_fit, stripes_intervals};
use subset::{SUBSET_BELOW, SubsetAsk, SubsetPf, subset_pf};

/// The random scene's response: the largest `|x|` of a realization over the duration.
pub const AMPLITUDE: Response = Response {
    name: "amplitude",
    unit: "m",
    description: "largest |x| over the load's duration",
};

/// The random scene's damping quantity: the share of realizations whose `|x|` stays within the
/// threshold, `p_s = 1 - p_f`.
pub const SURVIVAL: Damping = Damping {
    name: "p_s",
    symbol: "p_s",
    title: "Survival probability",
    unit: "1",
    description: "share of realizations whose |x| stays within the threshold, 1 - p_f",
};

pub use crate::study::INTENSITY_KEYS;
pub use point::{CONFIDENCE, PointPf, beta_of};

/// The reducer's options for a random or record study: the study's own, with the amplitude as
/// the response and `p_s` as the damping quantity, averaged over the realizations (there is no
/// ideal case).
pub fn options(study: &Study) -> Options {
    let mut o = Options::of_study(study, AMPLITUDE, SURVIVAL);
    o.di_source = DiSource::Mean;
    o
}

/// The swept intensity of a study: the axis, its index among the study's axes, and which of
/// its values is the design intensity (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Intensity {
    pub key: String,
    pub axis: usize,
    pub values: Vec<f64>,
    pub design: usize,
    /// Whether the study chose the design intensity (`[scene].design_intensity`).
    pub chosen: bool,
}

/// The study's intensity axis (`S0` or `scale`), if it sweeps one.
pub fn intensity(study: &Study) -> Option<Intensity> {
    let axis = study
        .axes
        .iter()
        .position(|a| INTENSITY_KEYS.contains(&a.key.as_str()))?;
    let values = study.axes[axis].values.clone();
    let chosen = study
        .design_intensity
        .and_then(|v| values.iter().position(|&x| x == v));
    Some(Intensity {
        key: study.axes[axis].key.clone(),
        axis,
        design: chosen.unwrap_or((values.len() - 1) / 2),
        chosen: chosen.is_some(),
        values,
    })
}

/// The study of the designs: the study without its intensity axis, the intensity fixed at the
/// design intensity.
pub fn design_study(study: &Study) -> Study {
    let mut s = study.clone();
    if let Some(i) = intensity(study) {
        let v = i.values[i.design];
        s.axes.remove(i.axis);
        if let Some(r) = s.scene.random_mut() {
            r.set(&i.key, v);
        }
    }
    s
}

/// The design point of the study's grid that is design `design` (over the design axes'
/// lengths `design_axes`) at intensity index `j` of `i`.
fn point_at(i: &Intensity, design: u64, j: usize, design_axes: &[usize]) -> u64 {
    // Mixed radix, last axis fastest: the design's digits with the intensity's put back.
    let mut digits = Vec::with_capacity(design_axes.len() + 1);
    let mut rest = design;
    for &n in design_axes.iter().rev() {
        digits.push(rest % n as u64);
        rest /= n as u64;
    }
    digits.reverse();
    digits.insert(i.axis, j as u64);
    let mut lens = design_axes.to_vec();
    lens.insert(i.axis, i.values.len());
    digits
        .iter()
        .zip(&lens)
        .fold(0u64, |p, (&d, &n)| p * n as u64 + d)
}

/// What the random reduction adds to the core's [`Summary`].
#[derive(Clone, Debug, PartialEq)]
pub struct RandomSummary {
    /// The limit of `|x|` (m), if the study sets one.
    pub threshold: Option<f64>,
    /// Realizations per design point, and whether the load is a record.
    pub realizations: u64,
    pub record: bool,
    pub intensity: Option<Intensity>,
    /// Every design point of the study's grid reduced, in point order.
    pub points: Vec<PointPf>,
    /// Per design (the core's points, in design order): its fragility fit, when the study
    /// sweeps an intensity.
    pub fragility: Vec<(u64, Fragility)>,
    /// Per design whose fragility fit ended ok, with a hazard (in design order): the 95 %
    /// bootstrap interval over the motions of [`RandomSummary::lambda_f_stripes`]
    /// ([`stripes`]).
    pub stripes_interval: Vec<StripesInterval>,
    /// Per design that got one (in design order): subset simulation's `p_f` ([`subset`]).
    pub subset: Vec<(u64, SubsetPf)>,
    /// Per design whose fragility fit ended ok (in design order): its rank by median capacity
    /// `theta`, 1 the largest, ties to the lower design ([`capacity_ranks`]).
    pub capacity_rank: Vec<(u64, u64)>,
    /// The study's intensity measure, if it sets one.
    pub measure: Option<IntensitySpec>,
    /// The study's hazard, if it gives one.
    pub hazard: Option<SiteHazard>,
    /// Per design with capacities (in design order): its fragility from them and its annual
    /// risk ([`risk`]).
    pub risk: Vec<DesignRisk>,
    /// Every motion's capacity at the design stripe: `(design, case, capacity)`, in design then
    /// case order (the `capacities` table).
    pub capacities: Vec<(u64, u32, MotionCapacity)>,
}

impl RandomSummary {
    /// The design point of design `design` at intensity index `j` (the design itself without an
    /// intensity axis).
    pub fn grid_point(&self, design: u64, j: usize, design_axes: &[usize]) -> u64 {
        let Some(i) = &self.intensity else {
            return design;
        };
        point_at(i, design, j, design_axes)
    }

    /// The reliability of the design point `point`, if it was reduced.
    pub fn point(&self, point: u64) -> Option<&PointPf> {
        self.points
            .binary_search_by_key(&point, |p| p.point)
            .ok()
            .map(|i| &self.points[i])
    }

    /// Subset simulation's estimate for design `design`, if it got one.
    pub fn subset_of(&self, design: u64) -> Option<&SubsetPf> {
        self.subset
            .binary_search_by_key(&design, |f| f.0)
            .ok()
            .map(|i| &self.subset[i].1)
    }

    /// Subset simulation's estimate where it stands for design `design`'s `p_f`: where it got
    /// one above 0. Where its levels never passed the limit (`p_f = 0`, an interval with no
    /// meaning) Monte Carlo's bound says more, and the summary, the report and the charts take
    /// Monte Carlo's numbers.
    pub fn subset_estimate(&self, design: u64) -> Option<&SubsetPf> {
        self.subset_of(design).filter(|x| x.p_f > 0.0)
    }

    /// The rank of design `design` by median capacity, if its fit ended ok.
    pub fn capacity_rank_of(&self, design: u64) -> Option<u64> {
        self.capacity_rank
            .binary_search_by_key(&design, |f| f.0)
            .ok()
            .map(|i| self.capacity_rank[i].1)
    }

    /// The capacities' fragility and risk of design `design`, if it has capacities.
    pub fn risk_of(&self, design: u64) -> Option<&DesignRisk> {
        risk::risk_of(&self.risk, design)
    }

    /// Design `design`'s `p_f` at the design intensity as the ranking takes it, with its 95 %
    /// interval `(p_f, lo, hi)`: subset simulation's where it estimated one above 0, else Monte
    /// Carlo's (`lens`: the design grid's axis lengths, as [`RandomSummary::grid_point`]).
    pub fn design_pf(&self, design: u64, lens: &[usize]) -> Option<(f64, f64, f64)> {
        match self.subset_estimate(design) {
            Some(x) => Some((x.p_f, x.lo, x.hi)),
            None => {
                let j = self.intensity.as_ref().map_or(0, |i| i.design);
                let p = self.point(self.grid_point(design, j, lens))?;
                Some((p.p_f, p.p_f_lo, p.p_f_hi))
            }
        }
    }

    /// The fragility fit of design `design`, if any.
    pub fn fragility_of(&self, design: u64) -> Option<&Fragility> {
        self.fragility
            .binary_search_by_key(&design, |f| f.0)
            .ok()
            .map(|i| &self.fragility[i].1)
    }

    /// `lambda_f` (per year) over the stripes' own fragility ([`RandomSummary::fragility_of`]:
    /// the lognormal fitted to the share of motions that pass at each stripe, `P(f | IM)`
    /// itself, which needs no capacity), by quadrature over the study's hazard: the decision's
    /// `lambda_f` wherever it exists ([`risk`]). None without a hazard or a fit that ended ok.
    pub fn lambda_f_stripes(&self, design: u64) -> Option<f64> {
        let h = self.hazard.as_ref()?;
        let f = self
            .fragility_of(design)
            .filter(|f| f.outcome == FitOutcome::Ok)?;
        Some(lambda_f_lognormal(&h.curve, f.theta, f.beta))
    }

    /// The 95 % interval of [`RandomSummary::lambda_f_stripes`], a bootstrap over the motions
    /// ([`stripes`]). None where that has no value.
    pub fn lambda_f_stripes_interval(&self, design: u64) -> Option<(f64, f64)> {
        self.stripes_interval
            .binary_search_by_key(&design, |s| s.0)
            .ok()
            .map(|i| self.stripes_interval[i].1)
    }
}

/// The streaming reduction of a random or record study: the part files' rows in, one
/// [`PointPf`] per design point and the core's statistics per design at the design intensity
/// out. Memory: a chunk's rows, the runs of one design point up to a fixed budget
/// ([`stream::EXACT_BUDGET`]; beyond it the point streams, [`stream`]) and a fixed size per
/// design point; with capacities, a few numbers per realization of the stripes.
pub struct RandomReducer<'a> {
    study: &'a Study,
    core: Reducer<'a>,
    options: Options,
    threshold: Option<f64>,
    intensity: Option<Intensity>,
    /// The length of each axis of the study.
    lens: Vec<usize>,
    points: Vec<PointPf>,
    /// The design point being read: a point split into blocks of realizations
    /// ([`crate::plan::Plan::chunk_runs`]) spans several part files, read in order.
    pending: Option<Pending>,
    /// Realizations of a design point held to reduce it exactly.
    budget: usize,
    /// The design stripe's capacities: `(design, case, capacity)`.
    capacities: Vec<(u64, u32, MotionCapacity)>,
    /// Every stripe's run of every motion: `(design, case, im, passed)`, to find the motions
    /// whose response falls back below the limit above their capacity.
    stripe_runs: Vec<(u64, u32, f64, bool)>,
}

impl<'a> RandomReducer<'a> {
    /// `design` is [`design_study`]`(study)`, `options` the core's ([`options`] of it).
    pub fn new(study: &'a Study, design: &'a Study, options: Options) -> Self {
        let threshold = study.scene.random().and_then(|r| r.threshold);
        RandomReducer {
            study,
            core: Reducer::new(design, options),
            options,
            threshold,
            intensity: intensity(study),
            lens: study.axes.iter().map(|a| a.values.len()).collect(),
            points: Vec::new(),
            pending: None,
            budget: EXACT_BUDGET,
            capacities: Vec::new(),
            stripe_runs: Vec::new(),
        }
    }

    /// `(design, intensity index)` of a design point of the study's grid.
    fn split(&self, p: u64) -> (u64, usize) {
        let Some(i) = &self.intensity else {
            return (p, 0);
        };
        let mut rest = p;
        let mut digits = vec![0u64; self.lens.len()];
        for (a, &n) in self.lens.iter().enumerate().rev() {
            digits[a] = rest % n as u64;
            rest /= n as u64;
        }
        let design = digits
            .iter()
            .zip(&self.lens)
            .enumerate()
            .filter(|(a, _)| *a != i.axis)
            .fold(0u64, |d, (_, (&x, &n))| d * n as u64 + x);
        (design, digits[i.axis] as usize)
    }

    /// The realizations of a design point reduced exactly, beyond which it streams
    /// ([`stream::EXACT_BUDGET`] unless set here; a test's hook to cross it on a small study).
    pub fn with_budget(mut self, budget: usize) -> Self {
        self.budget = budget;
        self
    }

    /// Takes one part file's rows (in point order; part files in chunk order), one at a time:
    /// every design point they complete is reduced, the last one kept until the next point
    /// starts or [`RandomReducer::finish`].
    pub fn push(&mut self, rows: Vec<RunRow<RealizationRecord>>) {
        let mut ready = Vec::new();
        let design_j = self.intensity.as_ref().map_or(0, |i| i.design);
        let threshold = self.threshold;
        for r in rows {
            if let Some(p) = self.pending.take_if(|p| p.point != r.point) {
                self.close(p, &mut ready);
            }
            let (design, j) = self.split(r.point);
            let p = self.pending.get_or_insert_with(|| Pending {
                point: r.point,
                pf: PfAcc::default(),
                runs: (j == design_j).then(|| PointRuns::Exact(Vec::new())),
            });
            p.pf.add(&r.record.record, threshold);
            if let (Some(im), Some(b), Outcome::Ok) =
                (r.record.load[6], threshold, r.record.record.outcome)
            {
                let passed = r.record.record.amplitude > b;
                self.stripe_runs.push((design, r.case, im, passed));
            }
            if let Some(c) = &r.record.capacity
                && j == design_j
            {
                let m = (c.capacity, c.censored, c.resurrected, c.runs);
                self.capacities.push((design, r.case, m));
            }
            if let Some(runs) = &mut p.runs {
                runs.add(run_of(&r, design, threshold), self.budget);
            }
        }
        self.core.push(ready);
    }

    /// Reduces a design point read whole: its reliability, and its runs for the core (added to
    /// `ready` when held, reduced here when streamed).
    fn close(&mut self, p: Pending, ready: &mut Vec<Run>) {
        self.points
            .push(PointPf::of_counts(p.point, &p.pf, self.threshold));
        match p.runs {
            Some(PointRuns::Exact(runs)) => ready.extend(runs),
            Some(PointRuns::Streamed(s)) => {
                let (design, _) = self.split(p.point);
                let (stats, first) = stream::point_stats(&self.core, &self.options, design, *s);
                self.core.push_stats(stats, Some(first));
            }
            None => {}
        }
    }

    /// The core's summary over the designs, and the scene's own; with `subset = Some(ask)`
    /// subset simulation as asked (samples per level, repeats) for the designs with few exceedances
    /// ([`subset`]), whose estimate then ranks them (`p_s = 1 - p_f`).
    pub fn finish(mut self, subset: Option<SubsetAsk>) -> (Summary, RandomSummary) {
        if let Some(p) = self.pending.take() {
            let mut ready = Vec::new();
            self.close(p, &mut ready);
            self.core.push(ready);
        }
        self.points.sort_by_key(|p| p.point);
        self.points.dedup_by_key(|p| p.point);
        let design_lens: Vec<usize> = self
            .lens
            .iter()
            .enumerate()
            .filter(|(a, _)| self.intensity.as_ref().is_none_or(|i| i.axis != *a))
            .map(|(_, &n)| n)
            .collect();
        // Every stripe's run of every motion, by design, motion and intensity.
        let mut runs = std::mem::take(&mut self.stripe_runs);
        runs.sort_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)).then(a.2.total_cmp(&b.2)));
        // Each design's own fragility from its stripes' counts and, with a hazard, the interval
        // of its lambda_f; the risk's curve where it holds.
        let (fits, intervals) = self.stripes_fits(&design_lens, &runs);
        let mut risks = self.risks(&design_lens, &runs, &fits, &intervals);
        let hazard = self.study.hazard.as_ref();
        let mut subsets: Vec<(u64, SubsetPf)> = Vec::new();
        if let (Some(n), Some(b)) = (subset, self.threshold) {
            let (study, points, intensity) = (self.study, &self.points, &self.intensity);
            self.core.adjust(|designs| {
                for d in designs.iter_mut() {
                    let g = intensity
                        .as_ref()
                        .map_or(d.point, |i| point_at(i, d.point, i.design, &design_lens));
                    let few = points
                        .binary_search_by_key(&g, |p| p.point)
                        .is_ok_and(|i| points[i].exceed < SUBSET_BELOW);
                    if few && let Some(s) = subset_pf(study, g, b, n) {
                        d.di = 1.0 - s.p_f;
                        subsets.push((d.point, s));
                    }
                }
            });
        }
        if hazard.is_some() {
            // With a hazard the designs rank by lambda_f: p_s is then the probability of no
            // failure over the hazard's years, exp(-years lambda_f).
            self.core.adjust(|designs| {
                for d in designs.iter_mut() {
                    if let Ok(i) = risks.binary_search_by_key(&d.point, |r| r.design)
                        && let Some(r) = &risks[i].risk
                    {
                        d.di = 1.0 - r.p_f_years.0;
                    }
                }
            });
        }
        let summary = self.core.finish_with(&NoIdeal);
        rank_by_risk(&mut risks, &summary.points);
        let (realizations, record) = self.study.scene.random().map_or((0, false), |r| {
            (self.study.realizations, !r.draws_normals())
        });
        let mut rs = RandomSummary {
            threshold: self.threshold,
            realizations,
            record,
            intensity: self.intensity,
            points: self.points,
            fragility: Vec::new(),
            stripes_interval: Vec::new(),
            subset: subsets,
            capacity_rank: Vec::new(),
            measure: self.study.scene.random().and_then(|r| r.intensity),
            hazard: self.study.hazard.clone(),
            risk: risks,
            capacities: std::mem::take(&mut self.capacities),
        };
        // The fits of the designs the core reduced, in design order.
        let fits: Vec<(u64, Fragility)> = fits
            .into_iter()
            .filter(|f| summary.points.iter().any(|d| d.point == f.0))
            .collect();
        rs.capacity_rank = capacity_ranks(&fits);
        rs.stripes_interval = intervals;
        rs.fragility = fits;
        (summary, rs)
    }
}

impl RandomReducer<'_> {
    /// Each design's fragility fitted to its stripes' counts (in design order, where the study
    /// sweeps an intensity and sets a threshold) and, with a hazard, the bootstrap interval of
    /// its `lambda_f` over the motions where the fit ended ok ([`stripes`]). `runs`: every
    /// stripe's run of every motion, sorted by design then case.
    fn stripes_fits(
        &self,
        design_lens: &[usize],
        runs: &[(u64, u32, f64, bool)],
    ) -> (Vec<(u64, Fragility)>, Vec<StripesInterval>) {
        let (Some(i), Some(_)) = (&self.intensity, self.threshold) else {
            return (Vec::new(), Vec::new());
        };
        let designs: u64 = design_lens.iter().map(|&n| n as u64).product();
        let fits: Vec<(u64, Fragility)> = (0..designs)
            .into_par_iter()
            .map(|d| {
                let counts: Vec<Counts> = (0..i.values.len())
                    .filter_map(|j| {
                        let g = point_at(i, d, j, design_lens);
                        let k = self.points.binary_search_by_key(&g, |p| p.point).ok()?;
                        let p = &self.points[k];
                        Some(Counts {
                            im: i.values[j],
                            n: p.n,
                            exceed: p.exceed,
                        })
                    })
                    .collect();
                (d, fragility::fit(&counts))
            })
            .collect();
        let intervals = stripes_intervals(
            &fits,
            runs,
            &i.values,
            self.study.hazard.as_ref(),
            self.study.seed,
        );
        (fits, intervals)
    }

    /// Each design's fragility from its capacities and its risk ([`risk`]), in design order
    /// (ranked once the core has ranked the designs, [`risk::rank_by_risk`]); none without
    /// capacities.
    fn risks(
        &mut self,
        design_lens: &[usize],
        runs: &[(u64, u32, f64, bool)],
        fits: &[(u64, Fragility)],
        intervals: &[StripesInterval],
    ) -> Vec<DesignRisk> {
        let caps = &mut self.capacities;
        if caps.is_empty() {
            return Vec::new();
        }
        caps.sort_by_key(|c| (c.0, c.1));
        caps.dedup_by_key(|c| (c.0, c.1));
        let (ida_max, ida_tol) = self
            .study
            .scene
            .random()
            .and_then(|r| r.intensity)
            .map_or((f64::NAN, f64::NAN), |s| (s.ida_max, s.ida_tol));
        // A motion that did not pass at a stripe above its capacity (beyond the capacity's
        // tolerance) falls back: its response is not monotone in the scale, and the capacity
        // keeps the first passage.
        for c in caps.iter_mut() {
            let lo = runs.partition_point(|r| (r.0, r.1) < (c.0, c.1));
            let falls_back = runs[lo..]
                .iter()
                .take_while(|r| (r.0, r.1) == (c.0, c.1))
                .any(|r| !r.3 && !c.2.1 && r.2 >= c.2.0 * (1.0 + ida_tol));
            c.2.2 |= falls_back;
        }
        let caps = &self.capacities;
        let stripes_of = |design: u64| -> Vec<(f64, PointPf)> {
            let Some(i) = self.intensity.as_ref().filter(|i| i.key == "im") else {
                return Vec::new();
            };
            (0..i.values.len())
                .filter_map(|j| {
                    let g = point_at(i, design, j, design_lens);
                    let k = self.points.binary_search_by_key(&g, |p| p.point).ok()?;
                    Some((i.values[j], self.points[k]))
                })
                .collect()
        };
        let groups: Vec<&[(u64, u32, MotionCapacity)]> = caps.chunk_by(|a, b| a.0 == b.0).collect();
        let (hazard, seed) = (self.study.hazard.as_ref(), self.study.seed);
        groups
            .par_iter()
            .map(|g| {
                let motions: Vec<MotionCapacity> = g.iter().map(|c| c.2).collect();
                let own = stripes_fit(g[0].0, fits, intervals, hazard);
                let stripes = stripes_of(g[0].0);
                design_risk(g[0].0, &motions, &stripes, own, hazard, ida_max, seed)
            })
            .collect()
    }
}

/// The design point being read (module doc of [`stream`]).
struct Pending {
    point: u64,
    pf: PfAcc,
    /// The core's runs of the point, when it is at the design intensity.
    runs: Option<PointRuns>,
}

/// The designs ranked by median capacity (model.md §13): those whose fragility fit ended ok,
/// by `theta` descending (the intensity at which half the runs pass the threshold: the larger,
/// the stronger the design over every intensity, where the ranking by `p_f` looks at one),
/// ties to the lower design; `(design, rank)` in design order.
pub fn capacity_ranks(fits: &[(u64, Fragility)]) -> Vec<(u64, u64)> {
    let mut order: Vec<&(u64, Fragility)> = fits
        .iter()
        .filter(|(_, f)| f.outcome == FitOutcome::Ok && f.theta.is_finite())
        .collect();
    order.sort_by(|a, b| b.1.theta.total_cmp(&a.1.theta).then(a.0.cmp(&b.0)));
    let mut ranks: Vec<(u64, u64)> = order
        .iter()
        .enumerate()
        .map(|(r, (d, _))| (*d, r as u64 + 1))
        .collect();
    ranks.sort_by_key(|x| x.0);
    ranks
}

/// A stored realization as the core needs it: its design, the amplitude as the response and
/// whether it stayed within the threshold as the damping quantity (NaN without a threshold).
pub fn run_of(r: &RunRow<RealizationRecord>, design: u64, threshold: Option<f64>) -> Run {
    let rec = &r.record.record;
    Run {
        point: design,
        case: r.case,
        ideal: false,
        dm: r.dm,
        dd: r.dd,
        noise_seed: r.noise_seed,
        outcome: rec.outcome,
        response: rec.amplitude,
        di: threshold.map_or(f64::NAN, |b| if rec.amplitude > b { 0.0 } else { 1.0 }),
    }
}

/// A random load has no ideal case to simulate between the grid's designs.
pub struct NoIdeal;

impl IdealCase for NoIdeal {
    fn at(&self, _values: &[f64]) -> Option<[f64; 2]> {
        None
    }
}

/// The summary columns the scene adds for `rows` (the core's points, designs): `p_f`, its
/// interval, `beta`, `n_exceed`, `rms_x_mean`, the `threshold`, at the design intensity; with an
/// intensity axis also `intensity` (its key), `intensity_design` and the fragility fit
/// (`fragility_theta`, `fragility_beta`, their 95 % intervals, `fragility_outcome`) and, with a
/// hazard, `lambda_f_stripes` and its bootstrap interval (`lambda_f_stripes_lo`, `_hi`).
pub fn summary_columns(t: &mut Table, s: &Summary, rs: &RandomSummary, rows: &[&PointStats]) {
    let lens = lens(&s.grid);
    let j = rs.intensity.as_ref().map_or(0, |i| i.design);
    let pf: Vec<Option<&PointPf>> = rows
        .iter()
        .map(|d| rs.point(rs.grid_point(d.point, j, &lens)))
        .collect();
    let ss: Vec<Option<&SubsetPf>> = rows.iter().map(|d| rs.subset_of(d.point)).collect();
    let estimates: Vec<Option<&SubsetPf>> =
        rows.iter().map(|d| rs.subset_estimate(d.point)).collect();
    // A column of the Monte Carlo estimate, or subset simulation's where it stands for the
    // design's `p_f` ([`RandomSummary::subset_estimate`]).
    let either = |mc: &dyn Fn(&PointPf) -> f64, sub: &dyn Fn(&SubsetPf) -> f64| {
        Column::F64(
            pf.iter()
                .zip(&estimates)
                .map(|(p, s)| match s {
                    Some(s) => sub(s),
                    None => p.map_or(f64::NAN, mc),
                })
                .collect(),
        )
    };
    let f = |g: &dyn Fn(&PointPf) -> f64| {
        Column::F64(pf.iter().map(|p| p.map_or(f64::NAN, g)).collect())
    };
    t.push(
        "threshold",
        Column::F64(vec![rs.threshold.unwrap_or(f64::NAN); rows.len()]),
    );
    t.push("p_f", either(&|p| p.p_f, &|s| s.p_f));
    t.push("p_f_lo", either(&|p| p.p_f_lo, &|s| s.lo));
    t.push("p_f_hi", either(&|p| p.p_f_hi, &|s| s.hi));
    t.push("beta", either(&|p| p.beta, &|s| beta_of(s.p_f)));
    t.push(
        "p_f_method",
        Column::Str(
            ss.iter()
                .map(|s| match s {
                    Some(s) if s.converged => "subset",
                    Some(_) => "subset_unconverged",
                    None => "monte_carlo",
                })
                .map(str::to_string)
                .collect(),
        ),
    );
    t.push("p_f_cov", either(&|p| mc_cov(p.p_f, p.n), &|s| s.cov));
    t.push(
        "p_f_cov_upper",
        either(&|p| mc_cov(p.p_f, p.n), &|s| s.cov_upper),
    );
    t.push(
        "subset_runs",
        Column::U64(ss.iter().map(|s| s.map(|s| s.runs)).collect()),
    );
    t.push(
        "subset_repeats",
        Column::U64(ss.iter().map(|s| s.map(|s| s.repeats)).collect()),
    );
    t.push(
        "n_exceed",
        Column::U64(pf.iter().map(|p| p.map(|p| p.exceed)).collect()),
    );
    t.push("rms_x_mean", f(&|p| p.rms_x_mean));
    if !rs.risk.is_empty() {
        risk::summary_columns(t, &rs.risk, rs.hazard.as_ref(), rows);
    }
    let Some(i) = &rs.intensity else {
        return;
    };
    t.push("intensity", Column::Str(vec![i.key.clone(); rows.len()]));
    t.push(
        "intensity_design",
        Column::F64(vec![i.values[i.design]; rows.len()]),
    );
    let fits: Vec<Option<&Fragility>> = rows.iter().map(|d| rs.fragility_of(d.point)).collect();
    let g = |h: &dyn Fn(&Fragility) -> f64| {
        Column::F64(fits.iter().map(|x| x.map_or(f64::NAN, h)).collect())
    };
    t.push(
        "capacity_rank",
        Column::U64(rows.iter().map(|d| rs.capacity_rank_of(d.point)).collect()),
    );
    t.push("fragility_theta", g(&|x| x.theta));
    t.push("fragility_theta_lo", g(&|x| x.theta_lo));
    t.push("fragility_theta_hi", g(&|x| x.theta_hi));
    t.push("fragility_beta", g(&|x| x.beta));
    t.push("fragility_beta_lo", g(&|x| x.beta_lo));
    t.push("fragility_beta_hi", g(&|x| x.beta_hi));
    t.push(
        "fragility_outcome",
        Column::Str(
            fits.iter()
                .map(|x| x.map_or("none", |x| outcome_name(x.outcome)).to_string())
                .collect(),
        ),
    );
    if rs.hazard.is_some() {
        let interval: Vec<(f64, f64)> = rows
            .iter()
            .map(|d| {
                rs.lambda_f_stripes_interval(d.point)
                    .unwrap_or((f64::NAN, f64::NAN))
            })
            .collect();
        t.push(
            "lambda_f_stripes",
            Column::F64(
                rows.iter()
                    .map(|d| rs.lambda_f_stripes(d.point).unwrap_or(f64::NAN))
                    .collect(),
            ),
        );
        t.push(
            "lambda_f_stripes_lo",
            Column::F64(interval.iter().map(|x| x.0).collect()),
        );
        t.push(
            "lambda_f_stripes_hi",
            Column::F64(interval.iter().map(|x| x.1).collect()),
        );
    }
}

/// Monte Carlo's coefficient of variation of `p` from `n` runs, `sqrt((1 - p) / (n p))`.
fn mc_cov(p: f64, n: u64) -> f64 {
    ((1.0 - p) / (n as f64 * p)).sqrt()
}

/// The length of each axis of a grid.
fn lens(grid: &crate::reduce::common::Grid) -> Vec<usize> {
    (0..grid.n_axes()).map(|a| grid.n(a)).collect()
}

/// How a fragility fit ended, as the summary writes it.
pub fn outcome_name(o: FitOutcome) -> &'static str {
    match o {
        FitOutcome::Ok => "ok",
        FitOutcome::NoOverlap => "no_overlap",
        FitOutcome::Separated => "separated",
        FitOutcome::Invalid => "invalid",
        FitOutcome::Failed => "failed",
    }
}

/// The random scene of a study (`None` for another scene).
pub fn scene_of(study: &Study) -> Option<&RandomScene> {
    study.scene.random()
}

#[cfg(test)]
mod tests;
