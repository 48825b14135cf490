//! Issue 44, the random and record scenes in the sweep: a random study runs end to end through
//! the binary (run → reduce → status), its dataset is the same bits on 1 or 2 threads, in two
//! shards and after an interrupted run is resumed, a record study with a swept scale gets its fragility
//! columns, and `p_f` is the share of stored realizations whose amplitude passed the threshold
//! with its exact interval. Tiny studies (a few dozen realizations of a few seconds): the whole
//! file runs in a few seconds.

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::sim::random::RealizationRecord;
use impactsweep::store::{self, RunRow};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};
use predicates::prelude::*;

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// A structure in a Kanai–Tajimi ground motion's band (omega_n = 5 pi rad/s, 2 % damping),
/// with and without a damper and two clearances: 4 design points × `n` realizations of 2 s.
fn random_study(dir: &Path, name: &str, n: u64) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            "[study]\nname = \"{name}\"\nseed = 44\n[system]\nM = 1.0\nK = 246.7\nC = 0.628\n\
             e = 0.6\n[scene]\nkind = \"random\"\nspectrum = \"kanai-tajimi\"\nomega_g = 15.708\n\
             zeta_g = 0.6\nS0 = 0.004\nduration = 2\nthreshold = 0.012\nrealizations = {n}\n\
             [sweep]\nm = [0.0, 0.05]\nd = [0.01, 0.03]\n"
        ),
    )
    .unwrap();
    path
}

/// Every stored row of a run directory, in chunk order.
fn rows(dir: &Path) -> Vec<RunRow<RealizationRecord>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<RealizationRecord>(p).unwrap())
        .collect()
}

/// The part files of a run directory, by name, as bytes.
fn parts(dir: &Path) -> Vec<(String, Vec<u8>)> {
    common::dataset(dir)
        .into_iter()
        .filter(|(n, _)| n.ends_with(".parquet"))
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
fn issue_44_a_random_study_runs_reduces_and_reports_through_the_binary() {
    let tmp = tempfile::tempdir().unwrap();
    let study = random_study(tmp.path(), "quake", 24);
    let out = tmp.path().join("out");
    let dir = common::run_study_file(&study, &out, "quake");
    bin()
        .arg("status")
        .arg(&dir)
        .assert()
        .success()
        .stdout(predicate::str::contains("runs 96/96 done"))
        .stdout(predicate::str::contains("complete"));
    // The points table: one row per realization, the issue's columns, the load's values.
    let part = store::part_path(&dir, 0);
    let meta = store::part_metadata(&part).unwrap();
    assert_eq!(meta[store::META_TABLE], "random_points");
    let rows = rows(&dir);
    assert_eq!(rows.len(), 96);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.point_id, i as u64);
        assert_eq!((r.point, u64::from(r.case)), (i as u64 / 24, i as u64 % 24));
        assert_eq!(r.noise_seed, Some(u64::from(r.case)));
        let rec = &r.record.record;
        assert_eq!(rec.outcome, impactsweep::sim::Outcome::Ok);
        assert!(rec.amplitude > 0.0 && rec.rms_x > 0.0 && rec.rms_x < rec.amplitude);
        assert!(rec.rms_acc > 0.0 && rec.t_peak <= 2.0);
        // The first passage is stored exactly when the amplitude passed the threshold.
        assert_eq!(rec.first_passage_time.is_some(), rec.amplitude > 0.012);
        assert_eq!(r.record.load[0], Some(0.004)); // S0
        assert_eq!(r.record.load[5], None); // a random load has no scale
        if r.system.m == 0.0 {
            assert_eq!(rec.impacts, 0);
        }
    }
    // The same realization is the same load at every design: without a damper the clearance
    // changes nothing, bit for bit.
    for c in 0..24 {
        assert_eq!(rows[c].record.record, rows[24 + c].record.record);
    }
    bin().arg("reduce").arg(&dir).assert().success();
    // p_f is the share of realizations that passed, with its Clopper–Pearson interval.
    let summary = dir.join("summary.csv");
    let pf = column(&summary, "p_f");
    let (lo, hi) = (column(&summary, "p_f_lo"), column(&summary, "p_f_hi"));
    let exceed = column(&summary, "n_exceed");
    let points = column(&summary, "point");
    assert_eq!(points.len(), 4);
    let mut any_between = false;
    for (i, p) in points.iter().enumerate() {
        let p: u64 = p.parse().unwrap();
        let k = rows
            .iter()
            .filter(|r| r.point == p && r.record.record.amplitude > 0.012)
            .count();
        assert_eq!(exceed[i], k.to_string());
        let want = impactsweep::stats::binomial::clopper_pearson(k as u64, 24, 0.95);
        let got: f64 = pf[i].parse().unwrap();
        assert_eq!(got, k as f64 / 24.0);
        assert!((lo[i].parse::<f64>().unwrap() - want.lo).abs() < 1e-12);
        assert!((hi[i].parse::<f64>().unwrap() - want.hi).abs() < 1e-12);
        any_between |= k > 0 && k < 24;
    }
    assert!(
        any_between,
        "a test of p_f needs a design with 0 < p_f < 1: {pf:?}"
    );
    // Ranked by p_f: rank 1 has the lowest.
    let ranks = column(&summary, "rank");
    let best = ranks.iter().position(|r| r == "1").unwrap();
    let lowest = pf
        .iter()
        .map(|v| v.parse::<f64>().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(pf[best].parse::<f64>().unwrap(), lowest);
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("## First-passage reliability")
            && report.contains("24 realizations per design")
            && report.contains("Clopper–Pearson"),
        "{report}"
    );
    // The two designs without a damper (m = 0 at either d) are one system: one row, with
    // the range of their ranks.
    let table = report
        .split("## First-passage reliability")
        .nth(1)
        .and_then(|t| t.split("\n\n").find(|b| b.starts_with("| rank |")))
        .unwrap_or_else(|| panic!("{report}"));
    assert_eq!(table.lines().count(), 2 + 3, "{table}");
    assert!(
        table.contains("| m = 0 kg, any d (no damper, 2 designs) |")
            && !table.contains("m = 0 kg, d ="),
        "{table}"
    );
    assert!(dir.join("report.html").exists());
}

