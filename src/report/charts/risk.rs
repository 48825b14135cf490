//! The design charts of a load study (a random or record study with a threshold), in place of
//! the laboratory's design chart (reliability R against a strength, the safety factor) and
//! perfectibility map: the number the designs are ranked by, on a log scale, with its 95 %
//! interval.
//!
//! The number is the annual rate of failure `lambda_f` (per year, with its bootstrap interval)
//! where the study gives a hazard and capacities, else `p_f` at the design intensity (subset
//! simulation's where it ranked the design, else Monte Carlo's with its Clopper–Pearson
//! interval). A `p_f` of 0 (no run passed) is drawn as its interval's upper end, a bound.
//!
//! * `risk_profile_<axis>`: along each swept design axis through the best design, `log10` of
//!   the number with its interval as whiskers, and the structure without a damper (`m = 0`) as
//!   a dashed line;
//! * `risk_map_<a>_<b>`: over each pair of swept design axes through the best design, the cells
//!   coloured by `log10` of the number (the lowest brightest), each labelled with its value, the
//!   best design ringed.
//!
//! Each with its data as CSV (`point`, the axes, `value`, `lo`, `hi`, `bound`).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::common::interval::{Value, colour_span, log_span, short};
use super::plumbing::{
    BLUE, Chart, Data, GREY, LEGEND_SHARE, Plot, SMALL, Scale, TITLE, cell_edges, clear_corner,
    colour_bar, err, heat, map_chart, minmax, render, series_legend, xy_chart,
};
use crate::reduce::Summary;
use crate::reduce::random::RandomSummary;
use crate::report::text::{axis_desc, axis_value};
use crate::store::table::{Column, Table, axis_column};

/// What the charts draw: the number's name and unit, and each design's value.
pub(crate) struct Numbers {
    /// `λ_f (per year)` or `p_f at Sa = 0.2 g`.
    pub label: String,
    /// For titles: `Annual rate of failure λ_f`.
    pub what: String,
    /// For the colour bar: `log10 λ_f`.
    pub bar: String,
    values: Vec<(u64, Value)>,
}

/// Each design's number (module doc).
fn numbers(s: &Summary, rs: &RandomSummary) -> Numbers {
    if rs.hazard.is_some() && !rs.risk.is_empty() {
        let values = rs
            .risk
            .iter()
            .filter_map(|d| {
                let r = d.risk.as_ref()?;
                let (v, lo, hi) = r.lambda_f;
                (v > 0.0).then_some((
                    d.design,
                    Value {
                        v,
                        lo,
                        hi,
                        bound: false,
                    },
                ))
            })
            .collect();
        return Numbers {
            label: "log10 λ_f (failures per year)".into(),
            what: "Annual rate of failure λ_f".into(),
            bar: "log10 λ_f per year".into(),
            values,
        };
    }
    let lens: Vec<usize> = (0..s.grid.n_axes()).map(|a| s.grid.n(a)).collect();
    let at = rs.intensity.as_ref().map_or(String::new(), |i| {
        format!(" at {}", axis_value(&i.key, i.values[i.design]))
    });
    let values = s
        .points
        .iter()
        .filter_map(|d| {
            let (v, lo, hi) = rs.design_pf(d.point, &lens)?;
            // No run passed: the interval's upper end, a bound.
            let value = if v > 0.0 {
                Value {
                    v,
                    lo,
                    hi,
                    bound: false,
                }
            } else {
                Value {
                    v: hi,
                    lo: f64::NAN,
                    hi,
                    bound: true,
                }
            };
            (value.v > 0.0).then_some((d.point, value))
        })
        .collect();
    Numbers {
        label: format!("log10 p_f{at}"),
        what: format!("First-passage probability p_f{at}"),
        bar: "log10 p_f".into(),
        values,
    }
}

impl Numbers {
    /// Design `design`'s number, if it has one.
    pub fn of(&self, design: u64) -> Option<Value> {
        self.values
            .iter()
            .find(|(d, _)| *d == design)
            .map(|(_, v)| *v)
    }

