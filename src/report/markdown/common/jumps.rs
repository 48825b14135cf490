//! The jumps, grouped per axis, quantity and kind, then those on the lines through the
//! recommended design one by one.

use std::fmt::Write;

use crate::report::markdown::words::{MAX_ROWS, f};

use crate::reduce::common::stats::median;
use crate::reduce::common::tables::{per_axis_unit, quantity_of};
use crate::reduce::common::zones::LEVEL_SHARE;
use crate::reduce::{Jump, JumpKind, Quantity, StepRule, Summary};
use crate::report::text::{axis_unit, count, fmt_num, thousands};

/// The report's section on the jumps located along the design axes.
///
/// `window`: the study's motions that are not periodic carry their window maxima
/// (`nonperiodic_peak = "window"`), not amplitudes over a design life.
pub fn section(s: &Summary, window: bool) -> String {
    let mut o = String::from("## Jumps\n\n");
    let g = &s.grid;
    if (0..g.n_axes()).all(|a| g.n(a) < 2) {
        o.push_str("One design point: no line of the grid to look for jumps along.\n\n");
        return o;
    }
    rule(&mut o, s);
    counts(&mut o, s, window);
    if s.jumps.is_empty() {
        let _ = writeln!(o, "No jump along any axis.\n");
        return o;
    }
    o += &grouped(s);
    o += &through_anchor(s);
    o
}

/// How a jump is found, located and classed, with the study's tolerances and typical slopes.
fn rule(o: &mut String, s: &Summary) {
    let st = &s.jump_stats;
    let g = &s.grid;
    let (rname, runit) = quantity_of(s, Quantity::Response);
    let damping = &s.options.damping;
    let slopes: Vec<String> = (0..g.n_axes())
        .filter(|&a| st.typical_slope.get(a).is_some_and(|v| v.is_finite()))
        .map(|a| {
            format!(
                "{} {} along {}",
                f(st.typical_slope[a], 4),
                per_axis_unit(runit, axis_unit(g.key(a))),
                g.key(a)
            )
        })
        .collect();
    let _ = writeln!(
        o,
        "Along every line of the grid, a step is a change of the ideal case's {rname} by at least {} {runit}{} ({}) that the trend on either side does not explain; a kink is a change of the slope of {rname} by at least {} × its typical slope ({}). Each candidate is located by bisection with extra simulations of the ideal case to {} of the grid step, then classed: a step if the change stays as the bracket shrinks (where the bisection loses it among several steps close together, the span is cut into eight parts and the part with the largest change cut again, down to the same tolerance), a kink if only the slope changes, dropped otherwise (a steep but smooth stretch).\n",
        fmt_num(st.step_tol[0]),
        // (Without a finite tolerance on the second quantity, e.g. no threshold for p_s, the
        // steps are the response's alone.)
        if st.step_tol[1].is_finite() {
            format!(
                " or of its {} by at least {}",
                damping.symbol,
                damping.with_unit(&fmt_num(st.step_tol[1]))
            )
        } else {
            String::new()
        },
        step_rule(s),
        fmt_num(s.options.zones.kink_slope),
        if slopes.is_empty() {
            "–".to_string()
        } else {
            slopes.join(", ")
        },
        fmt_num(s.options.zones.locate),
    );
}

/// How the step tolerances were set: from the spread of the points' cases, or, where the cases
/// give no spread (one case per point, or cases that do not differ), from the quantity's median
/// value ([`crate::reduce::common::zones::step_tolerances`]).
fn step_rule(s: &Summary) -> String {
    let st = &s.jump_stats;
    let spread = fmt_num(s.options.zones.step_spread);
    let level = format!("{} %", fmt_num(100.0 * LEVEL_SHARE));
    let (rname, _) = quantity_of(s, Quantity::Response);
    let dname = s.options.damping.symbol;
    let rules: &[StepRule] = if st.step_tol[1].is_finite() {
        &st.step_rule
    } else {
        &st.step_rule[..1]
    };
    match rules {
        [StepRule::Spread] => format!("{spread} × the median spread over a point's cases"),
        [StepRule::Spread, StepRule::Spread] => {
            format!("{spread} × the median spread of each over a point's cases")
        }
        [StepRule::Level] => format!(
            "{level} of its median value over the points: a point's cases do not differ, so there is no spread to scale"
        ),
        [StepRule::Level, StepRule::Level] => format!(
            "{level} of each one's median value over the points: a point's cases do not differ, so there is no spread to scale"
        ),
        [r, _] => {
            let (by_spread, by_level) = if *r == StepRule::Spread {
                (rname, dname)
            } else {
                (dname, rname)
            };
            format!(
                "{spread} × the median spread over a point's cases for {by_spread}; {level} of the median value for {by_level}, whose cases do not differ"
            )
        }
        _ => String::new(),
    }
}

