//! The steady states of the recommended design's curve (docs/reduce.md): its frequency response
//! drawn as branches, and the basin shares of its attractors against the frequency.
//!
//! `branches`: stable periodic branches solid, unstable ones dashed, the non-impacting family
//! dotted grey; folds (`SN`), branch points (`BP`), period doublings (`PD`), Neimark–Sacker
//! points (`NS`), grazing (`GR`) and where impacts begin or end (`NI`) marked where they were
//! located and named (names that would overlap stacked; a hover gives the multipliers); the amplitudes of the motions that are not periodic as
//! shaded bars at their frequencies; the linear system dashed black; the design peak marked.
//! `basin_shares`: at each frequency, the share of the census's starts that reached each kind of
//! attractor (by period, the non-impacting family and the motions that are not periodic).

use crate::orbits::attractors::SteadyKind;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, Hovers, Key, LABEL, Plot, SMALL, TITLE, err, minmax, pad, plot_builder, tick,
};

use crate::orbits::response::Response;
use crate::reduce::Summary;
use crate::reduce::harmonic::{Curve, HarmonicSummary};
use crate::report::text::fmt_num;
use crate::store::table::{Column, Table};

pub const SIZE: (u32, u32) = (1000, 640);
const LEGEND_X: i32 = 80;
/// Metres to centimetres.
const CM: f64 = 100.0;
/// Intervals of the fine grid the closed-form curves are drawn on.
const FINE: usize = 600;

const STABLE: RGBColor = RGBColor(31, 119, 180);
const UNSTABLE: RGBColor = RGBColor(214, 39, 40);
const FAMILY: RGBColor = RGBColor(120, 120, 120);
const CHAOS: RGBAColor = RGBAColor(255, 127, 14, 0.35);
const PEAK: RGBColor = RGBColor(0, 0, 0);

/// The curve's steady states and where its design peak is.
pub struct Steady<'a> {
    pub r: &'a Response,
    /// The design's curve (the recommended design's; along `F0`, the one-point curve of its
    /// force).
    pub curve: &'a Curve,
    pub title_at: String,
    pub along: Along<'a>,
}

/// What the steady states are followed along: the frequency ratio, or (a study at one
/// frequency that sweeps `F0`) the force amplitude over the one-point curves of a group that
/// differ only in `F0`, in increasing `F0`.
pub enum Along<'a> {
    Ratio,
    Force(Vec<&'a Curve>),
}