    /// The chart's data: each listed design's axes and value.
    fn table(&self, s: &Summary, designs: &[u64]) -> Table {
        let g = &s.grid;
        let rows: Vec<(u64, Value)> = designs
            .iter()
            .filter_map(|&d| self.of(d).map(|v| (d, v)))
            .collect();
        let mut t = Table::default();
        t.push(
            "point",
            Column::U64(rows.iter().map(|r| Some(r.0)).collect()),
        );
        for a in 0..g.n_axes() {
            t.push(
                axis_column(g.key(a)),
                Column::F64(rows.iter().map(|r| g.value(r.0, a)).collect()),
            );
        }
        t.push("value", Column::F64(rows.iter().map(|r| r.1.v).collect()));
        t.push("lo", Column::F64(rows.iter().map(|r| r.1.lo).collect()));
        t.push("hi", Column::F64(rows.iter().map(|r| r.1.hi).collect()));
        t.push(
            "bound",
            Column::Bool(rows.iter().map(|r| r.1.bound).collect()),
        );
        t
    }
}

/// The risk charts of a load study: its numbers, the best design they go through, the
/// structure without a damper's number and the swept design axes. The plotters charts here and
/// the page's drawn ones ([`crate::report::html::random`]) are made from the same one.
pub(crate) struct RiskCharts<'a> {
    pub s: &'a Summary,
    pub n: Numbers,
    /// The best design: every profile and map is a slice through it.
    pub anchor: u64,
    /// The number of the structure without a damper (`m = 0`), drawn as a line.
    pub bare: Option<Value>,
    swept: Vec<usize>,
}

impl<'a> RiskCharts<'a> {
    /// None without a threshold, a best design or a design with a number.
    pub fn of(s: &'a Summary, rs: &RandomSummary) -> Option<RiskCharts<'a>> {
        let (Some(_), Some(anchor)) = (rs.threshold, s.anchor()) else {
            return None;
        };
        let n = numbers(s, rs);
        if n.values.is_empty() {
            return None;
        }
        let g = &s.grid;
        let bare = s
            .points
            .iter()
            .find(|p| g.without_damper(p.point))
            .and_then(|p| n.of(p.point));
        let swept = (0..g.n_axes()).filter(|&a| g.n(a) >= 2).collect();
        Some(RiskCharts {
            s,
            n,
            anchor,
            bare,
            swept,
        })
    }

    /// The profiles: each swept axis, its chart's file stem and the designs along it through
    /// the best design.
    pub fn profiles(&self) -> Vec<(usize, String, Vec<u64>)> {
        let g = &self.s.grid;
        self.swept
            .iter()
            .map(|&a| {
                (
                    a,
                    format!("risk_profile_{}", axis_column(g.key(a))),
                    g.slice(self.anchor, &[a]),
                )
            })
            .collect()
    }

    /// The maps: each pair of swept axes `(a, b)` (`a` up, `b` across), its chart's file stem
    /// and the designs of the slice through the best design.
    pub fn maps(&self) -> Vec<((usize, usize), String, Vec<u64>)> {
        let g = &self.s.grid;
        let mut out = Vec::new();
        for (i, &a) in self.swept.iter().enumerate() {
            for &b in &self.swept[i + 1..] {
                out.push((
                    (a, b),
                    format!(
                        "risk_map_{}_{}",
                        axis_column(g.key(a)),
                        axis_column(g.key(b))
                    ),
                    g.slice(self.anchor, &[a, b]),
                ));
            }
        }
        out
    }
}

/// The risk profiles and maps of a load study (module doc), through the best design.
pub fn charts(s: &Summary, rs: &RandomSummary, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let Some(rc) = RiskCharts::of(s, rs) else {
        return Ok(files);
    };
    let n = &rc.n;
    for (axis, stem, designs) in rc.profiles() {
        let chart = ProfileChart {
            s,
            n,
            axis,
            designs: designs.clone(),
            through: rc.anchor,
            bare: rc.bare,
        };
        files.extend(render(
            dir,
            &stem,
            (1000, 560),
            &chart,
            &Data::Table(n.table(s, &designs)),
        )?);
    }
    for ((a, b), stem, designs) in rc.maps() {
        let chart = MapChart {
            s,
            n,
            a,
            b,
            designs: designs.clone(),
            through: rc.anchor,
        };
        files.extend(render(
            dir,
            &stem,
            (1000, 700),
            &chart,
            &Data::Table(n.table(s, &designs)),
        )?);
    }
    Ok(files)
}

/// The other axes' values of a slice through `through`: `m = 0.2 kg`.
pub(crate) fn slice_text(s: &Summary, through: u64, shown: &[usize]) -> String {
    let g = &s.grid;
    (0..g.n_axes())
        .filter(|k| !shown.contains(k))
        .map(|k| axis_value(g.key(k), g.value(through, k)))
        .collect::<Vec<_>>()
        .join(", ")
}

struct ProfileChart<'a> {
    s: &'a Summary,
    n: &'a Numbers,
    axis: usize,
    designs: Vec<u64>,
    through: u64,
    bare: Option<Value>,
}

