//! The harmonic section's part on steady states that are not periodic (docs/scenes.md, "The
//! amplitude over a design life"): the design life, each design whose peak such a motion
//! carries (its kind, Lyapunov exponent, window maximum and life amplitude with its interval),
//! and the designs ranked apart although their peak intervals overlap.

use std::fmt::Write;

use crate::orbits::attractors::AttractorRow;
use crate::reduce::PointStats;
use crate::reduce::Summary;
use crate::reduce::harmonic::HarmonicSummary;
use crate::reduce::harmonic::verify::Verification;
use crate::report::markdown::words::{cm, design_text, f};
use crate::sim::harmonic::{LifeCurve, NonPeriodicPeak};

/// `s` seconds as the report says a design life: hours (and years beyond 10,000 h).
pub fn life_text(s: f64) -> String {
    let h = s / 3600.0;
    let hours = if h >= 10.0 { f(h, 0) } else { f(h, 2) };
    if h >= 10_000.0 {
        format!("{s:.4e} s ({hours} h, {} years)", f(h / 8766.0, 1))
    } else {
        format!("{s:.4e} s ({hours} h)")
    }
}

/// The peak of design `p` as an interval `[lo, hi]` (zero width when exact).
fn interval(fs: &HarmonicSummary, p: u64) -> Option<(f64, f64)> {
    fs.curve(p)?.peak_interval()
}

/// The section's paragraph and table on peaks carried by motions that are not periodic, and
/// the overlap note; empty when every shown design's peak is periodic.
pub fn section(s: &Summary, fs: &HarmonicSummary, shown: &[&PointStats]) -> String {
    let mut o = String::new();
    // Without stored attractors (no census, or a dataset written before them) there is no
    // life estimate to speak of.
    if !fs.curves.iter().any(|c| c.attractors.is_some()) {
        return o;
    }
    if fs.nonperiodic_peak == NonPeriodicPeak::Window {
        let _ = writeln!(
            o,
            "\n**No design life.** This study asks for window peaks (`[scene] nonperiodic_peak = \"window\"`): a steady state that is not periodic keeps the largest amplitude of the census's 200-period window as its design amplitude, a lower bound of what it reaches over a longer operation, and the peaks it carries are marked †. Its periodic steady states are the same as with design-life estimates. Remove the key (or set `\"life\"`) to estimate every such peak over a design life with its 90 % interval."
        );
        return o;
    }
    let rows: Vec<(&PointStats, &AttractorRow)> = shown
        .iter()
        .filter_map(|p| {
            let a = fs.curve(p.point)?.peak_attractor()?;
            (!a.kind.periodic()).then_some((*p, a))
        })
        .collect();
    let _ = writeln!(
        o,
        "\n**The design life.** A steady state that is not periodic has no single amplitude: the largest excursion grows with the time watched. Its design amplitude is the {} of its largest amplitude over a design life of {} (`[scene] design_life`, `life_quantile`), estimated from its per-period maxima by a generalized Pareto tail above a threshold and given with its 90 % interval (docs/scenes.md); a periodic orbit's amplitude is exact.",
        quantile_text(fs),
        life_text(fs.design_life)
    );
    if fs.life_curve == LifeCurve::Whole {
        let _ = writeln!(
            o,
            "\n**The whole curve measured** (`[scene] life_curve = \"whole\"`): besides the values that decide (a curve's peak, where the damper helps, a dip beside the peak), every frequency of each design's ideal curve was measured until the motions that could carry its value were settled (`life_tol` at three successive windows) or reached `life_max_periods` (`attractors.csv`: `measured_periods`, and `life_capped` where the cap stopped them). A perturbed case's curve serves only its peak and was raced as by default."
        );
    }
    if !rows.is_empty() {
        let _ = writeln!(
            o,
            "\n| design | carried by | λ1 per period (per s) | window max, 200 periods (cm) | life amplitude (cm) | 90 % interval (cm) | tail shape ξ | periods measured |\n|---|---|---|---|---|---|---|---|"
        );
        for (p, a) in &rows {
            let _ = writeln!(
                o,
                "| {} | {} | {} | {} | {} | {} | {} | {}{} |",
                design_text(s, p.point),
                a.kind.name(),
                exponent(a),
                cm(a.window_amplitude),
                cm(a.amplitude),
                if a.life_lo.is_finite() {
                    format!("{} – {}", cm(a.life_lo), cm(a.life_hi))
                } else {
                    "not measured".to_string()
                },
                f(a.tail_shape, 2),
                a.measured_periods,
                if a.life_capped { " (capped)" } else { "" }
            );
        }
    }
    o.push_str(&extrapolated(s, &rows));
    o.push_str(&verified(s, fs, !rows.is_empty()));
    o.push_str(&overlaps(s, fs, shown));
    o
}

