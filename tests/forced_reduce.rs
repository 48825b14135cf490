//! The harmonic scene's reduction (issue 12, item 4): per design (a design point without its
//! frequency) the peak amplitude over the swept band is the response (each case's peak a
//! sample: stress, R and the ranking use it), the peak reduction takes DI's place, the band
//! where the damper helps is located, and the charts draw the frequency-response curves with
//! the linear system beside them and the impacts per period and the period against r. The
//! reduction streams whole curves.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::reduce::harmonic::{self, HarmonicReducer};
use impactsweep::sim::HarmonicRecord;
use impactsweep::store::{self, RunRow};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// Eleven frequency ratios around resonance, no damper and Table I's inner mass, three cases
/// (the ideal one, a smaller and a larger clearance). A brief design life and no verification
/// (tests/life.rs tests those): what these tests check is the reduction's bookkeeping.
fn study_text(name: &str, chunk_points: u64) -> String {
    format!(
        r#"[study]
name = "{name}"
seed = 3

[system]
v0 = 0.0

[scene]
kind = "harmonic"
F0 = 0.3
n_trans_max = 800
life_max_periods = 2000
n_meas = 10

[sweep]
m = [0.0, 0.02]
r = {{ start = 0.9, stop = 1.1, num = 11 }}

[perturb]
dd = [-0.002, 0.002]

[reliability]
strength_mean = 300e6
strength_sd = 20e6
bootstrap = 50

[ranking]
verify_periods = 0

[run]
chunk_points = {chunk_points}
"#
    )
}

/// Runs and reduces the study into `tmp/out/<name>`; returns the run directory.
fn run_and_reduce(tmp: &Path, name: &str, chunk_points: u64) -> PathBuf {
    let study = tmp.join(format!("{name}.toml"));
    std::fs::write(&study, study_text(name, chunk_points)).unwrap();
    let dir = common::run_study_file(&study, &tmp.join("out"), name);
    bin().arg("reduce").arg(&dir).assert().success();
    dir
}

/// Writes `text` as study `name` in `tmp`, runs and reduces it: its run directory and report.
fn run_text(tmp: &Path, name: &str, text: &str) -> (PathBuf, String) {
    let study = tmp.join(format!("{name}.toml"));
    std::fs::write(&study, text).unwrap();
    let dir = common::run_study_file(&study, &tmp.join("out"), name);
    bin().arg("reduce").arg(&dir).assert().success();
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    (dir, md)
}

fn rows(dir: &Path) -> Vec<RunRow<HarmonicRecord>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<HarmonicRecord>(p).unwrap())
        .collect()
}

fn num(cell: &str) -> f64 {
    if cell.is_empty() {
        f64::NAN
    } else {
        cell.parse().unwrap()
    }
}

