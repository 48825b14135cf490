//! Zones found from the data (model.md §6), or declared in the study.
//!
//! 1. **Jumps.** Along each swept axis (every line of the grid along that axis, pooled), for
//!    `xmax` and for `DI`:
//!    * a **step** between neighbours `i`, `i+1`: the first difference `Δ_i` is an outlier,
//!      `|Δ_i - median(Δ)| / (1.4826 MAD(Δ)) > jump_k` (`[zones].jump_k`, default 6);
//!    * a **kink** at `i` (the curve turns abruptly, as the first peak does near e = 0.74,
//!      model.md §7): the second difference `Δ²_i = Δ_i - Δ_{i-1}` is an outlier by the same
//!      rule *and* the slope changes by more than [`KINK_STEPS`] typical steps,
//!      `|Δ²_i - median(Δ²)| > KINK_STEPS · median(|Δ|)`. The second condition keeps the gentle
//!      curvature of very smooth data (whose MAD is tiny) from counting as a kink. A step makes
//!      two outlying second differences, one either side; those are not kinks.
//!
//!    1.4826 MAD estimates the SD of normal differences; a smooth curve has differences that
//!    drift slowly, so they stay within a few MADs of their median, while a jump stands out
//!    however large the smooth drift is. The scale is floored at `1e-3 median(|Δ|)` so that
//!    exactly linear data (MAD = 0) does not turn rounding into jumps. `xmax` is the ideal
//!    case's (noise-free, unperturbed: the design's own behaviour, which noise would blur) when
//!    every point has one, else the mean over the cases; DI is the point's DI.
//! 2. **Labels.** Every design point gets one label:
//!    * `unreliable around a jump` — it is on either side of a step, or at a kink or next to
//!      it: a small error in the design variable changes the behaviour abruptly (the paper's
//!      zone II);
//!    * `strong damping, reliable` — `R >= r_min` and `DI >= di_strong` (the paper's zone I);
//!    * `reliable, weak damping` — `R >= r_min`, `DI < di_strong` (zone III);
//!    * `unreliable, strong damping` / `unreliable, weak damping` — `R < r_min`;
//!    * `no data` — R or DI unknown (no ok run, or no ok ideal run).
//!
//!    `r_min` is `[zones].r_min` (default 0.98), `di_strong` is `[zones].di_strong` (default: the
//!    median DI of the sweep, so "strong" means "better than half of the designs").
//! 3. **Zones.** With one swept axis, contiguous runs of one label are the zones, named I, II,
//!    … along the axis; a run shorter than [`MIN_ZONE_POINTS`] points that is neither around a
//!    jump nor without data is merged into its longer neighbour (one stray point does not make
//!    a zone; a failed one stays visible). With two or
//!    more axes, the points of one label form one region of the map (its ranges are the
//!    bounding box). Each zone gets its mean R, mean DI and the perfectibility of eq. 11 applied
//!    to those means, normalised by the best zone means (as in the paper's Table III).
//! 4. **Declared zones** (`[zones].declared`) replace steps 2–3: a point belongs to the first
//!    declared zone whose range on its axis holds the point's value. Jumps are still reported.

use super::PointStats;
use super::stats::{mad, median, perfectibility};
use crate::study::{Ranking, Zones};

/// Zones shorter than this (in design points, along one axis) are merged into a neighbour
/// unless they sit around a jump.
pub const MIN_ZONE_POINTS: usize = 3;

/// A kink must change the slope by more than this many typical steps (`median |Δ|`). A
/// symmetric V (slopes +s, -s) changes it by 2 typical steps and is a kink; the gentle bends of
/// the paper study's first peak (e = 0.51, 0.92) change it by about 1 and are not, its turns at
/// e = 0.74 and 0.80 by about 4.6 and are.
pub const KINK_STEPS: f64 = 1.5;

pub const LABEL_JUMP: &str = "unreliable around a jump";
pub const LABEL_STRONG: &str = "strong damping, reliable";
pub const LABEL_WEAK: &str = "reliable, weak damping";
pub const LABEL_UNREL_STRONG: &str = "unreliable, strong damping";
pub const LABEL_UNREL_WEAK: &str = "unreliable, weak damping";
pub const LABEL_NO_DATA: &str = "no data";

