//! The reduction of a run directory (`impactsweep reduce`, the Python binding's `reduce`) and
//! the waveform plots (`plot waveform`).
//!
//! [`reduce_dir`] checks the run directory (its schema version, every part against its
//! checksum), then hands its part files to the study's scene, chosen here and nowhere else:
//! [`free::reduce`], [`harmonic::reduce`] or [`random::reduce_random`]. Each streams the part
//! files through its reducer one at a time (each holds whole design points, so memory stays a
//! chunk plus a fixed size per design point) and writes into the run directory: `summary`,
//! `zones`, `jumps` and `sensitivity` as Parquet and CSV (columns in `docs/schema.md`),
//! `report.md` and the charts (SVG and PNG, each with its data as CSV), and `report.html`, the
//! report as one self-contained page with the charts inlined (docs/reduce.md;
//! [`write_outputs`], with what the scene adds). A dataset of another schema version is refused
//! with what to do; the run's size guard is not applied again.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::api::outputs::Reduced;
use crate::api::setup::{Setup, trace};
use crate::api::{free, harmonic, random};
use crate::report::charts;
use crate::sim::Scene;
use crate::store;
use crate::study::{LoadOptions, Study};

pub use crate::api::outputs::write_outputs;
pub use crate::api::reduce_options::{ReduceArgs, options};

/// `impactsweep plot waveform`.
#[derive(Clone, Debug, Default)]
pub struct WaveformArgs {
    pub sets: Vec<String>,
    pub out: PathBuf,
    pub e: Vec<f64>,
    pub t_end: f64,
}

/// Reduces a run directory: the one-line summary (`reduced N design points (…)`) and the
/// files written.
pub fn reduce_dir(args: &ReduceArgs) -> anyhow::Result<(String, Vec<PathBuf>)> {
    let dir = &args.dir;
    store::manifest::check_dir_version(dir)?;
    // The dataset exists: the size guard of `run` (which protects against starting a huge
    // sweep by mistake) has no business here; a study run with --allow-large reduces.
    let study = Study::load_with(&dir.join("study.toml"), LoadOptions { allow_large: true })?;
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
    let audit = read_audit(dir)?;
    // The one place the scene chooses its reduction.
    let reduced = match study.scene {
        Scene::Free => free::reduce(&study, dir, &parts, args, audit.as_ref())?,
        Scene::Harmonic(_) => harmonic::reduce(&study, dir, &st, &parts, args, audit.as_ref())?,
        Scene::Random(_) => random::reduce_random(&study, dir, &parts, args)?,
    };
    let (summary, files, from_shards) = match reduced {
        Reduced::Whole {
            summary,
            files,
            from_shards,
        } => (summary, files, from_shards),
        Reduced::Shard(line, files) => return Ok((line, files)),
    };
    let line = format!(
        "reduced {} design points ({} zones, {} jumps, {} Pareto-optimal{})",
        summary.points.len(),
        summary.zones.len(),
        summary.jumps.len(),
        summary.points.iter().filter(|p| p.pareto).count(),
        match summary.recommended {
            Some(p) => format!(
                "; recommended: {}",
                crate::report::markdown::design_text(&summary, p)
            ),
            None => "; no robust design".to_string(),
        }
    ) + &if from_shards > 0 {
        format!("; {from_shards} verified motions measured by the analysis shards")
    } else {
        String::new()
    };
    Ok((line, files))
}

/// The run's accuracy audit from `RUN_DIR/manifest.json`, when the run made one.
pub fn read_audit(dir: &Path) -> anyhow::Result<Option<crate::accuracy::Audit>> {
    Ok(store::read_manifest(dir)?.and_then(|m| m.audit))
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
