//! Regions of the design grid: connected sets of points of one class, and the rule that merges
//! tiny ones into a neighbour.
//!
//! Two points are neighbours when they differ by one index along one axis (the grid's edges,
//! not its diagonals). A region is a maximal connected set of points of one class.
//!
//! **Merge rule.** A region of fewer than `min_size` points whose class is not *sticky* is
//! merged into the neighbouring region it shares the most neighbour pairs with (ties: the larger
//! region, then the one met first in point order), and takes that region's class; regions of
//! the same class that touch after a merge become one. The smallest such region goes first,
//! ties in point order, until none is left. A region whose only neighbours are sticky, or that
//! has none, stays whatever its size. Sticky regions (points around a jump, points without
//! data) are never merged away nor merged into: a failed point or an abrupt change must stay
//! visible. Every region stays connected: a merge joins two regions that touch.

use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

use super::grid::Grid;

/// No class: the point is not in the dataset.
pub const MISSING: u8 = u8::MAX;
/// No region.
pub const NO_REGION: u32 = u32::MAX;

/// One region: its class, its size and its first point (the smallest index).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    pub class: u8,
    pub size: usize,
    pub first: u64,
}

/// The regions of `class` (one entry per grid point, [`MISSING`] for points not in the
/// dataset) after the merge rule: the region of every point ([`NO_REGION`] for missing ones)
/// and the regions, numbered in the order of their first point.
pub fn regions(
    grid: &Grid,
    class: &[u8],
    min_size: usize,
    sticky: impl Fn(u8) -> bool,
) -> (Vec<u32>, Vec<Region>) {
    let (mut of, raw) = components(grid, class);
    let mut forest = Forest::new(&raw);
    let adjacency = adjacency(grid, &of, raw.len());
    forest.merge_small(adjacency, min_size, &sticky);
    // Renumber the surviving roots in the order of their first point.
    let mut roots: Vec<u32> = (0..raw.len() as u32)
        .filter(|&r| forest.find(r) == r)
        .collect();
    roots.sort_by_key(|&r| forest.first[r as usize]);
    let mut new_id = vec![NO_REGION; raw.len()];
    for (i, &r) in roots.iter().enumerate() {
        new_id[r as usize] = i as u32;
    }
    let out: Vec<Region> = roots
        .iter()
        .map(|&r| Region {
            class: forest.class[r as usize],
            size: forest.size[r as usize],
            first: forest.first[r as usize],
        })
        .collect();
    for r in of.iter_mut() {
        if *r != NO_REGION {
            *r = new_id[forest.find(*r) as usize];
        }
    }
    (of, out)
}

/// Connected components of equal class (before merging), numbered by first point.
fn components(grid: &Grid, class: &[u8]) -> (Vec<u32>, Vec<Region>) {
    let n = class.len();
    let mut of = vec![NO_REGION; n];
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for start in 0..n {
        if class[start] == MISSING || of[start] != NO_REGION {
            continue;
        }
        let id = out.len() as u32;
        let c = class[start];
        let mut size = 0;
        of[start] = id;
        stack.push(start as u64);
        while let Some(p) = stack.pop() {
            size += 1;
            for a in 0..grid.n_axes() {
                for d in [-1, 1] {
                    if let Some(q) = grid.step(p, a, d) {
                        let qi = q as usize;
                        if of[qi] == NO_REGION && class[qi] == c {
                            of[qi] = id;
                            stack.push(q);
                        }
                    }
                }
            }
        }
        out.push(Region {
            class: c,
            size,
            first: start as u64,
        });
    }
    (of, out)
}

/// For every region, its neighbouring regions and the number of neighbour pairs they share.
fn adjacency(grid: &Grid, of: &[u32], n_regions: usize) -> Vec<BTreeMap<u32, u32>> {
    let mut adj = vec![BTreeMap::new(); n_regions];
    for (p, &r) in of.iter().enumerate() {
        if r == NO_REGION {
            continue;
        }
        for a in 0..grid.n_axes() {
            if let Some(q) = grid.step(p as u64, a, 1) {
                let s = of[q as usize];
                if s != NO_REGION && s != r {
                    *adj[r as usize].entry(s).or_insert(0) += 1;
                    *adj[s as usize].entry(r).or_insert(0) += 1;
                }
            }
        }
    }
    adj
}

