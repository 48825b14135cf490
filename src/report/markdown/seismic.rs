//! The top of a random or record study's report: what the study is (the load model, the
//! structure's period and damping, the limit and the base shear it implies, the intensity
//! measure, the hazard) and its decision in place of the paper's recommendation: the best
//! design by annual risk when a hazard is given, else by first-passage probability at the
//! design intensity, with whether the next design is told apart from it.

use std::fmt::Write;

use crate::reduce::random::risk::Curve;
use crate::reduce::random::{RandomSummary, beta_of};
use crate::reduce::{PointStats, Summary};
use crate::report::markdown::words::{cm, design_text, f, prob, ranked};
use crate::report::text::{fmt_num, thousands};
use crate::sim::random::intensity::G;
use crate::sim::random::{Excitation, Input, Measure, RandomScene, Spectrum};
use crate::study::Study;

/// The load in words.
fn load_text(r: &RandomScene) -> String {
    let on = match r.input {
        Input::Base => "ground acceleration",
        Input::Force => "a force on the main mass",
    };
    match &r.excitation {
        Excitation::Record(rec) => format!(
            "a recorded {on} ({} samples at dt = {} s), {} s",
            thousands(rec.values.len() as u64),
            fmt_num(r.dt),
            fmt_num(r.duration)
        ),
        Excitation::Suite(suite) => {
            let names: Vec<&str> = suite.records.iter().map(|x| x.name.as_str()).collect();
            let shown = if names.len() <= 12 {
                names.join(", ")
            } else {
                format!("{}, … {}", names[..10].join(", "), names[names.len() - 1])
            };
            format!(
                "a suite of {} records of {on} ({shown}), each over its own length ({} s at the \
                 longest) at its own dt (the finest {} s), one record per run",
                suite.records.len(),
                fmt_num(r.duration),
                fmt_num(r.dt)
            )
        }
        Excitation::Random(load) => {
            let spectrum = match load.spectrum {
                Spectrum::White => "band-limited white noise".to_string(),
                Spectrum::KanaiTajimi { omega_g, zeta_g } => format!(
                    "Kanai–Tajimi noise (ω_g = {} rad/s, ζ_g = {})",
                    fmt_num(omega_g),
                    fmt_num(zeta_g)
                ),
                Spectrum::CloughPenzien {
                    omega_g,
                    zeta_g,
                    omega_f,
                    zeta_f,
                } => format!(
                    "Clough–Penzien noise (ω_g = {} rad/s, ζ_g = {}, high-pass ω_f = {} rad/s, \
                     ζ_f = {})",
                    fmt_num(omega_g),
                    fmt_num(zeta_g),
                    fmt_num(omega_f),
                    fmt_num(zeta_f)
                ),
            };
            let envelope = load.envelope.map_or(String::new(), |e| {
                format!(
                    " under Jennings' envelope (rise to {} s, strong motion to {} s, then \
                     exp(−{} (t − {})))",
                    fmt_num(e.t1),
                    fmt_num(e.t2),
                    fmt_num(e.c),
                    fmt_num(e.t2)
                )
            });
            format!(
                "{on}, {spectrum}{envelope}, S0 = {} (two-sided, per rad/s), {} s at dt = {} s, \
                 a new realization per run",
                fmt_num(load.S0),
                fmt_num(r.duration),
                fmt_num(r.dt)
            )
        }
    }
}