#[test]
fn issue_12_each_design_reduces_to_its_peak_over_the_band() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = run_and_reduce(tmp.path(), "fr", 11);
    let (header, summary) = common::csv_by_point(&dir.join("summary.csv"));
    // Two designs (m = 0 and 0.02): the frequency is not a column of the summary.
    assert_eq!(summary.len(), 2);
    assert_eq!(&header[..2], ["point", "mass_inner"]);
    for col in [
        "peak_amplitude_mean",
        "peak_amplitude_ideal",
        "peak_reduction",
        "peak_r",
        "linear_peak",
        "help_r_from",
        "help_r_to",
        "help_share",
        "periodic_share",
        "peak_periodic",
    ] {
        assert!(header.iter().any(|h| h == col), "{col} not in {header:?}");
    }
    // `peak_periodic`: the steady state carrying the design's peak (the worst of the census,
    // issue 16) is periodic; `peak_from_rest` is the largest amplitude reached from rest.
    for (design, row) in &summary {
        let ideal: Vec<_> = rows(&dir)
            .into_iter()
            .filter(|r| r.point / 11 == *design && r.ideal)
            .collect();
        let peak = ideal
            .iter()
            .max_by(|a, b| {
                let (x, y) = (
                    a.record.steady.amplitude_worst,
                    b.record.steady.amplitude_worst,
                );
                x.total_cmp(&y)
            })
            .unwrap();
        assert_eq!(
            row["peak_periodic"],
            (peak.record.steady.worst_period >= 1).to_string(),
            "design {design}"
        );
        let rest = ideal
            .iter()
            .map(|r| r.record.amplitude)
            .fold(f64::NAN, f64::max);
        assert_eq!(num(&row["peak_from_rest"]), rest);
        assert!(num(&row["peak_amplitude_ideal"]) >= rest * (1.0 - 1e-9));
    }
    assert!(!header.iter().any(|h| h == "xmax_mean" || h == "di"));

    // Each case's peak over the band, from the stored runs.
    let mut peaks: BTreeMap<(u64, u32), (f64, f64)> = BTreeMap::new();
    for r in rows(&dir) {
        let e = peaks
            .entry((r.point / 11, r.case))
            .or_insert((f64::NAN, f64::NAN));
        e.0 = e.0.max(r.record.steady.amplitude_worst);
        e.1 = e.1.max(r.record.amplitude_linear);
    }
    // (No verification in this study: `verify_periods = 0`.)
    assert!(!dir.join("verification.csv").exists());
    for (design, row) in &summary {
        let of = |c: u32| peaks[&(*design, c)];
        let samples: Vec<f64> = (0..3).map(|c| of(c).0).collect();
        let max = samples.iter().copied().fold(f64::NAN, f64::max);
        let min = samples.iter().copied().fold(f64::NAN, f64::min);
        let mean = samples.iter().sum::<f64>() / 3.0;
        assert_eq!(num(&row["peak_amplitude_max"]), max, "design {design}");
        assert_eq!(num(&row["peak_amplitude_min"]), min, "design {design}");
        assert!((num(&row["peak_amplitude_mean"]) / mean - 1.0).abs() < 1e-12);
        assert_eq!(num(&row["peak_amplitude_ideal"]), of(0).0);
        assert_eq!(num(&row["linear_peak"]), of(0).1);
        let pr = 1.0 - of(0).0 / of(0).1;
        assert_eq!(num(&row["peak_reduction_ideal"]), pr);
        // The stress follows the peak amplitude (eq. 10: 3 E r / L^2 = 8.16e9 Pa per m).
        let k = 3.0 * 200e9 * 3.4e-3 / 0.25;
        assert!((num(&row["stress_mean"]) / (k * mean) - 1.0).abs() < 1e-12);
    }
    // No damper: the linear system, PR = 0 to the simulator's accuracy, it helps nowhere.
    let bare = &summary[&0];
    assert!(num(&bare["peak_reduction_ideal"]).abs() < 1e-9, "{bare:?}");
    assert!(num(&bare["help_r_from"]).is_nan());
    assert_eq!(num(&bare["help_share"]), 0.0);
    assert_eq!(num(&bare["peak_r"]), 1.0);
    assert_eq!(num(&bare["periodic_share"]), 1.0);
    // Table I's inner mass removes most of the resonance at r = 1; over the band its peak sits
    // lower, near the stuck pair's resonance sqrt(M / (M + m)) = 0.913.
    let damped = &summary[&1];
    let at_1 = rows(&dir)
        .into_iter()
        .find(|r| r.point == 11 + 5 && r.ideal)
        .unwrap();
    assert!(at_1.record.attenuation < 0.1, "{:?}", at_1.record);
    // Its peak is a chaotic motion's design-life estimate (about 3.35 cm, its 90 % interval
    // +-5 %), so the reduction is asked with that margin: PR > 0.25, not a draw's 0.3.
    assert!(num(&damped["peak_reduction_ideal"]) > 0.25, "{damped:?}");
    let pr_hi = 1.0 - num(&damped["peak_life_hi"]) / num(&damped["linear_peak"]);
    assert!(pr_hi > 0.2, "{damped:?}");
    assert_eq!(num(&damped["peak_r"]), 0.9);
    let (from, to) = (num(&damped["help_r_from"]), num(&damped["help_r_to"]));
    assert!(from < 1.0 && to > 1.0, "{from} {to}");
    assert_eq!(damped["rank"], "1");

    // The charts: one design axis, so one of each, with the scene's names.
    for stem in [
        "frequency_response",
        "impacts_per_period",
        "peak_reduction",
        "design_chart",
        "peak_amplitude_spread",
    ] {
        for ext in ["svg", "png", "csv"] {
            let f = dir.join(format!("{stem}.{ext}"));
            assert!(f.exists(), "{} missing", f.display());
        }
    }
    // The frequency response's data: every run of the ideal case of both designs.
    let text = std::fs::read_to_string(dir.join("frequency_response.csv")).unwrap();
    let head = common::csv_cells(text.lines().next().unwrap());
    assert_eq!(
        head,
        [
            "point",
            "mass_inner",
            "r",
            "omega",
            "outcome",
            "amplitude",
            "amplitude_design",
            "design_period",
            "amplitude_linear",
            "attenuation",
            "impacts_per_period",
            "period",
            "converged",
            "life_lo",
            "life_hi",
            "known"
        ]
    );
    assert_eq!(text.lines().count(), 1 + 2 * 11);
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("## Frequency response\n"), "{report}");
    assert!(
        report.contains("66 runs were simulated (ok:66)"),
        "{report}"
    );
    assert!(report.contains("| 1 | m = 0.02 kg | "), "{report}");
    assert!(report.contains("## Pareto set on (R, PR)"));
    assert!(report.contains("![frequency_response.svg](frequency_response.svg)"));
    // Issue 16: the steady states of the recommended design's curve, and the tables.
    for stem in ["branches", "basin_shares"] {
        assert!(
            dir.join(format!("{stem}.png")).exists(),
            "{stem}.png missing"
        );
    }
    // Issue 23: the attractors are the sweep's (a part per chunk); reduce writes the ideal
    // case's rows as CSV, and the branches.
    assert!(dir.join("attractors/part-000000.parquet").exists());
    assert!(dir.join("attractors.csv").exists());
    assert!(!dir.join("attractors.parquet").exists());
    assert!(dir.join("branches.parquet").exists());
    assert!(dir.join("branches.csv").exists());
    assert!(report.contains("carried by"), "{report}");
    assert!(
        !report.contains("DI"),
        "the free-decay quantity leaked into the report"
    );
}

