//! Shared test helpers: studies built in Rust for the engine's tests (independent of the
//! study-file parser), study files for the binary's tests, and a schema-version-1 dataset.
#![allow(dead_code)]

pub mod life;

use std::path::{Path, PathBuf};

use impactsweep::model::System;
use impactsweep::sim::{NoiseSettings, Request, SolverSettings};
use impactsweep::study::{
    Axis, Case, DiSource, Ranking, Reliability, RunSettings, SafetyForm, Study, VERIFY_PERIODS,
    Zones,
};

/// The Table I system, `e` over `n_e` values in [0.45, 0.95], `m` over 3 values, four cases per
/// point (ideal, a clearance change, two noisy ones), noise on.
pub fn study(name: &str, n_e: usize) -> Study {
    let e: Vec<f64> = (0..n_e)
        .map(|i| 0.45 + 0.5 * i as f64 / (n_e - 1) as f64)
        .collect();
    Study {
        path: PathBuf::from(format!("{name}.toml")),
        source: format!("# built in tests/determinism.rs\n[study]\nname = \"{name}\"\n"),
        name: name.to_string(),
        seed: 2013,
        request: Request::default(),
        scene: impactsweep::sim::Scene::Free,
        system: System::TABLE_I,
        axes: vec![
            Axis {
                key: "e".into(),
                values: e,
            },
            Axis {
                key: "m".into(),
                values: vec![0.015, 0.02, 0.025],
            },
        ],
        realizations: 0,
        design_intensity: None,
        hazard: None,
        cases: vec![
            Case {
                dm: 0.0,
                dd: 0.0,
                noise_seed: None,
                ideal: true,
            },
            Case {
                dm: 0.0,
                dd: 0.001,
                noise_seed: None,
                ideal: false,
            },
            Case {
                dm: 0.0,
                dd: 0.0,
                noise_seed: Some(23341),
                ideal: false,
            },
            Case {
                dm: 0.001,
                dd: -0.001,
                noise_seed: Some(22413),
                ideal: false,
            },
        ],
        noise: Some(NoiseSettings {
            power: 5e-9,
            sample_time: 1e-3,
        }),
        solver: SolverSettings::default(),
        reliability: Reliability {
            E: 200e9,
            r: 3.4e-3,
            L: 0.5,
            strength_mean: 300e6,
            strength_sd: 30e6,
            safety_form: SafetyForm::Exact,
            bootstrap: 200,
            confidence: 0.95,
        },
        zones: Zones::default(),
        ranking: Ranking {
            wf1: 0.5,
            wf2: 0.5,
            di_source: DiSource::Ideal,
            verify_periods: VERIFY_PERIODS,
        },
        run: RunSettings {
            chunk_points: 16,
            chunk_realizations: impactsweep::study::DEFAULT_CHUNK_RUNS,
            audit: 0,
        },
    }
}

/// A small study: `n_e` values of `e` × 3 values of `m`, 4 cases (ideal, a clearance change, two
/// noisy cases).
pub fn study_text(name: &str, n_e: usize, chunk_points: u64) -> String {
    format!(
        r#"[study]
name = "{name}"
seed = 11

[sweep]
e = {{ start = 0.45, stop = 0.95, num = {n_e} }}
m = [0.015, 0.02, 0.025]

[noise]
power = 5e-10
sample_time = 1e-3

[perturb]
cases = [
  {{ dd = 0.001 }},
  {{ noise_seed = 1 }},
  {{ dm = -0.001, dd = -0.001, noise_seed = 2 }},
]

[run]
chunk_points = {chunk_points}
"#
    )
}

pub fn write_study(dir: &Path, name: &str, n_e: usize, chunk_points: u64) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, study_text(name, n_e, chunk_points)).unwrap();
    path
}

