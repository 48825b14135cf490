//! `impactsweep plan` on the bundled studies (issue 3, items 2 and 5): exact counts, the output
//! location, the estimates, and the figures `configs/paper.toml` quotes in its comments.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::plan::Plan;
use impactsweep::sim::{self, NoProbe};
use impactsweep::study::{Case, Study};

fn config(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("configs")
        .join(name)
}

/// Runs `impactsweep plan` and returns stdout.
fn plan(study: &Path, out: &Path) -> String {
    let out = Command::cargo_bin("impactsweep")
        .unwrap()
        .args([
            "plan".as_ref(),
            study.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The value of a `label:   value` line.
fn field<'a>(text: &'a str, label: &str) -> &'a str {
    text.lines()
        .find_map(|l| l.strip_prefix(&format!("{label}:")))
        .unwrap_or_else(|| panic!("no '{label}:' line in\n{text}"))
        .trim()
}

#[test]
fn paper_plan_counts_and_location() {
    let tmp = tempfile::tempdir().unwrap();
    let text = plan(&config("paper.toml"), tmp.path());
    assert_eq!(field(&text, "design points"), "51");
    assert_eq!(
        field(&text, "cases/point"),
        "12 (1 ideal, 6 perturbed, 9 with noise)"
    );
    assert_eq!(field(&text, "total runs"), "612");
    assert_eq!(field(&text, "axes"), "e = 0.45 .. 0.95 (51 values)");
    assert!(field(&text, "noise").starts_with("on: power 5e-10 m^2 s, sample time 0.001 s"));
    assert!(field(&text, "solver").starts_with("exact (tol 1e-12,"));
    assert_eq!(
        field(&text, "output"),
        format!("{}/", tmp.path().join("paper").display())
    );
    assert!(field(&text, "time estimate").contains("over a sample of 200 runs"));
    assert_eq!(
        field(&text, "disk estimate"),
        "65.7 kB (rough: about 90 bytes of Parquet per run and 10.6 kB per part file)"
    );
    // plan writes nothing.
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 0);
}

#[test]
fn quick_plan_counts() {
    let tmp = tempfile::tempdir().unwrap();
    let text = plan(&config("quick.toml"), tmp.path());
    assert_eq!(field(&text, "design points"), "6");
    assert_eq!(
        field(&text, "cases/point"),
        "4 (1 ideal, 2 perturbed, 1 with noise)"
    );
    assert_eq!(field(&text, "total runs"), "24");
    assert_eq!(field(&text, "chunks"), "3 of up to 2 design points");
    assert!(field(&text, "time estimate").contains("over a sample of 24 runs"));
}

#[test]
fn overnight_plan_has_a_million_runs_within_the_size_guard() {
    let tmp = tempfile::tempdir().unwrap();
    let text = plan(&config("overnight.toml"), tmp.path());
    assert_eq!(field(&text, "design points"), "44541");
    assert_eq!(
        field(&text, "cases/point"),
        "28 (1 ideal, 24 perturbed, 27 with noise)"
    );
    let runs: u64 = field(&text, "total runs").parse().unwrap();
    assert_eq!(runs, 1_247_148);
    assert!((1_000_000..=impactsweep::study::MAX_RUNS).contains(&runs));
    let keys: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("axes:"))
        .take(3)
        .map(|l| l[16..].split(' ').next().unwrap())
        .collect();
    assert_eq!(keys, ["e", "m", "d"]);
}

#[test]
fn a_study_without_noise_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("s.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"s\"\n[sweep]\nm = [0.0, 0.01, 0.02]\n",
    )
    .unwrap();
    let text = plan(&study, tmp.path());
    assert_eq!(field(&text, "noise"), "off");
    assert_eq!(field(&text, "total runs"), "3");
    assert_eq!(
        field(&text, "cases/point"),
        "1 (1 ideal, 0 perturbed, 0 with noise)"
    );
}

