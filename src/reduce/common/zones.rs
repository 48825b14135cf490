//! Zones found from the data (model.md §6), or declared in the study.
//!
//! 1. **Jumps** along every axis, located and classed by [`super::jumps`].
//! 2. **Classes.** Every design point gets one:
//!    * `around a jump` — its ±1-step neighbourhood along an axis reaches a located jump: a
//!      small error in that design variable changes the behaviour abruptly (the paper's zone II);
//!    * `strong damping, reliable` — R shown at or above `r_min`: the lower end of its
//!      bootstrap interval (at the study's confidence) is `>= r_min`; and `DI >= di_strong`
//!      (the paper's zone I);
//!    * `reliable, weak damping` — R shown at or above `r_min`, `DI < di_strong` (zone III);
//!    * `strong damping, reliability not shown` / `weak damping, reliability not shown` — the
//!      interval of R reaches below `r_min`: with a dozen cases a point whose R is just above
//!      the threshold is not shown to reach it;
//!    * `strong damping, reliability not computed` / `weak damping, reliability not computed` —
//!      a study without a strength (`[reliability] strength_mean`, `strength_sd`): no point
//!      has an R, so the class follows DI alone;
//!    * `no data` — R or DI unknown (no ok run, or no ok ideal run).
//!
//!    `r_min` is `[zones].r_min` (default 0.98), `di_strong` is `[zones].di_strong` (default:
//!    the median DI of the sweep, so "strong" means "better than half of the designs").
//! 3. **Zones** are the regions of [`super::regions`]: connected sets of points of one class,
//!    tiny ones (fewer than `min_zone` of the design points) merged into a neighbour; the points
//!    around a jump and the points without data are never merged. Zones are named I, II, … in
//!    the order of their first point (along the axis with one axis).
//! 4. **Each zone** is described by its points: class, count, bounding box, the best point
//!    (highest perfectibility), a representative point (the one deepest inside the zone: the
//!    most steps from its border and from the edge of the grid), the means of R and DI, and
//!    eq. 11 applied to those means normalised by the best zone means (as in the paper's
//!    Table III).
//! 5. **Declared zones** (`[[zones.zone]]`) replace steps 2–3: a point belongs to the first
//!    declared zone whose range on its axis holds the point's value. Jumps are still found.

use std::collections::VecDeque;

use super::class::Class;
use super::grid::Grid;
use super::jumps::{self, IdealCase, Jump, JumpSettings, Quantity};
use super::point::PointStats;
use super::regions::{self, MISSING, NO_REGION};
use super::stats::{median, perfectibility};
use crate::study::{DeclaredZone, Ranking};

/// The settings of zone finding beyond the study's `r_min`, `di_strong` and declared zones
/// (`[zones]` of the study, see [`crate::study::Zones`] for their defaults and ranges).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZoneParams {
    /// A region of fewer than this fraction of the design points merges into a neighbour.
    pub min_zone: f64,
    /// The step tolerance of a quantity is this many times its typical spread across a point's
    /// cases (the median over the points of its SD over the ok cases).
    pub step_spread: f64,
    /// A kink changes the slope of the response by at least this many typical slopes.
    pub kink_slope: f64,
    /// Jumps are located to this fraction of the grid step.
    pub locate: f64,
}

/// What decides the zones.
#[derive(Clone, Debug, PartialEq)]
pub struct ZoneConfig<'a> {
    pub r_min: f64,
    pub di_strong: Option<f64>,
    pub declared: &'a [DeclaredZone],
    pub params: ZoneParams,
}

/// A zone: a connected region of one class, or a declared zone.
#[derive(Clone, Debug, PartialEq)]
pub struct Zone {
    /// "I", "II", … or the declared name.
    pub name: String,
    /// The class of its points; `None` for a declared zone.
    pub class: Option<Class>,
    /// Per axis: the smallest and largest value of the zone's points.
    pub ranges: Vec<(f64, f64)>,
    pub n_points: usize,
    /// Of those, the points merged in from a smaller neighbouring region: their own class
    /// ([`PointStats::class`]) is not the zone's (issue 18: a "reliable" zone can hold points
    /// whose own R interval reaches below `r_min`). 0 for declared zones.
    pub n_merged: usize,
    /// The point with the highest perfectibility, and the one deepest inside the zone.
    pub best: Option<u64>,
    pub representative: Option<u64>,
    /// Means over the zone's points with known R and DI.
    pub mean_r: f64,
    pub mean_di: f64,
    /// Eq. 11 on the zone means, normalised by the best zone means (%).
    pub perfectibility: f64,
}

