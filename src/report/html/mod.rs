//! The HTML pages (issue 18): `report.html` beside `report.md` in every reduced run directory,
//! and `OUT/index.html` for an output root ([`index`]).
//!
//! `report.html` is one self-contained file: the report's Markdown as HTML ([`markdown`]: the
//! same sections and words, opening with the recommended design), inline CSS, a few lines of
//! inline script, and every chart inlined as SVG. Nothing is fetched: no font, no script, no
//! image, no link to another file. It reads the same from a copied or mailed file.
//!
//! The charts that can say which design a mark is are drawn here as SVG text, one element per
//! design point with its summary values as `data-*` attributes and its hover text as `<title>`
//! ([`hover`]): the zone and perfectibility maps ([`maps`]) and the design charts with the
//! response's boxes ([`profile`]); a load study's risk profiles and maps ([`random`], the
//! page's scene sibling, drawn by [`numbers`]). The other charts (the frequency response, the
//! small multiples, …) are the plotters SVGs of the run directory, inlined. Clicking a row of the
//! zones table highlights that zone's cells and points; the page's script also shows the hover
//! text beside the pointer at once (a browser shows a `<title>` only after a pause).

pub mod hover;
pub mod index;
pub mod maps;
pub mod markdown;
pub mod numbers;
pub mod profile;
pub mod random;

use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::reduce::Summary;
use crate::report::charts::common::map::{MapChart, MapKind};
use crate::report::charts::plumbing::Profile;
use crate::store::table::axis_column;
use markdown::esc;

/// The page's style sheet.
const CSS: &str = include_str!("page.css");
/// The page's script: hover text beside the pointer, zone rows that highlight their cells.
const SCRIPT: &str = include_str!("page.js");

/// `<meta>` names the index reads back from a report page.
pub const META_RECOMMENDED: &str = "impactsweep-recommended";
pub const META_THUMBNAIL: &str = "impactsweep-thumbnail";
/// The best ranked design, for a study without a robust one.
pub const META_BEST: &str = "impactsweep-best";

/// Above this many cells a map is not drawn one element per cell (the page would weigh about
/// a kilobyte per cell): the plotters SVG stands in for it.
pub const MAX_CELLS: usize = 20_000;
/// Above this many points along its axis a design chart is the plotters SVG too.
pub const MAX_PROFILE: usize = 5_000;
/// A plotters SVG larger than this (bytes) is not inlined; the page names the file instead.
pub const MAX_INLINE: u64 = 8_000_000;

/// The charts drawn here, by the file name of the plotters SVG they stand for.
fn interactive(s: &Summary) -> Vec<(String, String)> {
    let g = &s.grid;
    let mut out = Vec::new();
    let Some(anchor) = s.anchor() else {
        return out;
    };
    if g.n_axes() == 0 {
        return out;
    }
    let design = |a: usize, name: String| {
        let pr = Profile::new(s, a, anchor);
        let html = format!(
            "<figcaption>{}</figcaption>\n<div class=\"svg\">{}</div>\n",
            esc(&profile::caption(&pr)),
            profile::design_svg(&pr)
        );
        (name, html)
    };
    if g.n_axes() == 1 {
        out.push(design(0, "design_chart.svg".to_string()));
        return out;
    }
    let swept: Vec<usize> = (0..g.n_axes()).filter(|&a| g.n(a) >= 2).collect();
    for &a in &swept {
        out.push(design(
            a,
            format!("design_chart_{}.svg", axis_column(g.key(a))),
        ));
    }
    for (i, &a) in swept.iter().enumerate() {
        for &b in &swept[i + 1..] {
            let pair = format!("{}_{}", axis_column(g.key(a)), axis_column(g.key(b)));
            for (stem, kind, what) in [
                (
                    "perfectibility_map",
                    MapKind::Perfectibility,
                    "Perfectibility P (eq. 11)",
                ),
                ("zone_map", MapKind::Zones, "Zones"),
            ] {
                let chart = MapChart {
                    s,
                    a,
                    b,
                    through: anchor,
                    kind,
                };
                let slice = chart.slice();
                let at = if slice.is_empty() {
                    String::new()
                } else {
                    format!("; slice at {slice}")
                };
                let html = format!(
                    "<figcaption>{what} over {} (up) and {} (across){}; outlined: the {} design</figcaption>\n<div class=\"svg\">{}</div>\n{}",
                    esc(g.key(a)),
                    esc(g.key(b)),
                    esc(&at),
                    if s.recommended == Some(anchor) {
                        "recommended"
                    } else {
                        "best"
                    },
                    maps::map_svg(&chart),
                    maps::legend(&chart)
                );
                out.push((format!("{stem}_{pair}.svg"), html));
            }
        }
    }
    out
}

