//! Issue 10: the reducer in N dimensions. Zones are connected regions, the recommended design
//! is robust, the maps show the real slices (a map's data is exactly the summary rows of its
//! slice), the edge warning appears when the best designs sit on the edge, and the report reads
//! at the size of configs/overnight.toml (44,541 design points: no table over 30 rows).

use std::path::Path;

use crate::common;

use impactsweep::api::reduce::write_outputs;
use impactsweep::reduce::free;
use impactsweep::reduce::testing::{FnIdeal, paper_study, reduce_simulated, row, study};
use impactsweep::reduce::{Reducer, Summary};
use impactsweep::sim::Outcome;
use impactsweep::study::{Axis, Study};

fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The paper's system and 12 cases over e (21 values) × m (6) × d (6): the 21 × 6 × 6 study of
/// the issue, whose zones used to fall apart into pieces.
fn three_axes() -> (Study, Summary) {
    let mut s = paper_study();
    s.axes = vec![
        Axis {
            key: "e".into(),
            values: linspace(0.45, 0.95, 21),
        },
        Axis {
            key: "m".into(),
            values: linspace(0.01, 0.03, 6),
        },
        Axis {
            key: "d".into(),
            values: linspace(0.005, 0.015, 6),
        },
    ];
    s.run.chunk_points = 100;
    s.reliability.bootstrap = 500;
    let sum = reduce_simulated(&s);
    (s, sum)
}

#[test]
fn issue_10_three_axes_zones_are_connected_regions_and_the_recommendation_is_robust() {
    let (_, sum) = three_axes();
    let g = &sum.grid;
    assert_eq!(sum.points.len(), 756);
    // Every zone is one connected region: a flood fill from its first point inside the zone
    // reaches all its points.
    for (z, zone) in sum.zones.iter().enumerate() {
        let members: Vec<u64> = sum
            .points
            .iter()
            .filter(|p| p.zone == z as u32)
            .map(|p| p.point)
            .collect();
        assert_eq!(members.len(), zone.n_points);
        let mut seen = std::collections::HashSet::from([members[0]]);
        let mut stack = vec![members[0]];
        while let Some(p) = stack.pop() {
            for a in 0..3 {
                for d in [-1, 1] {
                    if let Some(q) = g.step(p, a, d)
                        && sum.point(q).unwrap().zone == z as u32
                        && seen.insert(q)
                    {
                        stack.push(q);
                    }
                }
            }
        }
        assert_eq!(seen.len(), members.len(), "zone {} falls apart", zone.name);
        // Its bounding box holds its points, its best and representative points are its own.
        for &p in &members {
            for (a, (lo, hi)) in zone.ranges.iter().enumerate() {
                assert!((*lo..=*hi).contains(&g.value(p, a)));
            }
        }
        assert!(zone.representative.is_some_and(|p| members.contains(&p)));
    }
    // The recommended design: the best rank among robust points, and robust by the definition
    // checked here from scratch.
    let rec = sum.recommended.expect("a robust design");
    let p = sum.point(rec).unwrap();
    assert!(p.robust && p.all_ok && p.class.recommended());
    for a in 0..3 {
        assert!(g.end(rec, a).is_none(), "on an edge of axis {a}");
    }
    for q in g.neighbourhood(rec) {
        let n = sum.point(q).unwrap();
        let class = sum.zone_of(n).and_then(|z| z.class).unwrap();
        assert!(class.recommended(), "neighbour {q} is {class:?}");
    }
    assert_eq!(g.neighbourhood(rec).len(), 27);
    let better_robust = sum
        .points
        .iter()
        .filter(|q| q.robust && q.rank < p.rank)
        .count();
    assert_eq!(better_robust, 0);
}

#[test]
fn issue_10_a_maps_data_is_the_summary_rows_of_its_slice() {
    let (s, sum) = three_axes();
    let tmp = tempfile::tempdir().unwrap();
    let keep = std::env::var_os("IMPACTSWEEP_KEEP_CHARTS").map(|d| Path::new(&d).join("nd"));
    let dir = keep.as_deref().unwrap_or(tmp.path());
    write_outputs(&s, &sum, dir, None).unwrap();
    let rec = sum.recommended.unwrap();
    let g = &sum.grid;
    // (stem, the axes the chart varies)
    let charts = [
        ("perfectibility_map_e_mass_inner", vec![0, 1]),
        ("zone_map_e_mass_inner", vec![0, 1]),
        ("perfectibility_map_e_d", vec![0, 2]),
        ("zone_map_e_d", vec![0, 2]),
        ("perfectibility_map_mass_inner_d", vec![1, 2]),
        ("zone_map_mass_inner_d", vec![1, 2]),
        ("design_chart_e", vec![0]),
        ("design_chart_mass_inner", vec![1]),
        ("design_chart_d", vec![2]),
        ("xmax_spread_e", vec![0]),
    ];
    for (stem, free) in charts {
        // Its data: summary rows, the columns it draws.
        let points = common::chart_rows_are_summary_rows(
            &dir.join(format!("{stem}.csv")),
            &dir.join("summary.csv"),
        );
        // The slice: every point equal to the recommended design on the other axes.
        let slice: Vec<u64> = (0..g.len())
            .filter(|&p| (0..3).all(|a| free.contains(&a) || g.index(p, a) == g.index(rec, a)))
            .collect();
        assert_eq!(points, slice, "{stem}");
        // The title names the slice.
        let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
        let fixed: Vec<usize> = (0..3).filter(|a| !free.contains(a)).collect();
        for a in fixed {
            let key = g.key(a);
            let v = impactsweep::report::charts::fmt_num(g.value(rec, a));
            assert!(
                svg.contains(&format!("{key} = {v}")),
                "{stem}.svg does not name {key} = {v}"
            );
        }
    }
    // Three axes: the zones as small multiples over e.
    assert!(dir.join("zone_maps_e.png").exists());
}

