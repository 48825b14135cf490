//! The reduction of a harmonic study's run directory ([`reduce`]): its part files and their
//! attractors streamed through [`harmonic::HarmonicReducer`] (a design is a design point without
//! its frequency, `reduce/harmonic/design.rs`), the per-design analysis whole or as one shard of
//! it (`--shard`, written to `RUN_DIR/analysis/`), then the outputs every scene writes with the
//! harmonic scene's added ([`HarmonicOutputs`]): the steady states (`attractors.csv`,
//! `branches`), the bifurcation curves, the verification table, the frequency-response and
//! design-map charts and the report's section.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::api::outputs::{Reduced, SceneOutputs, write_outputs_with};
use crate::api::reduce_options::{ReduceArgs, options_over};
use crate::reduce::harmonic::{self, analysis, bifurcations};
use crate::reduce::{PointStats, Summary};
use crate::report::charts;
use crate::report::markdown::{self, SceneText};
use crate::sim::HarmonicRecord;
use crate::store::table::Table;
use crate::store::{self, TableKind};
use crate::study::Study;
use crate::sweep::status::Status;

/// Reduces the done parts `parts` of a harmonic study (`st`, the run directory's status) into
/// `dir`, or runs shard `args.shard` of its per-design analysis.
pub(crate) fn reduce(
    study: &Study,
    dir: &Path,
    st: &Status,
    parts: &[PathBuf],
    args: &ReduceArgs,
    audit: Option<&crate::accuracy::Audit>,
) -> anyhow::Result<Reduced> {
    let design = harmonic::design_study(study);
    let opts = options_over(harmonic::options(&design), args);
    let mut r = harmonic::HarmonicReducer::new(study, &design, opts);
    for (&k, p) in st.done.iter().zip(parts) {
        let side = store::attractors::attractors_part_path(dir, k);
        let recorded = st.manifest.chunk(k).is_some_and(|c| c.attractors.is_some());
        let attractors = if recorded || side.exists() {
            Some(store::attractors::read_part(&side)?)
        } else {
            None
        };
        r.push(
            store::read_rows::<HarmonicRecord>(p)
                .with_context(|| format!("reading {}", p.display()))?,
            attractors,
        );
    }
    let plan = analysis_plan(study, dir, args.shard)?;
    let (summary, mut fs, probes) = r.finish(&plan);
    fs.curve_lines = args.bifurcation_curves;
    if let Some(shard) = args.shard {
        let (line, files) = write_analysis_shard(study, dir, shard, &fs, &probes)?;
        return Ok(Reduced::Shard(line, files));
    }
    let from_shards = fs
        .verification
        .peaks
        .iter()
        .flat_map(|p| &p.verified)
        .filter(|v| !v.as_raced && plan.prior.verified.contains_key(&v.motion.key()))
        .count();
    let files = write_outputs_with(study, &summary, dir, audit, Some(&HarmonicOutputs(&fs)))?;
    Ok(Reduced::Whole {
        summary: Box::new(summary),
        files,
        from_shards,
    })
}

/// The harmonic scene's additions to the outputs: its band columns in the summary, its steady
/// states, bifurcations and verification tables, its frequency-response and design-map charts
/// and its report section.
struct HarmonicOutputs<'a>(&'a harmonic::HarmonicSummary);

impl SceneOutputs for HarmonicOutputs<'_> {
    fn summary_columns(&self, t: &mut Table, rows: &[&PointStats]) {
        harmonic::summary_columns(t, self.0, rows);
    }

    fn write(
        &self,
        study: &Study,
        summary: &Summary,
        dir: &Path,
    ) -> anyhow::Result<(Vec<PathBuf>, Vec<PathBuf>)> {
        let fs = self.0;
        let mut files = Vec::new();
        let mut chart_files = Vec::new();
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
            let t = harmonic::verify::table(&fs.verification, rank);
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
            .map(|c| harmonic::steady::section_samples(study, c))
            .unwrap_or_default();
        chart_files.extend(charts::harmonic::frequency_response::charts(
            summary, fs, &steady, &samples, dir,
        )?);
        if let Some(anchor) = summary.anchor() {
            chart_files.extend(charts::harmonic::design_map::charts(
                summary, fs, &curves, anchor, dir,
            )?);
        }
        Ok((files, chart_files))
    }

    fn scene_text(&self, study: &Study, summary: &Summary) -> SceneText {
        markdown::harmonic::scene_text(study, summary, self.0)
    }
}

/// How this reduction runs the per-design analysis: as shard `shard`, or whole with what a
/// complete set of earlier shards left in `RUN_DIR/analysis/`.
fn analysis_plan(
    study: &Study,
    dir: &Path,
    shard: Option<(u64, u64)>,
) -> anyhow::Result<analysis::Plan> {
    use analysis::{Plan, Prior, Shard};
    use harmonic::shard::{branches_from_part, probes_from_table, verification_from_part};
    if let Some((index, count)) = shard {
        return Ok(Plan {
            shard: Some(Shard { index, count }),
            prior: Prior::default(),
        });
    }
    let Some(set) = store::analysis::read_complete(dir, &study.source)? else {
        return Ok(Plan::default());
    };
    let keys: Vec<String> = harmonic::design_study(study)
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
    fs: &harmonic::HarmonicSummary,
    anchor: Option<u64>,
    dir: &Path,
) -> anyhow::Result<(Vec<crate::orbits::response::Response>, Vec<PathBuf>)> {
    use store::summary::TableWriter;
    let mut writers: Option<(TableWriter, TableWriter)> = None;
    let mut kept = Vec::new();
    harmonic::steady::steady_states_in_batches(study, fs, |batch| -> anyhow::Result<()> {
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
        attractors.append(harmonic::steady::attractors_table(&batch))?;
        branches.append(harmonic::steady::branches_table(&batch))?;
        kept.extend(batch.into_iter().map(|r| {
            if anchor.is_some_and(|a| harmonic::steady::draws_anchor(fs, a, &r)) {
                r
            } else {
                harmonic::steady::located_only(r)
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
    fs: &harmonic::HarmonicSummary,
    probes: &[(Vec<u64>, Option<[f64; 2]>)],
) -> anyhow::Result<(String, Vec<PathBuf>)> {
    let keys: Vec<String> = harmonic::design_study(study)
        .axes
        .iter()
        .map(|a| a.key.clone())
        .collect();
    let steady = harmonic::steady::steady_states(study, fs);
    let branches: usize = steady.iter().map(|r| r.branches.len()).sum();
    let files = store::analysis::write_shard(
        dir,
        shard,
        &study.source,
        vec![
            (
                TableKind::Probes,
                harmonic::shard::probes_table(&keys, probes),
            ),
            (TableKind::Branches, harmonic::shard::branches_part(&steady)),
            (
                TableKind::Verification,
                harmonic::shard::verification_part(&fs.verification),
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
