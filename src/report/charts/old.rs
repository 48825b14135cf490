//! Charts, each written as SVG and PNG (plotters). The PNG text is drawn with DejaVu Sans,
//! embedded in the binary and registered once as `sans-serif`.
//!
//! * `di` — DI against the swept axis (the paper's Figure 4), jumps marked;
//! * `design_chart` — the paper's Figure 6 in two panels sharing the swept axis, zones shaded
//!   and named in both: R with its bootstrap interval and the `r_min` threshold on its own
//!   range on top, mu_n (left axis) and DI (right axis) below;
//! * `xmax_spread` — box plot of `xmax` over the cases of every design point;
//! * `perfectibility_map`, `zone_map` — with two swept axes;
//! * [`waveforms`] — main-mass displacement with and without the damper, and for two `e` with
//!   the first peak magnified (the paper's Figures 2 and 5).

use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{Context, anyhow};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::reduce::Summary;
use crate::reduce::zones::{
    LABEL_JUMP, LABEL_NO_DATA, LABEL_STRONG, LABEL_UNREL_STRONG, LABEL_UNREL_WEAK, LABEL_WEAK,
};

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
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

fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing: {e:?}")
}

/// A chart that can draw itself on any backend.
trait Chart {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static;
}

/// Writes `<dir>/<stem>.svg` and `<dir>/<stem>.png`; returns both paths.
fn render<C: Chart>(
    dir: &Path,
    stem: &str,
    size: (u32, u32),
    chart: &C,
) -> anyhow::Result<Vec<PathBuf>> {
    register_fonts();
    let svg = dir.join(format!("{stem}.svg"));
    let png = dir.join(format!("{stem}.png"));
    {
        let root = SVGBackend::new(&svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        chart
            .draw(&root)
            .with_context(|| format!("drawing {}", svg.display()))?;
        root.present().map_err(err)?;
    }
    {
        let root = BitMapBackend::new(&png, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        chart
            .draw(&root)
            .with_context(|| format!("drawing {}", png.display()))?;
        root.present().map_err(err)?;
    }
    Ok(vec![svg, png])
}

fn label_color(label: &str) -> RGBColor {
    match label {
        LABEL_STRONG => RGBColor(166, 217, 160),
        LABEL_JUMP => RGBColor(244, 165, 130),
        LABEL_WEAK => RGBColor(171, 203, 232),
        LABEL_UNREL_STRONG => RGBColor(253, 219, 130),
        LABEL_UNREL_WEAK => RGBColor(215, 190, 230),
        LABEL_NO_DATA => RGBColor(200, 200, 200),
        _ => RGBColor(220, 220, 220),
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

fn pad(lo: f64, hi: f64, frac: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = (hi - lo).abs().max(1e-12 * hi.abs().max(1.0));
    (lo - frac * span, hi + frac * span)
}

fn minmax(v: impl IntoIterator<Item = f64>) -> (f64, f64) {
    v.into_iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        })
}

/// Unit of a system key, for axis labels.
pub fn axis_unit(key: &str) -> &'static str {
    match key {
        "M" | "m" => "kg",
        "K" => "N/m",
        "C" => "N s/m",
        "d" | "x0" | "y0" => "m",
        "v0" | "w0" => "m/s",
        _ => "–",
    }
}

fn axis_desc(key: &str) -> String {
    match key {
        "e" => "coefficient of restitution e (–)".into(),
        k => format!("{k} ({})", axis_unit(k)),
    }
}

/// Above this many design points, charts draw lines and bands instead of markers and boxes,
/// and mark only the strongest jumps: a chart stays readable and an SVG stays small.
const MANY: usize = 300;
/// Jumps drawn at most.
const MAX_JUMP_LINES: usize = 30;

const TITLE: (&str, u32) = ("sans-serif", 22);
const LABEL: (&str, u32) = ("sans-serif", 18);
const SMALL: (&str, u32) = ("sans-serif", 15);

/// Zone spans along axis 0 (1-axis sweeps): (from, to, name, label), boundaries halfway
/// between neighbouring points.
fn zone_spans(s: &Summary) -> Vec<(f64, f64, String, String)> {
    let vals: Vec<f64> = s.points.iter().map(|p| p.values[0]).collect();
    let mut out = Vec::new();
    for z in &s.zones {
        let idx: Vec<usize> = (0..s.points.len())
            .filter(|&i| s.points[i].zone == z.name)
            .collect();
        let (Some(&first), Some(&last)) = (idx.first(), idx.last()) else {
            continue;
        };
        let lo = if first == 0 {
            vals[0]
        } else {
            (vals[first - 1] + vals[first]) / 2.0
        };
        let hi = if last + 1 == vals.len() {
            vals[last]
        } else {
            (vals[last] + vals[last + 1]) / 2.0
        };
        out.push((lo, hi, z.name.clone(), z.label.clone()));
    }
    out
}

struct DiChart<'a>(&'a Summary);

