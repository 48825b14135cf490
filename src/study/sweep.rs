//! `[sweep]`: the swept axes, in file order. An axis is a list of strictly increasing numbers,
//! `{start, stop, step}` or `{start, stop, num}`; its values are computed from an integer index,
//! never accumulated.

use std::collections::BTreeMap;

use super::axis::{Axis, RawAxis};
use super::context::{Cx, num};
use super::system::{self, RawSystem};
use crate::error::InputError;
use crate::model::{RangeError, SYSTEM_KEYS, UNIT_KEYS};
use crate::numeric::{linspace, round15};
use crate::sim::Harmonic;
use crate::sim::random::RandomScene;

/// The scene keys a study may sweep besides the system's, how one value of them is checked,
/// and whether the message for an unknown axis lists them.
pub(super) struct SceneAxes<'k> {
    pub keys: &'k [&'static str],
    pub check: fn(&str, f64) -> Result<(), RangeError>,
    pub listed: bool,
    /// Whether the scene takes several damper units, so that `units` and `d_spread` are axes.
    pub units: bool,
}

impl SceneAxes<'static> {
    /// A scene that sweeps no key of its own (free decay).
    pub(super) const NONE: SceneAxes<'static> = SceneAxes {
        keys: &[],
        check: no_scene_key,
        listed: false,
        units: true,
    };
}

/// The check of [`SceneAxes::NONE`], never reached: a key outside `keys` is refused first.
fn no_scene_key(key: &str, v: f64) -> Result<(), RangeError> {
    Err(RangeError::new(key, v, "not a key of this scene"))
}

/// Hard limit on the length of one axis (its values are held in memory: 80 MB at this size).
/// Not lifted by `allow_large`.
pub const MAX_AXIS_VALUES: u64 = 10_000_000;

/// The validated `[sweep]`: the axes in file order, each a system key or one of the scene's
/// sweepable keys `scene.keys` (a harmonic study's `F0`, `omega` or `r`, whose cross-checks
/// with `[scene]` are the harmonic parser's; a random study's load keys). A key is either fixed
/// in `[system]` or swept, not both.
pub(super) fn axes(
    cx: &Cx,
    raw: &BTreeMap<String, RawAxis>,
    system: &RawSystem,
    scene: &SceneAxes,
) -> Result<Vec<Axis>, InputError> {
    let mut keys: Vec<&String> = raw.keys().collect();
    keys.sort_by_key(|k| cx.key_pos("sweep", k));
    let mut axes = Vec::new();
    for key in keys {
        let at = format!("[sweep].{key}");
        let system_key = SYSTEM_KEYS.contains(&key.as_str())
            || (scene.units && UNIT_KEYS.contains(&key.as_str()));
        if !system_key && !scene.keys.contains(&key.as_str()) {
            let hint = if Harmonic::AXES.contains(&key.as_str()) {
                " (F0, omega and r are axes of the harmonic scene: [scene] kind = \"harmonic\")"
            } else if RandomScene::AXES.contains(&key.as_str()) {
                " (S0, omega_g, zeta_g, omega_f and zeta_f are axes of the random scene as its \
                 spectrum has them, scale of the record scene)"
            } else {
                ""
            };
            let mut allowed: Vec<&str> = SYSTEM_KEYS.to_vec();
            if scene.units {
                allowed.extend(UNIT_KEYS);
            }
            if scene.listed {
                allowed.extend(scene.keys);
            }
            return Err(cx.err(
                &at,
                cx.source("sweep", key),
                format!(
                    "unknown axis '{key}'; allowed: {}{hint}",
                    allowed.join(", ")
                ),
            ));
        }
        if let Some(v) = system.get(key) {
            return Err(cx.err(
                &format!("[system].{key}"),
                num(v),
                format!("{key} is also swept in [sweep]; a key is either fixed or swept, not both"),
            ));
        }
        let check = if system_key {
            system::check_key
        } else {
            scene.check
        };
        let values = axis_values(cx, key, &raw[key], check)?;
        axes.push(Axis {
            key: key.clone(),
            values,
        });
    }
    Ok(axes)
}

