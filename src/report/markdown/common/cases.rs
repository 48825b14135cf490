//! What was reduced, the nominal design's cases (the paper's Table II), the outcomes of the runs
//! and the normality of the response.

use std::fmt::Write;

use crate::report::markdown::words::{MAX_ROWS, SceneText, cm, design_text, f, reliability_clause};

use crate::reduce::Summary;
use crate::reduce::common::tables::outcome_text;
use crate::report::text::{axis_unit, count, fmt_num, thousands};
use crate::sim::Outcome;
use crate::study::Study;

/// Points and runs reduced, and the swept axes; `scene` says what a point is called and what
/// its runs are.
pub fn overview(study: &Study, s: &Summary, scene: &SceneText) -> String {
    let mut o = String::new();
    let n_runs: u64 = scene
        .runs
        .as_ref()
        .map_or_else(|| s.outcome_totals.iter().sum(), |r| r.0);
    let cases = study.n_cases();
    let per_point = scene
        .per_point
        .clone()
        .unwrap_or_else(|| format!("{} per point", count(cases, "case", "cases")));
    let (one, many) = scene.point;
    let planned = s.n_points_planned;
    let _ = writeln!(
        o,
        "{} of {} reduced ({}).{}\n",
        thousands(s.points.len() as u64),
        count(planned, one, many),
        match &scene.runs {
            Some((_, what)) => format!("{}: {what}", count(n_runs, "run", "runs")),
            None => format!("{}: {per_point}", count(n_runs, "run", "runs")),
        },
        if (s.points.len() as u64) < s.n_points_planned {
            " **The run is incomplete: the missing points are left out of everything below.**"
        } else {
            ""
        }
    );
    let axes: Vec<String> = s
        .grid
        .axes
        .iter()
        .map(|(k, v)| {
            format!(
                "`{k}` from {} to {} ({} values, {})",
                fmt_num(v[0]),
                fmt_num(v[v.len() - 1]),
                v.len(),
                axis_unit(k)
            )
        })
        .collect();
    if !axes.is_empty() {
        let _ = writeln!(o, "Swept: {}.\n", axes.join("; "));
    }
    o
}

/// The cases of the nominal design point (the one nearest the study's base system).
pub fn nominal(s: &Summary) -> String {
    let mut o = String::new();
    let Some((np, rows)) = &s.nominal else {
        return o;
    };
    let name = s.options.response.name;
    let _ = writeln!(o, "## Nominal design: the cases (Table II)\n");
    let point = s.point(*np);
    let _ = writeln!(
        o,
        "Design point {np}{}, the one nearest the study's base system.\n",
        if s.grid.n_axes() > 0 {
            format!(" ({})", design_text(s, *np))
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        o,
        "| # | case | Δm (g) | Δd (mm) | noise seed | outcome | {name} (cm) | {} |\n|---|---|---|---|---|---|---|---|",
        s.options.damping.label()
    );
    for (i, r) in rows.iter().enumerate().take(MAX_ROWS) {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            i + 1,
            if r.ideal { "ideal" } else { "" },
            fmt_num(r.dm * 1e3),
            fmt_num(r.dd * 1e3),
            r.noise_seed
                .map(|x| x.to_string())
                .unwrap_or_else(|| "none".into()),
            r.outcome,
            cm(r.response),
            f(r.di, 5)
        );
    }
    // The point's count: a random design streamed beyond its budget keeps its first runs only.
    let total = point.map_or(rows.len(), |p| p.n_cases as usize);
    if total > MAX_ROWS {
        let _ = writeln!(
            o,
            "\n… and {} more cases (the runs of point {np} in `points/`).",
            total - MAX_ROWS
        );
    }
    if let Some(p) = point {
        let mut reliability = reliability_clause(s, p, 4);
        if !reliability.is_empty() {
            reliability = format!(" {reliability},");
        }
        let _ = writeln!(
            o,
            "\n{name} over the {} ok cases: mean **{} cm**, SD **{} cm** (eq. 9, N − 1). Stress: mean {} MPa, SD {} MPa.{reliability} Anderson–Darling on ln {name}: A*² = {}, p = {}.\n",
            p.n_ok,
            cm(p.response.mean),
            cm(p.response.sd),
            f(p.stress.mean / 1e6, 2),
            f(p.stress.sd / 1e6, 2),
            f(p.ad_stat, 3),
            f(p.ad_p, 3)
        );
    }
    o
}

