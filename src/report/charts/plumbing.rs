//! What every chart shares: the embedded font, rendering to SVG and PNG with the chart's data
//! beside it as CSV, colours, axis labels, number formatting, legend rows, and the profile of
//! the summary along one axis.

use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{Context, anyhow};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::reduce::{Class, Jump, PointStats, Summary};
use crate::report::text::{axis_value, fmt_num};
use crate::store::table::Table;

static FONT: &[u8] = include_bytes!("../../../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font for every style plotters may ask for.
pub fn register_fonts() {
    REGISTER.call_once(|| {
        for style in [
            FontStyle::Normal,
            FontStyle::Bold,
            FontStyle::Italic,
            FontStyle::Oblique,
        ] {
            // The font is embedded and known to parse; a failure would only lose PNG text.
            let _ = plotters::style::register_font("sans-serif", style, FONT);
        }
    });
}

pub fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing: {e:?}")
}

/// A chart that can draw itself on any backend.
pub trait Chart {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static;

    /// Where the chart records its hover targets while it draws ([`render`] puts them into the
    /// SVG); `None` for a chart without.
    fn hovers(&self) -> Option<&Hovers> {
        None
    }
}

/// A hover target of a chart: a box in the SVG's pixels and what hovering it says.
#[derive(Clone, Debug, PartialEq)]
pub struct Hover {
    pub x0: i32,
    pub y0: i32,
    pub x1: i32,
    pub y1: i32,
    pub text: String,
}

/// The hover targets a chart's draw recorded (a chart holds one, [`Chart::hovers`]).
#[derive(Debug, Default)]
pub struct Hovers(std::cell::RefCell<Vec<Hover>>);

impl Hovers {
    /// A target `half` pixels around the point `(x, y)`.
    pub fn point(&self, (x, y): (i32, i32), half: i32, text: String) {
        self.0.borrow_mut().push(Hover {
            x0: x - half,
            y0: y - half,
            x1: x + half,
            y1: y + half,
            text,
        });
    }

    /// A target over the box between two corners.
    pub fn area(&self, a: (i32, i32), b: (i32, i32), text: String) {
        self.0.borrow_mut().push(Hover {
            x0: a.0.min(b.0),
            y0: a.1.min(b.1),
            x1: a.0.max(b.0),
            y1: a.1.max(b.1),
            text,
        });
    }

    fn take(&self) -> Vec<Hover> {
        std::mem::take(&mut *self.0.borrow_mut())
    }
}

/// Escapes text for XML content.
fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Adds `hovers` to the SVG file at `path`: each an invisible box (`data-hover`) with its text
/// as `<title>`, above everything drawn, so a viewer shows the text on hovering it (and
/// `report.html` beside the pointer at once).
fn add_hovers(path: &Path, hovers: &[Hover]) -> anyhow::Result<()> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let Some(end) = text.rfind("</svg>") else {
        return Ok(());
    };
    let mut layer = String::from("<g class=\"hovers\">\n");
    for h in hovers {
        layer.push_str(&format!(
            "<rect data-hover=\"\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#000\" fill-opacity=\"0\"><title>{}</title></rect>\n",
            h.x0,
            h.y0,
            (h.x1 - h.x0).max(1),
            (h.y1 - h.y0).max(1),
            xml_escape(&h.text)
        ));
    }
    layer.push_str("</g>\n");
    let out = format!("{}{layer}{}", &text[..end], &text[end..]);
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

