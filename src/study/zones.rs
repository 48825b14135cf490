//! `[zones]`: the thresholds of automatic zone finding and zones declared by hand (read by the
//! reducer; docs/model.md §6).

use serde::Deserialize;

use super::sweep::Axis;
use super::{Cx, num};
use crate::error::InputError;

/// `[zones]`: automatic zone finding and declared overrides.
#[derive(Clone, Debug, PartialEq)]
pub struct Zones {
    /// Jump threshold: a first difference larger than `jump_k` robust standard deviations
    /// (MAD × 1.4826) of the first differences is a jump. Default 6.
    pub jump_k: f64,
    /// Reliability at or above which a point is "reliable". Default 0.98.
    pub r_min: f64,
    /// DI at or above which damping is "strong" (m/s); default: the median DI of the sweep.
    pub di_strong: Option<f64>,
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
            jump_k: 6.0,
            r_min: 0.98,
            di_strong: None,
            declared: Vec::new(),
        }
    }
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawZones {
    jump_k: Option<f64>,
    r_min: Option<f64>,
    di_strong: Option<f64>,
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
        if !(k.is_finite() && k > 0.0) {
            return Err(cx.err("[zones].jump_k", num(k), "must be a finite number > 0"));
        }
        zones.jump_k = k;
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
    for (i, z) in rz.zone.iter().enumerate() {
        let at = format!("[zones].zone[{i}]");
        if z.name.trim().is_empty() || rz.zone[..i].iter().any(|o| o.name == z.name) {
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
        zones.declared.push(DeclaredZone {
            name: z.name.clone(),
            axis: z.axis.clone(),
            from: z.from,
            to: z.to,
        });
    }
    Ok(zones)
}
