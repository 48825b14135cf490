//! What a shard of a harmonic study's analysis stores in `RUN_DIR/analysis/`
//! ([`crate::store::analysis`]) and the final `reduce` reads back ([`super::analysis`] has how
//! the analysis is split): its jump probes ([`probes_table`]), its designs' branches with each
//! row's section ([`branches_part`]) and its share of the verification's direct measurements
//! ([`verification_part`]).

use std::collections::{BTreeMap, HashMap};

use super::steady::branches_table;
use super::verify::{Measured, Verification, Verified};
use crate::orbits::life::LifeSummary;
use crate::orbits::response::{BranchRow, Response};
use crate::stats::extremes::LifeEstimate;
use crate::store::table::{Column, Table};

/// The probes table of a shard: one row per probe, the design axes' values (columns named as
/// the axes), `ok` and the probe's `peak_amplitude` and `peak_reduction`.
pub fn probes_table(axes: &[String], probes: &[(Vec<u64>, Option<[f64; 2]>)]) -> Table {
    let mut t = Table::default();
    for (a, key) in axes.iter().enumerate() {
        t.push(
            crate::store::table::axis_column(key),
            Column::F64(probes.iter().map(|p| f64::from_bits(p.0[a])).collect()),
        );
    }
    t.push(
        "ok",
        Column::Bool(probes.iter().map(|p| p.1.is_some()).collect()),
    );
    for (k, name) in ["peak_amplitude", "peak_reduction"].iter().enumerate() {
        t.push(
            *name,
            Column::F64(
                probes
                    .iter()
                    .map(|p| p.1.map_or(f64::NAN, |v| v[k]))
                    .collect(),
            ),
        );
    }
    t
}

/// [`probes_table`] read back; `None` when a column is missing.
pub fn probes_from_table(
    axes: &[String],
    t: &Table,
) -> Option<HashMap<Vec<u64>, Option<[f64; 2]>>> {
    let cols: Vec<&Vec<f64>> = axes
        .iter()
        .map(|k| f64s(t, &crate::store::table::axis_column(k)))
        .collect::<Option<_>>()?;
    let Column::Bool(ok) = t.get("ok")? else {
        return None;
    };
    let (peak, pr) = (f64s(t, "peak_amplitude")?, f64s(t, "peak_reduction")?);
    Some(
        (0..t.n_rows())
            .map(|i| {
                let key = cols.iter().map(|c| c[i].to_bits()).collect();
                (key, ok[i].then_some([peak[i], pr[i]]))
            })
            .collect(),
    )
}

/// The branches of `responses` as a shard stores them: the `branches` table's columns and each
/// row's section (`section_x`, `section_v`, `section_z`, `section_w`).
pub fn branches_part(responses: &[Response]) -> Table {
    let mut t = branches_table(responses);
    let rows: Vec<&BranchRow> = responses.iter().flat_map(|r| &r.branches).collect();
    for (k, name) in ["section_x", "section_v", "section_z", "section_w"]
        .iter()
        .enumerate()
    {
        t.push(*name, Column::F64(rows.iter().map(|b| b.s[k]).collect()));
    }
    t
}

/// [`branches_part`] read back, by design; `None` when a column is missing or of another type.
pub fn branches_from_part(t: &Table) -> Option<BTreeMap<u64, Vec<BranchRow>>> {
    let (f, u, s) = (
        |n: &str| f64s(t, n),
        |n: &str| u64s(t, n),
        |n: &str| strs(t, n),
    );
    let Column::Bool(stable) = t.get("stable")? else {
        return None;
    };
    let (point, branch, period) = (u("point")?, u("branch")?, u("period")?);
    let (r, omega, f0, amp) = (f("r")?, f("omega")?, f("F0")?, f("amplitude")?);
    let (ipp, mu) = (f("impacts_per_period")?, f("multiplier_max")?);
    let (stability, label, end) = (s("stability")?, s("label")?, s("end")?);
    let sec = [
        f("section_x")?,
        f("section_v")?,
        f("section_z")?,
        f("section_w")?,
    ];
    // The multipliers and the grazing speed (absent from parts of older versions: NaN).
    let nan = vec![f64::NAN; t.n_rows()];
    let g = |name: &str| f(name).unwrap_or(&nan);
    let mus: Vec<[&Vec<f64>; 2]> = (1..=4)
        .map(|k| [g(&format!("mu{k}_re")), g(&format!("mu{k}_im"))])
        .collect();
    let graze = g("min_impact_speed");
    // Where a branch ends at a grazing, what follows (absent from parts of older versions).
    let outcome = s("grazing_outcome");
    let located = match t.get("located") {
        Some(Column::Bool(v)) => v.clone(),
        _ => vec![false; t.n_rows()],
    };
    let mut out: BTreeMap<u64, Vec<BranchRow>> = BTreeMap::new();
    for i in 0..t.n_rows() {
        let design = point[i]?;
        out.entry(design).or_default().push(BranchRow {
            design,
            branch: branch[i]? as u32,
            r: r[i],
            omega: omega[i],
            F0: f0[i],
            amplitude: amp[i],
            period: period[i]? as u32,
            impacts_per_period: ipp[i],
            stable: stable[i],
            stability: intern(&stability[i]),
            multiplier_max: mu[i],
            multipliers: std::array::from_fn(|k| (mus[k][0][i], mus[k][1][i])),
            min_impact_speed: graze[i],
            label: intern(&label[i]),
            located: located[i],
            end: intern(&end[i]),
            grazing_outcome: outcome.map_or("", |o| intern(&o[i])),
            s: [sec[0][i], sec[1][i], sec[2][i], sec[3][i]],
        });
    }
    Some(out)
}

