//! The streaming reducer: a dataset of runs → one [`PointStats`] per design point as the chunks
//! come ([`Reducer::push`]), then what needs the whole sweep ([`Reducer::finish_with`]).
//!
//! The reducer streams: [`Reducer::push`] takes one chunk of [`Run`]s at a time (a chunk holds
//! whole design points, in point order, as the store writes them), turns each design point into
//! a [`PointStats`] and drops the runs. Memory is a chunk plus a fixed number of bytes per
//! design point, whatever the cases per point. [`Reducer::finish_with`] then needs the whole
//! sweep: perfectibility normalises by the best R and DI, ranks and the Pareto set compare
//! points, jumps and zones look along the axes ([`super::zones`], [`super::jumps`],
//! [`super::regions`]), sensitivity decomposes the grid's variance ([`super::sensitivity`]), the
//! recommendation looks at every point's neighbourhood ([`super::recommend`]).
//!
//! Per design point, over the cases whose outcome is `ok` (a point whose cases did not all end
//! `ok` is flagged with `all_ok = false` and its failed runs are counted, never averaged in):
//! * the response ([`super::Response`]: `xmax` in the free-decay scene) mean and SD (eq. 9,
//!   `N - 1`), stress `S = 3 E r xmax / L^2` (eq. 10) and its lognormal parameters; strength
//!   lognormal from the study;
//! * `R` (eq. 6), its bootstrap confidence interval (seeded from the study seed and the point),
//!   the safety factor (eq. 7–8, exact or the paper's form), Anderson–Darling on `ln xmax`;
//! * `DI` from the ideal case, or the mean over the cases.

use rayon::prelude::*;

use super::class::Class;
use super::grid::Grid;
use super::jumps::IdealCase;
use super::options::Options;
use super::point::{PointStats, ResponseStats, Run};
use super::stats::{self, LogNormal};
use super::summary::{Sensitivity, Summary};
use super::zones;
use super::{rank, recommend, regions, sensitivity};
use crate::sim::Outcome;
use crate::sim::noise::mix64;
use crate::study::{DiSource, SafetyForm, Study};

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

/// The index of an outcome in [`Outcome::ALL`] order (how the counts per outcome are kept).
pub fn outcome_index(o: Outcome) -> usize {
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

    /// Takes a design point whose statistics a scene made itself (a random study's point
    /// beyond its exact budget, streamed: [`crate::reduce::random::stream`]), its runs counted
    /// by outcome as [`Reducer::push`] counts them; `nominal`: the runs the report lists when
    /// it is the nominal point.
    pub fn push_stats(&mut self, stats: PointStats, nominal: Option<Vec<Run>>) {
        for (t, &c) in self.outcome_totals.iter_mut().zip(&stats.outcomes) {
            *t += u64::from(c);
        }
        if stats.point == self.nominal_point
            && let Some(runs) = nominal
        {
            self.nominal = Some((stats.point, runs));
        }
        self.points.push(stats);
    }

    /// The strength (Pa) as a lognormal variable, and the stress per metre of response
    /// (`3 E r / L^2`, Pa/m; eq. 10): what [`Reducer::point_stats`] takes from the study.
    pub fn strength(&self) -> LogNormal {
        self.strength
    }

    pub fn stress_per_m(&self) -> f64 {
        self.stress_per_m
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

    /// The ranking the points reduced so far would get (eq. 11, [`rank::apply`] on a copy):
    /// each ranked point and its rank, best first. A scene that measures again what decides the
    /// ranking (the harmonic scene's verification) asks for it before [`Reducer::finish_with`].
    pub fn ranks(&self) -> Vec<(u64, u64)> {
        let mut points = self.points.clone();
        points.sort_by_key(|p| p.point);
        points.dedup_by_key(|p| p.point);
        let ranking = &self.study.ranking;
        rank::apply(&mut points, ranking.wf1, ranking.wf2);
        let mut ranked: Vec<(u64, u64)> = points
            .iter()
            .filter_map(|p| p.rank.map(|r| (p.point, r)))
            .collect();
        ranked.sort_by_key(|&(_, r)| r);
        ranked
    }

    /// Reduces one design point's runs again, in place of what [`Reducer::push`] made of them
    /// (its runs measured again); a point not reduced yet is added.
    pub fn replace(&mut self, runs: &[Run]) {
        let Some(first) = runs.first() else {
            return;
        };
        let stats = self.point_stats(runs);
        if first.point == self.nominal_point {
            self.nominal = Some((self.nominal_point, runs.to_vec()));
        }
        match self.points.iter_mut().find(|p| p.point == first.point) {
            Some(p) => *p = stats,
            None => self.points.push(stats),
        }
    }

    /// The study reduced (its scene's study: a harmonic study's designs,
    /// [`crate::reduce::harmonic::design_study`]).
    pub fn study(&self) -> &'a Study {
        self.study
    }

    /// Lets a scene replace what its designs' runs give by its own estimate before the ranking
    /// (a random study's subset simulation of `p_f`, [`crate::reduce::random::subset`]): `f`
    /// gets the designs reduced so far, in design order.
    pub fn adjust(&mut self, f: impl FnOnce(&mut [PointStats])) {
        self.points.sort_by_key(|p| p.point);
        self.points.dedup_by_key(|p| p.point);
        f(&mut self.points);
    }

    /// Everything that needs the whole sweep, with `ideal` the study's ideal case anywhere in
    /// the design space (where the jumps are located): the scene's own
    /// ([`crate::reduce::free::finish`] simulates it; the harmonic scene continues its stored
    /// attractors, [`crate::reduce::harmonic::probe::HarmonicIdeal`]), or a function on synthetic
    /// data in tests.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::free;
    use crate::reduce::testing::*;
    use crate::sim::Outcome;

    fn points(rs_dis: &[(f64, f64)]) -> Vec<PointStats> {
        let s = study(
            vec![("e", (0..rs_dis.len()).map(|i| i as f64).collect())],
            1,
        );
        let r = Reducer::new(&s, free::options(&s));
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
    fn a_design_point_costs_a_fixed_256_bytes() {
        // Issue 10: memory grows with design points, never with runs; a point holds no heap
        // data (its values come from the grid, its zone is an index).
        assert!(std::mem::size_of::<PointStats>() <= 256);
    }
}
