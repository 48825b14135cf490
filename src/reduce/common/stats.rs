//! Statistics of one design point (model.md §5): sample mean and SD (eq. 9), lognormal
//! parameters, reliability (eq. 6), safety factor (eq. 7–8), a bootstrap confidence interval of
//! `R` and the Anderson–Darling normality test of `ln xmax`.
//!
//! Everything here is a pure function of numbers; the random generator of the bootstrap is
//! built from a seed the caller passes in.

use rand_pcg::Pcg64Mcg;
use statrs::distribution::{ContinuousCDF, Normal};

/// Mean and sample standard deviation (eq. 9, the `N - 1` form). `(NaN, NaN)` for an empty
/// sample; the SD is NaN for a single value.
pub fn mean_sd(xs: &[f64]) -> (f64, f64) {
    let n = xs.len();
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let mean = xs.iter().sum::<f64>() / n as f64;
    if n == 1 {
        return (mean, f64::NAN);
    }
    let ss: f64 = xs.iter().map(|x| (x - mean) * (x - mean)).sum();
    (mean, (ss / (n - 1) as f64).sqrt())
}

pub use crate::numeric::{median, quantile};

/// Median absolute deviation from the median (unscaled). NaN when empty.
pub fn mad(xs: &[f64]) -> f64 {
    let m = median(xs);
    let dev: Vec<f64> = xs.iter().map(|x| (x - m).abs()).collect();
    median(&dev)
}

/// A lognormal variable by its mean and SD, and its parameters `mu_ln`, `sigma_ln`
/// (model.md §5: `sigma_ln = sqrt(ln(1 + Cv^2))`, `mu_ln = ln(mu) - sigma_ln^2 / 2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogNormal {
    pub mean: f64,
    pub sd: f64,
    pub mu_ln: f64,
    pub sigma_ln: f64,
}

impl LogNormal {
    /// From mean and SD (mean > 0, SD >= 0; otherwise the parameters are NaN).
    pub fn from_mean_sd(mean: f64, sd: f64) -> LogNormal {
        let (mu_ln, sigma_ln) = if mean > 0.0 && sd >= 0.0 {
            let cv = sd / mean;
            let s2 = cv.mul_add(cv, 1.0).ln();
            (mean.ln() - s2 / 2.0, s2.sqrt())
        } else {
            (f64::NAN, f64::NAN)
        };
        LogNormal {
            mean,
            sd,
            mu_ln,
            sigma_ln,
        }
    }

    /// Coefficient of variation `sd / mean`.
    pub fn cv(&self) -> f64 {
        self.sd / self.mean
    }
}

fn std_normal() -> Normal {
    // Infallible: mean 0 and SD 1 are valid parameters.
    Normal::standard()
}

/// Standard normal CDF `Phi`.
pub fn phi(z: f64) -> f64 {
    std_normal().cdf(z)
}

/// Standard normal quantile `Phi^-1`.
pub fn phi_inv(p: f64) -> f64 {
    std_normal().inverse_cdf(p)
}

/// The reliability index `(mu_ln_S - mu_ln_s) / sqrt(sigma_ln_S^2 + sigma_ln_s^2)`: the argument
/// of `Phi` in eq. 6, equal to `-z` with `z = Phi^-1(1 - R)`. Kept apart from `R` because `Phi`
/// rounds to 1 above about 8.3 while the index stays informative.
pub fn reliability_index(strength: &LogNormal, stress: &LogNormal) -> f64 {
    let den = strength.sigma_ln.hypot(stress.sigma_ln);
    let num = strength.mu_ln - stress.mu_ln;
    if den > 0.0 {
        num / den
    } else if num > 0.0 {
        f64::INFINITY
    } else if num < 0.0 {
        f64::NEG_INFINITY
    } else {
        f64::NAN
    }
}

/// Reliability, eq. 6: `R = Phi(reliability_index)`.
pub fn reliability(strength: &LogNormal, stress: &LogNormal) -> f64 {
    phi(reliability_index(strength, stress))
}