impl Steady<'_> {
    /// The abscissa of a branch row.
    fn x_branch(&self, b: &crate::orbits::response::BranchRow) -> f64 {
        match self.along {
            Along::Ratio => b.r,
            Along::Force(_) => b.F0,
        }
    }

    /// The abscissa of an attractor row.
    fn x_attractor(&self, a: &crate::orbits::attractors::AttractorRow) -> f64 {
        match self.along {
            Along::Ratio => a.run.r,
            Along::Force(_) => a.run.F0,
        }
    }

    /// The parameter's name in hover texts and titles, and the axis description.
    fn x_name(&self) -> (&'static str, &'static str) {
        match self.along {
            Along::Ratio => ("r", "frequency ratio r = omega / sqrt(K/M) (–)"),
            Along::Force(_) => ("F0", "force amplitude F0 (N)"),
        }
    }

    /// The swept values (their count sets the bar widths).
    fn n_values(&self) -> usize {
        match &self.along {
            Along::Ratio => self.curve.points.len(),
            Along::Force(cs) => cs.len(),
        }
    }

    /// The linear system in closed form on `FINE` intervals from `x0` to `x1`, `(x, amplitude
    /// in m)`: against `r` the resonance curve, against `F0` a line through the origin.
    fn linear_line(&self, x0: f64, x1: f64) -> Vec<(f64, f64)> {
        match self.along {
            Along::Ratio => self.curve.linear_line(x0, x1, FINE),
            Along::Force(_) => {
                let r = self.curve.points.first().map_or(f64::NAN, |p| p.r);
                (0..=FINE)
                    .map(|i| {
                        let f0 = x0 + (x1 - x0) * i as f64 / FINE as f64;
                        (f0, self.curve.system.linear_amplitude(f0, r))
                    })
                    .collect()
            }
        }
    }

    /// The design peaks to mark, `(x, peak in m, named)`: the curve's peak against `r`;
    /// against `F0`, the peak at each force of the group, the design's own named.
    fn peaks(&self) -> Vec<(f64, f64, bool)> {
        match &self.along {
            Along::Ratio => {
                let (peak, r) = self.curve.peak();
                vec![(r, peak, true)]
            }
            Along::Force(cs) => cs
                .iter()
                .map(|c| (c.f0, c.peak().0, c.design == self.curve.design))
                .collect(),
        }
    }

    /// Branch segments: `(branch, stability, points)` split where stability changes.
    fn segments(&self) -> Vec<(&'static str, Vec<(f64, f64)>)> {
        let mut out: Vec<(&'static str, Vec<(f64, f64)>)> = Vec::new();
        let mut last: Option<(u32, &'static str)> = None;
        for b in &self.r.branches {
            let key = (b.branch, b.stability);
            let p = (self.x_branch(b), b.amplitude * CM);
            match (last, out.last_mut()) {
                (Some(k), Some(seg)) if k == key => seg.1.push(p),
                (Some((br, _)), Some(seg)) if br == b.branch => {
                    // Stability changed along the branch: the new segment starts where the
                    // old one ended, so the curve stays joined.
                    let joint = seg.1.last().copied();
                    let mut pts = Vec::new();
                    pts.extend(joint);
                    pts.push(p);
                    out.push((b.stability, pts));
                }
                _ => out.push((b.stability, vec![p])),
            }
            last = Some(key);
        }
        out
    }

    fn y_max(&self) -> f64 {
        let (_, hi) = minmax(
            self.r
                .branches
                .iter()
                .map(|b| b.amplitude * CM)
                .chain(self.r.attractors.iter().map(|a| a.amplitude * CM))
                .chain({
                    let (x0, x1) = self.x_range();
                    self.linear_line(x0, x1).into_iter().map(|(_, a)| a * CM)
                }),
        );
        if hi.is_finite() && hi > 0.0 {
            hi * 1.08
        } else {
            1.0
        }
    }

    fn x_range(&self) -> (f64, f64) {
        let (x0, x1) = match &self.along {
            Along::Ratio => minmax(self.curve.points.iter().map(|p| p.r)),
            Along::Force(cs) => minmax(cs.iter().map(|c| c.f0)),
        };
        if x1 > x0 { (x0, x1) } else { pad(x0, x1, 0.5) }
    }
}

fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[(Key, String)],
) -> anyhow::Result<DrawingArea<DB, Shift>>
where
    DB::ErrorType: 'static,
{
    crate::report::charts::plumbing::legend_block(area, LEGEND_X, items)
}

/// The frequency response as branches; every branch point a hover target.
pub struct Branches<'a>(pub &'a Steady<'a>, pub Hovers);

impl Chart for Branches<'_> {
    fn hovers(&self) -> Option<&Hovers> {
        Some(&self.1)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let st = self.0;
        let (title, rest) = root.split_vertically(40);
        title
            .titled(
                &format!("Steady states against {}{}", st.x_name().0, st.title_at),
                TITLE,
            )
            .map_err(err)?;
        let items = vec![
            (Key::Line(STABLE), "stable periodic orbit".to_string()),
            (Key::Dashed(UNSTABLE), "unstable periodic orbit".to_string()),
            (Key::Dashed(FAMILY), "no impacts (neutral)".to_string()),
            (Key::Swatch(CHAOS), "not periodic (amplitude)".to_string()),
            (Key::Dashed(BLACK), "linear system".to_string()),
        ];
        let plot = legend(&rest, &items)?;
        let (x0, x1) = st.x_range();
        let mut chart = plot_builder(&plot, 48)
            .build_cartesian_2d(x0..x1, 0.0..st.y_max())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(st.x_name().1)
            .x_label_formatter(&tick)
            .y_desc("steady amplitude (cm)")
            .y_label_formatter(&|v: &f64| fmt_num(*v))
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        draw_curves(&mut chart, st, (x0, x1))?;
        draw_labels(&mut chart, st)?;
        hover_targets(&chart, st, &self.1);
        draw_peaks(&mut chart, st)?;
        Ok(())
    }
}