#[test]
fn issue_44_threads_shards_and_resume_give_the_same_bits() {
    let tmp = tempfile::tempdir().unwrap();
    let study = random_study(tmp.path(), "det", 12);
    let run = |out: &str, threads: &str, extra: &[&str]| -> PathBuf {
        let out = tmp.path().join(out);
        bin()
            .arg("run")
            .arg(&study)
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
    assert_eq!(parts(&one).len(), 4);
    assert!(
        common::dataset(&one) == common::dataset(&two),
        "the datasets differ"
    );
    // An interrupted run (one chunk of four written), resumed on two threads.
    let s = Study::load(&study).unwrap();
    let resumed = tmp.path().join("resumed");
    let first = sweep::run_study(
        &s,
        &resumed,
        &SweepOptions {
            threads: Some(1),
            chunk_points: Some(1),
            stop_after: Some(1),
            ..SweepOptions::default()
        },
    )
    .unwrap();
    assert_eq!((first.chunks_written, first.chunks_left), (1, 3));
    bin()
        .arg("run")
        .arg(&study)
        .args(["--out", resumed.to_str().unwrap(), "--quiet", "--resume"])
        .args(["--threads", "2"])
        .assert()
        .success();
    assert!(
        parts(&resumed.join("det")) == parts(&one),
        "the resumed parts differ"
    );
    // Two shards into one directory.
    for shard in ["0/2", "1/2"] {
        run("sharded", "1", &["--chunk-points", "1", "--shard", shard]);
    }
    assert!(
        parts(&tmp.path().join("sharded").join("det")) == parts(&one),
        "the sharded parts differ"
    );
    // Another chunk size cuts other part files, of the same rows.
    let whole = run("whole", "2", &[]);
    assert_eq!(parts(&whole).len(), 1);
    assert_eq!(rows(&whole), rows(&one));
    // A design point's realizations split into blocks of 5 (5, 5 and 2 of 12: 3 chunks a
    // point, 12 in all): interrupted after 4, resumed, and in three shards, the same rows; its
    // reduction (each point's blocks read together) the same summary as the whole points'.
    let text = std::fs::read_to_string(&study).unwrap() + "[run]\nchunk_realizations = 5\n";
    let blocked_study = tmp.path().join("blocked.toml");
    std::fs::write(&blocked_study, text.replace("\"det\"", "\"blocked\"")).unwrap();
    let b = Study::load(&blocked_study).unwrap();
    let blocked = tmp.path().join("blocked");
    let first = sweep::run_study(
        &b,
        &blocked,
        &SweepOptions {
            threads: Some(2),
            stop_after: Some(4),
            ..SweepOptions::default()
        },
    )
    .unwrap();
    assert_eq!((first.chunks_written, first.chunks_left), (4, 8));
    bin()
        .arg("run")
        .arg(&blocked_study)
        .args(["--out", blocked.to_str().unwrap(), "--quiet", "--resume"])
        .assert()
        .success();
    let blocked = blocked.join("blocked");
    assert_eq!(parts(&blocked).len(), 12);
    assert_eq!(rows(&blocked), rows(&one));
    for shard in ["0/3", "1/3", "2/3"] {
        bin()
            .arg("run")
            .arg(&blocked_study)
            .args([
                "--out",
                tmp.path().join("bshard").to_str().unwrap(),
                "--quiet",
            ])
            .args(["--shard", shard])
            .assert()
            .success();
    }
    assert!(
        parts(&tmp.path().join("bshard").join("blocked")) == parts(&blocked),
        "the sharded blocks differ"
    );
    bin()
        .arg("status")
        .arg(&blocked)
        .assert()
        .success()
        .stdout(predicate::str::contains("chunks 12/12 done"));
    for dir in [&blocked, &whole] {
        bin().arg("reduce").arg(dir).assert().success();
    }
    assert_eq!(
        std::fs::read(blocked.join("summary.csv")).unwrap(),
        std::fs::read(whole.join("summary.csv")).unwrap(),
        "the blocked reduction differs"
    );
}

#[test]
fn issue_44_a_record_study_with_a_swept_scale_gets_its_fragility() {
    let tmp = tempfile::tempdir().unwrap();
    // A 3-s accelerogram: a 2.5 Hz burst under a rise and a decay, at 0.01 s.
    let quake = |t: f64| -> f64 {
        let a = (t * std::f64::consts::TAU * 2.5).sin()
            * (t / 0.5).min(1.0)
            * (-(t - 1.5).max(0.0)).exp();
        f64::from(a as f32)
    };
    let mut csv = String::from("t,a\n");
    for k in 0..=300 {
        let t = k as f64 / 100.0;
        csv.push_str(&format!("{t},{}\n", quake(k as f64 * 0.01)));
    }
    std::fs::write(tmp.path().join("quake.csv"), csv).unwrap();
    let study = tmp.path().join("rec.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"rec\"\n[system]\nM = 1.0\nK = 246.7\nC = 0.628\ne = 0.6\n\
         [scene]\nkind = \"record\"\nrecord = \"quake.csv\"\nduration = 4\nthreshold = 0.1\n\
         [sweep]\nm = [0.0, 0.05]\nscale = [0.25, 0.5, 1, 2, 4, 8]\n",
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "rec");
    let rows = rows(&dir);
    assert_eq!(rows.len(), 12);
    for r in &rows {
        assert_eq!(r.noise_seed, None); // a record draws no normals
        assert!(r.record.load[5].is_some() && r.record.load[0].is_none());
        assert_eq!(r.record.record.samples, 400);
    }
    // The structure alone is linear: its amplitude grows in proportion to the scale.
    let bare: Vec<f64> = rows
        .iter()
        .filter(|r| r.system.m == 0.0)
        .map(|r| r.record.record.amplitude / r.record.load[5].unwrap())
        .collect();
    for a in &bare {
        assert!((a / bare[0] - 1.0).abs() < 1e-9, "{bare:?}");
    }
    // The same record as Parquet (`t` as Float64, `a` as Float32 widened back: the CSV's
    // values are written as the f32 they round to, so both files hold the same numbers) runs
    // to the same records, and its run directory keeps `record.parquet`.
    let (ts, accs): (Vec<f64>, Vec<f64>) = (0..=300)
        .map(|k| (k as f64 / 100.0, quake(k as f64 * 0.01)))
        .unzip();
    let schema = std::sync::Arc::new(arrow_schema::Schema::new(vec![
        arrow_schema::Field::new("t", arrow_schema::DataType::Float64, false),
        arrow_schema::Field::new("a", arrow_schema::DataType::Float32, false),
    ]));
    let batch = arrow_array::RecordBatch::try_new(
        schema.clone(),
        vec![
            std::sync::Arc::new(arrow_array::Float64Array::from(ts)),
            std::sync::Arc::new(arrow_array::Float32Array::from(
                accs.iter().map(|&a| a as f32).collect::<Vec<f32>>(),
            )),
        ],
    )
    .unwrap();
    let file = std::fs::File::create(tmp.path().join("quake.parquet")).unwrap();
    let mut w = parquet::arrow::ArrowWriter::try_new(file, schema, None).unwrap();
    w.write(&batch).unwrap();
    w.close().unwrap();
    let pq_study = tmp.path().join("recpq.toml");
    std::fs::write(
        &pq_study,
        std::fs::read_to_string(&study)
            .unwrap()
            .replace("quake.csv", "quake.parquet")
            .replace("\"rec\"", "\"recpq\""),
    )
    .unwrap();
    let pq_dir = common::run_study_file(&pq_study, &tmp.path().join("out"), "recpq");
    assert!(pq_dir.join("record.parquet").exists());
    let pq_rows = self::rows(&pq_dir);
    assert_eq!(pq_rows.len(), rows.len());
    for (p, c) in pq_rows.iter().zip(&rows) {
        assert_eq!(p.record, c.record, "the Parquet record runs as its CSV");
    }
    // The run directory keeps the record beside its study.toml: its own study loads from
    // there (reduce and status read it), wherever the record was.
    assert!(dir.join("record.csv").exists());
    std::fs::remove_file(tmp.path().join("quake.csv")).unwrap();
    bin().arg("status").arg(&dir).assert().success();
    bin().arg("reduce").arg(&dir).assert().success();
    let summary = dir.join("summary.csv");
    // Two designs (the scale is the intensity), ranked at the design scale 1 (the lower
    // middle of six values), each with its fragility fit.
    assert_eq!(column(&summary, "point").len(), 2);
    assert_eq!(column(&summary, "intensity"), ["scale", "scale"]);
    assert_eq!(column(&summary, "intensity_design"), ["1", "1"]);
    let outcomes = column(&summary, "fragility_outcome");
    // One record per scale: every design's exceedances are separated in scale (all safe
    // below some scale, all passed above it), so the fit says so instead of a number.
    assert_eq!(outcomes, ["separated", "separated"]);
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("### Fragility over scale"), "{report}");
    // The fragility chart and its data: both designs at the six scales (the one without
    // damper is drawn dashed beside the ranked one).
    assert!(dir.join("fragility.png").exists() && dir.join("fragility.svg").exists());
    let data = std::fs::read_to_string(dir.join("fragility.csv")).unwrap();
    assert_eq!(data.lines().next(), Some("point,intensity,p_f,p_f_fitted"));
    assert_eq!(data.lines().count(), 1 + 12);
    assert!(report.contains("fragility.svg"), "{report}");
    assert!(
        report.contains("1 record run per design")
            || report.contains("6 intensities × 1 record run"),
        "{report}"
    );
}

