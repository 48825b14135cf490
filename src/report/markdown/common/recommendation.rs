//! The recommended design, why better-ranked designs were passed over, and whether the best
//! designs sit on the edge of the swept range.

use std::fmt::Write;

use crate::report::markdown::words::{cm, confidence, design_text, f, ranked, reliability_clause};

use crate::reduce::common::grid::End;
use crate::reduce::common::recommend::{NotRobust, reasons};
use crate::reduce::{PointStats, Summary};
use crate::report::text::{axis_unit, axis_value, fmt_num, thousands};

/// Better-ranked designs listed with the reasons they were passed over, at most.
const PASSED_OVER: usize = 5;

pub fn section(s: &Summary) -> String {
    let mut o = String::from("## Recommended design\n\n");
    let ranked = ranked(s);
    match s.recommended.and_then(|p| s.point(p)) {
        Some(p) => {
            let _ = writeln!(
                o,
                "**{}** (design point {}).\n",
                design_text(s, p.point),
                p.point
            );
            o += &figures(s, p, ranked.len());
            let n = s.grid.neighbourhood(p.point).len();
            let _ = writeln!(
                o,
                "Robust: the {n} designs within one grid step of it on every axis (itself included) all lie in recommended zones — R shown at or above r_min = {} at {} confidence, no jump nearby — so an error of one step in any design variable, or in all of them, keeps the design there.\n",
                fmt_num(s.r_min),
                confidence(s)
            );
            let better: Vec<&&PointStats> = ranked.iter().take_while(|q| q.rank < p.rank).collect();
            if !better.is_empty() {
                let _ = writeln!(
                    o,
                    "{} design{} rank{} higher but {} not robust:\n",
                    better.len(),
                    if better.len() == 1 { "" } else { "s" },
                    if better.len() == 1 { "s" } else { "" },
                    if better.len() == 1 { "is" } else { "are" }
                );
                for q in better.iter().take(PASSED_OVER) {
                    let _ = writeln!(
                        o,
                        "- rank {}, {} (P = {} %): {}",
                        q.rank.unwrap_or(0),
                        design_text(s, q.point),
                        f(q.perfectibility, 2),
                        why(s, q)
                    );
                }
                if better.len() > PASSED_OVER {
                    let _ = writeln!(
                        o,
                        "- … and {} more (column `robust` of the summary)",
                        better.len() - PASSED_OVER
                    );
                }
                let _ = writeln!(o);
            }
        }
        None if !s.computes_r() => {
            let _ = writeln!(
                o,
                "**No design is recommended**: a recommendation needs R, and the study gives no strength (above)."
            );
            if let Some(p) = ranked.first() {
                let _ = writeln!(
                    o,
                    "\nThe best ranked design, by {} alone, is {} (design point {}).\n",
                    s.options.damping.symbol,
                    design_text(s, p.point),
                    p.point
                );
                o += &figures(s, p, ranked.len());
            } else {
                let _ = writeln!(o);
            }
        }
        None => {
            let _ = writeln!(
                o,
                "**No design is robust**: none has its whole neighbourhood (one grid step on every axis) in recommended zones (R shown at or above r_min = {} at {} confidence, no jump nearby), away from the edge of the swept range.\n",
                fmt_num(s.r_min),
                confidence(s)
            );
            if let Some(p) = ranked.first() {
                let _ = writeln!(
                    o,
                    "The best ranked design is {} (design point {}); it is not robust: {}.\n",
                    design_text(s, p.point),
                    p.point,
                    why(s, p)
                );
                o += &figures(s, p, ranked.len());
            }
        }
    }
    o += &edges(s);
    o
}

/// R, μn, DI, the response and P of a design, and its zone.
fn figures(s: &Summary, p: &PointStats, n_ranked: usize) -> String {
    let zone = s
        .zone_of(p)
        .map(|z| format!(" Zone {} ({}).", z.name, z.label()))
        .unwrap_or_default();
    let mut reliability = reliability_clause(s, p, 3);
    if !reliability.is_empty() {
        reliability.push_str(", ");
    }
    format!(
        "{reliability}{} = {}, {} mean {} cm (SD {} cm), perfectibility {} % (rank {} of {}).{zone}\n\n",
        s.options.damping.symbol,
        s.options.damping.with_unit(&f(p.di, 5)),
        s.options.response.name,
        cm(p.response.mean),
        cm(p.response.sd),
        f(p.perfectibility, 2),
        p.rank.map(thousands).unwrap_or_else(|| "–".into()),
        thousands(n_ranked as u64)
    )
}

/// The reasons a design is not robust, as a phrase.
fn why(s: &Summary, p: &PointStats) -> String {
    let g = &s.grid;
    let text: Vec<String> = reasons(s, p)
        .into_iter()
        .map(|r| match r {
            NotRobust::Unranked => format!("R or {} unknown", s.options.damping.symbol),
            NotRobust::FailedCases => "some of its cases did not end ok".to_string(),
            NotRobust::Edge(a, end) => format!(
                "on the {} edge of {}",
                match end {
                    End::Low => "lower",
                    End::High => "upper",
                },
                g.key(a)
            ),
            NotRobust::Missing => "part of its neighbourhood was not computed".to_string(),
            NotRobust::Zone(Some(c)) => format!("a neighbour is {}", c.label()),
            NotRobust::Zone(None) => "a neighbour is outside the recommended zones".to_string(),
        })
        .collect();
    text.join("; ")
}

/// The edges of the swept range the best designs sit on, and which way to extend.
fn edges(s: &Summary) -> String {
    let mut o = String::new();
    if s.edges.is_empty() {
        return o;
    }
    let _ = writeln!(
        o,
        "**The best designs sit on the edge of the swept range**; the optimum may lie beyond it:\n"
    );
    let g = &s.grid;
    for e in &s.edges {
        let key = g.key(e.axis);
        let (side, dir) = match e.end {
            End::Low => ("lower", "below"),
            End::High => ("upper", "above"),
        };
        let mut who = Vec::new();
        if e.best {
            who.push("the best design".to_string());
        }
        if e.recommended {
            who.push("the recommended one".to_string());
        }
        let who = if who.is_empty() {
            String::new()
        } else {
            format!(", including {}", who.join(" and "))
        };
        let value = match axis_unit(key) {
            "–" => fmt_num(e.value),
            u => format!("{} {u}", fmt_num(e.value)),
        };
        let advice = if e.extendable {
            format!("extend `{key}` {dir} {value}")
        } else {
            format!(
                "one more grid step of `{key}` {dir} {value} leaves the model's range ({}); what \
                 lies between is reached with a finer step",
                crate::model::System::allowed(key)
            )
        };
        let _ = writeln!(
            o,
            "- {} is the {side} end of `{key}`: {} of the top {} designs {} there{who}. {}{}.",
            axis_value(key, e.value),
            e.n_top,
            e.top,
            if e.n_top == 1 { "sits" } else { "sit" },
            advice[..1].to_uppercase(),
            &advice[1..]
        );
    }
    let _ = writeln!(o);
    o
}