#[test]
fn issue_12_the_reduction_streams_whole_curves() {
    // One curve per part, or both in one: the same summary, bit for bit.
    let tmp = tempfile::tempdir().unwrap();
    let one = run_and_reduce(tmp.path(), "one", 22);
    let two = run_and_reduce(tmp.path(), "two", 11);
    assert_eq!(store::part_files(&two).unwrap().len(), 2);
    let strip = |dir: &Path| {
        let (h, rows) = common::csv_by_point(&dir.join("summary.csv"));
        (h, rows)
    };
    assert_eq!(strip(&one), strip(&two));
    // A part that ends inside a curve (not what the engine writes, but a reader must not
    // split a design): the rows are carried to the next part.
    let study = Study::parse(Path::new("s.toml"), &study_text("lib", 22)).unwrap();
    sweep::run_study(&study, tmp.path(), &SweepOptions::default()).unwrap();
    let all = rows(&tmp.path().join("lib"));
    let design = harmonic::design_study(&study);
    let reduce = |cuts: &[usize]| {
        let mut r = HarmonicReducer::new(&study, &design, harmonic::options(&design));
        let mut start = 0;
        for &c in cuts.iter().chain(std::iter::once(&all.len())) {
            r.push(all[start..c].to_vec(), None);
            start = c;
        }
        let (s, f, _) = r.finish(&Default::default());
        (format!("{:?}", s.points), f)
    };
    let whole = reduce(&[]);
    assert_eq!(reduce(&[7, 40]), whole);
    assert_eq!(whole.1.runs, 66);
    assert_eq!(whole.1.curves.len(), 2);
}

