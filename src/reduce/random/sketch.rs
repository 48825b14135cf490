//! A mergeable quantile sketch with a relative-error guarantee: integer counts in fixed
//! log-spaced bins (the idea of DDSketch, Masson, Rim & Lee 2019), the bins cut by the bits of
//! the `f64` itself so that the bin of a value is exact on every platform.
//!
//! # The bins
//! A non-negative `f64` is `2^e (1 + f)`, `f` in `[0, 1)`; its bin is its exponent and the
//! first [`MANTISSA_BITS`] `= m` bits of `f`: the top `11 + m` bits of its IEEE 754 pattern,
//! `key = bits >> (52 - m)`. Positive `f64` order as their bit patterns, so the keys are
//! monotone in the value; a bin spans `[2^e (1 + j 2^-m), 2^e (1 + (j + 1) 2^-m))`, whose width
//! is at most `2^-m` of its lower end: `2^m = 256` bins per octave, a fixed grid that does not
//! depend on the data. A value `x` is represented by its bin's harmonic midpoint
//! `v = 2 lo hi / (lo + hi)`, so that
//!
//! ```text
//! |v - x| / x <= (hi - lo) / (hi + lo) < 2^-(m + 1) = ALPHA = 1/512 (0.195 %)
//! ```
//!
//! for every normal `x` (above `f64::MIN_POSITIVE`, 2.2e-308; zero is its own bin and exact).
//! Negative values go to a mirrored set of bins.
//!
//! # Merge and determinism
//! A sketch is its counts per bin, exact integers: merging two sketches adds their counts, so
//! the sketch of a set of values is the same bits whatever the order, the chunking or the
//! split it was built in. Memory: 8 bytes per bin between the smallest and the largest key
//! seen (about 2 KB per octave spanned; at most 2^19 bins, 4 MiB, over the whole `f64` range).
//!
//! # Quantiles
//! [`Sketch::quantile`] is [`crate::numeric::quantile_of_ranks`] (the interpolation of the
//! exact quantiles) over the sketch's order statistics: rank 0 and rank `n - 1` are the exact
//! minimum and maximum, kept beside the counts; rank `i` in between is the representative
//! value of the bin holding it, clamped to `[min, max]`. Each order statistic is then within a
//! relative `ALPHA` of the exact one, and so is the interpolation between two of the same sign:
//! the sketch's quantile of non-negative values is within `ALPHA` (0.195 %) of the exact one.

/// Mantissa bits that cut each octave into bins (`2^8 = 256` bins an octave).
pub const MANTISSA_BITS: u32 = 8;

/// The relative-error guarantee of a quantile of non-negative values, `2^-(m + 1)`.
pub const ALPHA: f64 = 1.0 / (1u64 << (MANTISSA_BITS + 1)) as f64;

const SHIFT: u32 = 52 - MANTISSA_BITS;

/// Counts in the bins of one sign of values, dense between the lowest and highest key seen.
#[derive(Clone, Debug, Default, PartialEq)]
struct Bins {
    /// The key of `counts[0]`.
    offset: u64,
    counts: Vec<u64>,
}

impl Bins {
    fn add(&mut self, key: u64, k: u64) {
        if self.counts.is_empty() {
            self.offset = key;
            self.counts.push(0);
        } else if key < self.offset {
            let grow = (self.offset - key) as usize;
            self.counts.splice(0..0, std::iter::repeat_n(0, grow));
            self.offset = key;
        } else if key - self.offset >= self.counts.len() as u64 {
            self.counts.resize((key - self.offset) as usize + 1, 0);
        }
        self.counts[(key - self.offset) as usize] += k;
    }

    /// `(key, count)` of the bins with a count, ascending by key.
    fn iter(&self) -> impl DoubleEndedIterator<Item = (u64, u64)> + '_ {
        self.counts
            .iter()
            .enumerate()
            .filter(|(_, c)| **c > 0)
            .map(|(i, &c)| (self.offset + i as u64, c))
    }
}

/// The representative value of the bin `key` of non-negative values (module doc).
fn representative(key: u64) -> f64 {
    let lo = f64::from_bits(key << SHIFT);
    let hi = f64::from_bits((key + 1) << SHIFT);
    if lo == 0.0 {
        // The bin of zero and the smallest subnormals: zero is exact.
        return 0.0;
    }
    if hi.is_infinite() {
        return lo;
    }
    2.0 * lo * (hi / (lo + hi))
}

/// The sketch of a set of values (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Sketch {
    /// Values `>= 0` by `|x|`'s key, and values `< 0` by `|x|`'s key.
    pos: Bins,
    neg: Bins,
    n: u64,
    min: f64,
    max: f64,
}

