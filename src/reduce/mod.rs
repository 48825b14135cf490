//! Reduce: a dataset of runs → one summary row per design point, zones and a ranking
//! (model.md §5–6).
//!
//! The reducer streams: [`Reducer::push`] takes one chunk of [`Run`]s at a time (a chunk holds
//! whole design points, in point order, as the store writes them), turns each design point into
//! a [`PointStats`] and drops the runs. Memory is a chunk plus a fixed number of bytes per
//! design point, whatever the cases per point. [`Reducer::finish`] then needs the whole sweep:
//! perfectibility normalises by the best R and DI, ranks and the Pareto set compare points,
//! jumps and zones look along the axes ([`zones`], [`jumps`], [`regions`]), sensitivity
//! decomposes the grid's variance ([`sensitivity`]), the recommendation looks at every point's
//! neighbourhood ([`recommend`]).
//!
//! Per design point, over the cases whose outcome is `ok` (a point whose cases did not all end
//! `ok` is flagged with `all_ok = false` and its failed runs are counted, never averaged in):
//! * the response ([`Response`]: `xmax` in the free-decay scene) mean and SD (eq. 9, `N - 1`),
//!   stress `S = 3 E r xmax / L^2` (eq. 10) and its lognormal parameters; strength lognormal
//!   from the study;
//! * `R` (eq. 6), its bootstrap confidence interval (seeded from the study seed and the point),
//!   the safety factor (eq. 7–8, exact or the paper's form), Anderson–Darling on `ln xmax`;
//! * `DI` from the ideal case, or the mean over the cases.

pub mod analysis;
pub mod bifurcations;
pub mod forced;
pub mod grid;
pub mod jumps;
pub mod orbits;
pub mod probe;
pub mod rank;
pub mod recommend;
pub mod regions;
pub mod sensitivity;
pub mod stats;
pub mod table;
pub mod zones;

use rayon::prelude::*;

use crate::sim::Outcome;
use crate::sim::noise::mix64;
use crate::study::{DiSource, SafetyForm, Study};
use stats::LogNormal;

pub use grid::Grid;
pub use jumps::{IdealCase, Jump, JumpKind, Quantity};
pub use recommend::EdgeWarning;
pub use zones::{Class, JumpStats, Zone, ZoneParams};

/// The per-point response: the one quantity from which stress, R and the ranking follow (the
/// largest positive peak `xmax` in the free-decay scene). Summary columns are named after it
/// (`xmax_mean`, `xmax_sd`, …).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Response {
    /// Column prefix and name in the report.
    pub name: &'static str,
    /// Its unit (SI).
    pub unit: &'static str,
    /// What it is, for a person.
    pub description: &'static str,
}

impl Response {
    /// The free-decay scene's response: the largest positive half-cycle maximum (model.md §3).
    pub const XMAX: Response = Response {
        name: "xmax",
        unit: "m",
        description: "largest positive peak",
    };
}

/// The per-point damping quantity: the second criterion of perfectibility (eq. 11), of the
/// "strong damping" class and of the Pareto set, beside R. The damping inclination `DI` in the
/// free-decay scene, the peak reduction in the harmonic one ([`forced::PEAK_REDUCTION`]).
/// Summary columns are named after it (`di`, `di_ideal`, `di_sd`, zones' `mean_di`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Damping {
    /// Column name and prefix.
    pub name: &'static str,
    /// How the report and the charts write it (`DI`), and its name as a chart's title starts
    /// (`Damping inclination`).
    pub symbol: &'static str,
    pub title: &'static str,
    /// Its unit (SI; `1` for a ratio).
    pub unit: &'static str,
    /// What it is, for a person.
    pub description: &'static str,
}

impl Damping {
    /// The free-decay scene's damping quantity: eq. 5, `(X1 - X2) / (t2 - t1)` (model.md §3).
    pub const DI: Damping = Damping {
        name: "di",
        symbol: "DI",
        title: "Damping inclination",
        unit: "m/s",
        description: "damping inclination",
    };