/// A motion's largest Lyapunov exponent with its standard error, per period and per second;
/// "not measured" without one (the simulator stopped its probe).
fn exponent(a: &AttractorRow) -> String {
    if a.lyapunov.is_nan() {
        return "not measured".to_string();
    }
    format!(
        "{} ± {} ({})",
        f(a.lyapunov, 3),
        f(a.lyapunov_se, 3),
        f(a.lyapunov_per_s, 1)
    )
}

/// The verification's paragraph and table (docs/scenes.md, "The decision verified"): which
/// designs decided the ranking, each direct measurement beside the estimate it checks, and the
/// ranks it moved; empty when nothing was verified, but where one design ranks and a peak rests
/// on an estimate (`estimated`), which is told why it was not verified.
fn verified(s: &Summary, fs: &HarmonicSummary, estimated: bool) -> String {
    let v = &fs.verification;
    if v.designs.is_empty() {
        return if estimated && v.periods > 0 && v.ranks_before.len() == 1 {
            "\n**Not verified.** One design ranks, so there is no order to decide and `reduce` does not measure its peak motions again (the designs that decide a ranking are measured directly over `[ranking] verify_periods` periods): the peak rests on the race's estimate above, with its interval and the periods it rests on. A smaller `[scene] life_tol` measures it longer.\n".to_string()
        } else {
            String::new()
        };
    }
    let mut o = String::new();
    let names: Vec<String> = v.designs.iter().map(|&d| design_text(s, d)).collect();
    let measured: usize = v.peaks.iter().map(|p| p.verified.len()).sum();
    let raced = v
        .peaks
        .iter()
        .flat_map(|p| &p.verified)
        .filter(|m| m.as_raced)
        .count();
    let _ = writeln!(
        o,
        "\n**The decision verified.** The designs that decide the ranking (the best ranked as the sweep measured it, and every design whose peak interval overlaps its peak) are {}{}. Every motion that is not periodic and could carry a peak of one of their cases was measured directly, from its stored state on 16 independent chains for {} periods (a motion whose interval fell wholly below its case's peak on the way stopped there: it cannot carry the peak), and the ranking uses those values ({}; the estimates' periods are the sweep's race{}).",
        names.join(", "),
        if v.rounds > 1 {
            format!(
                " (in {} rounds: where the direct values made another design the best, or one overlapping it, that had not been measured, the verification ran again on the ranking so moved, so the best-ranked design rests on direct measurements)",
                v.rounds
            )
        } else {
            String::new()
        },
        crate::report::text::thousands(v.periods),
        crate::report::text::count(measured as u64, "motion", "motions"),
        if raced > 0 {
            format!(
                "; {} the race had already measured that long {} taken as {} (\"as raced\")",
                crate::report::text::count(raced as u64, "motion", "motions"),
                if raced == 1 { "is" } else { "are" },
                if raced == 1 { "it is" } else { "they are" }
            )
        } else {
            String::new()
        }
    );
    if measured > 0 {
        verified_table(&mut o, s, v);
    }
    verified_moves(&mut o, s, v);
    o
}

/// The verification's table: each motion measured directly, beside the estimate it checks,
/// and its case's peak before and after.
fn verified_table(o: &mut String, s: &Summary, v: &Verification) {
    let _ = writeln!(
        o,
        "\n| design | case | at r | estimate (cm) [90 %] | periods | direct (cm) [90 %] | periods | largest seen (cm) | case peak before → after (cm) |\n|---|---|---|---|---|---|---|---|---|"
    );
    for p in &v.peaks {
        for m in &p.verified {
            let c = &m.motion;
            let direct = m.direct.and_then(|d| d.estimate.map(|e| (d, e)));
            let _ = writeln!(
                o,
                "| {} | {} | {} | {} [{} – {}] | {} | {} | {} | {} | {} → {} |",
                design_text(s, p.design),
                p.case,
                f(c.r, 3),
                cm(c.amplitude),
                cm(c.lo),
                cm(c.hi),
                crate::report::text::thousands(c.measured),
                if m.as_raced {
                    format!(
                        "{} [{} – {}], as raced",
                        cm(c.amplitude),
                        cm(c.lo),
                        cm(c.hi)
                    )
                } else {
                    direct.map_or("failed".into(), |(_, e)| {
                        format!("{} [{} – {}]", cm(e.amplitude), cm(e.lo), cm(e.hi))
                    })
                },
                if m.as_raced {
                    crate::report::text::thousands(c.measured)
                } else {
                    direct.map_or("–".into(), |(d, _)| {
                        crate::report::text::thousands(d.measured)
                    })
                },
                direct.map_or("–".into(), |(d, _)| cm(d.window_max)),
                cm(p.before),
                cm(p.after)
            );
        }
    }
}

