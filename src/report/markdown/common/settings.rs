//! How the report was computed: stress, strength, safety factor, R's interval, DI, ranking and
//! the zone settings.

use std::fmt::Write;

use crate::reduce::Summary;
use crate::report::markdown::words::{confidence, f};
use crate::report::text::fmt_num;
use crate::study::{DiSource, SafetyForm, Study};

pub fn section(study: &Study, s: &Summary) -> String {
    let mut o = String::from("## How this was computed\n\n");
    let rel = &study.reliability;
    let name = s.options.response.name;
    let _ = writeln!(
        o,
        "- Stress (eq. 10): S = 3 E r {name} / L², E = {} GPa, r = {} mm, L = {} m, i.e. {:.3} MPa per cm of {name}.",
        fmt_num(rel.E / 1e9),
        fmt_num(rel.r * 1e3),
        fmt_num(rel.L),
        s.stress_per_m * 0.01 / 1e6
    );
    if s.computes_r() {
        let _ = writeln!(
            o,
            "- Strength: lognormal, mean {} MPa, SD {} MPa (Cv {:.3}; μ_ln = {:.4}, σ_ln = {:.4}).",
            fmt_num(rel.strength_mean / 1e6),
            fmt_num(rel.strength_sd / 1e6),
            s.strength.cv(),
            s.strength.mu_ln,
            s.strength.sigma_ln
        );
    } else {
        let _ = writeln!(
            o,
            "- Strength: not given (`[reliability] strength_mean` and `strength_sd`): R, μn and the safety factor are not computed."
        );
    }
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
        "- R interval: percentile bootstrap, {} resamples of the ok cases, {} confidence, seeded by the study seed and the design point.",
        s.options.bootstrap,
        confidence(s)
    );
    let d = &s.options.damping;
    let _ = writeln!(
        o,
        "- {}: {}. Perfectibility (eq. 11): WF1 = {}, WF2 = {}, R_max = {}, {}_max = {}.",
        d.symbol,
        match s.options.di_source {
            DiSource::Ideal => "from the ideal case",
            DiSource::Mean => "mean over the ok cases",
        },
        fmt_num(study.ranking.wf1),
        fmt_num(study.ranking.wf2),
        f(s.r_max, 5),
        d.symbol,
        d.with_unit(&f(s.di_max, 5))
    );
    let _ = writeln!(
        o,
        "- Classes: reliable when the lower end of R's {} interval is at least r_min = {}; strong damping when {} ≥ {}{}; around a jump when a point's ±1-step neighbourhood along an axis reaches a located jump (see Jumps).",
        confidence(s),
        fmt_num(s.r_min),
        d.symbol,
        d.with_unit(&f(s.di_strong, 5)),
        if study.zones.di_strong.is_none() {
            format!(" (the median {})", d.symbol)
        } else {
            String::new()
        }
    );
    let p = &s.options.zones;
    let _ = writeln!(
        o,
        "- Zones: connected regions of one class; a region smaller than {} % of the design points ({} points) merges into a neighbour. Jumps: step tolerance {} × the median spread over the cases, kink at {} × the typical slope, located to {} of the grid step.{}\n",
        fmt_num(100.0 * p.min_zone),
        s.min_zone_points,
        fmt_num(p.step_spread),
        fmt_num(p.kink_slope),
        fmt_num(p.locate),
        if study.zones.declared.is_empty() {
            ""
        } else {
            " Zones are declared in the study and override the automatic ones."
        }
    );
    o
}

/// The report's warning, at its top, when the study gives no strength: R and the safety factor
/// are not computed, what the zones and the ranking use instead, and the lines to add. Empty
/// when R is computed.
pub fn no_strength(s: &Summary) -> String {
    if s.computes_r() || s.points.iter().all(|p| !p.di.is_finite()) {
        return String::new();
    }
    let q = s.options.damping.symbol;
    format!(
        "**Reliability not computed: the study gives no strength.** R, its interval, μn and the safety factor need the strength of the part the stress acts on, as a lognormal law: add to the study\n\n```toml\n[reliability]\nstrength_mean = 300e6   # Pa, mean strength (e.g. a structural steel's endurance limit)\nstrength_sd = 24e6      # Pa, its standard deviation\n```\n\nand reduce again (`impactsweep reduce RUN_DIR`; nothing is simulated again). Until then the zones are classed by {q} alone (\"reliability not computed\"), perfectibility is {q} relative to the best, P = 100 {q} / {q}_max (eq. 11 without its R term), the ranking follows it, no design is recommended (a recommendation needs R) and the Pareto set on R and {q} is empty.\n\n"
    )
}