/// What the search found: candidates, extra simulations, jumps and how each was located, and
/// the candidates between estimates. `window`: as in [`section`].
fn counts(o: &mut String, s: &Summary, window: bool) {
    let st = &s.jump_stats;
    let _ = writeln!(
        o,
        "{}, {}: {}{}, {} dropped{}.\n",
        count(st.candidates as u64, "candidate", "candidates"),
        count(st.sims, "extra simulation", "extra simulations"),
        count(s.jumps.len() as u64, "jump", "jumps"),
        if st.estimated_steps + st.stopped_steps > 0 {
            format!(
                " ({} located to the tolerance, {} at a bisection's bracket that stopped at an estimate, {} between estimates)",
                s.jumps
                    .len()
                    .saturating_sub(st.estimated_steps + st.stopped_steps),
                st.stopped_steps,
                st.estimated_steps
            )
        } else {
            " located".to_string()
        },
        count(st.dropped as u64, "smooth stretch", "smooth stretches"),
        if st.failed > 0 {
            format!(
                ", {} not followed (a simulation inside did not end ok)",
                st.failed
            )
        } else {
            String::new()
        }
    );
    if st.estimated > 0 {
        let _ = writeln!(
            o,
            "{} of the candidates lay between designs whose peaks are estimates: a motion that is not periodic carries the peak at every point of the span, and its amplitude over the design life is known within a 90 % interval. A midpoint's estimate has the same statistical error, so these are not bisected; a step is looked for between neighbours: {} had two neighbouring designs whose intervals do not overlap and whose change is the step tolerance beyond the trend either side, reported as steps at that grid interval (`location_tol` is half of it); {} had none (a change within the intervals, or a trend or a bend across the span) and are counted among the dropped.\n",
            st.estimated,
            st.estimated_steps,
            st.estimated - st.estimated_steps,
        );
    }
    if st.stopped_steps > 0 {
        let _ = writeln!(
            o,
            "{} stopped at a midpoint whose peak is an estimate (a chaotic motion continued there still wanders, and the bracketing designs' {} at that frequency reach above the midpoint's exact peak): they are reported at the bracket reached, with half its width as `location_tol`.\n",
            if st.stopped_steps == 1 {
                "1 step's bisection".to_string()
            } else {
                format!("{} steps' bisections", st.stopped_steps)
            },
            if window {
                "window maxima"
            } else {
                "amplitudes over the design life"
            },
        );
    }
}

/// One row per axis, quantity and kind: count, lines, where, how large.
fn grouped(s: &Summary) -> String {
    let g = &s.grid;
    let mut o = String::from(
        "| axis | quantity | kind | jumps | lines with one | location: min – median – max | size: median (largest) |\n|---|---|---|---|---|---|---|\n",
    );
    for a in 0..g.n_axes() {
        for q in Quantity::ALL {
            for kind in [JumpKind::Step, JumpKind::Kink] {
                let js: Vec<&Jump> = s
                    .jumps
                    .iter()
                    .filter(|j| j.axis == a && j.quantity == q && j.kind == kind)
                    .collect();
                if js.is_empty() {
                    continue;
                }
                let mut lines: Vec<u64> = js.iter().map(|j| g.with_index(j.below, a, 0)).collect();
                lines.sort_unstable();
                lines.dedup();
                let n_lines = g.len() / g.n(a) as u64;
                let locs: Vec<f64> = js.iter().map(|j| j.location).collect();
                let (lo, hi) = locs
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                        (l.min(v), h.max(v))
                    });
                let sizes: Vec<f64> = js.iter().map(|j| j.size.abs()).collect();
                let largest = sizes.iter().copied().fold(0.0, f64::max);
                let (name, unit) = quantity_of(s, q);
                let unit = spaced(&match kind {
                    JumpKind::Step => unit.to_string(),
                    JumpKind::Kink => per_axis_unit(unit, axis_unit(g.key(a))),
                });
                let _ = writeln!(
                    o,
                    "| {} | {name} | {} | {} | {} of {} | {} – {} – {} | {} ({}){unit} |",
                    g.key(a),
                    kind.name(),
                    thousands(js.len() as u64),
                    thousands(lines.len() as u64),
                    thousands(n_lines),
                    fmt_num(lo),
                    fmt_num(median(&locs)),
                    fmt_num(hi),
                    fmt_num(median(&sizes)),
                    fmt_num(largest)
                );
            }
        }
    }
    let _ = writeln!(
        o,
        "\nA step's size is the change of the quantity across it, a kink's the change of its slope. Every jump is in `jumps.parquet`, with the other axes' values of its line.\n"
    );
    o
}

