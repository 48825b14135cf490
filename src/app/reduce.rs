//! `reduce` and `plot waveform`: the reducer's commands.
//!
//! `reduce RUN_DIR` streams the part files of a run directory through
//! [`crate::reduce::Reducer`] one at a time (each holds whole design points, so memory stays
//! O(design points)), then writes into the run directory: `summary`, `zones` and `jumps` as
//! Parquet and CSV (columns in `docs/schema.md`), `report.md` and the charts (SVG and PNG).
//! A dataset of another schema version is refused with what to do.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::app::simulate::{Setup, trace};
use crate::reduce::{self, Options, Summary, table};
use crate::report::{charts, markdown};
use crate::store::{self, TableKind};
use crate::study::{DiSource, SafetyForm, Study};

/// `impactsweep reduce RUN_DIR`.
#[derive(Clone, Debug, Default)]
pub struct ReduceArgs {
    pub dir: PathBuf,
    /// Use the paper's small-C_n safety factor instead of Shigley's exact relation.
    pub paper_safety: bool,
    /// DI as the mean over cases instead of the ideal case.
    pub di_mean: bool,
}

/// `impactsweep plot waveform`.
#[derive(Clone, Debug, Default)]
pub struct WaveformArgs {
    pub sets: Vec<String>,
    pub out: PathBuf,
    pub e: Vec<f64>,
    pub t_end: f64,
}

/// The study's choices with the command-line overrides.
pub fn options(study: &Study, args: &ReduceArgs) -> Options {
    let mut o = Options::from_study(study);
    if args.paper_safety {
        o.safety_form = SafetyForm::Paper;
    }
    if args.di_mean {
        o.di_source = DiSource::Mean;
    }
    o
}