    /// Its symbol with its unit, as an axis or a table column is labelled: `DI (m/s)`, `PR (–)`
    /// for a ratio.
    pub fn label(&self) -> String {
        let unit = if self.unit == "1" { "–" } else { self.unit };
        format!("{} ({unit})", self.symbol)
    }

    /// A value with its unit: `0.01234 m/s`, or the number alone for a ratio.
    pub fn with_unit(&self, value: &str) -> String {
        if self.unit == "1" {
            value.to_string()
        } else {
            format!("{value} {}", self.unit)
        }
    }
}

/// Choices the command line can override over the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub safety_form: SafetyForm,
    pub di_source: DiSource,
    /// Zone and jump settings beyond the study's `r_min`, `di_strong` and declared zones.
    pub zones: ZoneParams,
    pub response: Response,
    pub damping: Damping,
    /// Bootstrap resamples for R's interval (`[reliability].bootstrap`).
    pub bootstrap: usize,
}

impl Options {
    /// The study's own choices.
    pub fn from_study(study: &Study) -> Options {
        Options {
            safety_form: study.reliability.safety_form,
            di_source: study.ranking.di_source,
            zones: ZoneParams {
                min_zone: study.zones.min_zone,
                step_spread: study.zones.step_spread,
                kink_slope: study.zones.kink_slope,
                locate: study.zones.locate,
            },
            response: Response::XMAX,
            damping: Damping::DI,
            bootstrap: study.reliability.bootstrap,
        }
    }
}

/// One run as the reducer needs it: its identity, its case and the observables the statistics
/// use. The store's rows are converted to this; the reducer knows nothing else of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Run {
    pub point: u64,
    pub case: u32,
    pub ideal: bool,
    /// The case's change of the inner mass (kg) and of the clearance (m), and its noise seed.
    pub dm: f64,
    pub dd: f64,
    pub noise_seed: Option<u64>,
    pub outcome: Outcome,
    /// The response ([`Response`]): `xmax` in the free-decay scene (m).
    pub response: f64,
    /// Damping inclination (m/s).
    pub di: f64,
}

/// The response over the ok cases of a design point: mean, SD (N - 1), five-number summary,
/// and the ideal case's value (NaN when it did not end `ok`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResponseStats {
    pub mean: f64,
    pub sd: f64,
    pub min: f64,
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    pub max: f64,
    pub ideal: f64,
}

/// The summary of one design point. The first block is computed from its own runs; the last
/// (`perfectibility` to `zone`) needs the whole sweep and is filled by [`Reducer::finish`].
/// Its axis values are [`Summary::values`].
#[derive(Clone, Debug, PartialEq)]
pub struct PointStats {
    /// Design point index.
    pub point: u64,
    /// Runs found for this point, and how many ended `ok` (the statistics use only those).
    pub n_cases: u32,
    pub n_ok: u32,
    /// Runs per outcome, in [`Outcome::ALL`] order.
    pub outcomes: [u32; 6],
    /// Every case ended `ok`.
    pub all_ok: bool,
    /// The response over the ok cases.
    pub response: ResponseStats,
    /// Stress (eq. 10, Pa) as a lognormal variable.
    pub stress: LogNormal,
    /// `beta = (mu_ln_S - mu_ln_s) / sqrt(sigma_ln_S^2 + sigma_ln_s^2)`; `R = Phi(beta)`.
    pub reliability_index: f64,
    /// Reliability, eq. 6.
    pub reliability: f64,
    /// Bootstrap confidence interval of `R`.
    pub reliability_lo: f64,
    pub reliability_hi: f64,
    /// `C_n` of eq. 7 and the safety factor `mu_n`.
    pub cn: f64,
    pub safety_factor: f64,
    /// Anderson–Darling on the log of the response: corrected statistic and p-value.
    pub ad_stat: f64,
    pub ad_p: f64,
    /// Damping inclination (m/s) as the ranking uses it ([`Options::di_source`]), the ideal
    /// case's, and its SD over the ok cases.
    pub di: f64,
    pub di_ideal: f64,
    pub di_sd: f64,
    /// Eq. 11 (%), rank (1 = best; `None` when R or DI is unknown), Pareto-optimal on (R, DI).
    pub perfectibility: f64,
    pub rank: Option<u64>,
    pub pareto: bool,
    /// Its class, and its zone: an index into [`Summary::zones`], [`regions::NO_REGION`] when it
    /// is in none (outside every declared zone).
    pub class: Class,
    pub zone: u32,
    /// Its whole ±1-step neighbourhood lies in recommended zones ([`recommend`]).
    pub robust: bool,
}