/// A chart's data: the summary rows of the points it draws with the columns it draws (after
/// `point` and the axis columns), or a table of its own.
pub enum Data<'a> {
    Rows(&'a Summary, &'a [&'a PointStats], &'a [&'a str]),
    Table(Table),
    /// The chart draws from a table `reduce` has already written under the chart's name
    /// (`<stem>.csv`, every design's rows; the chart shows one design's): no file is written.
    Written,
}

impl Data<'_> {
    /// Writes the data as CSV, a batch of rows at a time.
    fn write(&self, path: &Path) -> anyhow::Result<()> {
        use crate::reduce::common::tables::summary_rows;
        use crate::store::summary::write_csv_in_batches;
        use crate::store::table::axis_column;
        match self {
            Data::Rows(s, points, columns) => {
                let mut keep: Vec<String> = vec!["point".into()];
                keep.extend((0..s.grid.n_axes()).map(|a| axis_column(s.grid.key(a))));
                keep.extend(columns.iter().map(|c| c.to_string()));
                write_csv_in_batches(path, points.len(), |r| {
                    summary_rows(s, &points[r]).select(&keep)
                })
            }
            Data::Table(t) => write_csv_in_batches(path, t.n_rows(), |r| t.rows(r)),
            Data::Written => Ok(()),
        }
    }
}

/// Writes `<dir>/<stem>.svg`, `<dir>/<stem>.png` and the chart's data `<dir>/<stem>.csv`;
/// returns the three paths (two with [`Data::Written`], whose table is already there).
pub fn render<C: Chart>(
    dir: &Path,
    stem: &str,
    size: (u32, u32),
    chart: &C,
    data: &Data,
) -> anyhow::Result<Vec<PathBuf>> {
    register_fonts();
    let svg = dir.join(format!("{stem}.svg"));
    let png = dir.join(format!("{stem}.png"));
    let csv = dir.join(format!("{stem}.csv"));
    {
        let root = SVGBackend::new(&svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        if let Some(h) = chart.hovers() {
            h.take();
        }
        chart
            .draw(&root)
            .with_context(|| format!("drawing {}", svg.display()))?;
        root.present().map_err(err)?;
    }
    if let Some(h) = chart.hovers() {
        let list = h.take();
        if !list.is_empty() {
            add_hovers(&svg, &list)?;
        }
    }
    {
        let root = BitMapBackend::new(&png, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        chart
            .draw(&root)
            .with_context(|| format!("drawing {}", png.display()))?;
        root.present().map_err(err)?;
        if let Some(h) = chart.hovers() {
            h.take();
        }
    }
    if matches!(data, Data::Written) {
        return Ok(vec![svg, png]);
    }
    data.write(&csv)?;
    Ok(vec![svg, png, csv])
}

pub const TITLE: (&str, u32) = ("sans-serif", 22);
pub const LABEL: (&str, u32) = ("sans-serif", 18);
pub const SMALL: (&str, u32) = ("sans-serif", 15);

/// Above this many design points, charts draw lines and bands instead of markers and boxes,
/// and mark only the strongest jumps: a chart stays readable and an SVG stays small.
pub const MANY: usize = 300;
/// Jumps drawn at most.
pub const MAX_JUMP_LINES: usize = 30;

pub const BLUE: RGBColor = RGBColor(31, 119, 180);
pub const GREEN: RGBColor = RGBColor(44, 160, 44);
pub const RED_LINE: RGBColor = RGBColor(214, 39, 40);
/// The colours of the designs a fragility chart draws, in order (the structure without damper
/// is [`GREY`]).
pub const DESIGN_COLORS: [RGBColor; 5] = [
    BLUE,
    RED_LINE,
    GREEN,
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
];
pub const GREY: RGBColor = RGBColor(60, 60, 60);

/// The colour of a class.
pub fn class_color(c: Class) -> RGBColor {
    match c {
        Class::StrongReliable => RGBColor(166, 217, 160),
        Class::AroundJump => RGBColor(244, 165, 130),
        Class::WeakReliable => RGBColor(171, 203, 232),
        Class::StrongNotShown => RGBColor(253, 219, 130),
        Class::WeakNotShown => RGBColor(215, 190, 230),
        Class::NoData => RGBColor(200, 200, 200),
        Class::StrongNotComputed => RGBColor(141, 211, 199),
        Class::WeakNotComputed => RGBColor(222, 222, 170),
    }
}

/// Colours for declared zones, cycled.
const DECLARED: [RGBColor; 5] = [
    RGBColor(166, 217, 160),
    RGBColor(244, 165, 130),
    RGBColor(171, 203, 232),
    RGBColor(253, 219, 130),
    RGBColor(215, 190, 230),
];

/// The colour of zone `z` (an index into `s.zones`): declared zones cycle through a palette by
/// their index, automatic ones are coloured by class; grey outside every zone.
pub fn zone_color(s: &Summary, z: u32) -> RGBColor {
    match s.zones.get(z as usize) {
        Some(zone) => match zone.class {
            Some(c) => class_color(c),
            None => DECLARED[z as usize % DECLARED.len()],
        },
        None => RGBColor(230, 230, 230),
    }
}

/// `lo..hi` widened by `frac` of the span on both sides (`0..1` when not finite).
pub fn pad(lo: f64, hi: f64, frac: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = (hi - lo).abs().max(1e-12 * hi.abs().max(1.0));
    (lo - frac * span, hi + frac * span)
}

/// The smallest and largest finite value.
pub fn minmax(v: impl IntoIterator<Item = f64>) -> (f64, f64) {
    v.into_iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        })
}

/// `lo..hi` widened a little below and by room for the zone names above; `min_span` keeps a
/// flat series from collapsing the axis.
pub fn with_headroom(lo: f64, hi: f64, min_span: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = (hi - lo).max(min_span).max(1e-12 * hi.abs().max(1.0));
    // A narrower series is centred on an axis `span` wide.
    let mid = (lo + hi) / 2.0;
    let (lo, hi) = (lo.min(mid - span / 2.0), hi.max(mid + span / 2.0));
    (lo - 0.08 * span, hi + 0.24 * span)
}

/// A chart of two linear `f64` axes, as [`xy_chart`] builds it.
pub type Plot<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A tick label of a plotters-placed tick on an `f64` axis: plotters' own shortest form (at most
/// five decimals, never in exponent form) without its trailing `.0`, so that an axis reads `0`,
/// `0.05`, `0.1`, `1` as the report writes numbers ([`fmt_num`]), not `0.0`, `0.05`, `0.1`, `1.0`.
/// Set on every axis whose ticks plotters places.
pub fn tick(v: &f64) -> String {
    plotters::data::float::FloatPrettyPrinter {
        allow_scientific: false,
        min_decimal: 0,
        max_decimal: 5,
    }
    .print(*v)
}

/// An x–y chart on `area`: its caption, the ranges, a light grid and the axis descriptions.
/// An x axis over a design axis (`x_grid`, the grid's values; empty for a continuous axis) is
/// labelled at those values alone, as the report writes them ([`Scale::ticks`]), where it has
/// at most [`GRID_TICKS`] of them or is drawn on a log scale; otherwise plotters' ticks. The x
/// range is in `scale`'s coordinates ([`Scale::to`]), and a log scale says so in the axis's
/// description.
pub fn xy_chart<'a, DB: DrawingBackend + 'a>(
    area: &DrawingArea<DB, Shift>,
    caption: (&str, (&str, u32)),
    (x, y): (std::ops::Range<f64>, std::ops::Range<f64>),
    (x_desc, y_desc): (&str, &str),
    (x_grid, scale): (&[f64], Scale),
) -> anyhow::Result<Plot<'a, DB>>
where
    DB::ErrorType: 'static,
{
    let y_low = y.start;
    let mut chart = ChartBuilder::on(area)
        .caption(caption.0, caption.1)
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y)
        .map_err(err)?;
    let x_ticks = scale.ticks(x_grid);
    let mut mesh = chart.configure_mesh();
    // (Plotters' default ticks left as they are: set explicitly, even to their default count,
    // they draw a different light grid.)
    if !x_ticks.is_empty() {
        mesh.x_labels(0);
    }
    mesh.x_desc(scale.desc(x_desc))
        .y_desc(y_desc)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(SMALL)
        .axis_desc_style(LABEL)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    x_ticks_at(area, &chart, (&x_ticks, scale), y_low)?;
    Ok(chart)
}

