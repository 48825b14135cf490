//! The streaming reduction of a harmonic study's parts ([`HarmonicReducer`]): each design's runs →
//! one core [`Run`] per case (its peak amplitude and peak reduction over the band) and the ideal
//! case's [`Curve`]; then the core's reduction over the designs, its jumps located by
//! [`HarmonicIdeal`].

use super::analysis::{Plan, Probes};
use super::curve::{Curve, CurvePoint};
use super::design::design_peak;
use super::probe::HarmonicIdeal;
use super::summary::HarmonicSummary;
use super::verify::{self, CasePeak, CaseTop, LifeQuestion, Verification};
use crate::orbits::attractors::AttractorRow;
use crate::reduce::common::{Options, Reducer, Run, Summary, outcome_index};
use crate::sim::harmonic::{DesignPeak, LifeCurve, NonPeriodicPeak};
use crate::sim::{HarmonicRecord, Outcome};
use crate::store::RunRow;
use crate::study::Study;

/// The streaming reduction of a harmonic study's parts.
pub struct HarmonicReducer<'a> {
    study: &'a Study,
    reducer: Reducer<'a>,
    /// Frequencies per curve and cases per design point.
    n_f: u64,
    n_cases: u64,
    /// Rows of a design whose curve is not complete yet (a chunk that ended inside a curve).
    pending: Vec<RunRow<HarmonicRecord>>,
    /// The ideal case's stored attractors, by design.
    attractors: std::collections::BTreeMap<u64, Vec<AttractorRow>>,
    /// Whether the parts came with attractors.
    stored: bool,
    curves: Vec<Curve>,
    runs: u64,
    outcomes: [u64; 6],
    /// Which steady state is the design quantity.
    peak: DesignPeak,
    /// What a verification needs of each design and case ([`verify`]): its highest motions
    /// that are not periodic, its system and linear peak (m), and each design's runs.
    tops: std::collections::BTreeMap<(u64, u32), CaseTop>,
    systems: std::collections::BTreeMap<(u64, u32), (crate::model::System, f64)>,
    runs_of: std::collections::BTreeMap<u64, Vec<Run>>,
}

impl<'a> HarmonicReducer<'a> {
    /// `design` is [`super::design_study`] of `study`; `options` usually [`super::options`] of it.
    pub fn new(study: &'a Study, design: &'a Study, options: Options) -> Self {
        HarmonicReducer {
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
            tops: Default::default(),
            systems: Default::default(),
            runs_of: Default::default(),
        }
    }

