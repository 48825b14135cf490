//! The random and record scenes' chart: `fragility` (SVG, PNG and its data as CSV), drawn when
//! a study sweeps an intensity (`S0` or a record's `scale`) and sets a threshold. Each shown
//! design's Monte Carlo `p_f` at every swept intensity (markers) and its fitted lognormal
//! fragility curve `Phi(ln(IM / theta) / beta)` (a line), over `log10` of the intensity: the
//! ranked designs first ([`MAX_DESIGNS`] of them, the last place given to the design of the
//! largest median capacity when the ranking at the design intensity left it out: their curves
//! cross), and the structure without damper (a design with `m = 0`, dashed grey) beside them
//! when the study has one.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plumbing::{
    Chart, DESIGN_COLORS, Data, GREY, LABEL, Scale, err, render, series_legend, shorten, xy_chart,
};
use crate::reduce::Summary;
use crate::reduce::random::RandomSummary;
use crate::report::text::{axis_value, fmt_num};
use crate::store::table::{Column, Table};

/// Designs drawn at most besides the structure without damper.
pub const MAX_DESIGNS: usize = 5;

/// One design's curve: its label, its `(log10 IM, p_f)` points and its fitted curve.
struct Curve {
    name: String,
    points: Vec<(f64, f64)>,
    fit: Vec<(f64, f64)>,
    bare: bool,
}

struct FragilityChart {
    title: String,
    x_desc: String,
    curves: Vec<Curve>,
    x: (f64, f64),
}

impl Chart for FragilityChart {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let mut chart = xy_chart(
            root,
            (&self.title, LABEL),
            (self.x.0..self.x.1, -0.02..1.02),
            (&self.x_desc, "P(max |x| > threshold)"),
            (&[], Scale::Linear),
        )?;
        let colors = DESIGN_COLORS;
        let mut k = 0;
        for c in &self.curves {
            let color = if c.bare {
                GREY
            } else {
                k += 1;
                colors[(k - 1) % colors.len()]
            };
            let style = color.stroke_width(2);
            if c.bare {
                chart
                    .draw_series(DashedLineSeries::new(c.fit.iter().copied(), 8, 5, style))
                    .map_err(err)?;
            } else {
                chart
                    .draw_series(LineSeries::new(c.fit.iter().copied(), style))
                    .map_err(err)?;
            }
            chart
                .draw_series(c.points.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(err)?
                .label(c.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
        }
        series_legend(&mut chart, SeriesLabelPosition::UpperLeft)
    }
}

/// Draws `<dir>/fragility.{svg,png,csv}` when the study sweeps an intensity and sets a
/// threshold; returns the files written (none otherwise).
pub fn charts(s: &Summary, rs: &RandomSummary, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    if !rs.risk.is_empty() {
        return super::seismic::charts(s, rs, dir);
    }
    let (Some(i), Some(b)) = (&rs.intensity, rs.threshold) else {
        return Ok(Vec::new());
    };
    let lens: Vec<usize> = (0..s.grid.n_axes()).map(|a| s.grid.n(a)).collect();
    let mut shown: Vec<u64> = {
        let mut r: Vec<_> = s.points.iter().filter(|p| p.rank.is_some()).collect();
        r.sort_by_key(|p| p.rank);
        r.iter().take(MAX_DESIGNS).map(|p| p.point).collect()
    };
    let bare = s
        .points
        .iter()
        .find(|p| s.grid.without_damper(p.point))
        .map(|p| p.point);
    // The design of the largest median capacity too, where the ranking at the design intensity
    // left it out (the curves cross).
    if let Some(&(top, _)) = rs.capacity_rank.iter().find(|(_, r)| *r == 1)
        && !shown.contains(&top)
    {
        shown.pop();
        shown.push(top);
    }
    shown.retain(|&d| Some(d) != bare);
    let logs: Vec<f64> = i.values.iter().map(|v| v.log10()).collect();
    let (x0, x1) = (logs[0], logs[logs.len() - 1]);
    let span = (x1 - x0).max(0.1);
    let x = (x0 - 0.05 * span, x1 + 0.05 * span);
    let mut data = Table::default();
    let (mut d_col, mut im_col, mut pf_col, mut fit_col) = (vec![], vec![], vec![], vec![]);
    let mut curves = Vec::new();
    for (d, is_bare) in shown
        .iter()
        .map(|&d| (d, false))
        .chain(bare.map(|d| (d, true)))
    {
        let fit = rs.fragility_of(d);
        let mut points = Vec::new();
        for (j, &im) in i.values.iter().enumerate() {
            let Some(p) = rs.point(rs.grid_point(d, j, &lens)) else {
                continue;
            };
            points.push((logs[j], p.p_f));
            d_col.push(Some(d));
            im_col.push(im);
            pf_col.push(p.p_f);
            fit_col.push(fit.map_or(f64::NAN, |f| f.probability(im)));
        }
        let line: Vec<(f64, f64)> = match fit {
            Some(f) if f.theta.is_finite() => (0..=80)
                .map(|k| {
                    let lx = x.0 + (x.1 - x.0) * k as f64 / 80.0;
                    (lx, f.probability(10f64.powf(lx)))
                })
                .collect(),
            _ => points.clone(),
        };
        let label = if s.grid.n_axes() == 0 {
            "the study's system".to_string()
        } else {
            (0..s.grid.n_axes())
                .map(|a| axis_value(s.grid.key(a), s.grid.value(d, a)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        curves.push(Curve {
            name: shorten(
                &if is_bare {
                    format!("{label} (no damper)")
                } else {
                    label
                },
                60,
            ),
            points,
            fit: line,
            bare: is_bare,
        });
    }
    data.push("point", Column::U64(d_col));
    data.push("intensity", Column::F64(im_col));
    data.push("p_f", Column::F64(pf_col));
    data.push("p_f_fitted", Column::F64(fit_col));
    let chart = FragilityChart {
        title: format!("Fragility: P(max |x| > {} m) against {}", fmt_num(b), i.key),
        x_desc: format!("log10 {}", i.key),
        curves,
        x,
    };
    render(dir, "fragility", (1000, 620), &chart, &Data::Table(data))
}
