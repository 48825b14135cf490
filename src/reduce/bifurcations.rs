//! Bifurcation curves over the design space (docs/reduce.md, "Bifurcations over the design
//! space"): every fold, period doubling, Neimark–Sacker point and grazing located on a design's
//! branches ([`crate::orbits::locate`]) followed in `(r, p)` for each swept design axis `p` (`m`,
//! `d`, `e`, `C`, `F0`) over the swept range of `p`, the other axes held at the design's values
//! ([`crate::orbits::twopar`]), as the `bifurcations` table.
//!
//! One curve serves every design it passes through: a located point is not followed again when
//! a curve already followed in the same plane (the other axes' values), of the same kind and
//! period, has its point at this design's value of `p` within `1e-6` of it in `r`, or when an
//! earlier located point of the same design is that point. Designs are taken in order, and a
//! design's curves are followed in parallel and kept in the order of its points, so the table is
//! the same for any thread count.

use super::forced::ForcedSummary;
use super::grid::Grid;
use rayon::prelude::*;

use super::table::{Column, Table};
use crate::orbits::continuation::Label;
use crate::orbits::response::Response;
use crate::orbits::twopar::{self, Axis, BifurcationCurve, Seed};
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
/// axis or without a swept design axis among `m`, `d`, `e`, `C`, `F0`).
pub fn curves(study: &Study, grid: &Grid, fs: &ForcedSummary, steady: &[Response]) -> Vec<Curve> {
    let Some((_, freqs)) = &fs.frequency else {
        return Vec::new();
    };
    let axes: Vec<(usize, Axis)> = (0..grid.n_axes())
        .filter(|&a| grid.n(a) >= 2)
        .filter_map(|a| Axis::of_key(grid.key(a)).map(|x| (a, x)))
        .collect();
    if axes.is_empty() || freqs.len() < 2 {
        return Vec::new();
    }
    let mut out: Vec<Curve> = Vec::new();
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
        // This design's located points not on a curve followed already (from an earlier design,
        // or an earlier point of this one: mirror halves and branches that meet at one point are
        // located more than once), in order.
        let mut todo: Vec<(usize, Axis, Seed)> = Vec::new();
        // A grazing where an impact's speed vanishes, located from the impacting side, has no
        // multipliers (the map is not differentiable there) and cannot seed a curve; the same
        // grazing located from its smooth side can.
        let seeds = resp
            .branches
            .iter()
            .filter(|b| b.located && b.multiplier_max.is_finite());
        for b in seeds {
            let label = match b.label {
                "SN" => Label::SN,
                "PD" => Label::PD,
                "NS" => Label::NS,
                "GR" => Label::GR,
                _ => continue,
            };
            for &(a, axis) in &axes {
                let p = grid.value(resp.design, a);
                let known = out.iter().any(|k| {
                    k.axis_index == a
                        && k.curve.label == label
                        && same_plane(grid, k.seed_design, resp.design, a)
                        && k.curve.points.iter().any(|q| {
                            q.at_value
                                && q.p == p
                                && q.period == b.period
                                && (q.r - b.r).abs() <= 1e-6
                        })
                });
                let twin = todo.iter().any(|(ta, _, t)| {
                    *ta == a
                        && t.label == label
                        && t.period == b.period
                        && (t.f.ratio() - b.r).abs() <= 1e-6
                });
                if known || twin {
                    continue;
                }
                let seed = Seed {
                    f: base.at_ratio(b.r),
                    s: b.s,
                    period: b.period,
                    label,
                };
                todo.push((a, axis, seed));
            }
        }
        // Followed in parallel, kept in order: the same table for any thread count.
        let followed: Vec<Option<Curve>> = todo
            .par_iter()
            .map(|(a, axis, seed)| {
                let values = grid.axis_values(*a);
                let range = values
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(x, y), v| {
                        (x.min(*v), y.max(*v))
                    });
                twopar::follow(seed, *axis, range, (r_lo, r_hi), values).map(|curve| Curve {
                    seed_design: resp.design,
                    axis_index: *a,
                    curve,
                })
            })
            .collect();
        out.extend(followed.into_iter().flatten());
    }
    out
}

/// Whether designs `x` and `y` have the same values on every axis but `a`.
fn same_plane(grid: &Grid, x: u64, y: u64, a: usize) -> bool {
    (0..grid.n_axes()).all(|k| k == a || grid.index(x, k) == grid.index(y, k))
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