impl Chart for DiChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.0;
        let last = s.axes.len() - 1;
        let key = &s.axes[last].0;
        let (x0, x1) = minmax(s.points.iter().map(|p| p.values[last]));
        let (y0, y1) = minmax(s.points.iter().map(|p| p.di));
        let (y0, y1) = pad(y0.min(0.0), y1, 0.08);
        let mut chart = ChartBuilder::on(root)
            .caption("Damping inclination DI against the design variable", TITLE)
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(axis_desc(key))
            .y_desc("DI (m/s)")
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        // One series per combination of the other axes (at most 8 drawn).
        let mut groups: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
        for p in &s.points {
            let name: Vec<String> = (0..last)
                .map(|a| format!("{} = {}", s.axes[a].0, fmt_num(p.values[a])))
                .collect();
            let name = if name.is_empty() {
                format!("DI ({})", di_source(s))
            } else {
                name.join(", ")
            };
            match groups.iter_mut().find(|g| g.0 == name) {
                Some(g) => g.1.push((p.values[last], p.di)),
                None => groups.push((name, vec![(p.values[last], p.di)])),
            }
        }
        for (gi, (name, pts)) in groups.iter().take(8).enumerate() {
            let color = Palette99::pick(gi).to_rgba();
            let pts: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.1.is_finite()).collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(err)?
                .label(name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
            if pts.len() <= MANY {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(err)?;
            }
        }
        // Jumps along the plotted axis, the strongest first.
        let mut jumps: Vec<_> = s.jumps.iter().filter(|j| &j.axis == key).collect();
        let n_jumps = jumps.len();
        jumps.sort_by(|a, b| b.z.total_cmp(&a.z));
        jumps.truncate(MAX_JUMP_LINES);
        let jump_label = if n_jumps > MAX_JUMP_LINES {
            format!("jump: the {MAX_JUMP_LINES} strongest of {n_jumps} steps/kinks")
        } else {
            "jump: step or kink of xmax or DI".to_string()
        };
        let mut first = true;
        for j in jumps {
            let x = j.at;
            let series = chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x, y0), (x, y1)],
                    RED.mix(0.6).stroke_width(1),
                )))
                .map_err(err)?;
            if first {
                series
                    .label(jump_label.clone())
                    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED.mix(0.6)));
                first = false;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(SMALL)
            .draw()
            .map_err(err)?;
        Ok(())
    }
}

fn di_source(s: &Summary) -> &'static str {
    match s.options.di_source {
        crate::study::DiSource::Ideal => "ideal case",
        crate::study::DiSource::Mean => "mean over cases",
    }
}

/// Short number formatting for labels.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.4e}")
    }
}

/// The design chart (the paper's Figure 6) in two panels sharing the swept axis, the zones
/// shaded and named in both: on top R with its bootstrap interval on its own tight range and
/// the `r_min` threshold dashed; below the safety factor (left axis) and DI (right axis).
/// Legends sit in rows above the panels, never over data.
struct DesignChart<'a>(&'a Summary);

/// Size of the design chart (pixels).
const DESIGN_SIZE: (u32, u32) = (1000, 820);
/// Margin and label-area widths of both panels: equal, so the two plots align on the x axis.
const DESIGN_MARGIN: u32 = 12;
const DESIGN_LEFT: u32 = 80;
const DESIGN_RIGHT: u32 = 80;
/// Height of a legend row (pixels).
const LEGEND_ROW: u32 = 30;

/// A legend key.
enum Key {
    Line(RGBColor),
    LineDot(RGBColor),
    Dashed(RGBColor),
    Swatch(RGBAColor),
}

