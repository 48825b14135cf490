//! `[system]`: the base parameters (Table I defaults when absent), each within its range
//! ([`System::validate`]), and its per-unit tables `[[system.unit]]` (model.md §14).

use serde::Deserialize;

use super::axis::Axis;
use super::context::{Cx, num, range_value};
use super::perturb::Case;
use crate::error::InputError;
use crate::model::{MAX_UNITS, RangeError, SYSTEM_KEYS, System, UNIT_KEYS, Unit};

/// The keys a table of units decides: refused in `[system]` and `[sweep]` beside it.
const TABLE_KEYS: [&str; 5] = ["m", "d", "e", "units", "d_spread"];

/// One `[[system.unit]]` as written.
#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawUnit {
    m: Option<f64>,
    d: Option<f64>,
    e: Option<f64>,
    y0: Option<f64>,
    w0: Option<f64>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub(super) struct RawSystem {
    M: Option<f64>,
    m: Option<f64>,
    K: Option<f64>,
    C: Option<f64>,
    d: Option<f64>,
    e: Option<f64>,
    x0: Option<f64>,
    v0: Option<f64>,
    y0: Option<f64>,
    w0: Option<f64>,
    units: Option<f64>,
    d_spread: Option<f64>,
    /// `[[system.unit]]`: the per-unit tables.
    unit: Option<Vec<RawUnit>>,
}

impl RawSystem {
    pub(super) fn get(&self, key: &str) -> Option<f64> {
        match key {
            "M" => self.M,
            "m" => self.m,
            "K" => self.K,
            "C" => self.C,
            "d" => self.d,
            "e" => self.e,
            "x0" => self.x0,
            "v0" => self.v0,
            "y0" => self.y0,
            "w0" => self.w0,
            "units" => self.units,
            "d_spread" => self.d_spread,
            _ => None,
        }
    }
}

/// Checks one system key's own range (not the `y0 - x0` constraint, checked separately).
pub(super) fn check_key(key: &str, v: f64) -> Result<(), RangeError> {
    let mut s = System::TABLE_I;
    s.set(key, v);
    if key == "x0" || key == "y0" {
        s.x0 = v;
        s.y0 = v;
    }
    s.validate()
}

/// The validated `[system]` on Table I's defaults.
pub(super) fn system(cx: &Cx, raw: &RawSystem) -> Result<System, InputError> {
    system_on(cx, raw, System::TABLE_I)
}

/// The validated `[system]` on the defaults `base`, with its `[[system.unit]]` tables (each
/// unit's `y0`, `w0` default to the system's).
pub(super) fn system_on(cx: &Cx, raw: &RawSystem, base: System) -> Result<System, InputError> {
    let mut system = base;
    for key in SYSTEM_KEYS.into_iter().chain(UNIT_KEYS) {
        if let Some(v) = raw.get(key) {
            check_key(key, v).map_err(|e| cx.err(&format!("[system].{key}"), num(v), e.allowed))?;
            system.set(key, v);
        }
    }
    let Some(raw_units) = &raw.unit else {
        return Ok(system);
    };
    if let Some((key, v)) = TABLE_KEYS.iter().find_map(|k| raw.get(k).map(|v| (*k, v))) {
        return Err(cx.err(
            &format!("[system].{key}"),
            num(v),
            format!(
                "{key} is decided by the [[system.unit]] tables (model.md §14): give each \
                 unit's m, d and e there; m, d, e, units and d_spread cannot be set beside them"
            ),
        ));
    }
    if raw_units.is_empty() || raw_units.len() as f64 > MAX_UNITS {
        return Err(cx.err(
            "[system].unit",
            format!("{} tables", raw_units.len()),
            "give 1 to 64 [[system.unit]] tables, one per damper unit",
        ));
    }
    let units = raw_units
        .iter()
        .enumerate()
        .map(|(i, u)| unit(cx, i, u, &system))
        .collect::<Result<Vec<Unit>, InputError>>()?;
    Ok(system.with_units(&units))
}

/// Unit `i` of `[[system.unit]]`, its start defaulting to the system's, checked alone
/// ([`System::check_unit`]).
fn unit(cx: &Cx, i: usize, raw: &RawUnit, system: &System) -> Result<Unit, InputError> {
    let need = |key: &str, v: Option<f64>| {
        v.ok_or_else(|| {
            InputError::new(format!(
                "{}: [system].unit[{i}].{key}: missing; every unit needs its own m, d and e \
                 (y0 and w0 default to the system's)",
                cx.file
            ))
        })
    };
    let u = Unit {
        m: need("m", raw.m)?,
        d: need("d", raw.d)?,
        e: need("e", raw.e)?,
        y0: raw.y0.unwrap_or(system.y0),
        w0: raw.w0.unwrap_or(system.w0),
    };
    System::check_unit(i, &u, system.x0)
        .map_err(|e| cx.err(&format!("[system].{}", e.key), range_value(&e), e.allowed))?;
    Ok(u)
}

/// The rules between `[[system.unit]]` and the rest of a study (model.md §14), once its axes
/// and cases are known: no axis over a key the tables decide or over the units' start (`y0`,
/// `w0`), every unit inside its cavity at both ends of an `x0` axis, and no perturbed `m` or
/// `d` (they are the plain system's). The same rules for a single table, though it is the
/// plain system: a study's tables fix their units, whatever their number.
pub(super) fn check_tables(
    cx: &Cx,
    raw: &RawSystem,
    system: &System,
    axes: &[Axis],
    cases: &[Case],
) -> Result<(), InputError> {
    if raw.unit.is_none() {
        return Ok(());
    }
    let units = system.unit_list();
    for axis in axes {
        let key = axis.key.as_str();
        if TABLE_KEYS.contains(&key) || key == "y0" || key == "w0" {
            return Err(cx.err(
                &format!("[sweep].{key}"),
                cx.source("sweep", key),
                format!(
                    "{key} is fixed by the [[system.unit]] tables (model.md §14); a study with \
                     unit tables sweeps none of m, d, e, y0, w0, units, d_spread"
                ),
            ));
        }
        if key == "x0" {
            for x0 in [axis.values[0], axis.values[axis.values.len() - 1]] {
                for (i, u) in units.iter().enumerate() {
                    System::check_unit(i, u, x0).map_err(|e| {
                        cx.err("[sweep].x0", num(x0), format!("{}: {}", e.key, e.allowed))
                    })?;
                }
            }
        }
    }
    if let Some(case) = cases.iter().find(|c| c.dm != 0.0 || c.dd != 0.0) {
        let (key, v) = if case.dm != 0.0 {
            ("dm", case.dm)
        } else {
            ("dd", case.dd)
        };
        return Err(cx.err(
            &format!("[perturb].{key}"),
            num(v),
            "perturbed m and d belong to the plain system; with [[system.unit]] tables each \
             unit's m and d are its own (perturb them by listing the tables again)",
        ));
    }
    Ok(())
}