/// The motions that are not periodic (a bar from 0 to their amplitude), the linear system and
/// the branches over `x0..x1`.
fn draw_curves<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    st: &Steady,
    (x0, x1): (f64, f64),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    // Motions that are not periodic: a bar from 0 to the largest amplitude over the window.
    let dx = (x1 - x0) / (st.n_values().max(2) as f64) / 3.0;
    chart
        .draw_series(
            st.r.attractors
                .iter()
                .filter(|a| !a.kind.periodic() && a.amplitude.is_finite())
                .map(|a| {
                    let x = st.x_attractor(a);
                    Rectangle::new([(x - dx, 0.0), (x + dx, a.amplitude * CM)], CHAOS.filled())
                }),
        )
        .map_err(err)?;
    // The linear system in closed form on a fine grid (not a polygon through the swept
    // frequencies).
    let lin: Vec<(f64, f64)> = st
        .linear_line(x0, x1)
        .into_iter()
        .map(|(r, a)| (r, a * CM))
        .collect();
    chart
        .draw_series(DashedLineSeries::new(lin, 6, 4, BLACK.stroke_width(1)))
        .map_err(err)?;
    for (stability, pts) in st.segments() {
        match stability {
            "stable" => {
                chart
                    .draw_series(LineSeries::new(pts, STABLE.stroke_width(2)))
                    .map_err(err)?;
            }
            "unstable" => {
                chart
                    .draw_series(DashedLineSeries::new(pts, 5, 4, UNSTABLE.stroke_width(2)))
                    .map_err(err)?;
            }
            _ => {
                // The non-impacting family is the linear steady state: drawn in closed form
                // over the stretch where continuation found it.
                let (r0, r1) = minmax(pts.iter().map(|p| p.0));
                let fine: Vec<(f64, f64)> = st
                    .linear_line(r0, r1)
                    .into_iter()
                    .map(|(r, a)| (r, a * CM))
                    .collect();
                chart
                    .draw_series(DashedLineSeries::new(fine, 2, 3, FAMILY.stroke_width(2)))
                    .map_err(err)?;
            }
        }
    }
    Ok(())
}

/// A dot exactly at each labelled (located) point, its name beside it, names that would
/// overlap stacked upwards.
fn draw_labels<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    st: &Steady,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    // Labels: a dot exactly at each (located) point, its name beside it, names that would
    // overlap stacked upwards.
    let labelled: Vec<_> =
        st.r.branches
            .iter()
            .filter(|b| !b.label.is_empty())
            .collect();
    let at: Vec<(i32, i32)> = labelled
        .iter()
        .map(|b| chart.backend_coord(&(st.x_branch(b), b.amplitude * CM)))
        .collect();
    // The same label at the same spot (the two mirror halves of a pair, located each on
    // its own branch) is named once.
    let named: Vec<bool> = (0..labelled.len())
        .map(|i| {
            !(0..i).any(|j| {
                labelled[j].label == labelled[i].label
                    && (at[j].0 - at[i].0).abs() <= 4
                    && (at[j].1 - at[i].1).abs() <= 4
            })
        })
        .collect();
    let shown: Vec<(i32, i32)> = at
        .iter()
        .zip(&named)
        .filter(|p| *p.1)
        .map(|p| *p.0)
        .collect();
    let mut lifts = spread(&shown).into_iter();
    let lifts: Vec<Option<i32>> = named
        .iter()
        .map(|&n| if n { lifts.next() } else { None })
        .collect();
    chart
        .draw_series(labelled.iter().zip(&lifts).map(|(b, lift)| {
            let pos = (st.x_branch(b), b.amplitude * CM);
            let name = if lift.is_some() { b.label } else { "" };
            EmptyElement::at(pos)
                + Circle::new((0, 0), 4, BLACK.filled())
                + Text::new(
                    name.to_string(),
                    (5, -16 - lift.unwrap_or(0)),
                    SMALL.into_font(),
                )
        }))
        .map_err(err)?;
    Ok(())
}

/// Every branch point a hover target, the labelled ones last.
fn hover_targets<'a, DB: DrawingBackend + 'a>(chart: &Plot<'a, DB>, st: &Steady, hovers: &Hovers) {
    // The labelled points last, so that their targets lie on top of their neighbours'.
    let order =
        st.r.branches
            .iter()
            .filter(|b| b.label.is_empty())
            .chain(st.r.branches.iter().filter(|b| !b.label.is_empty()));
    for b in order {
        let at = chart.backend_coord(&(st.x_branch(b), b.amplitude * CM));
        let mut text = format!(
            "branch {}, period {}, {}\n{} = {}, amplitude {} cm",
            b.branch,
            b.period,
            b.stability,
            st.x_name().0,
            fmt_num(st.x_branch(b)),
            fmt_num(b.amplitude * CM)
        );
        if !b.label.is_empty() {
            text = format!(
                "{} ({}){}\n{text}\nmultipliers {}",
                b.label,
                label_name(b.label),
                if b.located { ", located" } else { "" },
                multipliers_text(&b.multipliers)
            );
        }
        hovers.point(at, if b.label.is_empty() { 3 } else { 5 }, text);
    }
}