/// Where a profile chart's points go: the swept values and their scale, the drawn designs'
/// `(x, value)` on that scale, the axes' ranges (`log10` of the number upward) and the
/// legend's corner.
struct ProfileFrame {
    xs: Vec<f64>,
    scale: Scale,
    pts: Vec<(f64, Value)>,
    x_range: (f64, f64),
    y_range: (f64, f64),
    corner: SeriesLabelPosition,
}

impl ProfileChart<'_> {
    /// The frame: every design's value and interval on the axes, padded, and the legend in a
    /// corner clear of the whiskers and of the bare structure's line; where none is, room above
    /// everything for it.
    fn frame(&self) -> ProfileFrame {
        let g = &self.s.grid;
        let xs: Vec<f64> = self
            .designs
            .iter()
            .map(|&d| g.value(d, self.axis))
            .collect();
        // The axis on the scale its values are evenly spaced on (`m = 0` of the bare structure
        // keeps it linear).
        let scale = Scale::of(&xs);
        let pts: Vec<(f64, Value)> = self
            .designs
            .iter()
            .filter(|&&d| !g.without_damper(d))
            .filter_map(|&d| {
                let x = scale.to(g.value(d, self.axis));
                self.n.of(d).map(|v| (x, v))
            })
            .collect();
        let (x0, x1) = minmax(xs.iter().map(|&x| scale.to(x)));
        let step = if xs.len() > 1 {
            (x1 - x0) / (xs.len() - 1) as f64
        } else {
            1.0
        };
        let (y0, y1) = log_span(&pts, self.bare);
        let x_range = (x0 - 0.5 * step, x1 + 0.5 * step);
        let spans: Vec<(f64, f64, f64)> = pts
            .iter()
            .map(|&(x, v)| {
                let lo = if v.lo > 0.0 { v.lo.log10() } else { y0 };
                (x, lo, v.hi.log10().max(v.log()))
            })
            .collect();
        let levels: Vec<f64> = self.bare.iter().map(|b| b.log()).collect();
        let (corner, y1) = match clear_corner(&spans, &levels, x_range, (y0, y1)) {
            Some(corner) => (corner, y1),
            None => (
                SeriesLabelPosition::UpperRight,
                y0 + (y1 - y0) / (1.0 - LEGEND_SHARE.1),
            ),
        };
        ProfileFrame {
            xs,
            scale,
            pts,
            x_range,
            y_range: (y0, y1),
            corner,
        }
    }

    /// The chart's title: the number along the axis, and the slice through the best design.
    fn title(&self) -> String {
        let slice = slice_text(self.s, self.through, &[self.axis]);
        format!(
            "{} along {}{}",
            self.n.what,
            self.s.grid.key(self.axis),
            if slice.is_empty() {
                String::new()
            } else {
                format!(" at {slice}")
            }
        )
    }
}

