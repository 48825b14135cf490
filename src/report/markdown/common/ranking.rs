//! The ten best designs by perfectibility and the Pareto set on (R, DI).

use std::fmt::Write;

use crate::report::markdown::words::{MAX_ROWS, cm, confidence, design_text, f, interval, ranked};

use crate::reduce::{PointStats, Summary};
use crate::report::text::thousands;

fn head(s: &Summary) -> String {
    format!(
        "| rank | design | R | R interval ({}) | μn | {} | {} mean (cm) | P (%) | zone | robust |\n|---|---|---|---|---|---|---|---|---|---|",
        confidence(s),
        s.options.damping.label(),
        s.options.response.name
    )
}

fn row(s: &Summary, p: &PointStats) -> String {
    format!(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
        p.rank.map(|r| r.to_string()).unwrap_or_default(),
        design_text(s, p.point),
        f(p.reliability, 5),
        interval(p.reliability_lo, p.reliability_hi, 5),
        f(p.safety_factor, 3),
        f(p.di, 5),
        cm(p.response.mean),
        f(p.perfectibility, 2),
        s.zone_name(p),
        if p.robust { "yes" } else { "no" }
    )
}

pub fn top(s: &Summary) -> String {
    let mut o = format!("## Top 10 by perfectibility\n\n{}\n", head(s));
    for p in ranked(s).iter().take(10) {
        let _ = writeln!(o, "{}", row(s, p));
    }
    let _ = writeln!(o);
    o
}

pub fn pareto(s: &Summary) -> String {
    let mut pareto: Vec<_> = s.points.iter().filter(|p| p.pareto).collect();
    pareto.sort_by_key(|p| p.rank);
    let d = s.options.damping.symbol;
    let mut o = format!(
        "## Pareto set on (R, {d})\n\n{} design points are not beaten on both R and {d} by any other:\n\n{}\n",
        thousands(pareto.len() as u64),
        head(s)
    );
    for p in pareto.iter().take(MAX_ROWS) {
        let _ = writeln!(o, "{}", row(s, p));
    }
    if pareto.len() > MAX_ROWS {
        let _ = writeln!(
            o,
            "\n… and {} more (column `pareto` of the summary).",
            pareto.len() - MAX_ROWS
        );
    }
    let _ = writeln!(o);
    o
}