/// How a chart draws a swept axis along x: linear, or in `log10` where the grid's values are
/// more evenly spaced so (a geometric grid: 1, 2, 4, 8 units, or clearances of 5, 10, 20 and
/// 40 mm), so that neighbouring designs stand equally apart and their boxes are equally wide.
/// On a linear axis a geometric grid crowds its first values together and draws the last box
/// widest, as if it stood for more.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

impl Scale {
    /// `Log` when the grid's values (any order) are at least three distinct positive numbers
    /// whose gaps are more even in `log10` than as they are (the largest gap over the smallest,
    /// and the linear one uneven beyond 1 %); `Linear` otherwise.
    pub fn of(values: &[f64]) -> Scale {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        if v.len() < 3 || v[0] <= 0.0 {
            return Scale::Linear;
        }
        let unevenness = |w: &[f64]| {
            let gaps = w.windows(2).map(|g| g[1] - g[0]);
            let (lo, hi) = minmax(gaps);
            hi / lo
        };
        let linear = unevenness(&v);
        let logs: Vec<f64> = v.iter().map(|x| x.log10()).collect();
        if linear > 1.01 && unevenness(&logs) < linear {
            Scale::Log
        } else {
            Scale::Linear
        }
    }

    /// The chart's coordinate of the value `v`.
    pub fn to(self, v: f64) -> f64 {
        match self {
            Scale::Linear => v,
            Scale::Log => v.log10(),
        }
    }

    /// The axis's description, with `, log scale` after it on a log scale.
    pub fn desc(self, d: &str) -> String {
        match self {
            Scale::Linear => d.to_string(),
            Scale::Log => format!("{d}, log scale"),
        }
    }

    /// The grid's values labelled under the axis: all of them up to [`GRID_TICKS`], none above
    /// on a linear axis (plotters' ticks then), and on a log axis every `k`-th value and the
    /// last, at most [`GRID_TICKS`] (plotters' ticks would read `log10` of the values).
    pub fn ticks(self, values: &[f64]) -> Vec<f64> {
        match self {
            Scale::Linear => grid_ticks(values).to_vec(),
            Scale::Log => {
                let n = values.len();
                let every = n.div_ceil(GRID_TICKS).max(1);
                let mut out: Vec<f64> = values.iter().step_by(every).copied().collect();
                // The last value too, unless it would crowd the one before.
                if n > 0 && 2 * ((n - 1) % every) >= every {
                    out.push(values[n - 1]);
                }
                out
            }
        }
    }
}

/// The chart builder of a plot under a title and a legend block (the frequency-response and
/// steady-state charts): 12 px margins, 4 px at the top, `x_label` px under the x axis, 80 px
/// beside the y axis.
pub fn plot_builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x_label: u32,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin(12)
        .margin_top(4)
        .x_label_area_size(x_label)
        .y_label_area_size(80);
    b
}

/// The legend of a chart's labelled series, boxed, at `position`.
pub fn series_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    position: SeriesLabelPosition,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(SMALL)
        .draw()
        .map_err(err)
}

/// The share of a plot's width and of its height that [`clear_corner`] keeps for a legend box
/// of up to four short rows.
pub const LEGEND_SHARE: (f64, f64) = (0.25, 0.25);

