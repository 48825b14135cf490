//! The reduction of a run directory (`impactsweep reduce`, the Python binding's `reduce`) and
//! the waveform plots (`plot waveform`).
//!
//! [`reduce_dir`] streams the part files of a run directory through
//! [`crate::reduce::Reducer`] one at a time (each holds whole design points, so memory stays
//! a chunk plus a fixed size per design point), converting the store's rows to the reducer's
//! own ([`free::run_of`]), then writes into the run directory: `summary`, `zones`, `jumps` and
//! `sensitivity` as Parquet and CSV (columns in `docs/schema.md`), `report.md` and the charts
//! (SVG and PNG, each with its data as CSV), and `report.html`, the report as one
//! self-contained page with the charts inlined (docs/reduce.md). A dataset of another schema version is refused with
//! what to do; the run's size guard is not applied again.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::api::setup::{Setup, trace};
use crate::reduce::core::tables;
use crate::reduce::forced::{self, analysis, bifurcations};
use crate::reduce::random::subset::{DEFAULT_SUBSET_N, SubsetAsk};
use crate::reduce::{self, Options, Summary, free};
use crate::report::{charts, html, markdown};
use crate::sim::{ForcedRecord, Scene};
use crate::store::{self, TableKind};
use crate::study::{DiSource, LoadOptions, SafetyForm, Study};

/// `impactsweep reduce RUN_DIR`. Its default: the study's own settings, subset simulation of
/// [`DEFAULT_SUBSET_N`] samples per level where a random study's Monte Carlo saw few
/// exceedances.
#[derive(Clone, Debug)]
pub struct ReduceArgs {
    pub dir: PathBuf,
    /// Use the paper's small-C_n safety factor instead of Shigley's exact relation.
    pub paper_safety: bool,
    /// DI as the mean over cases instead of the ideal case.
    pub di_mean: bool,
    /// Overrides `[reliability].bootstrap`.
    pub bootstrap: Option<usize>,
    /// `(I, N)`: only shard `I` of `N` of a harmonic study's per-design analysis
    /// ([`crate::reduce::forced::analysis`]), written to `RUN_DIR/analysis/`; no report.
    pub shard: Option<(u64, u64)>,
    /// A harmonic study: the lines of the design grid its bifurcation curves are followed along.
    pub bifurcation_curves: analysis::CurveLines,
    /// A random study: subset simulation of this many samples per level for the designs whose
    /// realizations passed the threshold fewer than 10 times
    /// ([`crate::reduce::random::subset`]); `None`: Monte Carlo only.
    pub subset: Option<usize>,
    /// A random study: independent subset simulations per such design (at least 1), their mean
    /// its `p_f` and their spread its interval when more than 1. Default 1.
    pub subset_repeats: usize,
}

impl Default for ReduceArgs {
    fn default() -> Self {
        ReduceArgs {
            dir: PathBuf::new(),
            paper_safety: false,
            di_mean: false,
            bootstrap: None,
            shard: None,
            bifurcation_curves: analysis::CurveLines::default(),
            subset: Some(DEFAULT_SUBSET_N),
            subset_repeats: 1,
        }
    }
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
    options_over(free::options(study), args)
}