/// A study at one frequency that sweeps the force amplitude: `reduce` follows each design's
/// branches along `F0` (issue 16, item 3): `branches.csv` has rows at the study's one `r`
/// with `F0` moving over the swept range, and `attractors.csv` a census at every force.
#[test]
fn issue_16_a_force_sweep_is_followed_along_f0() {
    let tmp = tempfile::tempdir().unwrap();
    let text = r#"[study]
name = "force"
seed = 5

[system]
m = 0.005
d = 0.005
C = 0.1
v0 = 0.0

[scene]
kind = "harmonic"
r = 0.85
starts = 4

[sweep]
F0 = [0.05, 0.1, 0.15, 0.2]

[reliability]
strength_mean = 300e6
strength_sd = 20e6
bootstrap = 20
"#;
    let study = tmp.path().join("force.toml");
    std::fs::write(&study, text).unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "force");
    bin().arg("reduce").arg(&dir).assert().success();
    let csv = |name: &str| -> Vec<BTreeMap<String, String>> {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let mut lines = text.lines();
        let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
        lines
            .map(|l| {
                head.iter()
                    .cloned()
                    .zip(l.split(',').map(String::from))
                    .collect()
            })
            .collect()
    };
    let branches = csv("branches.csv");
    assert!(
        branches[0].contains_key("impacts_per_period")
            && branches[0].contains_key("multiplier_max"),
        "branches.csv is the branches table, not a chart's columns: {:?}",
        branches[0].keys()
    );
    // Issue 25: the steady-state charts of a force sweep are drawn against F0.
    for chart in ["branches", "basin_shares"] {
        let svg = std::fs::read_to_string(dir.join(format!("{chart}.svg"))).unwrap();
        assert!(svg.contains("force amplitude F0 (N)"), "{chart}.svg");
        assert!(svg.contains("F0 = "), "{chart}.svg has hover texts in F0");
    }
    let impacting: Vec<_> = branches
        .iter()
        .filter(|b| num(&b["impacts_per_period"]) > 0.0)
        .collect();
    assert!(
        impacting.len() >= 5,
        "{} impacting branch rows",
        impacting.len()
    );
    let f0s: Vec<f64> = impacting.iter().map(|b| num(&b["F0"])).collect();
    let (lo, hi) = f0s
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    assert!(
        lo >= 0.05 - 1e-12 && hi <= 0.2 + 1e-12 && hi - lo > 0.05,
        "F0 in [{lo}, {hi}]"
    );
    for b in &branches {
        assert!((num(&b["r"]) - 0.85).abs() < 1e-9, "{b:?}");
    }
    let attractors = csv("attractors.csv");
    let column = |name: &str| -> std::collections::BTreeSet<String> {
        attractors.iter().map(|a| a[name].clone()).collect()
    };
    assert_eq!(column("point").len(), 4, "a census at each of the 4 forces");
    assert_eq!(
        column("F0").len(),
        4,
        "the attractors' F0: {:?}",
        column("F0")
    );
}

