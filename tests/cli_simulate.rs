//! `impactsweep simulate` through the real binary: JSON keys, the human summary, the trace,
//! and bad input (exit status 2, the message names the key, the value and the range).

use assert_cmd::Command;

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

#[test]
fn json_has_every_documented_key() {
    let out = bin().args(["simulate", "--json"]).output().unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "x1",
        "t1",
        "x2",
        "t2",
        "xmax",
        "di",
        "impacts",
        "sticks",
        "outcome",
        "t_stop",
        "energy_impact",
        "energy_viscous",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["outcome"], "ok");
    assert_eq!(v["system"]["e"], 0.9);
    let x1 = v["x1"].as_f64().unwrap();
    assert!((0.027..0.030).contains(&x1), "x1 = {x1}");
}

#[test]
fn human_summary_has_units() {
    let out = bin()
        .args(["simulate", "--set", "e=0.45"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("outcome  ok"), "{text}");
    assert!(text.contains(" cm at t1 = "), "{text}");
    assert!(text.contains(" m/s"), "{text}");
    assert!(text.contains("sticking phases"), "{text}");
}

#[test]
fn trace_has_samples_and_every_impact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wave.csv");
    let out = bin()
        .args(["simulate", "--json", "--trace"])
        .arg(&path)
        .args(["--dt", "1e-3", "--t-end", "0.2"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let impacts = v["impacts"].as_u64().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,x,y"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    // 201 samples (t = 0, 1 ms, ..., 200 ms) plus one row per impact.
    assert_eq!(rows.len() as u64, 201 + impacts, "impacts {impacts}");
    assert!(
        rows.windows(2).all(|w| w[0][0] <= w[1][0]),
        "rows in time order"
    );
    assert!(
        rows.iter()
            .all(|r| (r[2] - r[1]).abs() <= 0.005 * (1.0 + 1e-12))
    );
}

fn refused(args: &[&str], message: &str) {
    let out = bin().args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.trim_end(), format!("error: {message}"), "{args:?}");
}

#[test]
fn bad_keys_and_values_exit_2_with_the_range() {
    refused(
        &["simulate", "--set", "e=1.3"],
        "--set e = 1.3: the coefficient of restitution must be in [0, 1]",
    );
    refused(
        &["simulate", "--set", "M=0"],
        "--set M = 0: the main mass must be a finite number > 0 (kg)",
    );
    refused(
        &["simulate", "--set", "d=abc"],
        "--set d=abc: 'abc' is not a number",
    );
    refused(
        &["simulate", "--set", "y0=0.01"],
        "--set y0 = 0.01: the inner mass must start inside the cavity: |y0 - x0| = 0.01 exceeds d/2 = 0.005",
    );
    refused(
        &["simulate", "--set", "tol=0"],
        "--set tol = 0: must be in [1e-15, 0.001]",
    );
    let out = bin().args(["simulate", "--set", "q=1"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.starts_with("error: --set q=1: unknown key 'q'; allowed keys: M m K C d e"),
        "{err}"
    );
}
