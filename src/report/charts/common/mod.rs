//! The summary charts every scene has ([`summary_charts`]): the damping quantity against one
//! axis ([`di`]), the design chart ([`design`]), the response's spread over the cases
//! ([`spread`]), the perfectibility and zone maps over two axes ([`map`]) and the zone maps as
//! small multiples over three ([`multiples`]). They read the core's [`Summary`] only.

pub mod design;
pub mod di;
pub mod interval;
pub mod map;
pub mod multiples;
pub mod spread;

use std::path::{Path, PathBuf};

use crate::reduce::Summary;
use crate::report::charts::plumbing::{self, Data, Profile};
use crate::store::table::axis_column;

/// Draws every summary chart into `dir`; returns the files written (SVG, PNG and CSV of each).
pub fn summary_charts(s: &Summary, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    charts_of(s, dir, None)
}

/// The core charts of a load study (a random or record study): the spread charts with the limit
/// of `|x|` drawn (`limit`, m), without the laboratory's damping chart, design chart (R against
/// a strength, the safety factor), perfectibility and zone maps, which the risk charts replace
/// ([`crate::report::charts::risk`]).
pub fn load_charts(s: &Summary, dir: &Path, limit: Option<f64>) -> anyhow::Result<Vec<PathBuf>> {
    charts_of(s, dir, Some(limit))
}

/// [`summary_charts`], or with `load` [`load_charts`] with its limit.
fn charts_of(s: &Summary, dir: &Path, load: Option<Option<f64>>) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let g = &s.grid;
    let Some(anchor) = s.anchor() else {
        return Ok(files);
    };
    if g.n_axes() == 0 {
        return Ok(files);
    }
    let cols = Columns::of(s, load);
    if g.n_axes() == 1 {
        let pr = Profile::new(s, 0, anchor);
        if load.is_some() {
            return profile_charts(s, dir, &pr, &cols, "");
        }
        let d = s.options.damping.name;
        files.extend(plumbing::render(
            dir,
            d,
            di::SIZE,
            &di::DiChart(&pr),
            &Data::Rows(s, &pr.points, &[d]),
        )?);
        files.extend(profile_charts(s, dir, &pr, &cols, "")?);
        return Ok(files);
    }
    let swept: Vec<usize> = (0..g.n_axes()).filter(|&a| g.n(a) >= 2).collect();
    for &a in &swept {
        let pr = Profile::new(s, a, anchor);
        let suffix = format!("_{}", axis_column(g.key(a)));
        files.extend(profile_charts(s, dir, &pr, &cols, &suffix)?);
    }
    // A load study's maps are its risk maps; the zones rest on the laboratory's classes.
    if load.is_some() {
        return Ok(files);
    }
    for (i, &a) in swept.iter().enumerate() {
        for &b in &swept[i + 1..] {
            files.extend(maps(s, dir, (a, b), anchor)?);
        }
    }
    if swept.len() == 3 {
        let chart = multiples::ZoneMultiples::new(s, swept[0], (swept[1], swept[2]), anchor);
        let points = chart.points();
        let data = Data::Rows(s, &points, &["class", "zone"]);
        files.extend(plumbing::render(
            dir,
            &format!("zone_maps_{}", axis_column(g.key(swept[0]))),
            multiples::SIZE,
            &chart,
            &data,
        )?);
    }
    Ok(files)
}

/// The columns each profile chart draws (its data: these, after point and the axes).
struct Columns {
    /// The spread chart's file stem, `<response>_spread`.
    spread: String,
    spread_cols: Vec<String>,
    design_cols: [&'static str; 7],
    /// A load study: no design chart, the limit of `|x|` (m) on the spread chart.
    load: Option<Option<f64>>,
}

impl Columns {
    fn of(s: &Summary, load: Option<Option<f64>>) -> Columns {
        let r = s.options.response.name;
        Columns {
            load,
            spread: format!("{r}_spread"),
            spread_cols: ["min", "q1", "median", "q3", "max", "ideal"]
                .iter()
                .map(|q| format!("{r}_{q}"))
                .collect(),
            design_cols: [
                "reliability",
                "reliability_lo",
                "reliability_hi",
                "safety_factor",
                s.options.damping.name,
                "class",
                "zone",
            ],
        }
    }
}

/// The design chart and the spread chart along the profile `pr`, their file stems ending in
/// `suffix` (`_<axis>` when the study has several axes).
fn profile_charts(
    s: &Summary,
    dir: &Path,
    pr: &Profile,
    cols: &Columns,
    suffix: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let spread_cols: Vec<&str> = cols.spread_cols.iter().map(String::as_str).collect();
    let mut files = Vec::new();
    if cols.load.is_none() {
        files.extend(plumbing::render(
            dir,
            &format!("design_chart{suffix}"),
            design::SIZE,
            &design::DesignChart(pr),
            &Data::Rows(s, &pr.points, &cols.design_cols),
        )?);
    }
    files.extend(plumbing::render(
        dir,
        &format!("{}{suffix}", cols.spread),
        spread::SIZE,
        &spread::SpreadChart(pr, cols.load.flatten()),
        &Data::Rows(s, &pr.points, &spread_cols),
    )?);
    Ok(files)
}

/// The perfectibility map and the zone map over the axes `(a, b)`, through `anchor`.
fn maps(
    s: &Summary,
    dir: &Path,
    (a, b): (usize, usize),
    anchor: u64,
) -> anyhow::Result<Vec<PathBuf>> {
    let g = &s.grid;
    let pair = format!("{}_{}", axis_column(g.key(a)), axis_column(g.key(b)));
    let mut files = Vec::new();
    for (stem, kind, columns) in [
        (
            "perfectibility_map",
            map::MapKind::Perfectibility,
            &["perfectibility", "rank", "robust"][..],
        ),
        ("zone_map", map::MapKind::Zones, &["class", "zone"][..]),
    ] {
        let chart = map::MapChart {
            s,
            a,
            b,
            through: anchor,
            kind,
        };
        let points = chart.points();
        let data = Data::Rows(s, &points, columns);
        files.extend(plumbing::render(
            dir,
            &format!("{stem}_{pair}"),
            map::SIZE,
            &chart,
            &data,
        )?);
    }
    Ok(files)
}
