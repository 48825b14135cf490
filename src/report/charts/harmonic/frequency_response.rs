//! The harmonic scene's charts (model.md §8): the frequency-response curves of a row of designs
//! with the linear system beside them, and their impacts per forcing period and period of the
//! steady state against the frequency.
//!
//! The designs drawn are a line of the design grid through the recommended design (the best
//! when none is robust) along one design axis, at most [`MAX_CURVES`] of them spread evenly
//! along it; with no design axis, the one curve. Every curve is the ideal case's (noise-free,
//! unperturbed). The amplitude drawn is the design quantity (the worst steady state of the
//! census, or the one from rest with `design_peak = "from_rest"`). Filled markers are periodic
//! steady states (period 1 to 8), hollow ones are not (quasi-periodic, chaotic or not
//! converged). Where the design amplitude is a design-life estimate of a motion that is not
//! periodic, its 90 % interval is drawn as a shaded band (a whisker where the band has a single
//! frequency), and the curve's line joins only the values known to within [`KNOWN`] (periodic
//! steady states, exact; life estimates whose whole interval lies within ±5 % of the value): an
//! uncertain value is a hollow marker inside its band, so that the line shows the physics and
//! the band what the estimator leaves open. The amplitude axis is linear
//! from 0, or logarithmic when the linear system's resonance peak is more than [`LOG_RATIO`]
//! times the smallest damped peak (lightly damped systems with an effective damper).

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, Hovers, Key, LABEL, SMALL, TITLE, err, minmax, pad, plot_builder, tick,
};

use crate::reduce::harmonic::{Curve, HarmonicSummary};
use crate::reduce::{Grid, Summary};
use crate::report::text::{axis_desc, axis_value, count, fmt_num};
use crate::store::table::{Column, Table, axis_column};

/// Curves drawn at most in one chart.
pub const MAX_CURVES: usize = 8;
/// A logarithmic amplitude axis above this ratio of the largest amplitude to the smallest
/// design peak ([`Row::log_scale`]).
pub const LOG_RATIO: f64 = 20.0;
/// A value is drawn on the curve's line when its 90 % interval lies within this relative
/// distance of it: `lo >= (1 - KNOWN) a` and `hi <= (1 + KNOWN) a` ([`known`]).
pub const KNOWN: f64 = 0.05;
/// Opacity of a curve's interval band.
const BAND_ALPHA: f64 = 0.22;
/// Above this many frequencies per curve, no markers.
const MAX_MARKERS: usize = 200;

/// Where the legend starts (pixels from the left).
const LEGEND_X: i32 = 80;

pub const SIZE: (u32, u32) = (1000, 620);
pub const IMPACTS_SIZE: (u32, u32) = (1000, 760);

/// A categorical palette (Tableau 10 without its grey).
const PALETTE: [RGBColor; 9] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The designs a chart draws: their curves, their legend labels and what they share.
pub struct Row<'a> {
    pub f: &'a HarmonicSummary,
    pub curves: Vec<&'a Curve>,
    pub labels: Vec<String>,
    /// The other design axes' values (` at d = 0.01 m`), empty when none.
    pub at: String,
    /// `(key, unit label)` of the x axis: `r` or `omega`.
    pub x: String,
}