/// Sensitivity of one quantity to one axis ([`sensitivity`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// A summary column: the response's mean, `di`, `reliability` or `perfectibility`.
    pub quantity: String,
    pub axis: usize,
    pub first_order: f64,
    pub total: f64,
    /// The points it was computed over (those whose cases all ended ok and where it is known).
    pub n_points: usize,
}

/// Everything the report needs.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The swept axes.
    pub grid: Grid,
    /// One entry per design point found, in point order.
    pub points: Vec<PointStats>,
    /// Design points the study plans.
    pub n_points_planned: u64,
    /// Zones, named in the order of their first point.
    pub zones: Vec<Zone>,
    /// Jumps located along the axes, and how they were found.
    pub jumps: Vec<Jump>,
    pub jump_stats: JumpStats,
    /// First-order and total-effect indices per quantity and axis (two or more axes).
    pub sensitivity: Vec<Sensitivity>,
    /// The recommended design point ([`recommend`]) and the edges the best designs sit on.
    pub recommended: Option<u64>,
    pub edges: Vec<EdgeWarning>,
    /// The DI threshold used for "strong damping" (m/s).
    pub di_strong: f64,
    /// The reliability the lower end of R's interval must reach (`[zones].r_min`).
    pub r_min: f64,
    /// A region smaller than this (design points) was merged into a neighbour.
    pub min_zone_points: usize,
    /// The nominal design point (nearest the study's base system) and its runs.
    pub nominal: Option<(u64, Vec<Run>)>,
    /// Runs per outcome over the whole dataset, in [`Outcome::ALL`] order.
    pub outcome_totals: [u64; 6],
    /// The strength distribution (Pa).
    pub strength: LogNormal,
    /// `3 E r / L^2`: stress per metre of the response (Pa/m).
    pub stress_per_m: f64,
    pub options: Options,
    /// Confidence level of the bootstrap interval of R.
    pub confidence: f64,
    /// Best R and DI over the sweep (the eq. 11 denominators).
    pub r_max: f64,
    pub di_max: f64,
}

impl Summary {
    /// The axis values of a point, in axis order.
    pub fn values(&self, p: &PointStats) -> Vec<f64> {
        self.grid.values(p.point)
    }

    /// The point with index `point`, if it is in the dataset.
    pub fn point(&self, point: u64) -> Option<&PointStats> {
        self.points
            .binary_search_by_key(&point, |p| p.point)
            .ok()
            .map(|i| &self.points[i])
    }

    /// The zone of a point, if any.
    pub fn zone_of(&self, p: &PointStats) -> Option<&Zone> {
        self.zones.get(p.zone as usize)
    }

    /// Whether R is computed anywhere: false for a study without a strength
    /// ([`rank::computes_r`]).
    pub fn computes_r(&self) -> bool {
        rank::computes_r(&self.points)
    }

    /// The design point the report and the charts centre on: the recommended one, else the best
    /// ranked, else the first.
    pub fn anchor(&self) -> Option<u64> {
        self.recommended
            .or_else(|| {
                self.points
                    .iter()
                    .filter(|p| p.rank.is_some())
                    .min_by_key(|p| p.rank)
                    .map(|p| p.point)
            })
            .or_else(|| self.points.first().map(|p| p.point))
    }

    /// The point was merged into its zone from a smaller neighbouring region: its own class is
    /// not its zone's ([`Zone::n_merged`] counts them).
    pub fn merged(&self, p: &PointStats) -> bool {
        self.zone_of(p)
            .and_then(|z| z.class)
            .is_some_and(|c| c != p.class)
    }

