//! The speed/accuracy chart of `impactsweep tradeoff`: error against wall time per run, both
//! axes logarithmic, one line per solver through its knob ladder, the SciPy peer as single
//! markers, and the 0.1 % goal as a dashed line. Written as SVG and PNG (the PNG's text uses the
//! bundled DejaVu Sans, so it renders the same on any machine).

use std::path::Path;

use plotters::coord::combinators::LogCoord;
use plotters::prelude::*;

/// One solver's points `(time per run in s, relative error)`, in ladder order.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// Draw markers only (a peer measured at one setting).
    pub peer: bool,
}

/// Errors below this are drawn on it (an exact match would be off a log axis).
pub const FLOOR: f64 = 1e-16;

/// Draws `series` to `STEM.svg` and `STEM.png`; `goal` is drawn as a horizontal line; `axes`
/// names the time (horizontal) and the error (vertical).
pub fn draw(series: &[Series], goal: f64, axes: (&str, &str), stem: &Path) -> anyhow::Result<()> {
    // The one embedded font, shared with the other charts (its bytes are included once).
    crate::report::charts::register_fonts();
    let svg = stem.with_extension("svg");
    let png = stem.with_extension("png");
    plot(
        SVGBackend::new(&svg, (960, 640)).into_drawing_area(),
        series,
        goal,
        axes,
    )
    .map_err(|e| anyhow::anyhow!("drawing {}: {e}", svg.display()))?;
    plot(
        BitMapBackend::new(&png, (960, 640)).into_drawing_area(),
        series,
        goal,
        axes,
    )
    .map_err(|e| anyhow::anyhow!("drawing {}: {e}", png.display()))?;
    Ok(())
}

fn plot<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    series: &[Series],
    goal: f64,
    (x_desc, y_desc): (&str, &str),
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let ((x0, x1), (y0, y1)) = ranges(series, goal);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Speed against accuracy (lower left is better)",
            ("sans-serif", 24),
        )
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    chart
        .draw_series(DashedLineSeries::new(
            [(x0, goal), (x1, goal)],
            6,
            4,
            BLACK.mix(0.5).stroke_width(1),
        ))?
        .label(format!("goal: {} %", goal * 100.0))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.5)));
    for (i, s) in series.iter().enumerate() {
        draw_series(&mut chart, s, PALETTE[i % PALETTE.len()])?;
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperMiddle)
        .draw()?;
    root.present()?;
    Ok(())
}

/// The axes' ranges `((x0, x1), (y0, y1))` around every finite point (errors floored at
/// [`FLOOR`]) and the goal, with room: half and twice the times, a fifth of the lowest error,
/// and four decades above the highest for the legend.
fn ranges(series: &[Series], goal: f64) -> ((f64, f64), (f64, f64)) {
    let pts = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0.is_finite() && p.0 > 0.0 && p.1.is_finite())
            .map(|&(t, e)| (t, e.max(FLOOR)))
    };
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, goal, goal);
    for (t, e) in pts() {
        x0 = x0.min(t);
        x1 = x1.max(t);
        y0 = y0.min(e);
        y1 = y1.max(e);
    }
    if !x0.is_finite() {
        (x0, x1) = (1e-6, 1e-3);
    }
    let (x0, x1) = (x0 / 2.0, x1 * 2.0);
    // Four decades of room above the highest point hold the legend.
    let (y0, y1) = (y0 / 5.0, y1 * 1e4);
    ((x0, x1), (y0, y1))
}

/// A solver's colours, in the series' order.
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

/// One series in `color`: a peer as triangles, a solver as a line through dots.
fn draw_series<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, LogChart>,
    s: &Series,
    color: RGBColor,
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let points: Vec<(f64, f64)> = s
        .points
        .iter()
        .filter(|p| p.0.is_finite() && p.0 > 0.0 && p.1.is_finite())
        .map(|&(t, e)| (t, e.max(FLOOR)))
        .collect();
    if s.peer {
        chart
            .draw_series(
                points
                    .iter()
                    .map(|&p| TriangleMarker::new(p, 9, color.filled())),
            )?
            .label(s.name.clone())
            .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 7, color.filled()));
    } else {
        chart
            .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))?
            .label(s.name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))?;
    }
    Ok(())
}

/// The chart's coordinates: both axes logarithmic.
type LogChart = Cartesian2d<LogCoord<f64>, LogCoord<f64>>;