    /// Reduces one part's rows (whole curves, in `point_id` order): one reducer run per design
    /// and case, and the ideal case's curve; `attractors` are the part's stored attractors
    /// (`None`: a dataset written before the sweep stored them).
    pub fn push(
        &mut self,
        rows: Vec<RunRow<HarmonicRecord>>,
        attractors: Option<Vec<AttractorRow>>,
    ) {
        self.stored |= attractors.is_some();
        for a in attractors.into_iter().flatten() {
            let design = a.run.point / self.n_f;
            self.tops
                .entry((design, a.run.case))
                .or_default()
                .add(&a, design);
            if a.run.ideal {
                self.attractors.entry(design).or_default().push(a);
            }
        }
        for r in &rows {
            self.runs += 1;
            self.outcomes[outcome_index(r.record.outcome)] += 1;
        }
        let mut rows = rows;
        if !self.pending.is_empty() {
            let mut all = std::mem::take(&mut self.pending);
            all.append(&mut rows);
            rows = all;
        }
        let full = (self.n_f * self.n_cases) as usize;
        let n_f = self.n_f;
        let mut groups: Vec<&[RunRow<HarmonicRecord>]> = rows
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
    fn design(&mut self, rows: &[RunRow<HarmonicRecord>], runs: &mut Vec<Run>) {
        let design = rows[0].point / self.n_f;
        let from = runs.len();
        let mut cases: Vec<u32> = rows.iter().map(|r| r.case).collect();
        cases.sort_unstable();
        cases.dedup();
        for c in cases {
            let of_case: Vec<&RunRow<HarmonicRecord>> =
                rows.iter().filter(|r| r.case == c).collect();
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
            self.systems.insert((design, c), (first.system, linear));
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
        self.runs_of.insert(design, runs[from..].to_vec());
    }

    /// Whether this reduction verifies the deciding designs ([`verify`]): peaks of the worst
    /// steady state with stored attractors, design-life amplitudes and `[ranking]
    /// verify_periods` above 0 (a motion of several units restarts from its stored
    /// `section_units`). (A shard of the analysis measures its share of the cases.)
    fn verifies(&self) -> bool {
        self.study.ranking.verify_periods > 0
            && self.stored
            && self.peak == DesignPeak::Worst
            && self
                .study
                .scene
                .harmonic()
                .is_some_and(|h| h.nonperiodic_peak == NonPeriodicPeak::Life)
    }

    /// The verification ([`verify`]): the deciding designs' cases measured directly (those
    /// `plan`'s earlier shards measured taken from them), their runs reduced again and the ideal
    /// curves' peaks updated. Then again, in rounds, while the ranking so moved has a best design
    /// (or one overlapping it) not verified yet: the best-ranked design of the final ranking
    /// always rests on direct measurements. A shard of the analysis measures only its share of
    /// the first round's cases ([`verify::share`]) and changes nothing: the final reduction takes
    /// its measurements and runs the rounds after (they depend on every shard's).
    fn verify(&mut self, plan: &Plan) -> Verification {
        let Some(&h) = self.study.scene.harmonic() else {
            return Verification::default();
        };
        let life = LifeQuestion {
            design_life: h.design_life,
            quantile: h.life_quantile,
            periods: self.study.ranking.verify_periods,
        };
        let ranks_before = self.reducer.ranks();
        let mut v = Verification {
            periods: life.periods,
            ranks_before,
            ..Verification::default()
        };
        loop {
            let new: Vec<u64> = self
                .deciding()
                .into_iter()
                .filter(|d| !v.designs.contains(d))
                .collect();
            if new.is_empty() {
                break;
            }
            let todo = self.cases_to_verify(&new);
            if let Some(shard) = plan.shard {
                let mine: Vec<_> = verify::share(&todo, shard.index, shard.count)
                    .cloned()
                    .collect();
                v.peaks = verify::verify_all(&mine, &self.study.solver, life, &plan.prior.verified);
                v.designs = new;
                v.rounds = 1;
                return v;
            }
            let mut peaks =
                verify::verify_all(&todo, &self.study.solver, life, &plan.prior.verified);
            self.take_verified(&peaks, &new);
            v.rounds += 1;
            for p in &mut peaks {
                p.round = v.rounds;
            }
            v.designs.extend(new);
            v.peaks.extend(peaks);
        }
        v.designs.sort_unstable();
        // In design and case order whatever the rounds (each case is verified once).
        v.peaks.sort_by_key(|p| (p.design, p.case));
        v
    }

    /// The designs that decide the ranking as it stands ([`verify::deciding`]).
    fn deciding(&self) -> Vec<u64> {
        let curves = &self.curves;
        let interval = |d: u64| {
            curves
                .binary_search_by_key(&d, |c| c.design)
                .ok()
                .and_then(|i| curves[i].peak_interval())
        };
        verify::deciding(&self.reducer.ranks(), interval)
    }

    /// The cases of `designs` a verification measures: those whose runs succeeded and kept a
    /// motion that is not periodic.
    fn cases_to_verify(&self, designs: &[u64]) -> Vec<verify::CaseToVerify<'_>> {
        let mut todo = Vec::new();
        for &d in designs {
            for r in self.runs_of.get(&d).into_iter().flatten() {
                let key = (d, r.case);
                if let (Some(top), Some(&(sys, _))) = (self.tops.get(&key), self.systems.get(&key))
                    && r.outcome == Outcome::Ok
                    && !top.top.is_empty()
                {
                    todo.push((key, top, sys, r.response));
                }
            }
        }
        todo
    }

    /// Takes in one round's case peaks: each case's run and its ideal curve get the new peak,
    /// and `designs` are reduced again.
    fn take_verified(&mut self, peaks: &[CasePeak], designs: &[u64]) {
        for p in peaks {
            let linear = self
                .systems
                .get(&(p.design, p.case))
                .map_or(f64::NAN, |s| s.1);
            if let Some(run) = self
                .runs_of
                .get_mut(&p.design)
                .and_then(|rs| rs.iter_mut().find(|r| r.case == p.case))
            {
                run.response = p.after;
                run.di = 1.0 - p.after / linear;
                if run.ideal
                    && let Ok(i) = self.curves.binary_search_by_key(&p.design, |c| c.design)
                {
                    for v in &p.verified {
                        self.curves[i].take_verified(v);
                    }
                }
            }
        }
        for d in designs {
            if let Some(rs) = self.runs_of.get(d) {
                self.reducer.replace(rs);
            }
        }
    }

    /// Everything that needs all the designs (the core's [`Reducer::finish_with`], its jumps
    /// located with [`HarmonicIdeal`]), and the curves.
    ///
    /// `plan` says whether this is one shard of the analysis and what earlier shards computed;
    /// the jump probes computed here are returned with the summaries (what a shard stores).
    pub fn finish(mut self, plan: &Plan) -> (Summary, HarmonicSummary, Probes) {
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
            c.count_mirror_images();
        }
        let verification = if self.verifies() {
            self.verify(plan)
        } else {
            Verification::default()
        };
        let harmonic = self.study.scene.harmonic();
        let ideal = HarmonicIdeal::new(self.study, &self.curves, plan);
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
            HarmonicSummary {
                frequency,
                curves: self.curves,
                runs: self.runs,
                outcomes: self.outcomes,
                design_peak: self.peak,
                analysis: plan.clone(),
                design_life: harmonic.map_or(f64::NAN, |h| h.design_life),
                life_quantile: harmonic.map_or(f64::NAN, |h| h.life_quantile),
                nonperiodic_peak: harmonic.map_or(NonPeriodicPeak::Life, |h| h.nonperiodic_peak),
                life_curve: harmonic.map_or(LifeCurve::Decisions, |h| h.life_curve),
                curve_lines: Default::default(),
                verification,
            },
            probes,
        )
    }
}