/// The combined coefficient of variation of eq. 7:
/// `C_n = sqrt((Cv_S^2 + Cv_s^2) / (1 + Cv_s^2))`.
pub fn c_n(cv_strength: f64, cv_stress: f64) -> f64 {
    ((cv_strength * cv_strength + cv_stress * cv_stress) / (1.0 + cv_stress * cv_stress)).sqrt()
}

/// Shigley's exact relation (eq. 8) with `z = Phi^-1(1 - R)` given directly:
/// `mu_n = exp(-z sqrt(ln(1 + C_n^2)) + ln sqrt(1 + C_n^2))`.
pub fn safety_factor_exact_z(z: f64, cn: f64) -> f64 {
    let l = cn.mul_add(cn, 1.0).ln();
    (-z * l.sqrt() + 0.5 * l).exp()
}

/// Shigley's exact relation from a reliability `R` in (0, 1).
pub fn safety_factor_exact(r: f64, cn: f64) -> f64 {
    safety_factor_exact_z(phi_inv(1.0 - r), cn)
}

/// The paper's small-`C_n` form: `mu_n ≈ exp[C_n (C_n / 2 + beta)]`, `beta` the reliability
/// index (`-z`). It is eq. 8 with `sqrt(ln(1 + C_n^2)) ≈ C_n` and `ln(1 + C_n^2) ≈ C_n^2`.
pub fn safety_factor_paper(beta: f64, cn: f64) -> f64 {
    (cn * (cn / 2.0 + beta)).exp()
}

/// A bootstrap confidence interval of `R` over the cases: `resamples` samples of the same size
/// drawn with replacement from `xs` (stress values, or anything proportional to them, since only
/// the coefficient of variation and the mean enter), `R` of each, and the percentile interval
/// at `confidence`. Deterministic for a fixed `seed`.
///
/// Since `R = Phi(beta)` is monotone in the index `beta`, the percentiles are taken on `beta`
/// and mapped through `Phi`: the same interval, without rounding `R` to 1 along the way.
/// Indices are drawn as `(u32 * n) >> 32` (Lemire's multiply-shift; the bias is below
/// `n / 2^32`, far under the Monte Carlo error) from one `Pcg64Mcg` stream, resample after
/// resample, two resamples at a time ([`PairedStream`]: the same draws, each resample's sums in
/// the same order). `(NaN, NaN)` for fewer than 2 values. Not inlined: inside the reducer's
/// point statistics its sums were kept on the stack.
#[inline(never)]
pub fn bootstrap_reliability(
    xs: &[f64],
    strength: &LogNormal,
    resamples: usize,
    confidence: f64,
    seed: u64,
) -> (f64, f64) {
    let n = xs.len();
    if n < 2 || resamples == 0 {
        return (f64::NAN, f64::NAN);
    }
    let mut stream = PairedStream::new(Pcg64Mcg::new(u128::from(seed) << 1 | 1).state(), n);
    let mut betas = Vec::with_capacity(resamples);
    let index = |draw: u64| ((u64::from(draw as u32) * n as u64) >> 32) as usize;
    // Shift by the first value to keep the sum of squares accurate.
    let shift = xs[0];
    for _ in 0..resamples / 2 {
        let (mut sa, mut s2a, mut sb, mut s2b) = (0.0, 0.0, 0.0, 0.0);
        for _ in 0..n {
            let (i, j) = stream.next_pair();
            let (u, v) = (xs[index(i)] - shift, xs[index(j)] - shift);
            sa += u;
            s2a += u * u;
            sb += v;
            s2b += v * v;
        }
        stream.skip_block();
        betas.push(resample_index(strength, shift, n, sa, s2a));
        betas.push(resample_index(strength, shift, n, sb, s2b));
    }
    if resamples % 2 == 1 {
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let u = xs[index(stream.next_first())] - shift;
            s += u;
            s2 += u * u;
        }
        betas.push(resample_index(strength, shift, n, s, s2));
    }
    let alpha = (1.0 - confidence) / 2.0;
    (
        phi(crate::numeric::quantile_mut(&mut betas, alpha)),
        phi(crate::numeric::quantile_mut(&mut betas, 1.0 - alpha)),
    )
}

