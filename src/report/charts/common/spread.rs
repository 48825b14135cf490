//! The spread of the response over the cases of each design point along one axis: box plots
//! (min–max whiskers, quartile boxes, median) and the ideal case, or bands above
//! [`MANY`] points; the located jumps marked. With several axes it is drawn along each axis through the recommended
//! design.

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    BLUE, Chart, MANY, Plot, Profile, TITLE, err, minmax, pad, series_legend, xy_chart,
};

use crate::reduce::ResponseStats;
use crate::report::text::axis_desc;

/// The spread along a profile, and a limit of the response (m) drawn across it (a load study's
/// threshold), if any.
pub struct SpreadChart<'a>(pub &'a Profile<'a>, pub Option<f64>);

pub const SIZE: (u32, u32) = (1000, 560);

impl Chart for SpreadChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let pr = self.0;
        let name = pr.s.options.response.name;
        let xs = &pr.positions();
        let ((x0, x1), halves) = x_layout(xs);
        let cm = 100.0;
        let values = || {
            pr.points
                .iter()
                .flat_map(|p| [p.response.min * cm, p.response.max * cm])
        };
        let limit = self.1.map(|b| b * cm);
        let top = minmax(values()).1;
        let drawn = limit_drawn(limit, top);
        let (y0, y1) = minmax(values().chain(drawn));
        let (y0, y1) = pad(y0, y1, 0.08);
        let title = format!(
            "Spread of {name} over the cases along {}{}",
            pr.key(),
            pr.at()
        );
        let mut chart = xy_chart(
            root,
            (&title, TITLE),
            (x0..x1, y0..y1),
            (&axis_desc(pr.key()), &format!("{name} (cm)")),
            (&pr.xs, pr.scale),
        )?;
        super::di::jump_lines(&mut chart, pr, (y0, y1))?;
        match (limit, drawn) {
            (Some(b), Some(_)) => draw_limit(&mut chart, b, (x0, x1))?,
            (Some(b), None) => limit_above(&mut chart, b, top)?,
            _ => {}
        }
        if pr.points.len() > MANY {
            return self.bands(&mut chart);
        }
        draw_boxes(&mut chart, pr, (xs, &halves))?;
        let corner = legend_corner(pr, (xs, &halves), (x0, x1));
        series_legend(&mut chart, corner)?;
        Ok(())
    }
}

/// A limit is drawn across the spread when it lies within this many times the largest value
/// drawn; farther up the axis would squash the boxes to a line at its foot, and the legend
/// names the limit instead.
const LIMIT_REACH: f64 = 3.0;

/// The limit (cm) when the axis reaches it: within [`LIMIT_REACH`] times `top`, the largest
/// value drawn, and always when nothing finite is drawn.
fn limit_drawn(limit: Option<f64>, top: f64) -> Option<f64> {
    limit.filter(|&b| !(top.is_finite() && top > 0.0) || b <= LIMIT_REACH * top)
}

/// A limit `y` (cm) above the chart: a legend entry that names it and how far above the
/// largest value drawn (`top`) it lies.
fn limit_above<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    y: f64,
    top: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let red = RED;
    chart
        .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
        .map_err(err)?
        .label(format!(
            "limit {y:.3} cm, above the chart ({:.0} × the largest)",
            y / top
        ))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], red.stroke_width(2)));
    Ok(())
}

/// A limit of the response `y` (cm) as a red dashed line across `(x0, x1)`.
fn draw_limit<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    y: f64,
    (x0, x1): (f64, f64),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let red = RED;
    chart
        .draw_series(DashedLineSeries::new(
            [(x0, y), (x1, y)],
            8,
            5,
            red.stroke_width(2),
        ))
        .map_err(err)?
        .label(format!("limit {y:.3} cm"))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], red.stroke_width(2)));
    Ok(())
}

/// Each point's box at `xs` (half widths `halves`): min–max whisker, quartile box, median and
/// the ideal case's cross, the legend's entries from the first drawn.
fn draw_boxes<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plot<'a, DB>,
    pr: &Profile,
    (xs, halves): (&[f64], &[f64]),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let cm = 100.0;
    let box_color = BLUE;
    let any_ideal = pr.points.iter().any(|p| p.response.ideal.is_finite());
    let mut first = true;
    for (i, (p, &x)) in pr.points.iter().zip(xs).enumerate() {
        let p = &p.response;
        let w = halves[i];
        if !p.min.is_finite() {
            continue;
        }
        let whisker = chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x, p.min * cm), (x, p.max * cm)],
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
                [(x - w, p.q1 * cm), (x + w, p.q3 * cm)],
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
                vec![(x - w, p.median * cm), (x + w, p.median * cm)],
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
                std::iter::once(p.ideal)
                    .filter(|v| v.is_finite())
                    .map(|v| Cross::new((x, v * cm), 4, RED.stroke_width(2))),
            )
            .map_err(err)?;
        if first && any_ideal {
            ideal
                .label("ideal case")
                .legend(|(x, y)| Cross::new((x + 9, y), 4, RED.stroke_width(2)));
        }
        first = false;
    }
    Ok(())
}

