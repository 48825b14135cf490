//! Bifurcation curves over the design space (docs/reduce.md, "Bifurcations over the design
//! space"): every fold, period doubling, Neimark–Sacker point and grazing located on a design's
//! branches ([`crate::orbits::locate`]) followed in `(r, p)` for each swept design axis `p` (`m`,
//! `d`, `e`, `C`, `F0`) over the swept range of `p`, the other axes held at the design's values
//! ([`crate::orbits::twopar`]), as the `bifurcations` table.
//!
//! One curve serves every design it passes through: a located point is not followed again when
//! a curve already followed in the same plane (the other axes' values), of the same kind and
//! period, has its point at this design's value of `p` within `1e-6` of it in `r`, or when an
//! earlier located point of the same design is that point. So the lines of the grid along each
//! axis (the designs that differ only on it) are independent: they are followed in parallel, and
//! in each line the designs in order, a design's new curves in parallel; the curves are kept in
//! the order of the designs and their points, so the table is the same for any thread count.

use std::collections::BTreeMap;

use super::analysis::CurveLines;
use super::summary::HarmonicSummary;
use crate::reduce::common::Grid;
use rayon::prelude::*;

use crate::orbits::label::Label;
use crate::orbits::response::Response;
use crate::orbits::twopar::{self, Axis, BifurcationCurve, Seed};
use crate::store::table::{Column, Table};
use crate::study::Study;

/// A followed curve and where it lies: its plane (the design whose located point seeded it, and
/// the axis it moves along).
#[derive(Clone, Debug)]
pub struct Curve {
    pub seed_design: u64,
    /// Index of the axis in the design grid.
    pub axis_index: usize,
    pub curve: BifurcationCurve,
}

/// The bifurcation curves of a harmonic study along the frequency (empty without a frequency
/// axis, without a swept design axis among `m`, `d`, `e`, `C`, `F0`, or with several units),
/// along the lines of the grid that `lines` asks for (`anchor`: the recommended design;
/// without one, `Recommended` follows none).
pub fn curves(
    study: &Study,
    grid: &Grid,
    fs: &HarmonicSummary,
    steady: &[Response],
    lines: CurveLines,
    anchor: Option<u64>,
) -> Vec<Curve> {
    let Some((_, freqs)) = &fs.frequency else {
        return Vec::new();
    };
    // The curves over the design space follow one unit's section (a study of several units
    // locates its points on its branches, and follows no curve from them).
    if study.several_units() {
        return Vec::new();
    }
    let wanted = |design: u64, a: usize| match lines {
        CurveLines::All => true,
        CurveLines::None => false,
        CurveLines::Recommended => anchor.is_some_and(|an| {
            (0..grid.n_axes()).all(|k| k == a || grid.index(design, k) == grid.index(an, k))
        }),
    };
    let axes: Vec<(usize, Axis)> = (0..grid.n_axes())
        .filter(|&a| grid.n(a) >= 2)
        .filter_map(|a| Axis::of_key(grid.key(a)).map(|x| (a, x)))
        .collect();
    if axes.is_empty() || freqs.len() < 2 {
        return Vec::new();
    }
    // Every located point's seed along every axis, in the order of the table (design, point,
    // axis), grouped by line: a curve along axis `a` only serves designs of its own line (the
    // same values on every other axis), so the lines are independent of one another.
    let mut lines: BTreeMap<(usize, Vec<usize>), Vec<Candidate>> = BTreeMap::new();
    let mut order = 0usize;
    for resp in steady {
        let Some(c) = fs.curve(resp.design) else {
            continue;
        };
        let (r_lo, r_hi) = c
            .points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.r), b.max(p.r))
            });
        let base = crate::orbits::map::Forcing {
            sys: c.system,
            F0: c.f0,
            omega: c.system.omega(),
            settings: study.solver,
        };
        // A grazing where an impact's speed vanishes, located from the impacting side, has no
        // multipliers (the map is not differentiable there) and cannot seed a curve; the same
        // grazing located from its smooth side can.
        let seeds = resp
            .branches
            .iter()
            .filter(|b| b.located && b.multiplier_max.is_finite());
        for b in seeds {
            let Some(label) = Label::of_name(b.label) else {
                continue;
            };
            for &(a, axis) in axes.iter().filter(|(a, _)| wanted(resp.design, *a)) {
                lines
                    .entry((a, line_of(grid, resp.design, a)))
                    .or_default()
                    .push(Candidate {
                        order,
                        design: resp.design,
                        axis,
                        r_range: (r_lo, r_hi),
                        seed: Seed {
                            f: base.at_ratio(b.r),
                            s: b.s,
                            period: b.period,
                            label,
                        },
                    });
                order += 1;
            }
        }
    }
    // The lines in parallel, each design's new curves in parallel; kept in the table's order:
    // the same table for any thread count.
    let mut out: Vec<(usize, Curve)> = lines
        .into_par_iter()
        .flat_map_iter(|((a, _), cands)| follow_line(grid, a, cands))
        .collect();
    out.sort_by_key(|(order, _)| *order);
    out.into_iter().map(|(_, c)| c).collect()
}