/// Regions as a union-find forest with the data of each root.
struct Forest {
    parent: Vec<u32>,
    class: Vec<u8>,
    size: Vec<usize>,
    first: Vec<u64>,
}

impl Forest {
    fn new(raw: &[Region]) -> Forest {
        Forest {
            parent: (0..raw.len() as u32).collect(),
            class: raw.iter().map(|r| r.class).collect(),
            size: raw.iter().map(|r| r.size).collect(),
            first: raw.iter().map(|r| r.first).collect(),
        }
    }

    fn find(&mut self, mut r: u32) -> u32 {
        while self.parent[r as usize] != r {
            let up = self.parent[self.parent[r as usize] as usize];
            self.parent[r as usize] = up;
            r = up;
        }
        r
    }

    /// Joins root `from` into root `into`; `into` keeps its class.
    fn join(&mut self, adj: &mut [BTreeMap<u32, u32>], from: u32, into: u32) {
        self.parent[from as usize] = into;
        self.size[into as usize] += self.size[from as usize];
        self.first[into as usize] = self.first[into as usize].min(self.first[from as usize]);
        let moved = std::mem::take(&mut adj[from as usize]);
        adj[into as usize].remove(&from);
        for (nb, count) in moved {
            if nb == into {
                continue;
            }
            let m = adj[nb as usize].remove(&from).unwrap_or(0);
            debug_assert_eq!(m, count);
            *adj[nb as usize].entry(into).or_insert(0) += count;
            *adj[into as usize].entry(nb).or_insert(0) += count;
        }
    }

