//! The random and record scenes' section of a study that sweeps several damper units
//! (model.md §14): does splitting the added mass, or spreading the clearances, change the
//! risk?
//!
//! The designs are grouped by every swept axis but `units` and `d_spread` (a group: one
//! clearance, one mass, ...). In each group the reference is one unit with equal clearances
//! (the smallest `units` and `d_spread` swept), and every other design's figure (the annual
//! rate of failure `lambda_f` over the hazard when the study gives one, else `p_f` at the
//! design intensity) is set against it with both 95 % intervals: a design differs from the
//! reference only where the intervals do not overlap.

use std::fmt::Write;

use crate::reduce::Summary;
use crate::reduce::random::RandomSummary;
use crate::report::markdown::words::{f, prob};
use crate::report::text::axis_value;

/// The axes that describe the units.
const UNIT_AXES: [&str; 2] = ["units", "d_spread"];

/// One design's figure with its interval `(value, lo, hi)`, or `None` without one.
fn figure(s: &Summary, rs: &RandomSummary, p: u64) -> Option<(f64, f64, f64)> {
    if rs.hazard.is_some() && !rs.risk.is_empty() {
        return rs
            .risk_of(p)
            .and_then(|r| r.risk.as_ref())
            .map(|r| r.lambda_f);
    }
    let lens: Vec<usize> = (0..s.grid.n_axes()).map(|a| s.grid.n(a)).collect();
    rs.design_pf(p, &lens)
}

/// The section, empty unless the study sweeps `units` or `d_spread` and sets a limit.
pub(super) fn section(s: &Summary, rs: &RandomSummary) -> String {
    let unit_axes: Vec<usize> = (0..s.grid.n_axes())
        .filter(|&a| UNIT_AXES.contains(&s.grid.key(a)) && s.grid.n(a) > 1)
        .collect();
    if unit_axes.is_empty() || rs.threshold.is_none() {
        return String::new();
    }
    let risk = rs.hazard.is_some() && !rs.risk.is_empty();
    let name = if risk { "λ_f per year" } else { "p_f" };
    let others: Vec<usize> = (0..s.grid.n_axes())
        .filter(|a| !unit_axes.contains(a))
        .collect();
    let mut o = String::from("\n## Several units\n\n");
    let _ = writeln!(
        o,
        "The same added mass split over several units, each in its own cavity (docs/model.md \
         §14). Designs that share every other axis are compared with one unit of equal \
         clearances (the smallest `units` and `d_spread` swept): {}, with its 95 % interval. \
         A design differs from that reference only where the two intervals do not overlap.\n",
        if risk {
            "the annual rate of failure over the hazard"
        } else {
            "`p_f` at the design intensity"
        }
    );
    let _ = writeln!(
        o,
        "| group | reference {name} | other designs' {name}, lowest – highest | change | \
         designs apart from the reference |\n|---|---|---|---|---|"
    );
    let mut groups: Vec<u64> = s
        .points
        .iter()
        .map(|p| p.point)
        .filter(|&p| unit_axes.iter().all(|&a| s.grid.index(p, a) == 0))
        .collect();
    groups.sort_unstable();
    let mut widest = 0.0f64;
    let mut apart_all = 0;
    let mut compared_all = 0;
    for base in groups {
        let Some(r) = figure(s, rs, base) else {
            continue;
        };
        let members = group_members(s, rs, base, &unit_axes);
        if members.is_empty() {
            continue;
        }
        let (change, apart) = group_row(&mut o, s, (&unit_axes, &others), base, r, &members);
        widest = widest.max(change);
        apart_all += apart;
        compared_all += members.len();
    }
    let _ = writeln!(
        o,
        "\n{}\n",
        if compared_all == 0 {
            "No design of several units has a figure to compare.".to_string()
        } else if apart_all == 0 {
            format!(
                "Splitting the mass or spreading the clearances moved {name} by at most {} % \
                 here, and every design's interval overlaps its reference's: these motions do \
                 not tell the splits apart.",
                f(100.0 * widest, 1)
            )
        } else {
            format!(
                "{apart_all} of {compared_all} designs of several units differ from one unit \
                 beyond the intervals (listed above); the largest change is {} %.",
                f(100.0 * widest, 1)
            )
        }
    );
    o
}

/// The other designs of `base`'s group (every combination of the unit axes' values but the
/// reference's) that have a figure, with it.
fn group_members(
    s: &Summary,
    rs: &RandomSummary,
    base: u64,
    unit_axes: &[usize],
) -> Vec<(u64, (f64, f64, f64))> {
    let mut lines: Vec<u64> = vec![base];
    for &a in unit_axes {
        lines = lines
            .iter()
            .flat_map(|&p| (0..s.grid.n(a)).map(move |i| (p, i)))
            .map(|(p, i)| s.grid.with_index(p, a, i))
            .collect();
    }
    lines
        .into_iter()
        .filter(|&p| p != base)
        .filter_map(|p| figure(s, rs, p).map(|v| (p, v)))
        .collect()
}

/// One group's row of the table: the reference `r` (design `base`), the other designs'
/// lowest and highest figures, the change against the reference and the designs whose
/// intervals do not overlap its. Returns the largest change (a fraction, 0 without one) and
/// how many designs lie apart.
fn group_row(
    o: &mut String,
    s: &Summary,
    (unit_axes, others): (&[usize], &[usize]),
    base: u64,
    r: (f64, f64, f64),
    members: &[(u64, (f64, f64, f64))],
) -> (f64, usize) {
    let lo = members.iter().map(|m| m.1.0).fold(f64::INFINITY, f64::min);
    let hi = members
        .iter()
        .map(|m| m.1.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let change = |v: f64| if r.0 > 0.0 { v / r.0 - 1.0 } else { f64::NAN };
    let (c_lo, c_hi) = (change(lo), change(hi));
    let widest = if c_lo.is_finite() {
        c_lo.abs().max(c_hi.abs())
    } else {
        0.0
    };
    let apart: Vec<String> = members
        .iter()
        .filter(|(_, v)| v.1 > r.2 || v.2 < r.1)
        .map(|(p, v)| {
            let who: Vec<String> = unit_axes
                .iter()
                .map(|&a| axis_value(s.grid.key(a), s.grid.value(*p, a)))
                .collect();
            format!("{} ({})", who.join(", "), prob(v.0))
        })
        .collect();
    let group: Vec<String> = others
        .iter()
        .map(|&a| axis_value(s.grid.key(a), s.grid.value(base, a)))
        .collect();
    let _ = writeln!(
        o,
        "| {} | {} [{}, {}] | {} – {} | {} to {} % | {} |",
        if group.is_empty() {
            "every design".to_string()
        } else {
            group.join(", ")
        },
        prob(r.0),
        prob(r.1),
        prob(r.2),
        prob(lo),
        prob(hi),
        f(100.0 * c_lo, 1),
        f(100.0 * c_hi, 1),
        if apart.is_empty() {
            "none".to_string()
        } else {
            apart.join("; ")
        }
    );
    (widest, apart.len())
}
