//! Issue 67, earthquake decisions: intensity measures in g, capacities by incremental dynamic
//! analysis, annual risk over a hazard curve. A small Clough–Penzien study (2 designs, 3
//! stripes of Sa(T1), 120 realizations of 4 s) runs through the binary: the stripes' Monte
//! Carlo `p_f` lies inside the capacities' curve's bootstrap interval at every stripe, the
//! lognormal's `lambda_f` meets Cornell's closed form (so does the stripes' own fit's), the
//! decision's `lambda_f` is the stripes' own fit's where motions fall back (inside its
//! interval) and the capacities' where none does, the designs rank by
//! `lambda_f`, and the capacities are the same bits on 1 or 2 threads, another
//! chunk size and after a resume. Bad hazard tables are refused naming the file, the line and
//! what is allowed.

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::reduce::random::{RandomReducer, design_study, options};
use impactsweep::sim::random::RealizationRecord;
use impactsweep::store::{self, RunRow};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

const STUDY: &str = "[study]\nname = \"NAME\"\nseed = 67\n[system]\nM = 1.0\nK = 246.7\nC = 0.628\n\
e = 0.6\nd = 0.02\n[scene]\nkind = \"random\"\nspectrum = \"clough-penzien\"\nomega_g = 15.708\n\
zeta_g = 0.6\nomega_f = 1.5708\nzeta_f = 0.6\nS0 = 0.005\nduration = 4\n\
envelope = { t1 = 0.5, t2 = 2.5, c = 0.5 }\nthreshold = 0.01\nrealizations = 120\n\
intensity = \"sa\"\ndesign_intensity = 0.2\n[sweep]\nm = [0.0, 0.1]\nim = [0.15, 0.2, 0.25]\n\
[hazard]\nk0 = 4e-4\nk = 2.5\n";

fn study(dir: &Path, name: &str, extra: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, STUDY.replace("NAME", name) + extra).unwrap();
    path
}

fn rows(dir: &Path) -> Vec<RunRow<RealizationRecord>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<RealizationRecord>(p).unwrap())
        .collect()
}

/// A CSV column by name, one string per row.
fn column(path: &Path, name: &str) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = common::csv_cells(lines.next().unwrap());
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("{name} not in {header:?}"));
    lines.map(|l| common::csv_cells(l)[i].clone()).collect()
}

