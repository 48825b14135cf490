//! `report.md`: the reduction of a run directory for a person. Deterministic: no timestamps,
//! no paths outside the run directory, numbers at fixed precision.

use std::fmt::Write;

use crate::reduce::Summary;
use crate::reduce::table::outcome_text;
use crate::sim::Outcome;
use crate::study::{SafetyForm, Study};

use super::charts::{axis_unit, fmt_num};

fn f(v: f64, digits: usize) -> String {
    if v.is_finite() {
        format!("{v:.digits$}")
    } else if v.is_nan() {
        "–".into()
    } else if v > 0.0 {
        "∞".into()
    } else {
        "−∞".into()
    }
}

fn cm(v: f64) -> String {
    f(v * 100.0, 3)
}

fn values(s: &Summary, vals: &[f64]) -> String {
    s.axes
        .iter()
        .zip(vals)
        .map(|((k, _), v)| format!("{k} = {}", fmt_num(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The audit of `manifest.json`: relative errors as a table when they come as
/// `{max, median, n}` objects, the rest as a list, and the JSON itself.
fn audit_text(a: &serde_json::Value) -> String {
    let mut o = String::new();
    if let Some(map) = a.as_object() {
        let stats: Vec<_> = map
            .iter()
            .filter(|(_, v)| v.get("max").is_some() && v.get("median").is_some())
            .collect();
        if !stats.is_empty() {
            let _ = writeln!(
                o,
                "Points re-run against a tighter reference; relative errors:\n\n| quantity | max | median | n |\n|---|---|---|---|"
            );
            for (k, v) in stats {
                let num = |key: &str| {
                    v.get(key)
                        .and_then(|x| x.as_f64())
                        .map(|x| format!("{x:.2e}"))
                        .unwrap_or_else(|| "–".into())
                };
                let n = v.get("n").map(|x| x.to_string()).unwrap_or_default();
                let _ = writeln!(o, "| {k} | {} | {} | {n} |", num("max"), num("median"));
            }
            let _ = writeln!(o);
        }
        for (k, v) in map {
            if !(v.is_object() || v.is_array()) {
                let _ = writeln!(o, "- {k}: {v}");
            }
        }
        let _ = writeln!(o);
    }
    let _ = writeln!(
        o,
        "From `manifest.json`:\n\n```json\n{}\n```\n",
        serde_json::to_string_pretty(a).unwrap_or_default()
    );
    o
}

/// "between e = 0.73 and 0.74" for a step, "at e = 0.74" for a kink.
fn jump_where(j: &crate::reduce::Jump) -> String {
    if j.kind == "kink" {
        format!("at {} = {}", j.axis, fmt_num(j.at))
    } else {
        format!(
            "between {} = {} and {}",
            j.axis,
            fmt_num(j.from),
            fmt_num(j.to)
        )
    }
}

/// The report text. `charts` are file names relative to the run directory; `audit` is the
/// `audit` value of `manifest.json` when there is one.
pub fn report(
    study: &Study,
    s: &Summary,
    charts: &[String],
    audit: Option<&serde_json::Value>,
) -> String {
    let mut o = String::new();
    let rel = &study.reliability;
    let _ = writeln!(o, "# impactsweep report: {}\n", study.name);
    let n_runs: u64 = s.outcome_totals.iter().sum();
    let _ = writeln!(
        o,
        "{} of {} design points reduced ({} runs, {} cases per point).{}\n",
        s.points.len(),
        s.n_points_planned,
        n_runs,
        study.cases.len(),
        if (s.points.len() as u64) < s.n_points_planned {
            " **The run is incomplete: the missing points are left out of everything below.**"
        } else {
            ""
        }
    );
    let axes: Vec<String> = s
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
    let _ = writeln!(o, "Swept: {}.\n", axes.join("; "));

    let _ = writeln!(o, "## Settings\n");
    let _ = writeln!(
        o,
        "- Stress (eq. 10): S = 3 E r xmax / L², E = {} GPa, r = {} mm, L = {} m, i.e. {:.3} MPa per cm of xmax.",
        fmt_num(rel.E / 1e9),
        fmt_num(rel.r * 1e3),
        fmt_num(rel.L),
        s.stress_per_m * 0.01 / 1e6
    );
    let _ = writeln!(
        o,
        "- Strength: lognormal, mean {} MPa, SD {} MPa (Cv {:.3}; μ_ln = {:.4}, σ_ln = {:.4}).",
        fmt_num(rel.strength_mean / 1e6),
        fmt_num(rel.strength_sd / 1e6),
        s.strength.cv(),
        s.strength.mu_ln,
        s.strength.sigma_ln
    );
    let _ = writeln!(
        o,
        "- Safety factor: {}.",
        match s.options.safety_form {
            SafetyForm::Exact => "Shigley's exact lognormal relation (eq. 8)",
            SafetyForm::Paper => "the paper's small-C_n form exp[C_n (C_n/2 + β)]",
        }
    );
    let _ = writeln!(
        o,
        "- R interval: percentile bootstrap, {} resamples of the ok cases, {:.0} % confidence, seeded by the study seed and the design point.",
        rel.bootstrap,
        100.0 * rel.confidence
    );
    let _ = writeln!(
        o,
        "- DI: {}. Perfectibility (eq. 11): WF1 = {}, WF2 = {}, R_max = {}, DI_max = {} m/s.",
        match s.options.di_source {
            crate::study::DiSource::Ideal => "from the ideal case",
            crate::study::DiSource::Mean => "mean over the ok cases",
        },
        fmt_num(study.ranking.wf1),
        fmt_num(study.ranking.wf2),
        f(s.r_max, 5),
        f(s.di_max, 5)
    );
    let _ = writeln!(
        o,
        "- Zones: a step when a first difference, a kink when a second difference (and the slope change exceeds {} typical steps) is more than {} robust SDs from the median; reliable when R ≥ {}; strong damping when DI ≥ {} m/s{}.{}\n",
        fmt_num(crate::reduce::zones::KINK_STEPS),
        fmt_num(study.zones.jump_k),
        fmt_num(study.zones.r_min),
        f(s.di_strong, 5),
        if study.zones.di_strong.is_none() {
            " (the median DI)"
        } else {
            ""
        },
        if study.zones.declared.is_empty() {
            ""
        } else {
            " Zones are declared in the study and override the automatic ones."
        }
    );

    // Outcomes.
    let _ = writeln!(o, "## Outcomes\n");
    let _ = writeln!(o, "| outcome | runs |\n|---|---|");
    for (oc, n) in Outcome::ALL.iter().zip(&s.outcome_totals) {
        if *n > 0 {
            let _ = writeln!(o, "| {} | {} |", oc.name(), n);
        }
    }
    let flagged: Vec<_> = s.points.iter().filter(|p| !p.all_ok).collect();
    if flagged.is_empty() {
        let _ = writeln!(o, "\nEvery run ended `ok`.\n");
    } else {
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
                values(s, &p.values),
                p.n_ok,
                p.n_cases,
                outcome_text(&p.outcomes, true)
            );
        }
        if flagged.len() > 20 {
            let _ = writeln!(o, "- … and {} more", flagged.len() - 20);
        }
        let _ = writeln!(o);
    }

    // Nominal design (Table II).
    if let Some((np, rows)) = &s.nominal {
        let _ = writeln!(o, "## Nominal design: the cases (Table II)\n");
        let point = s.points.iter().find(|p| p.point == *np);
        let _ = writeln!(
            o,
            "Design point {np}{}, the one nearest the study's base system.\n",
            point
                .map(|p| format!(" ({})", values(s, &p.values)))
                .unwrap_or_default()
        );
        let _ = writeln!(
            o,
            "| # | case | Δm (g) | Δd (mm) | noise seed | outcome | xmax (cm) | DI (m/s) |\n|---|---|---|---|---|---|---|---|"
        );
        for (i, r) in rows.iter().enumerate() {
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
                cm(r.xmax),
                f(r.di, 5)
            );
        }
        if let Some(p) = point {
            let _ = writeln!(
                o,
                "\nxmax over the {} ok cases: mean **{} cm**, SD **{} cm** (eq. 9, N − 1). Stress: mean {} MPa, SD {} MPa. R = {} (95 % interval {} – {}), μn = {}, Anderson–Darling on ln xmax: A*² = {}, p = {}.\n",
                p.n_ok,
                cm(p.xmax_mean),
                cm(p.xmax_sd),
                f(p.stress.mean / 1e6, 2),
                f(p.stress.sd / 1e6, 2),
                f(p.reliability, 5),
                f(p.reliability_lo, 5),
                f(p.reliability_hi, 5),
                f(p.safety_factor, 4),
                f(p.ad_stat, 3),
                f(p.ad_p, 3)
            );
        }
    }

    // Jumps.
    let _ = writeln!(o, "## Jumps\n");
    if s.jumps.is_empty() {
        let _ = writeln!(o, "No step or kink of xmax or DI along any axis.\n");
    } else {
        let _ = writeln!(
            o,
            "A step is an outlying first difference between neighbours; a kink an outlying change of slope at a point (second difference). xmax here is the ideal case's.\n"
        );
        let _ = writeln!(
            o,
            "| axis | kind | where | quantity | change | robust z |\n|---|---|---|---|---|---|"
        );
        for j in s.jumps.iter().take(40) {
            let change = if j.quantity == "xmax" {
                format!("{:+.4} cm", j.delta * 100.0)
            } else {
                format!("{:+.5} m/s", j.delta)
            };
            let _ = writeln!(
                o,
                "| {} | {} | {} | {} | {} | {:.1} |",
                j.axis,
                j.kind,
                jump_where(j),
                j.quantity,
                change,
                j.z
            );
        }
        if s.jumps.len() > 40 {
            let _ = writeln!(o, "\n… and {} more.", s.jumps.len() - 40);
        }
        if let Some(big) = s.jumps.iter().max_by(|a, b| a.z.total_cmp(&b.z)) {
            let _ = writeln!(
                o,
                "\nThe strongest: a {} of {} {} (robust z = {:.1}).\n",
                big.kind,
                big.quantity,
                jump_where(big),
                big.z
            );
        }
    }

    // Zones (Table III).
    let _ = writeln!(o, "## Zones (Table III)\n");
    let mut head = String::from("| zone | what it is |");
    let mut rule = String::from("|---|---|");
    for (k, _) in &s.axes {
        let _ = write!(head, " {k} range |");
        rule.push_str("---|");
    }
    let _ = writeln!(
        o,
        "{head} points | mean R | mean DI (m/s) | perfectibility (%) |\n{rule}---|---|---|---|"
    );
    for z in &s.zones {
        let ranges: String = z
            .ranges
            .iter()
            .map(|(_, a, b)| format!(" {} – {} |", fmt_num(*a), fmt_num(*b)))
            .collect();
        let _ = writeln!(
            o,
            "| {} | {} |{} {} | {} | {} | {} |",
            z.name,
            z.label,
            ranges,
            z.n_points,
            f(z.mean_r, 4),
            f(z.mean_di, 4),
            f(z.perfectibility, 1)
        );
    }
    let _ = writeln!(
        o,
        "\nZone perfectibility is eq. 11 on the zone means, normalised by the best zone means (as the paper's Table III). A zone \"around a jump\" is not recommended whatever its R: there a small error in the design variable changes the behaviour abruptly (the paper's zone II).\n"
    );

    // Top 10 and Pareto.
    let mut ranked: Vec<_> = s.points.iter().filter(|p| p.rank.is_some()).collect();
    ranked.sort_by_key(|p| p.rank);
    let _ = writeln!(o, "## Top 10 by perfectibility\n");
    let row_head = "| rank | design | R | R interval | μn | DI (m/s) | xmax mean (cm) | P (%) | zone |\n|---|---|---|---|---|---|---|---|---|";
    let _ = writeln!(o, "{row_head}");
    let row = |p: &crate::reduce::PointStats| {
        format!(
            "| {} | {} | {} | {} – {} | {} | {} | {} | {} | {} |",
            p.rank.map(|r| r.to_string()).unwrap_or_default(),
            values(s, &p.values),
            f(p.reliability, 5),
            f(p.reliability_lo, 5),
            f(p.reliability_hi, 5),
            f(p.safety_factor, 3),
            f(p.di, 5),
            cm(p.xmax_mean),
            f(p.perfectibility, 2),
            p.zone
        )
    };
    for p in ranked.iter().take(10) {
        let _ = writeln!(o, "{}", row(p));
    }
    let mut pareto: Vec<_> = s.points.iter().filter(|p| p.pareto).collect();
    pareto.sort_by_key(|p| p.rank);
    let _ = writeln!(
        o,
        "\n## Pareto set on (R, DI)\n\n{} design points are not beaten on both R and DI by any other:\n",
        pareto.len()
    );
    let _ = writeln!(o, "{row_head}");
    for p in pareto.iter().take(30) {
        let _ = writeln!(o, "{}", row(p));
    }
    if pareto.len() > 30 {
        let _ = writeln!(
            o,
            "\n… and {} more (column `pareto` of the summary).",
            pareto.len() - 30
        );
    }

    // Normality.
    let tested: Vec<_> = s.points.iter().filter(|p| p.ad_p.is_finite()).collect();
    let rejected = tested.iter().filter(|p| p.ad_p < 0.05).count();
    let _ = writeln!(o, "\n## Is ln xmax normal?\n");
    if tested.is_empty() {
        let _ = writeln!(
            o,
            "No design point has three or more distinct ok values: nothing to test.\n"
        );
    } else {
        let _ = writeln!(
            o,
            "Anderson–Darling (mean and variance estimated, Stephens' small-sample correction) rejects normality of ln xmax at the 5 % level for {} of {} design points. With {} cases per point the test has little power; where it rejects, read R as a model-based figure, not a measured one.\n",
            rejected,
            tested.len(),
            study.cases.len()
        );
    }

    if let Some(a) = audit {
        let _ = writeln!(o, "## Accuracy audit\n");
        let _ = writeln!(o, "{}", audit_text(a));
    }

    if !charts.is_empty() {
        let _ = writeln!(o, "## Charts\n");
        for c in charts.iter().filter(|c| c.ends_with(".svg")) {
            let _ = writeln!(o, "![{c}]({c})\n");
        }
    }
    let _ = writeln!(
        o,
        "Files: `summary.parquet` and `summary.csv` (one row per design point), `zones.parquet`, `jumps.parquet` (and CSV); SI units throughout (every column in impactsweep's `docs/schema.md`)."
    );
    o
}