impl<'a> Row<'a> {
    /// The designs along design axis `axis` through `through` (or the one design when
    /// `axis` is `None`), at most [`MAX_CURVES`], spread evenly.
    pub fn new(s: &Summary, f: &'a HarmonicSummary, axis: Option<usize>, through: u64) -> Row<'a> {
        let g = &s.grid;
        let mut designs = match axis {
            Some(a) => g.slice(through, &[a]),
            None => vec![through],
        };
        if designs.len() > MAX_CURVES {
            let n = designs.len();
            designs = (0..MAX_CURVES)
                .map(|i| designs[i * (n - 1) / (MAX_CURVES - 1)])
                .collect();
        }
        let curves: Vec<&Curve> = designs.iter().filter_map(|&d| f.curve(d)).collect();
        let labels = curves
            .iter()
            .map(|c| match axis {
                Some(a) => axis_value(g.key(a), g.value(c.design, a)),
                None => "the design".to_string(),
            })
            .collect();
        let at = (0..g.n_axes())
            .filter(|&b| Some(b) != axis)
            .map(|b| axis_value(g.key(b), g.value(through, b)))
            .collect::<Vec<_>>()
            .join(", ");
        let x = f
            .frequency
            .as_ref()
            .map_or("r".to_string(), |(k, _)| k.clone());
        Row {
            f,
            curves,
            labels,
            at: if at.is_empty() {
                String::new()
            } else {
                format!(" at {at}")
            },
            x,
        }
    }

    fn xs(&self, c: &Curve) -> Vec<f64> {
        c.points
            .iter()
            .map(|p| if self.x == "omega" { p.omega } else { p.r })
            .collect()
    }

    fn x_range(&self) -> (f64, f64) {
        let (x0, x1) = minmax(self.curves.iter().flat_map(|c| self.xs(c)));
        if x1 > x0 { (x0, x1) } else { pad(x0, x1, 0.5) }
    }

    fn x_desc(&self) -> String {
        if self.x == "omega" {
            axis_desc("omega")
        } else {
            "frequency ratio r = omega / sqrt(K/M) (–)".to_string()
        }
    }

    /// Whether the amplitude axis is logarithmic: when the largest amplitude drawn (the linear
    /// system's resonance, usually) is more than [`LOG_RATIO`] times the smallest design peak, a
    /// linear axis would flatten the damped curves onto the floor.
    pub fn log_scale(&self) -> bool {
        let peaks = self.curves.iter().map(|c| c.peak().0);
        let (lo, _) = minmax(peaks);
        let (_, hi) = minmax(self.curves.iter().flat_map(|c| {
            c.points
                .iter()
                .flat_map(|p| [p.design, p.linear])
                .collect::<Vec<_>>()
        }));
        lo > 0.0 && hi / lo > LOG_RATIO
    }

    /// Whether every curve has the same linear system (then it is drawn once).
    fn one_linear(&self) -> bool {
        self.curves.windows(2).all(|w| {
            w[0].points.len() == w[1].points.len()
                && w[0]
                    .points
                    .iter()
                    .zip(&w[1].points)
                    .all(|(a, b)| a.linear.to_bits() == b.linear.to_bits())
        })
    }

    /// The chart's data: one row per run drawn.
    pub fn data(&self, s: &Summary) -> Table {
        let g: &Grid = &s.grid;
        let rows: Vec<(u64, &crate::reduce::harmonic::CurvePoint)> = self
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(move |p| (c.design, p)))
            .collect();
        let f = |h: &dyn Fn(&crate::reduce::harmonic::CurvePoint) -> f64| {
            Column::F64(rows.iter().map(|(_, p)| h(p)).collect())
        };
        let mut t = Table::default();
        t.push(
            "point",
            Column::U64(rows.iter().map(|(d, _)| Some(*d)).collect()),
        );
        for a in 0..g.n_axes() {
            t.push(
                axis_column(g.key(a)),
                Column::F64(rows.iter().map(|(d, _)| g.value(*d, a)).collect()),
            );
        }
        t.push("r", f(&|p| p.r));
        t.push("omega", f(&|p| p.omega));
        t.push(
            "outcome",
            Column::Str(rows.iter().map(|(_, p)| p.outcome.name().into()).collect()),
        );
        t.push("amplitude", f(&|p| p.amplitude));
        t.push("amplitude_design", f(&|p| p.design));
        t.push(
            "design_period",
            Column::U64(
                rows.iter()
                    .map(|(_, p)| Some(u64::from(p.design_period)))
                    .collect(),
            ),
        );
        t.push("amplitude_linear", f(&|p| p.linear));
        t.push("attenuation", f(&|p| p.attenuation));
        t.push("impacts_per_period", f(&|p| p.impacts_per_period));
        t.push(
            "period",
            Column::U64(
                rows.iter()
                    .map(|(_, p)| Some(u64::from(p.period)))
                    .collect(),
            ),
        );
        t.push(
            "converged",
            Column::Bool(rows.iter().map(|(_, p)| p.converged).collect()),
        );
        // The design amplitude's 90 % life interval (NaN where it is no life estimate) and
        // whether the value is on the drawn line ([`known`]).
        let life: Vec<Option<(f64, f64)>> = self
            .curves
            .iter()
            .flat_map(|c| (0..c.points.len()).map(move |i| life_interval(c, i)))
            .collect();
        t.push(
            "life_lo",
            Column::F64(life.iter().map(|l| l.map_or(f64::NAN, |l| l.0)).collect()),
        );
        t.push(
            "life_hi",
            Column::F64(life.iter().map(|l| l.map_or(f64::NAN, |l| l.1)).collect()),
        );
        t.push(
            "known",
            Column::Bool(
                self.curves
                    .iter()
                    .flat_map(|c| (0..c.points.len()).map(move |i| known(c, i)))
                    .collect(),
            ),
        );
        t
    }
}

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Draws a curve's markers: filled where the steady state is periodic, hollow where not.
fn markers<DB: DrawingBackend, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    pts: &[(f64, f64, bool)],
    c: RGBColor,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    if pts.len() > MAX_MARKERS {
        return Ok(());
    }
    chart
        .draw_series(pts.iter().map(|&(x, y, periodic)| {
            let style = if periodic {
                c.filled()
            } else {
                c.stroke_width(1)
            };
            Circle::new((x, y), 3, style)
        }))
        .map_err(err)?;
    Ok(())
}