impl Zone {
    /// The class label, or "declared".
    pub fn label(&self) -> &'static str {
        self.class.map_or("declared", Class::label)
    }

    pub fn declared(&self) -> bool {
        self.class.is_none()
    }
}

/// The jump-finding figures the report quotes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JumpStats {
    /// The step tolerance per quantity ([`Quantity::index`]), in the quantity's units, and how
    /// each was set ([`step_tolerances`]).
    pub step_tol: [f64; 2],
    pub step_rule: [StepRule; 2],
    /// The typical slope of the response per axis.
    pub typical_slope: Vec<f64>,
    pub candidates: usize,
    pub dropped: usize,
    pub failed: usize,
    /// Candidates between statistical estimates, and the steps among them
    /// ([`jumps::Found::estimated`]).
    pub estimated: usize,
    pub estimated_steps: usize,
    /// Steps whose bisection stopped at an estimate ([`jumps::Found::stopped_steps`]).
    pub stopped_steps: usize,
    /// Extra simulations of the ideal case.
    pub sims: u64,
}

/// What [`find`] returns.
#[derive(Clone, Debug)]
pub struct Found {
    pub zones: Vec<Zone>,
    pub jumps: Vec<Jump>,
    pub stats: JumpStats,
    pub di_strong: f64,
    /// The smallest zone that is not merged (design points).
    pub min_zone_points: usize,
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

/// The class of a point (module doc); `with_r`: the study computes R (it gives a strength).
pub fn classify(
    p: &PointStats,
    near_jump: bool,
    r_min: f64,
    di_strong: f64,
    with_r: bool,
) -> Class {
    if !p.di.is_finite() || (with_r && !p.reliability.is_finite()) {
        Class::NoData
    } else if near_jump {
        Class::AroundJump
    } else if !with_r {
        if p.di >= di_strong {
            Class::StrongNotComputed
        } else {
            Class::WeakNotComputed
        }
    } else {
        // The lower end of the interval; R itself when there is no interval (one ok case).
        let lo = if p.reliability_lo.is_finite() {
            p.reliability_lo.min(p.reliability)
        } else {
            p.reliability
        };
        match (lo >= r_min, p.di >= di_strong) {
            (true, true) => Class::StrongReliable,
            (true, false) => Class::WeakReliable,
            (false, true) => Class::StrongNotShown,
            (false, false) => Class::WeakNotShown,
        }
    }
}

/// How a quantity's step tolerance was set ([`step_tolerances`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StepRule {
    /// `step_spread` times the median over the points of its SD over the ok cases.
    #[default]
    Spread,
    /// [`LEVEL_SHARE`] of its median magnitude: the points have no spread to scale (one case
    /// each, or cases that do not differ).
    Level,
}

/// The step tolerance's share of a quantity's median magnitude where its cases give no spread.
pub const LEVEL_SHARE: f64 = 0.01;

/// The step tolerance of each quantity, and its rule: `step_spread` times the median over the
/// points of its SD over the ok cases; without a spread (one case per point, or cases that do
/// not differ: the median SD is below 1e-9 of the median magnitude), 1 % of its median
/// magnitude.
pub fn step_tolerances(points: &[PointStats], step_spread: f64) -> ([f64; 2], [StepRule; 2]) {
    let tol = |sd: &dyn Fn(&PointStats) -> f64, level: &dyn Fn(&PointStats) -> f64| {
        let sds: Vec<f64> = points.iter().map(sd).collect();
        let levels: Vec<f64> = points.iter().map(|p| level(p).abs()).collect();
        let (s, l) = (median(&sds), median(&levels));
        if s > 1e-9 * l {
            (step_spread * s, StepRule::Spread)
        } else {
            (LEVEL_SHARE * l, StepRule::Level)
        }
    };
    let [(r, rr), (d, dr)] = [
        tol(&|p| p.response.sd, &|p| p.response.mean),
        tol(&|p| p.di_sd, &|p| p.di),
    ];
    ([r, d], [rr, dr])
}

/// Finds the jumps, classes the points, cuts the zones and fills `points[i].zone` and
/// `points[i].class`. `points` sorted by index; `pos[p]` is the position of grid point `p` in
/// `points` (`u32::MAX` when missing).
pub fn find(
    grid: &Grid,
    points: &mut [PointStats],
    pos: &[u32],
    cfg: &ZoneConfig,
    ranking: &Ranking,
    ideal: &dyn IdealCase,
) -> Found {
    let (step_tol, step_rule) = step_tolerances(points, cfg.params.step_spread);
    let found = find_jumps(grid, points, pos, cfg, step_tol, ideal);
    let dis: Vec<f64> = points.iter().map(|p| p.di).collect();
    let di_strong = cfg.di_strong.unwrap_or_else(|| median(&dis));
    classify_points(grid, points, pos, &found.jumps, cfg, di_strong);
    let min_zone_points = ((cfg.params.min_zone * points.len() as f64).ceil() as usize).max(1);
    let zones = cut_zones(grid, points, cfg, min_zone_points, ranking);
    Found {
        zones,
        jumps: found.jumps,
        stats: JumpStats {
            step_tol,
            step_rule,
            typical_slope: found.typical_slope,
            candidates: found.candidates,
            dropped: found.dropped,
            failed: found.failed,
            estimated: found.estimated,
            estimated_steps: found.estimated_steps,
            stopped_steps: found.stopped_steps,
            sims: found.sims,
        },
        di_strong,
        min_zone_points,
    }
}