    /// The name of a point's zone ("" when it has none).
    pub fn zone_name(&self, p: &PointStats) -> &str {
        self.zone_of(p).map_or("", |z| z.name.as_str())
    }
}

/// The study's ideal case, simulated at any design: the base system with the axis values set,
/// no perturbation, no noise, the study's solver and request.
pub struct SimulatedIdeal<'a> {
    pub study: &'a Study,
}

impl IdealCase for SimulatedIdeal<'_> {
    fn at(&self, values: &[f64]) -> Option<[f64; 2]> {
        let mut sys = self.study.system;
        for (axis, v) in self.study.axes.iter().zip(values) {
            sys.set(&axis.key, *v);
        }
        sys.validate().ok()?;
        let s = self.study;
        let rec = crate::sim::simulate(&sys, &s.solver, &s.request, None, &mut crate::sim::NoProbe);
        (rec.outcome == Outcome::Ok).then_some([rec.xmax, rec.di])
    }
}

/// The streaming reducer.
pub struct Reducer<'a> {
    study: &'a Study,
    options: Options,
    strength: LogNormal,
    stress_per_m: f64,
    nominal_point: u64,
    nominal: Option<(u64, Vec<Run>)>,
    points: Vec<PointStats>,
    outcome_totals: [u64; 6],
}

fn outcome_index(o: Outcome) -> usize {
    Outcome::ALL.iter().position(|&x| x == o).unwrap_or(0)
}

impl<'a> Reducer<'a> {
    pub fn new(study: &'a Study, options: Options) -> Self {
        let rel = &study.reliability;
        Reducer {
            study,
            options,
            strength: LogNormal::from_mean_sd(rel.strength_mean, rel.strength_sd),
            stress_per_m: 3.0 * rel.E * rel.r / (rel.L * rel.L),
            nominal_point: nominal_point(study),
            nominal: None,
            // The planned points at once: no doubling of the vector as chunks arrive (pages
            // of points a partial run never delivers are never touched).
            points: Vec::with_capacity(usize::try_from(study.n_points()).unwrap_or(0)),
            outcome_totals: [0; 6],
        }
    }

    /// The design point nearest the study's base system along every axis.
    pub fn nominal_point(&self) -> u64 {
        self.nominal_point
    }

    /// Reduces one chunk: runs of whole design points in point order. Points are computed in
    /// parallel; each point's bootstrap has its own seed, so the result does not depend on the
    /// thread count. The runs are dropped afterwards: memory grows with design points only.
    pub fn push(&mut self, runs: Vec<Run>) {
        let groups: Vec<&[Run]> = runs.chunk_by(|a, b| a.point == b.point).collect();
        for r in &runs {
            self.outcome_totals[outcome_index(r.outcome)] += 1;
        }
        if let Some(g) = groups.iter().find(|g| g[0].point == self.nominal_point) {
            self.nominal = Some((self.nominal_point, g.to_vec()));
        }
        let this = &*self;
        let stats: Vec<PointStats> = groups.par_iter().map(|g| this.point_stats(g)).collect();
        self.points.extend(stats);
    }

