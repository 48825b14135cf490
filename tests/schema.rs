//! The data contract (issue 9): column names unique without case in every table the tool
//! writes, the masses as `mass_main` and `mass_inner`, units in the Parquet field metadata,
//! `docs/schema.md` in step with the code, and a clear message for a dataset of schema version 1.

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use impactsweep::store::schema::{self, SCHEMA_VERSION, TableKind, case_clashes};
use predicates::prelude::*;

fn bin() -> Command {
    Command::cargo_bin("impactsweep").unwrap()
}

/// Runs the two-axis test study (`e` × `m`, `n_e` values of `e`) into `tmp/out`; returns the
/// study file and its run directory.
fn run(tmp: &Path, name: &str, n_e: usize) -> (PathBuf, PathBuf) {
    let study = common::write_study(tmp, name, n_e, 2);
    let out = tmp.join("out");
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .assert()
        .success();
    (study, out.join(name))
}

/// [`run`] with 4 values of `e`, then `reduce`; returns the run directory.
fn run_and_reduce(tmp: &Path, name: &str) -> PathBuf {
    let (_, dir) = run(tmp, name, 4);
    bin().arg("reduce").arg(&dir).assert().success();
    dir
}

fn csv_header(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let first = text.lines().next().unwrap_or("");
    first.split(',').map(String::from).collect()
}

#[test]
fn issue_9_csv_tables_name_the_masses_uniquely_without_case() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = run_and_reduce(tmp.path(), "csv");
    let summary = csv_header(&dir.join("summary.csv"));
    assert_eq!(&summary[..3], ["point", "e", "mass_inner"]);
    let zones = csv_header(&dir.join("zones.csv"));
    for want in ["e_from", "e_to", "mass_inner_from", "mass_inner_to"] {
        assert!(zones.iter().any(|c| c == want), "{want} not in {zones:?}");
    }
    let jumps = csv_header(&dir.join("jumps.csv"));
    assert_eq!(jumps[0], "axis");
    for (name, header) in [("summary", &summary), ("zones", &zones), ("jumps", &jumps)] {
        let clashes = case_clashes(header.iter().map(String::as_str));
        assert!(clashes.is_empty(), "{name}.csv: {clashes:?}");
    }
    // The axis values of a jump are column names too.
    let text = std::fs::read_to_string(dir.join("jumps.csv")).unwrap();
    for line in text.lines().skip(1) {
        let axis = line.split(',').next().unwrap();
        assert!(["e", "mass_inner"].contains(&axis), "{line}");
    }
}

#[test]
fn issue_9_every_parquet_field_carries_its_unit() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = run_and_reduce(tmp.path(), "units");
    let files = [
        (TableKind::Points, impactsweep::store::part_path(&dir, 0)),
        (TableKind::Summary, dir.join("summary.parquet")),
        (TableKind::Zones, dir.join("zones.parquet")),
        (TableKind::Jumps, dir.join("jumps.parquet")),
        (TableKind::Sensitivity, dir.join("sensitivity.parquet")),
    ];
    for (kind, path) in files {
        let builder = impactsweep::store::open(&path).unwrap();
        let meta = impactsweep::store::metadata_of(&builder);
        assert_eq!(meta[schema::META_TABLE], kind.name(), "{}", path.display());
        assert_eq!(
            meta[schema::META_SCHEMA_VERSION],
            SCHEMA_VERSION.to_string()
        );
        for field in builder.schema().fields() {
            let unit = field.metadata().get(schema::FIELD_UNIT);
            assert_eq!(
                unit.map(String::as_str),
                schema::unit(kind, field.name()),
                "{} {}",
                path.display(),
                field.name()
            );
        }
        if kind != TableKind::Sensitivity {
            let unit_of = |c: &str| {
                builder
                    .schema()
                    .field_with_name(c)
                    .ok()
                    .map(|f| f.metadata()[schema::FIELD_UNIT].clone())
            };
            let col = if kind == TableKind::Zones {
                "mass_inner_from"
            } else {
                "mass_inner"
            };
            assert_eq!(unit_of(col).as_deref(), Some("kg"), "{}", path.display());
        }
    }
}

