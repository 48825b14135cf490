//! The reduction of a random or record study's run directory ([`reduce_random`]): its part
//! files streamed through [`crate::reduce::random::RandomReducer`], then the same outputs as
//! the other scenes (`summary` with the scene's columns, `zones`, `jumps`, `sensitivity`, the
//! charts, `report.md` with the scene's section, `report.html`).

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::api::outputs::Reduced;
use crate::api::reduce_options::{ReduceArgs, options_over};
use crate::reduce::common::tables;
use crate::reduce::random::subset::SubsetAsk;
use crate::reduce::random::{self, RandomReducer, RandomSummary};
use crate::reduce::{PointStats, Summary};
use crate::report::{charts, html, markdown};
use crate::sim::random::RealizationRecord;
use crate::store::{self, TableKind};
use crate::study::Study;

/// Reduces the done parts `parts` of a random or record study into `dir`, with the command
/// line's overrides of the scene's options (`args`) and, where Monte Carlo saw few exceedances,
/// subset simulation as `args.subset` and `args.subset_repeats` ask
/// ([`crate::reduce::random::subset`]).
pub(crate) fn reduce_random(
    study: &Study,
    dir: &Path,
    parts: &[PathBuf],
    args: &ReduceArgs,
) -> anyhow::Result<Reduced> {
    let design = random::design_study(study);
    let opts = options_over(random::options(&design), args);
    let mut r = RandomReducer::new(study, &design, opts);
    for p in parts {
        r.push(
            store::read_rows::<RealizationRecord>(p)
                .with_context(|| format!("reading {}", p.display()))?,
        );
    }
    let subset = args.subset.map(|n| SubsetAsk {
        n,
        repeats: args.subset_repeats.max(1),
    });
    let (summary, rs) = r.finish(subset);
    let files = write_outputs(study, &summary, &rs, dir)?;
    Ok(Reduced::Whole {
        summary: Box::new(summary),
        files,
        from_shards: 0,
    })
}

/// Writes every output of a random study's reduction into `dir`; returns the files written.
fn write_outputs(
    study: &Study,
    summary: &Summary,
    rs: &RandomSummary,
    dir: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut files = Vec::new();
    let points: Vec<&PointStats> = summary.points.iter().collect();
    files.extend(store::summary::write_table_in_batches(
        dir,
        TableKind::Summary,
        points.len(),
        |r| {
            let rows = &points[r];
            let mut t = tables::summary_rows(summary, rows);
            random::summary_columns(&mut t, summary, rs, rows);
            t
        },
    )?);
    drop(points);
    files.extend(super::tables::write_core_tables(summary, dir)?);
    // The motions' capacities, or no table rather than an earlier reduce's.
    if rs.capacities.is_empty() {
        for name in ["capacities.parquet", "capacities.csv"] {
            let stale = dir.join(name);
            if stale.exists() {
                std::fs::remove_file(&stale)
                    .with_context(|| format!("removing {}", stale.display()))?;
            }
        }
    } else {
        let suite: Vec<&str> = study
            .scene
            .random()
            .map(|r| r.suite().iter().map(|x| x.name.as_str()).collect())
            .unwrap_or_default();
        let t = random::risk::capacities_table(&summary.grid, &rs.capacities, &suite);
        files.extend(store::summary::write_table(dir, TableKind::Capacities, &t)?);
    }
    let mut chart_files = charts::random::charts(summary, rs, dir)?;
    chart_files.extend(charts::risk::charts(summary, rs, dir)?);
    chart_files.extend(charts::load_charts(summary, dir, rs.threshold)?);
    let names: Vec<String> = chart_files
        .iter()
        .filter_map(|f| f.file_name().and_then(|n| n.to_str()).map(String::from))
        .collect();
    files.extend(chart_files);
    let p = dir.join("report.md");
    let scene = markdown::random::scene_text(study, summary, rs);
    let md = markdown::report_with(study, summary, &names, None, &scene);
    std::fs::write(&p, &md).with_context(|| format!("writing {}", p.display()))?;
    files.push(p);
    files.push(html::write_report(
        &md,
        summary,
        &names,
        dir,
        html::random::interactive(summary, rs),
    )?);
    Ok(files)
}
