//! The random and record scenes' section of `report.md` ([`scene_text`]): each design's
//! first-passage probability `p_f` with its exact 95 % interval, in rank order, and with a swept
//! intensity its `p_f` at every intensity and its fragility fit (median capacity `theta`,
//! dispersion `beta`).

use std::fmt::Write;

use crate::reduce::random::risk::DesignRisk;
use crate::reduce::random::{RandomSummary, beta_of, outcome_name};
use crate::reduce::{PointStats, Summary};
use crate::report::markdown::words::{MAX_ROWS, SceneText, cm, design_text, f, prob, ranked, sig};
use crate::report::text::{axis_value, count, fmt_num, thousands};
use crate::sim::random::IntensitySpec;

/// How the core's sections word a random or record study, and its own section.
pub fn scene_text(study: &crate::study::Study, s: &Summary, rs: &RandomSummary) -> SceneText {
    let per = count(
        rs.realizations,
        if rs.record {
            "record run"
        } else {
            "realization"
        },
        if rs.record {
            "record runs"
        } else {
            "realizations"
        },
    );
    let per_design = match &rs.intensity {
        Some(i) => format!(
            "{} × {} per design",
            count(i.values.len() as u64, "intensity", "intensities"),
            per
        ),
        None => format!("{per} per design"),
    };
    SceneText {
        section: section(s, rs) + &super::random_units::section(s, rs),
        point: ("design", "designs"),
        per_point: Some(per_design.clone()),
        window_peaks: false,
        runs: Some(every_run(rs, &per_design)),
        head: super::seismic::head(study, rs),
        decision: Some(super::seismic::decision(s, rs)),
        laboratory: s.computes_r(),
    }
}

/// Every run the numbers rest on: each design point's realizations (every intensity), the
/// capacity searches' runs beyond each motion's first, subset simulation's runs.
fn every_run(rs: &RandomSummary, per_design: &str) -> (u64, String) {
    let sweep: u64 = rs.points.len() as u64 * rs.realizations;
    let ida: u64 = rs
        .capacities
        .iter()
        .map(|c| u64::from(c.2.3.saturating_sub(1)))
        .sum();
    let subset: u64 = rs.subset.iter().map(|s| s.1.runs).sum();
    let mut parts = vec![format!("{} in the sweep ({per_design})", thousands(sweep))];
    if ida > 0 {
        parts.push(format!(
            "{} more by the capacity searches of {} motions",
            thousands(ida),
            thousands(rs.capacities.len() as u64)
        ));
    }
    if subset > 0 {
        parts.push(format!("{} by subset simulation", thousands(subset)));
    }
    (sweep + ida + subset, parts.join(", "))
}

/// How subset simulation's `p_f` and interval come about, when it ran: a single run's interval
/// from its stated coefficient of variation with the levels fully correlated, or with
/// `--subset-repeats R` the mean of `R` independent runs and its interval from their spread.
fn subset_sentence(rs: &RandomSummary) -> String {
    let repeats = rs.subset.iter().map(|s| s.1.repeats).max().unwrap_or(0);
    match repeats {
        0 => String::new(),
        1 => " Where fewer than 10 realizations passed, `p_f` is subset simulation's (Au and Beck \
               2001, over the realization's white-noise samples; its interval from its \
               coefficient of variation with the levels fully correlated, a bound that covers \
               the truth in 99–100 % of runs in the committed validation), and it ranks the \
               design. `reduce --subset-repeats R` runs R independent simulations instead."
            .to_string(),
        r => format!(
            " Where fewer than 10 realizations passed, `p_f` is the mean of {r} independent \
             subset simulations (Au and Beck 2001, over the realization's white-noise samples; \
             `reduce --subset-repeats {r}`), its interval `p_f exp(∓t σ)` from the spread of the \
             {r} runs (σ² = ln(1 + CoV²), CoV that of their mean, t Student's with {} degrees of \
             freedom; the CoV shown), and it ranks the design.",
            r - 1
        ),
    }
}

/// A number at label precision, `–` when unknown.
pub(super) fn num(v: f64) -> String {
    if v.is_finite() {
        fmt_num(v)
    } else {
        "–".into()
    }
}

