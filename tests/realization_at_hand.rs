//! Issue 67 item 9, one realization at hand: `impactsweep simulate --set scene=random` (and
//! `scene=record`) with a load's keys, a realization and a seed prints the row the sweep of the
//! one-point study of those keys stores, the same bits, under a study's defaults; its trace is
//! `simulate --study`'s; bad keys name the key, the value and what is allowed.

use std::path::Path;

use assert_cmd::Command;
use impactsweep::api::random_batch::RandomBatch;
use impactsweep::api::realization::RandomSetup;
use impactsweep::sim::random::RealizationRecord;
use impactsweep::store::{self, RunRow};

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// A Clough–Penzien load under the stripe `im = 0.3` g of PGA, the filters and the structure's
/// initial state left to their defaults: the keys of `--set`.
const KEYS: [&str; 13] = [
    "scene=random",
    "spectrum=clough-penzien",
    "S0=0.004",
    "duration=2",
    "threshold=0.01",
    "intensity=pga",
    "im=0.3",
    "M=1",
    "K=246.7",
    "C=0.628",
    "m=0.05",
    "d=0.02",
    "e=0.6",
];

/// The one-point study of [`KEYS`], three realizations under seed 5.
const STUDY: &str = "[study]\nname = \"one\"\nseed = 5\n[system]\nM = 1.0\nK = 246.7\nC = 0.628\n\
m = 0.05\nd = 0.02\ne = 0.6\n[scene]\nkind = \"random\"\nspectrum = \"clough-penzien\"\n\
S0 = 0.004\nduration = 2\nthreshold = 0.01\nintensity = \"pga\"\nrealizations = 3\n\
[sweep]\nim = [0.3]\n";

fn rows(dir: &Path) -> Vec<RunRow<RealizationRecord>> {
    store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<RealizationRecord>(p).unwrap())
        .collect()
}