/// The `'static` name a stored label, end or stability was written from: the branch rows carry
/// them as `&'static str`. Each distinct name read back is kept once for the process.
fn intern(s: &str) -> &'static str {
    use std::sync::Mutex;
    static NAMES: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
    let Ok(mut names) = NAMES.lock() else {
        return "";
    };
    if let Some(n) = names.iter().find(|n| **n == s) {
        return n;
    }
    let n: &'static str = Box::leak(s.to_string().into_boxed_str());
    names.push(n);
    n
}

/// The columns a shard's verification part adds to the `verification` table's: the rest of each
/// direct measurement's [`LifeSummary`] (its tail law and whether it was capped or fitted), so
/// the final reduction rebuilds it bit for bit.
const DIRECT_EXTRA: [&str; 6] = [
    "direct_threshold",
    "direct_sigma",
    "direct_xi",
    "direct_xi_se",
    "direct_end_point",
    "direct_lowest_threshold",
];

/// The verification a shard made, as it stores it (`analysis/verification-I-of-N.parquet`): the
/// `verification` table's columns (no rank after: a shard ranks nothing) and [`DIRECT_EXTRA`],
/// `direct_exceedances`, `direct_fit_periods`, `direct_capped` and `direct_fitted`.
pub fn verification_part(v: &Verification) -> Table {
    let mut t = super::verify::table(v, |_| None);
    let rows: Vec<&Verified> = v.peaks.iter().flat_map(|p| &p.verified).collect();
    let fit = |m: &Verified| m.direct.and_then(|d| d.estimate);
    let extra: [fn(&LifeEstimate) -> f64; 6] = [
        |e| e.threshold,
        |e| e.sigma,
        |e| e.xi,
        |e| e.xi_se,
        |e| e.end_point,
        |e| e.lowest_threshold,
    ];
    for (name, get) in DIRECT_EXTRA.iter().zip(extra) {
        t.push(
            *name,
            Column::F64(
                rows.iter()
                    .map(|m| fit(m).map_or(f64::NAN, |e| get(&e)))
                    .collect(),
            ),
        );
    }
    t.push(
        "direct_exceedances",
        Column::U64(rows.iter().map(|m| fit(m).map(|e| e.exceedances)).collect()),
    );
    t.push(
        "direct_fit_periods",
        Column::U64(rows.iter().map(|m| fit(m).map(|e| e.measured)).collect()),
    );
    t.push(
        "direct_capped",
        Column::Bool(
            rows.iter()
                .map(|m| m.direct.is_some_and(|d| d.capped))
                .collect(),
        ),
    );
    t.push(
        "direct_fitted",
        Column::Bool(rows.iter().map(|m| fit(m).is_some()).collect()),
    );
    t
}

/// [`verification_part`] read back: the direct measurements of the motions the shard measured
/// (not those taken as raced), by motion; `None` when a column is missing or of another type.
pub fn verification_from_part(t: &Table) -> Option<Measured> {
    let (f, u, b) = (
        |n: &str| f64s(t, n),
        |n: &str| u64s(t, n),
        |n: &str| bools(t, n),
    );
    let (point, case, periods) = (u("point")?, u("case")?, u("direct_periods")?);
    let (exceed, fit_periods) = (u("direct_exceedances")?, u("direct_fit_periods")?);
    let (again, capped, fitted) = (
        b("measured_again")?,
        b("direct_capped")?,
        b("direct_fitted")?,
    );
    let (r, estimate, largest) = (f("r")?, f("estimate")?, f("largest_seen")?);
    let (amp, lo, hi) = (f("direct")?, f("direct_lo")?, f("direct_hi")?);
    let extra: Vec<&Vec<f64>> = DIRECT_EXTRA.iter().map(|n| f(n)).collect::<Option<_>>()?;
    let mut out = Measured::new();
    for i in 0..t.n_rows() {
        if !again[i] {
            continue;
        }
        let key = (
            point[i]?,
            u32::try_from(case[i]?).ok()?,
            r[i].to_bits(),
            estimate[i].to_bits(),
        );
        let direct = periods[i].map(|measured| LifeSummary {
            estimate: fitted[i].then(|| LifeEstimate {
                amplitude: amp[i],
                lo: lo[i],
                hi: hi[i],
                threshold: extra[0][i],
                sigma: extra[1][i],
                xi: extra[2][i],
                xi_se: extra[3][i],
                end_point: extra[4][i],
                exceedances: exceed[i].unwrap_or(0),
                measured: fit_periods[i].unwrap_or(0),
                lowest_threshold: extra[5][i],
            }),
            measured,
            capped: capped[i],
            window_max: largest[i],
        });
        out.insert(key, direct);
    }
    Some(out)
}

/// Column `name` of `t` as floats; `None` when missing or of another type.
fn f64s<'a>(t: &'a Table, name: &str) -> Option<&'a Vec<f64>> {
    match t.get(name)? {
        Column::F64(v) => Some(v),
        _ => None,
    }
}

/// Column `name` of `t` as nullable unsigned integers.
fn u64s<'a>(t: &'a Table, name: &str) -> Option<&'a Vec<Option<u64>>> {
    match t.get(name)? {
        Column::U64(v) => Some(v),
        _ => None,
    }
}

/// Column `name` of `t` as strings.
fn strs<'a>(t: &'a Table, name: &str) -> Option<&'a Vec<String>> {
    match t.get(name)? {
        Column::Str(v) => Some(v),
        _ => None,
    }
}

/// Column `name` of `t` as booleans.
fn bools<'a>(t: &'a Table, name: &str) -> Option<&'a Vec<bool>> {
    match t.get(name)? {
        Column::Bool(v) => Some(v),
        _ => None,
    }
}
