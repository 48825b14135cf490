//! The design chart of the page (the paper's Figure 6) along one axis through the anchor
//! design, drawn as SVG text: R with its interval on top (the `r_min` threshold dashed), the
//! damping quantity (DI or PR) below, the zones shaded behind both, the located jumps as
//! dashed lines and the anchor design marked. Every design point is one `<g class="pt">` with
//! its data and its hover text ([`super::hover`]); its spread (the response's box) is the
//! third panel, so hovering a box shows the same point.

use std::fmt::Write;

use super::hover::{data, hex, title_element};
use super::markdown::esc;
use crate::reduce::{Jump, Quantity};
use crate::reduce::{PointStats, Summary};
use crate::report::charts::plumbing::{Profile, cell_edges, minmax, pad, zone_color};
use crate::report::text::{axis_desc, axis_value, fmt_num};
use crate::store::table::axis_column;

/// The chart's width, its left and right margins and the plot's top (px); the risk charts
/// ([`super::numbers`]) share them.
pub(super) const W: f64 = 760.0;
pub(super) const LEFT: f64 = 90.0;
pub(super) const RIGHT: f64 = 20.0;
pub(super) const TOP: f64 = 22.0;
const PANEL: f64 = 150.0;
const GAP: f64 = 34.0;

/// What a jump is, for its hover text: `kink of xmax along e at 0.8099 ± 7.8e-5`.
pub fn jump_text(s: &Summary, j: &Jump) -> String {
    let q = match j.quantity {
        Quantity::Response => s.options.response.name,
        Quantity::Di => s.options.damping.symbol,
    };
    format!(
        "a located jump: {} of {q} along {} at {} ± {}",
        j.kind.name(),
        s.grid.key(j.axis),
        fmt_num(j.location),
        fmt_num(j.location_tol)
    )
}

/// One panel: its top, and a value → y mapping over `lo..hi`.
struct Panel {
    top: f64,
    lo: f64,
    hi: f64,
}

impl Panel {
    fn y(&self, v: f64) -> f64 {
        self.top + PANEL * (1.0 - (v - self.lo) / (self.hi - self.lo).max(1e-300))
    }
}

/// The SVG of the design chart along `pr`'s axis.
pub fn design_svg(pr: &Profile) -> String {
    let s = pr.s;
    let n = pr.points.len();
    let h = TOP + 3.0 * PANEL + 2.0 * GAP + 56.0;
    // Cells and positions on the axis's scale (`Scale`: a geometric grid in log10); `x` places
    // a value, `xp` a position.
    let edges = if n > 0 {
        cell_edges(&pr.positions())
    } else {
        vec![0.0, 1.0]
    };
    let (x0, x1) = (edges[0], edges[edges.len() - 1]);
    let xp = |p: f64| LEFT + (W - LEFT - RIGHT) * (p - x0) / (x1 - x0).max(1e-300);
    let x = |v: f64| xp(pr.at_x(v));
    let panels = panels(pr);
    let mut o = format!(
        "<svg class=\"profile\" data-axes=\"{}\" data-points=\"{n}\" viewBox=\"0 0 {W} {h}\" width=\"{W}\" height=\"{h}\" xmlns=\"http://www.w3.org/2000/svg\" role=\"img\">\n",
        axis_column(pr.key())
    );
    // Zones behind every panel.
    for (i, p) in pr.points.iter().enumerate() {
        let _ = writeln!(
            o,
            "<rect class=\"band\" x=\"{:.2}\" y=\"{TOP}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{}\"/>",
            xp(edges[i]),
            xp(edges[i + 1]) - xp(edges[i]),
            3.0 * PANEL + 2.0 * GAP,
            hex(zone_color(s, p.zone))
        );
    }
    let r = &s.options.response;
    let labels = [
        format!("R and its {} % interval", fmt_num(100.0 * s.confidence)),
        s.options.damping.label(),
        format!("{} over the cases ({})", r.name, r.unit),
    ];
    for (pn, label) in panels.iter().zip(&labels) {
        o += &frame(pn, label);
    }
    if s.r_min.is_finite() && s.r_min >= panels[0].lo && s.r_min <= panels[0].hi {
        let y = panels[0].y(s.r_min);
        let _ = writeln!(
            o,
            "<line class=\"threshold\" x1=\"{LEFT}\" y1=\"{y:.2}\" x2=\"{:.2}\" y2=\"{y:.2}\"><title>r_min = {}</title></line>",
            W - RIGHT,
            fmt_num(s.r_min)
        );
    }
    for (i, p) in pr.points.iter().enumerate() {
        let xc = x(pr.xs[i]);
        let half = ((xp(edges[i + 1]) - xp(edges[i])) * 0.3).clamp(1.0, 8.0);
        o += &point(s, p, xc, half, &panels);
    }
    o += &marks(pr, &x);
    o += &x_axis(
        &pr.xs,
        &x,
        TOP + 3.0 * PANEL + 2.0 * GAP,
        &pr.scale.desc(&axis_desc(pr.key())),
    );
    o.push_str("</svg>\n");
    o
}