/// The legend's keys: one per design, and the linear system when it is drawn.
fn legend_items(row: &Row, linear: bool) -> Vec<(Key, String)> {
    let mut items: Vec<(Key, String)> = row
        .labels
        .iter()
        .enumerate()
        .map(|(i, l)| (Key::LineDot(color(i)), l.clone()))
        .collect();
    if linear && row.curves.iter().any(|c| !intervals(c).is_empty()) {
        items.push((
            Key::Swatch(BLACK.mix(BAND_ALPHA)),
            format!(
                "90 % interval over the design life of a motion that is not periodic; \
                 the line joins values known to ±{} %",
                fmt_num(KNOWN * 100.0)
            ),
        ));
    }
    if linear {
        items.push((
            Key::Dashed(BLACK),
            if row.one_linear() {
                "linear system (no inner mass)".to_string()
            } else {
                "linear systems (dashed, same colours)".to_string()
            },
        ));
    }
    items
}

/// Splits the legend off the top of `area` (one row, or as many as its keys need) and draws it;
/// returns the rest.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    row: &Row,
    linear: bool,
) -> anyhow::Result<DrawingArea<DB, Shift>>
where
    DB::ErrorType: 'static,
{
    crate::report::charts::plumbing::legend_block(area, LEGEND_X, &legend_items(row, linear))
}

/// Amplitude against the frequency, with the linear system; every point a hover target.
pub struct FrequencyResponse<'a>(pub &'a Row<'a>, pub Hovers);

