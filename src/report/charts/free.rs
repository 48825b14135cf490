//! Main-mass displacement against time (the paper's Figures 2 and 5): traces over the whole
//! motion, and optionally a second panel magnifying a time window (the first peak).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plumbing::{
    BLUE, Chart, GREEN, LABEL, RED_LINE, Scale, TITLE, err, minmax, pad, render, series_legend,
    xy_chart,
};
use crate::store::table::{Column, Table};

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
        let mut chart = xy_chart(
            area,
            (title, if window.is_some() { LABEL } else { TITLE }),
            (t0..t1, y0..y1),
            ("time t (s)", "main-mass displacement x (cm)"),
            (&[], Scale::Linear),
        )?;
        let colors = [BLUE, RED_LINE, GREEN];
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
        series_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
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

/// Draws a waveform chart `<dir>/<stem>.{svg,png}` and its data `<stem>.csv` (one row per
/// sample: trace number, time in s, displacement in m; the trace names in the chart's legend):
/// the traces over the whole time, and with `zoom` a second panel magnifying that time window.
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
    let mut data = Table::default();
    let rows = || {
        traces
            .iter()
            .enumerate()
            .flat_map(|(i, t)| t.points.iter().map(move |p| (i, p)))
    };
    data.push(
        "trace",
        Column::U64(rows().map(|(i, _)| Some(i as u64)).collect()),
    );
    data.push("t", Column::F64(rows().map(|(_, p)| p.0).collect()));
    data.push("x", Column::F64(rows().map(|(_, p)| p.1).collect()));
    render(
        dir,
        stem,
        size,
        &WaveChart {
            title: title.to_string(),
            traces,
            zoom,
        },
        &super::plumbing::Data::Table(data),
    )
}