/// The study's statement at the report's top.
pub fn head(study: &Study, rs: &RandomSummary) -> String {
    let Some(r) = study.scene.random() else {
        return String::new();
    };
    let sys = &study.system;
    let mut o = String::new();
    let zeta = sys.C / (2.0 * (sys.K * sys.M).sqrt());
    let _ = writeln!(o, "**Load.** {}.\n", load_text(r));
    let _ = writeln!(
        o,
        "**Structure.** M = {} kg, K = {} N/m, C = {} N s/m: T1 = 2π √(M/K) = {} s, ζ = {} %{}.\n",
        fmt_num(sys.M),
        fmt_num(sys.K),
        fmt_num(sys.C),
        f(sys.period(), 3),
        f(100.0 * zeta, 2),
        if study
            .axes
            .iter()
            .any(|a| a.key == "M" || a.key == "K" || a.key == "C")
        {
            " (the study's base values; it sweeps some of them)"
        } else {
            ""
        }
    );
    if let Some(b) = rs.threshold {
        let shear = sys.K * b / (sys.M * G);
        let _ = writeln!(
            o,
            "**Limit.** max |x| > {} cm of drift relative to the ground. On the linear structure \
             it is a base shear of K b = {} N, a base-shear coefficient K b / (M g) = {}{}.\n",
            cm(b),
            f(sys.K * b, 3),
            f(shear, 3),
            if shear > 0.5 {
                ": a storey would yield long before that in most buildings; a smaller limit \
                 (a drift ratio times the storey height, or first yield) suits a structure better"
            } else {
                ""
            }
        );
    }
    if let Some(spec) = rs.measure {
        let what = match spec.measure {
            Measure::Pga => "PGA, the peak ground acceleration".to_string(),
            Measure::Sa => format!(
                "Sa(T = {} s, 5 %), the spectral acceleration{}",
                f(spec.period, 3),
                if (spec.period - sys.period()).abs() <= 1e-9 * spec.period {
                    " at the structure's T1"
                } else {
                    ""
                }
            ),
        };
        let stripes = rs
            .intensity
            .as_ref()
            .filter(|i| i.key == "im")
            .map_or(String::new(), |i| {
                format!(
                    "; stripes at {} g, each motion scaled so that its own value equals the \
                     stripe's{}",
                    i.values
                        .iter()
                        .map(|v| fmt_num(*v))
                        .collect::<Vec<_>>()
                        .join(", "),
                    if matches!(r.excitation, Excitation::Random(_)) {
                        " (the load's S0 sets only the motions' own level: it scales out of \
                         every result but their own PGA and Sa)"
                    } else {
                        ""
                    }
                )
            });
        let _ = writeln!(o, "**Intensity.** {what}, in g{stripes}.\n");
    }
    if let Some(h) = &rs.hazard {
        let _ = writeln!(
            o,
            "**Hazard.** {} ({}), over {} years.\n",
            match &h.curve {
                crate::stats::hazard::Hazard::Power { k0, k } => format!(
                    "λ(x) = {} x^−{} per year, x in g",
                    fmt_num(*k0),
                    fmt_num(*k)
                ),
                crate::stats::hazard::Hazard::Table { im, .. } =>
                    format!("a table of {} rates", im.len()),
            },
            h.source.as_deref().unwrap_or("source not stated"),
            fmt_num(h.years)
        );
    }
    o
}

/// The decision: the best design and what tells it from the next.
pub fn decision(s: &Summary, rs: &RandomSummary) -> String {
    let mut o = String::from("## Decision\n\n");
    let Some(b) = rs.threshold else {
        o += "The study sets no `[scene] threshold`, so no design is chosen: the designs differ \
              only in their response statistics (below).\n\n";
        return o;
    };
    let order = ranked(s);
    let bare = s
        .points
        .iter()
        .find(|p| s.grid.without_damper(p.point))
        .map(|p| p.point);
    // A design other than the best that is a different system (not another m = 0 twin).
    let next = |best: &PointStats| {
        order.iter().copied().find(|d| {
            d.point != best.point
                && !(s.grid.without_damper(d.point) && s.grid.without_damper(best.point))
        })
    };
    if rs.hazard.is_some() && !rs.risk.is_empty() {
        risk_decision(&mut o, s, rs, &order, b, bare, next);
        return o;
    }
    pf_decision(&mut o, s, rs, &order, b, next);
    o
}

/// The decision by annual risk over the hazard: the best design's `λ_f`, the next one's, and
/// the structure without a damper's.
fn risk_decision<'a>(
    o: &mut String,
    s: &Summary,
    rs: &RandomSummary,
    order: &[&'a PointStats],
    b: f64,
    bare: Option<u64>,
    next: impl Fn(&PointStats) -> Option<&'a PointStats>,
) {
    let Some(best) = order.first() else {
        return;
    };
    let Some(r) = rs.risk_of(best.point).and_then(|r| r.risk.as_ref()) else {
        return;
    };
    let years = rs.hazard.as_ref().map_or(50.0, |h| h.years);
    let _ = writeln!(
        o,
        "By annual risk over the hazard, the best design is **{}**: λ_f = {} [{}, {}] failures \
         (max |x| > {} cm) per year, a probability of {} [{}, {}] in {} years (over {}).",
        design_text(s, best.point),
        prob(r.lambda_f.0),
        prob(r.lambda_f.1),
        prob(r.lambda_f.2),
        cm(b),
        prob(r.p_f_years.0),
        prob(r.p_f_years.1),
        prob(r.p_f_years.2),
        fmt_num(years),
        r.curve.text(),
    );
    basis_check(o, s, rs, order, best);
    if let Some(n) = next(best)
        && let Some(k) = rs.risk_of(n.point).and_then(|r| r.risk.as_ref())
    {
        let apart = k.lambda_f.1 > r.lambda_f.2;
        let _ = writeln!(
            o,
            "The next, {}, has λ_f = {} [{}, {}]: {}.",
            design_text(s, n.point),
            prob(k.lambda_f.0),
            prob(k.lambda_f.1),
            prob(k.lambda_f.2),
            if apart {
                "the intervals do not overlap, the order holds"
            } else {
                "the intervals overlap, so these motions do not tell the two apart; more \
                 realizations would"
            }
        );
    }
    if let Some(p) = bare
        && let Some(k) = rs.risk_of(p).and_then(|r| r.risk.as_ref())
    {
        let _ = writeln!(
            o,
            "Without a damper the structure's λ_f is {} per year: the best design divides it \
             by {}.",
            prob(k.lambda_f.0),
            f(k.lambda_f.0 / r.lambda_f.0, 1)
        );
    }
    o.push('\n');
}