/// `base` (the study's choices, or a scene's) with the command-line overrides.
fn options_over(base: Options, args: &ReduceArgs) -> Options {
    let mut o = base;
    if args.paper_safety {
        o.safety_form = SafetyForm::Paper;
    }
    if args.di_mean {
        o.di_source = DiSource::Mean;
    }
    if let Some(b) = args.bootstrap {
        o.bootstrap = b;
    }
    o
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
    // Direct measurements of the verification that analysis shards made and this reduction took.
    let mut from_shards = 0;
    let (summary, files) = match study.scene {
        Scene::Free => {
            let opts = options(&study, args);
            let chunks = parts.iter().map(|p| {
                store::read_part(p)
                    .map(|rows| rows.iter().map(free::run_of).collect())
                    .with_context(|| format!("reading {}", p.display()))
            });
            let summary = free::reduce(&study, opts, chunks)?;
            let files = write_outputs(&study, &summary, dir, audit.as_ref())?;
            (summary, files)
        }
        Scene::Harmonic(_) => {
            // A design is a design point without its frequency (reduce/forced/design.rs).
            let design = forced::design_study(&study);
            let opts = options_over(forced::options(&design), args);
            let mut r = forced::ForcedReducer::new(&study, &design, opts);
            for (&k, p) in st.done.iter().zip(&parts) {
                let side = store::attractors::attractors_part_path(dir, k);
                let recorded = st.manifest.chunk(k).is_some_and(|c| c.attractors.is_some());
                let attractors = if recorded || side.exists() {
                    Some(store::attractors::read_part(&side)?)
                } else {
                    None
                };
                r.push(
                    store::read_rows::<ForcedRecord>(p)
                        .with_context(|| format!("reading {}", p.display()))?,
                    attractors,
                );
            }
            let plan = analysis_plan(&study, dir, args.shard)?;
            let (summary, mut fs, probes) = r.finish(&plan);
            fs.curve_lines = args.bifurcation_curves;
            if let Some(shard) = args.shard {
                return write_analysis_shard(&study, dir, shard, &fs, &probes);
            }
            from_shards = fs
                .verification
                .peaks
                .iter()
                .flat_map(|p| &p.verified)
                .filter(|v| !v.as_raced && plan.prior.verified.contains_key(&v.motion.key()))
                .count();
            let files = write_outputs_with(&study, &summary, dir, audit.as_ref(), Some(&fs))?;
            (summary, files)
        }
        Scene::Random(_) => crate::api::random::reduce_random(
            &study,
            dir,
            &parts,
            |o| options_over(o, args),
            args.subset.map(|n| SubsetAsk {
                n,
                repeats: args.subset_repeats.max(1),
            }),
        )?,
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

/// How this reduction runs the per-design analysis: as shard `shard`, or whole with what a
/// complete set of earlier shards left in `RUN_DIR/analysis/`.
fn analysis_plan(
    study: &Study,
    dir: &Path,
    shard: Option<(u64, u64)>,
) -> anyhow::Result<analysis::Plan> {
    use analysis::{Plan, Prior, Shard};
    use forced::shard::{branches_from_part, probes_from_table, verification_from_part};
    if let Some((index, count)) = shard {
        return Ok(Plan {
            shard: Some(Shard { index, count }),
            prior: Prior::default(),
        });
    }
    let Some(set) = store::analysis::read_complete(dir, &study.source)? else {
        return Ok(Plan::default());
    };
    let keys: Vec<String> = forced::design_study(study)
        .axes
        .iter()
        .map(|a| a.key.clone())
        .collect();
    let mut prior = Prior {
        complete: true,
        ..Prior::default()
    };
    let bad = || {
        anyhow::anyhow!(
            "{}: an analysis shard's table lacks a column",
            dir.display()
        )
    };
    for t in &set.probes {
        prior
            .probes
            .extend(probes_from_table(&keys, t).ok_or_else(bad)?);
    }
    for t in &set.branches {
        prior
            .branches
            .extend(branches_from_part(t).ok_or_else(bad)?);
    }
    for t in &set.verification {
        prior
            .verified
            .extend(verification_from_part(t).ok_or_else(bad)?);
    }
    Ok(Plan { shard: None, prior })
}

/// The steady states of a harmonic study's designs, a batch of designs at a time (memory for
/// one batch, not the study's): `attractors.csv` and the `branches` table written as they come;
/// returns the states the report still needs (the recommended design's `anchor` whole, the
/// others' located points for the bifurcation curves) and the files written (none when the
/// study has no steady states to follow).
fn write_steady_states(
    study: &Study,
    fs: &forced::ForcedSummary,
    anchor: Option<u64>,
    dir: &Path,
) -> anyhow::Result<(Vec<crate::orbits::response::Response>, Vec<PathBuf>)> {
    use store::summary::TableWriter;
    let mut writers: Option<(TableWriter, TableWriter)> = None;
    let mut kept = Vec::new();
    forced::steady::steady_states_in_batches(study, fs, |batch| -> anyhow::Result<()> {
        if batch.is_empty() {
            return Ok(());
        }
        let (attractors, branches) = match writers.as_mut() {
            Some(w) => w,
            None => writers.insert((
                TableWriter::create_csv(&dir.join("attractors.csv"))?,
                TableWriter::create(dir, TableKind::Branches)?,
            )),
        };
        attractors.append(forced::steady::attractors_table(&batch))?;
        branches.append(forced::steady::branches_table(&batch))?;
        kept.extend(batch.into_iter().map(|r| {
            if anchor.is_some_and(|a| forced::steady::draws_anchor(fs, a, &r)) {
                r
            } else {
                forced::steady::located_only(r)
            }
        }));
        Ok(())
    })?;
    let mut files = Vec::new();
    if let Some((attractors, branches)) = writers {
        files.extend(attractors.finish()?);
        files.extend(branches.finish()?);
    }
    Ok((kept, files))
}

/// Writes what shard `shard` of the analysis computed (its designs' branches, its jump probes)
/// into `RUN_DIR/analysis/`.
fn write_analysis_shard(
    study: &Study,
    dir: &Path,
    shard: (u64, u64),
    fs: &forced::ForcedSummary,
    probes: &[(Vec<u64>, Option<[f64; 2]>)],
) -> anyhow::Result<(String, Vec<PathBuf>)> {
    let keys: Vec<String> = forced::design_study(study)
        .axes
        .iter()
        .map(|a| a.key.clone())
        .collect();
    let steady = forced::steady::steady_states(study, fs);
    let branches: usize = steady.iter().map(|r| r.branches.len()).sum();
    let files = store::analysis::write_shard(
        dir,
        shard,
        &study.source,
        vec![
            (
                TableKind::Probes,
                forced::shard::probes_table(&keys, probes),
            ),
            (TableKind::Branches, forced::shard::branches_part(&steady)),
            (
                TableKind::Verification,
                forced::shard::verification_part(&fs.verification),
            ),
        ],
    )?;
    let measured = fs
        .verification
        .peaks
        .iter()
        .flat_map(|p| &p.verified)
        .filter(|v| !v.as_raced)
        .count();
    let line = format!(
        "analysis shard {}/{}: {} jump probes, {} branch points, {} motions verified",
        shard.0,
        shard.1,
        probes.len(),
        branches,
        measured
    );
    Ok((line, files))
}

/// The run's accuracy audit from `RUN_DIR/manifest.json`, when the run made one.
pub fn read_audit(dir: &Path) -> anyhow::Result<Option<crate::accuracy::Audit>> {
    Ok(store::read_manifest(dir)?.and_then(|m| m.audit))
}

/// Writes every output of a reduction into `dir`; returns the files written.
pub fn write_outputs(
    study: &Study,
    summary: &Summary,
    dir: &Path,
    audit: Option<&crate::accuracy::Audit>,
) -> anyhow::Result<Vec<PathBuf>> {
    write_outputs_with(study, summary, dir, audit, None)
}

/// [`write_outputs`], and for a harmonic study (`forced`) its band columns in the summary, its
/// frequency-response charts and its report section.
pub fn write_outputs_with(
    study: &Study,
    summary: &Summary,
    dir: &Path,
    audit: Option<&crate::accuracy::Audit>,
    forced: Option<&forced::ForcedSummary>,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut files = Vec::new();
    // The summary in batches of points: one batch of columns in memory at a time.
    let points: Vec<&reduce::PointStats> = summary.points.iter().collect();
    files.extend(store::summary::write_table_in_batches(
        dir,
        TableKind::Summary,
        points.len(),
        |r| {
            let rows = &points[r];
            let mut t = tables::summary_rows(summary, rows);
            if let Some(fs) = forced {
                forced::summary_columns(&mut t, fs, rows);
            }
            t
        },
    )?);
    drop(points);
    files.extend(super::tables::write_core_tables(summary, dir)?);
    let mut chart_files = Vec::new();
    if let Some(fs) = forced {
        let (steady, written) = write_steady_states(study, fs, summary.anchor(), dir)?;
        files.extend(written);
        // The located bifurcations followed over the design axes.
        let curves = bifurcations::curves(
            study,
            &summary.grid,
            fs,
            &steady,
            fs.curve_lines,
            summary.anchor(),
        );
        if curves.is_empty() {
            // No table rather than an earlier reduce's, which would not match this one.
            for name in ["bifurcations.parquet", "bifurcations.csv"] {
                let stale = dir.join(name);
                if stale.exists() {
                    std::fs::remove_file(&stale)
                        .with_context(|| format!("removing {}", stale.display()))?;
                }
            }
        } else {
            let t = bifurcations::table(&curves);
            files.extend(store::summary::write_table(
                dir,
                TableKind::Bifurcations,
                &t,
            )?);
        }
        // The motions measured again to verify the ranking; no table when none was.
        if fs.verification.peaks.iter().all(|p| p.verified.is_empty()) {
            for name in ["verification.parquet", "verification.csv"] {
                let stale = dir.join(name);
                if stale.exists() {
                    std::fs::remove_file(&stale)
                        .with_context(|| format!("removing {}", stale.display()))?;
                }
            }
        } else {
            let rank = |d: u64| {
                summary
                    .points
                    .iter()
                    .find(|p| p.point == d)
                    .and_then(|p| p.rank)
            };
            let t = forced::verify::table(&fs.verification, rank);
            files.extend(store::summary::write_table(
                dir,
                TableKind::Verification,
                &t,
            )?);
        }
        // The recommended design's bifurcation diagram: its attractors' sections.
        let samples = summary
            .anchor()
            .filter(|_| fs.frequency.is_some() && !steady.is_empty())
            .and_then(|a| fs.curve(a))
            .map(|c| forced::steady::section_samples(study, c))
            .unwrap_or_default();
        chart_files.extend(charts::forced::frequency_response::charts(
            summary, fs, &steady, &samples, dir,
        )?);
        if let Some(anchor) = summary.anchor() {
            chart_files.extend(charts::forced::design_map::charts(
                summary, fs, &curves, anchor, dir,
            )?);
        }
    }
    chart_files.extend(charts::summary_charts(summary, dir)?);
    let names: Vec<String> = chart_files
        .iter()
        .filter_map(|f| f.file_name().and_then(|n| n.to_str()).map(String::from))
        .collect();
    files.extend(chart_files);
    let p = dir.join("report.md");
    let scene = forced
        .map(|fs| markdown::forced::scene_text(study, summary, fs))
        .unwrap_or_default();
    let md = markdown::report_with(study, summary, &names, audit, &scene);
    std::fs::write(&p, &md).with_context(|| format!("writing {}", p.display()))?;
    files.push(p);
    files.push(html::write_report(&md, summary, &names, dir)?);
    Ok(files)
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