/// A corner for a chart's legend clear of what the chart draws: the first of upper right, upper
/// left, lower right and lower left whose box ([`LEGEND_SHARE`] of the plot over `x` and `y`)
/// meets none of `spans` (vertical segments `(x, lo, hi)`; a point is one with `lo == hi`) and
/// none of `levels` (lines drawn across the whole plot at those heights); `None` when each
/// corner meets one.
pub fn clear_corner(
    spans: &[(f64, f64, f64)],
    levels: &[f64],
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<SeriesLabelPosition> {
    let (w, h) = (LEGEND_SHARE.0 * (x1 - x0), LEGEND_SHARE.1 * (y1 - y0));
    let corners = [
        (SeriesLabelPosition::UpperRight, (x1 - w, x1), (y1 - h, y1)),
        (SeriesLabelPosition::UpperLeft, (x0, x0 + w), (y1 - h, y1)),
        (SeriesLabelPosition::LowerRight, (x1 - w, x1), (y0, y0 + h)),
        (SeriesLabelPosition::LowerLeft, (x0, x0 + w), (y0, y0 + h)),
    ];
    corners
        .into_iter()
        .find_map(|(corner, (bx0, bx1), (by0, by1))| {
            let meets_span = spans
                .iter()
                .any(|&(x, lo, hi)| x >= bx0 && x <= bx1 && hi >= by0 && lo <= by1);
            let meets_level = levels.iter().any(|&y| y >= by0 && y <= by1);
            (!meets_span && !meets_level).then_some(corner)
        })
}

/// A legend key.
pub enum Key {
    Line(RGBColor),
    LineDot(RGBColor),
    Dashed(RGBColor),
    Swatch(RGBAColor),
    /// An interval: a vertical bar with caps.
    Whisker(RGBColor),
}

/// Vertical pitch of a legend's rows (pixels).
pub const LEGEND_PITCH: u32 = 22;

/// The legend items' rows: indices of `items` per row when they flow from pixel `x` across an
/// area `width` pixels wide (each row starts again at `x`).
fn legend_layout<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    items: &[(Key, String)],
) -> anyhow::Result<Vec<Vec<(usize, i32)>>>
where
    DB::ErrorType: 'static,
{
    let width = area.dim_in_pixel().0 as i32;
    let mut rows: Vec<Vec<(usize, i32)>> = vec![Vec::new()];
    let mut at = x;
    for (i, (_, text)) in items.iter().enumerate() {
        let (w, _) = area
            .estimate_text_size(text, &SMALL.into_text_style(area))
            .map_err(err)?;
        let need = 28 + w as i32;
        if at + need > width && at > x {
            rows.push(Vec::new());
            at = x;
        }
        rows.last_mut().expect("one row at least").push((i, at));
        at += need + 28;
    }
    Ok(rows)
}

/// How many legend rows `legend_row` needs for `items` from pixel `x` in `area`'s width.
pub fn legend_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    items: &[(Key, String)],
) -> anyhow::Result<u32>
where
    DB::ErrorType: 'static,
{
    Ok(legend_layout(area, x, items)?.len() as u32)
}

/// Splits a legend off the top of `area` (one row, or as many as `items` need, from pixel `x`),
/// draws it, and returns the rest of the area.
pub fn legend_block<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    items: &[(Key, String)],
) -> anyhow::Result<DrawingArea<DB, Shift>>
where
    DB::ErrorType: 'static,
{
    let rows = legend_lines(area, x, items)?;
    let (keys, rest) = area.split_vertically(34 + rows.saturating_sub(1) * LEGEND_PITCH);
    legend_row(&keys, x, items)?;
    Ok(rest)
}

/// Draws `items` in `area` from pixel `x`, flowing onto further rows (`LEGEND_PITCH` apart,
/// centred in the area) as long as the area is tall enough; items that still would not fit are
/// left off and an ellipsis says so. Size the area with [`legend_lines`] to show every item.
pub fn legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    items: &[(Key, String)],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let height = area.dim_in_pixel().1 as i32;
    let font = SMALL
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let rows = legend_layout(area, x, items)?;
    let pitch = LEGEND_PITCH as i32;
    let fit = ((height / pitch).max(1) as usize).min(rows.len());
    let top = (height - pitch * fit as i32) / 2 + pitch / 2;
    for (r, row) in rows.iter().take(fit).enumerate() {
        let y = top + pitch * r as i32;
        let last = r + 1 == fit && fit < rows.len();
        for &(i, x) in row {
            let (key, text) = &items[i];
            if last && i == row.last().map_or(0, |l| l.0) {
                area.draw_text("…", &font, (x, y)).map_err(err)?;
                break;
            }
            match key {
                Key::Line(c) => area.draw(&PathElement::new(
                    vec![(x, y), (x + 22, y)],
                    c.stroke_width(2),
                )),
                Key::LineDot(c) => area
                    .draw(&PathElement::new(
                        vec![(x, y), (x + 22, y)],
                        c.stroke_width(2),
                    ))
                    .and_then(|_| area.draw(&Circle::new((x + 11, y), 3, c.filled()))),
                Key::Dashed(c) => [(0, 6), (8, 14), (16, 22)].iter().try_for_each(|&(a, b)| {
                    area.draw(&PathElement::new(
                        vec![(x + a, y), (x + b, y)],
                        c.stroke_width(2),
                    ))
                }),
                Key::Swatch(c) => {
                    area.draw(&Rectangle::new([(x, y - 7), (x + 22, y + 7)], c.filled()))
                }
                Key::Whisker(c) => [
                    vec![(x + 11, y - 7), (x + 11, y + 7)],
                    vec![(x + 6, y - 7), (x + 16, y - 7)],
                    vec![(x + 6, y + 7), (x + 16, y + 7)],
                ]
                .into_iter()
                .try_for_each(|p| area.draw(&PathElement::new(p, c.stroke_width(1)))),
            }
            .map_err(err)?;
            area.draw_text(text, &font, (x + 28, y)).map_err(err)?;
        }
    }
    Ok(())
}