/// Draws `items` in one row of `area`, from pixel `x`; items that would not fit are left off
/// and an ellipsis says so.
fn legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    items: &[(Key, String)],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let (width, height) = area.dim_in_pixel();
    let y = height as i32 / 2;
    let font = SMALL
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let mut x = x;
    for (key, text) in items {
        let (w, _) = area.estimate_text_size(text, &font).map_err(err)?;
        if x + 28 + w as i32 > width as i32 {
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
            Key::Swatch(c) => area.draw(&Rectangle::new([(x, y - 7), (x + 22, y + 7)], c.filled())),
        }
        .map_err(err)?;
        area.draw_text(text, &font, (x + 28, y)).map_err(err)?;
        x += 28 + w as i32 + 28;
    }
    Ok(())
}

/// Colour of a zone: declared zones cycle through [`DECLARED`] by their index, automatic ones
/// are coloured by label.
fn zone_color(s: &Summary, name: &str, label: &str) -> RGBColor {
    if s.zones.iter().any(|z| z.declared) {
        let i = s.zones.iter().position(|z| z.name == name).unwrap_or(0);
        DECLARED[i % DECLARED.len()]
    } else {
        label_color(label)
    }
}

/// `lo..hi` widened a little below and by room for the zone names above; `min_span` keeps a
/// flat series from collapsing the axis.
fn with_headroom(lo: f64, hi: f64, min_span: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = (hi - lo).max(min_span).max(1e-12 * hi.abs().max(1.0));
    // A narrower series is centred on an axis `span` wide.
    let mid = (lo + hi) / 2.0;
    let (lo, hi) = (lo.min(mid - span / 2.0), hi.max(mid + span / 2.0));
    (lo - 0.08 * span, hi + 0.24 * span)
}

/// The R panel's range over `r` (R and its interval bounds): with `r_min` when that at most
/// doubles the span (so the threshold never flattens R), and room for the zone names above;
/// true when `r_min` is inside.
fn reliability_range(r: impl IntoIterator<Item = f64>, r_min: f64) -> ((f64, f64), bool) {
    let (lo, hi) = minmax(r);
    if !(lo.is_finite() && hi.is_finite()) {
        return ((0.0, 1.0), r_min.is_finite());
    }
    let span = (hi - lo).max(2e-3);
    let shown = r_min.is_finite() && r_min >= lo - span && r_min <= hi + span;
    let (lo, hi) = if shown {
        (lo.min(r_min), hi.max(r_min))
    } else {
        (lo, hi)
    };
    (with_headroom(lo, hi, 2e-3), shown)
}

/// Shades the zones over `y0..y1` and names those wide enough for their name near the top.
fn shade_zones<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    s: &Summary,
    (y0, y1): (f64, f64),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = ("sans-serif", 18)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (lo, hi, name, label) in zone_spans(s) {
        let color = zone_color(s, &name, &label);
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(lo, y0), (hi, y1)],
                color.mix(0.45).filled(),
            )))
            .map_err(err)?;
        let px = |x: f64| chart.backend_coord(&(x, y0)).0;
        let (w, _) = chart
            .plotting_area()
            .estimate_text_size(&name, &font)
            .map_err(err)?;
        if px(hi) - px(lo) < w as i32 + 4 {
            continue; // too narrow for its name
        }
        chart
            .draw_series(std::iter::once(Text::new(
                name.clone(),
                ((lo + hi) / 2.0, y1 - 0.03 * (y1 - y0)),
                font.clone(),
            )))
            .map_err(err)?;
    }
    Ok(())
}

