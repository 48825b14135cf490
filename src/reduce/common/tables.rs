//! The reducer's tables (summary, zones, jumps, sensitivity) as plain columns
//! ([`crate::store::table::Table`]): the store writes them to Parquet and CSV
//! ([`crate::store::summary`]), the report quotes them. No arrow here.

use super::{JumpKind, PointStats, Quantity, Summary};
use crate::sim::Outcome;
use crate::store::table::{Column, Table, axis_column};

/// One row per design point. Units: SI (m, Pa, m/s); `perfectibility` in %.
pub fn summary_table(s: &Summary) -> Table {
    summary_rows(s, &s.points.iter().collect::<Vec<_>>())
}

/// The summary columns of some of the points (a chart's data: the rows of its slice).
pub fn summary_rows(s: &Summary, p: &[&PointStats]) -> Table {
    let f = |g: &dyn Fn(&PointStats) -> f64| Column::F64(p.iter().map(|x| g(x)).collect());
    let u = |g: &dyn Fn(&PointStats) -> u64| Column::U64(p.iter().map(|x| Some(g(x))).collect());
    let r = s.options.response.name;
    let mut t = Table::default();
    t.push("point", u(&|x| x.point));
    for a in 0..s.grid.n_axes() {
        t.push(axis_column(s.grid.key(a)), f(&|x| s.grid.value(x.point, a)));
    }
    t.push("n", u(&|x| u64::from(x.n_ok)));
    t.push("n_cases", u(&|x| u64::from(x.n_cases)));
    t.push("n_ok", u(&|x| u64::from(x.n_ok)));
    t.push("all_ok", Column::Bool(p.iter().map(|x| x.all_ok).collect()));
    t.push(
        "failed",
        Column::Str(p.iter().map(|x| outcome_text(&x.outcomes, true)).collect()),
    );
    t.push(format!("{r}_mean"), f(&|x| x.response.mean));
    t.push(format!("{r}_sd"), f(&|x| x.response.sd));
    t.push(format!("{r}_min"), f(&|x| x.response.min));
    t.push(format!("{r}_q1"), f(&|x| x.response.q1));
    t.push(format!("{r}_median"), f(&|x| x.response.median));
    t.push(format!("{r}_q3"), f(&|x| x.response.q3));
    t.push(format!("{r}_max"), f(&|x| x.response.max));
    t.push(format!("{r}_ideal"), f(&|x| x.response.ideal));
    t.push("stress_mean", f(&|x| x.stress.mean));
    t.push("stress_sd", f(&|x| x.stress.sd));
    t.push("stress_mu_ln", f(&|x| x.stress.mu_ln));
    t.push("stress_sigma_ln", f(&|x| x.stress.sigma_ln));
    t.push("strength_mu_ln", f(&|_| s.strength.mu_ln));
    t.push("strength_sigma_ln", f(&|_| s.strength.sigma_ln));
    t.push("reliability_index", f(&|x| x.reliability_index));
    t.push("reliability", f(&|x| x.reliability));
    t.push("reliability_lo", f(&|x| x.reliability_lo));
    t.push("reliability_hi", f(&|x| x.reliability_hi));
    t.push("cn", f(&|x| x.cn));
    t.push("safety_factor", f(&|x| x.safety_factor));
    t.push("ad_stat", f(&|x| x.ad_stat));
    t.push("ad_p", f(&|x| x.ad_p));
    let d = s.options.damping.name;
    t.push(d, f(&|x| x.di));
    t.push(format!("{d}_ideal"), f(&|x| x.di_ideal));
    t.push(format!("{d}_sd"), f(&|x| x.di_sd));
    t.push("perfectibility", f(&|x| x.perfectibility));
    t.push("rank", Column::U64(p.iter().map(|x| x.rank).collect()));
    t.push("pareto", Column::Bool(p.iter().map(|x| x.pareto).collect()));
    t.push("robust", Column::Bool(p.iter().map(|x| x.robust).collect()));
    t.push(
        "class",
        Column::Str(p.iter().map(|x| x.class.label().to_string()).collect()),
    );
    t.push(
        "zone",
        Column::Str(p.iter().map(|x| s.zone_name(x).to_string()).collect()),
    );
    t
}

/// One row per zone: name, label, size, bounding box (`<axis>_from`, `<axis>_to`), the best
/// point and a representative one (`best_point`, `best_<axis>`, `rep_point`, `rep_<axis>`),
/// means and perfectibility.
pub fn zones_table(s: &Summary) -> Table {
    let z = &s.zones;
    let g = &s.grid;
    let mut t = Table::default();
    t.push(
        "zone",
        Column::Str(z.iter().map(|x| x.name.clone()).collect()),
    );
    t.push(
        "label",
        Column::Str(z.iter().map(|x| x.label().to_string()).collect()),
    );
    t.push(
        "declared",
        Column::Bool(z.iter().map(|x| x.declared()).collect()),
    );
    t.push(
        "n_points",
        Column::U64(z.iter().map(|x| Some(x.n_points as u64)).collect()),
    );
    t.push(
        "n_merged",
        Column::U64(z.iter().map(|x| Some(x.n_merged as u64)).collect()),
    );
    for a in 0..g.n_axes() {
        let c = axis_column(g.key(a));
        t.push(
            format!("{c}_from"),
            Column::F64(z.iter().map(|x| x.ranges[a].0).collect()),
        );
        t.push(
            format!("{c}_to"),
            Column::F64(z.iter().map(|x| x.ranges[a].1).collect()),
        );
    }
    for (prefix, which) in [("best", true), ("rep", false)] {
        let pick = |x: &super::Zone| if which { x.best } else { x.representative };
        t.push(
            format!("{prefix}_point"),
            Column::U64(z.iter().map(pick).collect()),
        );
        for a in 0..g.n_axes() {
            t.push(
                format!("{prefix}_{}", axis_column(g.key(a))),
                Column::F64(
                    z.iter()
                        .map(|x| pick(x).map_or(f64::NAN, |p| g.value(p, a)))
                        .collect(),
                ),
            );
        }
    }
    t.push(
        "mean_reliability",
        Column::F64(z.iter().map(|x| x.mean_r).collect()),
    );
    t.push(
        format!("mean_{}", s.options.damping.name),
        Column::F64(z.iter().map(|x| x.mean_di).collect()),
    );
    t.push(
        "perfectibility",
        Column::F64(z.iter().map(|x| x.perfectibility).collect()),
    );
    t
}

