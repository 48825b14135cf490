//! Charts of one number per design on the page, drawn as SVG text so that every design is one
//! element with its data and its hover text, as the laboratory's maps and design charts are
//! ([`super::maps`], [`super::profile`]): the number on a `log10` scale with its 95 % interval,
//! or only its bound where no run passed ([`Value`]). The scene says what the number is and
//! what each design's element carries ([`super::random`]: a load study's risk, `lambda_f` or
//! `p_f`).
//!
//! * a profile along one axis: one `<g class="pt">` per design, its interval a whisker, its
//!   estimate a dot (a downward triangle for a bound; hollow for the structure without a
//!   damper, whose number is also a dashed line across);
//! * a map over two axes: one `<rect class="cell">` per design, coloured by `log10` of its
//!   number (the lowest brightest) and labelled with it, the anchor design outlined.

use std::fmt::Write;

use super::hover::hex;
use super::maps::{Frame, axes};
use super::markdown::esc;
use super::profile::{LEFT, RIGHT, TOP, W, x_axis};
use crate::reduce::{PointStats, Summary};
use crate::report::charts::common::interval::{Value, colour_span, log_span, short};
use crate::report::charts::plumbing::{Scale, cell_edges, heat, minmax};
use crate::report::text::{axis_desc, fmt_num};
use crate::store::table::axis_column;

/// The profile's plot height.
const PANEL: f64 = 280.0;
/// Below the plot: the ticks and the axis' description.
const BOTTOM: f64 = 56.0;
/// The map's tallest cell (px): a risk map has few designs, each labelled with its number.
const CELL_TALL: f64 = 80.0;
/// The narrowest cell labelled with its number (`< 0.018`: 7 characters).
const LABEL_WIDTH: f64 = 50.0;

/// What a chart of one number per design draws.
pub struct NumberChart<'a> {
    pub s: &'a Summary,
    /// The charts' `data-kind`: `risk`.
    pub kind: &'a str,
    /// The profile's axis label: `log10 λ_f (failures per year)`.
    pub label: &'a str,
    /// The map's colour ramp: `log10 λ_f per year`.
    pub bar: &'a str,
    /// The design every chart is a slice through, marked on each.
    pub anchor: u64,
    /// The number of the structure without a damper (`m = 0`): a dashed line on the profiles.
    pub bare: Option<Value>,
    /// Each design's number, if it has one.
    pub value: &'a dyn Fn(u64) -> Option<Value>,
    /// The start of a design's element (`tag`, then `attrs`) with its data and its hover text
    /// (`<title>`), left open.
    pub open: &'a dyn Fn(&PointStats, &str, &str) -> String,
}