/// Viridis-like ramp from dark blue (0) to yellow (1).
pub fn heat(t: f64) -> RGBColor {
    let stops = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = t.clamp(0.0, 1.0) * (stops.len() - 1) as f64;
    let i = (t.floor() as usize).min(stops.len() - 2);
    let f = t - i as f64;
    let (a, b) = (stops[i], stops[i + 1]);
    RGBColor(
        (a.0 + f * (b.0 - a.0)) as u8,
        (a.1 + f * (b.1 - a.1)) as u8,
        (a.2 + f * (b.2 - a.2)) as u8,
    )
}

/// A map's axes over the cell edges `eb` (x) and `ea` (y), without a mesh. An axis of at most
/// [`GRID_TICKS`] values (`vb`, `va`: the grid's, each inside its cell) is labelled at those
/// values alone, as [`fmt_num`] writes them (`1, 2, 4, 8` units, not a tick at every unit from 1 to
/// 10; `0` where a computed tick would read `-0.0`); a denser one gets plotters' ticks.
pub fn map_chart<'a, DB: DrawingBackend + 'a>(
    area: &DrawingArea<DB, Shift>,
    (eb, ea): (&[f64], &[f64]),
    (vb, va): (&[f64], &[f64]),
    (x_desc, y_desc): (&str, &str),
) -> anyhow::Result<Plot<'a, DB>>
where
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(86)
        .build_cartesian_2d(eb[0]..eb[eb.len() - 1], ea[0]..ea[ea.len() - 1])
        .map_err(err)?;
    // The grid's values where an axis has few, else plotters' ticks (10, its default).
    let (x_ticks, y_ticks) = (grid_ticks(vb), grid_ticks(va));
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(if x_ticks.is_empty() { 10 } else { 0 })
        .y_labels(if y_ticks.is_empty() { 10 } else { 0 })
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(SMALL)
        .axis_desc_style(LABEL)
        .draw()
        .map_err(err)?;
    x_ticks_at(area, &chart, (x_ticks, Scale::Linear), ea[0])?;
    y_ticks_at(area, &chart, y_ticks, eb[0])?;
    Ok(chart)
}

/// The grid's values `v` as an axis's ticks when there are at most [`GRID_TICKS`] of them;
/// none (plotters' ticks then) when there are more.
pub fn grid_ticks(v: &[f64]) -> &[f64] {
    if v.len() <= GRID_TICKS { v } else { &[] }
}

/// The pixel of `(x, y)` of `chart` within `area`.
fn pixel_in<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    (x, y): (f64, f64),
) -> (i32, i32) {
    let base = area.get_base_pixel();
    let (px, py) = chart.backend_coord(&(x, y));
    (px - base.0, py - base.1)
}

/// A tick and a label ([`fmt_num`]) under the x axis (at height `y`) at each of the values
/// `xs`, placed on `scale`; a label that would pass the area's right edge (a tick at the axis's
/// end) is moved left to fit.
pub fn x_ticks_at<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    (xs, scale): (&[f64], Scale),
    y: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = SMALL
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    let width = area.dim_in_pixel().0 as i32;
    for &x in xs {
        let (px, py) = pixel_in(area, chart, (scale.to(x), y));
        area.draw(&PathElement::new(vec![(px, py), (px, py + 5)], BLACK))
            .map_err(err)?;
        let text = fmt_num(x);
        let half = area.estimate_text_size(&text, &font).map_err(err)?.0 as i32 / 2;
        let at = px.min(width - 2 - half);
        area.draw(&Text::new(text, (at, py + 8), font.clone()))
            .map_err(err)?;
    }
    Ok(())
}

/// A tick and a label ([`fmt_num`]) left of the y axis (at `x`) at each of `ys`.
fn y_ticks_at<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    ys: &[f64],
    x: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = SMALL
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Right, VPos::Center));
    for &y in ys {
        let (px, py) = pixel_in(area, chart, (x, y));
        area.draw(&PathElement::new(vec![(px - 5, py), (px, py)], BLACK))
            .map_err(err)?;
        area.draw(&Text::new(fmt_num(y), (px - 8, py), font.clone()))
            .map_err(err)?;
    }
    Ok(())
}

/// An axis of at most this many grid values is labelled at those values ([`map_chart`],
/// [`xy_chart`], the design chart).
pub const GRID_TICKS: usize = 12;

/// A map's colour bar: [`heat`] from 1 at the top to 0 at the bottom, `label` above it, `top`
/// and `bottom` beside its ends.
pub fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    label: &str,
    top: &str,
    bottom: &str,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let h = area.dim_in_pixel().1 as i32 - 40;
    for k in 0..h {
        let t = 1.0 - k as f64 / h as f64;
        area.draw(&Rectangle::new(
            [(0, 20 + k), (24, 21 + k)],
            heat(t).filled(),
        ))
        .map_err(err)?;
    }
    for (text, at) in [(label, (0, 0)), (top, (30, 14)), (bottom, (30, 14 + h))] {
        area.draw(&Text::new(text.to_string(), at, SMALL.into_font()))
            .map_err(err)?;
    }
    Ok(())
}

