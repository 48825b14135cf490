//! The summary, zone and jump tables as plain columns: the store writes them to Parquet and CSV
//! ([`crate::store::summary`]). No arrow here. Axis columns are named by
//! [`column_name`] (the data contract: `M` → `mass_main`, `m` → `mass_inner`).

use super::Summary;
use crate::sim::Outcome;
use crate::store::schema::column_name;

/// One column of a table.
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    F64(Vec<f64>),
    /// Nullable unsigned integers.
    U64(Vec<Option<u64>>),
    Bool(Vec<bool>),
    Str(Vec<String>),
}

impl Column {
    pub fn len(&self) -> usize {
        match self {
            Column::F64(v) => v.len(),
            Column::U64(v) => v.len(),
            Column::Bool(v) => v.len(),
            Column::Str(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Cell `i` as CSV text: shortest round-trip numbers, empty for NaN and null.
    pub fn cell(&self, i: usize) -> String {
        match self {
            Column::F64(v) if v[i].is_nan() => String::new(),
            Column::F64(v) => format!("{}", v[i]),
            Column::U64(v) => v[i].map(|x| x.to_string()).unwrap_or_default(),
            Column::Bool(v) => v[i].to_string(),
            Column::Str(v) => csv_quote(&v[i]),
        }
    }
}

fn csv_quote(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Named columns of equal length.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Table {
    pub columns: Vec<(String, Column)>,
}

impl Table {
    pub fn push(&mut self, name: impl Into<String>, col: Column) {
        self.columns.push((name.into(), col));
    }

    pub fn n_rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.1.len())
    }

    pub fn get(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.0 == name).map(|c| &c.1)
    }

    /// RFC 4180 CSV with a header line.
    pub fn to_csv(&self) -> String {
        let mut out = String::new();
        let names: Vec<&str> = self.columns.iter().map(|c| c.0.as_str()).collect();
        out.push_str(&names.join(","));
        out.push('\n');
        for i in 0..self.n_rows() {
            let row: Vec<String> = self.columns.iter().map(|c| c.1.cell(i)).collect();
            out.push_str(&row.join(","));
            out.push('\n');
        }
        out
    }
}

/// One row per design point. Units: SI (m, Pa, m/s); `perfectibility` in %.
pub fn summary_table(s: &Summary) -> Table {
    let p = &s.points;
    let f = |g: &dyn Fn(&super::PointStats) -> f64| Column::F64(p.iter().map(g).collect());
    let mut t = Table::default();
    t.push(
        "point",
        Column::U64(p.iter().map(|x| Some(x.point)).collect()),
    );
    for (a, (key, _)) in s.axes.iter().enumerate() {
        t.push(column_name(key), f(&|x| x.values[a]));
    }
    t.push(
        "n",
        Column::U64(p.iter().map(|x| Some(u64::from(x.n_ok))).collect()),
    );
    t.push(
        "n_cases",
        Column::U64(p.iter().map(|x| Some(u64::from(x.n_cases))).collect()),
    );
    t.push(
        "n_ok",
        Column::U64(p.iter().map(|x| Some(u64::from(x.n_ok))).collect()),
    );
    t.push("all_ok", Column::Bool(p.iter().map(|x| x.all_ok).collect()));
    t.push(
        "failed",
        Column::Str(p.iter().map(|x| outcome_text(&x.outcomes, true)).collect()),
    );
    t.push("xmax_mean", f(&|x| x.xmax_mean));
    t.push("xmax_sd", f(&|x| x.xmax_sd));
    t.push("xmax_min", f(&|x| x.xmax_min));
    t.push("xmax_median", f(&|x| x.xmax_median));
    t.push("xmax_max", f(&|x| x.xmax_max));
    t.push("xmax_ideal", f(&|x| x.xmax_ideal));
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
    t.push("di", f(&|x| x.di));
    t.push("perfectibility", f(&|x| x.perfectibility));
    t.push("rank", Column::U64(p.iter().map(|x| x.rank).collect()));
    t.push("pareto", Column::Bool(p.iter().map(|x| x.pareto).collect()));
    t.push(
        "zone",
        Column::Str(p.iter().map(|x| x.zone.clone()).collect()),
    );
    t
}

/// One row per zone; each axis gets `<column>_from` and `<column>_to`.
pub fn zones_table(s: &Summary) -> Table {
    let z = &s.zones;
    let mut t = Table::default();
    t.push(
        "zone",
        Column::Str(z.iter().map(|x| x.name.clone()).collect()),
    );
    t.push(
        "label",
        Column::Str(z.iter().map(|x| x.label.clone()).collect()),
    );
    t.push(
        "declared",
        Column::Bool(z.iter().map(|x| x.declared).collect()),
    );
    for (a, (key, _)) in s.axes.iter().enumerate() {
        t.push(
            format!("{}_from", column_name(key)),
            Column::F64(z.iter().map(|x| x.ranges[a].1).collect()),
        );
        t.push(
            format!("{}_to", column_name(key)),
            Column::F64(z.iter().map(|x| x.ranges[a].2).collect()),
        );
    }
    t.push(
        "n_points",
        Column::U64(z.iter().map(|x| Some(x.n_points as u64)).collect()),
    );
    t.push(
        "mean_reliability",
        Column::F64(z.iter().map(|x| x.mean_r).collect()),
    );
    t.push(
        "mean_di",
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

/// One row per jump: axis (its column name), kind (`step` or `kink`), where (`at`) and the values spanned,
/// quantity (`xmax` in m or `di` in m/s), the first (step) or second (kink) difference and its
/// robust z-score.
pub fn jumps_table(s: &Summary) -> Table {
    let j = &s.jumps;
    let mut t = Table::default();
    t.push(
        "axis",
        Column::Str(j.iter().map(|x| column_name(&x.axis).to_string()).collect()),
    );
    t.push(
        "kind",
        Column::Str(j.iter().map(|x| x.kind.to_string()).collect()),
    );
    t.push("at", Column::F64(j.iter().map(|x| x.at).collect()));
    t.push("from", Column::F64(j.iter().map(|x| x.from).collect()));
    t.push("to", Column::F64(j.iter().map(|x| x.to).collect()));
    t.push(
        "quantity",
        Column::Str(j.iter().map(|x| x.quantity.to_string()).collect()),
    );
    t.push("delta", Column::F64(j.iter().map(|x| x.delta).collect()));
    t.push("z", Column::F64(j.iter().map(|x| x.z).collect()));
    t
}
