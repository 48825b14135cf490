//! Small numeric helpers shared by the whole crate: the one median, the one quantile, the
//! one linspace (a grid computed from the index, never accumulated), the one quadrature
//! ([`gauss_legendre_n`], what the forced and random scenes integrate their motion with), and
//! the one way random bits become numbers ([`mix64`] for seeds, [`open_uniform`] and
//! [`inverse_normal`] for deviates).

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
    quantile_of_ranks(sorted.len(), q, |i| sorted[i])
}

/// [`quantile_sorted`] of `n` values sorted ascending, the `i`-th read as `at(i)`: the same
/// interpolation for a caller that holds only the order statistics it reads (ranks
/// `floor((n - 1) q)` and the next). NaN when `n` is 0.
pub fn quantile_of_ranks(n: usize, q: f64, at: impl Fn(usize) -> f64) -> f64 {
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let a = at(lo);
    let frac = h - lo as f64;
    if lo + 1 < n && frac != 0.0 {
        a + frac * (at(lo + 1) - a)
    } else {
        a
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

/// `(int f.0, int f.1)` over `[a, b]` by 8-point Gauss–Legendre on pieces at most `h_max` long
/// ([`gauss_legendre_n`] with two integrands).
pub fn gauss_legendre(a: f64, b: f64, h_max: f64, f: impl Fn(f64) -> (f64, f64)) -> (f64, f64) {
    let [s0, s1] = gauss_legendre_n(a, b, h_max, |t| {
        let (p, q) = f(t);
        [p, q]
    });
    (s0, s1)
}

/// `int f_i` over `[a, b]` for each of the `N` integrands of `f`, by 8-point Gauss–Legendre on
/// pieces at most `h_max` long. On a smooth motion with pieces at most 1/16 of its fastest
/// period the error is at rounding (the rule is exact for polynomials of degree 15; on a sine
/// over 1/16 of its period its error is about `(2 pi / 16)^16 / 16! = 2e-20` of it).
pub fn gauss_legendre_n<const N: usize>(
    a: f64,
    b: f64,
    h_max: f64,
    f: impl Fn(f64) -> [f64; N],
) -> [f64; N] {
    // Nodes and weights of 8-point Gauss–Legendre on [-1, 1] (positive half).
    const X: [f64; 4] = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_2,
    ];
    const W: [f64; 4] = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let mut s = [0.0; N];
    if b <= a {
        return s;
    }
    let pieces = ((b - a) / h_max).ceil().max(1.0) as u64;
    let h = (b - a) / pieces as f64;
    for i in 0..pieces {
        let lo = a + i as f64 * h;
        let hi = if i + 1 == pieces { b } else { lo + h };
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        for (x, w) in X.iter().zip(W) {
            let p = f(mid - half * x);
            let q = f(mid + half * x);
            for k in 0..N {
                s[k] += w * half * (p[k] + q[k]);
            }
        }
    }
    s
}

/// `int f_i` over `[a, b]` for each of the `N` integrands of `f` by one 5-point Gauss–Legendre
/// rule: exact for polynomials of degree 9, and off by
/// `(b - a)^11 (5!)^4 / (11 (10!)^3) |f^(10)| = 3.9e-13 (b - a)^11 |f^(10)|` at most. For the
/// square of a motion whose derivatives are bounded by `B rho^j` (`j >= 2`) on a piece with
/// `rho (b - a) <= 0.1`, `|f^(10)| <= 2^10 rho^10 B'^2` (`B'` the bound of the motion and of
/// `x' / rho` with its linear part), so the error is below `4e-20 (b - a) B'^2`, a ten-thousandth
/// of the rounding of the integral itself.
pub fn gauss_legendre_5<const N: usize>(a: f64, b: f64, f: impl Fn(f64) -> [f64; N]) -> [f64; N] {
    const X: [f64; 2] = [0.538_469_310_105_683, 0.906_179_845_938_664];
    const W: [f64; 2] = [0.478_628_670_499_366_5, 0.236_926_885_056_189_1];
    const W0: f64 = 0.568_888_888_888_888_9;
    let mut s = [0.0; N];
    if b <= a {
        return s;
    }
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let c = f(mid);
    for k in 0..N {
        s[k] += W0 * half * c[k];
    }
    for (x, w) in X.iter().zip(W) {
        let p = f(mid - half * x);
        let q = f(mid + half * x);
        for k in 0..N {
            s[k] += w * half * (p[k] + q[k]);
        }
    }
    s
}

/// The uniform number in `(0, 1)` 64 random bits stand for: the top 53 bits plus a half. It
/// never decreases with `bits`. Rounding would make the very top value (a chance of 2^-53)
/// exactly 1, whose normal deviate is infinite; it is held at the largest `f64` below 1, which
/// changes no other value.
#[inline]
pub fn open_uniform(bits: u64) -> f64 {
    // (Through i64: the same value, a cheaper conversion than from u64 on x86-64.)
    let u = (((bits >> 11) as i64) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64);
    u.min(1.0 - f64::EPSILON / 2.0)
}

/// SplitMix64 finaliser: a bijective 64-bit mixer (Steele, Lea & Flood 2014), what every seed
/// of the crate is derived with.
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The standard normal quantile at `p` in `(0, 1)`: Wichura's algorithm AS 241 (PPND16,
/// Applied Statistics 37 (1988) 477–484), relative error about `1e-16`: a rational function in
/// the centre (`|p - 0.5| <= 0.425`) and of `sqrt(-ln(min(p, 1 - p)))` in the tails.
/// The coefficients are the published ones, some with more digits than an `f64` holds.
#[inline]
#[allow(clippy::excessive_precision)]
pub fn inverse_normal(p: f64) -> f64 {
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180625 - q * q;
        let num = ((((((2.509_080_928_730_122_7e3 * r + 3.343_057_558_358_813e4) * r
            + 6.726_577_092_700_87e4)
            * r
            + 4.592_195_393_154_987e4)
            * r
            + 1.373_169_376_550_946e4)
            * r
            + 1.971_590_950_306_551_3e3)
            * r
            + 1.331_416_678_917_843_8e2)
            * r
            + 3.387_132_872_796_366_5;
        let den = ((((((5.226_495_278_852_545e3 * r + 2.872_908_573_572_194_3e4) * r
            + 3.930_789_580_009_271e4)
            * r
            + 2.121_379_430_158_659_7e4)
            * r
            + 5.394_196_021_424_751e3)
            * r
            + 6.871_870_074_920_579e2)
            * r
            + 4.231_333_070_160_091e1)
            * r
            + 1.0;
        return q * num / den;
    }
    let r = if q < 0.0 { p } else { 1.0 - p };
    let r = (-r.ln()).sqrt();
    let val = if r <= 5.0 {
        let r = r - 1.6;
        let num = ((((((7.745_450_142_783_414e-4 * r + 2.272_384_498_926_918_4e-2) * r
            + 2.417_807_251_774_506e-1)
            * r
            + 1.270_458_252_452_368_4)
            * r
            + 3.647_848_324_763_204_5)
            * r
            + 5.769_497_221_460_691)
            * r
            + 4.630_337_846_156_545)
            * r
            + 1.423_437_110_749_683_5;
        let den = ((((((1.050_750_071_644_416_9e-9 * r + 5.475_938_084_995_345e-4) * r
            + 1.519_866_656_361_645_7e-2)
            * r
            + 1.481_039_764_274_800_8e-1)
            * r
            + 6.897_673_349_851e-1)
            * r
            + 1.676_384_830_183_803_8)
            * r
            + 2.053_191_626_637_758_8)
            * r
            + 1.0;
        num / den
    } else {
        let r = r - 5.0;
        let num = ((((((2.010_334_399_292_288_1e-7 * r + 2.711_555_568_743_487_6e-5) * r
            + 1.242_660_947_388_078_4e-3)
            * r
            + 2.653_218_952_657_612_4e-2)
            * r
            + 2.965_605_718_285_048_7e-1)
            * r
            + 1.784_826_539_917_291_3)
            * r
            + 5.463_784_911_164_114)
            * r
            + 6.657_904_643_501_103;
        let den = ((((((2.044_263_103_389_939_7e-15 * r + 1.421_511_758_316_446e-7) * r
            + 1.846_318_317_510_054_8e-5)
            * r
            + 7.868_691_311_456_133e-4)
            * r
            + 1.487_536_129_085_061_5e-2)
            * r
            + 1.369_298_809_227_358e-1)
            * r
            + 5.998_322_065_558_879e-1)
            * r
            + 1.0;
        num / den
    };
    if q < 0.0 { -val } else { val }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_normal_agrees_with_the_erfc_inverse() {
        // Against statrs's inverse erfc (what the measurement noise uses), over the centre, the
        // tails and the extreme probabilities a 53-bit uniform can give.
        let mut ps: Vec<f64> = (1..1000).map(|i| i as f64 / 1000.0).collect();
        ps.extend([
            1e-300, 1e-100, 1e-20, 1e-10, 1e-5, 0.0749, 0.075, 0.0751, 0.925, 0.9251,
        ]);
        ps.extend([
            1.0 - 1e-10,
            1.0 - 1.1e-16,
            open_uniform(0),
            open_uniform(u64::MAX),
        ]);
        for p in ps {
            let (a, b) = (inverse_normal(p), crate::sim::noise::normal(p));
            let tol = 4e-15 * b.abs().max(1.0);
            assert!((a - b).abs() <= tol, "p = {p:e}: {a} vs {b}");
        }
    }

    #[test]
    fn five_point_gauss_legendre_is_exact_to_degree_nine_and_no_further() {
        let (a, b) = (0.3f64, 1.7f64);
        let exact = |n: i32| (b.powi(n + 1) - a.powi(n + 1)) / f64::from(n + 1);
        for n in 0..=9 {
            let [i] = gauss_legendre_5(a, b, |t| [t.powi(n)]);
            assert!(
                (i - exact(n)).abs() <= 8.0 * f64::EPSILON * exact(n),
                "degree {n}"
            );
        }
        let [i] = gauss_legendre_5(a, b, |t| [t.powi(10)]);
        assert!((i - exact(10)).abs() > 1e-6 * exact(10));
        assert_eq!(gauss_legendre_5(b, a, |t| [t]), [0.0]);
    }

    #[test]
    fn gauss_legendre_is_exact_for_trigonometric_pieces() {
        let w = 63.0;
        let (a, b) = (0.013, 0.4);
        let (i0, i1) = gauss_legendre(a, b, std::f64::consts::TAU / w / 16.0, |t| {
            ((w * t).cos(), (w * t).sin().powi(2))
        });
        let e0 = ((w * b).sin() - (w * a).sin()) / w;
        let e1 = 0.5 * (b - a) - ((2.0 * w * b).sin() - (2.0 * w * a).sin()) / (4.0 * w);
        assert!((i0 - e0).abs() <= 1e-15, "{i0} {e0}");
        assert!((i1 - e1).abs() <= 1e-15 * e1.abs().max(1.0), "{i1} {e1}");
    }

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
