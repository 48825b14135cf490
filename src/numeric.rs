//! Small numeric helpers shared by the whole crate: the one median, the one quantile and the
//! one linspace (a grid computed from the index, never accumulated).

/// Linear-interpolation quantile (type 7, the default of R and numpy) of a sample without NaN,
/// by selection (O(n); reorders `v`). NaN when empty. `q` is clamped to `[0, 1]`.
///
/// With `h = (n - 1) q`, `lo = floor(h)`: `v_(lo) + (h - lo) (v_(lo+1) - v_(lo))` over the
/// sorted sample, `v_(lo)` itself when `h` is whole.
pub fn quantile_mut(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let h = (v.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let (_, a, rest) = v.select_nth_unstable_by(lo, f64::total_cmp);
    let a = *a;
    let frac = h - lo as f64;
    if frac == 0.0 || rest.is_empty() {
        return a;
    }
    let b = rest.iter().copied().fold(f64::INFINITY, f64::min);
    a + frac * (b - a)
}

/// [`quantile_mut`] of a copy of `xs` without its NaN values. NaN when nothing is left.
pub fn quantile(xs: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = xs.iter().copied().filter(|x| !x.is_nan()).collect();
    quantile_mut(&mut v, q)
}

/// [`quantile_mut`] of a sample already sorted ascending (by `f64::total_cmp`, no NaN): the same
/// value, without the selection, for many quantiles of one sample. NaN when empty.
pub fn quantile_sorted(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let a = sorted[lo];
    let frac = h - lo as f64;
    match sorted.get(lo + 1) {
        Some(&b) if frac != 0.0 => a + frac * (b - a),
        _ => a,
    }
}

/// Median of a sample, NaN values left out (NaN when nothing is left): [`quantile`] at 0.5.
pub fn median(xs: &[f64]) -> f64 {
    quantile(xs, 0.5)
}

/// Rounds to 15 significant digits, so a grid computed as `start + i * step` gives the double
/// the user would type (`0.45 + 3 * 0.01` → `0.48`, not `0.48000000000000004`). Any decimal
/// with at most 15 significant digits is the nearest double to itself, and `start + i * step`
/// is within a few ulps (< 1e-15 relative) of it, so this recovers it; for other values it
/// moves them by less than 5e-16 relative.
///
/// The result is exactly `format!("{v:.14e}").parse()` (the decimal with 15 significant digits
/// nearest to `v`, ties to even, read back as the nearest double), without formatting: a sweep
/// of 10^7 runs along one axis would otherwise spend seconds in the formatter (issue 11). For
/// `1e-8 <= |v| < 1e37` the 15-digit integer `N = round(|v| 10^p)`, `p = 14 - floor(log10 |v|)`,
/// is found exactly: `10^|p|` is an exact double (`|p| <= 22`), the product or quotient is
/// carried with its exact rounding error (a fused multiply-add), and `N 10^-p` is one correctly
/// rounded operation on exact operands. Values whose scaled fraction lies within 1e-9 of a half,
/// and all other magnitudes, take the formatter.
pub fn round15(v: f64) -> f64 {
    const POW10: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    let slow = |v: f64| format!("{v:.14e}").parse().unwrap_or(v);
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let a = v.abs();
    if !(1e-8..1e37).contains(&a) {
        return slow(v);
    }
    let mut e10 = a.log10().floor() as i32;
    for _ in 0..3 {
        let p = 14 - e10;
        if !(-22..=22).contains(&p) {
            return slow(v);
        }
        let scale = POW10[p.unsigned_abs() as usize];
        // The exact scaled value is hi + lo (lo < ulp(hi) in size).
        let (hi, lo) = if p >= 0 {
            let hi = a * scale;
            (hi, a.mul_add(scale, -hi))
        } else {
            let hi = a / scale;
            (hi, (-hi).mul_add(scale, a) / scale)
        };
        let n0 = hi.round();
        let d = (hi - n0) + lo;
        if (d.abs() - 0.5).abs() <= 1e-9 {
            return slow(v);
        }
        let n = if d > 0.5 {
            n0 + 1.0
        } else if d < -0.5 {
            n0 - 1.0
        } else {
            n0
        };
        if n < 1e14 {
            e10 -= 1;
        } else if n > 1e15 {
            e10 += 1;
        } else {
            let r = if p >= 0 { n / scale } else { n * scale };
            return r.copysign(v);
        }
    }
    slow(v)
}

/// `n` values from `start` to `stop` inclusive, each computed from its index
/// (`start + (stop - start) * i / (n - 1)`, rounded by [`round15`]), the endpoints exact.
/// `n = 1` gives `[start]`; `n = 0` nothing.
pub fn linspace(start: f64, stop: f64, n: u64) -> Vec<f64> {
    match n {
        0 => Vec::new(),
        1 => vec![start],
        _ => {
            let span = stop - start;
            let last = (n - 1) as f64;
            let mut values: Vec<f64> = (0..n)
                .map(|i| round15(start + span * (i as f64 / last)))
                .collect();
            values[0] = start;
            values[(n - 1) as usize] = stop;
            values
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_by_selection_matches_sorting() {
        let xs: Vec<f64> = (0..2000)
            .map(|i| ((i * 7919) % 2003) as f64 * 0.37)
            .collect();
        let mut sorted = xs.clone();
        sorted.sort_by(f64::total_cmp);
        for q in [0.0, 0.025, 0.5, 0.975, 1.0] {
            let h = (sorted.len() - 1) as f64 * q;
            let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
            let want = sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo]);
            let mut v = xs.clone();
            assert_eq!(quantile_mut(&mut v, q), want, "q = {q}");
        }
        // The sorted sample's quantile is the selection's, bit for bit (a sample with ties).
        let ties: Vec<f64> = xs.iter().map(|x| (x * 0.1).floor()).collect();
        let mut sorted = ties.clone();
        sorted.sort_by(f64::total_cmp);
        for i in 0..=1000 {
            let q = f64::from(i) / 1000.0;
            let mut v = ties.clone();
            assert_eq!(
                quantile_sorted(&sorted, q).to_bits(),
                quantile_mut(&mut v, q).to_bits(),
                "q = {q}"
            );
        }
        assert!(quantile_sorted(&[], 0.5).is_nan());
    }

    #[test]
    fn median_drops_nan_and_interpolates() {
        assert!(median(&[]).is_nan());
        assert!(median(&[f64::NAN]).is_nan());
        assert_eq!(median(&[3.0, f64::NAN, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&[f64::INFINITY]), f64::INFINITY);
        assert_eq!(quantile(&[0.0, 10.0], 0.25), 2.5);
    }

    #[test]
    fn linspace_is_computed_from_the_index_with_exact_endpoints() {
        assert_eq!(linspace(0.0, 1.0, 5), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        assert_eq!(linspace(0.3, 0.3, 1), vec![0.3]);
        assert!(linspace(0.0, 1.0, 0).is_empty());
        let v = linspace(0.001, 0.0123, 7);
        assert_eq!(v[0].to_bits(), 0.001f64.to_bits());
        assert_eq!(v[6].to_bits(), 0.0123f64.to_bits());
        assert_eq!(linspace(0.45, 0.95, 51)[3], 0.48);
    }

    #[test]
    fn round15_recovers_typed_decimals() {
        assert_eq!(round15(0.1 + 0.2), 0.3);
        assert_eq!(round15(0.45 + 3.0 * 0.01), 0.48);
        assert_eq!(round15(-2.5e-7), -2.5e-7);
        assert_eq!(round15(0.0), 0.0);
    }

    #[test]
    fn round15_agrees_with_the_formatter() {
        let slow = |v: f64| -> f64 { format!("{v:.14e}").parse().unwrap() };
        let mut state = 0x1234_5678_9abc_def0u64;
        let mut next = || {
            state = crate::sim::noise::mix64(state);
            state
        };
        for i in 0..200_000u64 {
            let bits = next();
            // Random magnitudes over the whole fast range and beyond, and grid-like values.
            let v = match i % 3 {
                0 => {
                    f64::from_bits(bits >> 2 | 0x3000_0000_0000_0000)
                        * if bits & 1 == 0 { 1.0 } else { -1.0 }
                }
                1 => 10f64.powf((bits % 10_000) as f64 / 10_000.0 * 50.0 - 12.0),
                _ => 0.45 + (bits % 1_000_000) as f64 * (0.5 / 999_999.0),
            };
            assert_eq!(round15(v).to_bits(), slow(v).to_bits(), "{v:e}");
        }
        for v in [
            0.1 + 0.2,
            0.45 + 3.0 * 0.01,
            9.999999999999999e2,
            1e15,
            5e-324,
            1e300,
        ] {
            assert_eq!(round15(v).to_bits(), slow(v).to_bits(), "{v:e}");
        }
        assert_eq!(round15(0.0), 0.0);
        assert!(round15(f64::NAN).is_nan());
    }
}