/// Runs per outcome, and the design points with failed runs.
pub fn outcomes(s: &Summary) -> String {
    let mut o = String::from("## Outcomes\n\n| outcome | runs |\n|---|---|\n");
    for (oc, n) in Outcome::ALL.iter().zip(&s.outcome_totals) {
        if *n > 0 {
            let _ = writeln!(o, "| {} | {} |", oc.name(), thousands(*n));
        }
    }
    let flagged: Vec<_> = s.points.iter().filter(|p| !p.all_ok).collect();
    if flagged.is_empty() {
        let _ = writeln!(o, "\nEvery run ended `ok`.\n");
        return o;
    }
    let _ = writeln!(
        o,
        "\n**{} design points have runs that did not end `ok`**; their statistics use only the ok runs (column `all_ok = false` in the summary):\n",
        flagged.len()
    );
    for p in flagged.iter().take(20) {
        let _ = writeln!(
            o,
            "- point {} ({}): {} of {} ok; {}",
            p.point,
            design_text(s, p.point),
            p.n_ok,
            p.n_cases,
            outcome_text(&p.outcomes, true)
        );
    }
    if flagged.len() > 20 {
        let _ = writeln!(o, "- … and {} more", flagged.len() - 20);
    }
    let _ = writeln!(o);
    o
}

/// Anderson–Darling on the log of the response over the points.
pub fn normality(study: &Study, s: &Summary) -> String {
    let name = s.options.response.name;
    let tested: Vec<_> = s.points.iter().filter(|p| p.ad_p.is_finite()).collect();
    let rejected = tested.iter().filter(|p| p.ad_p < 0.05).count();
    let mut o = format!("## Is ln {name} normal?\n\n");
    if tested.is_empty() {
        let _ = writeln!(
            o,
            "No design point has three or more distinct ok values: nothing to test.\n"
        );
    } else {
        let share = rejected as f64 / tested.len() as f64;
        // Under a lognormal response each point rejects with probability 0.05 (the test's
        // level): more rejections than 1 % of such studies would give is the model failing,
        // not chance.
        let chance = {
            use statrs::distribution::{Binomial, DiscreteCDF};
            Binomial::new(0.05, tested.len() as u64)
                .map_or(1.0, |b| b.sf((rejected as u64).saturating_sub(1)))
        };
        let verdict = if rejected > 0 && chance < 0.01 {
            format!(
                "**That is {} % of the points, where a lognormal response would give about 5 % by chance (so many or more, were the points independent, with probability {}): the lognormal model does not describe {name} well over this study, and R, which rests on it, is the model's figure rather than a measured one.** Look at `{name}` over the cases of a flagged point (the points table) before relying on its R.",
                fmt_num((100.0 * share).round()),
                if chance < 1e-4 {
                    "below 1e-4".to_string()
                } else {
                    format!("{chance:.1e}")
                }
            )
        } else {
            format!(
                "With {} cases per point the test has little power; where it rejects, read R as a model-based figure, not a measured one.",
                study.n_cases()
            )
        };
        let _ = writeln!(
            o,
            "Anderson–Darling (mean and variance estimated, Stephens' small-sample correction) rejects normality of ln {name} at the 5 % level for {} of {} design points. {verdict}\n",
            thousands(rejected as u64),
            thousands(tested.len() as u64),
        );
    }
    o
}
