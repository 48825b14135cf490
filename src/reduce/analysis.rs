//! A harmonic study's per-design analysis, whole or in shards (docs/reduce.md, "The analysis in
//! shards").
//!
//! Two parts of `reduce` simulate: the periodic branches followed by continuation from each
//! design's stored attractors ([`super::orbits`]), and the probes that locate jumps between the
//! grid's designs ([`super::probe`]). The rest (statistics, zones, the ranking, the report) reads
//! the dataset only. `reduce --shard I/N` runs the cheap streaming reduction, then only its share
//! of the simulating work: the designs `d` with `d % N == I`, and the jump probes on the grid
//! lines whose key falls to shard `I` ([`Shard::owns_line`]); it writes what it computed into
//! `RUN_DIR/analysis/` ([`crate::store::analysis`]) and no report. A later `reduce` without
//! `--shard` finds a complete set of `N` shards written for this study, takes their branches and
//! probes instead of computing them, and writes every output: the same bits a `reduce` alone
//! writes, since each design's branches and each probe are deterministic and independent of
//! everything else. What no shard computed (an incomplete set) is computed there.

use std::collections::{BTreeMap, HashMap};

use super::table::{Column, Table};
use crate::orbits::response::{BranchRow, Response};
use crate::sim::noise::mix64;

/// Shard `index` of `count` of the analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    /// The designs a shard analyses: `design % count == index`.
    pub fn owns_design(&self, design: u64) -> bool {
        design % self.count.max(1) == self.index
    }

    /// The probes a shard computes: those whose grid line's key ([`line_key`]) falls to it. All
    /// probes of one line (a jump's bisection asks for several, and the bisections of the peak
    /// and of PR share their first midpoints) fall to one shard.
    pub fn owns_line(&self, key: u64) -> bool {
        mix64(key) % self.count.max(1) == self.index
    }
}

/// The key of the grid line a probe lies on: which axis is off the grid and the grid indices of
/// the others (not where along the line it is: the bisections of one line stay in one shard).
/// `grid` holds each design axis's values, `values` the probe's.
pub fn line_key(grid: &[Vec<f64>], values: &[f64]) -> u64 {
    let mut key = 0x5EED_u64;
    for (a, (axis, &v)) in grid.iter().zip(values).enumerate() {
        let part = match axis.iter().position(|&g| g == v) {
            Some(i) => i as u64,
            None => (1 << 40) | a as u64,
        };
        key = mix64(key ^ part);
    }
    key
}

/// Jump probes: the bits of a probe's design-axis values, and its `[peak amplitude, peak
/// reduction]` (`None`: the design is not valid or a run failed).
pub type Probes = Vec<(Vec<u64>, Option<[f64; 2]>)>;

/// What earlier shards computed, for the final reduction.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prior {
    /// Probe results by the bits of the probe's axis values.
    pub probes: HashMap<Vec<u64>, Option<[f64; 2]>>,
    /// Branch rows by design.
    pub branches: BTreeMap<u64, Vec<BranchRow>>,
    /// A complete set of shards: every design was analysed (one without a row has no branch).
    pub complete: bool,
}

impl Prior {
    /// The branches an earlier shard found for design `d`, if one analysed it.
    pub fn branches_of(&self, d: u64) -> Option<Vec<BranchRow>> {
        match self.branches.get(&d) {
            Some(b) => Some(b.clone()),
            None => self.complete.then(Vec::new),
        }
    }
}

/// How the analysis runs: whole (`shard: None`), or as one shard; with what earlier shards
/// computed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plan {
    pub shard: Option<Shard>,
    pub prior: Prior,
}

impl Plan {
    /// Whether this run analyses design `d` itself.
    pub fn computes_design(&self, d: u64) -> bool {
        self.prior.branches_of(d).is_none() && self.shard.is_none_or(|s| s.owns_design(d))
    }
}

/// The probes table of a shard: one row per probe, the design axes' values (columns named as
/// the axes), `ok` and the probe's `peak_amplitude` and `peak_reduction`.
pub fn probes_table(axes: &[String], probes: &[(Vec<u64>, Option<[f64; 2]>)]) -> Table {
    let mut t = Table::default();
    for (a, key) in axes.iter().enumerate() {
        t.push(
            super::table::axis_column(key),
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
    let f64s = |name: &str| match t.get(name)? {
        Column::F64(v) => Some(v),
        _ => None,
    };
    let cols: Vec<&Vec<f64>> = axes
        .iter()
        .map(|k| f64s(&super::table::axis_column(k)))
        .collect::<Option<_>>()?;
    let Column::Bool(ok) = t.get("ok")? else {
        return None;
    };
    let (peak, pr) = (f64s("peak_amplitude")?, f64s("peak_reduction")?);
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
    let mut t = super::orbits::branches_table(responses);
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
    let f = |name: &str| match t.get(name)? {
        Column::F64(v) => Some(v),
        _ => None,
    };
    let u = |name: &str| match t.get(name)? {
        Column::U64(v) => Some(v),
        _ => None,
    };
    let s = |name: &str| match t.get(name)? {
        Column::Str(v) => Some(v),
        _ => None,
    };
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