/// Issue 9: `status` and `reduce` tell a user with a dataset of schema version 1 what it is,
/// what this build reads and what to do; `run --resume` refuses to mix versions.
#[test]
fn issue_9_a_schema_version_1_dataset_gets_a_clear_message() {
    let tmp = tempfile::tempdir().unwrap();
    let (study, dir) = run(tmp.path(), "old", 3);
    let out = tmp.path().join("out");
    common::downgrade_to_v1(&dir);
    let says_what_to_do = || {
        predicate::str::contains("data of schema version 1")
            .and(predicate::str::contains("written by impactsweep 0.1.0"))
            .and(predicate::str::contains(format!(
                "this build of impactsweep reads schema version {SCHEMA_VERSION}"
            )))
            .and(predicate::str::contains(
                "impactsweep run STUDY.toml --out NEW_DIR",
            ))
    };
    bin()
        .arg("status")
        .arg(&dir)
        .assert()
        .code(2)
        .stdout("")
        .stderr(says_what_to_do());
    bin()
        .arg("reduce")
        .arg(&dir)
        .assert()
        .code(2)
        .stderr(says_what_to_do());
    assert!(!dir.join("summary.parquet").exists());
    bin()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--resume", "--quiet"])
        .assert()
        .code(2)
        .stderr(says_what_to_do());
    // Without the manifest, the part file's own metadata names it.
    std::fs::remove_file(dir.join("manifest.json")).unwrap();
    bin().arg("reduce").arg(&dir).assert().code(2).stderr(
        predicate::str::contains("part-000000.parquet: data of schema version 1")
            .and(predicate::str::contains("(mass columns `M` and `m`)")),
    );
}

/// One documented column: name (possibly a `<axis>` template), type and unit.
struct DocColumn {
    name: String,
    data_type: String,
    unit: String,
}

/// The column tables of `docs/schema.md`, by table name (`## points` ...).
fn documented() -> Vec<(String, Vec<DocColumn>)> {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/schema.md"))
            .unwrap();
    let mut out: Vec<(String, Vec<DocColumn>)> = Vec::new();
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            out.push((h.trim().to_string(), Vec::new()));
            continue;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // | `name` | type | unit | meaning |
        if cells.len() == 6
            && cells[1].starts_with('`')
            && let Some((_, cols)) = out.last_mut()
        {
            cols.push(DocColumn {
                name: cells[1].trim_matches('`').to_string(),
                data_type: cells[2].to_string(),
                unit: if cells[3] == "-" {
                    String::new()
                } else {
                    cells[3].to_string()
                },
            });
        }
    }
    out
}

/// Whether a documented name covers a written column (`<axis>` stands for any system column).
fn covers(doc: &str, column: &str) -> bool {
    if !doc.contains("<axis>") {
        return doc == column;
    }
    impactsweep::model::SYSTEM_KEYS
        .iter()
        .any(|k| doc.replace("<axis>", schema::column_name(k)) == column)
}

/// A small harmonic study (issue 12) run into `tmp/out/<name>`; returns its run directory. Its
/// design life and verification measure at their shortest window (2,000 periods): the tables'
/// columns do not depend on it, and the default's 1,024,000 periods cost about 50 s of CPU here.
fn run_harmonic(tmp: &Path, name: &str) -> PathBuf {
    let study = tmp.join(format!("{name}.toml"));
    std::fs::write(
        &study,
        format!(
            "[study]\nname = \"{name}\"\n[system]\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\n\
             F0 = 0.3\nlife_max_periods = 2000\n[sweep]\nr = [0.9, 1.0, 1.1]\nm = [0.0, 0.02]\n\
             [noise]\npower = 1e-12\nsample_time = 1e-3\n[perturb]\ncases = [{{ noise_seed = 1 }}]\n\
             [ranking]\nverify_periods = 2000\n"
        ),
    )
    .unwrap();
    common::run_study_file(&study, &tmp.join("out"), name)
}

/// A tiny random study with a swept intensity (issue 44) run and reduced into `tmp/out/<name>`;
/// returns its run directory.
fn run_random(tmp: &Path, name: &str) -> PathBuf {
    let study = tmp.join(format!("{name}.toml"));
    std::fs::write(
        &study,
        format!(
            "[study]\nname = \"{name}\"\n[system]\nK = 246.7\nC = 0.628\n[scene]\n\
             kind = \"random\"\nspectrum = \"kanai-tajimi\"\nomega_g = 15.7\nzeta_g = 0.6\n\
             S0 = 0.004\nduration = 1\nthreshold = 0.005\nrealizations = 8\n\
             intensity = \"sa\"\n[sweep]\nim = [0.05, 0.1, 0.2]\nm = [0.0, 0.05]\n\
             [hazard]\nk0 = 1e-4\nk = 2.5\n"
        ),
    )
    .unwrap();
    let dir = common::run_study_file(&study, &tmp.join("out"), name);
    bin().arg("reduce").arg(&dir).assert().success();
    dir
}