impl NumberChart<'_> {
    /// The SVG of the profile along `axis` over `designs`.
    pub fn profile_svg(&self, axis: usize, designs: &[u64]) -> String {
        let s = self.s;
        let g = &s.grid;
        let xs: Vec<f64> = designs.iter().map(|&d| g.value(d, axis)).collect();
        let scale = Scale::of(&xs);
        let positions: Vec<f64> = xs.iter().map(|&x| scale.to(x)).collect();
        let edges = cell_edges(&positions);
        let (x0, x1) = (edges[0], edges[edges.len() - 1]);
        let xp = |p: f64| LEFT + (W - LEFT - RIGHT) * (p - x0) / (x1 - x0).max(1e-300);
        let drawn: Vec<(f64, Value)> = designs
            .iter()
            .zip(&positions)
            .filter(|(d, _)| !g.without_damper(**d))
            .filter_map(|(&d, &x)| (self.value)(d).map(|v| (x, v)))
            .collect();
        let (y0, y1) = log_span(&drawn, self.bare);
        let y = |l: f64| TOP + PANEL * (1.0 - (l - y0) / (y1 - y0).max(1e-300));
        let h = TOP + PANEL + BOTTOM;
        let mut o = format!(
            "<svg class=\"profile\" data-kind=\"{}\" data-axes=\"{}\" data-points=\"{}\" viewBox=\"0 0 {W} {h}\" width=\"{W}\" height=\"{h}\" xmlns=\"http://www.w3.org/2000/svg\" role=\"img\">\n",
            self.kind,
            axis_column(g.key(axis)),
            designs.len()
        );
        o += &y_axis(self.label, (y0, y1), &y);
        if let Some(b) = self.bare {
            let yb = y(b.log());
            let _ = writeln!(
                o,
                "<line class=\"threshold\" x1=\"{LEFT}\" y1=\"{yb:.2}\" x2=\"{:.2}\" y2=\"{yb:.2}\"/>",
                W - RIGHT
            );
        }
        let line: Vec<String> = drawn
            .iter()
            .filter(|(_, v)| !v.bound)
            .map(|(x, v)| format!("{:.2},{:.2}", xp(*x), y(v.log())))
            .collect();
        if line.len() > 1 {
            let _ = writeln!(
                o,
                "<polyline class=\"estimate-line\" points=\"{}\"/>",
                line.join(" ")
            );
        }
        for (i, &d) in designs.iter().enumerate() {
            let Some(p) = s.point(d) else { continue };
            let xc = xp(positions[i]);
            let half = ((xp(edges[i + 1]) - xp(edges[i])) * 0.3).clamp(1.0, 10.0);
            o += &(self.open)(p, "g", " class=\"pt\"");
            let _ = write!(
                o,
                "<rect class=\"hit\" x=\"{:.2}\" y=\"{TOP}\" width=\"{:.2}\" height=\"{PANEL}\"/>",
                xc - half,
                2.0 * half
            );
            if let Some(v) = (self.value)(d) {
                o += &mark(&v, xc, y0, &y, g.without_damper(d));
            }
            o.push_str("</g>\n");
        }
        let xa = xp(scale.to(g.value(self.anchor, axis)));
        let _ = writeln!(
            o,
            "<line class=\"anchor-line\" x1=\"{xa:.2}\" y1=\"{TOP}\" x2=\"{xa:.2}\" y2=\"{:.2}\"/><text class=\"anchor-label\" x=\"{:.2}\" y=\"{:.2}\">best</text>",
            TOP + PANEL,
            xa + 4.0,
            TOP + 14.0
        );
        o += &x_axis(
            &xs,
            &|v| xp(scale.to(v)),
            TOP + PANEL,
            &scale.desc(&axis_desc(g.key(axis))),
        );
        o.push_str("</svg>\n");
        o
    }

    /// The map's colour span in `log10` of the number over `designs` (see
    /// [`colour_span`]), and whether it was widened.
    fn span(&self, designs: &[u64]) -> (f64, f64, bool) {
        let cells: Vec<(u64, Option<Value>)> =
            designs.iter().map(|&d| (d, (self.value)(d))).collect();
        let (l0, l1) = minmax(cells.iter().filter_map(|c| c.1.map(|v| v.log())));
        colour_span(l0, l1, &cells)
    }

    /// The SVG of the map over `(a, b)` (`a` up, `b` across) of `designs`.
    pub fn map_svg(&self, (a, b): (usize, usize), designs: &[u64]) -> String {
        let s = self.s;
        let g = &s.grid;
        let fr = Frame::new(g.n(a), g.n(b), CELL_TALL);
        let (cw, ch) = (fr.cw, fr.ch);
        let at = |d: u64| fr.at(g.index(d, a), g.index(d, b));
        let h = fr.height();
        let (l0, l1, _) = self.span(designs);
        let mut o = format!(
            "<svg class=\"map\" data-kind=\"{}\" data-axes=\"{} {}\" data-cells=\"{}\" viewBox=\"0 0 {W} {h}\" width=\"{W}\" height=\"{h}\" xmlns=\"http://www.w3.org/2000/svg\" role=\"img\">\n",
            self.kind,
            axis_column(g.key(a)),
            axis_column(g.key(b)),
            designs.len()
        );
        for &d in designs {
            let Some(p) = s.point(d) else { continue };
            let (x, y) = at(d);
            let v = (self.value)(d);
            let fill = v.map_or("#c8c8c8".to_string(), |v| hex(heat(shade(&v, (l0, l1)))));
            o += &(self.open)(
                p,
                "rect",
                &format!(
                    " class=\"cell\" x=\"{x:.2}\" y=\"{y:.2}\" width=\"{cw:.2}\" height=\"{ch:.2}\" fill=\"{fill}\""
                ),
            );
            o.push_str("</rect>\n");
            // A label only where it fits (about 7 px a character at 12 px); hovering the cell
            // says the number anyway.
            if let Some(v) = v.filter(|_| cw >= LABEL_WIDTH && ch >= 16.0) {
                let dark = shade(&v, (l0, l1)) <= 0.55;
                let _ = writeln!(
                    o,
                    "<text class=\"cell-value{}\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}{}</text>",
                    if dark { " on-dark" } else { "" },
                    x + cw / 2.0,
                    y + ch / 2.0 + 4.0,
                    if v.bound { "&lt; " } else { "" },
                    short(v.v)
                );
            }
        }
        let (x, y) = at(self.anchor);
        let _ = writeln!(
            o,
            "<rect class=\"anchor\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\"><title>the best design</title></rect>",
            x + 1.5,
            y + 1.5,
            cw - 3.0,
            ch - 3.0
        );
        o += &axes(g, (a, b), &fr);
        o.push_str("</svg>\n");
        o
    }

    /// The legend under a chart: the estimate, its interval and a bound (a profile), or the colour
    /// ramp's span (a map); the best design's mark.
    pub fn legend(&self, designs: &[u64], map: bool) -> String {
        let mut o = String::from("<div class=\"legend\">");
        if map {
            let (l0, l1, widened) = self.span(designs);
            let _ = write!(
                o,
                "<span><i class=\"ramp ramp-reversed\"></i>{} from {} (bright) to {} (dark){}</span><span><i class=\"outlined\"></i>the best design</span>",
                esc(self.bar),
                fmt_num((l0 * 100.0).round() / 100.0),
                fmt_num((l1 * 100.0).round() / 100.0),
                if widened {
                    ": the colours span the median 95 % interval, the values differ by less than it"
                } else {
                    ""
                }
            );
        } else {
            o.push_str("<span><i class=\"dot\"></i>estimate</span><span><i class=\"whiskerkey\"></i>95 % interval</span>");
            if designs
                .iter()
                .any(|&d| (self.value)(d).is_some_and(|v| v.bound))
            {
                o.push_str(
                    "<span><i class=\"boundkey\"></i>no run passed: below this bound</span>",
                );
            }
            if let Some(b) = self.bare {
                let _ = write!(
                    o,
                    "<span><i class=\"barekey\"></i>no damper (m = 0): {}{}</span>",
                    if b.bound { "&lt; " } else { "" },
                    short(b.v)
                );
            }
        }
        o.push_str("</div>\n");
        o
    }
}