/// The jumps of the ideal case's response and DI over the grid ([`jumps::find`]).
fn find_jumps(
    grid: &Grid,
    points: &[PointStats],
    pos: &[u32],
    cfg: &ZoneConfig,
    step_tol: [f64; 2],
    ideal: &dyn IdealCase,
) -> jumps::Found {
    let q: Vec<[f64; 2]> = pos
        .iter()
        .map(|&i| {
            if i == u32::MAX {
                [f64::NAN; 2]
            } else {
                let p = &points[i as usize];
                [p.response.ideal, p.di_ideal]
            }
        })
        .collect();
    let settings = JumpSettings {
        step_tol,
        kink_slope: cfg.params.kink_slope,
        locate: cfg.params.locate,
    };
    jumps::find(grid, &q, &settings, ideal)
}

/// Each point's class ([`classify`]): a point next to a jump is near one.
fn classify_points(
    grid: &Grid,
    points: &mut [PointStats],
    pos: &[u32],
    jumps: &[jumps::Jump],
    cfg: &ZoneConfig,
    di_strong: f64,
) {
    let mut near = vec![false; points.len()];
    for j in jumps {
        for p in jumps::around(grid, j) {
            let i = pos[p as usize];
            if i != u32::MAX {
                near[i as usize] = true;
            }
        }
    }
    let with_r = super::rank::computes_r(points);
    for (i, p) in points.iter_mut().enumerate() {
        p.class = classify(p, near[i], cfg.r_min, di_strong, with_r);
    }
}

/// The zones: the regions of like class of at least `min_zone_points` points (or the declared
/// ones), each point's `zone` filled, each zone described and its perfectibility given.
fn cut_zones(
    grid: &Grid,
    points: &mut [PointStats],
    cfg: &ZoneConfig,
    min_zone_points: usize,
    ranking: &Ranking,
) -> Vec<Zone> {
    let (region_of, members): (Vec<u32>, Vec<(String, Option<Class>)>) = if cfg.declared.is_empty()
    {
        let mut class = vec![MISSING; grid.len() as usize];
        for p in points.iter() {
            class[p.point as usize] = p.class as u8;
        }
        let (of, regs) = regions::regions(grid, &class, min_zone_points, |c| {
            Class::from_u8(c).sticky()
        });
        let names = regs
            .iter()
            .enumerate()
            .map(|(i, r)| (roman(i + 1), Some(Class::from_u8(r.class))))
            .collect();
        (of, names)
    } else {
        declared_zones(grid, points, cfg.declared)
    };
    let mut lists: Vec<Vec<usize>> = vec![Vec::new(); members.len()];
    for (i, p) in points.iter_mut().enumerate() {
        let z = region_of[p.point as usize];
        p.zone = z;
        if z != NO_REGION {
            lists[z as usize].push(i);
        }
    }
    let depth = depth(grid, &region_of);
    drop(region_of);
    let mut zones: Vec<Zone> = members
        .into_iter()
        .zip(&lists)
        .map(|((name, class), list)| describe(grid, points, &depth, name, class, list))
        .collect();
    let best = |f: fn(&Zone) -> f64| {
        zones
            .iter()
            .map(f)
            .filter(|v| v.is_finite())
            .fold(f64::NAN, f64::max)
    };
    let (r_max, di_max) = (best(|z| z.mean_r), best(|z| z.mean_di));
    for z in &mut zones {
        z.perfectibility = if r_max.is_finite() {
            perfectibility(z.mean_r, z.mean_di, r_max, di_max, ranking.wf1, ranking.wf2)
        } else {
            // No R anywhere (no strength): the damping quantity alone (rank::apply).
            100.0 * z.mean_di / di_max
        };
    }
    zones
}

