//! A load study's page (a random or record study with a threshold): its risk profiles and risk
//! maps drawn one element per design ([`super::numbers`]), from the same [`RiskCharts`] as the
//! PNG and SVG files: the number the designs are ranked by (`lambda_f` with a hazard, else `p_f`
//! at the design intensity). A design's element carries the summary's `p_f` and (with a hazard)
//! `lambda_f` columns with their intervals beside the common ones ([`super::hover::data`]); its
//! hover text says the number and its interval, `p_f` at the design intensity where the number
//! is `lambda_f`, the response, zone, class and rank.

use std::fmt::Write;

use super::hover::{data, num};
use super::markdown::esc;
use super::numbers::NumberChart;
use crate::reduce::random::RandomSummary;
use crate::reduce::{PointStats, Summary};
use crate::report::charts::common::interval::{Value, short};
use crate::report::charts::risk::{RiskCharts, slice_text};
use crate::report::markdown::{design_text, f};
use crate::report::text::{axis_value, thousands};

/// The page's drawn risk charts, by the file name of the plotters SVG each stands for (none
/// where the study has no risk chart).
pub fn interactive(s: &Summary, rs: &RandomSummary) -> Vec<(String, String)> {
    let Some(rc) = RiskCharts::of(s, rs) else {
        return Vec::new();
    };
    let value = |d: u64| rc.n.of(d);
    let open = |p: &PointStats, tag: &str, attrs: &str| open(&rc, rs, p, tag, attrs);
    let chart = NumberChart {
        s,
        kind: "risk",
        label: &rc.n.label,
        bar: &rc.n.bar,
        anchor: rc.anchor,
        bare: rc.bare,
        value: &value,
        open: &open,
    };
    let mut out = Vec::new();
    for (axis, stem, designs) in rc.profiles() {
        let html = format!(
            "<figcaption>{}</figcaption>\n<div class=\"svg\">{}</div>\n{}",
            esc(&caption(
                &rc,
                &[axis],
                &format!("along {}", s.grid.key(axis))
            )),
            chart.profile_svg(axis, &designs),
            chart.legend(&designs, false)
        );
        out.push((format!("{stem}.svg"), html));
    }
    for ((a, b), stem, designs) in rc.maps() {
        let g = &s.grid;
        let html = format!(
            "<figcaption>{}</figcaption>\n<div class=\"svg\">{}</div>\n{}",
            esc(&caption(
                &rc,
                &[a, b],
                &format!("over {} (up) and {} (across)", g.key(a), g.key(b))
            )),
            chart.map_svg((a, b), &designs),
            chart.legend(&designs, true)
        );
        out.push((format!("{stem}.svg"), html));
    }
    out
}

/// `Annual rate of failure λ_f along d; slice at m = 0.2 kg; marked: the best design`.
fn caption(rc: &RiskCharts, shown: &[usize], over: &str) -> String {
    let slice = slice_text(rc.s, rc.anchor, shown);
    format!(
        "{} {over}{}; marked: the best design, {}",
        rc.n.what,
        if slice.is_empty() {
            String::new()
        } else {
            format!("; slice at {slice}")
        },
        design_text(rc.s, rc.anchor)
    )
}

/// A number as words: `0.013 (95 % interval 0.013 – 0.014)`, or `below 0.018 (no run passed)`.
fn value_text(v: &Value) -> String {
    if v.bound {
        format!(
            "below {} (no run passed: the bound of its 95 % interval)",
            short(v.v)
        )
    } else {
        format!(
            "{} (95 % interval {} – {})",
            short(v.v),
            short_or_zero(v.lo),
            short(v.hi)
        )
    }
}

/// The hover text of a design of a risk chart, one fact a line.
/// `pf`: its `p_f` at the design intensity with its interval ([`RandomSummary::design_pf`]).
fn title(
    rc: &RiskCharts,
    rs: &RandomSummary,
    p: &PointStats,
    pf: Option<(f64, f64, f64)>,
) -> String {
    let s = rc.s;
    let mut o = format!("{} (design point {})", design_text(s, p.point), p.point);
    if p.point == rc.anchor {
        o.push_str("\nthe best design");
    }
    if s.grid.without_damper(p.point) {
        o.push_str("\nno damper (m = 0)");
    }
    match rc.n.of(p.point) {
        Some(v) => {
            let _ = write!(o, "\n{}: {}", rc.n.what, value_text(&v));
        }
        None => {
            let _ = write!(o, "\n{}: none", rc.n.what);
        }
    }
    if rs.hazard.is_some()
        && let Some((v, lo, hi)) = pf
    {
        let at = rs.intensity.as_ref().map_or(String::new(), |i| {
            format!(" at {}", axis_value(&i.key, i.values[i.design]))
        });
        let _ = write!(
            o,
            "\np_f{at}: {} (95 % interval {} – {})",
            short_or_zero(v),
            short_or_zero(lo),
            short_or_zero(hi)
        );
    }
    let r = &s.options.response;
    let _ = write!(
        o,
        "\n{}: median {}, max {} {}",
        r.name,
        f(p.response.median, 4),
        f(p.response.max, 4),
        r.unit
    );
    match s.zone_of(p) {
        Some(z) => {
            let _ = write!(o, "\nzone {}: {}", z.name, z.label());
        }
        None => o.push_str("\nin no zone"),
    }
    let _ = write!(
        o,
        "\nclass: {}\nrank {}",
        p.class.label(),
        p.rank.map_or("–".to_string(), |r| format!(
            "{} of {}",
            thousands(r),
            thousands(s.points.len() as u64)
        ))
    );
    o
}

/// [`short`], and `0` for zero (no run passed).
fn short_or_zero(v: f64) -> String {
    if v == 0.0 { "0".into() } else { short(v) }
}

/// The element that opens a design: its data ([`data`], and the summary's `p_f` and, with a
/// hazard, `lambda_f` columns with their intervals) and its hover text.
fn open(rc: &RiskCharts, rs: &RandomSummary, p: &PointStats, tag: &str, attrs: &str) -> String {
    let s = rc.s;
    let lens: Vec<usize> = (0..s.grid.n_axes()).map(|a| s.grid.n(a)).collect();
    let mut risk = String::new();
    let mut put = |name: &str, (v, lo, hi): (f64, f64, f64)| {
        for (suffix, x) in [("", v), ("_lo", lo), ("_hi", hi)] {
            let _ = write!(risk, " data-{name}{suffix}=\"{}\"", num(x));
        }
    };
    let pf = rs.design_pf(p.point, &lens);
    if let Some(pf) = pf {
        put("p_f", pf);
    }
    if rs.hazard.is_some() {
        let lambda = rs
            .risk_of(p.point)
            .and_then(|d| d.risk.as_ref())
            .map_or((f64::NAN, f64::NAN, f64::NAN), |r| r.lambda_f);
        put("lambda_f", lambda);
    }
    format!(
        "<{tag}{attrs}{}{risk}><title>{}</title>",
        data(s, p),
        esc(&title(rc, rs, p, pf))
    )
}