/// The three panels' ranges: R with its interval (and `r_min`), the damping quantity, the
/// response over the cases.
fn panels(pr: &Profile) -> [Panel; 3] {
    let (rlo, rhi) = minmax(
        pr.points
            .iter()
            .flat_map(|p| [p.reliability_lo, p.reliability_hi, p.reliability])
            .chain(std::iter::once(pr.s.r_min).filter(|v| v.is_finite())),
    );
    let (rlo, rhi) = pad(rlo, rhi, 0.06);
    let (dlo, dhi) = pad_of(pr.points.iter().map(|p| p.di));
    let (slo, shi) = pad_of(
        pr.points
            .iter()
            .flat_map(|p| [p.response.min, p.response.max]),
    );
    [
        Panel {
            top: TOP,
            lo: rlo,
            hi: rhi,
        },
        Panel {
            top: TOP + PANEL + GAP,
            lo: dlo,
            hi: dhi,
        },
        Panel {
            top: TOP + 2.0 * (PANEL + GAP),
            lo: slo,
            hi: shi,
        },
    ]
}

/// The jumps located on the line (dashed, with their hover text) and the anchor design.
fn marks(pr: &Profile, x: &dyn Fn(f64) -> f64) -> String {
    let s = pr.s;
    let bottom = TOP + 3.0 * PANEL + 2.0 * GAP;
    let mut o = String::new();
    for j in &pr.jumps {
        let xj = x(j.location);
        let _ = writeln!(
            o,
            "<line class=\"jump\" x1=\"{xj:.2}\" y1=\"{TOP}\" x2=\"{xj:.2}\" y2=\"{bottom:.2}\"><title>{}</title></line>",
            esc(&jump_text(s, j))
        );
    }
    if let Some(p) = s
        .anchor()
        .and_then(|a| pr.points.iter().find(|p| p.point == a))
    {
        let xa = x(s.grid.value(p.point, pr.axis));
        let what = if s.recommended == Some(p.point) {
            "recommended"
        } else {
            "best"
        };
        let _ = writeln!(
            o,
            "<line class=\"anchor-line\" x1=\"{xa:.2}\" y1=\"{TOP}\" x2=\"{xa:.2}\" y2=\"{bottom:.2}\"/><text class=\"anchor-label\" x=\"{:.2}\" y=\"{:.2}\">{what}</text>",
            xa + 4.0,
            TOP + 14.0
        );
    }
    o
}

fn pad_of(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = minmax(v);
    pad(lo, hi, 0.08)
}