impl DesignChart<'_> {
    /// The zone key: one swatch per zone name (declared zones) or label (automatic zones).
    fn zone_keys(&self) -> Vec<(Key, String)> {
        let s = self.0;
        let declared = s.zones.iter().any(|z| z.declared);
        let mut keys: Vec<(Key, String)> = Vec::new();
        let mut seen: Vec<&str> = Vec::new();
        for z in &s.zones {
            if !s.points.iter().any(|p| p.zone == z.name) {
                continue;
            }
            let text = if declared { &z.name } else { &z.label };
            if seen.contains(&text.as_str()) {
                continue;
            }
            seen.push(text);
            let c = zone_color(s, &z.name, &z.label);
            keys.push((Key::Swatch(c.mix(0.6)), format!("zone: {text}")));
        }
        keys
    }

    fn reliability_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x0, x1): (f64, f64),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.0;
        let blue = RGBColor(31, 119, 180);
        let grey = RGBColor(60, 60, 60);
        let ((y0, y1), r_min_shown) = reliability_range(
            s.points
                .iter()
                .flat_map(|p| [p.reliability, p.reliability_lo, p.reliability_hi]),
            s.r_min,
        );
        let has_r = s.points.iter().any(|p| p.reliability.is_finite());
        let (keys, plot) = area.split_vertically(LEGEND_ROW);
        let mut items = vec![
            (
                Key::Swatch(blue.mix(0.3)),
                format!("{:.0} % bootstrap interval of R", 100.0 * s.confidence),
            ),
            (
                if s.points.len() <= MANY {
                    Key::LineDot(blue)
                } else {
                    Key::Line(blue)
                },
                "reliability R".to_string(),
            ),
        ];
        if s.r_min.is_finite() {
            let where_ = if r_min_shown {
                "reliable at or above"
            } else if s.r_min < y0 {
                "below the plotted range"
            } else {
                "above the plotted range"
            };
            items.push((
                Key::Dashed(grey),
                format!("r_min = {} ({where_})", fmt_num(s.r_min)),
            ));
        }
        if has_r {
            legend_row(&keys, (DESIGN_MARGIN + DESIGN_LEFT) as i32, &items)?;
        }
        let mut chart = ChartBuilder::on(&plot)
            .margin(DESIGN_MARGIN)
            .margin_top(4)
            .margin_right(DESIGN_MARGIN + DESIGN_RIGHT)
            .x_label_area_size(30)
            .y_label_area_size(DESIGN_LEFT)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        shade_zones(&mut chart, s, (y0, y1))?;
        chart
            .configure_mesh()
            .y_desc("reliability R (–)")
            .y_labels(8)
            // The headroom for the zone names may pass 1; R never does, so no label there.
            .y_label_formatter(&|v| {
                if *v > 1.0 + 1e-9 {
                    String::new()
                } else {
                    fmt_num(*v)
                }
            })
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(err)?;
        if !has_r {
            use plotters::style::text_anchor::{HPos, Pos, VPos};
            chart
                .draw_series(std::iter::once(Text::new(
                    "R not available: the study gives no strength ([reliability].strength_mean)",
                    ((x0 + x1) / 2.0, (y0 + y1) / 2.0),
                    LABEL
                        .into_font()
                        .color(&BLACK)
                        .pos(Pos::new(HPos::Center, VPos::Center)),
                )))
                .map_err(err)?;
            return Ok(());
        }
        let band: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|p| (p.values[0], p.reliability_hi))
            .chain(
                s.points
                    .iter()
                    .rev()
                    .map(|p| (p.values[0], p.reliability_lo)),
            )
            .filter(|p| p.1.is_finite())
            .collect();
        if !band.is_empty() {
            chart
                .draw_series(std::iter::once(Polygon::new(band, blue.mix(0.3).filled())))
                .map_err(err)?;
        }
        if r_min_shown {
            chart
                .draw_series(DashedLineSeries::new(
                    [(x0, s.r_min), (x1, s.r_min)],
                    8,
                    5,
                    grey.stroke_width(2),
                ))
                .map_err(err)?;
        }
        let r = series(s, |p| p.reliability);
        chart
            .draw_series(LineSeries::new(r.clone(), blue.stroke_width(2)))
            .map_err(err)?;
        if r.len() <= MANY {
            chart
                .draw_series(r.iter().map(|&p| Circle::new(p, 3, blue.filled())))
                .map_err(err)?;
        }
        Ok(())
    }

    fn damping_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x0, x1): (f64, f64),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.0;
        let key = &s.axes[0].0;
        let green = RGBColor(44, 160, 44);
        let red = RGBColor(214, 39, 40);
        let (keys, plot) = area.split_vertically(LEGEND_ROW);
        let di_key = if s.points.len() <= MANY {
            Key::LineDot(red)
        } else {
            Key::Line(red)
        };
        let mut items = Vec::new();
        if s.points.iter().any(|p| p.safety_factor.is_finite()) {
            items.push((Key::Line(green), "safety factor μn (left axis)".to_string()));
        }
        items.push((di_key, format!("DI, {} (right axis)", di_source(s))));
        legend_row(&keys, (DESIGN_MARGIN + DESIGN_LEFT) as i32, &items)?;
        let (m0, m1) = minmax(s.points.iter().map(|p| p.safety_factor));
        let (m0, m1) = with_headroom(m0, m1, 0.0);
        let (d0, d1) = minmax(s.points.iter().map(|p| p.di));
        let (d0, d1) = with_headroom(d0.min(0.0), d1, 0.0);
        let mut chart = ChartBuilder::on(&plot)
            .margin(DESIGN_MARGIN)
            .margin_top(4)
            .x_label_area_size(48)
            .y_label_area_size(DESIGN_LEFT)
            .right_y_label_area_size(DESIGN_RIGHT)
            .build_cartesian_2d(x0..x1, m0..m1)
            .map_err(err)?
            .set_secondary_coord(x0..x1, d0..d1);
        shade_zones(&mut chart, s, (m0, m1))?;
        chart
            .configure_mesh()
            .x_desc(axis_desc(key))
            .y_desc("safety factor μn (–)")
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(err)?;
        chart
            .configure_secondary_axes()
            .y_desc("DI (m/s)")
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .draw()
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                series(s, |p| p.safety_factor),
                green.stroke_width(2),
            ))
            .map_err(err)?;
        let di = series(s, |p| p.di);
        chart
            .draw_secondary_series(LineSeries::new(di.clone(), red.stroke_width(2)))
            .map_err(err)?;
        if di.len() <= MANY {
            chart
                .draw_secondary_series(di.iter().map(|&p| Circle::new(p, 3, red.filled())))
                .map_err(err)?;
        }
        Ok(())
    }
}