/// `p_f` against an independent Monte Carlo of the linear structure (the inner mass absent) on
/// the same loads: white force of density `S0` sampled at `dt` and linear between samples, so
/// the exact motion over each sample is the free motion in closed form plus the particular
/// solution of a linear load, written here from the textbook (underdamped, start at rest). The
/// largest `|x|` at the samples is at most the exact amplitude and at least
/// `amplitude (1 - kappa dt^2 / 8)`, `kappa = |x''| / |x|` at the peak (a parabola sampled at most
/// `dt / 2` from its top); `kappa` is `omega^2` plus the force's share, `|F| / (M |x|)`, which
/// at these peaks (`|x| > 0.15 m`, `|F| < 5 sigma_F = 177 N`) stays below `4 omega^2`. Each
/// realization's stored amplitude lies in that band, and the sweep's exceedance count between
/// the counts the samples give with and without that margin. A check of the sampled
/// structure's rms against `pi S0 / (K C)` is `tests/random.rs`'s.
#[test]
fn issue_44_p_f_of_the_linear_structure_matches_an_independent_monte_carlo() {
    use impactsweep::sim::random::{Normals, RealizationStream};
    let (m, k, c, s0, dt, duration, b, n) = (1.0, 400.0, 2.0, 1.0, 0.005, 10.0, 0.17, 200u64);
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("lin.toml");
    std::fs::write(
        &study,
        format!(
            "[study]\nname = \"lin\"\nseed = 9\n[system]\nM = {m}\nK = {k}\nC = {c}\nm = 0.0\n\
             [scene]\nkind = \"random\"\ninput = \"force\"\nspectrum = \"white\"\nS0 = {s0}\n\
             dt = {dt}\nduration = {duration}\nthreshold = {b}\nrealizations = {n}\n"
        ),
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "lin");
    let rows = rows(&dir);
    assert_eq!(rows.len(), n as usize);
    // The structure: x'' + 2 a x' + w^2 x = F / M, a = zeta w.
    let w = f64::sqrt(k / m);
    let a = c / (2.0 * m);
    let wd = (w * w - a * a).sqrt();
    let (e, cs, sn) = ((-a * dt).exp(), (wd * dt).cos(), (wd * dt).sin());
    let free = |x: f64, v: f64| {
        (
            e * (x * cs + (v + a * x) / wd * sn),
            e * (v * cs - (a * v + w * w * x) / wd * sn),
        )
    };
    let sigma = (std::f64::consts::TAU * s0 / dt).sqrt();
    let samples = (duration / dt).round() as usize;
    let margin = 4.0 * (w * dt).powi(2) / 8.0;
    let (mut strict, mut loose) = (0u64, 0u64);
    for r in &rows {
        let mut normals = RealizationStream::new(9, 0, u64::from(r.case));
        let (mut x, mut v, mut top) = (0.0f64, 0.0f64, 0.0f64);
        let mut f0 = sigma * normals.next_normal();
        for _ in 0..samples {
            let f1 = sigma * normals.next_normal();
            // Particular solution of F = f0 + s t: x_p = (F - C s / K) / K, v_p = s / K.
            let s = (f1 - f0) / dt;
            let (xp0, vp) = ((f0 - c * s / k) / k, s / k);
            let (xh, vh) = free(x - xp0, v - vp);
            x = xh + (f1 - c * s / k) / k;
            v = vh + vp;
            top = top.max(x.abs());
            f0 = f1;
        }
        let amp = r.record.record.amplitude;
        assert!(
            top <= amp * (1.0 + 1e-9) && top >= amp * (1.0 - margin),
            "realization {}: samples' largest |x| {top} against the amplitude {amp}",
            r.case
        );
        strict += u64::from(top > b);
        loose += u64::from(top > b * (1.0 - margin));
    }
    bin().arg("reduce").arg(&dir).assert().success();
    let exceed: u64 = column(&dir.join("summary.csv"), "n_exceed")[0]
        .parse()
        .unwrap();
    assert!(
        strict <= exceed && exceed <= loose,
        "{exceed} against {strict} ..= {loose}"
    );
    // The band is narrow (0.5 % of the threshold): the check decides nearly every realization.
    assert!(loose - strict <= 6, "{strict} ..= {loose}");
    assert!(exceed > n / 4 && exceed < 3 * n / 4, "p_f = {exceed}/{n}");
}