/// A design's interval (a whisker from the axis' foot `y0` where its lower end is 0) and its
/// estimate (a dot; a downward triangle for a bound; hollow for the structure without a damper,
/// whose number is also the dashed line).
fn mark(v: &Value, xc: f64, y0: f64, y: &dyn Fn(f64) -> f64, bare: bool) -> String {
    let lo = if v.lo > 0.0 { v.lo.log10() } else { y0 };
    let yv = y(v.log());
    let mut o = format!(
        "<line class=\"interval\" x1=\"{xc:.2}\" y1=\"{:.2}\" x2=\"{xc:.2}\" y2=\"{:.2}\"/>",
        y(lo),
        y(v.hi.log10().max(v.log()))
    );
    if v.bound {
        let _ = write!(
            o,
            "<polygon class=\"bound\" points=\"{:.2},{:.2} {:.2},{:.2} {xc:.2},{:.2}\"/>",
            xc - 6.0,
            yv - 5.0,
            xc + 6.0,
            yv - 5.0,
            yv + 6.0
        );
    } else {
        let _ = write!(
            o,
            "<circle class=\"{}\" cx=\"{xc:.2}\" cy=\"{yv:.2}\" r=\"4\"/>",
            if bare { "bare" } else { "r" }
        );
    }
    o
}