/// `(axis value, f(point))` over the points where `f` is finite.
fn series(s: &Summary, f: impl Fn(&crate::reduce::PointStats) -> f64) -> Vec<(f64, f64)> {
    s.points
        .iter()
        .map(|p| (p.values[0], f(p)))
        .filter(|p| p.1.is_finite())
        .collect()
}

impl Chart for DesignChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.0;
        let x = minmax(s.points.iter().map(|p| p.values[0]));
        let x = if x.1 > x.0 { x } else { pad(x.0, x.1, 0.5) };
        let root = root
            .titled(
                "Design chart: reliability, safety factor and damping by zone",
                TITLE,
            )
            .map_err(err)?;
        let (zone_key, rest) = root.split_vertically(LEGEND_ROW);
        legend_row(
            &zone_key,
            (DESIGN_MARGIN + DESIGN_LEFT) as i32,
            &self.zone_keys(),
        )?;
        let h = rest.dim_in_pixel().1 as i32;
        let (top, bottom) = rest.split_vertically(h * 44 / 100);
        self.reliability_panel(&top, x)?;
        self.damping_panel(&bottom, x)
    }
}

struct SpreadChart<'a>(&'a Summary);

impl Chart for SpreadChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.0;
        let one = s.axes.len() == 1;
        let xs: Vec<f64> = s
            .points
            .iter()
            .map(|p| if one { p.values[0] } else { p.point as f64 })
            .collect();
        let (x0, x1) = minmax(xs.iter().copied());
        let step = if xs.len() > 1 {
            (x1 - x0) / (xs.len() - 1) as f64
        } else {
            1.0
        };
        let (x0, x1) = (x0 - step, x1 + step);
        let cm = 100.0;
        let (y0, y1) = minmax(
            s.points
                .iter()
                .flat_map(|p| [p.xmax_min * cm, p.xmax_max * cm]),
        );
        let (y0, y1) = pad(y0, y1, 0.08);
        let mut chart = ChartBuilder::on(root)
            .caption("Spread of xmax over the cases of each design point", TITLE)
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(if one {
                axis_desc(&s.axes[0].0)
            } else {
                "design point index".to_string()
            })
            .y_desc("xmax (cm)")
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        let w = step * 0.35;
        let box_color = RGBColor(31, 119, 180);
        if s.points.len() > MANY {
            return self.bands(&mut chart, &xs);
        }
        let mut first = true;
        for (p, &x) in s.points.iter().zip(&xs) {
            if !p.xmax_min.is_finite() {
                continue;
            }
            let whisker = chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x, p.xmax_min * cm), (x, p.xmax_max * cm)],
                    BLACK.mix(0.7),
                )))
                .map_err(err)?;
            if first {
                whisker
                    .label("min – max")
                    .legend(|(x, y)| PathElement::new(vec![(x + 9, y - 6), (x + 9, y + 6)], BLACK));
            }
            let bx = chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(x - w, p.xmax_q1 * cm), (x + w, p.xmax_q3 * cm)],
                    box_color.mix(0.5).filled(),
                )))
                .map_err(err)?;
            if first {
                bx.label("quartiles").legend(move |(x, y)| {
                    Rectangle::new([(x, y - 6), (x + 18, y + 6)], box_color.mix(0.5).filled())
                });
            }
            let med = chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x - w, p.xmax_median * cm), (x + w, p.xmax_median * cm)],
                    BLACK.stroke_width(2),
                )))
                .map_err(err)?;
            if first {
                med.label("median").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2))
                });
            }
            let ideal = chart
                .draw_series(
                    std::iter::once(p.xmax_ideal)
                        .filter(|v| v.is_finite())
                        .map(|v| Cross::new((x, v * cm), 4, RED.stroke_width(2))),
                )
                .map_err(err)?;
            if first {
                ideal
                    .label("ideal case")
                    .legend(|(x, y)| Cross::new((x + 9, y), 4, RED.stroke_width(2)));
            }
            first = false;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(SMALL)
            .draw()
            .map_err(err)?;
        Ok(())
    }
}