/// `p_f` with its interval: `0.125 [0.06, 0.23]`.
pub(super) fn pf_text(p: f64, lo: f64, hi: f64) -> String {
    if p.is_nan() {
        return "–".into();
    }
    format!("{} [{}, {}]", prob(p), prob(lo), prob(hi))
}

/// The designs in rank order (all, by point, when none is ranked).
fn shown(s: &Summary) -> Vec<&PointStats> {
    let r = ranked(s);
    if r.is_empty() {
        s.points.iter().collect()
    } else {
        r
    }
}

/// The design values a design without a damper (`m = 0`) does not depend on: the clearance and
/// the restitution act only through the inner mass.
const DAMPER_KEYS: [&str; 2] = ["d", "e"];

/// One row of a table of designs: the design, its rank's text and its name. The designs
/// without a damper (`m = 0` on a swept `m`) that differ only in [`DAMPER_KEYS`] are one system,
/// the main mass alone, whose results are the same; they are listed once, as `m = 0 kg, any d
/// (no damper, N designs)`, with the range of their ranks (`rank_of`).
pub(super) fn rows<'a>(
    s: &Summary,
    designs: &[&'a PointStats],
    rank_of: impl Fn(&PointStats) -> Option<u64>,
) -> Vec<(&'a PointStats, String, String)> {
    let n = s.grid.n_axes();
    // What tells two designs without a damper apart: the axes other than m, d and e.
    let system = |p: u64| -> Vec<u64> {
        (0..n)
            .filter(|&a| s.grid.key(a) != "m" && !DAMPER_KEYS.contains(&s.grid.key(a)))
            .map(|a| s.grid.value(p, a).to_bits())
            .collect()
    };
    let rank = |d: &PointStats| rank_of(d).map_or("–".into(), |r| r.to_string());
    let mut out = Vec::new();
    let mut listed: Vec<Vec<u64>> = Vec::new();
    for &d in designs {
        if !s.grid.without_damper(d.point) {
            out.push((d, rank(d), design_text(s, d.point)));
            continue;
        }
        let key = system(d.point);
        if listed.contains(&key) {
            continue;
        }
        let twins: Vec<&PointStats> = designs
            .iter()
            .copied()
            .filter(|t| s.grid.without_damper(t.point) && system(t.point) == key)
            .collect();
        listed.push(key);
        if twins.len() < 2 {
            out.push((d, rank(d), design_text(s, d.point)));
            continue;
        }
        let ranks: Vec<u64> = twins.iter().filter_map(|t| rank_of(t)).collect();
        let rank_text = match (ranks.iter().min(), ranks.iter().max()) {
            (Some(lo), Some(hi)) if lo != hi => format!("{lo}–{hi}"),
            _ => rank(d),
        };
        let name = (0..n)
            .map(|a| {
                let key = s.grid.key(a);
                if DAMPER_KEYS.contains(&key) {
                    format!("any {key}")
                } else {
                    axis_value(key, s.grid.value(d.point, a))
                }
            })
            .collect::<Vec<_>>()
            .join(", ");
        out.push((
            d,
            rank_text,
            format!("{name} (no damper, {} designs)", twins.len()),
        ));
    }
    out
}