#[test]
fn issue_67_capacities_agree_with_the_stripes_and_the_designs_rank_by_annual_risk() {
    let tmp = tempfile::tempdir().unwrap();
    let path = study(tmp.path(), "risk", "");
    let out = tmp.path().join("out");
    let dir = common::run_study_file(&path, &out, "risk");
    let all = rows(&dir);
    // Every realization carries its own intensity measures; the design stripe its capacity.
    assert_eq!(all.len(), 2 * 3 * 120);
    for r in &all {
        let own = r.record.own.expect("pga and sa");
        assert!(own.pga > 0.0 && own.sa > 0.0);
        let stripe = r.record.load[6].unwrap();
        let gain = r.record.load[5].unwrap();
        assert!((gain * own.sa / stripe - 1.0).abs() < 1e-12);
        assert_eq!(r.record.capacity.is_some(), stripe == 0.2);
    }
    // The reduction: the stripes against the capacities.
    let s = Study::load(&dir.join("study.toml")).unwrap();
    let design = design_study(&s);
    let mut reducer = RandomReducer::new(&s, &design, options(&design));
    reducer.push(all.clone());
    let (_, rs) = reducer.finish(None);
    assert_eq!(rs.risk.len(), 2);
    for d in &rs.risk {
        assert_eq!(d.n, 120);
        assert_eq!(d.stripes.len(), 3);
        for x in &d.stripes {
            assert!(
                x.p_f >= x.empirical_lo && x.p_f <= x.empirical_hi,
                "design {} at {} g: Monte Carlo {} outside the capacities' [{}, {}]",
                d.design,
                x.im,
                x.p_f,
                x.empirical_lo,
                x.empirical_hi
            );
        }
        // Some stripe sees failures and some does not fail everything: the test has teeth.
        assert!(
            d.stripes.iter().any(|x| x.p_f > 0.0 && x.p_f < 1.0),
            "{d:?}"
        );
        let k = d.risk.as_ref().unwrap();
        assert!(k.lambda_f.0 > 0.0 && k.lambda_f.1 <= k.lambda_f.0 && k.lambda_f.0 <= k.lambda_f.2);
        assert!(k.deaggregation[0] < k.deaggregation[1] && k.deaggregation[1] < k.deaggregation[2]);
    }
    // The reduce's tables: Cornell's closed form, the ranking by lambda_f.
    bin().arg("reduce").arg(&dir).assert().success();
    let summary = dir.join("summary.csv");
    let logn = column(&summary, "lambda_f_lognormal");
    let cornell = column(&summary, "lambda_f_cornell");
    for (a, b) in logn.iter().zip(&cornell) {
        let (a, b): (f64, f64) = (a.parse().unwrap(), b.parse().unwrap());
        assert!((a / b - 1.0).abs() < 1e-6, "{a} against Cornell's {b}");
    }
    let lambda: Vec<f64> = column(&summary, "lambda_f")
        .iter()
        .map(|v| v.parse().unwrap())
        .collect();
    let risk_rank: Vec<u64> = column(&summary, "risk_rank")
        .iter()
        .map(|v| v.parse().unwrap())
        .collect();
    let rank: Vec<u64> = column(&summary, "rank")
        .iter()
        .map(|v| v.parse().unwrap())
        .collect();
    let best = if lambda[0] <= lambda[1] { 0 } else { 1 };
    assert_eq!(risk_rank[best], 1);
    assert_eq!(rank, risk_rank, "the designs rank by lambda_f");
    let caps = dir.join("capacities.csv");
    assert_eq!(column(&caps, "capacity").len(), 240);
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("Capacities by incremental dynamic analysis"));
    assert!(report.contains("Annual risk"));
    // The check over the stripes' own fragility: `lambda_f` over the lognormal fitted to the
    // stripes' counts, Cornell's closed form of `fragility_theta` and `fragility_beta` under
    // this power law (k0 = 4e-4, k = 2.5), and the decision says it.
    let number = |name: &str| -> Vec<f64> {
        column(&summary, name)
            .iter()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let (theta, beta) = (number("fragility_theta"), number("fragility_beta"));
    let stripes = number("lambda_f_stripes");
    for d in 0..2 {
        let cornell = 4e-4 * theta[d].powf(-2.5) * (2.5f64 * 2.5 * beta[d] * beta[d] / 2.0).exp();
        assert!(
            (stripes[d] / cornell - 1.0).abs() < 1e-6,
            "design {d}: {} over the stripes against Cornell's {cornell}",
            stripes[d]
        );
    }
    // The decision rests on the stripes' own fit where motions fall back (there a capacity is
    // the crossing its search met), else on the capacities' curve that holds; `lambda_f` is then
    // that value, the stripes' inside their bootstrap interval, and the decision states the
    // other basis as its check.
    let curve = column(&summary, "lambda_f_curve");
    let (lo, hi) = (number("lambda_f_stripes_lo"), number("lambda_f_stripes_hi"));
    let capacities = number("lambda_f_capacities");
    let fit_ok = column(&summary, "fit_ok");
    let fall_back = number("capacities_resurrected");
    let (empirical, lognormal) = (number("lambda_f_empirical"), number("lambda_f_lognormal"));
    for d in 0..2 {
        assert!(lo[d] < stripes[d] && stripes[d] < hi[d], "design {d}");
        let own = if fit_ok[d] == "true" {
            lognormal[d]
        } else {
            empirical[d]
        };
        assert_eq!(
            capacities[d], own,
            "design {d}: the capacities' curve that holds"
        );
        if fall_back[d] > 0.0 {
            assert_eq!(curve[d], "stripes", "design {d}");
            assert_eq!(lambda[d], stripes[d], "design {d}");
        } else {
            assert_ne!(curve[d], "stripes", "design {d}");
            assert_eq!(lambda[d], capacities[d], "design {d}");
        }
    }
    // The structure without a damper never falls back; the damped design does here, so both
    // bases are exercised.
    assert_eq!(fall_back[0], 0.0);
    assert!(fall_back[1] > 0.0, "{fall_back:?}");
    assert!(report.contains("its λ_f is"), "{report}");
}