    /// The statistics of one design point from its runs.
    pub fn point_stats(&self, runs: &[Run]) -> PointStats {
        let rel = &self.study.reliability;
        let point = runs[0].point;
        let mut outcomes = [0u32; 6];
        let mut ys = Vec::with_capacity(runs.len());
        let mut dis = Vec::with_capacity(runs.len());
        let mut di_ideal = f64::NAN;
        let mut y_ideal = f64::NAN;
        for r in runs {
            outcomes[outcome_index(r.outcome)] += 1;
            if r.outcome == Outcome::Ok {
                ys.push(r.response);
                dis.push(r.di);
                if r.ideal {
                    di_ideal = r.di;
                    y_ideal = r.response;
                }
            }
        }
        let n_ok = ys.len() as u32;
        let (mean, sd) = stats::mean_sd(&ys);
        let q = |p: f64| stats::quantile(&ys, p);
        let k = self.stress_per_m;
        // A single run has no spread: SD 0 (`max` maps its NaN SD to 0), a degenerate
        // lognormal whose R is 0 or 1.
        let stress = LogNormal::from_mean_sd(k * mean, k * sd.max(0.0));
        let beta = stats::reliability_index(&self.strength, &stress);
        let reliability = stats::phi(beta);
        let stresses: Vec<f64> = ys.iter().map(|x| k * x).collect();
        let seed = mix64(self.study.seed ^ mix64(point ^ 0xB00_757A9));
        let (lo, hi) = stats::bootstrap_reliability(
            &stresses,
            &self.strength,
            self.options.bootstrap,
            rel.confidence,
            seed,
        );
        let cn = stats::c_n(self.strength.cv(), stress.cv());
        let safety_factor = match self.options.safety_form {
            SafetyForm::Exact => stats::safety_factor_exact_z(-beta, cn),
            SafetyForm::Paper => stats::safety_factor_paper(beta, cn),
        };
        let logs: Vec<f64> = ys.iter().filter(|x| **x > 0.0).map(|x| x.ln()).collect();
        let (ad_stat, ad_p) = stats::anderson_darling(&logs);
        let (di_mean, di_sd) = stats::mean_sd(&dis);
        let di = match self.options.di_source {
            DiSource::Ideal => di_ideal,
            DiSource::Mean => di_mean,
        };
        PointStats {
            point,
            n_cases: runs.len() as u32,
            n_ok,
            outcomes,
            all_ok: n_ok as usize == runs.len(),
            response: ResponseStats {
                mean,
                sd,
                min: q(0.0),
                q1: q(0.25),
                median: q(0.5),
                q3: q(0.75),
                max: q(1.0),
                ideal: y_ideal,
            },
            stress,
            reliability_index: beta,
            reliability,
            reliability_lo: lo,
            reliability_hi: hi,
            cn,
            safety_factor,
            ad_stat,
            ad_p,
            di,
            di_ideal,
            di_sd,
            perfectibility: f64::NAN,
            rank: None,
            pareto: false,
            class: Class::NoData,
            zone: regions::NO_REGION,
            robust: false,
        }
    }

    /// Everything that needs the whole sweep, with the study's ideal case simulated where the
    /// jumps are located.
    pub fn finish(self) -> Summary {
        let study = self.study;
        self.finish_with(&SimulatedIdeal { study })
    }

    /// [`Reducer::finish`] with another source of the ideal case (tests on synthetic data).
    pub fn finish_with(mut self, ideal: &dyn IdealCase) -> Summary {
        self.points.sort_by_key(|p| p.point);
        self.points.dedup_by_key(|p| p.point);
        let study = self.study;
        let ranking = &study.ranking;
        let (r_max, di_max) = rank::apply(&mut self.points, ranking.wf1, ranking.wf2);
        let grid = Grid::new(
            study
                .axes
                .iter()
                .map(|a| (a.key.clone(), a.values.clone()))
                .collect(),
        );
        let mut pos = vec![u32::MAX; grid.len() as usize];
        for (i, p) in self.points.iter().enumerate() {
            if let Some(slot) = pos.get_mut(p.point as usize) {
                *slot = i as u32;
            }
        }
        let cfg = zones::ZoneConfig {
            r_min: study.zones.r_min,
            di_strong: study.zones.di_strong,
            declared: &study.zones.declared,
            params: self.options.zones,
        };
        let found = zones::find(&grid, &mut self.points, &pos, &cfg, ranking, ideal);
        recommend::mark_robust(&grid, &mut self.points, &pos, &found.zones);
        let recommended = recommend::recommended(&self.points);
        let extendable = |a: usize, v: f64| {
            let mut sys = study.system;
            sys.set(&study.axes[a].key, v) && sys.validate().is_ok()
        };
        let edges = recommend::edges(&grid, &self.points, recommended, &extendable);
        let sensitivity = sensitivities(&grid, &self.points, &self.options);
        Summary {
            n_points_planned: study.n_points(),
            points: self.points,
            zones: found.zones,
            jumps: found.jumps,
            jump_stats: found.stats,
            sensitivity,
            recommended,
            edges,
            di_strong: found.di_strong,
            r_min: study.zones.r_min,
            min_zone_points: found.min_zone_points,
            nominal: self.nominal,
            outcome_totals: self.outcome_totals,
            strength: self.strength,
            stress_per_m: self.stress_per_m,
            options: self.options,
            confidence: study.reliability.confidence,
            r_max,
            di_max,
            grid,
        }
    }
}