/// The section: the method in two lines, the table of designs, the fragility table.
pub(super) fn section(s: &Summary, rs: &RandomSummary) -> String {
    let mut o = String::from("## First-passage reliability\n\n");
    let Some(b) = rs.threshold else {
        o += "The study sets no `[scene] threshold`: no first-passage probability is computed \
              and the designs are not ranked on one. Set a threshold (m) to rank them.\n\n";
        return o;
    };
    let at = match &rs.intensity {
        Some(i) => format!(
            " at the design intensity {} = {} ({})",
            i.key,
            fmt_num(i.values[i.design]),
            if i.chosen {
                "the study's `design_intensity`"
            } else {
                "the middle of the swept values; `[scene] design_intensity` chooses another"
            }
        ),
        None => String::new(),
    };
    let _ = writeln!(
        o,
        "`p_f` = P(max |x| > {} cm) over the load's duration{at}, by Monte Carlo over each \
         design's {}: the share that passed, with its exact (Clopper–Pearson) 95 % interval; \
         `beta` = −Φ⁻¹(p_f). {}; two designs whose intervals overlap are not told apart by this \
         many runs.{}\n",
        cm(b),
        if rs.record {
            count(rs.realizations, "record run", "record runs")
        } else {
            count(rs.realizations, "realization", "realizations")
        },
        if rs.hazard.is_some() && !rs.risk.is_empty() {
            "The rank is by annual risk over the study's hazard (*Capacities by incremental \
             dynamic analysis*, below), not by this `p_f` at one intensity"
        } else {
            "Rank 1 has the lowest `p_f` (the ranking is by `p_s = 1 − p_f` unless the study \
             gives a strength; designs that all kept `p_s = 1` rank by their mean amplitude, \
             the margin to the limit)"
        },
        subset_sentence(rs),
    );
    let _ = writeln!(
        o,
        "| rank | design | p_f [95 % interval] | beta | exceedances | mean amplitude (cm) | mean rms x (cm) |\n|---|---|---|---|---|---|---|"
    );
    let lens: Vec<usize> = (0..s.grid.n_axes()).map(|a| s.grid.n(a)).collect();
    let j = rs.intensity.as_ref().map_or(0, |i| i.design);
    let designs = shown(s);
    let listed = rows(s, &designs, |d| d.rank);
    for (d, rank, name) in listed.iter().take(MAX_ROWS) {
        let Some(p) = rs.point(rs.grid_point(d.point, j, &lens)) else {
            continue;
        };
        let (pf, beta) = match rs.subset_of(d.point) {
            // Subset simulation's levels did not reach the limit: Monte Carlo's bound says more.
            Some(x) if x.p_f == 0.0 => (
                format!(
                    "{} (below Monte Carlo's bound; subset simulation did not reach the limit)",
                    pf_text(p.p_f, p.p_f_lo, p.p_f_hi)
                ),
                beta_of(p.p_f_hi),
            ),
            Some(x) => (
                format!(
                    "{} (subset simulation, CoV {})",
                    pf_text(x.p_f, x.lo, x.hi),
                    f(x.cov, 2)
                ),
                beta_of(x.p_f),
            ),
            None => (pf_text(p.p_f, p.p_f_lo, p.p_f_hi), p.beta),
        };
        let _ = writeln!(
            o,
            "| {rank} | {name} | {} | {} | {} of {} | {} | {} |",
            pf,
            f(beta, 3),
            thousands(p.exceed),
            thousands(p.n),
            cm(d.response.mean),
            cm(p.rms_x_mean)
        );
    }
    if listed.len() > MAX_ROWS {
        let _ = writeln!(
            o,
            "\n{} more in `summary.csv`.",
            thousands((listed.len() - MAX_ROWS) as u64)
        );
    }
    o.push('\n');
    // The capacities' fragility supersedes the fit to the stripes' counts.
    if rs.risk.is_empty() {
        o += &fragility(s, rs, &designs, &lens);
    }
    o += &risk_section(s, rs, &designs);
    o
}

