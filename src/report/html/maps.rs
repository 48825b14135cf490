//! The maps of the page, drawn here as SVG text (not plotters) so that every design point is
//! exactly one `<rect class="cell">` with its data and its hover text ([`super::hover`]): the
//! zone map (cells coloured by their zone's class, merged-in points hatched, zone names) and the
//! perfectibility map, over a pair of axes through the anchor design as the PNG/SVG maps are.
//! The anchor design is outlined and the jumps located between two cells of the slice are drawn
//! on the border between them.

use std::fmt::Write;

use super::hover::{data, hex, title_element};
use super::markdown::esc;
use crate::reduce::PointStats;
use crate::reduce::common::Grid;
use crate::report::charts::common::map::{MapChart, MapKind};
use crate::report::charts::plumbing::{heat, minmax, zone_color};
use crate::report::markdown::f;
use crate::report::text::{axis_desc, fmt_num};
use crate::store::table::axis_column;

const W: f64 = 760.0;
const LEFT: f64 = 90.0;
const TOP: f64 = 12.0;
const RIGHT: f64 = 20.0;
const BOTTOM: f64 = 60.0;
/// The zone and perfectibility maps' tallest cell (px).
const CELL_TALL: f64 = 34.0;

/// Cell geometry: axis `a` vertical (its first value at the bottom), `b` horizontal; the risk
/// maps' too ([`super::numbers`]).
pub(super) struct Frame {
    na: usize,
    nb: usize,
    pub cw: f64,
    pub ch: f64,
}

impl Frame {
    /// Square-ish cells at most `tall` px high, the map between 160 and 460 px high.
    pub fn new(na: usize, nb: usize, tall: f64) -> Frame {
        let cw = (W - LEFT - RIGHT) / nb as f64;
        let ch = (cw.min(tall) * na as f64).clamp(160.0, 460.0) / na as f64;
        Frame { na, nb, cw, ch }
    }

    pub fn height(&self) -> f64 {
        TOP + self.ch * self.na as f64 + BOTTOM
    }

    /// Top-left corner of cell `(ia, ib)`.
    pub fn at(&self, ia: usize, ib: usize) -> (f64, f64) {
        (
            LEFT + ib as f64 * self.cw,
            TOP + (self.na - 1 - ia) as f64 * self.ch,
        )
    }
}

/// Ticks: at most about ten labelled values of an axis.
fn ticks(n: usize) -> impl Iterator<Item = usize> {
    let every = n.div_ceil(10).max(1);
    (0..n).filter(move |i| i % every == 0 || *i == n - 1)
}