/// One design point: R with its interval, the damping value, the response's box.
fn point(s: &Summary, p: &PointStats, xc: f64, half: f64, pn: &[Panel; 3]) -> String {
    let mut o = format!("<g class=\"pt\"{}>{}", data(s, p), title_element(s, p));
    // An invisible column to hover, the height of the chart.
    let _ = write!(
        o,
        "<rect class=\"hit\" x=\"{:.2}\" y=\"{TOP}\" width=\"{:.2}\" height=\"{:.2}\"/>",
        xc - half,
        2.0 * half,
        3.0 * PANEL + 2.0 * GAP
    );
    let fin = |v: f64| v.is_finite();
    if fin(p.reliability_lo) && fin(p.reliability_hi) {
        let _ = write!(
            o,
            "<line class=\"interval\" x1=\"{xc:.2}\" y1=\"{:.2}\" x2=\"{xc:.2}\" y2=\"{:.2}\"/>",
            pn[0].y(p.reliability_lo),
            pn[0].y(p.reliability_hi)
        );
    }
    if fin(p.reliability) {
        let _ = write!(
            o,
            "<circle class=\"r\" cx=\"{xc:.2}\" cy=\"{:.2}\" r=\"3\"/>",
            pn[0].y(p.reliability)
        );
    }
    if fin(p.di) {
        let _ = write!(
            o,
            "<circle class=\"d\" cx=\"{xc:.2}\" cy=\"{:.2}\" r=\"3\"/>",
            pn[1].y(p.di)
        );
    }
    let q = &p.response;
    if [q.min, q.q1, q.q3, q.max].iter().all(|v| v.is_finite()) {
        let b = &pn[2];
        let _ = write!(
            o,
            "<line class=\"whisker\" x1=\"{xc:.2}\" y1=\"{:.2}\" x2=\"{xc:.2}\" y2=\"{:.2}\"/><rect class=\"box\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\"/><line class=\"median\" x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\"/>",
            b.y(q.min),
            b.y(q.max),
            xc - half,
            b.y(q.q3),
            2.0 * half,
            (b.y(q.q1) - b.y(q.q3)).max(0.5),
            xc - half,
            b.y(q.median),
            xc + half,
            b.y(q.median)
        );
    }
    o.push_str("</g>\n");
    o
}

/// A panel's frame, its label above it and the values at its bottom and top.
fn frame(pn: &Panel, label: &str) -> String {
    format!(
        "<rect class=\"frame\" x=\"{LEFT}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{PANEL}\"/><text class=\"panel-label\" x=\"{LEFT}\" y=\"{:.2}\">{}</text><text class=\"tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text><text class=\"tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>\n",
        pn.top,
        W - LEFT - RIGHT,
        pn.top - 6.0,
        esc(label),
        LEFT - 6.0,
        pn.top + 10.0,
        short(pn.hi),
        LEFT - 6.0,
        pn.top + PANEL,
        short(pn.lo)
    )
}

/// A tick value to four significant digits.
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return fmt_num(v);
    }
    let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    fmt_num(format!("{v:.digits$}").parse().unwrap_or(v))
}

/// The swept axis under a chart whose plot ends at `bottom`: ticks at about ten of its values
/// `xs` (placed by `x`) and its description `desc`.
pub(super) fn x_axis(xs: &[f64], x: &dyn Fn(f64) -> f64, bottom: f64, desc: &str) -> String {
    let n = xs.len();
    let every = n.div_ceil(10).max(1);
    let mut o = String::new();
    for (i, &v) in xs.iter().enumerate() {
        if i % every == 0 || i + 1 == n {
            let _ = writeln!(
                o,
                "<text class=\"tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
                x(v),
                bottom + 16.0,
                fmt_num(v)
            );
        }
    }
    let _ = writeln!(
        o,
        "<text class=\"desc\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
        LEFT + (W - LEFT - RIGHT) / 2.0,
        bottom + 40.0,
        esc(desc)
    );
    o
}

/// The caption of a design chart: the axis, and the slice when there are other axes.
pub fn caption(pr: &Profile) -> String {
    let s = pr.s;
    let mut c = format!(
        "Design chart (Figure 6) along {}: R with its interval, {}, and {} over the cases",
        pr.key(),
        s.options.damping.symbol,
        s.options.response.name
    );
    if !pr.slice.is_empty() {
        let _ = write!(c, "; at {}", pr.slice);
    }
    if let Some(a) = s.anchor() {
        let _ = write!(
            c,
            "; marked: {}",
            axis_value(pr.key(), s.grid.value(a, pr.axis))
        );
    }
    c
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn ticks_to_four_significant_digits() {
        assert_eq!(short(0.820812), "0.8208");
        assert_eq!(short(-0.022888), "-0.02289");
        assert_eq!(short(1234.56), "1235");
        assert_eq!(short(0.0), "0");
    }
}
