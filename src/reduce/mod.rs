//! Reduce: a dataset of runs → one summary row per design point, zones and a ranking
//! (model.md §5–6).
//!
//! The reducer streams: [`Reducer::push`] takes one chunk of [`RunRow`]s at a time (a chunk
//! holds whole design points, rows in `point_id` order, as the store writes them), turns each
//! design point into a [`PointStats`] and drops the rows. Memory is O(design points), never
//! O(runs). [`Reducer::finish`] then needs the whole sweep: perfectibility normalises by the
//! best R and DI, ranks and the Pareto set compare points, zones look along the axes.
//!
//! Per design point, over the cases whose outcome is `ok` (a point whose cases did not all end
//! `ok` is flagged with `all_ok = false` and its failed runs are counted, never averaged in):
//! * `xmax` mean and SD (eq. 9, `N - 1`), stress `S = 3 E r xmax / L^2` (eq. 10) and its
//!   lognormal parameters; strength lognormal from the study;
//! * `R` (eq. 6), its bootstrap confidence interval (seeded from the study seed and the point),
//!   the safety factor (eq. 7–8, exact or the paper's form), Anderson–Darling on `ln xmax`;
//! * `DI` from the ideal case, or the mean over the cases.

pub mod rank;
pub mod stats;
pub mod table;
pub mod zones;

use rayon::prelude::*;

use crate::plan::Plan;
use crate::sim::Outcome;
use crate::sim::noise::mix64;
use crate::store::RunRow;
use crate::study::{DiSource, SafetyForm, Study};
use stats::LogNormal;

pub use zones::{Jump, Zone};

/// Choices the command line can override over the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub safety_form: SafetyForm,
    pub di_source: DiSource,
}

impl Options {
    /// The study's own choices.
    pub fn from_study(study: &Study) -> Options {
        Options {
            safety_form: study.reliability.safety_form,
            di_source: study.ranking.di_source,
        }
    }
}

/// One run of the nominal design point, for the Table II-like case table.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseRow {
    pub case: u32,
    pub ideal: bool,
    pub dm: f64,
    pub dd: f64,
    pub noise_seed: Option<u64>,
    pub outcome: Outcome,
    pub xmax: f64,
    pub di: f64,
}

/// The summary of one design point. The first block is computed from its own runs; the last
/// (`perfectibility`, `rank`, `pareto`, `zone`) needs the whole sweep and is filled by
/// [`Reducer::finish`].
#[derive(Clone, Debug, PartialEq)]
pub struct PointStats {
    /// Design point index.
    pub point: u64,
    /// Its axis values, in axis order.
    pub values: Vec<f64>,
    /// Runs found for this point, and how many ended `ok` (the statistics use only those).
    pub n_cases: u32,
    pub n_ok: u32,
    /// Runs per outcome, in [`Outcome::ALL`] order.
    pub outcomes: [u32; 6],
    /// Every case ended `ok`.
    pub all_ok: bool,
    /// `xmax` over the ok cases (m): mean, SD (N - 1), and five-number summary.
    pub xmax_mean: f64,
    pub xmax_sd: f64,
    pub xmax_min: f64,
    pub xmax_q1: f64,
    pub xmax_median: f64,
    pub xmax_q3: f64,
    pub xmax_max: f64,
    /// `xmax` of the ideal case (m), NaN when it did not end `ok`.
    pub xmax_ideal: f64,
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
    /// Anderson–Darling on `ln xmax`: corrected statistic and p-value.
    pub ad_stat: f64,
    pub ad_p: f64,
    /// Damping inclination (m/s).
    pub di: f64,
    /// Eq. 11 (%), rank (1 = best; `None` when R or DI is unknown), Pareto-optimal on (R, DI).
    pub perfectibility: f64,
    pub rank: Option<u64>,
    pub pareto: bool,
    /// The zone's name (see [`zones`]).
    pub zone: String,
}

/// Everything the report needs.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Axis keys and their values (the grid).
    pub axes: Vec<(String, Vec<f64>)>,
    /// One entry per design point found, in point order.
    pub points: Vec<PointStats>,
    /// Design points the study plans.
    pub n_points_planned: u64,
    /// Zones, in order along the axis (1 axis) or by label (2+ axes).
    pub zones: Vec<Zone>,
    /// Jumps found along the axes.
    pub jumps: Vec<Jump>,
    /// The DI threshold used for "strong damping" (m/s).
    pub di_strong: f64,
    /// The reliability at or above which a point is "reliable" (`[zones].r_min`).
    pub r_min: f64,
    /// The nominal design point (nearest the study's base system) and its runs.
    pub nominal: Option<(u64, Vec<CaseRow>)>,
    /// Runs per outcome over the whole dataset, in [`Outcome::ALL`] order.
    pub outcome_totals: [u64; 6],
    /// The strength distribution (Pa).
    pub strength: LogNormal,
    /// `3 E r / L^2`: stress per metre of `xmax` (Pa/m).
    pub stress_per_m: f64,
    pub options: Options,
    /// Confidence level of the bootstrap interval of R.
    pub confidence: f64,
    /// Best R and DI over the sweep (the eq. 11 denominators).
    pub r_max: f64,
    pub di_max: f64,
}

