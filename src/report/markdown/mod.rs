//! `report.md`: the reduction of a run directory for a person, one function per section.
//! Deterministic: no timestamps, no paths outside the run directory, numbers at fixed
//! precision. No table is longer than [`MAX_ROWS`] rows, whatever the size of the sweep: the
//! rest stays in the Parquet and CSV tables, and the text says so.
//!
//! Order: the recommendation first (what to build, and whether the swept range was wide
//! enough), then the zones, the jumps, the sensitivity, the ranking, the nominal design's
//! cases, the outcomes, normality, how it was computed, the accuracy audit and the charts.

mod common;
pub mod harmonic;
pub mod random;
mod random_units;
pub mod seismic;
mod words;

use std::fmt::Write;

pub(crate) use words::f;
pub use words::{MAX_ROWS, SceneText, design_text};

use crate::reduce::Summary;
use crate::study::Study;

/// The report text. `charts` are file names relative to the run directory; `audit` is the
/// run's accuracy audit (`manifest.json`) when there is one.
pub fn report(
    study: &Study,
    s: &Summary,
    charts: &[String],
    audit: Option<&crate::accuracy::Audit>,
) -> String {
    report_with(study, s, charts, audit, &SceneText::default())
}

/// [`report`] with what the study's scene adds ([`SceneText`]: the harmonic scene's frequency
/// response after the recommendation, [`harmonic::scene_text`]).
pub fn report_with(
    study: &Study,
    s: &Summary,
    charts: &[String],
    audit: Option<&crate::accuracy::Audit>,
    scene: &SceneText,
) -> String {
    use self::common::{
        audit, cases, jumps, ranking, recommendation, sensitivity, settings, zones,
    };
    let mut o = format!("# impactsweep report: {}\n\n", study.name);
    o += &cases::overview(study, s, scene);
    o += &scene.head;
    match &scene.decision {
        Some(d) => o += d,
        None => {
            o += &settings::no_strength(s);
            o += &recommendation::section(s);
        }
    }
    o += &scene.section;
    if scene.laboratory {
        o += &zones::section(s);
    }
    o += &jumps::section(s, scene.window_peaks);
    o += &sensitivity::section(s);
    if scene.laboratory {
        o += &ranking::top(s);
        o += &ranking::pareto(s);
        o += &cases::nominal(s);
    }
    o += &cases::outcomes(s);
    if scene.laboratory {
        o += &cases::normality(study, s);
        o += &settings::section(study, s);
    }
    if let Some(a) = audit {
        o += &audit::section(a);
    }
    o += &charts_section(charts);
    o
}

fn charts_section(charts: &[String]) -> String {
    let mut o = String::new();
    if !charts.is_empty() {
        let _ = writeln!(
            o,
            "## Charts\n\nEach chart's data is the CSV file of the same name (the summary rows it draws).\n"
        );
        for c in charts.iter().filter(|c| c.ends_with(".svg")) {
            let _ = writeln!(o, "![{c}]({c})\n");
        }
    }
    let _ = writeln!(
        o,
        "Files: `summary.parquet` (one row per design point), `zones.parquet`, `jumps.parquet`, `sensitivity.parquet`, each also as CSV; SI units throughout (every column in impactsweep's `docs/schema.md`)."
    );
    o
}
