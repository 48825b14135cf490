//! The design grid as the reducer sees it: the swept axes, a design point's coordinates along
//! them, its neighbours and the lines of the grid along one axis.
//!
//! Design point `p` is the mixed-radix number of its axis indices, the last axis fastest (the
//! plan's contract), so the neighbour one step along axis `a` is `p ± stride(a)`.

/// The swept axes: key and values, in axis order.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub axes: Vec<(String, Vec<f64>)>,
    strides: Vec<u64>,
    len: u64,
}

/// Which end of an axis a point sits on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    Low,
    High,
}

impl Grid {
    pub fn new(axes: Vec<(String, Vec<f64>)>) -> Grid {
        let mut strides = vec![1u64; axes.len()];
        for a in (0..axes.len().saturating_sub(1)).rev() {
            strides[a] = strides[a + 1] * axes[a + 1].1.len() as u64;
        }
        let len = axes.iter().map(|a| a.1.len() as u64).product();
        Grid { axes, strides, len }
    }

    /// Number of design points (1 without axes).
    pub fn len(&self) -> u64 {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn n_axes(&self) -> usize {
        self.axes.len()
    }

    /// Number of values of axis `a`.
    pub fn n(&self, a: usize) -> usize {
        self.axes[a].1.len()
    }

    pub fn key(&self, a: usize) -> &str {
        &self.axes[a].0
    }

    /// The values of axis `a`, in grid order.
    pub fn axis_values(&self, a: usize) -> &[f64] {
        &self.axes[a].1
    }

    /// The step in the point index between neighbours along axis `a`.
    pub fn stride(&self, a: usize) -> u64 {
        self.strides[a]
    }

    /// The index of point `p` along axis `a`.
    pub fn index(&self, p: u64, a: usize) -> usize {
        ((p / self.strides[a]) % self.n(a) as u64) as usize
    }

    /// The value of axis `a` at point `p`.
    pub fn value(&self, p: u64, a: usize) -> f64 {
        self.axes[a].1[self.index(p, a)]
    }

    /// Whether point `p` has no damper: `m = 0` on a swept `m` (the main mass alone, whatever
    /// the damper's other values).
    pub fn without_damper(&self, p: u64) -> bool {
        (0..self.n_axes()).any(|a| self.key(a) == "m" && self.value(p, a) == 0.0)
    }

    /// The axis values of point `p`, in axis order.
    pub fn values(&self, p: u64) -> Vec<f64> {
        (0..self.n_axes()).map(|a| self.value(p, a)).collect()
    }

    /// The point `delta` steps from `p` along axis `a`, if it is on the grid.
    pub fn step(&self, p: u64, a: usize, delta: i64) -> Option<u64> {
        let i = self.index(p, a) as i64 + delta;
        if i < 0 || i >= self.n(a) as i64 {
            return None;
        }
        Some((p as i64 + delta * self.strides[a] as i64) as u64)
    }

    /// The point with index `i` along axis `a` and the other coordinates of `p`.
    pub fn with_index(&self, p: u64, a: usize, i: usize) -> u64 {
        p - self.index(p, a) as u64 * self.strides[a] + i as u64 * self.strides[a]
    }

    /// The first point of every line of the grid along axis `a` (index 0 along `a`), in
    /// increasing order; the line through `start` is `start + i * stride(a)`.
    pub fn line_starts(&self, a: usize) -> impl Iterator<Item = u64> + '_ {
        let stride = self.strides[a];
        let block = stride * self.n(a) as u64;
        (0..self.len)
            .step_by(block.max(1) as usize)
            .flat_map(move |b| b..b + stride)
    }

    /// The end of axis `a` that `p` sits on, for an axis of two or more values.
    pub fn end(&self, p: u64, a: usize) -> Option<End> {
        let n = self.n(a);
        match self.index(p, a) {
            _ if n < 2 => None,
            0 => Some(End::Low),
            i if i + 1 == n => Some(End::High),
            _ => None,
        }
    }

    /// The points whose every coordinate is within one step of `p`'s (the box of ±1 step on
    /// every axis, clipped at the edges), `p` included, in increasing order.
    pub fn neighbourhood(&self, p: u64) -> Vec<u64> {
        let mut out = vec![p];
        for a in 0..self.n_axes() {
            let mut next = Vec::with_capacity(out.len() * 3);
            for &q in &out {
                next.extend(self.step(q, a, -1));
                next.push(q);
                next.extend(self.step(q, a, 1));
            }
            out = next;
        }
        out.sort_unstable();
        out
    }

    /// The sub-grid of the points equal to `p` on every axis but those in `free`: their indices
    /// in increasing order.
    pub fn slice(&self, p: u64, free: &[usize]) -> Vec<u64> {
        let mut out = vec![p];
        for &a in free {
            out = out
                .iter()
                .flat_map(|&q| (0..self.n(a)).map(move |i| (q, i)))
                .map(|(q, i)| self.with_index(q, a, i))
                .collect();
        }
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Grid {
        Grid::new(vec![
            ("e".into(), vec![0.5, 0.6, 0.7]),
            ("m".into(), vec![0.01, 0.02]),
            ("d".into(), vec![0.005, 0.01, 0.015, 0.02]),
        ])
    }

    #[test]
    fn coordinates_follow_the_plan() {
        let g = grid();
        assert_eq!(g.len(), 24);
        assert_eq!((g.stride(0), g.stride(1), g.stride(2)), (8, 4, 1));
        // p = 1 * 8 + 1 * 4 + 2 = 14: e = 0.6, m = 0.02, d = 0.015.
        assert_eq!(g.values(14), vec![0.6, 0.02, 0.015]);
        assert_eq!(g.step(14, 0, 1), Some(22));
        assert_eq!(g.step(14, 1, 1), None);
        assert_eq!(g.step(14, 2, -2), Some(12));
        assert_eq!(g.with_index(14, 2, 0), 12);
        assert_eq!(g.end(14, 1), Some(End::High));
        assert_eq!(g.end(14, 0), None);
        assert_eq!(g.end(12, 2), Some(End::Low));
    }

    #[test]
    fn lines_cover_the_grid_once() {
        let g = grid();
        for a in 0..3 {
            let (n, stride) = (g.n(a) as u64, g.stride(a));
            let mut all: Vec<u64> = g
                .line_starts(a)
                .flat_map(|s| (0..n).map(move |i| s + i * stride))
                .collect();
            assert_eq!(all.len(), 24);
            all.sort_unstable();
            all.dedup();
            assert_eq!(all.len(), 24, "axis {a}");
        }
        assert_eq!(
            g.line_starts(1).collect::<Vec<_>>(),
            vec![0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19]
        );
    }

    #[test]
    fn neighbourhood_and_slice() {
        let g = grid();
        // Interior in e and d, edge in m: 3 x 2 x 3 = 18 points.
        assert_eq!(g.neighbourhood(14).len(), 18);
        // A corner: 2 x 2 x 2.
        assert_eq!(g.neighbourhood(0).len(), 8);
        // The (e, d) slice at m = 0.02 through point 14.
        let s = g.slice(14, &[0, 2]);
        assert_eq!(s.len(), 12);
        assert!(s.iter().all(|&q| g.value(q, 1) == 0.02));
        let no_axes = Grid::new(vec![]);
        assert_eq!((no_axes.len(), no_axes.neighbourhood(0)), (1, vec![0]));
    }
}