/// The streaming reducer.
pub struct Reducer<'a> {
    study: &'a Study,
    plan: Plan<'a>,
    options: Options,
    strength: LogNormal,
    stress_per_m: f64,
    nominal_point: u64,
    nominal: Option<(u64, Vec<CaseRow>)>,
    points: Vec<PointStats>,
    outcome_totals: [u64; 6],
}

fn outcome_index(o: Outcome) -> usize {
    Outcome::ALL.iter().position(|&x| x == o).unwrap_or(0)
}

impl<'a> Reducer<'a> {
    pub fn new(study: &'a Study, options: Options) -> Self {
        let rel = &study.reliability;
        let plan = Plan::new(study);
        Reducer {
            study,
            options,
            strength: LogNormal::from_mean_sd(rel.strength_mean, rel.strength_sd),
            stress_per_m: 3.0 * rel.E * rel.r / (rel.L * rel.L),
            nominal_point: nominal_point(study),
            nominal: None,
            points: Vec::new(),
            outcome_totals: [0; 6],
            plan,
        }
    }

    /// The design point nearest the study's base system along every axis.
    pub fn nominal_point(&self) -> u64 {
        self.nominal_point
    }

    /// Reduces one chunk: rows of whole design points in `point_id` order. Points are computed
    /// in parallel; each point's bootstrap has its own seed, so the result does not depend on
    /// the thread count.
    pub fn push(&mut self, rows: Vec<RunRow>) {
        let mut groups: Vec<&[RunRow]> = Vec::new();
        let mut start = 0;
        for i in 1..=rows.len() {
            if i == rows.len() || rows[i].point != rows[start].point {
                groups.push(&rows[start..i]);
                start = i;
            }
        }
        for r in &rows {
            self.outcome_totals[outcome_index(r.record.outcome)] += 1;
        }
        if let Some(g) = groups.iter().find(|g| g[0].point == self.nominal_point) {
            self.nominal = Some((
                self.nominal_point,
                g.iter()
                    .map(|r| CaseRow {
                        case: r.case,
                        ideal: r.ideal,
                        dm: r.dm,
                        dd: r.dd,
                        noise_seed: r.noise_seed,
                        outcome: r.record.outcome,
                        xmax: r.record.xmax,
                        di: r.record.di,
                    })
                    .collect(),
            ));
        }
        let this = &*self;
        let stats: Vec<PointStats> = groups.par_iter().map(|g| this.point_stats(g)).collect();
        self.points.extend(stats);
    }

    /// The statistics of one design point from its runs.
    pub fn point_stats(&self, runs: &[RunRow]) -> PointStats {
        let rel = &self.study.reliability;
        let point = runs[0].point;
        let mut outcomes = [0u32; 6];
        let mut xmax = Vec::with_capacity(runs.len());
        let mut dis = Vec::with_capacity(runs.len());
        let mut di_ideal = f64::NAN;
        let mut xmax_ideal = f64::NAN;
        for r in runs {
            outcomes[outcome_index(r.record.outcome)] += 1;
            if r.record.outcome == Outcome::Ok {
                xmax.push(r.record.xmax);
                dis.push(r.record.di);
                if r.ideal {
                    di_ideal = r.record.di;
                    xmax_ideal = r.record.xmax;
                }
            }
        }
        let n_ok = xmax.len() as u32;
        let (xmax_mean, xmax_sd) = stats::mean_sd(&xmax);
        let q = |p: f64| stats::quantile(&xmax, p);
        let k = self.stress_per_m;
        // A single run has no spread: SD 0 (`max` maps its NaN SD to 0), a degenerate
        // lognormal whose R is 0 or 1.
        let stress = LogNormal::from_mean_sd(k * xmax_mean, k * xmax_sd.max(0.0));
        let beta = stats::reliability_index(&self.strength, &stress);
        let reliability = stats::phi(beta);
        let stresses: Vec<f64> = xmax.iter().map(|x| k * x).collect();
        let seed = mix64(self.study.seed ^ mix64(point ^ 0xB00_757A9));
        let (lo, hi) = stats::bootstrap_reliability(
            &stresses,
            &self.strength,
            rel.bootstrap,
            rel.confidence,
            seed,
        );
        let cn = stats::c_n(self.strength.cv(), stress.cv());
        let safety_factor = match self.options.safety_form {
            SafetyForm::Exact => stats::safety_factor_exact_z(-beta, cn),
            SafetyForm::Paper => stats::safety_factor_paper(beta, cn),
        };
        let logs: Vec<f64> = xmax.iter().filter(|x| **x > 0.0).map(|x| x.ln()).collect();
        let (ad_stat, ad_p) = stats::anderson_darling(&logs);
        let di = match self.options.di_source {
            DiSource::Ideal => di_ideal,
            DiSource::Mean => stats::mean_sd(&dis).0,
        };
        PointStats {
            point,
            values: self.plan.point_values(point),
            n_cases: runs.len() as u32,
            n_ok,
            outcomes,
            all_ok: n_ok as usize == runs.len(),
            xmax_mean,
            xmax_sd,
            xmax_min: q(0.0),
            xmax_q1: q(0.25),
            xmax_median: q(0.5),
            xmax_q3: q(0.75),
            xmax_max: q(1.0),
            xmax_ideal,
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
            perfectibility: f64::NAN,
            rank: None,
            pareto: false,
            zone: String::new(),
        }
    }