/// The values of one axis, each extreme checked by `check_key`.
fn axis_values(
    cx: &Cx,
    key: &str,
    raw: &RawAxis,
    check_key: fn(&str, f64) -> Result<(), RangeError>,
) -> Result<Vec<f64>, InputError> {
    let at = format!("[sweep].{key}");
    let values = match raw {
        RawAxis::List(list) => {
            if list.is_empty() {
                return Err(cx.err(&at, "[]", "an axis needs at least one value"));
            }
            for (i, &v) in list.iter().enumerate() {
                if !v.is_finite() {
                    return Err(cx.err(&format!("{at}[{i}]"), num(v), "must be a finite number"));
                }
                if i > 0 && v <= list[i - 1] {
                    return Err(cx.err(
                        &format!("{at}[{i}]"),
                        num(v),
                        format!(
                            "the values of an axis must be strictly increasing (previous value {})",
                            num(list[i - 1])
                        ),
                    ));
                }
            }
            list.clone()
        }
        RawAxis::Range(r) => {
            for (k, v) in [("start", r.start), ("stop", r.stop)] {
                if !v.is_finite() {
                    return Err(cx.err(&format!("{at}.{k}"), num(v), "must be a finite number"));
                }
            }
            if r.stop < r.start {
                return Err(cx.err(
                    &format!("{at}.stop"),
                    num(r.stop),
                    format!(
                        "the axis is reversed: stop must be >= start = {}",
                        num(r.start)
                    ),
                ));
            }
            match (r.step, r.num) {
                (Some(_), Some(_)) => {
                    return Err(cx.err(
                        &at,
                        cx.source("sweep", key),
                        "give either step or num, not both",
                    ));
                }
                (None, None) => {
                    return Err(cx.err(
                        &at,
                        cx.source("sweep", key),
                        "a range needs a step ({start, stop, step}) or a count ({start, stop, num})",
                    ));
                }
                (Some(step), None) => step_values(cx, &at, r.start, r.stop, step)?,
                (None, Some(n)) => linspace_values(cx, &at, r.start, r.stop, n)?,
            }
        }
    };
    // Only the extremes: every rule on a single key is a range.
    for v in [values[0], values[values.len() - 1]] {
        check_key(key, v).map_err(|e| cx.err(&at, num(v), e.allowed))?;
    }
    Ok(values)
}

/// `start, start + step, ..., stop`: the count is `round((stop - start) / step) + 1` and the
/// last value must land within `1e-9 * step` of `stop`.
fn step_values(
    cx: &Cx,
    at: &str,
    start: f64,
    stop: f64,
    step: f64,
) -> Result<Vec<f64>, InputError> {
    let at_step = format!("{at}.step");
    if !(step.is_finite() && step > 0.0) {
        return Err(cx.err(&at_step, num(step), "the step must be a finite number > 0"));
    }
    let q = (stop - start) / step;
    if q.is_nan() || q + 1.0 > MAX_AXIS_VALUES as f64 {
        return Err(cx.err(
            &at_step,
            num(step),
            format!("the axis would have more than {MAX_AXIS_VALUES} values"),
        ));
    }
    let n = q.round();
    let last = start + n * step;
    if (last - stop).abs() > 1e-9 * step {
        return Err(cx.err(
            &at_step,
            num(step),
            format!(
                "(stop - start) / step = {} is not a whole number; stop must be start + n * step",
                num(q)
            ),
        ));
    }
    let n = n as u64;
    let mut values: Vec<f64> = (0..=n).map(|i| round15(start + i as f64 * step)).collect();
    if let Some(l) = values.last_mut() {
        *l = stop;
    }
    if values.windows(2).any(|w| w[1] <= w[0]) {
        return Err(cx.err(
            &at_step,
            num(step),
            "the step is too small to give distinct values at this magnitude",
        ));
    }
    Ok(values)
}

/// `num` values from `start` to `stop` inclusive, endpoints exact.
fn linspace_values(
    cx: &Cx,
    at: &str,
    start: f64,
    stop: f64,
    n: u64,
) -> Result<Vec<f64>, InputError> {
    let at_num = format!("{at}.num");
    if n == 0 || n > MAX_AXIS_VALUES {
        return Err(cx.err(
            &at_num,
            n,
            format!("num must be a whole number in [1, {MAX_AXIS_VALUES}]"),
        ));
    }
    if n == 1 {
        if start != stop {
            return Err(cx.err(&at_num, n, "num = 1 needs start = stop"));
        }
        return Ok(vec![start]);
    }
    let values = linspace(start, stop, n);
    if values.windows(2).any(|w| w[1] <= w[0]) {
        return Err(cx.err(
            &at_num,
            n,
            "the values would not be distinct: start must be < stop and num not too large",
        ));
    }
    Ok(values)
}