/// `simulate` with `sets` (each after `--set`) and `extra` arguments; its stdout.
fn simulate(sets: &[&str], extra: &[&str]) -> String {
    let mut cmd = bin();
    cmd.arg("simulate");
    for s in sets {
        cmd.args(["--set", s]);
    }
    let out = cmd.args(extra).output().unwrap();
    assert!(
        out.status.success(),
        "{sets:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn bits(v: &serde_json::Value) -> Option<u64> {
    v.as_f64().map(f64::to_bits)
}

/// The row's JSON compared with a stored row, every float by its bits.
fn same_row(json: &serde_json::Value, row: &RunRow<RealizationRecord>) {
    let want = serde_json::to_value(&row.record).unwrap();
    for part in ["load", "own", "capacity", "record"] {
        assert_eq!(json[part], want[part], "{part}");
    }
    assert_eq!(
        bits(&json["record"]["amplitude"]),
        Some(row.record.record.amplitude.to_bits())
    );
    assert_eq!(
        bits(&json["capacity"]["capacity"]),
        row.record.capacity.map(|c| c.capacity.to_bits())
    );
}

#[test]
fn a_random_realization_by_its_keys_is_the_sweeps_row() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("one.toml");
    std::fs::write(&study, STUDY).unwrap();
    let out = tmp.path().join("out");
    bin()
        .args([
            "run",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .arg("--quiet")
        .assert()
        .success();
    let stored = rows(&out.join("one"));
    assert_eq!(stored.len(), 3);
    // The stripe's capacity, first passages: the comparison sees the intensity's whole path.
    assert!(stored.iter().all(|r| r.record.capacity.is_some()));
    for row in &stored {
        let c = row.case.to_string();
        let mut sets = KEYS.to_vec();
        let (real, seed) = (format!("realization={c}"), "seed=5".to_string());
        sets.push(&real);
        sets.push(&seed);
        let json: serde_json::Value = serde_json::from_str(&simulate(&sets, &["--json"])).unwrap();
        same_row(&json, row);
        assert_eq!(json["realization"], row.case);
        assert_eq!(
            (json["seed"].as_u64(), json["scene"].as_str()),
            (Some(5), Some("random"))
        );
        assert_eq!(
            json["system"]["v0"], 0.0,
            "a study's structure starts at rest"
        );
        // The library's setup gives the same record.
        let owned: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let (mine, _) = RandomSetup::from_sets("random", &owned)
            .unwrap()
            .run(None)
            .unwrap();
        assert_eq!(mine, row.record);
    }
    // The trace is `simulate --study`'s, byte for byte.
    let (a, b) = (tmp.path().join("a.csv"), tmp.path().join("b.csv"));
    let mut sets = KEYS.to_vec();
    sets.extend(["realization=2", "seed=5"]);
    let text = simulate(&sets, &["--trace", a.to_str().unwrap(), "--dt", "0.01"]);
    for line in [
        "outcome  ",
        "amplitude ",
        " cm at t = ",
        "capacity ",
        " g (",
        "trace    ",
    ] {
        assert!(text.contains(line), "{line:?} in {text}");
    }
    bin()
        .args([
            "simulate",
            "--study",
            study.to_str().unwrap(),
            "--realization",
        ])
        .args(["2", "--trace", b.to_str().unwrap(), "--dt", "0.01"])
        .assert()
        .success();
    let trace = std::fs::read(&a).unwrap();
    assert!(trace.len() > 200 * 10);
    assert_eq!(trace, std::fs::read(&b).unwrap());
}

#[test]
fn a_record_by_its_keys_and_a_batch_row_are_the_sweeps_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let mut csv = String::from("t,a\n");
    for i in 0..301 {
        let t = i as f64 * 0.01;
        let a = 3.0 * (2.0 * std::f64::consts::PI * 2.3 * t).sin() * (-0.5 * t).exp();
        csv.push_str(&format!("{t:?},{a:?}\n"));
    }
    std::fs::write(tmp.path().join("quake.csv"), csv).unwrap();
    let study = tmp.path().join("rec.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"rec\"\n[system]\nK = 246.7\nd = 0.02\n[scene]\nkind = \"record\"\n\
         record = \"quake.csv\"\nthreshold = 0.02\n[sweep]\nscale = [0.5, 2.0]\nm = [0.0, 0.05]\n",
    )
    .unwrap();
    let out = tmp.path().join("out");
    bin()
        .args([
            "run",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .arg("--quiet")
        .assert()
        .success();
    let stored = rows(&out.join("rec"));
    assert_eq!(stored.len(), 4);
    let base = [
        "scene=record",
        "record=quake.csv",
        "K=246.7",
        "d=0.02",
        "threshold=0.02",
    ];
    // The binary reads the record relative to its working directory.
    for row in &stored {
        let scale = format!("scale={:?}", row.record.load[5].unwrap());
        let m = format!("m={:?}", row.system.m);
        let mut sets = base.to_vec();
        sets.extend([scale.as_str(), m.as_str()]);
        let mut cmd = bin();
        cmd.current_dir(tmp.path()).arg("simulate").arg("--json");
        for s in &sets {
            cmd.args(["--set", s]);
        }
        let output = cmd.output().unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        same_row(&json, row);
        assert_eq!(json["scene"], "record");
    }
    // A batch over the record: its rows are the sweep's, but for the row's own place.
    let path = tmp.path().join("quake.csv");
    let record = format!("record={}", path.display());
    let sets: Vec<String> = [
        "scene=record",
        &record,
        "K=246.7",
        "d=0.02",
        "threshold=0.02",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let setup = RandomSetup::from_sets("record", &sets).unwrap();
    let names = vec!["scale".to_string(), "m".to_string()];
    let cols = vec![
        stored.iter().map(|r| r.record.load[5].unwrap()).collect(),
        stored.iter().map(|r| r.system.m).collect(),
    ];
    let batch = RandomBatch::new(&setup, &names, &cols, stored.len()).unwrap();
    for (i, row) in stored.iter().enumerate() {
        let (s, c) = batch.row(i).unwrap();
        let mine = RandomBatch::run(i, &s, c, None, true);
        assert_eq!(mine.record, row.record);
        assert_eq!(mine.system, row.system);
        assert_eq!(
            (mine.point_id, mine.point, mine.case),
            (i as u64, i as u64, 0)
        );
    }
}

/// `simulate` with `sets` fails with exit status 2 and `message`.
fn refused(sets: &[&str], message: &str) {
    let mut cmd = bin();
    cmd.arg("simulate");
    for s in sets {
        cmd.args(["--set", s]);
    }
    let out = cmd.output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{sets:?}");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.trim_end().starts_with(&format!("error: {message}")),
        "{sets:?}: {err}"
    );
}

#[test]
fn bad_keys_of_a_realization_name_the_key_the_value_and_what_is_allowed() {
    let r = [
        "scene=random",
        "spectrum=kanai-tajimi",
        "S0=0.01",
        "duration=1",
    ];
    let with = |extra: &'static str| {
        let mut v = r.to_vec();
        v.push(extra);
        v
    };
    refused(
        &with("zeta_g=20"),
        "--set zeta_g = 20: a filter damping ratio must be in [0.001, 10]",
    );
    refused(
        &with("omega_f=3"),
        "--set omega_f = 3: spectrum = \"kanai-tajimi\" has no omega_f",
    );
    refused(
        &with("realization=-2"),
        "--set realization=-2: must be a whole number in [0, 9999999]",
    );
    refused(
        &with("t_end=3"),
        "--set t_end=3: a free-decay key (a random or record run lasts its duration) for \
         scene=random; allowed keys: scene input spectrum S0",
    );
    refused(
        &with("im=0.2"),
        "--set im=0.2: a stripe (g) scales each motion to its own intensity measure; add --set \
         intensity=pga or intensity=sa",
    );
    let mut stripe = with("intensity=sa");
    stripe.push("im=2000");
    refused(
        &stripe,
        "--set im = 2000: a stripe's intensity (g) must be in [1e-6, 1000]",
    );
    refused(
        &["scene=record", "record=nowhere.csv", "realization=1"],
        "--set realization=1: must be a whole number in [0, 0]: a record is one load",
    );
    refused(
        &["scene=random", "S0=0.01"],
        "--set scene=random: needs --set spectrum=...; allowed: white, kanai-tajimi, \
         clough-penzien",
    );
    refused(
        &["S0=0.01"],
        "--set S0=0.01: a key of the random scene; add --set scene=random",
    );
    refused(
        &["scale=2"],
        "--set scale=2: a key of the record scene; add --set scene=record",
    );
    let out = bin()
        .args([
            "simulate",
            "--set",
            "scene=random",
            "--set",
            "spectrum=white",
        ])
        .args(["--set", "S0=0.01", "--t-end", "2"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--t-end 2: a free-decay option"));
}