/// The ranks the verification moved, and the peaks that still rest on an estimate.
fn verified_moves(o: &mut String, s: &Summary, v: &Verification) {
    let mut moves = Vec::new();
    for p in &s.points {
        if let (Some(before), Some(after)) = (v.rank_before(p.point), p.rank)
            && before != after
        {
            moves.push(format!(
                "{} from {before} to {after}",
                design_text(s, p.point)
            ));
        }
    }
    let unsupported: Vec<String> = v
        .peaks
        .iter()
        .filter(|p| !p.supported)
        .map(|p| format!("{} case {}", design_text(s, p.design), p.case))
        .collect();
    let _ = writeln!(
        o,
        "\n{}",
        if moves.is_empty() {
            "The verification moved no rank.".to_string()
        } else {
            format!("**The verification moved ranks**: {}.", moves.join("; "))
        }
    );
    if !unsupported.is_empty() {
        let _ = writeln!(
            o,
            "\nThe peaks of {} still rest on an estimate not measured again (more motions could carry them than were measured, or a direct run failed).",
            unsupported.join(", ")
        );
    }
}

/// A life amplitude this many times the window maximum, from a run capped before its interval
/// met the tolerance, is flagged as resting on the tail model.
const FAR: f64 = 2.0;

/// The peaks among `rows` that are long extrapolations: capped (the interval did not reach
/// `life_tol` within `life_max_periods`) and at least [`FAR`] times the largest amplitude of
/// the census's window; with their tail shapes (near 0: an exponential, unbounded tail).
fn extrapolated(s: &Summary, rows: &[(&PointStats, &AttractorRow)]) -> String {
    let far: Vec<String> = rows
        .iter()
        .filter(|(_, a)| a.life_capped && a.amplitude >= FAR * a.window_amplitude)
        .map(|(p, a)| {
            format!(
                "{} ({}× the window maximum, ξ = {})",
                design_text(s, p.point),
                f(a.amplitude / a.window_amplitude, 1),
                f(a.tail_shape, 2)
            )
        })
        .collect();
    if far.is_empty() {
        return String::new();
    }
    format!(
        "
**Peaks that rest on the tail model.** These peaks are estimates over a design life far longer than the run measured, from a run capped before its interval met `life_tol`, and at least {}× the largest amplitude the census's window saw: {}. Where ξ is near 0 the fitted tail is exponential (unbounded), and the estimate grows with the logarithm of the design life; their ranking rests on that model more than on what was seen. Raise `life_max_periods` to narrow them.\n",
        f(FAR, 0),
        far.join("; ")
    )
}

fn quantile_text(fs: &HarmonicSummary) -> String {
    let q = fs.life_quantile;
    if q == 0.5 {
        "median".to_string()
    } else {
        format!("{} quantile", f(q, 3))
    }
}

/// Designs ranked next to each other whose peak intervals overlap: their order rests on a
/// difference inside the estimates' uncertainty.
fn overlaps(s: &Summary, fs: &HarmonicSummary, shown: &[&PointStats]) -> String {
    let mut pairs = Vec::new();
    for w in shown.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a.rank.is_none() || b.rank.is_none() {
            continue;
        }
        if let (Some(ia), Some(ib)) = (interval(fs, a.point), interval(fs, b.point))
            && ia.0 <= ib.1
            && ib.0 <= ia.1
            && (ia.0 != ia.1 || ib.0 != ib.1)
        {
            pairs.push(format!(
                "{} and {}",
                design_text(s, a.point),
                design_text(s, b.point)
            ));
        }
    }
    if pairs.is_empty() {
        return String::new();
    }
    format!(
        "\n**Ranked apart within their uncertainty.** The peak intervals of these neighbours in the ranking overlap, so their order is not established by the estimates: {}. Measure longer (`life_max_periods`, `life_tol`) or weigh them as equals.\n",
        pairs.join("; ")
    )
}
