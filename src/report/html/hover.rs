//! What hovering a design point shows, and the data a test checks it by: one element per design
//! point carries `data-<column>` attributes named and valued exactly as the summary's columns
//! (`summary.parquet`: numbers in Rust's shortest round-trip form, so a reader gets the same
//! `f64`), and a `<title>` with the same numbers for a person.

use std::fmt::Write;

use plotters::style::RGBColor;

use super::markdown::esc;
use crate::reduce::{PointStats, Summary};
use crate::report::markdown::{design_text, f};
use crate::report::text::{fmt_num, thousands};
use crate::store::table::axis_column;

/// A colour as CSS `#rrggbb`.
pub fn hex(c: RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// A number as an attribute value: Rust's shortest round-trip form, empty when not finite (the
/// summary's empty cell; a page never shows `NaN`).
pub fn num(v: f64) -> String {
    if v.is_finite() {
        v.to_string()
    } else {
        String::new()
    }
}

/// The `data-*` attributes of a design point (with a leading space): `point`, the axes, the
/// zone and class, R and its interval, the damping column, perfectibility, rank, merged.
pub fn data(s: &Summary, p: &PointStats) -> String {
    let mut o = format!(" data-point=\"{}\"", p.point);
    for a in 0..s.grid.n_axes() {
        let _ = write!(
            o,
            " data-{}=\"{}\"",
            axis_column(s.grid.key(a)),
            s.grid.value(p.point, a)
        );
    }
    let _ = write!(
        o,
        " data-zone=\"{}\" data-class=\"{}\" data-reliability=\"{}\" data-reliability_lo=\"{}\" data-reliability_hi=\"{}\" data-{}=\"{}\" data-perfectibility=\"{}\" data-rank=\"{}\"",
        esc(s.zone_name(p)),
        esc(p.class.label()),
        num(p.reliability),
        num(p.reliability_lo),
        num(p.reliability_hi),
        s.options.damping.name,
        num(p.di),
        num(p.perfectibility),
        p.rank.map(|r| r.to_string()).unwrap_or_default(),
    );
    if s.merged(p) {
        o.push_str(" data-merged=\"true\"");
    }
    if s.recommended == Some(p.point) {
        o.push_str(" data-recommended=\"true\"");
    }
    o
}

/// The hover text of a design point, one fact a line.
pub fn title(s: &Summary, p: &PointStats) -> String {
    let d = &s.options.damping;
    let mut o = format!("{} (design point {})", design_text(s, p.point), p.point);
    if s.recommended == Some(p.point) {
        o.push_str("\nthe recommended design");
    }
    match s.zone_of(p) {
        Some(z) => {
            let _ = write!(o, "\nzone {}: {}", z.name, z.label());
            if s.merged(p) {
                o.push_str(" (merged in from a smaller region)");
            }
        }
        None => o.push_str("\nin no zone"),
    }
    let _ = write!(
        o,
        "\nclass: {}\nR = {} ({} % interval {} – {})\n{} = {}\nperfectibility {} %, rank {}",
        p.class.label(),
        f(p.reliability, 5),
        fmt_num(100.0 * s.confidence),
        f(p.reliability_lo, 5),
        f(p.reliability_hi, 5),
        d.symbol,
        d.with_unit(&f(p.di, 5)),
        f(p.perfectibility, 2),
        p.rank.map_or("–".to_string(), |r| format!(
            "{} of {}",
            thousands(r),
            thousands(s.points.len() as u64)
        )),
    );
    o
}

/// `<title>…</title>` of a design point.
pub fn title_element(s: &Summary, p: &PointStats) -> String {
    format!("<title>{}</title>", esc(&title(s, p)))
}
