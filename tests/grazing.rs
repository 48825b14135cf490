//! Issue 45: branches continued through grazing, and no repeated points.
//!
//! On the issue's study (Table I's M and K with C = 0.1 N s/m, m = 5 g, d = 5 mm, e = 0.9,
//! F0 = 0.1 N, r = 0.85 … 1.15 at seven frequencies, 48 census starts), run then reduced:
//! every located grazing on a branch either continues (the branch goes on past its `GR` row) or
//! is explained (`grazing_end` with `grazing_outcome` `chaos` or `jump`), and where a branch goes
//! on with the new impact count through a swept frequency, its orbit there is the census's to
//! 1e-8. No branch of that study, nor of a small harmonic study, has two identical consecutive
//! points.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use assert_cmd::Command;
use impactsweep::orbits::map::{Section, eval};
use impactsweep::orbits::response::BranchRow;
use impactsweep::orbits::shoot::{Newton, Termination, distance, scale, solve};

/// The issue's study.
fn issue_study_text(name: &str) -> String {
    format!(
        r#"[study]
name = "{name}"
seed = 45

[system]
M = 0.1
K = 400.0
C = 0.1
m = 0.005
d = 0.005
e = 0.9
x0 = 0.0
v0 = 0.0
y0 = 0.0
w0 = 0.0

[scene]
kind = "harmonic"
F0 = 0.1
starts = 48

[sweep]
r = {{ start = 0.85, stop = 1.15, num = 7 }}
"#
    )
}

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// Writes `text` as study `name` under `root`, runs it, analyses its one shard
/// (`reduce --shard 0/1`, which keeps each branch row's section in `analysis/`) and reduces it:
/// the run directory.
fn run_and_reduce(root: &Path, name: &str, text: &str) -> PathBuf {
    let _ = std::fs::remove_dir_all(root);
    std::fs::create_dir_all(root).unwrap();
    let study = root.join(format!("{name}.toml"));
    std::fs::write(&study, text).unwrap();
    let dir = common::run_study_file(&study, &root.join("out"), name);
    bin()
        .args(["reduce", "--shard", "0/1"])
        .arg(&dir)
        .assert()
        .success();
    bin().arg("reduce").arg(&dir).assert().success();
    dir
}

/// The issue's study, run and reduced once for this file's tests.
fn issue_run() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("grazing-issue-45");
        run_and_reduce(&root, "issue45", &issue_study_text("issue45"))
    })
}

/// A CSV file's rows as maps from column to cell.
fn csv(path: &Path) -> Vec<BTreeMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = common::csv_cells(lines.next().unwrap());
    lines
        .map(|l| header.iter().cloned().zip(common::csv_cells(l)).collect())
        .collect()
}

fn num(cell: &str) -> f64 {
    if cell.is_empty() {
        f64::NAN
    } else {
        cell.parse().unwrap()
    }
}

/// The branch rows with their sections, from the shard's analysis.
fn branch_rows(dir: &Path) -> Vec<BranchRow> {
    let path = dir.join("analysis").join("branches-0-of-1.parquet");
    let t = impactsweep::store::summary::read_table(&path).unwrap();
    impactsweep::reduce::harmonic::shard::branches_from_part(&t)
        .expect("the shard's branches")
        .into_values()
        .flatten()
        .collect()
}

/// Consecutive rows of one branch with the same point (`r`, amplitude, impacts per period,
/// period), as `(branch, r)`.
fn repeated_points(rows: &[BTreeMap<String, String>]) -> Vec<(String, String)> {
    rows.windows(2)
        .filter(|w| {
            [
                "point",
                "branch",
                "r",
                "amplitude",
                "impacts_per_period",
                "period",
            ]
            .iter()
            .all(|c| w[0][*c] == w[1][*c])
        })
        .map(|w| (w[0]["branch"].clone(), w[0]["r"].clone()))
        .collect()
}

/// The stable periodic census orbit at `r` with `period` and `ipp` impacts per period, from
/// `attractors.csv`: its section.
fn census_orbit(
    attractors: &[BTreeMap<String, String>],
    r: f64,
    period: u32,
    ipp: f64,
) -> Vec<Section> {
    attractors
        .iter()
        .filter(|a| {
            a["kind"] == "periodic"
                && (num(&a["r"]) - r).abs() <= 1e-12
                && a["period"] == period.to_string()
                && (num(&a["impacts_per_period"]) - ipp).abs() <= 1e-12
        })
        .map(|a| ["section_x", "section_v", "section_z", "section_w"].map(|c| num(&a[c])))
        .collect()
}