/// Sensitivity indices of the response's mean, DI, R and perfectibility over the points whose
/// cases all ended ok (with one axis both are 1: it explains everything).
fn sensitivities(grid: &Grid, points: &[PointStats], options: &Options) -> Vec<Sensitivity> {
    type Of = fn(&PointStats) -> f64;
    let quantities: [(String, Of); 4] = [
        (format!("{}_mean", options.response.name), |p| {
            p.response.mean
        }),
        (options.damping.name.into(), |p| p.di),
        ("reliability".into(), |p| p.reliability),
        ("perfectibility".into(), |p| p.perfectibility),
    ];
    let mut out = Vec::new();
    for (name, f) in quantities {
        let mut y = vec![f64::NAN; grid.len() as usize];
        for p in points.iter().filter(|p| p.all_ok) {
            y[p.point as usize] = f(p);
        }
        let n_points = y.iter().filter(|v| v.is_finite()).count();
        for (axis, (first_order, total)) in sensitivity::indices(grid, &y).into_iter().enumerate() {
            out.push(Sensitivity {
                quantity: name.clone(),
                axis,
                first_order,
                total,
                n_points,
            });
        }
    }
    out
}

/// The design point nearest the study's base system: on every axis, the value closest to the
/// base system's value of that key (the first on a tie).
pub fn nominal_point(study: &Study) -> u64 {
    let mut p = 0u64;
    for axis in &study.axes {
        let base = study.system.get(&axis.key).unwrap_or(f64::NAN);
        let mut best = 0usize;
        for (i, v) in axis.values.iter().enumerate() {
            if (v - base).abs() < (axis.values[best] - base).abs() {
                best = i;
            }
        }
        p = p * axis.values.len() as u64 + best as u64;
    }
    p
}

/// Reduces a stream of chunks in one go.
pub fn reduce<I, E>(study: &Study, options: Options, chunks: I) -> Result<Summary, E>
where
    I: IntoIterator<Item = Result<Vec<Run>, E>>,
{
    let mut r = Reducer::new(study, options);
    for chunk in chunks {
        r.push(chunk?);
    }
    Ok(r.finish())
}

/// Helpers for tests: a study with the paper's defaults and synthetic runs.
#[doc(hidden)]
pub mod testing {
    use super::{IdealCase, Run};
    use crate::model::System;
    use crate::sim::{Outcome, Request, SolverSettings};
    use crate::study::{
        Axis, Case, DiSource, Ranking, Reliability, RunSettings, SafetyForm, Study, Zones,
    };

    /// A study over the given axes with `n_cases` cases (case 0 ideal), paper defaults for the
    /// reliability (strength mean 300 MPa, SD 24 MPa), zones and ranking.
    pub fn study(axes: Vec<(&str, Vec<f64>)>, n_cases: usize) -> Study {
        let cases = (0..n_cases)
            .map(|c| Case {
                dm: 0.0,
                dd: 0.0,
                noise_seed: (c > 0).then_some(c as u64),
                ideal: c == 0,
            })
            .collect();
        Study {
            path: "synthetic.toml".into(),
            source: String::new(),
            name: "synthetic".into(),
            seed: 7,
            request: Request::default(),
            scene: crate::sim::Scene::Free,
            system: System::TABLE_I,
            axes: axes
                .into_iter()
                .map(|(k, v)| Axis {
                    key: k.to_string(),
                    values: v,
                })
                .collect(),
            cases,
            noise: None,
            solver: SolverSettings::default(),
            reliability: Reliability {
                E: 200e9,
                r: 3.4e-3,
                L: 0.5,
                strength_mean: 300e6,
                strength_sd: 24e6,
                safety_form: SafetyForm::Exact,
                bootstrap: 2000,
                confidence: 0.95,
            },
            zones: Zones::default(),
            ranking: Ranking {
                wf1: 0.5,
                wf2: 0.5,
                di_source: DiSource::Ideal,
            },
            run: RunSettings {
                chunk_points: 16,
                audit: 0,
            },
        }
    }