impl Default for Sketch {
    fn default() -> Self {
        Sketch {
            pos: Bins::default(),
            neg: Bins::default(),
            n: 0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
}

impl Sketch {
    pub fn new() -> Self {
        Self::default()
    }

    /// Counts `x`; a NaN is left out (as the exact quantiles leave it out).
    pub fn add(&mut self, x: f64) {
        if x.is_nan() {
            return;
        }
        // -0.0 counts as 0.
        let key = x.abs().to_bits() >> SHIFT;
        if x < 0.0 {
            self.neg.add(key, 1);
        } else {
            self.pos.add(key, 1);
        }
        self.n += 1;
        self.min = self.min.min(x);
        self.max = self.max.max(x);
    }

    /// Adds `other`'s counts: the result is the sketch of both sets, whatever the order.
    pub fn merge(&mut self, other: &Sketch) {
        for (k, c) in other.pos.iter() {
            self.pos.add(k, c);
        }
        for (k, c) in other.neg.iter() {
            self.neg.add(k, c);
        }
        self.n += other.n;
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    /// The values counted.
    pub fn count(&self) -> u64 {
        self.n
    }

    /// The order statistic of rank `i` (0-based, `i < n`): exact at both ends, else its bin's
    /// representative clamped to the exact range.
    pub fn at_rank(&self, i: u64) -> f64 {
        if i == 0 {
            return self.min;
        }
        if i + 1 >= self.n {
            return self.max;
        }
        let mut seen = 0u64;
        // The negative values ascend as their magnitude descends.
        for (k, c) in self.neg.iter().rev() {
            seen += c;
            if i < seen {
                return (-representative(k)).clamp(self.min, self.max);
            }
        }
        for (k, c) in self.pos.iter() {
            seen += c;
            if i < seen {
                return representative(k).clamp(self.min, self.max);
            }
        }
        self.max
    }

    /// The quantile `q` in `[0, 1]`, interpolated as the exact one (module doc); NaN when
    /// empty.
    pub fn quantile(&self, q: f64) -> f64 {
        let n = usize::try_from(self.n).unwrap_or(usize::MAX);
        crate::numeric::quantile_of_ranks(n, q, |i| self.at_rank(i as u64))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::quantile;
    use proptest::prelude::*;

    #[test]
    fn the_bins_hold_their_values_within_alpha() {
        for &x in &[
            1e-300,
            3.3e-9,
            0.0123,
            1.0,
            1.0 + 1e-12,
            2.0 - 1e-15,
            7.7e5,
            1e300,
        ] {
            let v = representative(f64::to_bits(x) >> SHIFT);
            assert!(((v - x) / x).abs() < ALPHA, "{x}: {v}");
        }
        assert_eq!(representative(0), 0.0);
        assert_eq!(ALPHA, 1.0 / 512.0);
    }

    #[test]
    fn min_max_and_the_empty_sketch_are_exact() {
        let mut s = Sketch::new();
        assert!(s.quantile(0.5).is_nan());
        for x in [0.5, 0.25, f64::NAN, 4.0, 0.0] {
            s.add(x);
        }
        assert_eq!(s.count(), 4);
        assert_eq!((s.quantile(0.0), s.quantile(1.0)), (0.0, 4.0));
    }

    proptest! {
        #[test]
        fn quantiles_are_within_alpha_and_merge_in_any_order(
            xs in proptest::collection::vec(1e-6f64..1e3, 1..400),
            cut in 0usize..400,
            q in 0.0f64..=1.0,
        ) {
            let mut all = Sketch::new();
            for &x in &xs {
                all.add(x);
            }
            let exact = quantile(&xs, q);
            let got = all.quantile(q);
            prop_assert!(((got - exact) / exact).abs() <= ALPHA, "{got} vs {exact}");
            // Split anywhere, merged either way round: the same bits.
            let cut = cut.min(xs.len());
            let (mut a, mut b) = (Sketch::new(), Sketch::new());
            xs[..cut].iter().for_each(|&x| a.add(x));
            xs[cut..].iter().rev().for_each(|&x| b.add(x));
            let mut ab = a.clone();
            ab.merge(&b);
            b.merge(&a);
            prop_assert_eq!(&ab, &all);
            prop_assert_eq!(&b, &all);
        }

        #[test]
        fn signed_values_keep_their_order(xs in proptest::collection::vec(-1e3f64..1e3, 2..200)) {
            let mut s = Sketch::new();
            xs.iter().for_each(|&x| s.add(x));
            let ranks: Vec<f64> = (0..s.count()).map(|i| s.at_rank(i)).collect();
            prop_assert!(ranks.windows(2).all(|w| w[0] <= w[1]));
        }
    }
}