impl Chart for FrequencyResponse<'_> {
    fn hovers(&self) -> Option<&Hovers> {
        Some(&self.1)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let row = self.0;
        let (title, rest) = root.split_vertically(40);
        let plot = legend(&rest, row, true)?;
        title
            .titled(
                &format!("Design steady amplitude against {}{}", row.x, row.at),
                TITLE,
            )
            .map_err(err)?;
        let (x0, x1) = row.x_range();
        let (lo, hi) = minmax(
            row.curves
                .iter()
                .flat_map(|c| {
                    c.points
                        .iter()
                        .flat_map(|p| [p.design * CM, p.linear * CM])
                        .chain(
                            intervals(c)
                                .into_iter()
                                .flat_map(|(_, l, h)| [l * CM, h * CM]),
                        )
                        .chain(
                            linear_line(row, c, &row.xs(c))
                                .into_iter()
                                .map(|(_, a)| a * CM),
                        )
                })
                .filter(|v| *v > 0.0),
        );
        if row.log_scale() && lo > 0.0 && hi > lo {
            let mut chart = plot_builder(&plot, 48)
                .build_cartesian_2d(x0..x1, (lo / 1.5..hi * 1.5).log_scale())
                .map_err(err)?;
            chart
                .configure_mesh()
                .x_desc(row.x_desc())
                .x_label_formatter(&tick)
                .y_desc("steady amplitude (cm), log scale")
                .y_labels(8)
                .y_label_formatter(&|v: &f64| fmt_num(*v))
                .label_style(SMALL)
                .axis_desc_style(LABEL)
                .light_line_style(TRANSPARENT)
                .draw()
                .map_err(err)?;
            curves(&mut chart, row, &self.1)
        } else {
            let top = if hi.is_finite() { hi * 1.08 } else { 1.0 };
            let mut chart = plot_builder(&plot, 48)
                .build_cartesian_2d(x0..x1, 0.0..top)
                .map_err(err)?;
            chart
                .configure_mesh()
                .x_desc(row.x_desc())
                .x_label_formatter(&tick)
                .y_desc("steady amplitude (cm)")
                .y_label_formatter(&|v: &f64| fmt_num(*v))
                .label_style(SMALL)
                .axis_desc_style(LABEL)
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(err)?;
            curves(&mut chart, row, &self.1)
        }
    }
}

/// Metres to centimetres.
const CM: f64 = 100.0;

/// Draws the curves of `row` (amplitude in cm) and the linear system, on a linear or a
/// logarithmic y axis.
fn curves<DB: DrawingBackend, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    row: &Row,
    hovers: &Hovers,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    let one = row.one_linear();
    for (i, c) in row.curves.iter().enumerate() {
        let xs = row.xs(c);
        if i == 0 || !one {
            let lc = if one { BLACK } else { color(i) };
            let lin: Vec<(f64, f64)> = linear_line(row, c, &xs)
                .into_iter()
                .map(|(x, a)| (x, a * CM))
                .filter(|p| p.1 > 0.0)
                .collect();
            chart
                .draw_series(DashedLineSeries::new(lin, 6, 4, lc.stroke_width(2)))
                .map_err(err)?;
        }
        bands(chart, &xs, c, color(i))?;
        let drawn: Vec<(usize, f64, f64, bool)> = xs
            .iter()
            .zip(&c.points)
            .enumerate()
            .filter(|(_, (_, p))| p.design > 0.0 && p.design.is_finite())
            .map(|(j, (&x, p))| (j, x, p.design * CM, p.design_period >= 1))
            .collect();
        for run in known_runs(c, &drawn) {
            chart
                .draw_series(LineSeries::new(run, color(i).stroke_width(2)))
                .map_err(err)?;
        }
        let pts: Vec<(f64, f64, bool)> = drawn.iter().map(|&(_, x, y, p)| (x, y, p)).collect();
        markers(chart, &pts, color(i))?;
        for (j, p) in c.points.iter().enumerate() {
            if p.design > 0.0 && p.design.is_finite() {
                let at = chart.backend_coord(&(xs[j], p.design * CM));
                hovers.point(at, 5, point_text(row, i, c, j));
            }
        }
    }
    Ok(())
}

/// The hover text of point `j` of curve `i` of the row: the design, the frequency, the design
/// amplitude with its kind (and interval), the period and the impacts per period.
fn point_text(row: &Row, i: usize, c: &Curve, j: usize) -> String {
    let p = &c.points[j];
    let kind = match c.design_attractor(j) {
        Some(a) if !a.kind.periodic() && a.life_lo.is_finite() => format!(
            "{}; over the design life, 90 % interval [{} – {}] cm from {}{}",
            a.kind.name(),
            fmt_num(a.life_lo.min(a.amplitude) * CM),
            fmt_num(a.life_hi * CM),
            count(a.measured_periods, "period", "periods"),
            if a.life_capped { ", capped" } else { "" }
        ),
        Some(a) => a.kind.name().to_string(),
        None if p.design_period >= 1 => "periodic".to_string(),
        None => "not periodic".to_string(),
    };
    format!(
        "{}{}\nr = {}, omega = {} rad/s\namplitude {} cm ({kind})\nperiod {}, {} impacts per period\nlinear system {} cm",
        row.labels[i],
        row.at,
        fmt_num(p.r),
        fmt_num(p.omega),
        fmt_num(p.design * CM),
        if p.design_period >= 1 {
            p.design_period.to_string()
        } else {
            "none".to_string()
        },
        fmt_num(p.design_impacts),
        fmt_num(p.linear * CM)
    )
}