/// With a swept intensity: each design's `p_f` at every intensity and its fragility fit.
fn fragility(s: &Summary, rs: &RandomSummary, designs: &[&PointStats], lens: &[usize]) -> String {
    let Some(i) = &rs.intensity else {
        return String::new();
    };
    let mut o = format!(
        "### Fragility over {}\n\nEach design's `p_f` at every swept {} and the lognormal \
         fragility curve P(exceed | {k}) = Φ(ln({k} / theta) / beta) fitted to its counts by \
         maximum likelihood (95 % profile-likelihood intervals; 0 or ∞ where the likelihood does \
         not bound them). `theta`, the median capacity, is the \
         intensity at which half the runs pass the threshold; the designs are listed by it \
         (`capacity rank`, `capacity_rank` in `summary.csv`; a design whose fit did not end ok \
         has none). Two curves with different `beta` cross: a larger `theta` is not a lower \
         `p_f` at every intensity, and the intensities that matter are those the hazard \
         weighs.\n\n",
        i.key,
        i.key,
        k = i.key
    );
    let heads: Vec<String> = i
        .values
        .iter()
        .map(|v| format!("{} = {}", i.key, fmt_num(*v)))
        .collect();
    let _ = writeln!(
        o,
        "| capacity rank | design | {} | theta [95 %] | beta [95 %] | fit |\n|---|---|{}---|---|---|",
        heads.join(" | "),
        "---|".repeat(heads.len())
    );
    let mut by_capacity = designs.to_vec();
    by_capacity.sort_by_key(|d| (rs.capacity_rank_of(d.point).unwrap_or(u64::MAX), d.point));
    let listed = rows(s, &by_capacity, |d| rs.capacity_rank_of(d.point));
    for (d, rank, name) in listed.iter().take(MAX_ROWS) {
        let pfs: Vec<String> = (0..i.values.len())
            .map(|j| {
                rs.point(rs.grid_point(d.point, j, lens))
                    .map_or("–".into(), |p| f(p.p_f, 3))
            })
            .collect();
        let fit = rs.fragility_of(d.point);
        let (theta, beta, outcome) = fit.map_or(("–".into(), "–".into(), "none"), |x| {
            (
                format!(
                    "{} [{}, {}]",
                    num(x.theta),
                    num(x.theta_lo),
                    num(x.theta_hi)
                ),
                format!(
                    "{} [{}, {}]",
                    f(x.beta, 3),
                    f(x.beta_lo, 3),
                    f(x.beta_hi, 3)
                ),
                outcome_name(x.outcome),
            )
        });
        let _ = writeln!(
            o,
            "| {rank} | {name} | {} | {theta} | {beta} | {outcome} |",
            pfs.join(" | ")
        );
    }
    o.push('\n');
    o
}

/// With capacities (an intensity measure and a threshold): each design's fragility from its
/// motions' capacities, whether the lognormal holds, and with a hazard its annual risk; the
/// designs by `lambda_f` (with a hazard) or by median capacity.
fn risk_section(s: &Summary, rs: &RandomSummary, designs: &[&PointStats]) -> String {
    let Some(spec) = rs.measure else {
        return String::new();
    };
    if rs.risk.is_empty() {
        return String::new();
    }
    let im = im_name(&spec);
    let mut o = capacities_intro(rs, &spec, &im);
    let order = risk_order(rs, designs);
    let with_hazard = rs.hazard.is_some();
    if let Some(h) = &rs.hazard {
        let _ = writeln!(
            o,
            "**Annual risk** over the hazard curve {} ({}): `lambda_f` = ∫ P(f | {im}) \
             |dλ({im})| per year, and the probability of a failure in {} years, \
             1 − exp(−{} λ_f). `curve`: the fragility it is taken over, the stripes' own \
             (`stripes`: the lognormal fitted to the share of motions that pass at each stripe, \
             P(f | {im}) itself, which needs no capacity) where motions fall back (`fall back`: \
             there a capacity is the crossing its search met, not always the first), else the \
             capacities' curve that holds (every capacity a first passage). Its 95 % interval \
             resamples the motions, every stripe's run of a motion together. \
             `lambda_f capacities`: over the \
             capacities' curve that holds, the check; its interval resamples the motions only, \
             not the crossing each search met, so where motions fall back it is narrower than \
             its error. The designs are ranked by `lambda_f` (`risk_rank`; rank 1 the lowest). \
             `deagg. 10–50–90 %`: the {im} below which 10, 50 and 90 % of `lambda_f` comes \
             from.\n",
            hazard_text(&h.curve),
            h.source.as_deref().unwrap_or("the study's"),
            fmt_num(h.years),
            fmt_num(h.years),
        );
    }
    let head = if with_hazard {
        "| risk rank | design | lambda_f per year [95 %] | P_f in years [95 %] | curve | lambda_f capacities [95 %] | lambda_f empirical | lambda_f lognormal | deagg. 10–50–90 % (g) | theta (g) [95 %] | beta [95 %] | KS (5 % value) | fit | censored | fall back |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    } else {
        "| design | theta (g) [95 %] | beta [95 %] | KS (5 % value) | fit | censored | fall back |\n|---|---|---|---|---|---|---|"
    };
    let _ = writeln!(o, "{head}");
    let listed = rows(s, &order, |d| rs.risk_of(d.point).and_then(|r| r.risk_rank));
    for (d, rank, name) in listed.iter().take(MAX_ROWS) {
        let Some(r) = rs.risk_of(d.point) else {
            continue;
        };
        risk_row(&mut o, r, rank, name);
    }
    o.push('\n');
    o += &stripes_table(s, rs, &order);
    o
}

