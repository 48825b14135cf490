//! The low-`p_f` route of the random scene's reduction (model.md §13): a design whose
//! realizations passed the threshold fewer than [`SUBSET_BELOW`] times, where Monte Carlo's
//! estimate rests on too few failures, gets `p_f` by subset simulation
//! ([`crate::stats::subset`], Au and Beck 2001) over its realization's white-noise samples as
//! standard normals: the same simulator, the normals handed in as a slice
//! ([`GivenNormals`]), the response `max |x|` (NaN, i.e. not failing, for a run that did not
//! end `ok`); at a stripe of an intensity measure, of each sample's motion scaled to the stripe
//! as the sweep scales its realizations ([`RandomRun::at_stripe`]). Seeded by the study seed
//! alone, the same seed at every design point (common random numbers, as the sweep's
//! realizations: identical designs get identical estimates and two designs are compared on
//! correlated samples), so the same bits on any thread count. Asked for by `reduce --subset N` (`N` samples per level); a record has no normals to
//! sample and keeps Monte Carlo.
//!
//! Its interval is a lognormal one on the method's coefficient of variation with fully
//! correlated levels (`cov_upper`, the conservative bound):
//! `p exp(-+1.96 sigma)`, `sigma^2 = ln(1 + cov_upper^2)`, the upper end at most 1.
//!
//! With `reduce --subset-repeats R` (`R > 1`) each such design runs `R` independent subset
//! simulations ([`subset_repeats`]: repeat 0 on the seed of a single run, the others on seeds
//! mixed from it and the repeat's index), and its `p_f` is their mean. The interval is then
//! the repeats': `p exp(-+t sigma)`, `sigma^2 = ln(1 + cov^2)` with `cov` the mean's coefficient
//! of variation measured from the repeats' spread (`cov_repeats / sqrt(R)`) and `t` Student's
//! 0.975 quantile with `R - 1` degrees of freedom, the upper end at most 1; `cov` is that measured
//! CoV of the mean, `cov_upper` the runs' mean stated bound over `sqrt(R)`. The repeats measure
//! the error that the stated CoVs can only bound (model.md §13): `R` times the runs.

use crate::numeric::mix64;
use crate::plan::Plan;
use crate::sim::random::{GivenNormals, RandomRun};
use crate::stats::fragility::Z95;
use crate::stats::subset::{SubsetOutcome, SubsetSettings, subset_repeats};
use crate::study::Study;

/// Exceedances below which a design's `p_f` is estimated by subset simulation as well: Monte
/// Carlo's coefficient of variation `sqrt((1 - p) / (n p))` is then above about 0.3.
pub const SUBSET_BELOW: u64 = 10;

/// Samples per level by default (Au and Beck's choice): about 1,000 runs per decade of `p_f`.
pub const DEFAULT_SUBSET_N: usize = 1000;

/// Runs at most per design by default: with [`DEFAULT_SUBSET_N`] per level, 11 levels
/// (`p_f` down to about 1e-11), and never fewer than 6 levels (1e-6) for another `n`.
pub const MAX_SUBSET_RUNS: usize = 10_000;

/// A subset simulation's estimate of a design point's `p_f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubsetPf {
    pub p_f: f64,
    /// Its coefficient of variation with uncorrelated levels, and with fully correlated ones.
    pub cov: f64,
    pub cov_upper: f64,
    /// The interval (module doc).
    pub lo: f64,
    pub hi: f64,
    /// Levels run (the most of any repeat) and responses evaluated (over every repeat).
    pub levels: u64,
    pub runs: u64,
    /// Whether the last level reached the threshold (of every repeat).
    pub converged: bool,
    /// Independent runs whose mean is `p_f` (1: a single run; module doc).
    pub repeats: u64,
    /// The sample coefficient of variation of one run's estimate over the repeats (NaN for one
    /// repeat); `cov` is then that of their mean.
    pub cov_repeats: f64,
}

/// What `reduce --subset N --subset-repeats R` asks for: `n` samples per level, `repeats`
/// independent runs per design (at least 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubsetAsk {
    pub n: usize,
    pub repeats: usize,
}

impl SubsetAsk {
    /// One run of `n` per level.
    pub fn single(n: usize) -> Self {
        SubsetAsk { n, repeats: 1 }
    }
}

