//! `[perturb]`: the cases run at every design point (the ideal case first), as explicit cases
//! or as the factorial product of `dm`, `dd` and `noise_seeds`; cross-checked against every
//! design point's extremes (the inner mass starts inside the cavity, `m + dm >= 0`, `d + dd > 0`).

use serde::Deserialize;

use super::axis::{Axis, extent};
use super::context::{Cx, num};
use crate::error::InputError;
use crate::model::System;
use crate::sim::NoiseSettings;

/// One perturbation/noise case of a design point (model.md §4, the paper's Table II).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// Change of the inner mass `m` (kg).
    pub dm: f64,
    /// Change of the clearance `d` (m).
    pub dd: f64,
    /// Noise seed; `None` means no noise for this case.
    pub noise_seed: Option<u64>,
    /// The unperturbed, noise-free case.
    pub ideal: bool,
}

impl Case {
    /// The unperturbed, noise-free case (always `cases[0]`).
    pub const IDEAL: Case = Case {
        dm: 0.0,
        dd: 0.0,
        noise_seed: None,
        ideal: true,
    };
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPerturb {
    cases: Option<Vec<RawCase>>,
    dm: Option<Vec<f64>>,
    dd: Option<Vec<f64>>,
    noise_seeds: Option<Vec<u64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCase {
    #[serde(default)]
    dm: f64,
    #[serde(default)]
    dd: f64,
    noise_seed: Option<u64>,
}

/// A case and where it came from (for messages).
struct SourcedCase {
    case: Case,
    dm_at: String,
    dd_at: String,
    seed_at: String,
}

fn perturb_cases(cx: &Cx, raw: Option<&RawPerturb>) -> Result<Vec<SourcedCase>, InputError> {
    let mut out = vec![SourcedCase {
        case: Case::IDEAL,
        dm_at: String::new(),
        dd_at: String::new(),
        seed_at: String::new(),
    }];
    let Some(p) = raw else { return Ok(out) };
    let factorial = p.dm.is_some() || p.dd.is_some() || p.noise_seeds.is_some();
    let mut rows = Vec::new();
    if let Some(cases) = &p.cases {
        if factorial {
            let k = if p.dm.is_some() {
                "dm"
            } else if p.dd.is_some() {
                "dd"
            } else {
                "noise_seeds"
            };
            return Err(cx.err(
                &format!("[perturb].{k}"),
                cx.source("perturb", k),
                "give either explicit cases or the factorial lists dm, dd, noise_seeds, not both",
            ));
        }
        for (i, c) in cases.iter().enumerate() {
            let at = format!("[perturb].cases[{i}]");
            rows.push(SourcedCase {
                case: Case {
                    dm: c.dm,
                    dd: c.dd,
                    noise_seed: c.noise_seed,
                    ideal: false,
                },
                dm_at: format!("{at}.dm"),
                dd_at: format!("{at}.dd"),
                seed_at: format!("{at}.noise_seed"),
            });
        }
    } else if factorial {
        for (k, empty) in [
            ("dm", p.dm.as_ref().is_some_and(Vec::is_empty)),
            ("dd", p.dd.as_ref().is_some_and(Vec::is_empty)),
            (
                "noise_seeds",
                p.noise_seeds.as_ref().is_some_and(Vec::is_empty),
            ),
        ] {
            if empty {
                return Err(cx.err(
                    &format!("[perturb].{k}"),
                    "[]",
                    "an empty list gives no cases; leave the key out to mean no change",
                ));
            }
        }
        let dms = p.dm.clone().unwrap_or_else(|| vec![0.0]);
        let dds = p.dd.clone().unwrap_or_else(|| vec![0.0]);
        let seeds: Vec<Option<u64>> = match &p.noise_seeds {
            Some(s) => s.iter().map(|&x| Some(x)).collect(),
            None => vec![None],
        };
        for &dm in &dms {
            for &dd in &dds {
                for &seed in &seeds {
                    rows.push(SourcedCase {
                        case: Case {
                            dm,
                            dd,
                            noise_seed: seed,
                            ideal: false,
                        },
                        dm_at: "[perturb].dm".into(),
                        dd_at: "[perturb].dd".into(),
                        seed_at: "[perturb].noise_seeds".into(),
                    });
                }
            }
        }
    }
    for row in rows {
        let c = row.case;
        for (v, at) in [(c.dm, &row.dm_at), (c.dd, &row.dd_at)] {
            if !v.is_finite() {
                return Err(cx.err(at, num(v), "must be a finite number"));
            }
        }
        if c.dm == 0.0 && c.dd == 0.0 && c.noise_seed.is_none() {
            continue; // the ideal case, already cases[0]
        }
        out.push(row);
    }
    Ok(out)
}

/// The validated cases: `cases[0]` is the ideal case.
pub(super) fn cases(
    cx: &Cx,
    raw: Option<&RawPerturb>,
    axes: &[Axis],
    system: &System,
    noise: Option<&NoiseSettings>,
) -> Result<Vec<Case>, InputError> {
    let sourced = perturb_cases(cx, raw)?;
    let (m_lo, _, m_at) = extent(axes, system, "m");
    let (d_lo, _, d_at) = extent(axes, system, "d");
    let (x_lo, x_hi, _) = extent(axes, system, "x0");
    let (y_lo, y_hi, y_at) = extent(axes, system, "y0");
    let (gap, y_worst) = if (y_hi - x_lo).abs() >= (y_lo - x_hi).abs() {
        ((y_hi - x_lo).abs(), y_hi)
    } else {
        ((y_lo - x_hi).abs(), y_lo)
    };
    // With several units the smallest cavity is the first unit's, d (1 - d_spread).
    let (_, n_hi, _) = extent(axes, system, "units");
    let (_, s_hi, s_at) = extent(axes, system, "d_spread");
    let (d_min, spread) = if n_hi > 1.0 && s_hi > 0.0 {
        (
            d_lo * (1.0 - s_hi),
            format!(" x (1 - d_spread), d_spread up to {} ({s_at})", num(s_hi)),
        )
    } else {
        (d_lo, String::new())
    };
    if gap > 0.5 * d_min {
        return Err(cx.err(
            &y_at,
            num(y_worst),
            format!(
                "the inner mass must start inside the cavity: |y0 - x0| reaches {}, more than \
                 d/2 = {} ({d_at}{spread})",
                num(gap),
                num(0.5 * d_min)
            ),
        ));
    }
    for row in &sourced[1..] {
        let c = row.case;
        if let Some(seed) = c.noise_seed
            && noise.is_none()
        {
            return Err(cx.err(
                &row.seed_at,
                seed,
                "a noise seed needs a [noise] table (power, sample_time)",
            ));
        }
        if m_lo + c.dm < 0.0 {
            return Err(cx.err(
                &row.dm_at,
                num(c.dm),
                format!(
                    "m + dm must be >= 0 at every design point; the smallest m is {} kg ({m_at})",
                    num(m_lo)
                ),
            ));
        }
        if d_lo + c.dd <= 0.0 || (d_lo + c.dd).is_nan() {
            return Err(cx.err(
                &row.dd_at,
                num(c.dd),
                format!(
                    "d + dd must be > 0 at every design point; the smallest d is {} m ({d_at})",
                    num(d_lo)
                ),
            ));
        }
        if gap > 0.5 * (d_lo + c.dd) {
            return Err(cx.err(
                &row.dd_at,
                num(c.dd),
                format!(
                    "the inner mass must start inside the perturbed cavity: |y0 - x0| reaches {}, \
                     more than (d + dd)/2 = {}",
                    num(gap),
                    num(0.5 * (d_lo + c.dd))
                ),
            ));
        }
    }
    Ok(sourced.into_iter().map(|s| s.case).collect())
}