/// Every automatic label, in the order regions are listed with two or more axes.
pub const LABELS: [&str; 6] = [
    LABEL_STRONG,
    LABEL_JUMP,
    LABEL_WEAK,
    LABEL_UNREL_STRONG,
    LABEL_UNREL_WEAK,
    LABEL_NO_DATA,
];

/// A jump along one axis: a step between two neighbouring design points, or a kink at one.
#[derive(Clone, Debug, PartialEq)]
pub struct Jump {
    pub axis: String,
    /// `xmax` or `di`.
    pub quantity: &'static str,
    /// `step` or `kink`.
    pub kind: &'static str,
    /// The axis values spanned: the two sides of a step, the neighbours of a kink.
    pub from: f64,
    pub to: f64,
    /// Where it is: the middle of a step, the point of a kink.
    pub at: f64,
    /// The design points it marks (2 for a step, 3 for a kink).
    pub points: Vec<u64>,
    /// The first difference of a step or the second difference of a kink (m or m/s), and its
    /// robust z-score.
    pub delta: f64,
    pub z: f64,
}

/// A zone: a contiguous range of the axis (one axis) or a region of the map (two or more).
#[derive(Clone, Debug, PartialEq)]
pub struct Zone {
    /// "I", "II", … or the declared name.
    pub name: String,
    /// What the zone is good for (one of [`LABELS`]), or "declared".
    pub label: String,
    pub declared: bool,
    /// Per axis: key, smallest and largest value of the zone's points.
    pub ranges: Vec<(String, f64, f64)>,
    pub n_points: usize,
    /// Means over the zone's points with known R and DI.
    pub mean_r: f64,
    pub mean_di: f64,
    /// Eq. 11 on the zone means, normalised by the best zone means (%).
    pub perfectibility: f64,
}

/// What [`find`] returns.
#[derive(Clone, Debug)]
pub struct Found {
    pub zones: Vec<Zone>,
    pub jumps: Vec<Jump>,
    pub di_strong: f64,
}

/// Roman numeral of `n >= 1`.
pub fn roman(mut n: usize) -> String {
    const T: [(usize, &str); 13] = [
        (1000, "M"),
        (900, "CM"),
        (500, "D"),
        (400, "CD"),
        (100, "C"),
        (90, "XC"),
        (50, "L"),
        (40, "XL"),
        (10, "X"),
        (9, "IX"),
        (5, "V"),
        (4, "IV"),
        (1, "I"),
    ];
    let mut s = String::new();
    for (v, r) in T {
        while n >= v {
            s.push_str(r);
            n -= v;
        }
    }
    s
}

/// Robust z-scores of differences: `|Δ - median| / max(1.4826 MAD, 1e-3 median|Δ|)`.
pub fn robust_z(diffs: &[f64]) -> Vec<f64> {
    if diffs.is_empty() {
        return Vec::new();
    }
    let med = median(diffs);
    let abs: Vec<f64> = diffs.iter().map(|d| d.abs()).collect();
    let scale = (1.4826 * mad(diffs))
        .max(1e-3 * median(&abs))
        .max(f64::MIN_POSITIVE);
    diffs.iter().map(|d| (d - med).abs() / scale).collect()
}