/// The upper corner for the boxes' legend: the left one unless the boxes and whiskers reach
/// higher within the left fifth of the axis than within the right fifth (where the legend
/// would hide the first box's whisker).
fn legend_corner(
    pr: &Profile,
    (xs, halves): (&[f64], &[f64]),
    (x0, x1): (f64, f64),
) -> SeriesLabelPosition {
    let fifth = 0.2 * (x1 - x0);
    let top_within = |lo: f64, hi: f64| {
        pr.points
            .iter()
            .zip(xs)
            .zip(halves)
            .filter(|((_, x), w)| **x + **w >= lo && **x - **w <= hi)
            .map(|((p, _), _)| p.response.max)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    if top_within(x1 - fifth, x1) < top_within(x0, x0 + fifth) {
        SeriesLabelPosition::UpperRight
    } else {
        SeriesLabelPosition::UpperLeft
    }
}

/// The x axis's range, with room beyond each end, and each box's half width: 0.35 of the grid
/// step, or on an uneven grid (a geometric one) 0.35 of the distance to the nearer neighbour,
/// so that boxes never overlap. The room is a grid step, or on an uneven grid the end's own gap
/// (the mean step would leave an empty stretch before a geometric grid's first value).
fn x_layout(xs: &[f64]) -> ((f64, f64), Vec<f64>) {
    let (x0, x1) = minmax(xs.iter().copied());
    let step = if xs.len() > 1 {
        (x1 - x0) / (xs.len() - 1) as f64
    } else {
        1.0
    };
    let gaps: Vec<f64> = xs.windows(2).map(|g| (g[1] - g[0]).abs()).collect();
    let uneven = gaps.iter().copied().fold(0.0, f64::max)
        > 1.01 * gaps.iter().copied().fold(f64::INFINITY, f64::min);
    let mut sorted = xs.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let range = if uneven && n > 1 {
        (
            x0 - (sorted[1] - sorted[0]),
            x1 + (sorted[n - 1] - sorted[n - 2]),
        )
    } else {
        (x0 - step, x1 + step)
    };
    let halves = (0..xs.len())
        .map(|i| {
            let near = [i.checked_sub(1).map(|j| gaps[j]), gaps.get(i).copied()]
                .into_iter()
                .flatten()
                .fold(f64::INFINITY, f64::min);
            if uneven && near.is_finite() {
                near * 0.35
            } else {
                step * 0.35
            }
        })
        .collect();
    (range, halves)
}

impl SpreadChart<'_> {
    /// Many points: min–max and quartile bands, the median and the ideal case as lines.
    fn bands<'a, DB: DrawingBackend + 'a>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let pr = self.0;
        let cm = 100.0;
        let line = |f: fn(&ResponseStats) -> f64| pr.series(|p| f(&p.response) * cm);
        let band = |lo: fn(&ResponseStats) -> f64, hi: fn(&ResponseStats) -> f64| {
            let mut b = line(hi);
            b.extend(line(lo).into_iter().rev());
            b
        };
        let blue = BLUE;
        chart
            .draw_series(std::iter::once(Polygon::new(
                band(|p| p.min, |p| p.max),
                blue.mix(0.2).filled(),
            )))
            .map_err(err)?
            .label("min – max")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 18, y + 6)], blue.mix(0.2).filled())
            });
        chart
            .draw_series(std::iter::once(Polygon::new(
                band(|p| p.q1, |p| p.q3),
                blue.mix(0.5).filled(),
            )))
            .map_err(err)?
            .label("quartiles")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 18, y + 6)], blue.mix(0.5).filled())
            });
        chart
            .draw_series(LineSeries::new(line(|p| p.median), BLACK.stroke_width(1)))
            .map_err(err)?
            .label("median")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
        chart
            .draw_series(LineSeries::new(line(|p| p.ideal), RED.stroke_width(1)))
            .map_err(err)?
            .label("ideal case")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED));
        series_legend(chart, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{limit_drawn, x_layout};

    /// A limit far above the spread is named, not drawn; one within reach is drawn.
    #[test]
    fn a_far_limit_does_not_squash_the_spread() {
        assert_eq!(limit_drawn(Some(5.0), 0.11), None);
        assert_eq!(limit_drawn(Some(0.994), 2.0), Some(0.994));
        assert_eq!(limit_drawn(Some(3.0), 1.0), Some(3.0));
        assert_eq!(limit_drawn(Some(5.0), f64::NAN), Some(5.0));
        assert_eq!(limit_drawn(None, 1.0), None);
    }

    #[test]
    fn a_geometric_grid_gets_its_own_ends_room_and_boxes_that_never_overlap() {
        // The seismic showcases' clearances: room of 5 mm before the first (the mean step,
        // 11.7 mm, reached below zero) and 20 mm after the last.
        let ((lo, hi), halves) = x_layout(&[0.005, 0.01, 0.02, 0.04]);
        assert!(
            (lo - 0.0).abs() < 1e-15 && (hi - 0.06).abs() < 1e-15,
            "{lo} {hi}"
        );
        let want = [0.00175, 0.00175, 0.0035, 0.007];
        assert!(
            halves.iter().zip(want).all(|(h, w)| (h - w).abs() < 1e-15),
            "{halves:?}"
        );
        // An even grid: a step of room and 0.35 of a step for each half box.
        let ((lo, hi), halves) = x_layout(&[0.5, 0.6, 0.7]);
        assert!(
            (lo - 0.4).abs() < 1e-12 && (hi - 0.8).abs() < 1e-12,
            "{lo} {hi}"
        );
        assert!(
            halves.iter().all(|h| (h - 0.035).abs() < 1e-12),
            "{halves:?}"
        );
    }
}
