//! What a reduction writes into the run directory, whatever the scene: the `summary` table in
//! batches of points, the core's tables (`zones`, `jumps`, `sensitivity`), the core's charts,
//! `report.md` and `report.html` ([`write_outputs`]); a scene adds its columns, tables, charts
//! and report section through [`SceneOutputs`] ([`write_outputs_with`]). What a scene's
//! reduction gives back to [`crate::api::reduce::reduce_dir`] is a [`Reduced`].

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::reduce::common::tables;
use crate::reduce::{self, Summary};
use crate::report::markdown::SceneText;
use crate::report::{charts, html, markdown};
use crate::store::table::Table;
use crate::store::{self, TableKind};
use crate::study::Study;

/// What a scene's reduction of a run directory gives back.
pub(crate) enum Reduced {
    /// The whole reduction: the core's summary, the files written, and how many verified
    /// motions earlier analysis shards measured (a harmonic study's; 0 otherwise).
    Whole {
        summary: Box<Summary>,
        files: Vec<PathBuf>,
        from_shards: usize,
    },
    /// One analysis shard's work (a harmonic study's `--shard`): its one-line summary and files.
    Shard(String, Vec<PathBuf>),
}

/// What a scene adds to the outputs every reduction writes.
pub(crate) trait SceneOutputs {
    /// The scene's columns of the `summary` table, for the batch of points `rows`.
    fn summary_columns(&self, t: &mut Table, rows: &[&reduce::PointStats]);

    /// Writes the scene's own tables and charts into `dir`, after the core's tables: the tables'
    /// files and the charts' files (the charts come before the core's in the report).
    fn write(
        &self,
        study: &Study,
        summary: &Summary,
        dir: &Path,
    ) -> anyhow::Result<(Vec<PathBuf>, Vec<PathBuf>)>;

    /// The scene's words in the report.
    fn scene_text(&self, study: &Study, summary: &Summary) -> SceneText;
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

/// [`write_outputs`] with what the study's scene adds ([`SceneOutputs`]).
pub(crate) fn write_outputs_with(
    study: &Study,
    summary: &Summary,
    dir: &Path,
    audit: Option<&crate::accuracy::Audit>,
    scene: Option<&dyn SceneOutputs>,
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
            if let Some(scene) = scene {
                scene.summary_columns(&mut t, rows);
            }
            t
        },
    )?);
    drop(points);
    files.extend(super::tables::write_core_tables(summary, dir)?);
    let mut chart_files = Vec::new();
    if let Some(scene) = scene {
        let (written, charts) = scene.write(study, summary, dir)?;
        files.extend(written);
        chart_files.extend(charts);
    }
    chart_files.extend(charts::summary_charts(summary, dir)?);
    let names: Vec<String> = chart_files
        .iter()
        .filter_map(|f| f.file_name().and_then(|n| n.to_str()).map(String::from))
        .collect();
    files.extend(chart_files);
    let p = dir.join("report.md");
    let text = scene
        .map(|s| s.scene_text(study, summary))
        .unwrap_or_default();
    let md = markdown::report_with(study, summary, &names, audit, &text);
    std::fs::write(&p, &md).with_context(|| format!("writing {}", p.display()))?;
    files.push(p);
    files.push(html::write_report(&md, summary, &names, dir, Vec::new())?);
    Ok(files)
}