impl SpreadChart<'_> {
    /// Many points: min–max and quartile bands, the median and the ideal case as lines.
    fn bands<'a, DB: DrawingBackend + 'a>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
        xs: &[f64],
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.0;
        let cm = 100.0;
        let pts: Vec<(f64, &crate::reduce::PointStats)> = xs
            .iter()
            .copied()
            .zip(&s.points)
            .filter(|(_, p)| p.xmax_min.is_finite())
            .collect();
        let band = |lo: &dyn Fn(&crate::reduce::PointStats) -> f64,
                    hi: &dyn Fn(&crate::reduce::PointStats) -> f64| {
            pts.iter()
                .map(|(x, p)| (*x, hi(p) * cm))
                .chain(pts.iter().rev().map(|(x, p)| (*x, lo(p) * cm)))
                .collect::<Vec<_>>()
        };
        let blue = RGBColor(31, 119, 180);
        chart
            .draw_series(std::iter::once(Polygon::new(
                band(&|p| p.xmax_min, &|p| p.xmax_max),
                blue.mix(0.2).filled(),
            )))
            .map_err(err)?
            .label("min – max")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 18, y + 6)], blue.mix(0.2).filled())
            });
        chart
            .draw_series(std::iter::once(Polygon::new(
                band(&|p| p.xmax_q1, &|p| p.xmax_q3),
                blue.mix(0.5).filled(),
            )))
            .map_err(err)?
            .label("quartiles")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 18, y + 6)], blue.mix(0.5).filled())
            });
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|(x, p)| (*x, p.xmax_median * cm)),
                BLACK.stroke_width(1),
            ))
            .map_err(err)?
            .label("median")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
        chart
            .draw_series(LineSeries::new(
                pts.iter()
                    .filter(|(_, p)| p.xmax_ideal.is_finite())
                    .map(|(x, p)| (*x, p.xmax_ideal * cm)),
                RED.stroke_width(1),
            ))
            .map_err(err)?
            .label("ideal case")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(SMALL)
            .draw()
            .map_err(err)?;
        Ok(())
    }
}

/// A map over the first two axes: colour by perfectibility, or by zone.
struct MapChart<'a> {
    s: &'a Summary,
    zones: bool,
}