/// Edges of the cells of a map around the values `v` (halfway between neighbours, half a step
/// beyond the ends).
pub fn cell_edges(v: &[f64]) -> Vec<f64> {
    let n = v.len();
    let h = |i: usize| if n > 1 { (v[i + 1] - v[i]) / 2.0 } else { 0.5 };
    let mut e = Vec::with_capacity(n + 1);
    e.push(v[0] - h(0));
    for i in 0..n.saturating_sub(1) {
        e.push((v[i] + v[i + 1]) / 2.0);
    }
    e.push(v[n - 1] + h(n.saturating_sub(2)));
    e
}

/// The summary along one axis through one design point (the whole sweep with one axis): the
/// points in axis order, their values, and the jumps located on that line.
pub struct Profile<'a> {
    pub s: &'a Summary,
    pub axis: usize,
    pub points: Vec<&'a PointStats>,
    /// The points' values along the axis.
    pub xs: Vec<f64>,
    /// How the charts draw the axis ([`Scale::of`] the values); [`Profile::series`] and
    /// [`Profile::zone_spans`] are in its coordinates.
    pub scale: Scale,
    pub jumps: Vec<&'a Jump>,
    /// The other axes' values, `m = 0.02 kg, d = 0.01 m`; empty with one axis.
    pub slice: String,
}