/// The line through `design` along axis `a`: its index on every other axis, `usize::MAX` on
/// `a` itself.
fn line_of(grid: &Grid, design: u64, a: usize) -> Vec<usize> {
    (0..grid.n_axes())
        .map(|k| {
            if k == a {
                usize::MAX
            } else {
                grid.index(design, k)
            }
        })
        .collect()
}

/// A located point to follow along one axis: its place in the table's order, its design, the
/// axis, the design's range of `r` and the seed.
struct Candidate {
    order: usize,
    design: u64,
    axis: Axis,
    r_range: (f64, f64),
    seed: Seed,
}

/// The curves of one line along axis `a` (its candidates in design order). A located point is
/// not followed again when a curve from an earlier design of the line, of the same kind and
/// period, has its point at this design's value of `p` within `1e-6` of it in `r`, or when an
/// earlier point of the same design is that point (mirror halves and branches that meet at one
/// point are located more than once).
fn follow_line(grid: &Grid, a: usize, cands: Vec<Candidate>) -> Vec<(usize, Curve)> {
    let values = grid.axis_values(a);
    let range = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(x, y), v| {
            (x.min(*v), y.max(*v))
        });
    let mut out: Vec<(usize, Curve)> = Vec::new();
    let mut rest = cands.as_slice();
    while let Some(first) = rest.first() {
        let design = first.design;
        let n = rest.iter().take_while(|c| c.design == design).count();
        let (this, later) = rest.split_at(n);
        rest = later;
        let p = grid.value(design, a);
        let mut todo: Vec<&Candidate> = Vec::new();
        for c in this {
            let (label, period, r) = (c.seed.label, c.seed.period, c.seed.f.ratio());
            let known = out.iter().any(|(_, k)| {
                k.curve.label == label
                    && k.curve.points.iter().any(|q| {
                        q.at_value && q.p == p && q.period == period && (q.r - r).abs() <= 1e-6
                    })
            });
            let twin = todo.iter().any(|t| {
                t.seed.label == label
                    && t.seed.period == period
                    && (t.seed.f.ratio() - r).abs() <= 1e-6
            });
            if !(known || twin) {
                todo.push(c);
            }
        }
        let followed: Vec<Option<(usize, Curve)>> = todo
            .par_iter()
            .map(|c| {
                twopar::follow(&c.seed, c.axis, range, c.r_range, values).map(|curve| {
                    let curve = Curve {
                        seed_design: c.design,
                        axis_index: a,
                        curve,
                    };
                    (c.order, curve)
                })
            })
            .collect();
        out.extend(followed.into_iter().flatten());
    }
    out
}

/// The `bifurcations` table (docs/schema.md): one row per point of each curve.
pub fn table(curves: &[Curve]) -> Table {
    let rows: Vec<(u64, &Curve, &twopar::CurvePoint)> = curves
        .iter()
        .enumerate()
        .flat_map(|(i, c)| c.curve.points.iter().map(move |p| (i as u64, c, p)))
        .collect();
    let mut t = Table::default();
    t.push(
        "curve",
        Column::U64(rows.iter().map(|r| Some(r.0)).collect()),
    );
    t.push(
        "point",
        Column::U64(rows.iter().map(|r| Some(r.1.seed_design)).collect()),
    );
    t.push(
        "kind",
        Column::Str(
            rows.iter()
                .map(|r| r.1.curve.label.name().to_string())
                .collect(),
        ),
    );
    t.push(
        "p_name",
        Column::Str(
            rows.iter()
                .map(|r| r.1.curve.axis.name().to_string())
                .collect(),
        ),
    );
    t.push("p", Column::F64(rows.iter().map(|r| r.2.p).collect()));
    t.push("r", Column::F64(rows.iter().map(|r| r.2.r).collect()));
    t.push(
        "amplitude",
        Column::F64(rows.iter().map(|r| r.2.amplitude).collect()),
    );
    t.push(
        "period",
        Column::U64(rows.iter().map(|r| Some(u64::from(r.2.period))).collect()),
    );
    t.push(
        "impacts_per_period",
        Column::F64(rows.iter().map(|r| r.2.impacts_per_period).collect()),
    );
    t.push(
        "at_grid",
        Column::Bool(rows.iter().map(|r| r.2.at_value).collect()),
    );
    t
}
