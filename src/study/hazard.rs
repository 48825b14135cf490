//! `[hazard]`: the site's seismic hazard curve of a random or record study with an intensity
//! measure (docs/study.md, docs/scenes.md): a power law or a table, and the years of the
//! probability the report states.
//!
//! | key | unit | default | range |
//! |---|---|---|---|
//! | `k0`, `k` | per year at 1 g, 1 | | both `> 0` (with no `table`) |
//! | `table` | path | | a CSV with columns `im` (g) and `rate` (per year), relative to the study file (in a run directory, its copy `hazard.csv` when the path does not resolve there): at least two rows, `im > 0` strictly increasing, `rate > 0` strictly decreasing |
//! | `years` | years | 50 | `(0, 1e4]` |
//! | `source` | | none | where the curve comes from, for the report |

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::context::{Cx, num};
use crate::error::InputError;
use crate::stats::hazard::{Hazard, SiteHazard};

/// The run directory's copy of a hazard table.
pub const HAZARD_COPY: &str = "hazard.csv";

/// Default exposure of the probability of failure (years).
pub const DEFAULT_YEARS: f64 = 50.0;

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHazard {
    k0: Option<f64>,
    k: Option<f64>,
    table: Option<String>,
    years: Option<f64>,
    source: Option<String>,
}

/// The table's path as the study names it, resolved against the study's folder `dir`, or the
/// run directory's copy.
pub(super) fn table_path(dir: &Path, shown: &str) -> PathBuf {
    let path = dir.join(shown);
    if path.exists() {
        path
    } else {
        dir.join(HAZARD_COPY)
    }
}

/// Validates `[hazard]`; `dir` is the study file's folder.
pub(super) fn hazard(cx: &Cx, raw: &RawHazard, dir: &Path) -> Result<SiteHazard, InputError> {
    let curve = match (&raw.table, raw.k0, raw.k) {
        (Some(t), None, None) => table(cx, t, &table_path(dir, t))?,
        (Some(_), _, _) => {
            return Err(cx.err(
                "[hazard].table",
                cx.source("hazard", "table"),
                "give the hazard either as a table or as a power law (k0, k), not both",
            ));
        }
        (None, Some(k0), Some(k)) => {
            for (key, v) in [("k0", k0), ("k", k)] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(cx.err(
                        &format!("[hazard].{key}"),
                        num(v),
                        "the power law lambda(x) = k0 x^-k (x in g, per year) needs k0 > 0 and \
                         k > 0",
                    ));
                }
            }
            Hazard::Power { k0, k }
        }
        _ => {
            return Err(InputError::new(format!(
                "{}: [hazard]: needs a power law (k0 = annual rate at 1 g, k = its slope in \
                 log-log: lambda(x) = k0 x^-k) or table = \"hazard.csv\" (columns im in g, rate \
                 per year)",
                cx.file
            )));
        }
    };
    let years = raw.years.unwrap_or(DEFAULT_YEARS);
    if !(years.is_finite() && years > 0.0 && years <= 1e4) {
        return Err(cx.err(
            "[hazard].years",
            num(years),
            "the exposure (years) must be in (0, 10000]",
        ));
    }
    Ok(SiteHazard {
        curve,
        years,
        source: raw.source.clone(),
    })
}

/// Reads a hazard table: CSV with a header holding `im` and `rate`.
fn table(cx: &Cx, shown: &str, path: &Path) -> Result<Hazard, InputError> {
    let at = |detail: String| {
        InputError::new(format!(
            "{}: [hazard].table = {shown:?} ({}): {detail}",
            cx.file,
            path.display()
        ))
    };
    let text = std::fs::read_to_string(path).map_err(|e| at(format!("cannot read it: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(at(
            "empty; it needs a header `im,rate` and at least two rows".into(),
        ));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let col = |name: &str| names.iter().position(|n| *n == name);
    let (Some(ci), Some(cr)) = (col("im"), col("rate")) else {
        return Err(at(format!(
            "its header is {header:?}; it needs the columns im (g) and rate (per year)"
        )));
    };
    let (mut im, mut rate) = (Vec::new(), Vec::new());
    for (i, line) in lines {
        let row = i + 1;
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let cell = |c: usize, what: &str| -> Result<f64, InputError> {
            cells
                .get(c)
                .and_then(|s| s.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| at(format!("line {row}: {what} is not a number: {line:?}")))
        };
        let (x, r) = (cell(ci, "im")?, cell(cr, "rate")?);
        if x <= 0.0 {
            return Err(at(format!(
                "line {row}: im = {}; an intensity (g) must be > 0",
                num(x)
            )));
        }
        if r <= 0.0 {
            return Err(at(format!(
                "line {row}: rate = {}; an annual rate must be > 0",
                num(r)
            )));
        }
        if let (Some(&px), Some(&pr)) = (im.last(), rate.last()) {
            if x <= px {
                return Err(at(format!(
                    "line {row}: im = {} after {}; the intensities must increase strictly",
                    num(x),
                    num(px)
                )));
            }
            if r >= pr {
                return Err(at(format!(
                    "line {row}: rate = {} after {}; the rate of exceeding a larger intensity \
                     must be smaller (a hazard curve decreases strictly)",
                    num(r),
                    num(pr)
                )));
            }
        }
        im.push(x);
        rate.push(r);
    }
    if im.len() < 2 {
        return Err(at(format!(
            "{} row(s); a hazard table needs at least two",
            im.len()
        )));
    }
    Ok(Hazard::Table { im, rate })
}