/// `docs/schema.md` lists every column of every table the tool writes, with the type and unit
/// the files carry, and nothing else; the names are unique without case. The harmonic scene's
/// `forced_points` table too (issue 12), and the random scene's `random_points` (issue 44).
#[test]
fn issue_9_docs_schema_md_matches_every_written_table() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = run_and_reduce(tmp.path(), "docs");
    let forced = run_harmonic(tmp.path(), "forced");
    bin().arg("reduce").arg(&forced).assert().success();
    bin()
        .arg("reduce")
        .arg(&forced)
        .args(["--shard", "0/1"])
        .assert()
        .success();
    let tradeoff = tmp.path().join("tradeoff.parquet");
    impactsweep::store::tradeoff::write(&tradeoff, &[]).unwrap();
    // Issue 24: a harmonic study over r and d whose period doublings are followed over d.
    let bif_study = tmp.path().join("bif.toml");
    std::fs::write(
        &bif_study,
        "[study]\nname = \"bif\"\nseed = 1\n[system]\nm = 0.005\nC = 0.1\ne = 0.9\n\
         x0 = 0.0\nv0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\nstarts = 8\n\
         [sweep]\nd = [0.004, 0.005]\nr = {start = 0.87, stop = 0.93, step = 0.01}\n",
    )
    .unwrap();
    let bif = common::run_study_file(&bif_study, &tmp.path().join("out"), "bif");
    bin().arg("reduce").arg(&bif).assert().success();
    let random = run_random(tmp.path(), "random");
    // Issue 68: the attractors of a study of several units carry their whole section state.
    let units_study = tmp.path().join("units.toml");
    std::fs::write(
        &units_study,
        "[study]\nname = \"units\"\n[system]\nv0 = 0.0\nunits = 2\nd_spread = 0.2\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.3\nr = 1.0\nstarts = 2\nn_trans_max = 200\n\
         life_max_periods = 2000\n",
    )
    .unwrap();
    let units = common::run_study_file(&units_study, &tmp.path().join("out"), "units");
    // Issue 67: a record suite's capacities name the record.
    let suite = common::run_study_file(
        Path::new("configs/seismic-records.toml"),
        &tmp.path().join("out"),
        "seismic-records",
    );
    bin().arg("reduce").arg(&suite).assert().success();
    let docs = documented();
    // Each table with the files that hold it: a free-decay, a harmonic and a random reduction
    // write the same reducer tables, with the columns of their scene (issues 12 and 44).
    let both = |name: &str| vec![dir.join(name), forced.join(name), random.join(name)];
    for (kind, paths) in [
        (
            TableKind::Points,
            vec![impactsweep::store::part_path(&dir, 0)],
        ),
        (
            TableKind::HarmonicPoints,
            vec![impactsweep::store::part_path(&forced, 0)],
        ),
        (
            TableKind::RandomPoints,
            vec![impactsweep::store::part_path(&random, 0)],
        ),
        (TableKind::Summary, both("summary.parquet")),
        (
            TableKind::Capacities,
            vec![
                random.join("capacities.parquet"),
                suite.join("capacities.parquet"),
            ],
        ),
        (TableKind::Zones, both("zones.parquet")),
        (TableKind::Jumps, both("jumps.parquet")),
        (TableKind::Sensitivity, both("sensitivity.parquet")),
        (TableKind::Tradeoff, vec![tradeoff.clone()]),
        // Issue 23: the sweep's attractors parts, the branches, an analysis shard's probes.
        (
            TableKind::Attractors,
            vec![
                forced.join("attractors/part-000000.parquet"),
                units.join("attractors/part-000000.parquet"),
            ],
        ),
        (TableKind::Branches, vec![forced.join("branches.parquet")]),
        (
            TableKind::Probes,
            vec![forced.join("analysis/probes-0-of-1.parquet")],
        ),
        (
            TableKind::Bifurcations,
            vec![bif.join("bifurcations.parquet")],
        ),
    ] {
        let doc = &docs
            .iter()
            .find(|(h, _)| h == kind.name())
            .unwrap_or_else(|| panic!("docs/schema.md has no section `## {}`", kind.name()))
            .1;
        let mut written: Vec<String> = Vec::new();
        for path in &paths {
            let meta = impactsweep::store::metadata_of(&impactsweep::store::open(path).unwrap());
            assert_eq!(meta[schema::META_TABLE], kind.name(), "{}", path.display());
            let schema = impactsweep::store::open(path).unwrap().schema().clone();
            let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
            assert!(case_clashes(names.iter().copied()).is_empty(), "{names:?}");
            for field in schema.fields() {
                let d = doc
                    .iter()
                    .find(|d| covers(&d.name, field.name()))
                    .unwrap_or_else(|| {
                        panic!(
                            "{}: column `{}` is not in docs/schema.md",
                            kind.name(),
                            field.name()
                        )
                    });
                let mut ty = field.data_type().to_string();
                if field.is_nullable() {
                    ty.push_str(", nullable");
                }
                assert_eq!(d.data_type, ty, "{} `{}`: type", kind.name(), field.name());
                let unit = &field.metadata()[schema::FIELD_UNIT];
                if d.name.contains("<axis>") {
                    assert_eq!(d.unit, "unit of the axis");
                } else {
                    assert_eq!(&d.unit, unit, "{} `{}`: unit", kind.name(), field.name());
                }
                written.push(field.name().clone());
            }
        }
        for d in doc {
            assert!(
                written.iter().any(|n| covers(&d.name, n)),
                "{}: docs/schema.md lists `{}`, which the tool does not write",
                kind.name(),
                d.name
            );
        }
    }
}