/// The design peak (along F0, at every force; the design's own named).
fn draw_peaks<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    st: &Steady,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    // The design peak (along F0, at every force; the design's own named).
    for (x, peak, named) in st.peaks() {
        if !peak.is_finite() {
            continue;
        }
        // Three decimals (the chart's resolution), above and to the left of the cross: the
        // bifurcation labels crowd below and to the right of a peak on a fold.
        let name = if named {
            format!("design peak {:.3} cm", peak * CM)
        } else {
            String::new()
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((x, peak * CM))
                    + Cross::new((0, 0), 7, PEAK.stroke_width(3))
                    + Text::new(name, (-120, -22), SMALL.into_font()),
            ))
            .map_err(err)?;
    }
    Ok(())
}

/// Upward shifts (px) of the labels at pixel positions `at` so that no two names overlap: a
/// name within 22 px across and 14 px up or down of one already placed goes 15 px higher.
fn spread(at: &[(i32, i32)]) -> Vec<i32> {
    let mut placed: Vec<(i32, i32)> = Vec::new();
    let mut out = Vec::with_capacity(at.len());
    for &(x, y) in at {
        let mut lift = 0;
        while placed
            .iter()
            .any(|&(px, py)| (px - x).abs() < 22 && (py - (y - lift)).abs() < 14)
        {
            lift += 15;
        }
        placed.push((x, y - lift));
        out.push(lift);
    }
    out
}

/// A label's meaning, for hover texts.
fn label_name(label: &str) -> &'static str {
    match label {
        "SN" => "fold",
        "BP" => "branch point",
        "PD" => "period doubling",
        "NS" => "Neimark–Sacker",
        "GR" => "grazing",
        "NI" => "impacts begin or end",
        _ => "",
    }
}

/// The Floquet multipliers as `a ± bi` (the pairs once), by decreasing modulus; none (`NaN`)
/// at a located vanishing impact.
fn multipliers_text(mu: &[(f64, f64); 4]) -> String {
    let mut parts = Vec::new();
    for &(re, im) in mu {
        if !re.is_finite() || im < 0.0 {
            continue;
        }
        parts.push(if im > 0.0 {
            format!("{:.6} ± {:.6}i", re, im)
        } else {
            format!("{re:.6}")
        });
    }
    if parts.is_empty() {
        // A grazing located where an impact's speed vanishes: they grow without bound there.
        return "unbounded (an impact with zero approach speed)".to_string();
    }
    parts.join(", ")
}

/// Basin shares against the frequency (or `F0`); every bar a hover target.
pub struct Basins<'a>(pub &'a Steady<'a>, pub Hovers);

/// The attractor classes of the basin chart, and their colours.
fn class_of(kind: SteadyKind, period: u32, impacts: f64) -> (usize, &'static str) {
    if !kind.periodic() {
        (0, "not periodic")
    } else if impacts == 0.0 {
        (1, "no impacts")
    } else {
        match period {
            1 => (2, "period 1"),
            2 => (3, "period 2"),
            3 => (4, "period 3"),
            _ => (5, "period 4 to 8"),
        }
    }
}

const CLASS_COLOURS: [RGBColor; 6] = [
    RGBColor(255, 127, 14),
    RGBColor(120, 120, 120),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

impl Chart for Basins<'_> {
    fn hovers(&self) -> Option<&Hovers> {
        Some(&self.1)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let st = self.0;
        let (title, rest) = root.split_vertically(40);
        title
            .titled(
                &format!("Basin shares of the steady states{}", st.title_at),
                TITLE,
            )
            .map_err(err)?;
        let names = [
            "not periodic",
            "no impacts",
            "period 1",
            "period 2",
            "period 3",
            "period 4 to 8",
        ];
        let items: Vec<(Key, String)> = names
            .iter()
            .enumerate()
            .map(|(i, n)| (Key::Swatch(CLASS_COLOURS[i].to_rgba()), n.to_string()))
            .collect();
        let plot = legend(&rest, &items)?;
        let (x0, x1) = st.x_range();
        let n = st.n_values().max(2) as f64;
        let w = (x1 - x0) / n * 0.4;
        let mut chart = plot_builder(&plot, 48)
            .build_cartesian_2d(x0 - w..x1 + w, 0.0..1.0)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(st.x_name().1)
            .y_desc("share of the starts")
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        // Stacked bars: per frequency, the classes in order.
        let mut bars = Vec::new();
        let mut i = 0;
        let att = &st.r.attractors;
        while i < att.len() {
            let point = att[i].run.point;
            let mut shares = [0.0; 6];
            let r = st.x_attractor(&att[i]);
            while i < att.len() && att[i].run.point == point {
                let (c, _) = class_of(att[i].kind, att[i].period, att[i].impacts_per_period);
                shares[c] += att[i].basin_share;
                i += 1;
            }
            let mut y = 0.0;
            let mut text = format!("{} = {}", st.x_name().0, fmt_num(r));
            for (c, sh) in shares.iter().enumerate() {
                if *sh > 0.0 {
                    bars.push(Rectangle::new(
                        [(r - w, y), (r + w, y + sh)],
                        CLASS_COLOURS[c].filled(),
                    ));
                    y += sh;
                    text.push_str(&format!("\n{}: {} %", names[c], fmt_num(100.0 * sh)));
                }
            }
            self.1.area(
                chart.backend_coord(&(r - w, 0.0)),
                chart.backend_coord(&(r + w, y)),
                text,
            );
        }
        chart.draw_series(bars).map_err(err)?;
        Ok(())
    }
}

