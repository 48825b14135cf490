//! Real clients read a freshly written dataset (issue 3, item 6): pyarrow, DuckDB and polars
//! each check the row count, the column names and types, the key-value metadata, and a few
//! values against the simulator's own output (computed here by calling `sim::simulate`
//! directly, passed to `tests/interop.py` as JSON, floats as their IEEE-754 bits).
//!
//! Issue 9's acceptance: DuckDB reads every Parquet table the tool writes (points, summary,
//! zones, jumps, tradeoff) with no two column names equal without case, and a query naming
//! `mass_inner` returns exactly the study's inner masses.
//!
//! The Python interpreter is `$IMPACTSWEEP_PYTHON`, else the repository's `.venv/bin/python`
//! (`scripts/setup-python.sh` creates it with the pinned packages).

use crate::common;

use common::python;

use std::path::Path;

use impactsweep::plan::Plan;
use impactsweep::sim::{NoProbe, simulate};
use impactsweep::store;
use impactsweep::sweep::{self, SweepOptions};
use serde_json::json;

#[test]
fn pyarrow_duckdb_and_polars_read_the_dataset() {
    let study = common::study("interop", 9);
    let tmp = tempfile::tempdir().unwrap();
    let summary = sweep::run_study(
        &study,
        tmp.path(),
        &SweepOptions {
            chunk_points: Some(5),
            ..SweepOptions::default()
        },
    )
    .unwrap();
    let dir = tmp.path().join("interop");
    assert_eq!(summary.chunks_written, 6);

    // Expected values straight from the simulator, not from the store.
    let plan = Plan::new(&study);
    let mut rows = Vec::new();
    for (p, c) in [(0u64, 0u32), (4, 2), (13, 1), (26, 3)] {
        let run = plan.run(p, c);
        let mut stream = plan.noise_stream(&run);
        let noise = match (&study.noise, stream.as_mut()) {
            (Some(ns), Some(s)) => Some((ns, s)),
            _ => None,
        };
        let rec = simulate(
            &run.system,
            &study.solver,
            &study.request,
            noise,
            &mut NoProbe,
        );
        rows.push(json!({
            "point_id": run.point_id,
            "point": p,
            "case": c,
            "ideal": run.spec.ideal,
            "noise_seed": run.spec.noise_seed,
            "outcome": rec.outcome.name(),
            "solver": "exact",
            "impacts": rec.impacts,
            "bits": {
                "e": run.system.e.to_bits(),
                "mass_inner": run.system.m.to_bits(),
                "d": run.system.d.to_bits(),
                "dd": run.spec.dd.to_bits(),
                "x1": rec.x1.to_bits(),
                "t1": rec.t1.to_bits(),
                "xmax": rec.xmax.to_bits(),
                "di": rec.di.to_bits(),
                "energy_impact": rec.energy_impact.to_bits(),
            },
        }));
    }
    let columns: Vec<String> = store::points::schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    let expected = json!({
        "dir": dir,
        "n_rows": plan.n_runs(),
        "n_files": 6,
        "columns": columns,
        "study": study.source,
        "schema_version": store::SCHEMA_VERSION.to_string(),
        "rows": rows,
    });
    let spec = tmp.path().join("expected.json");
    std::fs::write(&spec, serde_json::to_string_pretty(&expected).unwrap()).unwrap();

    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop.py");
    let out = std::process::Command::new(python())
        .arg(&script)
        .arg(&spec)
        .output()
        .expect("running tests/interop.py");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "interop.py failed\nstdout:\n{stdout}\nstderr:\n{stderr}"
    );
    for client in ["pyarrow", "duckdb", "polars"] {
        assert!(
            stdout.contains(&format!("{client}: ok")),
            "{client} did not report\n{stdout}"
        );
    }
}

fn run_python(args: &[&std::ffi::OsStr]) -> String {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop.py");
    let out = std::process::Command::new(python())
        .arg(&script)
        .args(args)
        .output()
        .expect("running tests/interop.py");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "interop.py failed\nstdout:\n{stdout}\nstderr:\n{stderr}"
    );
    stdout
}

/// Issue 9: every Parquet table through DuckDB, on a study that sweeps `e` and `m` (with a case
/// that changes `m`).
#[test]
fn issue_9_duckdb_reads_every_table_and_mass_inner_is_the_inner_mass() {
    let tmp = tempfile::tempdir().unwrap();
    let path = common::write_study(tmp.path(), "tables", 5, 4);
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.push_str("\n[reliability]\nstrength_mean = 285e6\nstrength_sd = 20e6\n");
    std::fs::write(&path, &text).unwrap();
    let out = tmp.path().join("out");
    let bin = || assert_cmd::Command::cargo_bin("impactsweep").unwrap();
    bin()
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .assert()
        .success();
    let dir = out.join("tables");
    bin().arg("reduce").arg(&dir).assert().success();
    let trade = tmp.path().join("trade");
    bin()
        .args(["tradeoff", "--quick"])
        .arg(&path)
        .arg("--out")
        .arg(&trade)
        .assert()
        .success();

    let study = impactsweep::study::Study::load(&path).unwrap();
    let plan = Plan::new(&study);
    let axis = &study.axis("m").expect("the study sweeps m").values;
    let mut runs: Vec<f64> = Vec::new();
    for p in 0..plan.n_points() {
        for c in 0..plan.n_cases() as u32 {
            let m = plan.run(p, c).system.m;
            if !runs.iter().any(|x| x.to_bits() == m.to_bits()) {
                runs.push(m);
            }
        }
    }
    assert!(runs.len() > axis.len(), "a case must change m: {runs:?}");
    let expected = json!({
        "tables": {
            "points": dir.join("points/*.parquet"),
            "summary": dir.join("summary.parquet"),
            "zones": dir.join("zones.parquet"),
            "jumps": dir.join("jumps.parquet"),
            "tradeoff": trade.join("tradeoff.parquet"),
        },
        "mass_inner_axis": axis.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        "mass_inner_runs": runs.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
    });
    let spec = tmp.path().join("tables.json");
    std::fs::write(&spec, serde_json::to_string_pretty(&expected).unwrap()).unwrap();
    let stdout = run_python(&["--tables".as_ref(), spec.as_os_str()]);
    for table in ["points", "summary", "zones", "jumps", "tradeoff"] {
        assert!(
            stdout.contains(&format!("{table}: ")),
            "{table} not read\n{stdout}"
        );
    }
    assert!(stdout.contains("duckdb tables: ok"), "{stdout}");
}