    fn merge_small(
        &mut self,
        mut adj: Vec<BTreeMap<u32, u32>>,
        min_size: usize,
        sticky: &impl Fn(u8) -> bool,
    ) {
        // Regions of one class never touch at the start (they would be one component).
        let mut heap: BinaryHeap<Reverse<(usize, u64, u32)>> = (0..self.parent.len() as u32)
            .filter(|&r| self.size[r as usize] < min_size && !sticky(self.class[r as usize]))
            .map(|r| Reverse((self.size[r as usize], self.first[r as usize], r)))
            .collect();
        while let Some(Reverse((size, first, r))) = heap.pop() {
            if self.parent[r as usize] != r
                || self.size[r as usize] != size
                || self.first[r as usize] != first
            {
                continue; // stale entry
            }
            // The non-sticky neighbour sharing the most pairs; ties: larger, then first met.
            let target = adj[r as usize]
                .iter()
                .filter(|(nb, _)| !sticky(self.class[**nb as usize]))
                .max_by_key(|(nb, count)| {
                    (
                        **count,
                        self.size[**nb as usize],
                        Reverse(self.first[**nb as usize]),
                    )
                })
                .map(|(nb, _)| *nb);
            let Some(into) = target else { continue };
            self.join(&mut adj, r, into);
            // Same-class neighbours that now touch `into` become one region with it.
            let class = self.class[into as usize];
            let same: Vec<u32> = adj[into as usize]
                .keys()
                .copied()
                .filter(|nb| self.class[*nb as usize] == class)
                .collect();
            for nb in same {
                self.join(&mut adj, nb, into);
            }
            if self.size[into as usize] < min_size {
                heap.push(Reverse((
                    self.size[into as usize],
                    self.first[into as usize],
                    into,
                )));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize) -> Grid {
        Grid::new(vec![("e".into(), (0..n).map(|i| i as f64).collect())])
    }

    fn classes(s: &str) -> Vec<u8> {
        s.bytes()
            .map(|b| if b == b'.' { MISSING } else { b - b'a' })
            .collect()
    }

    fn render(of: &[u32], regs: &[Region]) -> String {
        of.iter()
            .map(|&r| {
                if r == NO_REGION {
                    '.'
                } else {
                    (b'a' + regs[r as usize].class) as char
                }
            })
            .collect()
    }

    #[test]
    fn one_axis_short_runs_merge_into_the_longer_neighbour() {
        // a×5, b×1, a×4, j×2 (sticky), b×1 at the end next to a sticky run: stays.
        let c = classes("aaaaabaaaajjb");
        let (of, regs) = regions(&line(c.len()), &c, 3, |k| k == b'j' - b'a');
        assert_eq!(render(&of, &regs), "aaaaaaaaaajjb");
        assert_eq!(regs.len(), 3);
        assert_eq!(regs[0].size, 10);
        assert_eq!(of[5], 0);
    }

    #[test]
    fn a_stray_point_takes_the_class_around_it_and_joins_both_sides() {
        let c = classes("aaabaaa");
        let (of, regs) = regions(&line(7), &c, 2, |_| false);
        assert_eq!(regs.len(), 1);
        assert_eq!(
            regs[0],
            Region {
                class: 0,
                size: 7,
                first: 0
            }
        );
        assert!(of.iter().all(|&r| r == 0));
    }

    #[test]
    fn missing_points_split_regions_and_stay_out() {
        let c = classes("aa.aa");
        let (of, regs) = regions(&line(5), &c, 1, |_| false);
        assert_eq!(regs.len(), 2);
        assert_eq!(of, vec![0, 0, NO_REGION, 1, 1]);
    }

    #[test]
    fn two_axes_regions_are_connected_by_edges_not_diagonals() {
        // 4 x 4, rows are axis 0:
        //   a a b b
        //   a a b b
        //   b b a a
        //   b b a a
        // Diagonal contact does not connect: four regions of 4 points.
        let g = Grid::new(vec![
            ("x".into(), vec![0.0, 1.0, 2.0, 3.0]),
            ("y".into(), vec![0.0, 1.0, 2.0, 3.0]),
        ]);
        let c = classes("aabbaabbbbaabbaa");
        let (of, regs) = regions(&g, &c, 1, |_| false);
        assert_eq!(regs.len(), 4);
        assert!(regs.iter().all(|r| r.size == 4));
        assert_eq!(of[0], of[5]);
        assert_ne!(of[5], of[10]);
        // With a minimum of 5, the first small region (a, first point 0) merges into the b it
        // shares the most pairs with (tie 2 - 2: both b regions have 4 points, the first met,
        // at point 2, wins); a region made of 8 points is then large enough.
        let (_, regs) = regions(&g, &c, 5, |_| false);
        assert!(regs.len() <= 2, "{regs:?}");
        assert!(regs.iter().all(|r| r.size >= 5));
    }

    #[test]
    fn every_region_is_connected_after_merging() {
        // A pseudo-random 3-class pattern on 9 x 7: check connectivity of each final region.
        let g = Grid::new(vec![
            ("x".into(), (0..9).map(f64::from).collect()),
            ("y".into(), (0..7).map(f64::from).collect()),
        ]);
        let c: Vec<u8> = (0..63u64)
            .map(|i| ((i * 2654435761) >> 7) as u8 % 3)
            .collect();
        let (of, regs) = regions(&g, &c, 6, |k| k == 2);
        for (r, reg) in regs.iter().enumerate() {
            let members: Vec<usize> = (0..63).filter(|&p| of[p] == r as u32).collect();
            assert_eq!(members.len(), reg.size);
            // Flood fill from the first member within the region reaches all.
            let mut seen = [false; 63];
            let mut stack = vec![members[0] as u64];
            seen[members[0]] = true;
            let mut n = 0;
            while let Some(p) = stack.pop() {
                n += 1;
                for a in 0..2 {
                    for d in [-1, 1] {
                        if let Some(q) = g.step(p, a, d)
                            && !seen[q as usize]
                            && of[q as usize] == r as u32
                        {
                            seen[q as usize] = true;
                            stack.push(q);
                        }
                    }
                }
            }
            assert_eq!(n, reg.size, "region {r} is not connected");
            // Members keep their class unless merged; sticky points never change class.
            for &p in &members {
                if c[p] == 2 {
                    assert_eq!(reg.class, 2);
                }
            }
        }
        // Regions of one class never touch.
        for p in 0..63u64 {
            for a in 0..2 {
                if let Some(q) = g.step(p, a, 1) {
                    let (r, s) = (of[p as usize], of[q as usize]);
                    if r != s {
                        assert_ne!(regs[r as usize].class, regs[s as usize].class, "{p} {q}");
                    }
                }
            }
        }
    }
}