fn heat(t: f64) -> RGBColor {
    // Viridis-like ramp from dark blue to yellow.
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

impl Chart for MapChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.s;
        let (ka, va) = (&s.axes[0].0, &s.axes[0].1);
        let (kb, vb) = (&s.axes[1].0, &s.axes[1].1);
        let edges = |v: &[f64]| -> Vec<f64> {
            let n = v.len();
            let mut e = Vec::with_capacity(n + 1);
            let h = |i: usize| if n > 1 { (v[i + 1] - v[i]) / 2.0 } else { 0.5 };
            e.push(v[0] - h(0));
            for i in 0..n - 1 {
                e.push((v[i] + v[i + 1]) / 2.0);
            }
            e.push(v[n - 1] + h(n.saturating_sub(2)));
            e
        };
        let (ea, eb) = (edges(va), edges(vb));
        let legend_w = if self.zones { 300 } else { 190 };
        let (area, legend_area) = root.split_horizontally(root.dim_in_pixel().0 as i32 - legend_w);
        let title = if self.zones {
            "Zones over the design map"
        } else {
            "Perfectibility P (eq. 11) over the design map"
        };
        let mut chart = ChartBuilder::on(&area)
            .caption(title, TITLE)
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(eb[0]..eb[eb.len() - 1], ea[0]..ea[ea.len() - 1])
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(axis_desc(kb))
            .y_desc(axis_desc(ka))
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .draw()
            .map_err(err)?;
        let (p0, p1) = minmax(s.points.iter().map(|p| p.perfectibility));
        let zone_names: Vec<&str> = s.zones.iter().map(|z| z.name.as_str()).collect();
        for p in &s.points {
            let na = vb.len() as u64;
            let (ia, ib) = ((p.point / na) as usize, (p.point % na) as usize);
            if ia >= va.len() {
                continue;
            }
            let color = if self.zones {
                let zi = zone_names.iter().position(|z| *z == p.zone).unwrap_or(0);
                s.zones
                    .get(zi)
                    .map(|z| {
                        if z.declared {
                            DECLARED[zi % DECLARED.len()]
                        } else {
                            label_color(&z.label)
                        }
                    })
                    .unwrap_or(RGBColor(220, 220, 220))
            } else if p.perfectibility.is_finite() {
                heat((p.perfectibility - p0) / (p1 - p0).max(1e-12))
            } else {
                RGBColor(200, 200, 200)
            };
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(eb[ib], ea[ia]), (eb[ib + 1], ea[ia + 1])],
                    color.filled(),
                )))
                .map_err(err)?;
        }
        // Legend: colour bar or zone list.
        let legend = legend_area.margin(60, 60, 10, 6);
        if self.zones {
            for (i, z) in s.zones.iter().enumerate() {
                let c = if z.declared {
                    DECLARED[i % DECLARED.len()]
                } else {
                    label_color(&z.label)
                };
                let y = 10 + 24 * i as i32;
                legend
                    .draw(&Rectangle::new([(0, y), (16, y + 16)], c.filled()))
                    .map_err(err)?;
                let text = if z.declared {
                    z.name.clone()
                } else {
                    format!("{} – {}", z.name, z.label)
                };
                legend
                    .draw(&Text::new(
                        text,
                        (22, y + 2),
                        ("sans-serif", 17).into_font(),
                    ))
                    .map_err(err)?;
            }
        } else {
            let h = legend.dim_in_pixel().1 as i32 - 40;
            for k in 0..h {
                let t = 1.0 - k as f64 / h as f64;
                legend
                    .draw(&Rectangle::new(
                        [(0, 20 + k), (24, 21 + k)],
                        heat(t).filled(),
                    ))
                    .map_err(err)?;
            }
            legend
                .draw(&Text::new("P (%)", (0, 0), SMALL.into_font()))
                .map_err(err)?;
            legend
                .draw(&Text::new(format!("{p1:.1}"), (30, 14), SMALL.into_font()))
                .map_err(err)?;
            legend
                .draw(&Text::new(
                    format!("{p0:.1}"),
                    (30, 14 + h),
                    SMALL.into_font(),
                ))
                .map_err(err)?;
        }
        Ok(())
    }
}

/// Draws every summary chart into `dir`; returns the files written.
pub fn summary_charts(s: &Summary, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    if s.points.is_empty() || s.axes.is_empty() {
        return Ok(files);
    }
    files.extend(render(dir, "di", (900, 560), &DiChart(s))?);
    if s.axes.len() == 1 {
        files.extend(render(dir, "design_chart", DESIGN_SIZE, &DesignChart(s))?);
    }
    files.extend(render(dir, "xmax_spread", (1000, 560), &SpreadChart(s))?);
    if s.axes.len() >= 2 {
        files.extend(render(
            dir,
            "perfectibility_map",
            (900, 640),
            &MapChart { s, zones: false },
        )?);
        files.extend(render(
            dir,
            "zone_map",
            (1000, 640),
            &MapChart { s, zones: true },
        )?);
    }
    Ok(files)
}

/// One displacement trace: name and (t, x) samples in s and m.
pub struct Trace {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

struct WaveChart<'a> {
    title: String,
    traces: &'a [Trace],
    /// A magnified window (t0, t1) drawn as a second panel.
    zoom: Option<(f64, f64)>,
}

