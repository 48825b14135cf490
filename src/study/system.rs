//! `[system]`: the base parameters (Table I defaults when absent), each within its range
//! ([`System::validate`]).

use serde::Deserialize;

use super::context::{Cx, num};
use crate::error::InputError;
use crate::model::{RangeError, SYSTEM_KEYS, System, UNIT_KEYS};

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

/// The validated `[system]`.
pub(super) fn system(cx: &Cx, raw: &RawSystem) -> Result<System, InputError> {
    let mut system = System::TABLE_I;
    for key in SYSTEM_KEYS.into_iter().chain(UNIT_KEYS) {
        if let Some(v) = raw.get(key) {
            check_key(key, v).map_err(|e| cx.err(&format!("[system].{key}"), num(v), e.allowed))?;
            system.set(key, v);
        }
    }
    Ok(system)
}