/// Issue 23: `reduce` reads the attractors the sweep stored and runs no census (the process's
/// count of census starts does not move), and every design's peak in the summary is an
/// attractor of the `attractors` table: the same number, at the frequency `peak_r` names.
#[test]
fn issue_23_reduce_runs_no_census_and_every_peak_is_an_attractor() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("nocensus.toml");
    std::fs::write(&study, study_text("nocensus", 22)).unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "nocensus");
    let before = impactsweep::reduce::harmonic::steady::census_starts();
    impactsweep::api::reduce::reduce_dir(&impactsweep::api::reduce::ReduceArgs {
        dir: dir.clone(),
        ..Default::default()
    })
    .unwrap();
    assert_eq!(
        impactsweep::reduce::harmonic::steady::census_starts(),
        before
    );
    let (_, summary) = common::csv_by_point(&dir.join("summary.csv"));
    let text = std::fs::read_to_string(dir.join("attractors.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let attractors: Vec<Vec<String>> = lines.map(common::csv_cells).collect();
    assert!(!attractors.is_empty());
    for (design, row) in &summary {
        let peak = num(&row["peak_amplitude_ideal"]);
        let r = num(&row["peak_r"]);
        let hit = attractors.iter().any(|a| {
            num(&a[at("point")]) as u64 / 11 == *design
                && num(&a[at("r")]) == r
                && num(&a[at("amplitude")]) == peak
        });
        assert!(
            hit,
            "design {design}: peak {peak} at r = {r} is no attractor"
        );
    }
    // A point carried by a life estimate says in its hover how many periods stand behind its
    // interval: a measured_periods of a motion that is not periodic in the table.
    let measured: std::collections::BTreeSet<String> = attractors
        .iter()
        .filter(|a| !["periodic", "neutral"].contains(&a[at("kind")].as_str()))
        .map(|a| a[at("measured_periods")].clone())
        .collect();
    let mut hovers = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !(name.starts_with("frequency_response") && name.ends_with(".svg")) {
            continue;
        }
        let svg = std::fs::read_to_string(&path).unwrap();
        for part in svg.split("over the design life, 90 % interval [").skip(1) {
            let from = part.split("] cm from ").nth(1).unwrap_or_else(|| {
                panic!("{name}: a life interval's hover without its periods: {part:.80}")
            });
            let n: String = from.split(" period").next().unwrap().replace(',', "");
            assert!(measured.contains(&n), "{name}: {n} periods is no motion's");
            hovers += 1;
        }
    }
    assert!(hovers > 0, "no hover of a life estimate");
}

/// Issue 23 with issue 24's curves: a bifurcation curve along one design axis serves only the
/// designs of its line (the other axes' values), so by default (`--bifurcation-curves
/// recommended`) `reduce` follows the lines through the recommended design, the ones its design
/// map draws, and `all` every line. On a 2 x 2 grid over `m` and `d`: the default's curves lie
/// on one line per axis, through one design, and are exactly `all`'s rows on those lines;
/// `all` has curves on the other lines too; `none` writes no table.
#[test]
fn issue_23_bifurcation_curves_follow_the_recommended_lines_by_default() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("lines.toml");
    std::fs::write(
        &study,
        r#"[study]
name = "lines"
seed = 5
[system]
C = 0.1
v0 = 0.0
[scene]
kind = "harmonic"
F0 = 0.1
n_trans_max = 800
life_max_periods = 2000
[sweep]
m = [0.005, 0.01]
d = [0.005, 0.01]
r = { start = 0.85, stop = 1.15, num = 13 }
[reliability]
strength_mean = 100e6
strength_sd = 8e6
[ranking]
verify_periods = 0
"#,
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "lines");
    let reduce = |lines: &str| -> Option<Vec<Vec<String>>> {
        bin()
            .arg("reduce")
            .arg(&dir)
            .args(["--bifurcation-curves", lines])
            .assert()
            .success();
        let text = std::fs::read_to_string(dir.join("bifurcations.csv")).ok()?;
        Some(text.lines().skip(1).map(common::csv_cells).collect())
    };
    let all = reduce("all").expect("every line: a bifurcations table");
    let (_, summary) = common::csv_by_point(&dir.join("summary.csv"));
    // The design's value of the axis the curve does not move along (columns: curve, point,
    // kind, p_name, ...).
    let other = |row: &Vec<String>| -> (String, String) {
        let design = &summary[&row[1].parse::<u64>().unwrap()];
        match row[3].as_str() {
            "m" => ("m".into(), design["d"].clone()),
            "d" => ("d".into(), design["mass_inner"].clone()),
            p => panic!("curve along {p}"),
        }
    };
    let default = reduce("recommended").expect("the recommended lines: a bifurcations table");
    // No curves: no table (nor the last reduce's, left behind).
    assert!(reduce("none").is_none(), "no curves: no table");
    assert!(!dir.join("bifurcations.parquet").exists());
    let lines: std::collections::BTreeSet<(String, String)> = default.iter().map(other).collect();
    for p in ["m", "d"] {
        assert!(
            lines.iter().filter(|l| l.0 == p).count() <= 1,
            "one line along {p}: {lines:?}"
        );
    }
    // The same rows (without the curve's number) as `all` has on those lines, in order.
    let strip = |rows: &[Vec<String>]| -> Vec<Vec<String>> {
        rows.iter().map(|r| r[1..].to_vec()).collect()
    };
    let on_lines: Vec<Vec<String>> = all
        .iter()
        .filter(|r| lines.contains(&other(r)))
        .cloned()
        .collect();
    assert!(!default.is_empty());
    assert_eq!(strip(&default), strip(&on_lines));
    assert!(
        all.len() > default.len(),
        "all lines: {} rows, the recommended ones {}",
        all.len(),
        default.len()
    );
}