#[test]
fn paper_study_is_table_i_and_table_ii() {
    let study = Study::load(&config("paper.toml")).unwrap();
    assert_eq!(study.name, "paper");
    assert_eq!(
        study.source,
        std::fs::read_to_string(config("paper.toml")).unwrap()
    );
    let mut table_i = impactsweep::model::System::TABLE_I;
    assert_eq!(study.system, table_i);
    let e = &study.axes[0];
    assert_eq!(e.key, "e");
    assert_eq!(e.values.len(), 51);
    assert_eq!((e.values[0], e.values[50]), (0.45, 0.95));
    // Table II, in the paper's row order, the seed vectors written as integers.
    let g = 0.001; // 1 g in kg, and 1 mm in m
    let rows = [
        (0.0, 0.0, None),
        (0.0, g, None),
        (0.0, -g, None),
        (0.0, 0.0, Some(23341)),
        (0.0, 0.0, Some(32324)),
        (0.0, 0.0, Some(22413)),
        (0.0, 0.0, Some(41313)),
        (0.0, 0.0, Some(32324)),
        (g, g, Some(41313)),
        (g, -g, Some(22413)),
        (-g, -g, Some(22413)),
        (-g, g, Some(23341)),
    ];
    let got: Vec<(f64, f64, Option<u64>)> = study
        .cases
        .iter()
        .map(|c| (c.dm, c.dd, c.noise_seed))
        .collect();
    assert_eq!(got, rows);
    assert_eq!(study.cases[0], Case::IDEAL);
    // A perturbed run's system.
    let plan = Plan::new(&study);
    let run = plan.run(45, 10);
    table_i.m -= g;
    table_i.d -= g;
    table_i.e = 0.9;
    assert_eq!(run.system, table_i);
}

/// The figures quoted in the comments of `configs/paper.toml` ([noise] and [reliability]),
/// recomputed from the file: at e = 0.9 the 12 values of xmax have mean 2.998 cm and SD
/// 0.069 cm (ideal 2.909 cm), and the lognormal R (model.md §5, eq. 6) runs from 0.979 to
/// 0.998 over the sweep. If the physics or the noise stream changes, update the comments.
#[test]
fn paper_comments_quote_what_the_file_gives() {
    let study = Study::load(&config("paper.toml")).unwrap();
    let plan = Plan::new(&study);
    let rel = study.reliability;
    let k = 3.0 * rel.E * rel.r / (rel.L * rel.L);
    let ln = |mu: f64, sd: f64| {
        let cv = sd / mu;
        let s = (1.0 + cv * cv).ln().sqrt();
        (mu.ln() - s * s / 2.0, s)
    };
    let phi = |z: f64| 0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2);
    let (mut r_lo, mut r_hi) = (1.0f64, 0.0f64);
    for p in 0..plan.n_points() {
        let xs: Vec<f64> = (0..plan.n_cases() as u32)
            .map(|c| {
                let run = plan.run(p, c);
                let mut stream = plan.noise_stream(&run);
                let noise = match (&study.noise, stream.as_mut()) {
                    (Some(ns), Some(s)) => Some((ns, s)),
                    _ => None,
                };
                sim::simulate(
                    &run.system,
                    &study.solver,
                    &study.request,
                    noise,
                    &mut NoProbe,
                )
                .xmax
            })
            .collect();
        let n = xs.len() as f64;
        let mean = xs.iter().sum::<f64>() / n;
        let sd = (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        if plan.point_values(p)[0] == 0.9 {
            assert!((mean * 100.0 - 2.998).abs() < 5e-4, "mean {}", mean * 100.0);
            assert!((sd * 100.0 - 0.069).abs() < 5e-4, "sd {}", sd * 100.0);
            assert!(
                (xs[0] * 100.0 - 2.909).abs() < 5e-4,
                "ideal {}",
                xs[0] * 100.0
            );
        }
        let (a, sa) = ln(rel.strength_mean, rel.strength_sd);
        let (b, sb) = ln(k * mean, k * sd);
        let r = phi((a - b) / (sa * sa + sb * sb).sqrt());
        r_lo = r_lo.min(r);
        r_hi = r_hi.max(r);
    }
    assert!((r_lo - 0.979).abs() < 5e-4, "lowest R {r_lo}");
    assert!((r_hi - 0.998).abs() < 5e-4, "highest R {r_hi}");
}

