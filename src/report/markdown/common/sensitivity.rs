//! Sensitivity indices per quantity and axis (model.md §9).

use std::fmt::Write;

use crate::report::markdown::words::f;

use crate::reduce::Summary;
use crate::report::text::thousands;

pub fn section(s: &Summary) -> String {
    if s.sensitivity.is_empty() || s.grid.n_axes() < 2 {
        return String::new();
    }
    let g = &s.grid;
    let mut o = String::from("## Sensitivity\n\n");
    let _ = writeln!(
        o,
        "Exact ANOVA on the grid, every design point weighted equally: the first-order index S of an axis is the share of a quantity's variance explained by that axis alone, the total-effect index S_T adds its interactions with the others (S_T − S is the interaction share).\n"
    );
    let mut head = String::from("| quantity |");
    let mut rule = String::from("|---|");
    for (k, _) in &g.axes {
        let _ = write!(head, " {k}: S | {k}: S_T |");
        rule.push_str("---|---|");
    }
    let _ = writeln!(o, "{head} points |\n{rule}---|");
    let mut quantities: Vec<&str> = Vec::new();
    for v in &s.sensitivity {
        if !quantities.contains(&v.quantity.as_str()) {
            quantities.push(&v.quantity);
        }
    }
    for q in quantities {
        let rows: Vec<_> = s.sensitivity.iter().filter(|v| v.quantity == q).collect();
        let cells: String = rows
            .iter()
            .map(|v| format!(" {} | {} |", f(v.first_order, 3), f(v.total, 3)))
            .collect();
        let n = rows.first().map_or(0, |v| v.n_points);
        let _ = writeln!(o, "| {q} |{cells} {} |", thousands(n as u64));
    }
    let n_points = s.points.len();
    let used = s.sensitivity.first().map_or(0, |v| v.n_points);
    if used < n_points || (n_points as u64) < s.n_points_planned {
        let _ = writeln!(
            o,
            "\nComputed over the {} design points whose cases all ended ok, of {} planned: the grid is incomplete, so the indices are the same sums over the points that remain, no longer an exact decomposition.",
            thousands(used as u64),
            thousands(s.n_points_planned)
        );
    }
    let _ = writeln!(o, "\nAlso in `sensitivity.parquet`.\n");
    o
}