/// Issue 45, item 1: every grazing continues or is explained, and a continued orbit is the
/// census's at the swept frequencies beyond it (to 1e-8 of its scale).
#[test]
fn issue_45_branches_go_on_through_grazing_or_say_what_follows() {
    let dir = issue_run();
    let table = csv(&dir.join("branches.csv"));
    assert!(
        table[0].contains_key("grazing_outcome"),
        "branches.csv has no grazing_outcome: {:?}",
        table[0].keys()
    );
    let rows = branch_rows(dir);
    assert_eq!(rows.len(), table.len(), "the shard's rows are the table's");
    let attractors = csv(&dir.join("attractors.csv"));
    let f = common::table_i(0.005, 0.005, 0.9, 0.1, 0.1, 1.0);
    let freqs: Vec<f64> = (0..7).map(|i| 0.85 + 0.05 * i as f64).collect();
    let (mut grazings, mut through, mut ended) = (0, 0, BTreeMap::<&str, u32>::new());
    let (mut compared, mut missed) = (0, 0);
    for (i, g) in rows.iter().enumerate() {
        // Every row's outcome is empty but at a grazing end.
        if g.end == "grazing_end" {
            assert!(
                ["chaos", "jump", "none"].contains(&g.grazing_outcome),
                "branch {} at r = {}: grazing_end with outcome {:?}",
                g.branch,
                g.r,
                g.grazing_outcome
            );
        } else {
            assert_eq!(g.grazing_outcome, "", "branch {} at r = {}", g.branch, g.r);
        }
        if g.label != "GR" {
            continue;
        }
        grazings += 1;
        if g.end == "closed" {
            // The branch came back onto a point it went through: this grazing was passed there.
            through += 1;
            continue;
        }
        if !g.end.is_empty() {
            eprintln!(
                "GR ends branch {} at r = {:.6}: {} ({})",
                g.branch, g.r, g.end, g.grazing_outcome
            );
            *ended.entry(g.grazing_outcome).or_default() += 1;
            assert!(
                g.end == "grazing_end" && ["chaos", "jump"].contains(&g.grazing_outcome),
                "a grazing at r = {} (branch {}) ends the branch unexplained: end {:?}, \
                 outcome {:?}",
                g.r,
                g.branch,
                g.end,
                g.grazing_outcome
            );
            continue;
        }
        // Inside its branch: it goes on. Past it (in the table's order), the rows with the
        // impact count it goes on with, up to where that changes again or the branch ends.
        through += 1;
        let before = rows[i - 1].impacts_per_period;
        let after = rows[i + 1].impacts_per_period;
        let segment: Vec<&BranchRow> = rows[i + 1..]
            .iter()
            .take_while(|b| {
                b.branch == g.branch && b.design == g.design && b.impacts_per_period == after
            })
            .collect();
        eprintln!(
            "GR inside branch {} at r = {:.6}: {} -> {} impacts per period, {} rows past it",
            g.branch,
            g.r,
            before,
            segment.first().map_or(f64::NAN, |b| b.impacts_per_period),
            segment.len()
        );
        for w in segment.windows(2) {
            let (a, b) = (w[0], w[1]);
            if !(a.stable && b.stable) || a.impacts_per_period != b.impacts_per_period {
                continue;
            }
            for &r in freqs.iter().filter(|&&r| (a.r - r) * (b.r - r) < 0.0) {
                let census = census_orbit(&attractors, r, a.period, a.impacts_per_period);
                if census.is_empty() {
                    // Its basin can be too small for the census's starts (next to a fold).
                    eprintln!("  at r = {r}: the census has no orbit with its impact count");
                    missed += 1;
                    continue;
                }
                let fr = f.at_ratio(r);
                let t = (r - a.r) / (b.r - a.r);
                let s0: Section = std::array::from_fn(|k| a.s[k] + t * (b.s[k] - a.s[k]));
                let p = u64::from(a.period);
                let (Termination::Converged { .. }, Some(st)) =
                    solve(&fr, p, &s0, &Newton::default())
                else {
                    panic!("Newton on the continued branch at r = {r} failed");
                };
                // The census's section is one of the orbit's p sections.
                let mut s = st.s;
                let mut best = f64::INFINITY;
                for _ in 0..p {
                    for c in &census {
                        best = best.min(distance(&fr, &s, c));
                    }
                    s = eval(&fr, &s, 1, false).end;
                }
                let rel = best / scale(&fr, &st.s);
                eprintln!("  at r = {r}: the census's orbit to {rel:e}");
                if rel > 1e-3 {
                    // Another orbit of the same period and impact count (at r = 0.9 on this
                    // study two coexist): the census's starts did not meet this one's basin,
                    // as above. A discrepancy of the same orbit is far below this.
                    eprintln!("  at r = {r}: the census holds another orbit of its impact count");
                    missed += 1;
                    continue;
                }
                assert!(
                    rel <= 1e-8,
                    "past the grazing at r = {} (branch {}), the orbit at r = {r} is {rel:e} \
                     from the census's",
                    g.r,
                    g.branch
                );
                compared += 1;
            }
        }
    }
    eprintln!(
        "{grazings} GR rows: {through} continued, ended {ended:?}; {compared} continued orbits \
         equal to the census's, {missed} with no census orbit of their impact count"
    );
    assert!(grazings > 0, "no grazing on the issue's study");
    assert!(through > 0, "no branch goes on through a grazing");
    assert!(compared > 0, "no continued orbit met a swept frequency");
}

/// Issue 45, item 2: no branch of the issue's study has two identical consecutive points
/// (branch 0 used to start with the same point twice at r = 0.85).
#[test]
fn issue_45_no_branch_repeats_a_point() {
    let rows = csv(&issue_run().join("branches.csv"));
    assert!(rows.len() > 10, "{} branch rows", rows.len());
    let repeated = repeated_points(&rows);
    assert!(repeated.is_empty(), "repeated points: {repeated:?}");
}

/// Issue 45, item 2, on a small harmonic study (issue 23's: seven inner masses, four
/// frequencies): no branch repeats a point.
#[test]
fn issue_45_no_branch_of_a_small_study_repeats_a_point() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = run_and_reduce(
        &tmp.path().join("small"),
        "small",
        &common::census_study_text("small"),
    );
    let rows = csv(&dir.join("branches.csv"));
    assert!(rows.len() > 10, "{} branch rows", rows.len());
    let repeated = repeated_points(&rows);
    assert!(repeated.is_empty(), "repeated points: {repeated:?}");
}