    /// A run with the given observables (the response is `xmax`).
    pub fn row(study: &Study, point: u64, case: u32, outcome: Outcome, xmax: f64, di: f64) -> Run {
        Run {
            point,
            case,
            ideal: case == 0,
            dm: 0.0,
            dd: 0.0,
            noise_seed: study.cases[case as usize].noise_seed,
            outcome,
            response: xmax,
            di,
        }
    }

    /// The ideal case of synthetic data: a function of the axis values.
    pub struct FnIdeal<F>(pub F);

    impl<F: Fn(&[f64]) -> Option<[f64; 2]> + Sync> IdealCase for FnIdeal<F> {
        fn at(&self, values: &[f64]) -> Option<[f64; 2]> {
            (self.0)(values)
        }
    }

    /// The study simulated ([`simulate_chunks`]) and reduced with its own options, jumps
    /// located with its own simulator.
    pub fn reduce_simulated(study: &Study) -> super::Summary {
        let mut r = super::Reducer::new(study, super::Options::from_study(study));
        for chunk in simulate_chunks(study) {
            r.push(chunk);
        }
        r.finish()
    }

    /// Runs the simulator over every run of the study's plan, chunk by chunk, as the sweep
    /// engine would store them.
    pub fn simulate_chunks(study: &Study) -> Vec<Vec<Run>> {
        let plan = crate::plan::Plan::new(study);
        (0..plan.n_chunks())
            .map(|k| {
                let mut rows = Vec::new();
                for p in plan.chunk_points(k) {
                    for c in 0..plan.n_cases() as u32 {
                        let run = plan.run(p, c);
                        let mut noise = plan.noise_stream(&run);
                        let ns = study.noise;
                        let rec = crate::sim::simulate(
                            &run.system,
                            &study.solver,
                            &study.request,
                            match (&ns, noise.as_mut()) {
                                (Some(ns), Some(st)) => Some((ns, st)),
                                _ => None,
                            },
                            &mut crate::sim::NoProbe,
                        );
                        rows.push(Run {
                            point: p,
                            case: c,
                            ideal: run.spec.ideal,
                            dm: run.spec.dm,
                            dd: run.spec.dd,
                            noise_seed: run.spec.noise_seed,
                            outcome: rec.outcome,
                            response: rec.xmax,
                            di: rec.di,
                        });
                    }
                }
                rows
            })
            .collect()
    }

    /// The paper's study as `configs/paper.toml` states it: `e` from 0.45 to 0.95 step 0.01,
    /// the 12 cases of Table II (the Simulink seed vectors written as integers), noise power
    /// 5e-10 m^2 s at Ts = 1 ms, strength LN(285 MPa, 20 MPa).
    pub fn paper_study() -> Study {
        let e: Vec<f64> = (0..=50).map(|i| 0.45 + i as f64 * 0.01).collect();
        let mut s = study(vec![("e", e)], 1);
        s.seed = 2013;
        s.reliability.strength_mean = 285e6;
        s.reliability.strength_sd = 20e6;
        let g = 1e-3;
        let mm = 1e-3;
        let c = |dm: f64, dd: f64, seed: Option<u64>| Case {
            dm,
            dd,
            noise_seed: seed,
            ideal: dm == 0.0 && dd == 0.0 && seed.is_none(),
        };
        let (a, b, c3, d) = (Some(23341), Some(32324), Some(22413), Some(41313));
        s.cases = vec![
            c(0.0, 0.0, None),
            c(0.0, mm, None),
            c(0.0, -mm, None),
            c(0.0, 0.0, a),
            c(0.0, 0.0, b),
            c(0.0, 0.0, c3),
            c(0.0, 0.0, d),
            c(0.0, 0.0, b),
            c(g, mm, d),
            c(g, -mm, c3),
            c(-g, -mm, c3),
            c(-g, mm, a),
        ];
        s.noise = Some(crate::sim::NoiseSettings {
            power: 5e-10,
            sample_time: 1e-3,
        });
        s
    }
}