/// `p_f = P(max |x| > b)` of design point `point` of `study` by subset simulation with
/// `ask.n` samples per level, the mean of `ask.repeats` independent runs (module doc); `None`
/// for a record (no normals) or settings subset simulation refuses (`n` a multiple of 10, at
/// least 100).
pub fn subset_pf(study: &Study, point: u64, b: f64, ask: SubsetAsk) -> Option<SubsetPf> {
    let (sys, scene) = Plan::new(study).point(point);
    let scene = scene.random()?;
    if !scene.draws_normals() {
        return None;
    }
    let setup = RandomRun::new(&sys, &study.solver, scene);
    let settings = settings_for(study, ask.n);
    // (The amplitude alone, NaN for a run that did not end `ok`.) At a stripe each sample's
    // motion is scaled to it as the sweep scales its realizations: the load's own level then
    // scales out.
    let rep = subset_repeats(
        setup.n_normals(),
        b,
        &settings,
        ask.repeats,
        |u| match &scene.intensity {
            Some(spec) => {
                let block = setup.load(GivenNormals::new(u));
                let (_, gain) = setup.at_stripe(spec, scene.im, &block);
                setup.amplitude_block(&study.request, &block, gain)
            }
            None => setup.amplitude(&study.request, GivenNormals::new(u)),
        },
    );
    if rep.runs.iter().any(|r| r.outcome == SubsetOutcome::Invalid) {
        return None;
    }
    let r = &rep.runs[0];
    let k = rep.runs.len();
    let (cov, cov_upper, t) = if k > 1 {
        let cov = if rep.p_f > 0.0 {
            rep.cov_mean
        } else {
            f64::INFINITY
        };
        (
            cov,
            rep.stated_cov_upper / (k as f64).sqrt(),
            student_975(k - 1),
        )
    } else {
        (r.cov, r.cov_upper, Z95)
    };
    // The single run's interval rests on its stated bound; the repeats' on their spread.
    let spread = if k > 1 { cov } else { cov_upper };
    let sigma = (1.0 + spread * spread).ln().sqrt();
    Some(SubsetPf {
        p_f: rep.p_f,
        cov,
        cov_upper,
        lo: rep.p_f * (-t * sigma).exp(),
        hi: (rep.p_f * (t * sigma).exp()).min(1.0),
        levels: rep
            .runs
            .iter()
            .map(|r| r.levels.len() as u64)
            .max()
            .unwrap_or(0),
        runs: rep.runs.iter().map(|r| r.evaluations).sum(),
        converged: rep
            .runs
            .iter()
            .all(|r| r.outcome == SubsetOutcome::Converged),
        repeats: k as u64,
        cov_repeats: rep.cov_run,
    })
}

/// The settings of a design's subset simulation in `study` with `n` samples per level: seeded
/// by the study's seed alone, at most [`MAX_SUBSET_RUNS`] runs (6 to 20 levels).
pub fn settings_for(study: &Study, n: usize) -> SubsetSettings {
    // Each level after the first adds n (1 - p0) runs.
    let per_level = (n - n / 10).max(1);
    SubsetSettings {
        n,
        seed: mix64(study.seed ^ 0x5B5E_75B5),
        max_levels: (1 + MAX_SUBSET_RUNS.saturating_sub(n) / per_level).clamp(6, 20),
        ..SubsetSettings::default()
    }
}