#[test]
fn issue_67_the_capacities_are_the_same_bits_on_any_thread_count_chunk_and_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let path = study(tmp.path(), "det", "");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("realizations = 120", "realizations = 10");
    std::fs::write(&path, text).unwrap();
    let run = |out: &str, threads: &str, extra: &[&str]| -> PathBuf {
        let out = tmp.path().join(out);
        bin()
            .arg("run")
            .arg(&path)
            .args([
                "--out",
                out.to_str().unwrap(),
                "--quiet",
                "--threads",
                threads,
            ])
            .args(extra)
            .assert()
            .success();
        out.join("det")
    };
    let one = run("one", "1", &["--chunk-points", "1"]);
    let two = run("two", "2", &["--chunk-points", "1"]);
    assert!(common::dataset(&one) == common::dataset(&two));
    let whole = run("whole", "2", &[]);
    assert_eq!(rows(&whole), rows(&one));
    assert!(rows(&one).iter().any(|r| r.record.capacity.is_some()));
    let s = Study::load(&path).unwrap();
    let resumed = tmp.path().join("resumed");
    let first = sweep::run_study(
        &s,
        &resumed,
        &SweepOptions {
            threads: Some(1),
            chunk_points: Some(1),
            stop_after: Some(2),
            ..SweepOptions::default()
        },
    )
    .unwrap();
    assert_eq!(first.chunks_written, 2);
    bin()
        .arg("run")
        .arg(&path)
        .args([
            "--out",
            resumed.to_str().unwrap(),
            "--quiet",
            "--resume",
            "--threads",
            "2",
        ])
        .assert()
        .success();
    assert_eq!(rows(&resumed.join("det")), rows(&one));
    // One realization at hand: `simulate --study` prints the sweep's row, the same bits, and
    // its trace.
    let all = rows(&one);
    let row = all
        .iter()
        .find(|r| r.point == 4 && r.case == 7)
        .expect("point 4, realization 7");
    let trace = tmp.path().join("q.csv");
    let out = bin()
        .args([
            "simulate",
            "--study",
            path.to_str().unwrap(),
            "--point",
            "4",
        ])
        .args([
            "--realization",
            "7",
            "--trace",
            trace.to_str().unwrap(),
            "--dt",
            "0.01",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let amplitude = json["record"]["amplitude"].as_f64().unwrap();
    assert_eq!(amplitude.to_bits(), row.record.record.amplitude.to_bits());
    let sa = json["own"]["sa"].as_f64().unwrap();
    assert_eq!(sa.to_bits(), row.record.own.unwrap().sa.to_bits());
    assert_eq!(
        json["capacity"]["capacity"].as_f64().map(f64::to_bits),
        row.record.capacity.map(|c| c.capacity.to_bits())
    );
    let lines = std::fs::read_to_string(&trace).unwrap().lines().count();
    assert!(lines > 400, "{lines} lines in the trace");
    let bad = bin()
        .args([
            "simulate",
            "--study",
            path.to_str().unwrap(),
            "--point",
            "99",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("--point 99") && err.contains("points 0 to 5"),
        "{err}"
    );
}

/// The error of loading `text` (with `hazard.csv` holding `table`) as a study.
fn error_of(tmp: &Path, name: &str, extra: &str, table: Option<&str>) -> String {
    if let Some(t) = table {
        std::fs::write(tmp.join("hazard.csv"), t).unwrap();
    }
    let text = STUDY
        .replace("NAME", name)
        .replace("[hazard]\nk0 = 4e-4\nk = 2.5\n", "")
        + extra;
    let path = tmp.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    Study::load(&path).unwrap_err().to_string()
}

#[test]
fn issue_67_bad_hazards_and_intensities_are_refused_with_what_is_allowed() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let table = "[hazard]\ntable = \"hazard.csv\"\n";
    let rising = error_of(t, "a", table, Some("im,rate\n0.1,0.01\n0.2,0.02\n"));
    assert!(
        rising.contains("a.toml") && rising.contains("hazard.csv"),
        "{rising}"
    );
    assert!(
        rising.contains("line 3") && rising.contains("decreases strictly"),
        "{rising}"
    );
    let negative = error_of(t, "b", table, Some("im,rate\n-0.1,0.01\n0.2,0.001\n"));
    assert!(
        negative.contains("line 2") && negative.contains("must be > 0"),
        "{negative}"
    );
    let one = error_of(t, "c", table, Some("im,rate\n0.1,0.01\n"));
    assert!(
        one.contains("1 row(s)") && one.contains("at least two"),
        "{one}"
    );
    let header = error_of(t, "d", table, Some("x,y\n0.1,0.01\n0.2,0.001\n"));
    assert!(header.contains("columns im (g) and rate"), "{header}");
    let both = error_of(t, "e", "[hazard]\nk0 = 1e-4\n", None);
    assert!(both.contains("[hazard]") && both.contains("k0"), "{both}");
    let k = error_of(t, "f", "[hazard]\nk0 = 1e-4\nk = -2\n", None);
    assert!(k.contains("[hazard].k = -2") && k.contains("k > 0"), "{k}");
    let years = error_of(t, "g", "[hazard]\nk0 = 1e-4\nk = 2\nyears = 0\n", None);
    assert!(
        years.contains("[hazard].years = 0") && years.contains("(0, 10000]"),
        "{years}"
    );
    // The intensity measure's own keys.
    let unknown = STUDY.replace("intensity = \"sa\"", "intensity = \"pgv\"");
    std::fs::write(t.join("h.toml"), unknown.replace("NAME", "h")).unwrap();
    let e = Study::load(&t.join("h.toml")).unwrap_err().to_string();
    assert!(
        e.contains("[scene].intensity = \"pgv\"") && e.contains("pga, sa"),
        "{e}"
    );
    let short = STUDY.replace("intensity = \"sa\"", "intensity = \"sa\"\nT = 0.001");
    std::fs::write(t.join("i.toml"), short.replace("NAME", "i")).unwrap();
    let e = Study::load(&t.join("i.toml")).unwrap_err().to_string();
    assert!(
        e.contains("[scene].T = 0.001") && e.contains("period of Sa"),
        "{e}"
    );
    let no_im = STUDY
        .replace("intensity = \"sa\"\n", "")
        .replace("design_intensity = 0.2\n", "");
    // Stripes without an intensity measure are named first, hazard or not.
    std::fs::write(t.join("j.toml"), no_im.replace("NAME", "j")).unwrap();
    let e = Study::load(&t.join("j.toml")).unwrap_err().to_string();
    assert!(
        e.contains("[sweep].im = [0.15, 0.2, 0.25]: stripes (g) scale each motion")
            && e.contains("give [scene] intensity = \"pga\" or \"sa\""),
        "{e}"
    );
    let no_stripes = no_im.replace("im = [0.15, 0.2, 0.25]\n", "");
    std::fs::write(t.join("k.toml"), no_stripes.replace("NAME", "k")).unwrap();
    let e = Study::load(&t.join("k.toml")).unwrap_err().to_string();
    assert!(
        e.contains("[hazard]") && e.contains("intensity = \"pga\" or \"sa\""),
        "{e}"
    );
}