/// Draws `branches`, `basin_shares` and `bifurcation` (from `samples`, the design's section
/// samples) for `design` into `dir`; returns the files. `r` holds the design's steady states:
/// along the frequency its own; along `F0` (a study without a frequency axis) those of the
/// group of forces it belongs to, drawn against `F0`.
pub fn charts(
    s: &Summary,
    f: &HarmonicSummary,
    r: &Response,
    design: u64,
    samples: &[crate::reduce::harmonic::steady::SectionSample],
    dir: &std::path::Path,
) -> anyhow::Result<Vec<std::path::PathBuf>> {
    let Some(curve) = f.curve(design) else {
        return Ok(Vec::new());
    };
    let along = if f.frequency.is_some() {
        Along::Ratio
    } else {
        let key = crate::reduce::harmonic::steady::force_group(curve);
        let mut cs: Vec<&Curve> = f
            .curves
            .iter()
            .filter(|c| crate::reduce::harmonic::steady::force_group(c) == key)
            .collect();
        cs.sort_by(|a, b| a.f0.total_cmp(&b.f0));
        Along::Force(cs)
    };
    let g = &s.grid;
    let at = (0..g.n_axes())
        .filter(|&a| matches!(along, Along::Ratio) || g.key(a) != "F0")
        .map(|a| crate::report::text::axis_value(g.key(a), g.value(design, a)))
        .collect::<Vec<_>>()
        .join(", ");
    let st = Steady {
        r,
        curve,
        title_at: if at.is_empty() {
            String::new()
        } else {
            format!(" at {at}")
        },
        along,
    };
    let mut files = crate::report::charts::plumbing::render(
        dir,
        "branches",
        SIZE,
        &Branches(&st, Hovers::default()),
        // `branches.csv` is the branches table (every design), written before the charts.
        &crate::report::charts::plumbing::Data::Written,
    )?;
    files.extend(crate::report::charts::plumbing::render(
        dir,
        "basin_shares",
        SIZE,
        &Basins(&st, Hovers::default()),
        &crate::report::charts::plumbing::Data::Table(basin_data(r)),
    )?);
    if !samples.is_empty() {
        let b = super::bifurcation::Bifurcation {
            samples,
            response: r,
            title_at: st.title_at.clone(),
        };
        files.extend(crate::report::charts::plumbing::render(
            dir,
            "bifurcation",
            super::bifurcation::SIZE,
            &b,
            &crate::report::charts::plumbing::Data::Table(b.data()),
        )?);
    }
    Ok(files)
}

fn basin_data(r: &Response) -> Table {
    let a = &r.attractors;
    let mut t = Table::default();
    t.push(
        "point",
        Column::U64(a.iter().map(|x| Some(x.run.point)).collect()),
    );
    t.push("r", Column::F64(a.iter().map(|x| x.run.r).collect()));
    t.push("F0", Column::F64(a.iter().map(|x| x.run.F0).collect()));
    t.push(
        "kind",
        Column::Str(a.iter().map(|x| x.kind.name().to_string()).collect()),
    );
    t.push(
        "period",
        Column::U64(a.iter().map(|x| Some(u64::from(x.period))).collect()),
    );
    t.push(
        "amplitude",
        Column::F64(a.iter().map(|x| x.amplitude).collect()),
    );
    t.push(
        "basin_share",
        Column::F64(a.iter().map(|x| x.basin_share).collect()),
    );
    t
}