    /// Everything that needs the whole sweep: eq. 11, rank, Pareto set, zones.
    pub fn finish(mut self) -> Summary {
        self.points.sort_by_key(|p| p.point);
        self.points.dedup_by_key(|p| p.point);
        let ranking = &self.study.ranking;
        let (r_max, di_max) = rank::apply(&mut self.points, ranking.wf1, ranking.wf2);
        let axes: Vec<(String, Vec<f64>)> = self
            .study
            .axes
            .iter()
            .map(|a| (a.key.clone(), a.values.clone()))
            .collect();
        let found = zones::find(&axes, &mut self.points, &self.study.zones, ranking);
        Summary {
            axes,
            n_points_planned: self.study.n_points(),
            points: self.points,
            zones: found.zones,
            jumps: found.jumps,
            di_strong: found.di_strong,
            r_min: self.study.zones.r_min,
            nominal: self.nominal,
            outcome_totals: self.outcome_totals,
            strength: self.strength,
            stress_per_m: self.stress_per_m,
            options: self.options,
            confidence: self.study.reliability.confidence,
            r_max,
            di_max,
        }
    }
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
    I: IntoIterator<Item = Result<Vec<RunRow>, E>>,
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
    use crate::model::System;
    use crate::sim::{Outcome, Record, Request, SolverSettings};
    use crate::store::RunRow;
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
            zones: Zones {
                jump_k: 6.0,
                r_min: 0.98,
                di_strong: None,
                declared: Vec::new(),
            },
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

    /// A stored run with the given observables.
    pub fn row(
        study: &Study,
        point: u64,
        case: u32,
        outcome: Outcome,
        xmax: f64,
        di: f64,
    ) -> RunRow {
        let n_cases = study.cases.len() as u64;
        let plan = crate::plan::Plan::new(study);
        RunRow {
            point_id: point * n_cases + u64::from(case),
            point,
            case,
            ideal: case == 0,
            dm: 0.0,
            dd: 0.0,
            noise_seed: study.cases[case as usize].noise_seed,
            system: plan.point_system(point),
            solver: "exact".into(),
            tol: 1e-12,
            record: Record {
                outcome,
                peaks: vec![(xmax, 0.01), (xmax * 0.9, 0.04)],
                x1: xmax,
                t1: 0.01,
                x2: xmax * 0.9,
                t2: 0.04,
                xmax,
                di,
                impacts: 3,
                sticks: 0,
                energy_impact: 0.0,
                energy_viscous: 0.0,
                t_stop: 0.05,
                steps: 10,
            },
        }
    }

    /// Runs the simulator over every run of the study's plan, chunk by chunk, as the sweep
    /// engine would store them.
    pub fn simulate_chunks(study: &Study) -> Vec<Vec<RunRow>> {
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
                        rows.push(RunRow {
                            point_id: run.point_id,
                            point: p,
                            case: c,
                            ideal: run.spec.ideal,
                            dm: run.spec.dm,
                            dd: run.spec.dd,
                            noise_seed: run.spec.noise_seed,
                            system: run.system,
                            solver: study.solver.kind.name().into(),
                            tol: study.solver.tol,
                            record: rec,
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
}