/// `reduce --subset N`: a design whose realizations passed the threshold fewer than 10 times
/// gets `p_f` by subset simulation (Au and Beck) over its white-noise samples, and its estimate
/// agrees with the Monte Carlo estimate of the same study (`--subset 0`) within both intervals
/// (the linear structure under white force, 3,000 realizations of 5 s: 6 passed 4.3 sigma).
/// Without `--subset` it is subset simulation with 1,000 per level.
#[test]
fn issue_44_subset_simulation_takes_the_designs_monte_carlo_barely_sees() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("rare.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"rare\"\nseed = 1\n[system]\nM = 1.0\nK = 400.0\nC = 2.0\nm = 0.0\n\
         [scene]\nkind = \"random\"\ninput = \"force\"\nspectrum = \"white\"\nS0 = 1.0\n\
         duration = 5\nthreshold = 0.27\nrealizations = 3000\n",
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "rare");
    bin()
        .arg("reduce")
        .arg(&dir)
        .args(["--subset", "0"])
        .assert()
        .success();
    let summary = dir.join("summary.csv");
    let num = |name: &str| -> f64 { column(&summary, name)[0].parse().unwrap() };
    assert_eq!(column(&summary, "p_f_method"), ["monte_carlo"]);
    let exceed = num("n_exceed");
    assert!(exceed < 10.0, "{exceed}");
    let (mc, mc_lo, mc_hi) = (num("p_f"), num("p_f_lo"), num("p_f_hi"));
    bin()
        .arg("reduce")
        .arg(&dir)
        .args(["--subset", "500"])
        .assert()
        .success();
    assert_eq!(column(&summary, "p_f_method"), ["subset"]);
    assert_eq!(num("n_exceed"), exceed);
    let (ss, ss_lo, ss_hi) = (num("p_f"), num("p_f_lo"), num("p_f_hi"));
    assert!(
        ss > 0.0 && ss_lo < ss && ss < ss_hi,
        "{ss} [{ss_lo}, {ss_hi}]"
    );
    assert!(
        mc_lo <= ss && ss <= mc_hi && ss_lo <= mc && mc <= ss_hi,
        "subset {ss} [{ss_lo}, {ss_hi}] against Monte Carlo {mc} [{mc_lo}, {mc_hi}]"
    );
    let (cov, upper) = (num("p_f_cov"), num("p_f_cov_upper"));
    assert!(cov > 0.0 && cov <= upper && upper < 1.0, "{cov} {upper}");
    // Three levels of 500 (the chains of the later levels start from the 50 seeds).
    assert_eq!(column(&summary, "subset_runs"), ["1400"]);
    assert_eq!(column(&summary, "subset_repeats"), ["1"]);
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("(subset simulation, CoV"), "{report}");
    assert!(
        report.contains("with the levels fully correlated"),
        "{report}"
    );
    // Issue 67: independent repeats, their mean and an interval from their spread, said so.
    bin()
        .arg("reduce")
        .arg(&dir)
        .args(["--subset", "500", "--subset-repeats", "4"])
        .assert()
        .success();
    assert_eq!(column(&summary, "subset_repeats"), ["4"]);
    let mean = num("p_f");
    assert!(
        mean > 0.0 && num("p_f_lo") < mean && mean < num("p_f_hi"),
        "{mean}"
    );
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("the mean of 4 independent subset simulations")
            && report.contains("from the spread of the 4 runs"),
        "{report}"
    );
    bin().arg("reduce").arg(&dir).assert().success();
    assert_eq!(column(&summary, "p_f_method"), ["subset"]);
    assert_eq!(column(&summary, "subset_runs"), ["3700"]);
    // One draw of each: their 95 % intervals overlap (tests/subset.rs checks the estimator
    // over many seeds).
    assert!(
        num("p_f_lo") <= mc_hi && mc_lo <= num("p_f_hi"),
        "subset {} [{}, {}] against Monte Carlo {mc} [{mc_lo}, {mc_hi}]",
        num("p_f"),
        num("p_f_lo"),
        num("p_f_hi")
    );
    bin()
        .arg("reduce")
        .arg(&dir)
        .args(["--subset", "55"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "expected 0 (Monte Carlo only) or a whole number of samples per level",
        ));
}

