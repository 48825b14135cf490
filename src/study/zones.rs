//! `[zones]`: the thresholds of automatic zone finding and zones declared by hand (read by the
//! reducer; docs/model.md §6).

use serde::Deserialize;

use super::axis::Axis;
use super::context::{Cx, num};
use crate::error::InputError;

/// `[zones]`: automatic zone finding and declared overrides.
#[derive(Clone, Debug, PartialEq)]
pub struct Zones {
    /// The lower end of R's bootstrap interval at or above which a point is "reliable".
    /// Default 0.98; in `[0, 1]`.
    pub r_min: f64,
    /// DI at or above which damping is "strong" (m/s); default: the median DI of the sweep.
    pub di_strong: Option<f64>,
    /// A region of fewer than this fraction of the design points merges into a neighbour.
    /// Default 0.02; in `[0, 0.5]` (0: no merging).
    pub min_zone: f64,
    /// A step is a change of the ideal case's quantity by at least this many times its typical
    /// spread across a point's cases (the median over the points of its SD). Default 1; `> 0`.
    pub step_spread: f64,
    /// A kink changes the slope of the ideal case's response by at least this many times its
    /// typical slope along the axis (the median `|slope|`). Default 1.5; `> 0`.
    pub kink_slope: f64,
    /// Jumps are located to this fraction of the grid step. Default 0.01; in `(0, 0.5]`.
    pub locate: f64,
    /// Zones declared in the study; when non-empty they replace the automatic ones.
    pub declared: Vec<DeclaredZone>,
}

/// A zone declared in the study: a name and a range of one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct DeclaredZone {
    pub name: String,
    pub axis: String,
    pub from: f64,
    pub to: f64,
}

impl Default for Zones {
    fn default() -> Self {
        Zones {
            r_min: 0.98,
            di_strong: None,
            min_zone: 0.02,
            step_spread: 1.0,
            kink_slope: 1.5,
            locate: 0.01,
            declared: Vec::new(),
        }
    }
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawZones {
    /// Replaced by `step_spread` and `kink_slope` (issue 10): read only to say so.
    jump_k: Option<f64>,
    r_min: Option<f64>,
    di_strong: Option<f64>,
    min_zone: Option<f64>,
    step_spread: Option<f64>,
    kink_slope: Option<f64>,
    locate: Option<f64>,
    #[serde(default)]
    zone: Vec<RawZone>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawZone {
    name: String,
    axis: String,
    from: f64,
    to: f64,
}

/// The validated `[zones]`; a declared zone must name a swept axis.
pub(super) fn zones(cx: &Cx, raw: &RawZones, axes: &[Axis]) -> Result<Zones, InputError> {
    let rz = raw;
    let mut zones = Zones::default();
    if let Some(k) = rz.jump_k {
        return Err(cx.err(
            "[zones].jump_k",
            num(k),
            "no longer a key: a jump is now decided in the quantity's own units; use step_spread \
             (steps, in spreads across a point's cases) and kink_slope (kinks, in typical slopes), \
             see docs/study.md",
        ));
    }
    let positive = |key: &str, v: Option<f64>, default: f64, unit: &str| match v {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => Err(cx.err(key, num(v), format!("must be a finite number > 0 ({unit})"))),
    };
    zones.step_spread = positive(
        "[zones].step_spread",
        rz.step_spread,
        zones.step_spread,
        "spreads across a point's cases",
    )?;
    zones.kink_slope = positive(
        "[zones].kink_slope",
        rz.kink_slope,
        zones.kink_slope,
        "typical slopes",
    )?;
    if let Some(v) = rz.min_zone {
        if !(0.0..=0.5).contains(&v) {
            return Err(cx.err(
                "[zones].min_zone",
                num(v),
                "a fraction of the design points in [0, 0.5]",
            ));
        }
        zones.min_zone = v;
    }
    if let Some(v) = rz.locate {
        if !(v > 0.0 && v <= 0.5) {
            return Err(cx.err(
                "[zones].locate",
                num(v),
                "a fraction of the grid step in (0, 0.5]",
            ));
        }
        zones.locate = v;
    }
    if let Some(r) = rz.r_min {
        if !(0.0..=1.0).contains(&r) {
            return Err(cx.err("[zones].r_min", num(r), "a reliability must be in [0, 1]"));
        }
        zones.r_min = r;
    }
    if let Some(di) = rz.di_strong {
        if !(di.is_finite() && di >= 0.0) {
            return Err(cx.err(
                "[zones].di_strong",
                num(di),
                "must be a finite number >= 0 (m/s)",
            ));
        }
        zones.di_strong = Some(di);
    }
    for i in 0..rz.zone.len() {
        zones.declared.push(declared(cx, &rz.zone, i, axes)?);
    }
    Ok(zones)
}

/// The validated declared zone `i` of `all`: a name unique among them, a swept axis, and a
/// range `from < to`.
fn declared(cx: &Cx, all: &[RawZone], i: usize, axes: &[Axis]) -> Result<DeclaredZone, InputError> {
    let z = &all[i];
    let at = format!("[zones].zone[{i}]");
    if z.name.trim().is_empty() || all[..i].iter().any(|o| o.name == z.name) {
        return Err(cx.err(
            &format!("{at}.name"),
            format!("{:?}", z.name),
            "a zone needs a non-empty name, unique in the study",
        ));
    }
    if !axes.iter().any(|a| a.key == z.axis) {
        let swept: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
        return Err(cx.err(
            &format!("{at}.axis"),
            format!("{:?}", z.axis),
            format!(
                "a zone is a range of a swept axis; swept: {}",
                if swept.is_empty() {
                    "none".to_string()
                } else {
                    swept.join(", ")
                }
            ),
        ));
    }
    if !(z.from.is_finite() && z.to.is_finite() && z.from < z.to) {
        return Err(cx.err(
            &format!("{at}.to"),
            num(z.to),
            format!("must be a finite number > from = {}", num(z.from)),
        ));
    }
    Ok(DeclaredZone {
        name: z.name.clone(),
        axis: z.axis.clone(),
        from: z.from,
        to: z.to,
    })
}