pub fn reduce(args: &ReduceArgs) -> anyhow::Result<()> {
    let dir = &args.dir;
    store::manifest::check_dir_version(dir)?;
    let study = Study::load(&dir.join("study.toml"))?;
    // Every part verified against its checksum first: a damaged dataset is refused, not reduced.
    let st = crate::sweep::status(dir)?;
    if let Some(e) = st.damage_error(dir) {
        return Err(e.context("refusing to reduce a damaged dataset"));
    }
    if !st.unrecorded.is_empty() {
        eprintln!(
            "warning: {}: chunks {} are not recorded yet (their run stopped before recording \
             them; they read as good parts of this study, but have no checksum to verify): run \
             `{}` to record them",
            dir.display(),
            crate::sweep::ranges(&st.unrecorded),
            crate::sweep::status::resume_command(dir)
        );
    }
    let parts: Vec<PathBuf> = st.done.iter().map(|&k| store::part_path(dir, k)).collect();
    if parts.is_empty() {
        anyhow::bail!(
            "{}: no part files in points/: nothing to reduce (has the sweep run?)",
            dir.display()
        );
    }
    let opts = options(&study, args);
    let chunks = parts
        .iter()
        .map(|p| store::read_part(p).with_context(|| format!("reading {}", p.display())));
    let summary = reduce::reduce(&study, opts, chunks)?;
    let audit = read_audit(dir)?;
    let files = write_outputs(&study, &summary, dir, audit.as_ref())?;
    println!(
        "reduced {} design points ({} zones, {} jumps, {} Pareto-optimal)",
        summary.points.len(),
        summary.zones.len(),
        summary.jumps.len(),
        summary.points.iter().filter(|p| p.pareto).count()
    );
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// The `audit` value of `RUN_DIR/manifest.json`, when the file and the key exist and the value
/// is not null.
pub fn read_audit(dir: &Path) -> anyhow::Result<Option<serde_json::Value>> {
    let path = dir.join("manifest.json");
    if !path.exists() {
        return Ok(None);
    }
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let v: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
    Ok(v.get("audit").filter(|a| !a.is_null()).cloned())
}

/// Writes every output of a reduction into `dir`; returns the files written.
pub fn write_outputs(
    study: &Study,
    summary: &Summary,
    dir: &Path,
    audit: Option<&serde_json::Value>,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut files = Vec::new();
    for (kind, t) in [
        (TableKind::Summary, table::summary_table(summary)),
        (TableKind::Zones, table::zones_table(summary)),
        (TableKind::Jumps, table::jumps_table(summary)),
    ] {
        files.extend(store::summary::write_table(dir, kind, &t)?);
    }
    let chart_files = charts::summary_charts(summary, dir)?;
    let names: Vec<String> = chart_files
        .iter()
        .filter_map(|f| f.file_name().and_then(|n| n.to_str()).map(String::from))
        .collect();
    files.extend(chart_files);
    let p = dir.join("report.md");
    std::fs::write(&p, markdown::report(study, summary, &names, audit))
        .with_context(|| format!("writing {}", p.display()))?;
    files.push(p);
    Ok(files)
}

pub fn waveform(args: &WaveformArgs) -> anyhow::Result<()> {
    for f in waveform_files(args)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// Draws `waveform_damper.{svg,png}` (with and without the damper) and `waveform_e.{svg,png}`
/// (two values of `e`, first peak magnified) into `args.out`.
pub fn waveform_files(args: &WaveformArgs) -> anyhow::Result<Vec<PathBuf>> {
    let mut setup = Setup::default();
    setup.apply(&args.sets)?;
    if !(args.t_end.is_finite() && args.t_end > 0.0) {
        return Err(crate::error::InputError::new(format!(
            "--t-end {}: must be a finite time > 0 (s)",
            args.t_end
        ))
        .into());
    }
    if args.e.len() != 2 {
        return Err(crate::error::InputError::new(format!(
            "--e: expected two values of e, got {}",
            args.e.len()
        ))
        .into());
    }
    for &e in &args.e {
        let mut s = setup.clone();
        s.apply(&[format!("e={e}")])?;
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let dt = args.t_end / 4000.0;
    let xs = |rows: Vec<(f64, crate::sim::State)>| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = rows.into_iter().map(|(t, s)| (t, s.x)).collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let fmt = crate::report::charts::fmt_num;
    let mut files = Vec::new();

    // With and without the damper (the paper's Figure 2).
    let (rec_with, with) = trace(&setup, dt, Some(args.t_end));
    let mut bare = setup.clone();
    bare.apply(&["m=0".to_string()])?;
    let (rec_bare, without) = trace(&bare, dt, Some(args.t_end));
    let traces = vec![
        charts::Trace {
            name: format!(
                "with impact damper (m = {} kg, e = {}): X1 = {:.3} cm",
                fmt(setup.system.m),
                fmt(setup.system.e),
                rec_with.x1 * 100.0
            ),
            points: xs(with),
        },
        charts::Trace {
            name: format!("without damper (m = 0): X1 = {:.3} cm", rec_bare.x1 * 100.0),
            points: xs(without),
        },
    ];
    files.extend(charts::waveforms(
        &args.out,
        "waveform_damper",
        "Main-mass displacement with and without the impact damper",
        &traces,
        None,
    )?);

    // Two values of e, first peak magnified (the paper's Figure 5).
    let mut traces = Vec::new();
    let mut t1s = Vec::new();
    for &e in &args.e {
        let mut s = setup.clone();
        s.apply(&[format!("e={e}")])?;
        let (rec, rows) = trace(&s, dt / 4.0, Some(args.t_end));
        t1s.push(rec.t1);
        traces.push(charts::Trace {
            name: format!(
                "e = {}: X1 = {:.3} cm at {:.4} s",
                fmt(e),
                rec.x1 * 100.0,
                rec.t1
            ),
            points: xs(rows),
        });
    }
    let period = 2.0 * std::f64::consts::PI * (setup.system.M / setup.system.K).sqrt();
    let t1s: Vec<f64> = t1s.into_iter().filter(|t| t.is_finite()).collect();
    let zoom = if t1s.is_empty() {
        None
    } else {
        let lo = t1s.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = t1s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some(((lo - 0.08 * period).max(0.0), hi + 0.08 * period))
    };
    files.extend(charts::waveforms(
        &args.out,
        "waveform_e",
        &format!(
            "Main-mass displacement for e = {} and e = {}",
            fmt(args.e[0]),
            fmt(args.e[1])
        ),
        &traces,
        zoom,
    )?);
    Ok(files)
}
