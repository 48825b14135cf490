//! The zones (the paper's Table III): one row per connected region, and with many zones a
//! summary per class first.

use std::fmt::Write;

use crate::report::markdown::words::{MAX_ROWS, f};

use crate::reduce::{Class, Summary, Zone};
use crate::report::text::{count, fmt_num, thousands};

/// The report's section on the zones: how they were drawn, per class with two or more axes,
/// then one row per zone (the largest [`MAX_ROWS`]).
pub fn section(s: &Summary) -> String {
    let mut o = String::from("## Zones (Table III)\n\n");
    let declared = s.zones.iter().any(Zone::declared);
    how_drawn(&mut o, s, declared);
    if !declared && s.grid.n_axes() >= 2 {
        o += &by_class(s);
    }
    let shown = rows(&mut o, s);
    if shown.len() < s.zones.len() {
        let rest: usize = (0..s.zones.len())
            .filter(|i| !shown.contains(i))
            .map(|i| s.zones[i].n_points)
            .sum();
        let _ = writeln!(
            o,
            "\nThe {} largest zones; {} smaller ones ({} points) are in `zones.parquet`.",
            shown.len(),
            s.zones.len() - shown.len(),
            thousands(rest as u64)
        );
    }
    let _ = writeln!(
        o,
        "\nMerged in: the zone's points that came from a smaller region merged into it; their own class is not the zone's (a point of a \"reliable\" zone merged in may not show R at or above r_min: its own class is in `summary.parquet`, column `class`). The ranges are the zone's bounding box; the best design has the highest perfectibility in the zone, the representative one lies deepest inside it (the most grid steps from its border and from the edge of the grid). Zone perfectibility is eq. 11 on the zone means, normalised by the best zone means (as the paper's Table III). A zone \"around a jump\" is not recommended whatever its R: there a small error in the design variable changes the behaviour abruptly (the paper's zone II).\n"
    );
    o
}

/// How the zones were drawn: declared by the study, or connected regions of one class merged
/// above the smallest size.
fn how_drawn(o: &mut String, s: &Summary, declared: bool) {
    if declared {
        let _ = writeln!(
            o,
            "Zones declared in the study (they override the automatic ones; a point belongs to the first declared zone whose range holds it).\n"
        );
    } else {
        let merge = if s.min_zone_points > 1 {
            format!(
                "a region of fewer than {} points ({} % of the design points) is merged into the neighbouring region it shares the most boundary with, except regions around a jump or without data",
                s.min_zone_points,
                fmt_num(100.0 * s.options.zones.min_zone)
            )
        } else {
            format!(
                "no region is merged ({} % of the design points is less than two points)",
                fmt_num(100.0 * s.options.zones.min_zone)
            )
        };
        let _ = writeln!(
            o,
            "Each zone is one connected region of design points of one class (neighbours differ by one step along one axis); {merge}. {}.\n",
            count(s.zones.len() as u64, "zone", "zones")
        );
    }
}

/// The table: every zone, or the largest [`MAX_ROWS`] in name order; returns the zones shown.
fn rows(o: &mut String, s: &Summary) -> Vec<usize> {
    let g = &s.grid;
    let mut shown: Vec<usize> = (0..s.zones.len()).collect();
    if shown.len() > MAX_ROWS {
        shown.sort_by_key(|&i| (std::cmp::Reverse(s.zones[i].n_points), i));
        shown.truncate(MAX_ROWS);
        shown.sort_unstable();
    }
    let mut head = String::from("| zone | what it is | points | merged in |");
    let mut rule = String::from("|---|---|---|---|");
    for (k, _) in &g.axes {
        let _ = write!(head, " {k} |");
        rule.push_str("---|");
    }
    let _ = writeln!(
        o,
        "{head} best design (P %) | representative design | mean R | mean {} | perfectibility (%) |\n{rule}---|---|---|---|---|",
        s.options.damping.label()
    );
    for &i in &shown {
        let z = &s.zones[i];
        let ranges: String = z
            .ranges
            .iter()
            .map(|(a, b)| {
                if a == b {
                    format!(" {} |", fmt_num(*a))
                } else {
                    format!(" {} – {} |", fmt_num(*a), fmt_num(*b))
                }
            })
            .collect();
        let best = z
            .best
            .and_then(|p| s.point(p))
            .map(|p| format!("{} ({})", values(s, p.point), f(p.perfectibility, 1)))
            .unwrap_or_else(|| "–".into());
        let rep = z
            .representative
            .map(|p| values(s, p))
            .unwrap_or_else(|| "–".into());
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} |{ranges} {best} | {rep} | {} | {} | {} |",
            z.name,
            z.label(),
            thousands(z.n_points as u64),
            thousands(z.n_merged as u64),
            f(z.mean_r, 4),
            f(z.mean_di, 4),
            f(z.perfectibility, 1)
        );
    }
    shown
}

/// Zones and points per class.
fn by_class(s: &Summary) -> String {
    let mut o =
        String::from("| class | zones | points | share of the points |\n|---|---|---|---|\n");
    let total: usize = s.zones.iter().map(|z| z.n_points).sum();
    for c in Class::ALL {
        let zs: Vec<&Zone> = s.zones.iter().filter(|z| z.class == Some(c)).collect();
        if zs.is_empty() {
            continue;
        }
        let n: usize = zs.iter().map(|z| z.n_points).sum();
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} % |",
            c.label(),
            zs.len(),
            thousands(n as u64),
            f(100.0 * n as f64 / total.max(1) as f64, 1)
        );
    }
    let _ = writeln!(o);
    o
}

/// A design's axis values without units, compact: `0.5, 0.02, 0.01`.
fn values(s: &Summary, p: u64) -> String {
    if s.grid.n_axes() == 0 {
        // Nothing swept but the frequency: the zone's one design.
        return "the study's system".into();
    }
    (0..s.grid.n_axes())
        .map(|a| fmt_num(s.grid.value(p, a)))
        .collect::<Vec<_>>()
        .join(", ")
}