/// `ok:11 event_cap:1`-style text of outcome counts; with `failed_only`, only the non-ok ones
/// (empty when all are ok).
pub fn outcome_text<T: Copy + Into<u64>>(counts: &[T; 6], failed_only: bool) -> String {
    Outcome::ALL
        .iter()
        .zip(counts)
        .filter(|(o, c)| (**c).into() > 0 && !(failed_only && **o == Outcome::Ok))
        .map(|(o, c)| format!("{}:{}", o.name(), (*c).into()))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The unit of a quantity per unit of an axis, as a kink's size has it: `m/kg`, or `m` along
/// a dimensionless axis.
pub fn per_axis_unit(unit: &str, axis_unit: &str) -> String {
    if axis_unit.is_empty() || axis_unit == "1" || axis_unit == "–" {
        unit.to_string()
    } else {
        format!("{unit}/{axis_unit}")
    }
}

/// The name and unit of a jump's quantity.
pub fn quantity_of(s: &Summary, q: Quantity) -> (&'static str, &'static str) {
    match q {
        Quantity::Response => (s.options.response.name, s.options.response.unit),
        Quantity::Di => (s.options.damping.name, s.options.damping.unit),
    }
}

/// One row per located jump: axis (its column name), kind (`step` or `kink`), quantity
/// (`xmax` in m or `di` in m/s), `location` and `location_tol` along the axis, every axis
/// column (the jump's own holds its location, the others the line it was found on), `from` and
/// `to` (the grid values around its interval, [`crate::reduce::Jump::grid_span`]), `size` (a step's change of the quantity, a kink's
/// change of slope) and `size_unit`.
pub fn jumps_table(s: &Summary) -> Table {
    let j = &s.jumps;
    let g = &s.grid;
    let mut t = Table::default();
    t.push(
        "axis",
        Column::Str(j.iter().map(|x| axis_column(g.key(x.axis))).collect()),
    );
    t.push(
        "kind",
        Column::Str(j.iter().map(|x| x.kind.name().to_string()).collect()),
    );
    t.push(
        "quantity",
        Column::Str(
            j.iter()
                .map(|x| quantity_of(s, x.quantity).0.to_string())
                .collect(),
        ),
    );
    t.push(
        "location",
        Column::F64(j.iter().map(|x| x.location).collect()),
    );
    t.push(
        "location_tol",
        Column::F64(j.iter().map(|x| x.location_tol).collect()),
    );
    for a in 0..g.n_axes() {
        t.push(
            axis_column(g.key(a)),
            Column::F64(
                j.iter()
                    .map(|x| {
                        if x.axis == a {
                            x.location
                        } else {
                            g.value(x.below, a)
                        }
                    })
                    .collect(),
            ),
        );
    }
    let (from, to): (Vec<f64>, Vec<f64>) = j.iter().map(|x| x.grid_span(g)).unzip();
    t.push("from", Column::F64(from));
    t.push("to", Column::F64(to));
    t.push("size", Column::F64(j.iter().map(|x| x.size).collect()));
    t.push(
        "size_unit",
        Column::Str(
            j.iter()
                .map(|x| {
                    let unit = quantity_of(s, x.quantity).1;
                    match x.kind {
                        JumpKind::Step => unit.to_string(),
                        JumpKind::Kink => {
                            per_axis_unit(unit, crate::model::System::unit(g.key(x.axis)))
                        }
                    }
                })
                .collect(),
        ),
    );
    t
}

/// One row per quantity and axis: first-order and total-effect indices (model.md §9) and the
/// number of points they were computed over.
pub fn sensitivity_table(s: &Summary) -> Table {
    let v = &s.sensitivity;
    let mut t = Table::default();
    t.push(
        "quantity",
        Column::Str(v.iter().map(|x| x.quantity.clone()).collect()),
    );
    t.push(
        "axis",
        Column::Str(v.iter().map(|x| axis_column(s.grid.key(x.axis))).collect()),
    );
    t.push(
        "first_order",
        Column::F64(v.iter().map(|x| x.first_order).collect()),
    );
    t.push("total", Column::F64(v.iter().map(|x| x.total).collect()));
    t.push(
        "n_points",
        Column::U64(v.iter().map(|x| Some(x.n_points as u64)).collect()),
    );
    t
}