/// The profile's frame, its `log10` ticks (about five) and its label.
fn y_axis(label: &str, (y0, y1): (f64, f64), y: &dyn Fn(f64) -> f64) -> String {
    let mut o = format!(
        "<rect class=\"frame\" x=\"{LEFT}\" y=\"{TOP}\" width=\"{:.2}\" height=\"{PANEL}\"/>\n",
        W - LEFT - RIGHT
    );
    let step = nice_step((y1 - y0) / 5.0);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let mut k = (y0 / step).ceil();
    while k * step <= y1 + 1e-9 * step {
        let l = k * step;
        let yy = y(l);
        let _ = writeln!(
            o,
            "<line class=\"grid\" x1=\"{LEFT}\" y1=\"{yy:.2}\" x2=\"{:.2}\" y2=\"{yy:.2}\"/><text class=\"tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
            W - RIGHT,
            LEFT - 6.0,
            yy + 4.0,
            format!("{l:.decimals$}").replace('-', "−")
        );
        k += 1.0;
    }
    let _ = writeln!(
        o,
        "<text class=\"desc\" transform=\"translate(16 {:.2}) rotate(-90)\" text-anchor=\"middle\">{}</text>",
        TOP + PANEL / 2.0,
        esc(label)
    );
    o
}

/// A tick step of 1, 2 or 5 times a power of ten, at least `raw`.
fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

/// The shade of a value over the span `(l0, l1)`: the lowest brightest.
fn shade(v: &Value, (l0, l1): (f64, f64)) -> f64 {
    1.0 - (v.log() - l0) / (l1 - l0).max(1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::testing;

    /// Every design of a map or a profile is one element, opened by the scene's `open`; the
    /// anchor is outlined once; a cell carries its number where the label fits, and a number
    /// known only as a bound reads `< `.
    #[test]
    fn one_element_per_design_and_labels_only_where_they_fit() {
        let chart_of = |m: Vec<f64>, d: Vec<f64>, check: &dyn Fn(&NumberChart, usize)| {
            let study = testing::study(vec![("m", m), ("d", d)], 1);
            let s = testing::reduce_simulated(&study);
            let value = |p: u64| {
                (p > 0).then_some(Value {
                    v: 1e-3 * (p + 1) as f64,
                    lo: 5e-4 * (p + 1) as f64,
                    hi: 2e-3 * (p + 1) as f64,
                    bound: p == 1,
                })
            };
            let open = |p: &PointStats, tag: &str, attrs: &str| {
                format!("<{tag}{attrs} data-point=\"{}\"><title>t</title>", p.point)
            };
            let chart = NumberChart {
                s: &s,
                kind: "risk",
                label: "log10 p_f",
                bar: "log10 p_f",
                anchor: 2,
                bare: None,
                value: &value,
                open: &open,
            };
            check(&chart, s.points.len());
        };
        // 2 x 2 designs: 325-px cells, every number labelled (design 0 has none).
        chart_of(vec![0.05, 0.1], vec![0.01, 0.02], &|c, n| {
            let all: Vec<u64> = (0..n as u64).collect();
            let map = c.map_svg((0, 1), &all);
            assert_eq!(map.matches("<rect class=\"cell\"").count(), 4);
            assert_eq!(map.matches(" data-point=").count(), 4);
            assert_eq!(map.matches("<rect class=\"anchor\"").count(), 1);
            assert_eq!(map.matches("class=\"cell-value").count(), 3);
            assert!(map.contains(">&lt; 0.0020</text>"), "{map}");
            let profile = c.profile_svg(1, &[2, 3]);
            assert_eq!(profile.matches("<g class=\"pt\"").count(), 2);
            assert_eq!(profile.matches("<circle class=\"r\"").count(), 2);
        });
        // 2 x 20 designs: 32-px cells, too narrow for a label; still one cell each.
        let d: Vec<f64> = (1..=20).map(|k| 0.001 * k as f64).collect();
        chart_of(vec![0.05, 0.1], d, &|c, n| {
            let all: Vec<u64> = (0..n as u64).collect();
            let map = c.map_svg((0, 1), &all);
            assert_eq!(map.matches("<rect class=\"cell\"").count(), 40);
            assert_eq!(map.matches("class=\"cell-value").count(), 0);
        });
    }

    #[test]
    fn tick_steps_are_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(nice_step(0.07), 0.1);
        assert_eq!(nice_step(0.15), 0.2);
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(2.0), 2.0);
        assert_eq!(nice_step(0.0), 1.0);
    }
}