/// The capacities' paragraph: how each motion's capacity is found and when the lognormal
/// fit holds.
fn capacities_intro(rs: &RandomSummary, spec: &IntensitySpec, im: &str) -> String {
    format!(
        "### Capacities by incremental dynamic analysis\n\nEach motion of the design stripe \
         is scaled until max |x| passes the limit: its capacity, the {im} (g) of a crossing of \
         the limit, to a relative {} (bracketed, then closed by false position and bisection; \
         {} runs a motion on average over the study). The fragility is the \
         capacities' distribution: the empirical curve, and the lognormal fit (`theta` their \
         geometric mean, `beta` their log standard deviation per ln {im}, maximum likelihood \
         with censoring where a motion never passed up to {} g), with 95 % bootstrap \
         intervals over the motions. The lognormal *holds* (`fit`) when its \
         Kolmogorov–Smirnov distance to the capacities is within Lilliefors' 5 % value, it \
         lies inside every stripe's Monte Carlo interval{}; where it does not, the empirical \
         curve is used. `fall back`: motions whose response passed the limit at their capacity \
         and not at a larger scale tried (by the search or at a stripe above the capacity): the \
         response is not monotone in the scale (a damper engages more in stronger shaking). \
         Such a motion passes in narrow windows of scale, more of them the finer one looks, so \
         its capacity is the crossing the search met, not a first passage any scan converges \
         to, and the capacities' curve parts from the stripes' `p_f` (the share of motions \
         that pass at that intensity, which needs no capacity) both ways: above it where \
         motions that passed at a lower scale fall back, below it where a motion passes in a \
         window under the crossing its search met.\n\n",
        f(spec.ida_tol, 3),
        f(
            rs.risk.iter().map(|r| r.runs_mean).sum::<f64>() / rs.risk.len() as f64,
            1
        ),
        fmt_num(spec.ida_max),
        if rs.hazard.is_some() {
            " and its annual rate of failure lies inside the empirical curve's interval"
        } else {
            ""
        },
    )
}

/// The designs in the risk table's order: by risk rank, then by median capacity (the largest
/// first), then by design.
fn risk_order<'a>(rs: &RandomSummary, designs: &[&'a PointStats]) -> Vec<&'a PointStats> {
    let mut order = designs.to_vec();
    // By risk rank, then by median capacity (the largest first), then by design.
    order.sort_by(|a, b| {
        let (ra, rb) = (rs.risk_of(a.point), rs.risk_of(b.point));
        let rank = |r: Option<&crate::reduce::random::risk::DesignRisk>| {
            r.and_then(|r| r.risk_rank).unwrap_or(u64::MAX)
        };
        let theta = |r: Option<&crate::reduce::random::risk::DesignRisk>| {
            r.and_then(|r| r.fit).map_or(f64::NEG_INFINITY, |f| f.theta)
        };
        rank(ra)
            .cmp(&rank(rb))
            .then(theta(rb).total_cmp(&theta(ra)))
            .then(a.point.cmp(&b.point))
    });
    order
}