/// Turns a run directory written by this build into what impactsweep 0.1.0 (schema version 1)
/// wrote: the mass columns back to `M` and `m`, `impactsweep.schema_version = 1` in every part
/// file and in `manifest.json` (issue 9: such a dataset must get a clear message).
pub fn downgrade_to_v1(run_dir: &Path) {
    use std::sync::Arc;

    use arrow_array::RecordBatch;
    use arrow_schema::{Field, Schema};
    use parquet::arrow::ArrowWriter;
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    use parquet::file::metadata::KeyValue;
    use parquet::file::properties::WriterProperties;

    for path in impactsweep::store::part_files(run_dir).unwrap() {
        let builder =
            ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&path).unwrap()).unwrap();
        let kv: Vec<KeyValue> = builder
            .metadata()
            .file_metadata()
            .key_value_metadata()
            .unwrap()
            .iter()
            .filter(|kv| kv.key.starts_with("impactsweep."))
            .map(|kv| match kv.key.as_str() {
                "impactsweep.schema_version" => KeyValue::new(kv.key.clone(), "1".to_string()),
                _ => kv.clone(),
            })
            .collect();
        let batches: Vec<RecordBatch> = builder.build().unwrap().map(Result::unwrap).collect();
        let old = batches[0].schema();
        let fields: Vec<Field> = old
            .fields()
            .iter()
            .map(|f| {
                let name = match f.name().as_str() {
                    "mass_main" => "M",
                    "mass_inner" => "m",
                    other => other,
                };
                Field::new(name, f.data_type().clone(), f.is_nullable())
            })
            .collect();
        let schema = Arc::new(Schema::new(fields));
        let props = WriterProperties::builder()
            .set_key_value_metadata(Some(kv))
            .build();
        let mut bytes = Vec::new();
        let mut w = ArrowWriter::try_new(&mut bytes, schema.clone(), Some(props)).unwrap();
        for b in &batches {
            w.write(&RecordBatch::try_new(schema.clone(), b.columns().to_vec()).unwrap())
                .unwrap();
        }
        w.close().unwrap();
        std::fs::write(&path, bytes).unwrap();
    }
    let manifest = run_dir.join("manifest.json");
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&manifest).unwrap()).unwrap();
    m["schema_version"] = 1.into();
    m["version"] = "0.1.0".into();
    std::fs::write(&manifest, serde_json::to_string_pretty(&m).unwrap()).unwrap();
}

/// The cells of one CSV line (RFC 4180: quoted cells may hold commas and doubled quotes).
pub fn csv_cells(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cell = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cell.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cell)),
            _ => cell.push(c),
        }
    }
    out.push(cell);
    out
}

/// A CSV file as its header and, by the first cell (the point index), its rows as maps from
/// column to cell.
pub fn csv_by_point(
    path: &std::path::Path,
) -> (
    Vec<String>,
    std::collections::BTreeMap<u64, std::collections::HashMap<String, String>>,
) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = csv_cells(lines.next().unwrap());
    let rows = lines
        .map(|l| {
            let cells = csv_cells(l);
            assert_eq!(cells.len(), header.len(), "{}: {l}", path.display());
            let row: std::collections::HashMap<String, String> =
                header.iter().cloned().zip(cells).collect();
            (row["point"].parse().unwrap(), row)
        })
        .collect();
    (header, rows)
}

/// Checks that a chart's data CSV holds summary rows: every row's cells equal the summary
/// row of its point in every column the chart has, which are `point`, the axis columns and at
/// least one more. Returns the points, in order.
pub fn chart_rows_are_summary_rows(chart: &std::path::Path, summary: &std::path::Path) -> Vec<u64> {
    let (header, rows) = csv_by_point(chart);
    let (sum_header, sum_rows) = csv_by_point(summary);
    assert!(
        header.len() >= 3 && header[0] == "point",
        "{}: {header:?}",
        chart.display()
    );
    for c in &header {
        assert!(
            sum_header.contains(c),
            "{}: `{c}` is not a summary column",
            chart.display()
        );
    }
    for (p, row) in &rows {
        for c in &header {
            assert_eq!(
                row[c],
                sum_rows[p][c],
                "{}: point {p}, {c}",
                chart.display()
            );
        }
    }
    rows.keys().copied().collect()
}