#[cfg(test)]
mod tests {
    use super::testing::*;
    use super::*;
    use crate::sim::Outcome;

    fn points(rs_dis: &[(f64, f64)]) -> Vec<PointStats> {
        let s = study(
            vec![("e", (0..rs_dis.len()).map(|i| i as f64).collect())],
            1,
        );
        let r = Reducer::new(&s, Options::from_study(&s));
        rs_dis
            .iter()
            .enumerate()
            .map(|(i, &(rel, di))| {
                let mut p = r.point_stats(&[row(&s, i as u64, 0, Outcome::Ok, 0.028, di)]);
                p.reliability = rel;
                p
            })
            .collect()
    }

    #[test]
    fn pareto_front_keeps_exactly_the_undominated() {
        // (R, DI): 0 and 1 trade off, 2 is dominated by 0, 3 equals 1, 4 has no DI.
        let mut pts = points(&[
            (0.99, 0.02),
            (0.95, 0.03),
            (0.98, 0.015),
            (0.95, 0.03),
            (0.999, f64::NAN),
        ]);
        assert_eq!(rank::pareto_front(&pts), vec![0, 1, 3]);
        let (rmax, dmax) = rank::apply(&mut pts, 0.5, 0.5);
        assert_eq!((rmax, dmax), (0.99, 0.03));
        assert_eq!(pts[4].rank, None);
        assert!(pts[4].perfectibility.is_nan() && !pts[4].pareto);
        // P(1) = 0.5 * 0.95/0.99 + 0.5 = 97.98 % beats P(0) = 50 + 33.3 = 83.3 %.
        assert_eq!(pts[1].rank, Some(1));
        assert_eq!(pts[3].rank, Some(2));
        assert_eq!(pts[0].rank, Some(3));
    }

    #[test]
    fn nominal_point_is_nearest_the_base_system() {
        let mut s = study(
            vec![("m", vec![0.01, 0.019, 0.03]), ("e", vec![0.5, 0.88, 0.95])],
            1,
        );
        s.system.e = 0.9;
        s.system.m = 0.02;
        // m -> 0.019 (index 1), e -> 0.88 (index 1): point 1 * 3 + 1.
        assert_eq!(nominal_point(&s), 4);
    }

    #[test]
    fn a_missing_point_is_left_out_not_invented() {
        let s = study(vec![("e", vec![0.5, 0.6, 0.7, 0.8])], 2);
        let mut rows = Vec::new();
        for p in [0u64, 1, 3] {
            for c in 0..2 {
                rows.push(row(&s, p, c, Outcome::Ok, 0.028, 0.02));
            }
        }
        let sum = reduce::<_, ()>(&s, Options::from_study(&s), [Ok(rows)]).unwrap();
        assert_eq!(sum.n_points_planned, 4);
        let found: Vec<u64> = sum.points.iter().map(|p| p.point).collect();
        assert_eq!(found, vec![0, 1, 3]);
        let md = crate::report::markdown::report(&s, &sum, &[], None);
        assert!(
            md.contains("3 of 4 design points") && md.contains("incomplete"),
            "{md}"
        );
    }

    #[test]
    fn a_design_point_costs_a_fixed_256_bytes() {
        // Issue 10: memory grows with design points, never with runs; a point holds no heap
        // data (its values come from the grid, its zone is an index).
        assert!(std::mem::size_of::<PointStats>() <= 256);
    }
}