/// Issue 9: `plan` warns when the part files will be tiny (many chunks of few runs), and says
/// what chunk size to use; the default chunk size gives no warning.
#[test]
fn plan_warns_when_part_files_will_be_tiny() {
    let tmp = tempfile::tempdir().unwrap();
    let grid = "[study]\nname = \"tiny\"\n[sweep]\ne = { start = 0.45, stop = 0.95, num = 400 }\n";
    let tiny = tmp.path().join("tiny.toml");
    std::fs::write(&tiny, format!("{grid}[run]\nchunk_points = 2\n")).unwrap();
    let text = plan(&tiny, tmp.path());
    let warning = field(&text, "warning");
    assert!(
        warning.starts_with("200 part files of 2 runs (about 10.8 kB, of which 10.6 kB is each"),
        "{warning}"
    );
    assert!(
        warning.contains("Set [run].chunk_points to 1000 or more"),
        "{warning}"
    );
    let default = tmp.path().join("default.toml");
    std::fs::write(&default, grid).unwrap();
    assert!(!plan(&default, tmp.path()).contains("warning"));
}

/// A harmonic study's curve is one task of the sweep: a study with one curve cannot use a
/// second thread, and the estimate says so instead of halving one curve's time.
#[test]
fn a_harmonic_estimate_takes_at_least_one_curve() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("one_curve.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"one_curve\"\n[system]\nm = 0.0\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n[sweep]\nr = { start = 0.9, stop = 1.1, num = 5 }\n",
    )
    .unwrap();
    let text = plan(&study, tmp.path());
    let estimate = field(&text, "time estimate");
    assert!(
        estimate.ends_with("a curve is one task, so its 1 curve keeps at most 1 thread busy)")
            || estimate.contains(" on 1 thread ("),
        "{estimate}"
    );
}

/// The bytes of every file under `dir`.
fn bytes_under(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .sum()
}

/// `fmt_bytes`'s text back to bytes ("61.5 kB").
fn parse_bytes(text: &str) -> f64 {
    let (v, unit) = text.split_once(' ').unwrap();
    let scale = match unit {
        "B" => 1.0,
        "kB" => 1e3,
        "MB" => 1e6,
        "GB" => 1e9,
        _ => panic!("unit {unit}"),
    };
    v.parse::<f64>().unwrap() * scale
}

/// A harmonic study with a census writes an `attractors` table beside its points (on the
/// showcase about three times their size): the disk estimate counts it, from the steady states
/// its timed sample found, and comes within a factor of 2 of what `run` writes.
#[test]
fn a_harmonic_disk_estimate_counts_the_attractors_table() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("states.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"states\"\n[system]\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n\
         starts = 4\nnonperiodic_peak = \"window\"\n[sweep]\nd = [0.005, 0.02]\n\
         r = { start = 0.9, stop = 1.1, num = 9 }\n",
    )
    .unwrap();
    let text = plan(&study, tmp.path());
    let disk = field(&text, "disk estimate");
    assert!(
        disk.contains("the attractors table about 90 bytes per steady state"),
        "{disk}"
    );
    let estimate = parse_bytes(disk.split(" (").next().unwrap());
    Command::cargo_bin("impactsweep")
        .unwrap()
        .args(["run".as_ref(), study.as_os_str(), "--out".as_ref()])
        .arg(tmp.path().join("out"))
        .assert()
        .success();
    let dir = tmp.path().join("out").join("states");
    let (points, attractors) = (
        bytes_under(&dir.join("points")),
        bytes_under(&dir.join("attractors")),
    );
    assert!(attractors > 0);
    let written = (points + attractors) as f64;
    assert!(
        (0.5..=2.0).contains(&(estimate / written)),
        "estimate {estimate} B against {written} B written ({points} points, {attractors} \
         attractors): {disk}"
    );
}

/// A harmonic study at one frequency: its timed sample is that frequency, said in the singular.
#[test]
fn a_one_frequency_sample_is_said_in_the_singular() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("one_r.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"one_r\"\n[system]\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\n\
         starts = 2\nnonperiodic_peak = \"window\"\n[sweep]\nm = [0.005, 0.01]\nr = [1.0]\n",
    )
    .unwrap();
    let text = plan(&study, tmp.path());
    // An axis of one value, too.
    assert!(text.contains("r = 1 (1 value)\n"), "{text}");
    let estimate = field(&text, "time estimate");
    assert!(
        estimate.contains("over a sample of 1 frequency of one design's curve"),
        "{estimate}"
    );
}