/// The linear system of `c` against the row's x axis (`xs`, its points' x): in closed form on a
/// fine grid when the axis is the frequency (`r` or `omega`), else through the points.
fn linear_line(row: &Row, c: &Curve, xs: &[f64]) -> Vec<(f64, f64)> {
    let (r0, r1) = minmax(c.points.iter().map(|p| p.r));
    let scale = match (row.x.as_str(), c.points.first()) {
        ("r", _) => Some(1.0),
        ("omega", Some(p)) if p.r > 0.0 => Some(p.omega / p.r),
        _ => None,
    };
    match scale {
        Some(k) if r1 > r0 => c
            .linear_line(r0, r1, 600)
            .into_iter()
            .map(|(r, a)| (r * k, a))
            .collect(),
        _ => xs
            .iter()
            .zip(&c.points)
            .map(|(&x, p)| (x, p.linear))
            .collect(),
    }
}

/// The 90 % design-life interval `(lo, hi)` (m) of point `i` of `c` when its design amplitude
/// is carried by a motion that is not periodic with a measured life interval.
fn life_interval(c: &Curve, i: usize) -> Option<(f64, f64)> {
    let a = c.design_attractor(i)?;
    (!a.kind.periodic() && a.life_lo.is_finite() && a.life_hi.is_finite())
        .then_some((a.life_lo.min(a.amplitude), a.life_hi))
}

/// The points of `c` with a life interval ([`life_interval`]): `(index, lo, hi)` in metres.
fn intervals(c: &Curve) -> Vec<(usize, f64, f64)> {
    (0..c.points.len())
        .filter_map(|i| life_interval(c, i).map(|(lo, hi)| (i, lo, hi)))
        .collect()
}

/// Whether point `i` of `c` is known to within [`KNOWN`]: a value without a life interval (a
/// periodic steady state is exact; a motion without a census has no interval to weigh), or one
/// whose whole interval lies within `±KNOWN` of it.
pub fn known(c: &Curve, i: usize) -> bool {
    let v = c.points[i].design;
    life_interval(c, i).is_none_or(|(lo, hi)| lo >= (1.0 - KNOWN) * v && hi <= (1.0 + KNOWN) * v)
}

/// The stretches of the curve's line: the runs of consecutive drawn points (`drawn`: index in
/// the curve, x, y, periodic) that are known ([`known`]); a stretch of one point is left to its
/// marker.
fn known_runs(c: &Curve, drawn: &[(usize, f64, f64, bool)]) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut last: Option<usize> = None;
    for &(j, x, y, _) in drawn {
        if !known(c, j) {
            last = None;
            continue;
        }
        match (last, runs.last_mut()) {
            (Some(k), Some(run)) if k + 1 == j => run.push((x, y)),
            _ => runs.push(vec![(x, y)]),
        }
        last = Some(j);
    }
    runs.retain(|r| r.len() >= 2);
    runs
}