/// The decision's check on the other basis: where the best design's `λ_f` is over its stripes,
/// its `λ_f` over the capacities' curve that holds; where it is over the capacities, its `λ_f`
/// over the stripes' own fit. Each with its interval, and whether the best design on that
/// basis is the same.
fn basis_check(
    o: &mut String,
    s: &Summary,
    rs: &RandomSummary,
    order: &[&PointStats],
    best: &PointStats,
) {
    let risk = |d: &PointStats| rs.risk_of(d.point).and_then(|r| r.risk.as_ref());
    let Some(own) = risk(best) else {
        return;
    };
    let over_stripes = own.curve == Curve::Stripes;
    // Each design's `λ_f` and interval on the other basis.
    let other = |d: &PointStats| -> Option<(f64, f64, f64)> {
        if over_stripes {
            Some(risk(d)?.capacities)
        } else {
            let v = rs.lambda_f_stripes(d.point)?;
            let (lo, hi) = rs.lambda_f_stripes_interval(d.point)?;
            Some((v, lo, hi))
        }
    };
    let Some(c) = other(best) else {
        return;
    };
    // Ties to the better ranked design, as the ranking's.
    let Some((low, lowest)) = order
        .iter()
        .filter_map(|d| Some((other(d)?.0, *d)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
    else {
        return;
    };
    let verdict = if lowest.point == best.point || low == c.0 {
        "it is the best design by them too".to_string()
    } else {
        format!(
            "by them the best design is {} (λ_f = {})",
            design_text(s, lowest.point),
            prob(low)
        )
    };
    let basis = if over_stripes {
        format!(
            "the capacities (incremental dynamic analysis, their {} curve)",
            own.capacities_curve.name()
        )
    } else {
        "the stripes' own fitted fragility (P(f | IM) at each stripe, which needs no capacity)"
            .to_string()
    };
    let _ = writeln!(
        o,
        "Over {basis} its λ_f is {} [{}, {}], and {verdict}.",
        prob(c.0),
        prob(c.1),
        prob(c.2),
    );
}

/// The decision without a hazard: the best design by `p_f` at the design intensity (or, where
/// no motion passed the limit, by the mean amplitude's margin to it) and the next one.
fn pf_decision<'a>(
    o: &mut String,
    s: &Summary,
    rs: &RandomSummary,
    order: &[&'a PointStats],
    b: f64,
    next: impl Fn(&PointStats) -> Option<&'a PointStats>,
) {
    let Some(best) = order.first() else {
        return;
    };
    let lens: Vec<usize> = (0..s.grid.n_axes()).map(|a| s.grid.n(a)).collect();
    let pf = |d: &PointStats| -> (f64, f64, f64) {
        rs.design_pf(d.point, &lens)
            .unwrap_or((f64::NAN, f64::NAN, f64::NAN))
    };
    let (p, lo, hi) = pf(best);
    let at = rs.intensity.as_ref().map_or(String::new(), |i| {
        format!(
            " at the design intensity {} = {}",
            i.key,
            fmt_num(i.values[i.design])
        )
    });
    if p == 0.0 {
        let _ = writeln!(
            o,
            "No design's motion passed the limit{at}, and subset simulation's levels did not \
             reach it: every `p_f` is only bounded, below its Monte Carlo interval's upper end \
             (the best's {}; β above {}), and the ranking then follows the mean \
             amplitude's margin to the limit: **{}** stays furthest from it (mean max |x| {} cm \
             against the limit's {} cm). A larger intensity, or more realizations, measures \
             `p_f` itself.\n",
            prob(hi),
            f(beta_of(hi), 2),
            design_text(s, best.point),
            cm(best.response.mean),
            cm(b),
        );
        return;
    }
    let _ = writeln!(
        o,
        "By first-passage probability{at}, the best design is **{}**: p_f = {} [{}, {}] \
         (max |x| > {} cm over the load's duration).",
        design_text(s, best.point),
        prob(p),
        prob(lo),
        prob(hi),
        cm(b)
    );
    if let Some(n) = next(best) {
        let (q, qlo, qhi) = pf(n);
        let _ = writeln!(
            o,
            "The next, {}, has p_f = {} [{}, {}]: {}.",
            design_text(s, n.point),
            prob(q),
            prob(qlo),
            prob(qhi),
            if qlo > hi {
                "the intervals do not overlap, the order holds"
            } else {
                "the intervals overlap, so these runs do not tell the two apart"
            }
        );
    }
    o.push('\n');
}