/// One design's row of the risk table: its fit's cells, and with a hazard its annual risk
/// first.
fn risk_row(o: &mut String, r: &DesignRisk, rank: &str, name: &str) {
    // The median capacity to four significant digits (its interval is about 2 % wide at 200
    // motions), the deaggregation's intensities to three (CSV keeps every digit).
    let iv = |v: (f64, f64, f64)| format!("{} [{}, {}]", sig(v.0, 4), sig(v.1, 4), sig(v.2, 4));
    let fit_cells = format!(
        "{} | {} [{}, {}] | {} ({}) | {} | {} of {} | {}",
        iv(r.theta),
        f(r.beta.0, 3),
        f(r.beta.1, 3),
        f(r.beta.2, 3),
        f(r.ks, 3),
        f(r.ks_critical, 3),
        if r.fit_ok {
            "holds"
        } else {
            "**does not hold**"
        },
        thousands(r.censored as u64),
        thousands(r.n as u64),
        thousands(r.resurrected as u64),
    );
    match &r.risk {
        Some(k) => {
            let pv = |v: (f64, f64, f64)| pf_text(v.0, v.1, v.2);
            let _ = writeln!(
                o,
                "| {rank} | {name} | {} | {} | {} | {} | {} | {} | {}–{}–{} | {fit_cells} |",
                pv(k.lambda_f),
                pv(k.p_f_years),
                k.curve.name(),
                pv(k.capacities),
                prob(k.empirical.0),
                prob(k.lognormal.0),
                sig(k.deaggregation[0], 3),
                sig(k.deaggregation[1], 3),
                sig(k.deaggregation[2], 3),
            );
        }
        None => {
            let _ = writeln!(o, "| {name} | {fit_cells} |");
        }
    }
}

/// Each design's stripes: Monte Carlo against both curves.
fn stripes_table(s: &Summary, rs: &RandomSummary, order: &[&PointStats]) -> String {
    let Some(first) = rs.risk.iter().find(|r| !r.stripes.is_empty()) else {
        return String::new();
    };
    let im = rs.measure.map_or("IM".into(), |m| im_name(&m));
    let mut o = format!(
        "**Stripes against the capacities.** At each stripe every motion is scaled so that its \
         own {im} equals the stripe's: the share that passed (Monte Carlo, Clopper–Pearson 95 \
         %), the empirical curve of the capacities there [bootstrap 95 %] and the lognormal \
         (a `*` where it lies outside the stripe's interval).\n\n"
    );
    let heads: Vec<String> = first
        .stripes
        .iter()
        .map(|x| format!("{im} = {} g", fmt_num(x.im)))
        .collect();
    let _ = writeln!(
        o,
        "| design | {} |\n|---|{}",
        heads.join(" | "),
        "---|".repeat(heads.len())
    );
    let listed = rows(s, order, |d| rs.risk_of(d.point).and_then(|r| r.risk_rank));
    for (d, _, name) in listed.iter().take(MAX_ROWS) {
        let Some(r) = rs.risk_of(d.point) else {
            continue;
        };
        let cells: Vec<String> = r
            .stripes
            .iter()
            .map(|x| {
                format!(
                    "{}; {} [{}, {}]; {}{}",
                    pf_text(x.p_f, x.p_f_lo, x.p_f_hi),
                    prob(x.empirical),
                    prob(x.empirical_lo),
                    prob(x.empirical_hi),
                    prob(x.lognormal),
                    if x.lognormal_ok() { "" } else { "*" }
                )
            })
            .collect();
        let _ = writeln!(o, "| {name} | {} |", cells.join(" | "));
    }
    o.push('\n');
    o
}

/// `PGA` or `Sa(0.4 s)`.
pub(super) fn im_name(spec: &crate::sim::random::IntensitySpec) -> String {
    match spec.measure {
        crate::sim::random::Measure::Pga => "PGA".into(),
        crate::sim::random::Measure::Sa => format!("Sa({} s)", f(spec.period, 3)),
    }
}

/// A hazard curve in words.
fn hazard_text(h: &crate::stats::hazard::Hazard) -> String {
    match h {
        crate::stats::hazard::Hazard::Power { k0, k } => {
            format!("λ(x) = {} x^−{} (x in g)", fmt_num(*k0), fmt_num(*k))
        }
        crate::stats::hazard::Hazard::Table { im, .. } => format!(
            "from a table of {} rows over {}–{} g (log-log interpolation, its end segments \
             extended)",
            im.len(),
            fmt_num(im[0]),
            fmt_num(im[im.len() - 1])
        ),
    }
}
