//! Issue 10's acceptance on the users' own study: the shipped `configs/overnight.toml`
//! (101 × 21 × 21 = 44,541 design points × 28 cases, 1.25 M runs) run and reduced with the
//! command line as a user would (`run --reduce`), then read back from the files it writes:
//! every zone is one connected region of the grid, the recommended design is robust (itself and
//! its 26 neighbours in recommended zones), the edge warning appears, and each map's data is
//! exactly the summary rows of the slice its title names.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use crate::common;

use common::{chart_rows_are_summary_rows, csv_by_point};

/// A zone label that may hold a recommended design (`reduce::zones::Class::recommended`).
fn recommended_label(label: &str) -> bool {
    label == "strong damping, reliable" || label == "reliable, weak damping"
}

/// The index of `v` among the sorted distinct values `axis`.
fn index(axis: &[f64], v: f64) -> i64 {
    axis.iter().position(|&a| a == v).unwrap() as i64
}

#[test]
fn issue_10_overnight_toml_reduced_has_connected_zones_a_robust_recommendation_and_real_slices() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("run")
        .arg(root.join("configs/overnight.toml"))
        .arg("--out")
        .arg(tmp.path())
        .args(["--quiet", "--reduce"])
        .assert()
        .success();
    let dir = tmp.path().join("overnight");
    let (_, rows) = csv_by_point(&dir.join("summary.csv"));
    assert_eq!(rows.len(), 44_541);

    // The grid: each point's indices along e, mass_inner and d.
    let cols = ["e", "mass_inner", "d"];
    let axes: Vec<Vec<f64>> = cols
        .iter()
        .map(|c| {
            let mut v: Vec<f64> = rows.values().map(|r| r[*c].parse().unwrap()).collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        })
        .collect();
    assert_eq!(axes.iter().map(Vec::len).collect::<Vec<_>>(), [101, 21, 21]);
    let at: HashMap<[i64; 3], u64> = rows
        .iter()
        .map(|(&p, r)| {
            let ix = [0, 1, 2].map(|a| index(&axes[a], r[cols[a]].parse().unwrap()));
            (ix, p)
        })
        .collect();
    let ix_of: HashMap<u64, [i64; 3]> = at.iter().map(|(&ix, &p)| (p, ix)).collect();

    // Every zone is one connected region: a flood fill from one member through neighbours
    // (one step along one axis) of the same zone reaches every member.
    let mut members: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    for (&p, r) in &rows {
        members.entry(r["zone"].clone()).or_default().push(p);
    }
    let (_, zones) = {
        let text = std::fs::read_to_string(dir.join("zones.csv")).unwrap();
        let mut lines = text.lines();
        let header = common::csv_cells(lines.next().unwrap());
        let zones: HashMap<String, HashMap<String, String>> = lines
            .map(|l| {
                let row: HashMap<String, String> =
                    header.iter().cloned().zip(common::csv_cells(l)).collect();
                (row["zone"].clone(), row)
            })
            .collect();
        (header, zones)
    };
    assert_eq!(zones.len(), members.len(), "zones.csv against the summary");
    for (zone, pts) in &members {
        assert_eq!(
            zones[zone]["n_points"].parse::<usize>().unwrap(),
            pts.len(),
            "zone {zone}"
        );
        let mut seen = std::collections::HashSet::from([pts[0]]);
        let mut stack = vec![pts[0]];
        while let Some(p) = stack.pop() {
            let ix = ix_of[&p];
            for a in 0..3 {
                for s in [-1, 1] {
                    let mut n = ix;
                    n[a] += s;
                    if let Some(&q) = at.get(&n)
                        && rows[&q]["zone"] == *zone
                        && seen.insert(q)
                    {
                        stack.push(q);
                    }
                }
            }
        }
        assert_eq!(seen.len(), pts.len(), "zone {zone} falls apart");
    }

    // The recommended design, named by the report, is robust: flagged so, in a recommended
    // class, off the grid's edges, and its whole neighbourhood lies in recommended zones.
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let rec: u64 = report
        .split("(design point ")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .and_then(|s| s.parse().ok())
        .expect("the report names the recommended design point");
    assert_eq!(rows[&rec]["robust"], "true");
    assert!(recommended_label(&rows[&rec]["class"]));
    let ix = ix_of[&rec];
    for de in -1..=1 {
        for dm in -1..=1 {
            for dd in -1..=1 {
                let q = at[&[ix[0] + de, ix[1] + dm, ix[2] + dd]];
                let label = &zones[&rows[&q]["zone"]]["label"];
                assert!(recommended_label(label), "neighbour {q} in {label}");
            }
        }
    }
    // The edge warning: the best designs sit at the largest m and d of the sweep.
    assert!(
        report.contains("**The best designs sit on the edge of the swept range**"),
        "{report}"
    );
    assert!(report.contains("Extend `d` above 0.015 m"), "{report}");

    // Each map's data is the summary rows of its slice through the recommended design: the
    // slice's every point, no other (the axis not drawn is at the recommended design's value).
    for (map, fixed) in [("e_mass_inner", 2), ("e_d", 1), ("mass_inner_d", 0)] {
        for kind in ["zone_map", "perfectibility_map"] {
            let chart = dir.join(format!("{kind}_{map}.csv"));
            let got = chart_rows_are_summary_rows(&chart, &dir.join("summary.csv"));
            let mut want: Vec<u64> = at
                .iter()
                .filter(|(k, _)| k[fixed] == ix[fixed])
                .map(|(_, &p)| p)
                .collect();
            want.sort_unstable();
            let mut got = got;
            got.sort_unstable();
            assert_eq!(got, want, "{}", chart.display());
        }
    }
}