/// The reliability index of one resample of `n` values from its sums `s` and `s2` of the values
/// less `shift`: [`reliability_index`] of `LogNormal::from_mean_sd(mean, sd)`, inlined (it runs
/// `resamples` times per design point).
#[inline]
fn resample_index(strength: &LogNormal, shift: f64, n: usize, s: f64, s2: f64) -> f64 {
    let nf = n as f64;
    let mean = shift + s / nf;
    let var = ((s2 - s * s / nf) / (nf - 1.0)).max(0.0);
    let l = (var / (mean * mean)).ln_1p();
    let num = strength.mu_ln - (mean.ln() - l / 2.0);
    let den = (strength.sigma_ln * strength.sigma_ln + l).sqrt();
    if den > 0.0 {
        num / den
    } else {
        num.signum() * f64::INFINITY
    }
}

/// `Pcg64Mcg`'s stream (rand_pcg's `Mcg128Xsl64`: the state times a constant, then the XSL RR
/// output) split into blocks of `block` draws, two consecutive blocks drawn side by side: chain
/// `a` walks one block while chain `b` walks the next, then each jumps over the other's
/// (`state * M^block`). The same draws as the generator's, in two independent multiply chains
/// instead of one, where the 128-bit multiply's latency set the pace: the bootstrap about 1.3
/// times as fast (BENCHMARKS.md, "Reduce").
struct PairedStream {
    a: u128,
    b: u128,
    /// `M^block`, the jump over a block.
    skip: u128,
}

/// rand_pcg's multiplier of `Mcg128Xsl64` (`pcg64_fast`).
const PCG_MULTIPLIER: u128 = 0x2360_ED05_1FC6_5DA4_4385_DF64_9FCC_F645;

impl PairedStream {
    /// The stream of a generator in `state`, in blocks of `block` draws.
    fn new(state: u128, block: usize) -> PairedStream {
        let skip = (0..block).fold(1u128, |m, _| m.wrapping_mul(PCG_MULTIPLIER));
        PairedStream {
            a: state,
            b: state.wrapping_mul(skip),
            skip,
        }
    }

    /// The output of a generator state (rand_pcg's `output_xsl_rr`).
    #[inline(always)]
    fn output(state: u128) -> u64 {
        let rot = (state >> 122) as u32;
        (((state >> 64) as u64) ^ (state as u64)).rotate_right(rot)
    }

    /// The next draw of the first block and of the second.
    #[inline(always)]
    fn next_pair(&mut self) -> (u64, u64) {
        self.a = self.a.wrapping_mul(PCG_MULTIPLIER);
        self.b = self.b.wrapping_mul(PCG_MULTIPLIER);
        (Self::output(self.a), Self::output(self.b))
    }

    /// The next draw of the first block alone (the last, unpaired block).
    #[inline(always)]
    fn next_first(&mut self) -> u64 {
        self.a = self.a.wrapping_mul(PCG_MULTIPLIER);
        Self::output(self.a)
    }

    /// After both blocks are drawn: on to the next two.
    fn skip_block(&mut self) {
        self.a = self.a.wrapping_mul(self.skip);
        self.b = self.b.wrapping_mul(self.skip);
    }
}