/// Draws the 90 % intervals of the design amplitudes of `c` that are life estimates: a shaded
/// band over every run of neighbouring frequencies that have one, its edges in the curve's
/// colour; a single frequency, a bar with caps.
fn bands<DB: DrawingBackend, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    xs: &[f64],
    c: &Curve,
    colour: RGBColor,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    let all = intervals(c);
    let mut runs: Vec<Vec<(usize, f64, f64)>> = Vec::new();
    for &(i, lo, hi) in &all {
        match runs.last_mut() {
            Some(run) if run.last().is_some_and(|l| l.0 + 1 == i) => run.push((i, lo, hi)),
            _ => runs.push(vec![(i, lo, hi)]),
        }
    }
    let edge = colour.mix(0.6).stroke_width(1);
    for run in runs {
        let (x, lo, hi): (Vec<f64>, Vec<f64>, Vec<f64>) = run
            .iter()
            .map(|&(i, lo, hi)| (xs[i], lo * CM, hi * CM))
            .fold((vec![], vec![], vec![]), |mut v, (x, l, h)| {
                v.0.push(x);
                v.1.push(l);
                v.2.push(h);
                v
            });
        if run.len() == 1 {
            whisker(chart, x[0], lo[0], hi[0], colour.stroke_width(1))?;
            continue;
        }
        let outline: Vec<(f64, f64)> = x
            .iter()
            .zip(&hi)
            .map(|(&x, &h)| (x, h))
            .chain(x.iter().zip(&lo).rev().map(|(&x, &l)| (x, l)))
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(
                outline,
                colour.mix(BAND_ALPHA).filled(),
            )))
            .map_err(err)?;
        for edge_line in [&hi, &lo] {
            chart
                .draw_series(LineSeries::new(
                    x.iter().copied().zip(edge_line.iter().copied()),
                    edge,
                ))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// A bar from `lo` to `hi` at `x`, with caps.
fn whisker<DB: DrawingBackend, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    x: f64,
    lo: f64,
    hi: f64,
    style: ShapeStyle,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(x, lo), (x, hi)],
            style,
        )))
        .map_err(err)?;
    chart
        .draw_series(
            [lo, hi]
                .map(|y| EmptyElement::at((x, y)) + PathElement::new(vec![(-4, 0), (4, 0)], style)),
        )
        .map_err(err)?;
    Ok(())
}

/// Impacts per forcing period (top) and the period of the steady state (bottom) against the
/// frequency.
pub struct ImpactsAndPeriod<'a>(pub &'a Row<'a>);

impl Chart for ImpactsAndPeriod<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let row = self.0;
        let (title, rest) = root.split_vertically(40);
        let plots = legend(&rest, row, false)?;
        title
            .titled(
                &format!(
                    "Impacts per forcing period and period of the steady state reached from rest{}",
                    row.at
                ),
                TITLE,
            )
            .map_err(err)?;
        let (top, bottom) = plots.split_vertically(plots.dim_in_pixel().1 * 3 / 5);
        impacts_panel(&top, row)?;
        period_panel(&bottom, row)
    }
}

/// The top panel of [`ImpactsAndPeriod`]: impacts per forcing period, one line per curve, the
/// periodic points filled.
fn impacts_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, row: &Row) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let (x0, x1) = row.x_range();
    let (_, i1) = minmax(
        row.curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| p.impacts_per_period)),
    );
    let i1 = if i1.is_finite() && i1 > 0.0 {
        i1 * 1.1
    } else {
        1.0
    };
    let mut chart = plot_builder(area, 30)
        .build_cartesian_2d(x0..x1, 0.0..i1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .y_desc("impacts per forcing period")
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(SMALL)
        .axis_desc_style(LABEL)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    for (i, c) in row.curves.iter().enumerate() {
        let pts: Vec<(f64, f64, bool)> = row
            .xs(c)
            .iter()
            .zip(&c.points)
            .filter(|(_, p)| p.impacts_per_period.is_finite())
            .map(|(&x, p)| (x, p.impacts_per_period, p.period >= 1))
            .collect();
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|&(x, y, _)| (x, y)),
                color(i).stroke_width(2),
            ))
            .map_err(err)?;
        markers(&mut chart, &pts, color(i))?;
    }
    Ok(())
}