/// Finds steps and kinks along every axis; `points` must be sorted by point index.
pub fn jumps(axes: &[(String, Vec<f64>)], points: &[PointStats], jump_k: f64) -> Vec<Jump> {
    let n_total: usize = axes.iter().map(|a| a.1.len()).product();
    let mut at = vec![usize::MAX; n_total];
    for (i, p) in points.iter().enumerate() {
        if (p.point as usize) < n_total {
            at[p.point as usize] = i;
        }
    }
    let mut out = Vec::new();
    let ideal = points.iter().all(|p| p.xmax_ideal.is_finite());
    for (a, (key, values)) in axes.iter().enumerate() {
        // Stride of axis `a` in the point index (last axis fastest).
        let stride: usize = axes[a + 1..].iter().map(|x| x.1.len()).product();
        let len = values.len();
        for quantity in ["xmax", "di"] {
            let get = |i: usize| -> f64 {
                if i == usize::MAX {
                    return f64::NAN;
                }
                let p = &points[i];
                match (quantity, ideal) {
                    ("xmax", true) => p.xmax_ideal,
                    ("xmax", false) => p.xmax_mean,
                    _ => p.di,
                }
            };
            // (positions in `points`, index along the axis, difference)
            let mut steps: Vec<([usize; 2], usize, f64)> = Vec::new();
            let mut kinks: Vec<([usize; 3], usize, f64)> = Vec::new();
            for base in 0..n_total {
                // `base` starts a line when its index along `a` is 0.
                if !(base / stride).is_multiple_of(len) {
                    continue;
                }
                let line: Vec<usize> = (0..len).map(|i| at[base + i * stride]).collect();
                let d: Vec<f64> = (0..len.saturating_sub(1))
                    .map(|i| get(line[i + 1]) - get(line[i]))
                    .collect();
                for i in 0..d.len() {
                    if d[i].is_finite() {
                        steps.push(([line[i], line[i + 1]], i, d[i]));
                    }
                    if i > 0 && (d[i] - d[i - 1]).is_finite() {
                        kinks.push(([line[i - 1], line[i], line[i + 1]], i, d[i] - d[i - 1]));
                    }
                }
            }
            let diffs: Vec<f64> = steps.iter().map(|s| s.2).collect();
            let mut stepped = std::collections::HashSet::new();
            for (&(pp, i, d), z) in steps.iter().zip(robust_z(&diffs)) {
                if z > jump_k {
                    stepped.insert(pp);
                    out.push(Jump {
                        axis: key.clone(),
                        quantity,
                        kind: "step",
                        from: values[i],
                        to: values[i + 1],
                        at: (values[i] + values[i + 1]) / 2.0,
                        points: pp.iter().map(|&k| points[k].point).collect(),
                        delta: d,
                        z,
                    });
                }
            }
            let abs: Vec<f64> = diffs.iter().map(|d| d.abs()).collect();
            let typical = median(&abs);
            let d2: Vec<f64> = kinks.iter().map(|k| k.2).collect();
            let med2 = median(&d2);
            for (&(pp, i, d), z) in kinks.iter().zip(robust_z(&d2)) {
                // A step makes two outlying second differences, one either side: not kinks.
                let by_step =
                    stepped.contains(&[pp[0], pp[1]]) || stepped.contains(&[pp[1], pp[2]]);
                if z > jump_k && (d - med2).abs() > KINK_STEPS * typical && !by_step {
                    out.push(Jump {
                        axis: key.clone(),
                        quantity,
                        kind: "kink",
                        from: values[i - 1],
                        to: values[i + 1],
                        at: values[i],
                        points: pp.iter().map(|&k| points[k].point).collect(),
                        delta: d,
                        z,
                    });
                }
            }
        }
    }
    out
}

/// The automatic label of a point.
pub fn label(p: &PointStats, near_jump: bool, r_min: f64, di_strong: f64) -> &'static str {
    if !(p.reliability.is_finite() && p.di.is_finite()) {
        LABEL_NO_DATA
    } else if near_jump {
        LABEL_JUMP
    } else if p.reliability >= r_min {
        if p.di >= di_strong {
            LABEL_STRONG
        } else {
            LABEL_WEAK
        }
    } else if p.di >= di_strong {
        LABEL_UNREL_STRONG
    } else {
        LABEL_UNREL_WEAK
    }
}