/// Declared zones: the zone of every grid point (`NO_REGION` outside them) and their names.
fn declared_zones(
    grid: &Grid,
    points: &[PointStats],
    declared: &[DeclaredZone],
) -> (Vec<u32>, Vec<(String, Option<Class>)>) {
    let mut of = vec![NO_REGION; grid.len() as usize];
    for p in points {
        let hit = declared.iter().position(|z| {
            grid.axes
                .iter()
                .position(|a| a.0 == z.axis)
                .is_some_and(|a| {
                    let v = grid.value(p.point, a);
                    let tol = 1e-9 * (z.to - z.from).abs().max(f64::MIN_POSITIVE);
                    v >= z.from.min(z.to) - tol && v <= z.from.max(z.to) + tol
                })
        });
        if let Some(k) = hit {
            of[p.point as usize] = k as u32;
        }
    }
    (
        of,
        declared.iter().map(|z| (z.name.clone(), None)).collect(),
    )
}

/// Steps from every point to the border of its zone or the edge of the grid (0 on them), by a
/// breadth-first search from those points inward; `u32::MAX` where there is neither.
fn depth(grid: &Grid, zone_of: &[u32]) -> Vec<u32> {
    let n = zone_of.len();
    let mut d = vec![u32::MAX; n];
    let mut queue = VecDeque::new();
    for p in 0..n as u64 {
        let z = zone_of[p as usize];
        if z == NO_REGION {
            continue;
        }
        let border = (0..grid.n_axes()).any(|a| {
            grid.end(p, a).is_some()
                || [-1, 1]
                    .iter()
                    .any(|&s| grid.step(p, a, s).is_some_and(|q| zone_of[q as usize] != z))
        });
        if border {
            d[p as usize] = 0;
            queue.push_back(p);
        }
    }
    while let Some(p) = queue.pop_front() {
        let z = zone_of[p as usize];
        for a in 0..grid.n_axes() {
            for s in [-1, 1] {
                if let Some(q) = grid.step(p, a, s)
                    && zone_of[q as usize] == z
                    && d[q as usize] == u32::MAX
                {
                    d[q as usize] = d[p as usize] + 1;
                    queue.push_back(q);
                }
            }
        }
    }
    d
}

fn describe(
    grid: &Grid,
    points: &[PointStats],
    depth: &[u32],
    name: String,
    class: Option<Class>,
    list: &[usize],
) -> Zone {
    let ranges = (0..grid.n_axes())
        .map(|a| {
            list.iter()
                .map(|&i| grid.value(points[i].point, a))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                })
        })
        .collect();
    let best = list
        .iter()
        .filter(|&&i| points[i].rank.is_some())
        .min_by_key(|&&i| points[i].rank)
        .map(|&i| points[i].point);
    // Deepest point; ties (and zones without a border) go to the first in point order.
    let representative = list.iter().map(|&i| points[i].point).max_by_key(|&p| {
        let d = depth[p as usize];
        (if d == u32::MAX { 0 } else { d }, std::cmp::Reverse(p))
    });
    // Without a strength no point has R: the zone's DI is still its mean (rank::apply).
    let with_r = list.iter().any(|&i| points[i].reliability.is_finite());
    let known: Vec<&PointStats> = list
        .iter()
        .map(|&i| &points[i])
        .filter(|p| (!with_r || p.reliability.is_finite()) && p.di.is_finite())
        .collect();
    let nk = known.len() as f64;
    let (mean_r, mean_di) = if known.is_empty() {
        (f64::NAN, f64::NAN)
    } else {
        (
            if with_r {
                known.iter().map(|p| p.reliability).sum::<f64>() / nk
            } else {
                f64::NAN
            },
            known.iter().map(|p| p.di).sum::<f64>() / nk,
        )
    };
    let n_merged = class.map_or(0, |c| {
        list.iter().filter(|&&i| points[i].class != c).count()
    });
    Zone {
        name,
        class,
        ranges,
        n_points: list.len(),
        n_merged,
        best,
        representative,
        mean_r,
        mean_di,
        perfectibility: f64::NAN,
    }
}

/// The label of a quantity in tables: the response's name or `di`.
pub fn quantity_name(q: Quantity, response: &str) -> String {
    match q {
        Quantity::Response => response.to_string(),
        Quantity::Di => "di".to_string(),
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
    fn depth_counts_steps_to_the_border_and_the_edge() {
        // One zone on a 7-point line: the edge is the border; the middle point is 3 deep.
        let g = Grid::new(vec![("x".into(), (0..7).map(f64::from).collect())]);
        assert_eq!(depth(&g, &[0; 7]), vec![0, 1, 2, 3, 2, 1, 0]);
        // Two zones meeting between 2 and 3.
        assert_eq!(depth(&g, &[0, 0, 0, 1, 1, 1, 1]), vec![0, 1, 0, 0, 1, 1, 0]);
    }
}