/// `impactsweep run STUDY --out OUT --quiet`, which must succeed; returns the run directory
/// `OUT/<name>`.
pub fn run_study_file(study: &Path, out: &Path, name: &str) -> PathBuf {
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("run")
        .arg(study)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .assert()
        .success();
    out.join(name)
}

/// A run directory's dataset as bytes: every part file by name (the points', then a harmonic
/// study's attractors parts), then `manifest.json`. Two runs of one study are the same dataset,
/// bit for bit, when these are equal.
pub fn dataset(run_dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = impactsweep::store::part_files(run_dir)
        .unwrap()
        .iter()
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().to_string(),
                std::fs::read(p).unwrap(),
            )
        })
        .collect();
    let side = run_dir.join("attractors");
    if let Ok(entries) = std::fs::read_dir(&side) {
        let mut names: Vec<_> = entries
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .filter(|n| n.ends_with(".parquet"))
            .collect();
        names.sort();
        for n in names {
            let bytes = std::fs::read(side.join(&n)).unwrap();
            files.push((format!("attractors/{n}"), bytes));
        }
    }
    files.push((
        "manifest.json".into(),
        std::fs::read(run_dir.join("manifest.json")).unwrap_or_default(),
    ));
    files
}

/// This host's name, as lock files write it.
pub fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .unwrap()
        .trim()
        .to_string()
}

/// A PID that no longer exists: a child that has exited and been reaped.
pub fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    assert!(!Path::new(&format!("/proc/{pid}")).exists());
    pid
}

/// The Python interpreter of the tests that call Python (interop readers, the SciPy peers):
/// `$IMPACTSWEEP_PYTHON`, else the repository's `.venv/bin/python` (`scripts/setup-python.sh`
/// creates it with the pinned packages).
pub fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("IMPACTSWEEP_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join(".venv/bin/python");
    assert!(
        venv.exists(),
        "no Python for this test: set IMPACTSWEEP_PYTHON or run scripts/setup-python.sh \
         (looked for {})",
        venv.display()
    );
    venv
}

/// Table I's `M`, `K` with the inner mass, clearance, restitution and damping given, at rest,
/// under `f0 cos(omega t)` at `omega = r sqrt(K/M)`: the steady-state tests' system.
pub fn table_i(
    m: f64,
    d: f64,
    e: f64,
    c: f64,
    f0: f64,
    r: f64,
) -> impactsweep::orbits::map::Forcing {
    let sys = System {
        m,
        d,
        e,
        C: c,
        x0: 0.0,
        v0: 0.0,
        ..System::TABLE_I
    };
    impactsweep::orbits::map::Forcing {
        omega: r * sys.omega(),
        sys,
        F0: f0,
        settings: SolverSettings::default(),
    }
}

/// Issue 23's study: seven inner masses, four frequencies around resonance, two cases, a short
/// census (4 starts, 400-period budget), a brief design life and no verification: cheap, with
/// coexisting and rattling steady states.
pub fn census_study_text(name: &str) -> String {
    format!(
        r#"[study]
name = "{name}"
seed = 23

[system]
v0 = 0.0

[scene]
kind = "harmonic"
F0 = 0.3
n_trans_max = 400
life_max_periods = 2000
starts = 4

[sweep]
m = {{ start = 0.0, stop = 0.03, num = 7 }}
r = {{ start = 0.9, stop = 1.05, num = 4 }}

[perturb]
dd = [0.001]

[ranking]
verify_periods = 0
"#
    )
}

/// `cp -r`: a directory copied with its subdirectories (a run directory reduced twice, pages
/// checked from another place).
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}