/// The structure without a damper as a dashed line across the chart, at its number `b`.
fn draw_bare<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    b: Value,
    x_range: (f64, f64),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let y = b.log();
    chart
        .draw_series(DashedLineSeries::new(
            [(x_range.0, y), (x_range.1, y)],
            8,
            5,
            GREY.stroke_width(2),
        ))
        .map_err(err)?
        .label(format!(
            "no damper: {}{}",
            if b.bound { "< " } else { "" },
            short(b.v)
        ))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], GREY.stroke_width(2)));
    Ok(())
}

/// The designs' intervals as whiskers (from the axis' foot `y0` where the lower end is 0),
/// their estimates as dots joined by a line, and the bounds of designs where no run passed as
/// downward arrows.
fn draw_designs<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    pts: &[(f64, Value)],
    y0: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let whisker = |&(x, v): &(f64, Value)| {
        let lo = if v.lo > 0.0 { v.lo.log10() } else { y0 };
        PathElement::new(vec![(x, lo), (x, v.hi.log10())], BLUE.stroke_width(2))
    };
    chart
        .draw_series(pts.iter().map(whisker))
        .map_err(err)?
        .label("95 % interval")
        .legend(|(x, y)| PathElement::new(vec![(x + 9, y - 6), (x + 9, y + 6)], BLUE));
    chart
        .draw_series(LineSeries::new(
            pts.iter()
                .filter(|p| !p.1.bound)
                .map(|(x, v)| (*x, v.log())),
            BLUE.mix(0.6).stroke_width(1),
        ))
        .map_err(err)?;
    chart
        .draw_series(
            pts.iter()
                .filter(|p| !p.1.bound)
                .map(|(x, v)| Circle::new((*x, v.log()), 5, BLUE.filled())),
        )
        .map_err(err)?
        .label("estimate")
        .legend(|(x, y)| Circle::new((x + 9, y), 5, BLUE.filled()));
    if pts.iter().any(|p| p.1.bound) {
        chart
            .draw_series(
                pts.iter()
                    .filter(|p| p.1.bound)
                    .map(|(x, v)| EmptyElement::at((*x, v.log())) + down()),
            )
            .map_err(err)?
            .label("no run passed: below this bound")
            .legend(|(x, y)| EmptyElement::at((x + 9, y)) + down());
    }
    Ok(())
}

impl Chart for ProfileChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let f = self.frame();
        let key = self.s.grid.key(self.axis);
        let mut chart = xy_chart(
            root,
            (&self.title(), TITLE),
            (f.x_range.0..f.x_range.1, f.y_range.0..f.y_range.1),
            (&axis_desc(key), &self.n.label),
            (&f.xs, f.scale),
        )?;
        if let Some(b) = self.bare {
            draw_bare(&mut chart, b, f.x_range)?;
        }
        draw_designs(&mut chart, &f.pts, f.y_range.0)?;
        series_legend(&mut chart, f.corner)?;
        Ok(())
    }
}

/// A downward triangle (an upper bound: the value lies below), in pixels about its point.
fn down() -> Polygon<(i32, i32)> {
    Polygon::new(vec![(-7, -6), (7, -6), (0, 7)], RED.filled())
}

struct MapChart<'a> {
    s: &'a Summary,
    n: &'a Numbers,
    a: usize,
    b: usize,
    designs: Vec<u64>,
    through: u64,
}