/// The SVG of one map.
pub fn map_svg(chart: &MapChart) -> String {
    let s = chart.s;
    let g = &s.grid;
    let (a, b) = (chart.a, chart.b);
    let fr = Frame::new(g.n(a), g.n(b), CELL_TALL);
    let h = fr.height();
    let points = chart.points();
    let kind = match chart.kind {
        MapKind::Zones => "zones",
        MapKind::Perfectibility => "perfectibility",
    };
    let mut o = format!(
        "<svg class=\"map\" data-kind=\"{kind}\" data-axes=\"{} {}\" data-cells=\"{}\" viewBox=\"0 0 {W} {h}\" width=\"{W}\" height=\"{h}\" xmlns=\"http://www.w3.org/2000/svg\" role=\"img\">\n",
        axis_column(g.key(a)),
        axis_column(g.key(b)),
        points.len()
    );
    let (p0, p1) = minmax(points.iter().map(|p| p.perfectibility));
    for p in &points {
        let (x, y) = fr.at(g.index(p.point, a), g.index(p.point, b));
        let fill = match chart.kind {
            MapKind::Zones => hex(zone_color(s, p.zone)),
            MapKind::Perfectibility if p.perfectibility.is_finite() => {
                hex(heat((p.perfectibility - p0) / (p1 - p0).max(1e-12)))
            }
            MapKind::Perfectibility => "#c8c8c8".to_string(),
        };
        let _ = writeln!(
            o,
            "<rect class=\"cell\" x=\"{x:.2}\" y=\"{y:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{fill}\"{}>{}</rect>",
            fr.cw,
            fr.ch,
            data(s, p),
            title_element(s, p)
        );
        if chart.kind == MapKind::Zones && s.merged(p) {
            let _ = writeln!(
                o,
                "<rect class=\"hatch\" x=\"{x:.2}\" y=\"{y:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"url(#hatch)\"/>",
                fr.cw, fr.ch
            );
        }
    }
    if chart.kind == MapKind::Zones {
        o += &zone_names(chart, &points, &fr);
    }
    o += &jumps(chart, &fr);
    if let Some(p) = s.point(chart.through) {
        let (x, y) = fr.at(g.index(p.point, a), g.index(p.point, b));
        let what = if s.recommended == Some(p.point) {
            "the recommended design"
        } else {
            "the best design (none is robust)"
        };
        let _ = writeln!(
            o,
            "<rect class=\"anchor\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\"><title>{what}</title></rect>",
            x - 1.5,
            y - 1.5,
            fr.cw + 3.0,
            fr.ch + 3.0
        );
    }
    o += &axes(g, (chart.a, chart.b), &fr);
    o.push_str("</svg>\n");
    o
}

/// Axis ticks, values and descriptions.
pub(super) fn axes(g: &Grid, (a, b): (usize, usize), fr: &Frame) -> String {
    let bottom = TOP + fr.ch * fr.na as f64;
    let mut o = format!(
        "<rect class=\"frame\" x=\"{LEFT}\" y=\"{TOP}\" width=\"{:.2}\" height=\"{:.2}\"/>\n",
        fr.cw * fr.nb as f64,
        fr.ch * fr.na as f64
    );
    for ib in ticks(fr.nb) {
        let x = LEFT + (ib as f64 + 0.5) * fr.cw;
        let _ = writeln!(
            o,
            "<text class=\"tick\" x=\"{x:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            bottom + 16.0,
            fmt_num(g.axes[b].1[ib])
        );
    }
    for ia in ticks(fr.na) {
        let y = TOP + (fr.na - 1 - ia) as f64 * fr.ch + fr.ch / 2.0 + 4.0;
        let _ = writeln!(
            o,
            "<text class=\"tick\" x=\"{:.2}\" y=\"{y:.2}\" text-anchor=\"end\">{}</text>",
            LEFT - 6.0,
            fmt_num(g.axes[a].1[ia])
        );
    }
    let _ = writeln!(
        o,
        "<text class=\"desc\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
        LEFT + fr.cw * fr.nb as f64 / 2.0,
        bottom + 40.0,
        esc(&axis_desc(g.key(b)))
    );
    let _ = writeln!(
        o,
        "<text class=\"desc\" transform=\"translate(16 {:.2}) rotate(-90)\" text-anchor=\"middle\">{}</text>",
        TOP + fr.ch * fr.na as f64 / 2.0,
        esc(&axis_desc(g.key(a)))
    );
    o
}

/// Every zone's name once, at the mean position of its cells in the slice.
fn zone_names(chart: &MapChart, points: &[&PointStats], fr: &Frame) -> String {
    let s = chart.s;
    let g = &s.grid;
    let mut sums: Vec<(u32, f64, f64, usize)> = Vec::new();
    for p in points {
        if s.zone_of(p).is_none() {
            continue;
        }
        let (x, y) = fr.at(g.index(p.point, chart.a), g.index(p.point, chart.b));
        match sums.iter_mut().find(|z| z.0 == p.zone) {
            Some(z) => {
                z.1 += x;
                z.2 += y;
                z.3 += 1;
            }
            None => sums.push((p.zone, x, y, 1)),
        }
    }
    let mut o = String::new();
    for (z, x, y, n) in sums {
        let n = n as f64;
        let _ = writeln!(
            o,
            "<text class=\"zone-name\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            x / n + fr.cw / 2.0,
            y / n + fr.ch / 2.0 + 5.0,
            esc(&s.zones[z as usize].name)
        );
    }
    o
}

/// The located jumps between two neighbouring cells of the slice: a line on their border at
/// the located value.
fn jumps(chart: &MapChart, fr: &Frame) -> String {
    let s = chart.s;
    let g = &s.grid;
    let in_slice = |p: u64| {
        (0..g.n_axes())
            .filter(|&k| k != chart.a && k != chart.b)
            .all(|k| g.index(p, k) == g.index(chart.through, k))
    };
    let mut o = String::new();
    let mut n = 0;
    for j in &s.jumps {
        if !(j.axis == chart.a || j.axis == chart.b) || !in_slice(j.below) {
            continue;
        }
        let (ia, ib) = (g.index(j.below, chart.a), g.index(j.below, chart.b));
        let (x, y) = fr.at(ia, ib);
        let (v0, v1) = (g.value(j.below, j.axis), g.value(j.above, j.axis));
        let t = ((j.location - v0) / (v1 - v0)).clamp(0.0, 1.0);
        let (x1, y1, x2, y2) = if j.axis == chart.b {
            let xj = x + fr.cw * (0.5 + t);
            (xj, y, xj, y + fr.ch)
        } else {
            let yj = y + fr.ch * (0.5 - t);
            (x, yj, x + fr.cw, yj)
        };
        let _ = writeln!(
            o,
            "<line class=\"jump\" x1=\"{x1:.2}\" y1=\"{y1:.2}\" x2=\"{x2:.2}\" y2=\"{y2:.2}\"><title>{}</title></line>",
            esc(&super::profile::jump_text(s, j))
        );
        n += 1;
    }
    if n > 0 {
        o.insert_str(0, &format!("<g class=\"jumps\" data-jumps=\"{n}\">\n"));
        o.push_str("</g>\n");
    }
    o
}

/// The legend under a map: the classes of its zones, merged-in points, the outline, jumps.
pub fn legend(chart: &MapChart) -> String {
    let s = chart.s;
    let points = chart.points();
    let mut o = String::from("<div class=\"legend\">");
    match chart.kind {
        MapKind::Zones => {
            let mut seen: Vec<u32> = Vec::new();
            for p in &points {
                if !seen.contains(&p.zone) {
                    seen.push(p.zone);
                }
            }
            seen.sort_unstable();
            for z in seen {
                let name = s.zones.get(z as usize).map_or("no zone".to_string(), |zn| {
                    format!("{}: {}", zn.name, zn.label())
                });
                let _ = write!(
                    o,
                    "<span><i style=\"background:{}\"></i>{}</span>",
                    hex(zone_color(s, z)),
                    esc(&name)
                );
            }
            if points.iter().any(|p| s.merged(p)) {
                o.push_str("<span><i class=\"hatched\"></i>merged in from a smaller region (its own class differs)</span>");
            }
        }
        MapKind::Perfectibility => {
            let (p0, p1) = minmax(points.iter().map(|p| p.perfectibility));
            let _ = write!(
                o,
                "<span><i class=\"ramp\"></i>perfectibility {} % – {} % (over this slice)</span>",
                f(p0, 1),
                f(p1, 1)
            );
        }
    }
    o.push_str("<span><i class=\"outlined\"></i>the design the slice goes through</span><span><i class=\"jumpkey\"></i>a located jump</span></div>\n");
    o
}
