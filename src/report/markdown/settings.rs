//! How the report was computed: stress, strength, safety factor, R's interval, DI, ranking and
//! the zone settings.

use std::fmt::Write;

use super::{confidence, f};
use crate::reduce::Summary;
use crate::report::charts::plumbing::fmt_num;
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