/// The design intensity chosen by `[scene] design_intensity`, subset simulation by default where
/// Monte Carlo barely sees a failure, its estimate ranking the designs, and the ranking by
/// median capacity: the linear structure under white force at two dampings, three intensities of
/// 400 realizations, ranked at the lowest, where no realization passes.
#[test]
fn issue_44_the_designs_rank_on_subset_simulation_at_the_chosen_intensity() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("damped.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"damped\"\nseed = 3\n[system]\nM = 1.0\nK = 400.0\nm = 0.0\n\
         [scene]\nkind = \"random\"\ninput = \"force\"\nspectrum = \"white\"\nduration = 5\n\
         threshold = 0.27\nrealizations = 400\ndesign_intensity = 0.5\n\
         [sweep]\nC = [2.0, 3.0]\nS0 = [0.5, 2.0, 8.0]\n",
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "damped");
    bin().arg("reduce").arg(&dir).assert().success();
    let summary = dir.join("summary.csv");
    let nums = |name: &str| -> Vec<f64> {
        column(&summary, name)
            .iter()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    assert_eq!(column(&summary, "intensity_design"), ["0.5", "0.5"]);
    assert_eq!(nums("n_exceed"), [0.0, 0.0]);
    assert_eq!(column(&summary, "p_f_method"), ["subset", "subset"]);
    let (pf, ps) = (nums("p_f"), nums("p_s"));
    // sigma_x = sqrt(pi S0 / (K C)): 4.3 and 5.3 sigma over 5 s, both near 1e-3 or below.
    assert!(pf[1] < pf[0] && pf[0] < 0.01 && pf[1] > 0.0, "{pf:?}");
    for (f, s) in pf.iter().zip(&ps) {
        assert_eq!(
            *s,
            1.0 - f,
            "the ranking's p_s is subset simulation's 1 - p_f"
        );
    }
    // The better damped design ranks first, on subset simulation's estimate where Monte Carlo
    // ties them at 0 of 400.
    assert_eq!(column(&summary, "rank"), ["2", "1"]);
    // Over the intensities it is also the stronger: the larger median capacity.
    let theta = nums("fragility_theta");
    assert!(theta[1] > theta[0], "{theta:?}");
    assert_eq!(column(&summary, "capacity_rank"), ["2", "1"]);
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("S0 = 0.5 (the study's `design_intensity`)"),
        "{report}"
    );
    assert!(report.contains("| capacity rank |"), "{report}");
}

/// The smallest random study a newcomer writes (a spectrum and its level, nothing else: one
/// design point, no threshold) runs, reduces and reports in words, without a `NaN` in them: the
/// jump section says there is no line to look along.
#[test]
fn the_smallest_random_study_reports_in_words() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("eq.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"eq\"\n[scene]\nkind = \"random\"\nspectrum = \"kanai-tajimi\"\n\
         S0 = 0.005\nduration = 2\nrealizations = 20\n",
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.path().join("out"), "eq");
    bin().arg("reduce").arg(&dir).assert().success();
    bin().arg("status").arg(&dir).assert().success();
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("One design point: no line of the grid to look for jumps along."),
        "{report}"
    );
    assert!(!report.contains("NaN"), "{report}");
}