/// Labels the points, cuts the zones and fills `points[i].zone`; `points` sorted by index.
pub fn find(
    axes: &[(String, Vec<f64>)],
    points: &mut [PointStats],
    cfg: &Zones,
    ranking: &Ranking,
) -> Found {
    let jumps = jumps(axes, points, cfg.jump_k);
    let dis: Vec<f64> = points
        .iter()
        .map(|p| p.di)
        .filter(|d| d.is_finite())
        .collect();
    let di_strong = cfg.di_strong.unwrap_or_else(|| median(&dis));
    let mut members: Vec<(String, String, bool, Vec<usize>)> = Vec::new(); // name, label, declared, points
    if !cfg.declared.is_empty() {
        let mut lists: Vec<Vec<usize>> = vec![Vec::new(); cfg.declared.len()];
        for (i, p) in points.iter().enumerate() {
            let hit = cfg.declared.iter().position(|z| {
                axes.iter().position(|a| a.0 == z.axis).is_some_and(|a| {
                    let v = p.values[a];
                    let tol = 1e-9 * (z.to - z.from).abs().max(f64::MIN_POSITIVE);
                    v >= z.from.min(z.to) - tol && v <= z.from.max(z.to) + tol
                })
            });
            if let Some(k) = hit {
                lists[k].push(i);
            }
        }
        for (z, list) in cfg.declared.iter().zip(lists) {
            members.push((z.name.clone(), "declared".into(), true, list));
        }
    } else {
        let mut near = vec![false; points.len()];
        let index: std::collections::HashMap<u64, usize> = points
            .iter()
            .enumerate()
            .map(|(i, p)| (p.point, i))
            .collect();
        for j in &jumps {
            for p in &j.points {
                if let Some(&i) = index.get(p) {
                    near[i] = true;
                }
            }
        }
        let labels: Vec<&str> = points
            .iter()
            .zip(&near)
            .map(|(p, &nj)| label(p, nj, cfg.r_min, di_strong))
            .collect();
        if axes.len() == 1 {
            for run in merge_short(runs(&labels)) {
                let name = roman(members.len() + 1);
                members.push((name, run.0.to_string(), false, run.1));
            }
        } else {
            for l in LABELS {
                let list: Vec<usize> = (0..points.len()).filter(|&i| labels[i] == l).collect();
                if !list.is_empty() {
                    let name = roman(members.len() + 1);
                    members.push((name, l.to_string(), false, list));
                }
            }
        }
    }
    let mut zones: Vec<Zone> = members
        .into_iter()
        .map(|(name, label, declared, list)| {
            for &i in &list {
                points[i].zone = name.clone();
            }
            zone_of(axes, points, name, label, declared, &list)
        })
        .collect();
    let r_max = zones
        .iter()
        .map(|z| z.mean_r)
        .filter(|v| v.is_finite())
        .fold(f64::NAN, f64::max);
    let di_max = zones
        .iter()
        .map(|z| z.mean_di)
        .filter(|v| v.is_finite())
        .fold(f64::NAN, f64::max);
    for z in &mut zones {
        z.perfectibility =
            perfectibility(z.mean_r, z.mean_di, r_max, di_max, ranking.wf1, ranking.wf2);
    }
    Found {
        zones,
        jumps,
        di_strong,
    }
}

/// Contiguous runs of equal labels: (label, point positions).
fn runs<'l>(labels: &[&'l str]) -> Vec<(&'l str, Vec<usize>)> {
    let mut out: Vec<(&str, Vec<usize>)> = Vec::new();
    for (i, &l) in labels.iter().enumerate() {
        match out.last_mut() {
            Some((last, list)) if *last == l => list.push(i),
            _ => out.push((l, vec![i])),
        }
    }
    out
}

/// Runs that are never merged away nor merged into: around a jump, and no data (a failed point
/// must stay visible).
fn sticky(label: &str) -> bool {
    label == LABEL_JUMP || label == LABEL_NO_DATA
}

/// Merges runs shorter than [`MIN_ZONE_POINTS`] (except jump and no-data runs) into their
/// longer neighbour that is not one of those, shortest first, then joins neighbours that ended
/// up with the same label. A short run between such runs, or at an end next to one, stays.
fn merge_short(mut runs: Vec<(&str, Vec<usize>)>) -> Vec<(&str, Vec<usize>)> {
    let target = |runs: &[(&str, Vec<usize>)], i: usize| -> Option<usize> {
        let ok = |j: usize| !sticky(runs[j].0);
        let left = i.checked_sub(1).filter(|&j| ok(j));
        let right = (i + 1 < runs.len()).then_some(i + 1).filter(|&j| ok(j));
        match (left, right) {
            (Some(l), Some(r)) => Some(if runs[r].1.len() > runs[l].1.len() {
                r
            } else {
                l
            }),
            (l, r) => l.or(r),
        }
    };
    loop {
        let victim = runs
            .iter()
            .enumerate()
            .filter(|(i, r)| {
                !sticky(r.0) && r.1.len() < MIN_ZONE_POINTS && target(&runs, *i).is_some()
            })
            .min_by_key(|(i, r)| (r.1.len(), *i))
            .map(|(i, _)| i);
        let Some(i) = victim else { break };
        let Some(into) = target(&runs, i) else { break };
        let (_, moved) = runs.remove(i);
        let into = if into > i { into - 1 } else { into };
        runs[into].1.extend(moved);
        runs[into].1.sort_unstable();
        // Join equal neighbours.
        let mut joined: Vec<(&str, Vec<usize>)> = Vec::new();
        for r in runs {
            match joined.last_mut() {
                Some(last) if last.0 == r.0 => last.1.extend(r.1),
                _ => joined.push(r),
            }
        }
        runs = joined;
    }
    runs
}