/// Issue 23: `reduce` analyses the designs' steady states on every thread, each taking the next
/// design, and hands them to the tables in design order: the attractors and branches tables
/// are the same bytes on one thread and on three.
#[test]
fn issue_23_the_steady_state_tables_are_the_same_on_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("threads.toml");
    let text = study_text("threads", 33).replace("m = [0.0, 0.02]", "m = [0.0, 0.01, 0.02]");
    assert!(text.contains("m = [0.0, 0.01, 0.02]"));
    std::fs::write(&study, text).unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "threads");
    let tables = |threads: &str| -> Vec<Vec<u8>> {
        bin()
            .arg("reduce")
            .arg(&dir)
            .env("RAYON_NUM_THREADS", threads)
            .assert()
            .success();
        ["attractors.csv", "branches.csv", "branches.parquet"]
            .iter()
            .map(|f| std::fs::read(dir.join(f)).unwrap())
            .collect()
    };
    let one = tables("1");
    assert!(one[1].len() > 1000, "no branches to compare");
    assert!(
        one == tables("3"),
        "the tables differ between 1 and 3 threads"
    );
}

/// The smallest harmonic study a newcomer writes (a name, a force and a swept `r`, no strength,
/// no design axis): the report names its one design in every table (the zones' too), shows no
/// `R = –` sentence or `– – –` interval, and says so when the design's peak lies at an end of
/// the swept band (the response beyond it unknown), and only then. The inner mass is 0, so the
/// linear system's peak at `r = 1` is the design's: inside a band around 1, at the end of a band
/// below it.
#[test]
fn a_harmonic_study_without_strength_or_design_axes_reads_cleanly() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, band, at_end) in [
        ("around", "start = 0.9, stop = 1.1, num = 5", false),
        ("below", "start = 0.9, stop = 0.98, num = 3", true),
    ] {
        let (dir, md) = run_text(
            tmp.path(),
            name,
            &format!(
                "[study]\nname = \"{name}\"\n[system]\nm = 0.0\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n[sweep]\nr = {{ {band} }}\n"
            ),
        );
        // The peak's r against the band's ends, from the summary.
        let (_, rows) = common::csv_by_point(&dir.join("summary.csv"));
        let peak_r = num(&rows.values().next().unwrap()["peak_r"]);
        let ends = if at_end { [0.9, 0.98] } else { [0.9, 1.1] };
        assert_eq!(
            ends.iter().any(|e| (peak_r - e).abs() < 1e-9),
            at_end,
            "{name}: peak at r = {peak_r}"
        );
        assert_eq!(
            md.contains("**Peaks at the band's end.** The peak of 1 of these designs lies at an end of the swept band (r = 0.980)"),
            at_end,
            "{name}: {md}"
        );
        assert!(!md.contains("– – –"), "{name}: {md}");
        assert!(!md.contains("R = –"), "{name}: {md}");
        let zone = md
            .lines()
            .find(|l| l.starts_with("| I | "))
            .unwrap_or_else(|| panic!("{name}: no zone row: {md}"));
        assert!(
            zone.contains("| the study's system (100.0) | the study's system |"),
            "{name}: {zone}"
        );
    }
}

