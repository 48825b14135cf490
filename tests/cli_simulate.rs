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

// ---- The harmonic scene (issue 12). ---------------------------------------------------------

fn forced_json(args: &[&str]) -> serde_json::Value {
    let out = bin().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn harmonic_scene_prints_the_forced_keys() {
    let v = forced_json(&[
        "simulate",
        "--set",
        "scene=harmonic",
        "--set",
        "F0=0.3",
        "--set",
        "omega=61.98064213930023",
        "--set",
        "n_meas=20",
        "--json",
    ]);
    for key in [
        "outcome",
        "amplitude",
        "impacts_per_period",
        "period",
        "amplitude_linear",
        "attenuation",
        "n_trans",
        "converged",
        "impacts",
        "sticks",
        "steps",
        "t_stop",
        "energy_force",
        "energy_impact",
        "energy_viscous",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["outcome"], "ok");
    assert_eq!(v["scene"], "harmonic");
    // omega = 0.98 sqrt(K/M): the period-1 orbit with two impacts per period.
    assert!((v["r"].as_f64().unwrap() - 0.98).abs() < 1e-12);
    assert_eq!(v["period"], 1);
    assert_eq!(v["impacts_per_period"], 2.0);
    assert!(v["converged"].as_bool().unwrap());
    let att = v["attenuation"].as_f64().unwrap();
    let ratio = v["amplitude"].as_f64().unwrap() / v["amplitude_linear"].as_f64().unwrap();
    assert_eq!(att, ratio);
    // The same run by ratio, with the transient fixed.
    let w = forced_json(&[
        "simulate",
        "--set",
        "scene=harmonic",
        "--set",
        "F0=0.3",
        "--set",
        "r=0.98",
        "--set",
        "n_trans=300",
        "--json",
    ]);
    assert_eq!(w["n_trans"], 300);
    assert_eq!(w["converged"], false);
    // The free-decay keys are not printed for the forced scene, and vice versa.
    assert!(w.get("x1").is_none() && w.get("di").is_none());
}

#[test]
fn harmonic_scene_summary_and_trace() {
    let out = bin()
        .args(["simulate", "--set", "scene=harmonic", "--set", "r=0.5"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("outcome  ok"), "{text}");
    assert!(text.contains("amplitude "), "{text}");
    assert!(text.contains(" per period, period "), "{text}");

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("forced.csv");
    let out = bin()
        .args([
            "simulate",
            "--set",
            "scene=harmonic",
            "--set",
            "F0=0.3",
            "--set",
            "r=0.98",
            "--set",
            "n_trans=5",
            "--set",
            "n_meas=3",
            "--json",
            "--dt",
            "1e-3",
            "--trace",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let impacts = v["impacts"].as_u64().unwrap();
    let t_stop = v["t_stop"].as_f64().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,x,y"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    // A sample every ms over the 8 forcing periods, plus one row per impact.
    let samples = (t_stop / 1e-3).floor() as u64 + 1;
    assert_eq!(rows.len() as u64, samples + impacts, "impacts {impacts}");
    assert!(rows.windows(2).all(|w| w[0][0] <= w[1][0]));
    assert!(
        rows.iter()
            .all(|r| (r[2] - r[1]).abs() <= 0.005 * (1.0 + 1e-9))
    );
}

#[test]
fn harmonic_scene_bad_input_exits_2_with_the_range() {
    refused(
        &[
            "simulate",
            "--set",
            "scene=harmonic",
            "--set",
            "omega=60",
            "--set",
            "r=1",
        ],
        "--set omega=60 and --set r=1: give the forcing frequency once, as omega (rad/s) or as r = omega / sqrt(K/M)",
    );
    refused(
        &["simulate", "--set", "scene=harmonic", "--set", "F0=-1"],
        "--set F0 = -1: the force amplitude must be a finite number > 0 (N)",
    );
    refused(
        &["simulate", "--set", "scene=harmonic", "--set", "omega=0"],
        "--set omega = 0: the forcing frequency must be a finite number > 0 (rad/s)",
    );
    refused(
        &["simulate", "--set", "scene=harmonic", "--set", "n_meas=0"],
        "--set n_meas = 0: must be in [1, 1000000]",
    );
    refused(
        &[
            "simulate",
            "--set",
            "scene=harmonic",
            "--set",
            "n_trans=1.5",
        ],
        "--set n_trans=1.5: must be a whole number >= 0",
    );
    refused(
        &["simulate", "--set", "F0=1"],
        "--set F0=1: a key of the harmonic scene; add --set scene=harmonic",
    );
    refused(
        &["simulate", "--set", "scene=steady"],
        "--set scene=steady: unknown scene; allowed: free, harmonic, random, record",
    );
    refused(
        &["simulate", "--set", "scene=harmonic", "--set", "peaks=3"],
        "--set peaks=3: a free-decay key; the harmonic scene runs n_trans + n_meas forcing periods",
    );
    refused(
        &["simulate", "--set", "scene=harmonic", "--t-end", "0.5"],
        "--t-end 0.5: a free-decay option; the harmonic scene runs n_trans + n_meas forcing periods",
    );
    refused(
        &["simulate", "--set", "scene=harmonic", "--set", "solver=rk4"],
        "--set solver=rk4: the harmonic scene is solved in closed form only; allowed: exact",
    );
    let out = bin()
        .args([
            "simulate",
            "--set",
            "scene=harmonic",
            "--set",
            "C=0",
            "--set",
            "r=1",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.starts_with(
            "error: --set r = 1: resonance without damping: |K - M omega^2 + i C omega| = "
        ),
        "{err}"
    );
}
