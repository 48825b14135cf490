//! Maps over a pair of axes, the other axes fixed at the recommended design's values (the slice
//! is named under the title): perfectibility as a colour scale, or the zones coloured by class
//! with their names, the points merged in from a smaller region hatched. The recommended design
//! is ringed.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, GREY, SMALL, TITLE, cell_edges, class_color, colour_bar, err, heat, map_chart, minmax,
    zone_color,
};

use crate::reduce::{Class, PointStats, Summary};
use crate::report::text::{axis_desc, axis_value};

pub const SIZE: (u32, u32) = (1000, 700);

/// What a map colours its cells by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    Perfectibility,
    Zones,
}

/// A map of axes `(a, b)` (`a` vertical, `b` horizontal) through design point `through`.
pub struct MapChart<'a> {
    pub s: &'a Summary,
    pub a: usize,
    pub b: usize,
    pub through: u64,
    pub kind: MapKind,
}

impl<'a> MapChart<'a> {
    /// The points of the slice, in point order.
    pub fn points(&self) -> Vec<&'a PointStats> {
        self.s
            .grid
            .slice(self.through, &[self.a, self.b])
            .into_iter()
            .filter_map(|p| self.s.point(p))
            .collect()
    }

    /// `d = 0.012 m`, the other axes' values; empty with two axes.
    pub fn slice(&self) -> String {
        let g = &self.s.grid;
        (0..g.n_axes())
            .filter(|&k| k != self.a && k != self.b)
            .map(|k| axis_value(g.key(k), g.value(self.through, k)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn title(&self) -> String {
        let g = &self.s.grid;
        let what = match self.kind {
            MapKind::Perfectibility => "Perfectibility P (eq. 11)",
            MapKind::Zones => "Zones",
        };
        format!("{what} over {} and {}", g.key(self.a), g.key(self.b))
    }

    fn subtitle(&self) -> String {
        let whose = if self.s.recommended == Some(self.through) {
            "the recommended design's"
        } else {
            "the best design's"
        };
        match self.slice() {
            s if s.is_empty() => {
                format!("ringed: {} (no other axis)", whose.trim_end_matches("'s"))
            }
            s => format!("slice at {s} ({whose}); ringed: that design"),
        }
    }
}

impl Chart for MapChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let s = self.s;
        let g = &s.grid;
        let (va, vb) = (&g.axes[self.a].1, &g.axes[self.b].1);
        let (ea, eb) = (cell_edges(va), cell_edges(vb));
        let root = root.titled(&self.title(), TITLE).map_err(err)?;
        let (sub, rest) = root.split_vertically(26);
        sub.draw(&Text::new(
            self.subtitle(),
            (12, 2),
            SMALL.into_font().color(&BLACK),
        ))
        .map_err(err)?;
        let legend_w = if self.kind == MapKind::Zones {
            330
        } else {
            150
        };
        let (area, legend_area) = rest.split_horizontally(rest.dim_in_pixel().0 as i32 - legend_w);
        let mut chart = map_chart(
            &area,
            (&eb, &ea),
            (vb, va),
            (&axis_desc(g.key(self.b)), &axis_desc(g.key(self.a))),
        )?;
        let points = self.points();
        let (p0, p1) = minmax(points.iter().map(|p| p.perfectibility));
        let cell = |p: &PointStats| {
            let (ia, ib) = (g.index(p.point, self.a), g.index(p.point, self.b));
            [(eb[ib], ea[ia]), (eb[ib + 1], ea[ia + 1])]
        };
        chart
            .draw_series(points.iter().map(|p| {
                let color = match self.kind {
                    MapKind::Zones => zone_color(s, p.zone),
                    MapKind::Perfectibility if p.perfectibility.is_finite() => {
                        heat((p.perfectibility - p0) / (p1 - p0).max(1e-12))
                    }
                    MapKind::Perfectibility => RGBColor(200, 200, 200),
                };
                Rectangle::new(cell(p), color.filled())
            }))
            .map_err(err)?;
        if self.kind == MapKind::Zones {
            // Merged-in points (their own class is not their zone's) hatched (issue 18).
            let hatch = GREY.stroke_width(1);
            chart
                .draw_series(
                    points
                        .iter()
                        .filter(|p| s.merged(p))
                        .flat_map(|p| hatch_lines(cell(p)))
                        .map(|l| PathElement::new(l, hatch)),
                )
                .map_err(err)?;
            self.zone_names(&mut chart, &points, &ea, &eb)?;
        }
        // The design the slice goes through.
        if let Some(p) = s.point(self.through) {
            let (x, y) = (g.value(p.point, self.b), g.value(p.point, self.a));
            chart
                .draw_series([
                    Circle::new((x, y), 9, WHITE.stroke_width(4)),
                    Circle::new((x, y), 9, BLACK.stroke_width(2)),
                ])
                .map_err(err)?;
        }
        let legend = legend_area.margin(50, 50, 6, 6);
        match self.kind {
            MapKind::Zones => class_legend(&legend, s, &points),
            MapKind::Perfectibility => {
                colour_bar(&legend, "P (%)", &format!("{p1:.1}"), &format!("{p0:.1}"))
            }
        }
    }
}