/// Student's t 0.975 quantile with `dof` degrees of freedom (at least 1).
fn student_975(dof: usize) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    StudentsT::new(0.0, 1.0, dof as f64).map_or(Z95, |t| t.inverse_cdf(0.975))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::testing;
    use crate::sim::random::{Excitation, Input, RandomLoad, RandomScene, Spectrum};
    use crate::sim::{NoProbe, Scene};
    use crate::stats::subset::repeat_seed;

    /// The structure alone (Table I, `m = 0`) under 1 s of white ground acceleration, and a
    /// threshold about 0.2 % of its realizations pass.
    fn white() -> (Study, f64) {
        let mut s = testing::study(vec![("m", vec![0.0])], 1);
        let scene = RandomScene {
            input: Input::Base,
            excitation: Excitation::Random(RandomLoad {
                spectrum: Spectrum::White,
                S0: 1.0,
                envelope: None,
            }),
            dt: 0.01,
            duration: 1.0,
            threshold: None,
            intensity: None,
            im: None,
        };
        s.scene = Scene::Random(scene);
        let (sys, Scene::Random(scene)) = Plan::new(&s).point(0) else {
            panic!()
        };
        let run = RandomRun::new(&sys, &s.solver, &scene);
        let mut a: Vec<f64> = (0..2000)
            .map(|r| {
                let n = crate::sim::random::RealizationStream::new(1, 0, r);
                run.run(&s.request, n, &mut NoProbe).amplitude
            })
            .collect();
        a.sort_by(f64::total_cmp);
        (s, a[1996])
    }

    /// The structure alone under white ground acceleration at own level `s0`, each motion
    /// scaled to a PGA stripe of 0.2 g.
    fn stripe(s0: f64) -> Study {
        let (mut s, _) = white();
        if let Scene::Random(scene) = &mut s.scene {
            scene.excitation = Excitation::Random(RandomLoad {
                spectrum: Spectrum::White,
                S0: s0,
                envelope: None,
            });
            scene.intensity = Some(crate::sim::random::IntensitySpec {
                measure: crate::sim::random::Measure::Pga,
                period: 0.5,
                ida_tol: 0.01,
                ida_max: 10.0,
            });
            scene.im = Some(0.2);
        }
        s
    }

    #[test]
    fn at_a_stripe_each_sample_is_scaled_to_it_so_the_loads_own_level_scales_out() {
        // A threshold about 0.2 % of the stripe's motions pass, as the sweep scales them.
        let s = stripe(1.0);
        let (sys, Scene::Random(scene)) = Plan::new(&s).point(0) else {
            panic!()
        };
        let run = RandomRun::new(&sys, &s.solver, &scene);
        let spec = scene.intensity.unwrap();
        let mut a: Vec<f64> = (0..2000)
            .map(|r| {
                let n = crate::sim::random::RealizationStream::new(1, 0, r);
                let block = run.load(n);
                let (own, gain) = run.at_stripe(&spec, scene.im, &block);
                assert!((gain * own.pga - 0.2).abs() < 1e-12);
                run.amplitude_block(&s.request, &block, gain)
            })
            .collect();
        a.sort_by(f64::total_cmp);
        let b = a[1996];
        let strong = subset_pf(&s, 0, b, SubsetAsk::single(200)).unwrap();
        // The motions at their own level pass far more often (S0 = 1) or never (S0 = 1e-6): the
        // estimate must not follow them.
        let weak = subset_pf(&stripe(1e-6), 0, b, SubsetAsk::single(200)).unwrap();
        assert!(
            (strong.p_f - weak.p_f).abs() <= 1e-6 * strong.p_f,
            "{} against {}",
            strong.p_f,
            weak.p_f
        );
        assert!(
            (5e-4..8e-3).contains(&strong.p_f),
            "p_f {} where about 2e-3 of the stripe's motions pass",
            strong.p_f
        );
    }

    #[test]
    fn repeats_give_the_mean_of_independent_runs_and_an_interval_from_their_spread() {
        let (s, b) = white();
        let one = subset_pf(&s, 0, b, SubsetAsk::single(100)).unwrap();
        assert_eq!(one.repeats, 1);
        assert!(one.cov_repeats.is_nan());
        let sigma = (1.0 + one.cov_upper * one.cov_upper).ln().sqrt();
        assert_eq!(one.lo, one.p_f * (-Z95 * sigma).exp());
        let ask = SubsetAsk { n: 100, repeats: 8 };
        let rep = subset_pf(&s, 0, b, ask).unwrap();
        assert_eq!(rep.repeats, 8);
        // Repeat 0 is the single run; the mean is over 8 runs on their own seeds.
        let settings = settings_for(&s, 100);
        let (sys, Scene::Random(scene)) = Plan::new(&s).point(0) else {
            panic!()
        };
        let run = RandomRun::new(&sys, &s.solver, &scene);
        let p: Vec<f64> = (0..8)
            .map(|r| {
                let st = SubsetSettings {
                    seed: repeat_seed(settings.seed, r),
                    ..settings
                };
                crate::stats::subset::subset_simulation(run.n_normals(), b, &st, |u| {
                    run.run(&s.request, GivenNormals::new(u), &mut NoProbe)
                        .amplitude
                })
                .p_f
            })
            .collect();
        assert_eq!(p[0], one.p_f);
        let mean = p.iter().sum::<f64>() / 8.0;
        assert!((rep.p_f - mean).abs() <= 1e-15 * mean);
        let sd = (p.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 7.0).sqrt();
        assert!((rep.cov_repeats - sd / mean).abs() < 1e-12);
        assert!((rep.cov - sd / mean / 8f64.sqrt()).abs() < 1e-12);
        // Student's t with 7 degrees of freedom.
        let s_log = (1.0 + rep.cov * rep.cov).ln().sqrt();
        assert!((rep.hi / rep.p_f - (2.364_624 * s_log).exp()).abs() < 1e-5);
        assert!(rep.lo < rep.p_f && rep.p_f < rep.hi);
        assert!(rep.runs > 8 * 100 && rep.runs >= one.runs);
    }
}