impl WaveChart<'_> {
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        title: &str,
        window: Option<(f64, f64)>,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let inside = |t: f64| window.is_none_or(|(a, b)| t >= a && t <= b);
        let (t0, t1) = window.unwrap_or_else(|| {
            minmax(
                self.traces
                    .iter()
                    .flat_map(|tr| tr.points.iter().map(|p| p.0)),
            )
        });
        let (y0, y1) = minmax(self.traces.iter().flat_map(|tr| {
            tr.points
                .iter()
                .filter(|p| inside(p.0))
                .map(|p| p.1 * 100.0)
        }));
        let (y0, y1) = pad(y0, y1, 0.06);
        let mut chart = ChartBuilder::on(area)
            .caption(title, if window.is_some() { LABEL } else { TITLE })
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(t0..t1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("time t (s)")
            .y_desc("main-mass displacement x (cm)")
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        let colors = [
            RGBColor(31, 119, 180),
            RGBColor(214, 39, 40),
            RGBColor(44, 160, 44),
        ];
        for (i, tr) in self.traces.iter().enumerate() {
            let c = colors[i % colors.len()];
            chart
                .draw_series(LineSeries::new(
                    tr.points
                        .iter()
                        .filter(|p| inside(p.0))
                        .map(|p| (p.0, p.1 * 100.0)),
                    c.stroke_width(2),
                ))
                .map_err(err)?
                .label(tr.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(SMALL)
            .draw()
            .map_err(err)?;
        Ok(())
    }
}

impl Chart for WaveChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        match self.zoom {
            None => self.panel(root, &self.title, None),
            Some(w) => {
                let h = root.dim_in_pixel().1 as i32;
                let (top, bottom) = root.split_vertically(h * 55 / 100);
                self.panel(&top, &self.title, None)?;
                self.panel(
                    &bottom,
                    &format!("first peak magnified (t = {:.4} – {:.4} s)", w.0, w.1),
                    Some(w),
                )
            }
        }
    }
}

/// Draws a waveform chart `<dir>/<stem>.{svg,png}`: the traces over the whole time, and with
/// `zoom` a second panel magnifying that time window.
pub fn waveforms(
    dir: &Path,
    stem: &str,
    title: &str,
    traces: &[Trace],
    zoom: Option<(f64, f64)>,
) -> anyhow::Result<Vec<PathBuf>> {
    let size = if zoom.is_some() {
        (1000, 820)
    } else {
        (1000, 520)
    };
    render(
        dir,
        stem,
        size,
        &WaveChart {
            title: title.to_string(),
            traces,
            zoom,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reliability_gets_a_tight_range_with_the_threshold() {
        // The paper's sweep: R and its interval within 0.972..0.999, r_min = 0.98.
        let r = [0.9972, 0.9963, 0.9981, 0.9797, 0.9725, 0.9868, 0.9990];
        let ((y0, y1), shown) = reliability_range(r, 0.98);
        assert!(shown);
        assert!(y0 < 0.9725 && y1 > 0.999, "{y0}..{y1}");
        // The whole axis is a few hundredths, not the 0.95..1.25 R shared with mu_n before.
        assert!(y1 - y0 < 0.04, "{y0}..{y1}");
        // Room above the data for the zone names: a fifth of the axis or more.
        assert!((y1 - 0.9990) / (y1 - y0) > 0.15, "{y0}..{y1}");
    }

    #[test]
    fn a_far_threshold_does_not_flatten_reliability() {
        let ((y0, y1), shown) = reliability_range([0.99, 0.995, 0.999], 0.5);
        assert!(!shown);
        assert!(y0 > 0.98 && y1 < 1.01, "{y0}..{y1}");
        // Inside the doubled span it is drawn.
        let ((y0, _), shown) = reliability_range([0.99, 0.995, 0.999], 0.985);
        assert!(shown && y0 < 0.985);
    }

    #[test]
    fn flat_or_missing_reliability_keeps_a_usable_axis() {
        // R = 1 everywhere: an axis a few thousandths wide around 1, not a degenerate one.
        let ((y0, y1), shown) = reliability_range([1.0, 1.0], 0.2);
        assert!(!shown);
        assert!(y1 - y0 >= 2e-3 && y0 < 1.0 && y1 > 1.0, "{y0}..{y1}");
        assert_eq!(reliability_range([f64::NAN], 0.98).0, (0.0, 1.0));
    }
}