impl MapChart<'_> {
    /// Writes every zone's name once, on its cell with the most cells of the same zone within
    /// two cells around (deep inside its part of the slice), when that is at least 5.
    fn zone_names<DB: DrawingBackend>(
        &self,
        chart: &mut ChartContext<
            '_,
            DB,
            Cartesian2d<
                plotters::coord::types::RangedCoordf64,
                plotters::coord::types::RangedCoordf64,
            >,
        >,
        points: &[&PointStats],
        ea: &[f64],
        eb: &[f64],
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        let g = &self.s.grid;
        let (na, nb) = (g.n(self.a), g.n(self.b));
        let mut zone_at = vec![u32::MAX; na * nb];
        for p in points {
            zone_at[g.index(p.point, self.a) * nb + g.index(p.point, self.b)] = p.zone;
        }
        let mut best: Vec<(u32, usize, usize)> = Vec::new(); // zone, cell, score
        for ia in 0..na {
            for ib in 0..nb {
                let z = zone_at[ia * nb + ib];
                if z == u32::MAX {
                    continue;
                }
                let mut score = 0;
                for da in ia.saturating_sub(2)..(ia + 3).min(na) {
                    for db in ib.saturating_sub(2)..(ib + 3).min(nb) {
                        score += usize::from(zone_at[da * nb + db] == z);
                    }
                }
                match best.iter_mut().find(|b| b.0 == z) {
                    Some(b) if b.2 < score => *b = (z, ia * nb + ib, score),
                    Some(_) => {}
                    None => best.push((z, ia * nb + ib, score)),
                }
            }
        }
        let font = ("sans-serif", 16)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        for (z, c, score) in best {
            if score < 5 {
                continue;
            }
            let (ia, ib) = (c / nb, c % nb);
            let at = ((eb[ib] + eb[ib + 1]) / 2.0, (ea[ia] + ea[ia + 1]) / 2.0);
            chart
                .draw_series(std::iter::once(Text::new(
                    self.s.zones[z as usize].name.clone(),
                    at,
                    font.clone(),
                )))
                .map_err(err)?;
        }
        Ok(())
    }
}

/// Three diagonal strokes across a cell `[(x0, y0), (x1, y1)]`: the lines `v = u + t` of the
/// unit cell for `t` in {-0.5, 0, 0.5}, clipped to it.
fn hatch_lines(c: [(f64, f64); 2]) -> Vec<Vec<(f64, f64)>> {
    let [(x0, y0), (x1, y1)] = c;
    let at = |u: f64, v: f64| (x0 + u * (x1 - x0), y0 + v * (y1 - y0));
    [-0.5, 0.0, 0.5]
        .iter()
        .map(|&t: &f64| {
            let (u0, u1) = ((-t).max(0.0), (1.0 - t).min(1.0));
            vec![at(u0, u0 + t), at(u1, u1 + t)]
        })
        .collect()
}

/// One swatch per class (or declared zone) present in the slice, and the hatch of merged-in
/// points when there are some.
fn class_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &Summary,
    points: &[&PointStats],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let mut items: Vec<(RGBColor, String)> = Vec::new();
    for c in Class::ALL {
        if points
            .iter()
            .any(|p| s.zone_of(p).and_then(|z| z.class) == Some(c))
        {
            items.push((class_color(c), c.label().to_string()));
        }
    }
    for (i, z) in s.zones.iter().enumerate() {
        if z.declared() && points.iter().any(|p| p.zone == i as u32) {
            items.push((zone_color(s, i as u32), format!("zone {}", z.name)));
        }
    }
    for (i, (c, text)) in items.iter().enumerate() {
        let y = 10 + 26 * i as i32;
        area.draw(&Rectangle::new([(0, y), (16, y + 16)], c.filled()))
            .map_err(err)?;
        area.draw(&Text::new(text.clone(), (22, y + 1), SMALL.into_font()))
            .map_err(err)?;
    }
    if points.iter().any(|p| s.merged(p)) {
        let y = 10 + 26 * items.len() as i32;
        area.draw(&Rectangle::new([(0, y), (16, y + 16)], WHITE.filled()))
            .map_err(err)?;
        for l in hatch_lines([(0.0, f64::from(y + 16)), (16.0, f64::from(y))]) {
            let px: Vec<(i32, i32)> = l.iter().map(|&(x, y)| (x as i32, y as i32)).collect();
            area.draw(&PathElement::new(px, GREY.stroke_width(1)))
                .map_err(err)?;
        }
        area.draw(&Text::new(
            "hatched: merged in".to_string(),
            (22, y + 1),
            SMALL.into_font(),
        ))
        .map_err(err)?;
    }
    Ok(())
}
