//! Sensitivity of a quantity to each axis on a full-factorial grid (model.md §9): first-order
//! and total-effect indices by exact ANOVA on the grid, every point weighted equally.
//!
//! Over the `N` points where the quantity is known, `V = Var(Y)` (divided by `N`);
//! * first order: `S_i = Var(E[Y | X_i]) / V`, the variance of the means over the points that
//!   share a value of axis `i`, each mean weighted by its number of points;
//! * total effect: `S_Ti = E[Var(Y | X_~i)] / V`, the mean over the lines of the grid along
//!   axis `i` (every other axis fixed) of the variance along the line, each line weighted by its
//!   number of points.
//!
//! On a complete grid both are exact for the grid, no sampling: `sum S_i <= 1`, `S_Ti >= S_i`,
//! and `S_Ti - S_i` is the share of the variance in interactions involving axis `i`. Points
//! left out (a failed case, no data) make the grid incomplete; the same sums are then taken over
//! the points that remain, which is no longer an exact decomposition (the report says how many
//! points are left out). NaN when `V = 0`.

use super::grid::Grid;

/// `(first_order, total)` of `y` for every axis; `y[p]` is the quantity at grid point `p`, NaN
/// for a point left out.
pub fn indices(grid: &Grid, y: &[f64]) -> Vec<(f64, f64)> {
    let known = || y.iter().copied().filter(|v| v.is_finite());
    let n = known().count();
    if n == 0 {
        return vec![(f64::NAN, f64::NAN); grid.n_axes()];
    }
    let nf = n as f64;
    let mean = known().sum::<f64>() / nf;
    let var = known().map(|v| (v - mean) * (v - mean)).sum::<f64>() / nf;
    (0..grid.n_axes())
        .map(|a| {
            if var <= 0.0 {
                return (f64::NAN, f64::NAN);
            }
            // First order: means per value of axis a.
            let k = grid.n(a);
            let mut sums = vec![0.0; k];
            let mut counts = vec![0usize; k];
            for (p, &v) in y.iter().enumerate() {
                if v.is_finite() {
                    let i = grid.index(p as u64, a);
                    sums[i] += v;
                    counts[i] += 1;
                }
            }
            let between: f64 = sums
                .iter()
                .zip(&counts)
                .filter(|(_, c)| **c > 0)
                .map(|(s, &c)| {
                    let m = s / c as f64;
                    c as f64 * (m - mean) * (m - mean)
                })
                .sum();
            // Total effect: variance along every line of axis a.
            let stride = grid.stride(a);
            let mut within = 0.0;
            for start in grid.line_starts(a) {
                let line: Vec<f64> = (0..k)
                    .map(|i| y[(start + i as u64 * stride) as usize])
                    .filter(|v| v.is_finite())
                    .collect();
                if line.is_empty() {
                    continue;
                }
                let m = line.iter().sum::<f64>() / line.len() as f64;
                within += line.iter().map(|v| (v - m) * (v - m)).sum::<f64>();
            }
            (between / nf / var, within / nf / var)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12
    }

    #[test]
    fn hand_computed_anova_on_a_two_by_three_grid() {
        // Axis A in {0, 1} (rows), axis B in {0, 1, 2} (columns), equal weights:
        //
        //          B=0  B=1  B=2 | E[Y|A]
        //   A=0     1    2    6  |   3
        //   A=1     3    4    2  |   3
        //   E[Y|B]  2    3    4  |   mean 3
        //
        // V = (4 + 1 + 9 + 0 + 1 + 1) / 6 = 8/3.
        // S_A = Var(3, 3) / V = 0.
        // S_B = Var(2, 3, 4) / V = ((1 + 0 + 1) / 3) / (8/3) = 1/4.
        // S_TA: lines along A (B fixed): {1,3} var 1, {2,4} var 1, {6,2} var 4; mean 2;
        //       2 / (8/3) = 3/4.
        // S_TB: lines along B (A fixed): {1,2,6} var 14/3, {3,4,2} var 2/3; mean 8/3; 1.
        // Check: V_A + V_B + V_AB = 0 + 2/3 + 2 = 8/3, and S_T - S = 3/4 on both axes is the
        // interaction's share.
        let g = Grid::new(vec![
            ("A".into(), vec![0.0, 1.0]),
            ("B".into(), vec![0.0, 1.0, 2.0]),
        ]);
        let y = [1.0, 2.0, 6.0, 3.0, 4.0, 2.0];
        let s = indices(&g, &y);
        assert!(close(s[0].0, 0.0) && close(s[0].1, 0.75), "{s:?}");
        assert!(close(s[1].0, 0.25) && close(s[1].1, 1.0), "{s:?}");
    }

    #[test]
    fn hand_computed_additive_function_on_a_cube() {
        // Y = a + 2 b on a 2 x 2 x 3 grid (c has no effect). Var(a) = 1/4 over {0, 1},
        // Var(2b) = 4 * 1/4 = 1: V = 5/4, S_a = S_Ta = 1/5, S_b = S_Tb = 4/5, S_c = S_Tc = 0.
        let g = Grid::new(vec![
            ("a".into(), vec![0.0, 1.0]),
            ("b".into(), vec![0.0, 1.0]),
            ("c".into(), vec![0.0, 1.0, 2.0]),
        ]);
        let y: Vec<f64> = (0..12u64)
            .map(|p| g.value(p, 0) + 2.0 * g.value(p, 1))
            .collect();
        let s = indices(&g, &y);
        for (i, want) in [0.2, 0.8, 0.0].into_iter().enumerate() {
            assert!(
                close(s[i].0, want) && close(s[i].1, want),
                "axis {i}: {s:?}"
            );
        }
    }

    #[test]
    fn constant_or_empty_gives_nan() {
        let g = Grid::new(vec![("a".into(), vec![0.0, 1.0])]);
        assert!(indices(&g, &[2.0, 2.0])[0].0.is_nan());
        assert!(indices(&g, &[f64::NAN, f64::NAN])[0].1.is_nan());
    }
}
