//! The random and record scenes' section of `report.md` ([`scene_text`]): each design's
//! first-passage probability `p_f` with its exact 95 % interval, in rank order, and with a swept
//! intensity its `p_f` at every intensity and its fragility fit (median capacity `theta`,
//! dispersion `beta`).

use std::fmt::Write;

use crate::reduce::random::{RandomSummary, beta_of, outcome_name};
use crate::reduce::{PointStats, Summary};
use crate::report::markdown::{MAX_ROWS, SceneText, cm, design_text, f, ranked};
use crate::report::text::{axis_value, count, fmt_num, thousands};

/// How the core's sections word a random or record study, and its own section.
pub fn scene_text(s: &Summary, rs: &RandomSummary) -> SceneText {
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
    SceneText {
        section: section(s, rs),
        point: ("design", "designs"),
        per_point: Some(match &rs.intensity {
            Some(i) => format!(
                "{} × {} per design",
                count(i.values.len() as u64, "intensity", "intensities"),
                per
            ),
            None => format!("{per} per design"),
        }),
        window_peaks: false,
    }
}

/// A number at label precision, `–` when unknown.
fn num(v: f64) -> String {
    if v.is_finite() {
        fmt_num(v)
    } else {
        "–".into()
    }
}

/// `p_f` with its interval: `0.125 [0.06, 0.23]`.
fn pf_text(p: f64, lo: f64, hi: f64) -> String {
    if p.is_nan() {
        return "–".into();
    }
    format!("{} [{}, {}]", prob(p), prob(lo), prob(hi))
}

/// A probability to two significant digits: `0.12`, `0.0031`, `4.7e-6` (below 1e-3), `0`.
fn prob(p: f64) -> String {
    if p == 0.0 || !p.is_finite() {
        return f(p, 0);
    }
    if p < 1e-3 {
        return format!("{p:.1e}");
    }
    let digits = (1 - p.log10().floor() as i32).max(2) as usize;
    f(p, digits)
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
fn rows<'a>(
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
pub fn section(s: &Summary, rs: &RandomSummary) -> String {
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
         `beta` = −Φ⁻¹(p_f). Rank 1 has the lowest `p_f` (the ranking is by `p_s = 1 − p_f` \
         unless the study gives a strength); two designs whose intervals overlap are not told \
         apart by this many runs.{}\n",
        cm(b),
        if rs.record {
            count(rs.realizations, "record run", "record runs")
        } else {
            count(rs.realizations, "realization", "realizations")
        },
        if rs.subset.is_empty() {
            ""
        } else {
            " Where fewer than 10 realizations passed, `p_f` is subset simulation's (Au and Beck \
             2001, over the realization's white-noise samples; its interval from its coefficient \
             of variation with the levels fully correlated), and it ranks the design."
        },
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
    o += &fragility(s, rs, &designs, &lens);
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
         maximum likelihood (95 % Wald intervals). `theta`, the median capacity, is the \
         intensity at which half the runs pass the threshold: the larger, the better the \
         design over every intensity. The designs are listed by it (`capacity rank`, \
         `capacity_rank` in `summary.csv`; a design whose fit did not end ok has none).\n\n",
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