fn zone_of(
    axes: &[(String, Vec<f64>)],
    points: &[PointStats],
    name: String,
    label: String,
    declared: bool,
    list: &[usize],
) -> Zone {
    let ranges = axes
        .iter()
        .enumerate()
        .map(|(a, (key, _))| {
            let vals = list.iter().map(|&i| points[i].values[a]);
            let lo = vals.clone().fold(f64::INFINITY, f64::min);
            let hi = vals.fold(f64::NEG_INFINITY, f64::max);
            (key.clone(), lo, hi)
        })
        .collect();
    let known: Vec<&PointStats> = list
        .iter()
        .map(|&i| &points[i])
        .filter(|p| p.reliability.is_finite() && p.di.is_finite())
        .collect();
    let nk = known.len() as f64;
    let (mean_r, mean_di) = if known.is_empty() {
        (f64::NAN, f64::NAN)
    } else {
        (
            known.iter().map(|p| p.reliability).sum::<f64>() / nk,
            known.iter().map(|p| p.di).sum::<f64>() / nk,
        )
    };
    Zone {
        name,
        label,
        declared,
        ranges,
        n_points: list.len(),
        mean_r,
        mean_di,
        perfectibility: f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roman_numerals() {
        let r: Vec<String> = [1, 2, 3, 4, 9, 14, 40, 1994]
            .iter()
            .map(|&n| roman(n))
            .collect();
        assert_eq!(r, ["I", "II", "III", "IV", "IX", "XIV", "XL", "MCMXCIV"]);
    }

    #[test]
    fn robust_z_singles_out_a_step() {
        let mut d = vec![0.01; 20];
        for (i, x) in d.iter_mut().enumerate() {
            *x += 1e-4 * ((i * 7) % 5) as f64;
        }
        d[12] = 0.05;
        let z = robust_z(&d);
        let over: Vec<usize> = (0..d.len()).filter(|&i| z[i] > 6.0).collect();
        assert_eq!(over, vec![12]);
        // Exactly linear data: MAD 0, the floor keeps rounding from becoming a jump.
        let lin: Vec<f64> = (0..20)
            .map(|i| 0.1 * (i + 1) as f64 - 0.1 * i as f64)
            .collect();
        assert!(robust_z(&lin).iter().all(|&z| z < 6.0));
    }

    #[test]
    fn short_runs_merge_into_the_longer_non_jump_neighbour() {
        let l =
            |s: &'static str, n: usize, start: usize| (s, (start..start + n).collect::<Vec<_>>());
        // strong×5, weak×1, strong×4, jump×2, weak×1 (at the end, next to a jump: stays).
        let runs = vec![
            l(LABEL_STRONG, 5, 0),
            l(LABEL_WEAK, 1, 5),
            l(LABEL_STRONG, 4, 6),
            l(LABEL_JUMP, 2, 10),
            l(LABEL_WEAK, 1, 12),
        ];
        let out = merge_short(runs);
        let shape: Vec<(&str, usize)> = out.iter().map(|r| (r.0, r.1.len())).collect();
        assert_eq!(
            shape,
            vec![(LABEL_STRONG, 10), (LABEL_JUMP, 2), (LABEL_WEAK, 1)]
        );
        assert_eq!(out[0].1, (0..10).collect::<Vec<_>>());
    }
}