impl<'a> Profile<'a> {
    pub fn new(s: &'a Summary, axis: usize, through: u64) -> Profile<'a> {
        let g = &s.grid;
        let points: Vec<&PointStats> = g
            .slice(through, &[axis])
            .into_iter()
            .filter_map(|p| s.point(p))
            .collect();
        let xs: Vec<f64> = points.iter().map(|p| g.value(p.point, axis)).collect();
        let scale = Scale::of(&xs);
        let line = g.with_index(through, axis, 0);
        let jumps = s
            .jumps
            .iter()
            .filter(|j| j.axis == axis && g.with_index(j.below, axis, 0) == line)
            .collect();
        let slice = (0..g.n_axes())
            .filter(|&a| a != axis)
            .map(|a| axis_value(g.key(a), g.value(through, a)))
            .collect::<Vec<_>>()
            .join(", ");
        Profile {
            s,
            axis,
            points,
            xs,
            scale,
            jumps,
            slice,
        }
    }

    /// The chart's coordinates of the points ([`Scale::to`] of [`Profile::xs`]).
    pub fn positions(&self) -> Vec<f64> {
        self.xs.iter().map(|&x| self.scale.to(x)).collect()
    }

    /// The chart's coordinate of the value `v` along the axis.
    pub fn at_x(&self, v: f64) -> f64 {
        self.scale.to(v)
    }

    pub fn key(&self) -> &str {
        self.s.grid.key(self.axis)
    }

    /// `(x, f(point))` where `f` is finite, `x` in the chart's coordinates, thinned for
    /// drawing ([`thin`]).
    pub fn series(&self, f: impl Fn(&PointStats) -> f64) -> Vec<(f64, f64)> {
        thin(
            self.xs
                .iter()
                .zip(&self.points)
                .map(|(&x, p)| (self.scale.to(x), f(p)))
                .filter(|p| p.1.is_finite())
                .collect(),
        )
    }

    /// Spans of consecutive points in one zone: (from, to, zone), in the chart's coordinates,
    /// boundaries halfway between neighbouring points.
    pub fn zone_spans(&self) -> Vec<(f64, f64, u32)> {
        let xs = &self.positions();
        let mut out: Vec<(usize, usize, u32)> = Vec::new();
        for (i, p) in self.points.iter().enumerate() {
            match out.last_mut() {
                Some(last) if last.2 == p.zone && last.1 + 1 == i => last.1 = i,
                _ => out.push((i, i, p.zone)),
            }
        }
        out.into_iter()
            .filter(|r| (r.2 as usize) < self.s.zones.len())
            .map(|(a, b, z)| {
                let lo = if a == 0 {
                    xs[0]
                } else {
                    (xs[a - 1] + xs[a]) / 2.0
                };
                let hi = if b + 1 == xs.len() {
                    xs[b]
                } else {
                    (xs[b] + xs[b + 1]) / 2.0
                };
                (lo, hi, z)
            })
            .collect()
    }

    /// The title suffix naming the slice: ` (m = 0.02 kg, d = 0.01 m)`.
    pub fn at(&self) -> String {
        if self.slice.is_empty() {
            String::new()
        } else {
            format!(" at {}", self.slice)
        }
    }
}

/// Vertices a drawn line keeps at most: four per pixel of the widest chart.
pub const MAX_VERTICES: usize = 4000;

/// A line of more than [`MAX_VERTICES`] points thinned for drawing: of each run of consecutive
/// points (`MAX_VERTICES / 2` runs), its lowest and its highest, in x order, so every spike
/// stays visible and the drawing does not change at the chart's resolution. The chart's data
/// (CSV) keeps every point.
pub fn thin(line: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let n = line.len();
    if n <= MAX_VERTICES {
        return line;
    }
    let runs = MAX_VERTICES / 2;
    let mut out = Vec::with_capacity(MAX_VERTICES);
    for k in 0..runs {
        let run = &line[k * n / runs..(k + 1) * n / runs];
        let lo = run.iter().min_by(|a, b| a.1.total_cmp(&b.1));
        let hi = run.iter().max_by(|a, b| a.1.total_cmp(&b.1));
        if let (Some(&lo), Some(&hi)) = (lo, hi) {
            if lo.0 <= hi.0 {
                out.extend([lo, hi]);
            } else {
                out.extend([hi, lo]);
            }
        }
    }
    out
}

/// `text` shortened to `max` characters with an ellipsis.
pub fn shorten(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(max.saturating_sub(1)).collect();
        s.push('…');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_legend_that_does_not_fit_flows_onto_more_rows_and_keeps_every_key() {
        let items: Vec<(Key, String)> = (0..5)
            .map(|i| {
                (
                    Key::Line(BLUE),
                    format!("a rather long legend entry number {i}"),
                )
            })
            .collect();
        register_fonts();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (1000, 60)).into_drawing_area();
            // Five entries of ~220 px each in 1000 px: more than one row, each row within width.
            let rows = legend_layout(&root, 90, &items).unwrap();
            assert!(rows.len() >= 2, "{rows:?}");
            assert_eq!(rows.iter().map(Vec::len).sum::<usize>(), 5);
            assert_eq!(legend_lines(&root, 90, &items[..1]).unwrap(), 1);
            // Drawn in an area two rows tall (as sized by legend_lines for two rows), every
            // entry's text is there and no ellipsis.
            let tall = rows.len() as u32 * LEGEND_PITCH + 8;
            let (keys, _) = root.split_vertically(tall);
            legend_row(&keys, 90, &items).unwrap();
            root.present().unwrap();
        }
        for i in 0..5 {
            assert!(svg.contains(&format!("number {i}")), "entry {i} missing");
        }
        assert!(!svg.contains('…'));
    }

    /// The SVG text elements' contents, in order.
    fn texts(svg: &str) -> Vec<String> {
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                Some(
                    t.split_once('>')?
                        .1
                        .split_once("</text>")?
                        .0
                        .trim()
                        .to_string(),
                )
            })
            .collect()
    }

    #[test]
    fn a_map_of_few_values_is_labelled_at_them_and_a_dense_one_by_plotters() {
        register_fonts();
        let draw = |vb: &[f64], va: &[f64]| {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (800, 600)).into_drawing_area();
                let (eb, ea) = (cell_edges(vb), cell_edges(va));
                map_chart(&root, (&eb, &ea), (vb, va), ("x axis", "y axis")).unwrap();
                root.present().unwrap();
            }
            texts(&svg)
        };
        // Units 1, 2, 4, 8 and a spread of 0 and 0.5: those values alone, as the report writes
        // them (the cells' edges would have given plotters' ticks at 3, 5, 6, ... and -0.0).
        let labels = draw(&[0.0, 0.5], &[1.0, 2.0, 4.0, 8.0]);
        for want in ["0", "0.5", "1", "2", "4", "8", "x axis", "y axis"] {
            assert!(
                labels.iter().any(|l| l == want),
                "{want} missing: {labels:?}"
            );
        }
        assert_eq!(labels.len(), 8, "{labels:?}");
        // 40 values along x: plotters' ticks there, the grid's on y.
        let xs: Vec<f64> = (0..40).map(|i| 0.8 + 0.01 * i as f64).collect();
        let labels = draw(&xs, &[0.005, 0.01]);
        assert!(labels.iter().any(|l| l == "0.005") && labels.iter().any(|l| l == "0.01"));
        let numbers = labels.iter().filter(|l| l.parse::<f64>().is_ok()).count();
        assert!((2 + 4..2 + 20).contains(&numbers), "{labels:?}");
    }

    #[test]
    fn a_profile_over_few_values_is_labelled_at_them_and_a_continuous_axis_by_plotters() {
        register_fonts();
        let draw = |range: std::ops::Range<f64>, grid: &[f64]| {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (800, 600)).into_drawing_area();
                xy_chart(
                    &root,
                    ("title", TITLE),
                    // A y range without whole numbers: its labels are none of the x axis's.
                    (range, 0.0..0.9),
                    ("x axis", "y axis"),
                    (grid, Scale::Linear),
                )
                .unwrap();
                root.present().unwrap();
            }
            texts(&svg)
        };
        // Units 1, 2, 4, 8: those values alone, as the report writes them (plotters' ticks over
        // the range read 0, 1, ..., 9, most of them where no design is).
        let labels = draw(-0.2..9.2, &[1.0, 2.0, 4.0, 8.0]);
        let x_numbers: Vec<&String> = labels
            .iter()
            .filter(|l| ["1", "2", "4", "8"].contains(&l.as_str()))
            .collect();
        assert_eq!(x_numbers.len(), 4, "{labels:?}");
        for absent in ["3", "3.0", "2.0", "9", "9.0"] {
            assert!(!labels.iter().any(|l| l == absent), "{absent}: {labels:?}");
        }
        // A continuous axis (no grid): plotters' ticks.
        let labels = draw(0.0..20.0, &[]);
        let numbers = labels.iter().filter(|l| l.parse::<f64>().is_ok()).count();
        assert!(numbers >= 2 + 4 + 4, "{labels:?}");
        // Written as the report writes numbers: `0`, `5`, `0.1`, never `0.0` or `5.0`.
        assert!(labels.iter().any(|l| l == "0"), "{labels:?}");
        assert!(!labels.iter().any(|l| l.ends_with(".0")), "{labels:?}");
    }

    #[test]
    fn a_tick_reads_as_the_report_writes_numbers() {
        for (v, label) in [
            (0.0, "0"),
            (1.0, "1"),
            (-3.0, "-3"),
            (0.05, "0.05"),
            (0.1 + 0.2, "0.3"),
            (1.05, "1.05"),
            (5e-17, "0"),
            (0.00025, "0.00025"),
            (1250.0, "1250"),
        ] {
            assert_eq!(tick(&v), label, "{v}");
        }
    }

    /// The labels of an SVG with their `x` attribute.
    fn placed_texts(svg: &str) -> Vec<(String, f64)> {
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                let (tag, rest) = t.split_once('>')?;
                let x = tag.split_once("x=\"")?.1.split_once('"')?.0.parse().ok()?;
                Some((rest.split_once("</text>")?.0.trim().to_string(), x))
            })
            .collect()
    }

    #[test]
    fn a_geometric_grid_is_drawn_on_a_log_scale_with_its_values_equally_apart() {
        // Geometric grids: units, the seismic showcases' clearances, a dense log-spaced sweep.
        assert_eq!(Scale::of(&[1.0, 2.0, 4.0, 8.0]), Scale::Log);
        assert_eq!(Scale::of(&[0.04, 0.02, 0.01, 0.005]), Scale::Log);
        let dense: Vec<f64> = (0..40)
            .map(|i| 1e-3 * 10f64.powf(i as f64 / 13.0))
            .collect();
        assert_eq!(Scale::of(&dense), Scale::Log);
        // Even grids, a grid through zero (the bare structure's m = 0), two values: linear.
        for linear in [
            &[0.5, 0.6, 0.7, 0.8, 0.9][..],
            &[0.005, 0.01, 0.015],
            &[0.0, 0.05, 0.1, 0.2],
            &[1.0, 8.0],
            &[],
        ] {
            assert_eq!(Scale::of(linear), Scale::Linear, "{linear:?}");
        }
        // Ticks: every value of a short grid; on a dense log axis at most GRID_TICKS of them,
        // first and last among them (plotters' would read log10 of the values).
        assert_eq!(
            Scale::Log.ticks(&[1.0, 2.0, 4.0, 8.0]),
            [1.0, 2.0, 4.0, 8.0]
        );
        let t = Scale::Log.ticks(&dense);
        assert!(t.len() <= GRID_TICKS && t.len() >= GRID_TICKS / 2, "{t:?}");
        assert_eq!((t[0], t[t.len() - 1]), (dense[0], dense[39]));
        assert!(Scale::Linear.ticks(&dense).is_empty());

        // Drawn: units 1, 2, 4, 8 labelled equally apart, and the axis says it is logarithmic.
        register_fonts();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (800, 600)).into_drawing_area();
            let xs = [1.0, 2.0, 4.0, 8.0];
            let scale = Scale::of(&xs);
            let (a, b) = (scale.to(1.0) - 0.2, scale.to(8.0) + 0.2);
            xy_chart(
                &root,
                ("title", TITLE),
                (a..b, 0.0..0.9),
                ("units (-)", "y axis"),
                (&xs, scale),
            )
            .unwrap();
            root.present().unwrap();
        }
        let placed = placed_texts(&svg);
        let at = |label: &str| placed.iter().find(|(t, _)| t == label).map(|p| p.1);
        let px: Vec<f64> = ["1", "2", "4", "8"]
            .iter()
            .map(|l| at(l).unwrap())
            .collect();
        let gaps: Vec<f64> = px.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(
            gaps.iter().all(|g| (g - gaps[0]).abs() <= 1.0 && *g > 50.0),
            "{px:?}"
        );
        assert!(at("units (-), log scale").is_some(), "{placed:?}");
    }

    #[test]
    fn a_legend_goes_to_a_corner_clear_of_the_data_or_nowhere() {
        let x = (0.0, 10.0);
        let y = (0.0, 1.0);
        // A line across the top (the bare structure's rate) and a point low on the left.
        let spans = [(1.0, 0.05, 0.1), (5.0, 0.4, 0.6)];
        assert_eq!(
            clear_corner(&spans, &[0.9], x, y),
            Some(SeriesLabelPosition::LowerRight)
        );
        // Nothing near the top: the upper right.
        assert_eq!(
            clear_corner(&spans, &[], x, y),
            Some(SeriesLabelPosition::UpperRight)
        );
        // Whiskers reaching into every corner: none.
        let spans = [(0.5, 0.0, 1.0), (9.5, 0.0, 1.0)];
        assert_eq!(clear_corner(&spans, &[], x, y), None);
    }

    #[test]
    fn thinning_keeps_the_spikes_and_bounds_the_vertices() {
        let mut line: Vec<(f64, f64)> = (0..1_000_000).map(|i| (i as f64, 0.0)).collect();
        line[123_457].1 = 5.0;
        line[876_543].1 = -3.0;
        let t = thin(line);
        assert!(t.len() <= MAX_VERTICES, "{}", t.len());
        assert!(t.contains(&(123_457.0, 5.0)) && t.contains(&(876_543.0, -3.0)));
        assert!(t.windows(2).all(|w| w[0].0 < w[1].0), "x order");
        // Short lines are drawn as they are.
        let short: Vec<(f64, f64)> = (0..100).map(|i| (i as f64, i as f64)).collect();
        assert_eq!(thin(short.clone()), short);
    }
}
