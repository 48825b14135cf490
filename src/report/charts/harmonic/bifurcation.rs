//! The bifurcation diagram of the recommended design (docs/reduce.md): the Poincaré section of
//! every attractor the census found, the main mass's displacement at the start of each forcing
//! period `x(kT)`, against the frequency ratio (a periodic orbit of period `p` is `p` points, a
//! chaotic motion a band of points), and beneath it each attractor's largest Lyapunov exponent
//! per forcing period (below zero: periodic and stable; above: chaotic).

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, Key, LABEL, SMALL, TITLE, err, minmax, pad, plot_builder, tick,
};

use crate::orbits::attractors::SteadyKind;
use crate::orbits::response::Response;
use crate::reduce::harmonic::steady::SectionSample;
use crate::report::text::fmt_num;
use crate::store::table::{Column, Table};

pub const SIZE: (u32, u32) = (1000, 820);
const LEGEND_X: i32 = 80;
/// Metres to centimetres.
const CM: f64 = 100.0;

/// The colour of an attractor kind.
fn colour(kind: SteadyKind) -> RGBColor {
    match kind {
        SteadyKind::Periodic => RGBColor(31, 119, 180),
        SteadyKind::Neutral => RGBColor(120, 120, 120),
        SteadyKind::Chaotic => RGBColor(255, 127, 14),
        SteadyKind::QuasiPeriodic => RGBColor(148, 103, 189),
        SteadyKind::NotSettled => RGBColor(140, 86, 75),
    }
}

const KINDS: [SteadyKind; 5] = [
    SteadyKind::Periodic,
    SteadyKind::Neutral,
    SteadyKind::Chaotic,
    SteadyKind::QuasiPeriodic,
    SteadyKind::NotSettled,
];

/// The diagram's data: the section samples and the attractors' exponents.
pub struct Bifurcation<'a> {
    pub samples: &'a [SectionSample],
    pub response: &'a Response,
    pub title_at: String,
}

impl Bifurcation<'_> {
    /// The chart data: one row per section sample.
    pub fn data(&self) -> Table {
        let s = self.samples;
        let mut t = Table::default();
        t.push("r", Column::F64(s.iter().map(|x| x.r).collect()));
        t.push(
            "attractor",
            Column::U64(s.iter().map(|x| Some(u64::from(x.attractor))).collect()),
        );
        t.push(
            "kind",
            Column::Str(s.iter().map(|x| x.kind.name().to_string()).collect()),
        );
        t.push("x", Column::F64(s.iter().map(|x| x.x).collect()));
        t
    }

    fn x_range(&self) -> (f64, f64) {
        let (x0, x1) = minmax(self.response.attractors.iter().map(|a| a.run.r));
        let w = (x1 - x0) * 0.01;
        if x1 > x0 {
            (x0 - w, x1 + w)
        } else {
            pad(x0, x1, 0.5)
        }
    }
}

impl Chart for Bifurcation<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let (title, rest) = root.split_vertically(40);
        title
            .titled(&format!("Bifurcation diagram{}", self.title_at), TITLE)
            .map_err(err)?;
        let present: Vec<SteadyKind> = KINDS
            .into_iter()
            .filter(|k| self.response.attractors.iter().any(|a| a.kind == *k))
            .collect();
        let items: Vec<(Key, String)> = present
            .iter()
            .map(|k| (Key::Swatch(colour(*k).to_rgba()), k.name().to_string()))
            .collect();
        let plots = crate::report::charts::plumbing::legend_block(&rest, LEGEND_X, &items)?;
        let (top, bottom) = plots.split_vertically(plots.dim_in_pixel().1 * 3 / 5);
        let (x0, x1) = self.x_range();
        let (lo, hi) = minmax(self.samples.iter().map(|s| s.x * CM));
        let (lo, hi) = if hi > lo {
            pad(lo, hi, 0.05)
        } else {
            pad(lo, hi, 1.0)
        };
        let mut chart = plot_builder(&top, 30)
            .build_cartesian_2d(x0..x1, lo..hi)
            .map_err(err)?;
        chart
            .configure_mesh()
            .y_desc("x(kT), section of each attractor (cm)")
            .x_label_formatter(&tick)
            // A tick at zero computed as 5e-17 reads as zero.
            .y_label_formatter(&|v: &f64| fmt_num(if v.abs() < 1e-12 { 0.0 } else { *v }))
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        for k in &present {
            let size = if k.periodic() { 3 } else { 1 };
            chart
                .draw_series(
                    self.samples
                        .iter()
                        .filter(|s| s.kind == *k)
                        .map(|s| Circle::new((s.r, s.x * CM), size, colour(*k).filled())),
                )
                .map_err(err)?;
        }
        self.exponents(&bottom, (x0, x1))
    }
}

impl Bifurcation<'_> {
    /// The bottom panel: λ1 per forcing period of every attractor, with its standard error.
    fn exponents<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x0, x1): (f64, f64),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let att: Vec<_> = self
            .response
            .attractors
            .iter()
            .filter(|a| a.lyapunov.is_finite())
            .collect();
        let (lo, hi) = minmax(att.iter().map(|a| a.lyapunov));
        let (lo, hi) = (lo.min(0.0), hi.max(0.0));
        let (lo, hi) = if hi > lo {
            pad(lo, hi, 0.08)
        } else {
            (-1.0, 1.0)
        };
        let mut chart = plot_builder(area, 48)
            .build_cartesian_2d(x0..x1, lo..hi)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("frequency ratio r = omega / sqrt(K/M) (–)")
            .x_label_formatter(&tick)
            .y_desc("λ1 per forcing period")
            .y_label_formatter(&|v: &f64| fmt_num(*v))
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(DashedLineSeries::new(
                [(x0, 0.0), (x1, 0.0)],
                5,
                4,
                BLACK.stroke_width(1),
            ))
            .map_err(err)?;
        for a in &att {
            let c = colour(a.kind);
            if a.lyapunov_se.is_finite() && a.lyapunov_se > 0.0 {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![
                            (a.run.r, a.lyapunov - a.lyapunov_se),
                            (a.run.r, a.lyapunov + a.lyapunov_se),
                        ],
                        c.stroke_width(1),
                    )))
                    .map_err(err)?;
            }
            chart
                .draw_series(std::iter::once(Circle::new(
                    (a.run.r, a.lyapunov),
                    3,
                    c.filled(),
                )))
                .map_err(err)?;
        }
        Ok(())
    }
}