/// Anderson–Darling test of normality with mean and variance estimated from the sample
/// (case 3 of Stephens 1974). Returns `(A*^2, p)`:
///
/// * `A^2 = -n - (1/n) Σ_{i=1..n} (2i - 1) [ln Φ(w_i) + ln(1 - Φ(w_{n+1-i}))]`,
///   `w_i = (x_(i) - mean) / sd` over the sorted sample, `sd` with `N - 1`;
/// * the small-sample correction `A*^2 = A^2 (1 + 0.75/n + 2.25/n^2)`;
/// * the p-value from D'Agostino & Stephens (1986, *Goodness-of-fit techniques*, Table 4.9):
///   `A* >= 0.6: exp(1.2937 - 5.709 A* + 0.0186 A*^2)`;
///   `0.34 <= A* < 0.6: exp(0.9177 - 4.279 A* - 1.38 A*^2)`;
///   `0.2 <= A* < 0.34: 1 - exp(-8.318 + 42.796 A* - 59.938 A*^2)`;
///   `A* < 0.2: 1 - exp(-13.436 + 101.14 A* - 223.73 A*^2)`
///   (`A*` here is `A*^2`, the corrected statistic). The first quadratic turns up past its
///   minimum, `A* = 5.709 / (2 * 0.0186) = 153.47` (`p` about `1e-190` there), and would reach 1
///   again near `A* = 307`: beyond the minimum `p` keeps its value there ([`ad_p_value`]), so a
///   sample far from normal never reads as normal.
///
/// `(NaN, NaN)` for fewer than 3 values or a sample without spread (all values equal): a
/// deterministic design point (no noise, no perturbation) has nothing to test.
pub fn anderson_darling(xs: &[f64]) -> (f64, f64) {
    let n = xs.len();
    if n < 3 {
        return (f64::NAN, f64::NAN);
    }
    let (mean, sd) = mean_sd(xs);
    if sd.is_nan() || sd <= 0.0 || !sd.is_finite() {
        return (f64::NAN, f64::NAN);
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let nd = std_normal();
    let nf = n as f64;
    let mut s = 0.0;
    for i in 0..n {
        let lo = nd.cdf((v[i] - mean) / sd).max(f64::MIN_POSITIVE);
        let hi = (1.0 - nd.cdf((v[n - 1 - i] - mean) / sd)).max(f64::MIN_POSITIVE);
        s += (2 * i + 1) as f64 * (lo.ln() + hi.ln());
    }
    let a2 = -nf - s / nf;
    let a = a2 * (1.0 + 0.75 / nf + 2.25 / (nf * nf));
    (a, ad_p_value(a))
}

/// The p-value of the corrected Anderson–Darling statistic `a` (`A*^2`) by D'Agostino &
/// Stephens's four pieces ([`anderson_darling`]), non-increasing in `a`: the first piece's
/// quadratic is held at its minimum beyond it.
pub fn ad_p_value(a: f64) -> f64 {
    /// Where `1.2937 - 5.709 a + 0.0186 a^2` stops falling.
    const TURN: f64 = 5.709 / (2.0 * 0.0186);
    let p = if a >= 0.6 {
        let a = a.min(TURN);
        (1.2937 - 5.709 * a + 0.0186 * a * a).exp()
    } else if a >= 0.34 {
        (0.9177 - 4.279 * a - 1.38 * a * a).exp()
    } else if a >= 0.2 {
        1.0 - (-8.318 + 42.796 * a - 59.938 * a * a).exp()
    } else {
        1.0 - (-13.436 + 101.14 * a - 223.73 * a * a).exp()
    };
    p.clamp(0.0, 1.0)
}

/// Perfectibility, eq. 11: `P = (WF1 R / R_max + WF2 DI / DI_max) * 100` (%). A value equal to
/// its best counts 1 even when the best is 0 (a study whose designs do not damp at all, such as
/// the structure without a damper: `0 / 0` would leave its only design unranked).
pub fn perfectibility(r: f64, di: f64, r_max: f64, di_max: f64, wf1: f64, wf2: f64) -> f64 {
    (wf1 * of_best(r, r_max) + wf2 * of_best(di, di_max)) * 100.0
}

/// `v / best`, 1 when `v` is the best.
pub fn of_best(v: f64, best: f64) -> f64 {
    if v == best { 1.0 } else { v / best }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::Rng;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn mean_sd_uses_n_minus_1_on_table_ii() {
        // model.md §4: the 12 values of Table II have mean 2.667 cm and SD 0.063 cm.
        let xs = [
            2.594, 2.619, 2.550, 2.768, 2.687, 2.645, 2.709, 2.687, 2.653, 2.716, 2.742, 2.637,
        ];
        let (m, s) = mean_sd(&xs);
        assert!(close(m, 2.667, 5e-4), "{m}");
        assert!(close(s, 0.063, 5e-4), "{s}");
    }

    #[test]
    fn shigley_worked_example() {
        // Shigley: strength LN(78.4, 5.90) kpsi, load LN(50, 4.1), R = 0.999 -> C_n = 0.111,
        // mu_n = 1.416.
        let cn = c_n(5.90 / 78.4, 4.1 / 50.0);
        assert!(close(cn, 0.111, 5e-4), "C_n = {cn}");
        let mu = safety_factor_exact(0.999, cn);
        assert!(close(mu, 1.416, 5e-4), "mu_n = {mu}");
        // The paper's form is close at this small C_n but not equal.
        let beta = -phi_inv(0.001);
        let mp = safety_factor_paper(beta, cn);
        assert!(close(mp, mu, 0.01) && mp != mu, "paper form {mp}");
    }

    #[test]
    fn equal_medians_give_one_half() {
        // Equal mu_ln means equal medians: R = 0.5 whatever the spreads.
        let s = LogNormal::from_mean_sd(100.0, 10.0);
        let mut l = LogNormal::from_mean_sd(100.0, 25.0);
        l.mu_ln = s.mu_ln;
        assert!(close(reliability(&s, &l), 0.5, 1e-12));
        // And by the mean/SD route: same mean, same Cv -> same parameters.
        let a = LogNormal::from_mean_sd(50.0, 5.0);
        assert!(close(reliability(&a, &a), 0.5, 1e-12));
    }

    #[test]
    fn lognormal_parameters_round_trip() {
        let l = LogNormal::from_mean_sd(3.0, 0.6);
        let mean = (l.mu_ln + l.sigma_ln * l.sigma_ln / 2.0).exp();
        let var = (l.sigma_ln * l.sigma_ln).exp_m1() * mean * mean;
        assert!(close(mean, 3.0, 1e-12));
        assert!(close(var.sqrt(), 0.6, 1e-12));
    }

    #[test]
    fn reliability_grows_with_the_margin() {
        let strength = LogNormal::from_mean_sd(300.0, 24.0);
        let near = LogNormal::from_mean_sd(250.0, 5.0);
        let far = LogNormal::from_mean_sd(200.0, 5.0);
        let (a, b) = (reliability(&strength, &near), reliability(&strength, &far));
        assert!(0.5 < a && a < b && b < 1.0, "{a} {b}");
    }

    #[test]
    fn eq11_on_table_iii() {
        // model.md §6: Table III's R and DI give 100 % and 90.1 % for zones I and II, and
        // about 75 % (not the printed 67.6 %) for zone III.
        let zones = [(0.9965, 0.0361), (0.9737, 0.0298), (0.9861, 0.0187)];
        let rmax = zones.iter().map(|z| z.0).fold(f64::MIN, f64::max);
        let dmax = zones.iter().map(|z| z.1).fold(f64::MIN, f64::max);
        let p: Vec<f64> = zones
            .iter()
            .map(|&(r, d)| perfectibility(r, d, rmax, dmax, 0.5, 0.5))
            .collect();
        assert!(close(p[0], 100.0, 1e-9));
        assert!(close(p[1], 90.1, 0.05), "{}", p[1]);
        assert!(close(p[2], 75.4, 0.05), "{}", p[2]);
        assert!((p[2] - 67.6).abs() > 5.0);
    }

    #[test]
    fn bootstrap_is_deterministic_and_brackets_r() {
        let xs: Vec<f64> = (0..12)
            .map(|i| 2.6 + 0.01 * ((i * 7) % 12) as f64)
            .collect();
        let strength = LogNormal::from_mean_sd(2.9, 0.1);
        let (m, s) = mean_sd(&xs);
        let r = reliability(&strength, &LogNormal::from_mean_sd(m, s));
        let a = bootstrap_reliability(&xs, &strength, 2000, 0.95, 42);
        let b = bootstrap_reliability(&xs, &strength, 2000, 0.95, 42);
        let c = bootstrap_reliability(&xs, &strength, 2000, 0.95, 43);
        assert_eq!(a.0.to_bits(), b.0.to_bits());
        assert_eq!(a.1.to_bits(), b.1.to_bits());
        assert_ne!(
            (a.0.to_bits(), a.1.to_bits()),
            (c.0.to_bits(), c.1.to_bits())
        );
        assert!(a.0 < r && r < a.1, "{a:?} vs {r}");
        assert!(a.1 - a.0 > 1e-4);
    }

    /// The bootstrap as it was written first: one generator, one resample after the other.
    fn bootstrap_one_stream(
        xs: &[f64],
        strength: &LogNormal,
        resamples: usize,
        confidence: f64,
        seed: u64,
    ) -> (f64, f64) {
        let n = xs.len();
        let mut rng = Pcg64Mcg::new(u128::from(seed) << 1 | 1);
        let mut betas = Vec::with_capacity(resamples);
        let shift = xs[0];
        for _ in 0..resamples {
            let (mut s, mut s2) = (0.0, 0.0);
            for _ in 0..n {
                let i = ((u64::from(rng.next_u32()) * n as u64) >> 32) as usize;
                let v = xs[i] - shift;
                s += v;
                s2 += v * v;
            }
            betas.push(resample_index(strength, shift, n, s, s2));
        }
        let alpha = (1.0 - confidence) / 2.0;
        (
            phi(crate::numeric::quantile_mut(&mut betas, alpha)),
            phi(crate::numeric::quantile_mut(&mut betas, 1.0 - alpha)),
        )
    }

    #[test]
    fn the_paired_stream_is_the_generators_stream_and_the_bootstrap_its_bits() {
        // The two chains' draws, block after block, are the generator's own.
        for (seed, block) in [(1u64, 1usize), (42, 2), (7, 5), (3, 28), (99, 101)] {
            let mut rng = Pcg64Mcg::new(u128::from(seed) << 1 | 1);
            let mut paired = PairedStream::new(rng.state(), block);
            for _ in 0..4 {
                let (mut first, mut second) = (Vec::new(), Vec::new());
                for _ in 0..block {
                    let (a, b) = paired.next_pair();
                    first.push(a);
                    second.push(b);
                }
                paired.skip_block();
                let from_rng: Vec<u64> = (0..2 * block).map(|_| rng.next_u64()).collect();
                assert_eq!(
                    [first, second].concat(),
                    from_rng,
                    "seed {seed}, block {block}"
                );
            }
            assert_eq!(paired.next_first(), rng.next_u64());
        }
        // The bootstrap's interval: the bits of one stream drawn resample after resample, for
        // even and odd resample counts and small and large samples.
        let strength = LogNormal::from_mean_sd(2.9, 0.1);
        for (n, resamples, seed) in [(2, 4000, 1), (12, 2000, 42), (28, 1999, 5), (29, 7, 9)] {
            let xs: Vec<f64> = (0..n)
                .map(|i| 2.6 + 0.013 * ((i * 7) % 11) as f64)
                .collect();
            let a = bootstrap_reliability(&xs, &strength, resamples, 0.95, seed);
            let b = bootstrap_one_stream(&xs, &strength, resamples, 0.95, seed);
            assert_eq!(
                (a.0.to_bits(), a.1.to_bits()),
                (b.0.to_bits(), b.1.to_bits()),
                "n {n}, resamples {resamples}"
            );
        }
    }

    #[test]
    fn bootstrap_index_agrees_with_the_lognormal_route() {
        // The inlined index in the bootstrap equals reliability_index on the same sample: with
        // all resamples equal to the sample itself (n values all equal but one), compare R.
        let strength = LogNormal::from_mean_sd(2.9, 0.1);
        let xs = [2.7, 2.8];
        let (lo, hi) = bootstrap_reliability(&xs, &strength, 4000, 0.5, 1);
        // Resamples are {2.7,2.7}, {2.8,2.8} (SD 0) or {2.7,2.8}: R of the mixed one lies
        // between the two extremes, and the interval's ends are among the three values.
        let r = |a: f64, b: f64| {
            let (m, s) = mean_sd(&[a, b]);
            reliability(&strength, &LogNormal::from_mean_sd(m, s))
        };
        let cands = [r(2.7, 2.7), r(2.8, 2.8), r(2.7, 2.8)];
        for v in [lo, hi] {
            assert!(
                cands.iter().any(|c| (c - v).abs() < 1e-12),
                "{v} not in {cands:?}"
            );
        }
    }

    #[test]
    fn anderson_darling_matches_scipy_statistic() {
        // Reference: scipy.stats.anderson(x, 'norm').statistic = 0.12318936065918074 (uncorrected A^2)
        // for this sample; the corrected statistic multiplies by 1 + 0.75/n + 2.25/n^2.
        let x = [
            2.594, 2.619, 2.550, 2.768, 2.687, 2.645, 2.709, 2.687, 2.653, 2.716, 2.742, 2.637,
        ];
        let (a, p) = anderson_darling(&x);
        let n = 12.0;
        let a2 = a / (1.0 + 0.75 / n + 2.25 / (n * n));
        assert!(close(a2, SCIPY_A2_TABLE_II, 1e-6), "A^2 = {a2}");
        assert!(p > 0.5, "p = {p}");
    }

    // scipy 1.x `stats.anderson(x, 'norm').statistic` (it uses the N - 1 SD too).
    const SCIPY_A2_TABLE_II: f64 = 0.123_189_360_659_180_74;

    #[test]
    fn anderson_darling_rejects_a_skewed_sample() {
        // Exponential quantiles: clearly not normal.
        let x: Vec<f64> = (1..=30)
            .map(|i| -(1.0 - (i as f64 - 0.5) / 30.0).ln())
            .collect();
        let (a, p) = anderson_darling(&x);
        // scipy: A^2 = 1.3651631045048944.
        let a2 = a / (1.0 + 0.75 / 30.0 + 2.25 / 900.0);
        assert!(close(a2, 1.365_163_104_504_894_4, 1e-6), "A^2 = {a2}");
        assert!(p < 0.01, "A* = {a}, p = {p}");
        assert!(anderson_darling(&[1.0, 1.0, 1.0]).0.is_nan());
    }

    /// The p-value never rises with the statistic: D'Agostino & Stephens's first quadratic turned
    /// up past A* = 153.5 and read 1 again from about 307 (a 10^6-realization sample far from
    /// lognormal read `ad_p = 1` at A* = 596).
    #[test]
    fn the_anderson_darling_p_value_falls_with_the_statistic() {
        let mut last = 1.0;
        for k in 0..100_000 {
            let a = k as f64 * 0.01;
            let p = ad_p_value(a);
            assert!(p <= last, "p({a}) = {p:e} rises from {last:e}");
            last = p;
        }
        assert!(ad_p_value(596.0) < 1e-150);
        // A sample of 10^5 values far from normal (a two-point mixture).
        let x: Vec<f64> = (0..100_000)
            .map(|i| f64::from(i % 2) + 1e-6 * f64::from(i % 7))
            .collect();
        let (a, p) = anderson_darling(&x);
        assert!(a > 1000.0 && p < 1e-150, "A* = {a}, p = {p:e}");
    }
}
