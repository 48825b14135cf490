//! Unit tests of the random scene's reduction.

use super::*;
use crate::reduce::testing;
use crate::sim::Scene;
use crate::sim::random::RandomScene;
use crate::stats::binomial::clopper_pearson;

#[test]
fn a_design_and_its_intensity_give_back_the_design_point() {
    // m (2) x S0 (3) x d (2): the intensity in the middle of the axes.
    let mut s = testing::study(
        vec![
            ("m", vec![0.0, 0.05]),
            ("S0", vec![0.001, 0.01, 0.1]),
            ("d", vec![0.01, 0.02]),
        ],
        1,
    );
    s.scene = Scene::Random(RandomScene::placeholder());
    let design = design_study(&s);
    assert_eq!(design.axes.len(), 2);
    let Scene::Random(r) = &design.scene else {
        panic!()
    };
    assert_eq!(r.get("S0"), Some(0.01));
    let reducer = RandomReducer::new(&s, &design, options(&design));
    let rs = RandomSummary {
        threshold: None,
        realizations: 1,
        record: false,
        intensity: intensity(&s),
        points: Vec::new(),
        fragility: Vec::new(),
        stripes_interval: Vec::new(),
        subset: Vec::new(),
        capacity_rank: Vec::new(),
        measure: None,
        hazard: None,
        risk: Vec::new(),
        capacities: Vec::new(),
    };
    let mut seen = Vec::new();
    for p in 0..12 {
        let (d, j) = reducer.split(p);
        assert!(d < 4 && j < 3);
        assert_eq!(rs.grid_point(d, j, &[2, 2]), p);
        seen.push((d, j));
    }
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), 12);
}

#[test]
fn p_f_is_the_share_that_passed_with_its_exact_interval() {
    let s = testing::study(vec![("m", vec![0.0])], 1);
    let row = |amplitude: f64, outcome: Outcome| RunRow {
        point_id: 0,
        point: 0,
        case: 0,
        ideal: false,
        dm: 0.0,
        dd: 0.0,
        noise_seed: Some(0),
        system: s.system,
        solver: "exact".into(),
        tol: 1e-12,
        record: RealizationRecord {
            load: [None; 7],
            own: None,
            capacity: None,
            record: crate::sim::random::RandomRecord {
                outcome,
                amplitude,
                t_peak: 0.0,
                rms_x: amplitude / 2.0,
                rms_acc: 0.0,
                first_passage_time: None,
                impacts: 0,
                sticks: 0,
                energy_impact: 0.0,
                samples: 1,
                t_stop: 1.0,
                steps: 1,
            },
        },
    };
    // 3 of 8 ok runs pass 1 cm; the run that stopped early is not counted.
    let mut rows: Vec<_> = [0.5, 2.0, 0.7, 1.5, 0.9, 3.0, 0.2, 0.4]
        .iter()
        .map(|a| row(a * 0.01, Outcome::Ok))
        .collect();
    rows.push(row(f64::NAN, Outcome::EventCap));
    let p = PointPf::of(0, &rows, Some(0.01));
    assert_eq!((p.n, p.exceed, p.p_f), (8, 3, 0.375));
    let ci = clopper_pearson(3, 8, 0.95);
    assert_eq!((p.p_f_lo, p.p_f_hi), (ci.lo, ci.hi));
    assert!((p.beta - 0.318_639).abs() < 1e-5, "{}", p.beta);
    // Without a threshold: no p_f.
    assert!(PointPf::of(0, &rows, None).p_f.is_nan());
    // The core's view: 1 when it stayed within, 0 when it passed.
    assert_eq!(run_of(&rows[1], 0, Some(0.01)).di, 0.0);
    assert_eq!(run_of(&rows[0], 0, Some(0.01)).di, 1.0);
}

/// Where subset simulation's levels never passed the limit (its `p_f` 0, its interval `[0, 1]`
/// from `0 x inf`), the summary's `p_f`, interval, `beta` and CoVs are Monte Carlo's, as the
/// report's and the charts' are: one design, one set of numbers.
#[test]
fn a_subset_that_never_passed_leaves_the_summary_to_monte_carlo() {
    let s = testing::study(vec![("m", vec![0.0, 0.05])], 1);
    let summary = testing::reduce_simulated(&s);
    let mc = |point: u64, exceed: u64| {
        let ci = clopper_pearson(exceed, 200, 0.95);
        PointPf {
            point,
            n: 200,
            exceed,
            p_f: exceed as f64 / 200.0,
            p_f_lo: ci.lo,
            p_f_hi: ci.hi,
            beta: f64::INFINITY,
            rms_x_mean: 0.001,
        }
    };
    let subset = |p_f: f64, lo: f64, hi: f64| SubsetPf {
        p_f,
        cov: if p_f > 0.0 { 0.3 } else { f64::INFINITY },
        cov_upper: if p_f > 0.0 { 0.5 } else { f64::INFINITY },
        lo,
        hi,
        levels: 6,
        runs: 5_000,
        converged: p_f > 0.0,
        repeats: 1,
        cov_repeats: f64::NAN,
    };
    let rs = RandomSummary {
        threshold: Some(0.05),
        realizations: 200,
        record: false,
        intensity: None,
        points: vec![mc(0, 0), mc(1, 0)],
        fragility: Vec::new(),
        stripes_interval: Vec::new(),
        // Design 0: the levels never passed; design 1: an estimate.
        subset: vec![(0, subset(0.0, 0.0, 1.0)), (1, subset(2e-6, 1e-6, 4e-6))],
        capacity_rank: Vec::new(),
        measure: None,
        hazard: None,
        risk: Vec::new(),
        capacities: Vec::new(),
    };
    assert!(rs.subset_estimate(0).is_none());
    assert_eq!(rs.subset_estimate(1).map(|x| x.p_f), Some(2e-6));
    let bound = clopper_pearson(0, 200, 0.95).hi;
    assert_eq!(rs.design_pf(0, &[2]), Some((0.0, 0.0, bound)));
    assert_eq!(rs.design_pf(1, &[2]), Some((2e-6, 1e-6, 4e-6)));
    let rows: Vec<&PointStats> = summary.points.iter().collect();
    let mut t = Table::default();
    summary_columns(&mut t, &summary, &rs, &rows);
    let col = |name: &str| match t.get(name) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    };
    assert_eq!(col("p_f"), vec![0.0, 2e-6]);
    assert_eq!(col("p_f_hi"), vec![bound, 4e-6]);
    assert_eq!(col("p_f_lo"), vec![0.0, 1e-6]);
    assert_eq!(col("p_f_cov")[1], 0.3);
    // Which method ran stays said: subset simulation ran on both.
    match t.get("p_f_method") {
        Some(Column::Str(v)) => assert_eq!(v, &vec!["subset_unconverged", "subset"]),
        other => panic!("{other:?}"),
    }
}