impl MapChart<'_> {
    /// The lines above the map: what the colours span where they were widened
    /// ([`colour_span`]), the slice, the ring and the bounds.
    fn notes<DB: DrawingBackend>(
        &self,
        sub: &DrawingArea<DB, Shift>,
        widened: bool,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        if widened {
            sub.draw(&Text::new(
                "the colours span the median 95 % interval: the values differ by less than it",
                (12, 20),
                SMALL.into_font().color(&BLACK),
            ))
            .map_err(err)?;
        }
        let slice = slice_text(self.s, self.through, &[self.a, self.b]);
        sub.draw(&Text::new(
            format!(
                "{}ringed: the best design; a value with < is an upper bound (no run passed)",
                if slice.is_empty() {
                    String::new()
                } else {
                    format!("slice at {slice}; ")
                }
            ),
            (12, 2),
            SMALL.into_font().color(&BLACK),
        ))
        .map_err(err)?;
        Ok(())
    }

    /// The cells, coloured by `log10` of their number over the span `(l0, l1)` (the lowest
    /// brightest; grey without one), each labelled with its value. `rect`: a design's cell.
    fn draw_cells<'a, DB: DrawingBackend + 'a>(
        &self,
        chart: &mut Plot<'a, DB>,
        cells: &[(u64, Option<Value>)],
        rect: impl Fn(u64) -> [(f64, f64); 2],
        (l0, l1): (f64, f64),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        let g = &self.s.grid;
        let shade = |v: &Value| heat(1.0 - (v.log() - l0) / (l1 - l0).max(1e-12));
        chart
            .draw_series(cells.iter().map(|(d, v)| {
                let color = v.as_ref().map_or(RGBColor(200, 200, 200), shade);
                Rectangle::new(rect(*d), color.filled())
            }))
            .map_err(err)?;
        let font = |v: &Value| {
            let bright = 1.0 - (v.log() - l0) / (l1 - l0).max(1e-12) > 0.55;
            ("sans-serif", 15)
                .into_font()
                .color(if bright { &BLACK } else { &WHITE })
                .pos(Pos::new(HPos::Center, VPos::Center))
        };
        chart
            .draw_series(cells.iter().filter_map(|(d, v)| {
                let v = v.as_ref()?;
                let at = (g.value(*d, self.b), g.value(*d, self.a));
                let text = if v.bound {
                    format!("< {}", short(v.v))
                } else {
                    short(v.v)
                };
                Some(Text::new(text, at, font(v)))
            }))
            .map_err(err)?;
        Ok(())
    }
}

/// A ring just inside the cell `[(x0, y0), (x1, y1)]` (the best design's), white under black.
fn draw_ring<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    [(x0, y0), (x1, y1)]: [(f64, f64); 2],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let (w, h) = ((x1 - x0) * 0.06, (y1 - y0) * 0.06);
    let ring = [
        (x0 + w, y0 + h),
        (x1 - w, y0 + h),
        (x1 - w, y1 - h),
        (x0 + w, y1 - h),
        (x0 + w, y0 + h),
    ];
    chart
        .draw_series([
            PathElement::new(ring.to_vec(), WHITE.stroke_width(4)),
            PathElement::new(ring.to_vec(), BLACK.stroke_width(2)),
        ])
        .map_err(err)?;
    Ok(())
}

impl Chart for MapChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let g = &self.s.grid;
        let (va, vb) = (&g.axes[self.a].1, &g.axes[self.b].1);
        let (ea, eb) = (cell_edges(va), cell_edges(vb));
        let title = format!(
            "{} over {} and {}",
            self.n.what,
            g.key(self.a),
            g.key(self.b)
        );
        let cells: Vec<(u64, Option<Value>)> =
            self.designs.iter().map(|&d| (d, self.n.of(d))).collect();
        let (l0, l1) = cells
            .iter()
            .filter_map(|c| c.1.map(|v| v.log()))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            });
        let (l0, l1, widened) = colour_span(l0, l1, &cells);
        let root = root.titled(&title, TITLE).map_err(err)?;
        let (sub, rest) = root.split_vertically(if widened { 44 } else { 26 });
        self.notes(&sub, widened)?;
        let (area, legend) = rest.split_horizontally(rest.dim_in_pixel().0 as i32 - 190);
        let mut chart = map_chart(
            &area,
            (&eb, &ea),
            (vb, va),
            (&axis_desc(g.key(self.b)), &axis_desc(g.key(self.a))),
        )?;
        let rect = |d: u64| {
            let (ia, ib) = (g.index(d, self.a), g.index(d, self.b));
            [(eb[ib], ea[ia]), (eb[ib + 1], ea[ia + 1])]
        };
        self.draw_cells(&mut chart, &cells, rect, (l0, l1))?;
        draw_ring(&mut chart, rect(self.through))?;
        colour_bar(
            &legend.margin(50, 50, 6, 0),
            &self.n.bar,
            &format!("{l0:.2}"),
            &format!("{l1:.2}"),
        )
    }
}