/// The bottom panel of [`ImpactsAndPeriod`]: the period of the steady state, 1 to 8, and 0 for
/// none (not periodic), each design a little apart so that equal periods stay visible.
fn period_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, row: &Row) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let (x0, x1) = row.x_range();
    let mut chart = plot_builder(area, 48)
        .build_cartesian_2d(x0..x1, -0.6..8.6)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(row.x_desc())
        .x_label_formatter(&tick)
        .y_desc("period (forcing periods)")
        .y_labels(10)
        .y_label_formatter(&|v: &f64| {
            let k = v.round();
            if (v - k).abs() > 1e-9 || !(0.0..=8.0).contains(&k) {
                String::new()
            } else if k == 0.0 {
                "none".to_string()
            } else {
                format!("{k}")
            }
        })
        .label_style(SMALL)
        .axis_desc_style(LABEL)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    let n = row.curves.len().max(1) as f64;
    for (i, c) in row.curves.iter().enumerate() {
        let dy = 0.36 * (i as f64 - (n - 1.0) / 2.0) / n;
        let pts: Vec<(f64, f64, bool)> = row
            .xs(c)
            .iter()
            .zip(&c.points)
            .filter(|(_, p)| p.outcome == crate::sim::Outcome::Ok)
            .map(|(&x, p)| (x, f64::from(p.period) + dy, p.period >= 1))
            .collect();
        chart
            .draw_series(pts.iter().map(|&(x, y, periodic)| {
                let style = if periodic {
                    color(i).filled()
                } else {
                    color(i).stroke_width(1)
                };
                Circle::new((x, y), 3, style)
            }))
            .map_err(err)?;
    }
    Ok(())
}

/// Draws the harmonic scene's charts into `dir`: `frequency_response` and `impacts_per_period`
/// (with two or more swept design axes, `frequency_response_<axis>` and
/// `impacts_per_period_<axis>` along each, through the recommended design). Returns the files
/// written (SVG, PNG and CSV of each).
pub fn charts(
    s: &Summary,
    f: &HarmonicSummary,
    steady: &[crate::orbits::response::Response],
    samples: &[crate::reduce::harmonic::steady::SectionSample],
    dir: &std::path::Path,
) -> anyhow::Result<Vec<std::path::PathBuf>> {
    let mut files = Vec::new();
    let Some(anchor) = s.anchor() else {
        return Ok(files);
    };
    let g = &s.grid;
    let swept: Vec<usize> = (0..g.n_axes()).filter(|&a| g.n(a) >= 2).collect();
    let lines: Vec<(Option<usize>, String)> = match swept.as_slice() {
        [] => vec![(None, String::new())],
        [a] => vec![(Some(*a), String::new())],
        many => many
            .iter()
            .map(|&a| (Some(a), format!("_{}", axis_column(g.key(a)))))
            .collect(),
    };
    // At one frequency there is no frequency axis to draw against (a study along the force has
    // its own charts below; one over design axes has the design chart).
    let lines = if f.frequency.is_some() {
        lines
    } else {
        Vec::new()
    };
    for (axis, suffix) in lines {
        let row = Row::new(s, f, axis, anchor);
        if row.curves.is_empty() {
            continue;
        }
        files.extend(crate::report::charts::plumbing::render(
            dir,
            &format!("frequency_response{suffix}"),
            SIZE,
            &FrequencyResponse(&row, Hovers::default()),
            &crate::report::charts::plumbing::Data::Table(row.data(s)),
        )?);
        files.extend(crate::report::charts::plumbing::render(
            dir,
            &format!("impacts_per_period{suffix}"),
            IMPACTS_SIZE,
            &ImpactsAndPeriod(&row),
            &crate::report::charts::plumbing::Data::Table(row.data(s)),
        )?);
    }
    // The steady-state charts: against the frequency, or against F0 for a study at one
    // frequency that sweeps the force (the response of the anchor's group of forces).
    let found = steady
        .iter()
        .find(|r| crate::reduce::harmonic::steady::draws_anchor(f, anchor, r));
    if let Some(r) = found {
        files.extend(super::steady_states::charts(s, f, r, anchor, samples, dir)?);
    }
    Ok(files)
}
