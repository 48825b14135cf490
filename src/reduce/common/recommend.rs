//! The recommendation: the best design whose whole neighbourhood is safe, and a warning when the
//! best designs sit on the edge of the swept range.
//!
//! * A design point is **robust** when it is ranked, all its cases ended ok, its own class is
//!   recommended (a stray point merged into a recommended zone is not), every point of its neighbourhood (±1 step
//!   on every axis: the 3 × 3 × … box around it) is in the dataset and lies in a zone whose
//!   class is recommended (`strong damping, reliable` or `reliable, weak damping`: R shown at
//!   or above `r_min`, no jump nearby), and it is not on the edge of an axis of three or more
//!   values (there its neighbourhood is cut off: what lies beyond was not computed). A design
//!   error of one grid step in any variable, or in all at once, keeps such a design in a
//!   recommended zone.
//! * The **recommended design** is the robust point with the best perfectibility (rank).
//! * **Edges.** For every axis of two or more values and each of its ends: the number of the
//!   top designs (the ten best ranks) that sit on it. An end is reported when the best design,
//!   the recommended one, or half or more of the top designs sit on it: the optimum may lie
//!   beyond the swept range, and the axis should be extended that way (the report says whether
//!   the model allows it).

use super::class::Class;
use super::grid::{End, Grid};
use super::point::PointStats;
use super::summary::{EdgeWarning, Summary};
use super::zones::Zone;

/// How many of the best ranks count as "the best designs" for the edge warning.
pub const TOP: usize = 10;

/// Sets `robust` on every point; `pos[p]` is the position of grid point `p` in `points`.
pub fn mark_robust(grid: &Grid, points: &mut [PointStats], pos: &[u32], zones: &[Zone]) {
    let ok_zone = |z: u32| {
        zones
            .get(z as usize)
            .and_then(|z| z.class)
            .is_some_and(|c| c.recommended())
    };
    let robust: Vec<bool> = points
        .iter()
        .map(|p| {
            p.rank.is_some()
                && p.all_ok
                && p.class.recommended()
                && (0..grid.n_axes()).all(|a| grid.n(a) < 3 || grid.end(p.point, a).is_none())
                && grid.neighbourhood(p.point).iter().all(|&q| {
                    let i = pos[q as usize];
                    i != u32::MAX && ok_zone(points[i as usize].zone)
                })
        })
        .collect();
    for (p, r) in points.iter_mut().zip(robust) {
        p.robust = r;
    }
}

/// The robust point with the best rank.
pub fn recommended(points: &[PointStats]) -> Option<u64> {
    points
        .iter()
        .filter(|p| p.robust)
        .min_by_key(|p| p.rank)
        .map(|p| p.point)
}

/// The edges the best designs sit on (module doc). `extendable(axis, value)` tells whether a
/// design with that axis value would be valid.
pub fn edges(
    grid: &Grid,
    points: &[PointStats],
    recommended: Option<u64>,
    extendable: &dyn Fn(usize, f64) -> bool,
) -> Vec<EdgeWarning> {
    let mut ranked: Vec<&PointStats> = points.iter().filter(|p| p.rank.is_some()).collect();
    ranked.sort_by_key(|p| p.rank);
    let top: Vec<u64> = ranked.iter().take(TOP).map(|p| p.point).collect();
    let Some(&best) = top.first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for a in 0..grid.n_axes() {
        let n = grid.n(a);
        if n < 2 {
            continue;
        }
        let xs = &grid.axes[a].1;
        for end in [End::Low, End::High] {
            let n_top = top.iter().filter(|&&p| grid.end(p, a) == Some(end)).count();
            let is_best = grid.end(best, a) == Some(end);
            let is_rec = recommended.is_some_and(|p| grid.end(p, a) == Some(end));
            if !(is_best || is_rec || 2 * n_top >= top.len()) {
                continue;
            }
            let (value, beyond) = match end {
                End::Low => (xs[0], xs[0] - (xs[1] - xs[0])),
                End::High => (xs[n - 1], xs[n - 1] + (xs[n - 1] - xs[n - 2])),
            };
            out.push(EdgeWarning {
                axis: a,
                end,
                value,
                n_top,
                top: top.len(),
                best: is_best,
                recommended: is_rec,
                extendable: extendable(a, beyond),
            });
        }
    }
    out
}

/// Why a design point is not robust.
#[derive(Clone, Debug, PartialEq)]
pub enum NotRobust {
    /// R or DI unknown.
    Unranked,
    /// Some of its cases did not end ok.
    FailedCases,
    /// On this end of this axis (of three or more values).
    Edge(usize, End),
    /// A point of its neighbourhood is not in the dataset.
    Missing,
    /// Points of its neighbourhood lie in zones of this class (`None`: declared or no zone).
    Zone(Option<Class>),
}

/// Every reason why `p` is not robust (empty when it is).
pub fn reasons(s: &Summary, p: &PointStats) -> Vec<NotRobust> {
    let g = &s.grid;
    let mut out = Vec::new();
    if p.rank.is_none() {
        out.push(NotRobust::Unranked);
    }
    if !p.all_ok {
        out.push(NotRobust::FailedCases);
    }
    for a in 0..g.n_axes() {
        if g.n(a) >= 3
            && let Some(end) = g.end(p.point, a)
        {
            out.push(NotRobust::Edge(a, end));
        }
    }
    for q in g.neighbourhood(p.point) {
        let reason = match s.point(q) {
            None => NotRobust::Missing,
            Some(n) => match s.zone_of(n).and_then(|z| z.class) {
                Some(c) if c.recommended() => continue,
                c => NotRobust::Zone(c),
            },
        };
        if !out.contains(&reason) {
            out.push(reason);
        }
    }
    out
}
