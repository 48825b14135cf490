//! Zones of a three-axis study as small multiples: zone maps over the last two axes, one panel
//! per value of the first (up to [`PANELS`] values, evenly spread over its range and always
//! including the recommended design's), with one legend for all.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, SMALL, TITLE, cell_edges, class_color, err, tick, zone_color,
};

use crate::reduce::{Class, PointStats, Summary};
use crate::report::text::{axis_desc, axis_value};

pub const SIZE: (u32, u32) = (1200, 1000);
/// Panels at most (4 columns × 3 rows).
pub const PANELS: usize = 12;
const COLUMNS: usize = 4;

pub struct ZoneMultiples<'a> {
    s: &'a Summary,
    /// The axis across the panels, and the map's (vertical, horizontal) axes.
    across: usize,
    map: (usize, usize),
    through: u64,
    /// The indices along `across` drawn.
    panels: Vec<usize>,
}

impl<'a> ZoneMultiples<'a> {
    pub fn new(s: &'a Summary, across: usize, map: (usize, usize), through: u64) -> Self {
        let n = s.grid.n(across);
        let mut panels: Vec<usize> = if n <= PANELS {
            (0..n).collect()
        } else {
            (0..PANELS - 1)
                .map(|k| (k * (n - 1) + (PANELS - 2) / 2) / (PANELS - 2))
                .collect()
        };
        let own = s.grid.index(through, across);
        if !panels.contains(&own) {
            panels.push(own);
        }
        panels.sort_unstable();
        panels.dedup();
        ZoneMultiples {
            s,
            across,
            map,
            through,
            panels,
        }
    }

    /// Every point drawn, in point order.
    pub fn points(&self) -> Vec<&'a PointStats> {
        let g = &self.s.grid;
        let mut out = Vec::new();
        for &i in &self.panels {
            let at = g.with_index(self.through, self.across, i);
            out.extend(
                g.slice(at, &[self.map.0, self.map.1])
                    .into_iter()
                    .filter_map(|p| self.s.point(p)),
            );
        }
        out.sort_by_key(|p| p.point);
        out
    }
}

impl ZoneMultiples<'_> {
    /// Panel `i` of the axis across (the map at its `i`-th value) in `area`: the cells
    /// coloured by zone on the edges `(ea, eb)`, the anchor design ringed in its own panel.
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        i: usize,
        (ea, eb): (&[f64], &[f64]),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.s;
        let g = &s.grid;
        let (a, b) = self.map;
        let at = g.with_index(self.through, self.across, i);
        let mut chart = ChartBuilder::on(area)
            .caption(
                axis_value(g.key(self.across), g.axes[self.across].1[i]),
                SMALL,
            )
            .margin(6)
            .margin_right(18)
            .x_label_area_size(34)
            .y_label_area_size(56)
            .build_cartesian_2d(eb[0]..eb[eb.len() - 1], ea[0]..ea[ea.len() - 1])
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(axis_desc(g.key(b)))
            .y_desc(axis_desc(g.key(a)))
            .x_labels(4)
            .y_labels(4)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style(("sans-serif", 12))
            .axis_desc_style(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        let points: Vec<&PointStats> = g
            .slice(at, &[a, b])
            .into_iter()
            .filter_map(|p| s.point(p))
            .collect();
        chart
            .draw_series(points.iter().map(|p| {
                let (ia, ib) = (g.index(p.point, a), g.index(p.point, b));
                Rectangle::new(
                    [(eb[ib], ea[ia]), (eb[ib + 1], ea[ia + 1])],
                    zone_color(s, p.zone).filled(),
                )
            }))
            .map_err(err)?;
        if g.index(self.through, self.across) == i {
            let (x, y) = (g.value(self.through, b), g.value(self.through, a));
            chart
                .draw_series([
                    Circle::new((x, y), 7, WHITE.stroke_width(3)),
                    Circle::new((x, y), 7, BLACK.stroke_width(2)),
                ])
                .map_err(err)?;
        }
        Ok(())
    }

    /// One legend row for every class shown, and what the ring marks.
    fn legend<DB: DrawingBackend>(&self, legend: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.s;
        // One legend row for every class shown, and the ring.
        let all = self.points();
        let mut x = 20;
        let y = 30;
        for c in Class::ALL {
            if !all
                .iter()
                .any(|p| s.zone_of(p).and_then(|z| z.class) == Some(c))
            {
                continue;
            }
            legend
                .draw(&Rectangle::new(
                    [(x, y), (x + 16, y + 16)],
                    class_color(c).filled(),
                ))
                .map_err(err)?;
            let text = c.label();
            let (w, _) = legend
                .estimate_text_size(text, &SMALL.into_text_style(legend))
                .map_err(err)?;
            legend
                .draw(&Text::new(text, (x + 22, y + 1), SMALL.into_font()))
                .map_err(err)?;
            x += 22 + w as i32 + 24;
        }
        let ring = if s.recommended == Some(self.through) {
            "ringed: the recommended design"
        } else {
            "ringed: the best design"
        };
        legend
            .draw(&Text::new(ring, (20, y + 28), SMALL.into_font()))
            .map_err(err)?;
        Ok(())
    }
}

impl Chart for ZoneMultiples<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.s;
        let g = &s.grid;
        let (a, b) = self.map;
        let title = format!(
            "Zones over {} and {} at {} values of {}",
            g.key(a),
            g.key(b),
            self.panels.len(),
            g.key(self.across)
        );
        let root = root.titled(&title, TITLE).map_err(err)?;
        let h = root.dim_in_pixel().1 as i32;
        let (body, legend) = root.split_vertically(h - 90);
        let rows = self.panels.len().div_ceil(COLUMNS);
        let cells = body.split_evenly((rows, COLUMNS));
        let (ea, eb) = (cell_edges(&g.axes[a].1), cell_edges(&g.axes[b].1));
        for (area, &i) in cells.iter().zip(&self.panels) {
            self.panel(area, i, (&ea, &eb))?;
        }
        self.legend(&legend)?;
        Ok(())
    }
}