/// A plotters SVG of the run directory, inlined (without an XML declaration); a note naming
/// the file when it is larger than [`MAX_INLINE`].
fn inline_svg(dir: &Path, file: &str) -> anyhow::Result<String> {
    let path = dir.join(file);
    let size = std::fs::metadata(&path)
        .with_context(|| format!("reading {}", path.display()))?
        .len();
    if size > MAX_INLINE {
        return Ok(format!(
            "<p class=\"too-large\">This chart's SVG is {} MB, too large to inline: open <code>{}</code> or its PNG in the run directory.</p>",
            size / 1_000_000,
            esc(file)
        ));
    }
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let start = text.find("<svg").unwrap_or(0);
    Ok(text[start..].to_string())
}

/// The page of a reduction: `md` is `report.md`'s text, `charts` the chart files it names
/// (relative to `dir`, the run directory, where the plotters SVGs are read from), `scene` the
/// scene's own drawn charts by the file name of the plotters SVG each stands for
/// ([`random::interactive`]; none for the other scenes).
pub fn report(
    md: &str,
    s: &Summary,
    charts: &[String],
    dir: &Path,
    scene: Vec<(String, String)>,
) -> anyhow::Result<String> {
    let mut drawn = interactive(s);
    drawn.extend(scene);
    let zones: Vec<String> = s.zones.iter().map(|z| z.name.clone()).collect();
    let mut figure = |file: &str| -> anyhow::Result<String> {
        let stem = file.strip_suffix(".svg").unwrap_or(file);
        let body = match drawn.iter().find(|(n, _)| n == file) {
            Some((_, html)) => html.clone(),
            None => format!("<div class=\"svg\">{}</div>\n", inline_svg(dir, file)?),
        };
        Ok(format!(
            "<figure class=\"chart\" id=\"fig-{}\">\n{body}<p class=\"files\">{}: <code>{}.svg</code>, <code>{}.png</code>, data <code>{}.csv</code></p>\n</figure>\n",
            esc(stem),
            if drawn.iter().any(|(n, _)| n == file) {
                "Drawn for this page from the summary; also"
            } else {
                "In the run directory"
            },
            esc(stem),
            esc(stem),
            esc(stem)
        ))
    };
    let body = markdown::to_html(md, &zones, &mut figure)?;
    let title = md
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("# "))
        .unwrap_or("impactsweep report");
    let recommended = s
        .recommended
        .map(|p| crate::report::markdown::design_text(s, p))
        .unwrap_or_default();
    let best = s
        .anchor()
        .filter(|_| s.recommended.is_none())
        .map(|p| crate::report::markdown::design_text(s, p))
        .unwrap_or_default();
    // The chart a study is chosen by: its design chart, or a load study's risk map or profile.
    let png = |stem: &str| {
        charts
            .iter()
            .find(|c| c.starts_with(stem) && c.ends_with(".png"))
    };
    let thumbnail = png("design_chart")
        .or_else(|| png("risk_map"))
        .or_else(|| png("risk_profile"))
        .or_else(|| png(""))
        .cloned()
        .unwrap_or_default();
    let mut o = String::new();
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<meta name=\"generator\" content=\"impactsweep\">\n<meta name=\"{META_RECOMMENDED}\" content=\"{}\">\n<meta name=\"{META_BEST}\" content=\"{}\">\n<meta name=\"{META_THUMBNAIL}\" content=\"{}\">\n<title>{}</title>\n<style>\n{CSS}</style>\n</head>\n<body>\n",
        esc(&recommended),
        esc(&best),
        esc(&thumbnail),
        esc(title)
    );
    o += &nav(md);
    o.push_str(HATCH);
    o.push_str("<div id=\"tip\" hidden></div>\n<main>\n");
    o += &body;
    let _ = write!(
        o,
        "</main>\n<script>\n{SCRIPT}</script>\n</body>\n</html>\n"
    );
    Ok(o)
}

/// The hatch pattern of merged-in cells, defined once for every map of the page.
const HATCH: &str = "<svg width=\"0\" height=\"0\" style=\"position:absolute\" aria-hidden=\"true\"><defs><pattern id=\"hatch\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" patternTransform=\"rotate(45)\"><line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"6\" stroke=\"#333\" stroke-width=\"1.6\"/></pattern></defs></svg>\n";

/// Links to the report's sections.
fn nav(md: &str) -> String {
    let mut o = String::from("<nav>");
    for (id, t) in markdown::sections(md) {
        let _ = write!(o, "<a href=\"#{id}\">{}</a>", markdown::inline(&t));
    }
    o.push_str("</nav>\n");
    o
}

/// Writes `dir/report.html` ([`report`]); returns its path.
pub fn write_report(
    md: &str,
    s: &Summary,
    charts: &[String],
    dir: &Path,
    scene: Vec<(String, String)>,
) -> anyhow::Result<PathBuf> {
    let page = report(md, s, charts, dir, scene)?;
    let path = dir.join("report.html");
    std::fs::write(&path, page).with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}