/// Rows of every markdown table in `md`.
fn table_lengths(md: &str) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    let mut heading = String::new();
    let mut n: Option<usize> = None;
    for line in md.lines().chain(std::iter::once("")) {
        if line.starts_with('|') {
            n = Some(n.map_or(0, |k| k + 1));
        } else {
            if let Some(k) = n.take() {
                // Minus the header's rule line.
                out.push((heading.clone(), k.saturating_sub(1)));
            }
            if let Some(h) = line.strip_prefix("## ") {
                heading = h.to_string();
            }
        }
    }
    out
}

#[test]
fn issue_10_the_report_reads_at_44541_points_and_warns_about_the_edge() {
    // configs/overnight.toml's grid (101 x 21 x 21), synthetic runs: xmax grows with e, falls
    // with m; DI grows with m and d, so the best designs sit at the largest m and d; a step of
    // xmax crosses the grid at e = 0.6 + 5 (m - 0.01) (a jump surface); 2 cases per point.
    let e = linspace(0.45, 0.95, 101);
    let m = linspace(0.01, 0.03, 21);
    let d = linspace(0.005, 0.015, 21);
    let mut s = study(vec![("e", e), ("m", m), ("d", d)], 2);
    s.reliability.bootstrap = 20;
    s.reliability.strength_mean = 285e6;
    s.reliability.strength_sd = 20e6;
    let ideal = |v: &[f64]| {
        let step = if v[0] > 0.6 + 5.0 * (v[1] - 0.01) {
            0.001
        } else {
            0.0
        };
        let x = 0.028 + 0.004 * v[0] - 0.05 * (v[1] - 0.02) + step;
        let di = 0.02 + 0.4 * (v[1] - 0.01) + 1.0 * (v[2] - 0.005) - 0.01 * v[0];
        Some([x, di])
    };
    let mut r = Reducer::new(&s, free::options(&s));
    let grid = impactsweep::reduce::Grid::new(
        s.axes
            .iter()
            .map(|a| (a.key.clone(), a.values.clone()))
            .collect(),
    );
    let per_chunk = 5000u64;
    let mut p0 = 0;
    while p0 < grid.len() {
        let p1 = (p0 + per_chunk).min(grid.len());
        let mut rows = Vec::new();
        for p in p0..p1 {
            let [x, di] = ideal(&grid.values(p)).unwrap();
            for c in 0..2u32 {
                let spread = 3e-4 * f64::from(c) * (1.0 + (p % 7) as f64 / 7.0);
                rows.push(row(&s, p, c, Outcome::Ok, x + spread, di));
            }
        }
        r.push(rows);
        p0 = p1;
    }
    let sum = r.finish_with(&FnIdeal(ideal));
    assert_eq!(sum.points.len(), 44_541);
    // The jump surface is found on every line along e that crosses it.
    assert!(sum.jumps.len() >= 400, "{}", sum.jumps.len());
    let rec = sum.recommended.expect("a robust design");
    assert!(sum.point(rec).unwrap().robust);
    // The best designs sit on the upper edges of m and d: the warning says which way to go.
    let warned: Vec<(String, String)> = sum
        .edges
        .iter()
        .map(|w| (sum.grid.key(w.axis).to_string(), format!("{:?}", w.end)))
        .collect();
    assert!(warned.contains(&("m".into(), "High".into())), "{warned:?}");
    assert!(warned.contains(&("d".into(), "High".into())), "{warned:?}");
    let md = impactsweep::report::markdown::report(&s, &sum, &[], None);
    assert!(md.contains("## Recommended design"), "{md}");
    assert!(
        md.find("## Recommended design") < md.find("## Zones"),
        "the report opens with the recommendation"
    );
    assert!(md.contains("Extend `m` above 0.03 kg"), "{md}");
    assert!(md.contains("Extend `d` above 0.015 m"), "{md}");
    for (section, n) in table_lengths(&md) {
        assert!(n <= 30, "a table of {n} rows in {section}");
    }
    // Jumps grouped per axis, zones per class and region, sensitivity per quantity and axis.
    for needle in ["| e | xmax | step |", "| class | zones |", "## Sensitivity"] {
        assert!(md.contains(needle), "report lacks {needle}");
    }
}