/// A harmonic study at one frequency over a design axis: whether the damper helps is a yes or
/// a no at that frequency, not a band from r to the same r at the band's edge; and a
/// dimensionless quantity's jump size has no unit `1` after it.
#[test]
fn a_study_at_one_frequency_says_whether_the_damper_helps_there() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, md) = run_text(
        tmp.path(),
        "single",
        "[study]\nname = \"single\"\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\nr = 1.0\n[sweep]\nm = [0.005, 0.01, 0.02]\n",
    );
    let rows: Vec<&str> = md
        .split("## Frequency response")
        .nth(1)
        .unwrap()
        .split("\n## ")
        .next()
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("| ") && l.contains(" | m = ") && !l.contains("chaotic |"))
        .collect();
    assert_eq!(rows.len(), 3, "{md}");
    for row in rows {
        let cells: Vec<&str> = row.split(" | ").collect();
        // The help column: the fourth cell from the end.
        let help = cells[cells.len() - 3];
        assert!(help == "yes" || help == "no", "{row}");
    }
    assert!(!md.contains("(band edge)"), "{md}");
    assert!(
        md.contains("A design's response is its **steady amplitude at that frequency**")
            && !md.contains("peak amplitude over the band"),
        "{md}"
    );
    // No frequency axis, so no chart against it; the designs are in the design chart.
    for stem in ["frequency_response", "impacts_per_period"] {
        assert!(!dir.join(format!("{stem}.png")).exists(), "{stem}.png");
    }
    assert!(dir.join("design_chart.png").exists());
    assert!(
        !md.lines()
            .any(|l| l.contains("peak_reduction") && l.ends_with(" 1 |")),
        "{md}"
    );
}

/// A band whose frequencies step over the linear resonance (7 values of `omega` from 55 to
/// 70 rad/s: r steps of 0.0395 against a resonance 2 zeta = 0.0158 wide) samples the linear
/// peak at 0.888 cm against 1.581 cm between them: the report says the band is too coarse for
/// the resonance, and PR compares sampled peaks. A band with r = 1 on its grid does not get
/// the note. (No inner mass: the motions the census cannot call settled keep the design life's
/// first window, `life_max_periods = 2000`; the note is about the linear peak.)
#[test]
fn a_band_too_coarse_for_the_resonance_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, axis, coarse) in [
        (
            "coarse",
            "omega = { start = 55.0, stop = 70.0, num = 7 }",
            true,
        ),
        ("fine", "r = { start = 0.9, stop = 1.1, num = 5 }", false),
    ] {
        let (_, md) = run_text(
            tmp.path(),
            name,
            &format!(
                "[study]\nname = \"{name}\"\n[system]\nm = 0.0\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\nlife_max_periods = 2000\n[sweep]\n{axis}\n"
            ),
        );
        assert_eq!(
            md.contains("**A band too coarse for the resonance** (1 of these designs). The linear system peaks at r = 0.9999 with 1.581 cm, between the swept frequencies, which sample it at 0.888 cm at most (r = 0.988)"),
            coarse,
            "{name}: {md}"
        );
        assert_eq!(md.contains("too coarse"), coarse, "{name}");
    }
}