/// The jumps on the lines through the recommended (or best) design, one by one.
fn through_anchor(s: &Summary) -> String {
    let mut o = String::new();
    let g = &s.grid;
    let Some(anchor) = s.anchor() else {
        return o;
    };
    let mut js: Vec<&Jump> = s
        .jumps
        .iter()
        .filter(|j| g.with_index(j.below, j.axis, 0) == g.with_index(anchor, j.axis, 0))
        .collect();
    js.sort_by(|a, b| {
        (a.axis, a.location)
            .partial_cmp(&(b.axis, b.location))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    if g.n_axes() == 1 {
        let _ = writeln!(o, "Every jump:\n");
    } else {
        let whose = if s.recommended == Some(anchor) {
            "recommended"
        } else {
            "best"
        };
        let _ = writeln!(
            o,
            "{} jumps on the lines through the {whose} design (one axis varied, the others at its values){}\n",
            js.len(),
            if js.is_empty() { "." } else { ":" }
        );
        if js.is_empty() {
            return o;
        }
    }
    let _ = writeln!(
        o,
        "| axis | kind | quantity | location ± tolerance | between | size |\n|---|---|---|---|---|---|"
    );
    for j in js.iter().take(MAX_ROWS) {
        let (name, unit) = quantity_of(s, j.quantity);
        let key = g.key(j.axis);
        let size = match j.kind {
            JumpKind::Step => format!("{}{}", fmt_num(j.size), spaced(unit)),
            JumpKind::Kink => format!(
                "{} {}",
                fmt_num(j.size),
                per_axis_unit(unit, axis_unit(key))
            ),
        };
        let (from, to) = j.grid_span(g);
        let _ = writeln!(
            o,
            "| {key} | {} | {name} | {} ± {} | {} – {} | {size} |",
            j.kind.name(),
            fmt_num(j.location),
            fmt_num(j.location_tol),
            fmt_num(from),
            fmt_num(to),
        );
    }
    if js.len() > MAX_ROWS {
        let _ = writeln!(
            o,
            "\n… and {} more in `jumps.parquet`.",
            js.len() - MAX_ROWS
        );
    }
    let _ = writeln!(o);
    o
}

/// A unit after a number: ` m`, and nothing for a dimensionless quantity (unit `1`).
fn spaced(unit: &str) -> String {
    if unit == "1" || unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::testing::{reduce_simulated, study};

    /// The rule the report states is the one the tolerances came from: with one case a point
    /// there is no spread, and the tolerances are 1 % of the quantities' median values.
    #[test]
    fn the_step_rule_stated_is_the_one_applied() {
        let axes = || vec![("e", vec![0.5, 0.6, 0.7, 0.8])];
        let one = reduce_simulated(&study(axes(), 1));
        assert_eq!(one.jump_stats.step_rule, [StepRule::Level; 2]);
        let text = section(&one, false);
        assert!(
            text.contains("(1 % of each one's median value over the points: a point's cases do not differ, so there is no spread to scale)"),
            "{text}"
        );
        assert!(!text.contains("median spread"), "{text}");
        // Noisy cases differ: the spread sets both.
        let mut noisy = study(axes(), 3);
        noisy.noise = Some(crate::sim::NoiseSettings {
            power: 5e-10,
            sample_time: 1e-3,
        });
        let noisy = reduce_simulated(&noisy);
        assert_eq!(noisy.jump_stats.step_rule, [StepRule::Spread; 2]);
        assert!(
            section(&noisy, false).contains("(1 × the median spread of each over a point's cases)")
        );
    }
}
