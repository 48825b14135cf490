//! The run's own noise stream (model.md §4): sample `k` of the measured displacement gets
//! `sqrt(P / Ts) * N_k`, with `N_k` a standard normal built from the `k`-th 64-bit output of a
//! PCG-64 stream by the inverse normal CDF. One output per sample, so sample `k` depends only on
//! the stream and `k`: the generator jumps over samples outside positive half-cycles
//! (`Pcg64::advance`, O(log k)) instead of drawing them, a run draws exactly the outputs of the
//! samples it reads, and it computes the normal deviate only for the samples that can be a
//! half-cycle's largest ([`NoisyPeak`]).
//!
//! Its settings, power and sample time ([`NoiseSettings`]), live here too: a leaf below the
//! scenes, re-exported by [`crate::sim`].

use rand_core::Rng;
use rand_pcg::Pcg64;
use serde::Serialize;

use crate::model::RangeError;

/// SplitMix64 finaliser ([`crate::numeric::mix64`]).
pub use crate::numeric::mix64;
/// The uniform number in `(0, 1)` a sample's 64 bits stand for ([`crate::numeric::open_uniform`]).
pub use crate::numeric::open_uniform as uniform;

/// Band-limited white noise on the measured displacement, Simulink style (model.md §4):
/// independent Gaussian samples every `sample_time` seconds with variance `power / sample_time`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NoiseSettings {
    /// Noise power `P` (m^2 s), `>= 0`.
    pub power: f64,
    /// Sample time `Ts` (s), `> 0`.
    pub sample_time: f64,
}

impl NoiseSettings {
    /// Checks `power >= 0` and `sample_time > 0`, both finite.
    pub fn validate(&self) -> Result<(), RangeError> {
        if !(self.power.is_finite() && self.power >= 0.0) {
            return Err(RangeError::new(
                "power",
                self.power,
                "the noise power must be a finite number >= 0 (m^2 s)",
            ));
        }
        if !(self.sample_time.is_finite() && self.sample_time > 0.0) {
            return Err(RangeError::new(
                "sample_time",
                self.sample_time,
                "the sample time must be a finite number > 0 (s)",
            ));
        }
        Ok(())
    }
}

impl NoiseSettings {
    /// Standard deviation of one sample, `sqrt(P / Ts)` (m).
    #[inline]
    pub fn sd(&self) -> f64 {
        (self.power / self.sample_time).sqrt()
    }
}

/// The standard normal deviate at probability `u`, by the inverse normal CDF.
#[inline]
pub fn normal(u: f64) -> f64 {
    -std::f64::consts::SQRT_2 * statrs::function::erf::erfc_inv(2.0 * u)
}

/// The largest noisy sample `x_k + sd N_k` of a positive half-cycle (model.md §4), fed the clean
/// displacements `x_k` in increasing `k` and flushed at the half-cycle's end.
///
/// Drawing the normal deviate (an inverse CDF) costs far more than the sample itself, and only
/// samples near the top can win. So each block of samples draws only its 64-bit outputs, takes
/// the noisy value `c0` of the samples with the largest `x` and the largest output (and the
/// running best), and computes the deviate of sample `i` only where the output's probability
/// `u_i` exceeds `Phi((c0 - x_i) / sd)` (from a table, rounded down to its grid, with relative
/// margins of 1e-9): every other sample is smaller than `c0` whatever the rounding, so the
/// result (value and time, ties to the earliest, as one sample at a time would give) is the
/// same bits as drawing them all. Near the peak a few samples of a half-cycle need their
/// deviate; far from it one in thousands does.
#[derive(Debug)]
pub(crate) struct NoisyPeak {
    n: usize,
    /// Sample index, clean displacement and the probability of its deviate, per sample.
    ks: [u64; Self::BLOCK],
    xs: [f64; Self::BLOCK],
    us: [f64; Self::BLOCK],
    /// The samples with the largest `x` and the largest `u` so far in the block.
    ix: usize,
    iu: usize,
}

impl Default for NoisyPeak {
    fn default() -> Self {
        NoisyPeak {
            n: 0,
            ks: [0; Self::BLOCK],
            xs: [0.0; Self::BLOCK],
            us: [0.0; Self::BLOCK],
            ix: 0,
            iu: 0,
        }
    }
}

impl NoisyPeak {
    /// Samples held before a flush (a positive half-cycle of the paper's study has about 50);
    /// at most 64, the bits of [`NoisyPeak::flush`]'s mask.
    const BLOCK: usize = 64;

    /// Adds sample `k` with clean displacement `x` (its stream output is drawn now); flushes a
    /// full block into `best`.
    #[inline]
    pub(crate) fn push(
        &mut self,
        k: u64,
        x: f64,
        stream: &mut NoiseStream,
        ns: &NoiseSettings,
        best: &mut Option<(f64, f64)>,
    ) {
        let n = self.n;
        let u = uniform(stream.bits(k));
        self.ks[n] = k;
        self.xs[n] = x;
        self.us[n] = u;
        if n == 0 || x > self.xs[self.ix] {
            self.ix = n;
        }
        if n == 0 || u > self.us[self.iu] {
            self.iu = n;
        }
        self.n = n + 1;
        if self.n == Self::BLOCK {
            self.flush(ns, best);
        }
    }

    /// Resolves the samples held into `best` (value, time), keeping the earliest of equal
    /// values, and empties the block.
    pub(crate) fn flush(&mut self, ns: &NoiseSettings, best: &mut Option<(f64, f64)>) {
        let n = self.n;
        if n == 0 {
            return;
        }
        self.n = 0;
        let sd = ns.sd();
        let (ix, iu) = (self.ix, self.iu);
        let (xs, us) = (&self.xs, &self.us);
        let noisy = |i: usize| xs[i] + normal(us[i]) * sd;
        let (cx, cu) = (noisy(ix), noisy(iu));
        let xmax = xs[ix];
        let mut c0 = cx.max(cu);
        if let Some((b, _)) = *best {
            c0 = c0.max(b);
        }
        // Sample i can reach c0 only if its deviate exceeds (c0 - x_i - margin) / sd; the
        // table bounds that deviate's probability from below, first for the whole block
        // (x_i <= max x), then per sample.
        let bounded = sd > 0.0 && sd.is_finite() && c0.is_finite() && xmax.is_finite();
        let margin = 1e-9 * (c0.abs() + xmax.abs() + sd);
        let inv_sd = 1.0 / sd;
        let table = phi_table();
        let block = if bounded {
            table.below((c0 - xmax - margin) * inv_sd)
        } else {
            f64::NEG_INFINITY
        };
        // The samples past the block's bound, as a bit mask (a loop without branches over the
        // whole array, the stale entries past `n` masked off), then those alone in increasing
        // `i`: the same samples in the same order as testing each in turn.
        let mut mask = 0u64;
        for (i, u) in us.iter().enumerate() {
            mask |= u64::from(*u > block) << i;
        }
        if n < Self::BLOCK {
            mask &= (1u64 << n) - 1;
        }
        mask |= (1u64 << ix) | (1u64 << iu);
        while mask != 0 {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let c = if i == ix {
                cx
            } else if i == iu {
                cu
            } else if !bounded || us[i] > table.below((c0 - xs[i] - margin) * inv_sd) {
                noisy(i)
            } else {
                continue;
            };
            if !matches!(*best, Some((b, _)) if c <= b) {
                *best = Some((c, self.ks[i] as f64 * ns.sample_time));
            }
        }
    }
}

/// The standard normal CDF on a grid, each value lowered by a relative 1e-9 (far beyond the
/// rounding of `erfc`), so that `below(z) <= Phi(z)` for every `z`: a probability `u` at or
/// under it has a deviate `normal(u) <= z`.
struct PhiTable {
    phi: [f64; PhiTable::N],
}

impl PhiTable {
    const Z0: f64 = -9.0;
    const STEP: f64 = 0.0625;
    const N: usize = 289; // -9 to +9

    fn new() -> Self {
        let mut phi = [0.0; Self::N];
        for (j, p) in phi.iter_mut().enumerate() {
            let z = Self::Z0 + j as f64 * Self::STEP;
            *p = 0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2) * (1.0 - 1e-9);
        }
        PhiTable { phi }
    }

    /// A lower bound of `Phi(z)`: the table at the grid point at or below `z` (0 below the
    /// grid, and for NaN; the top entry above it).
    #[inline]
    fn below(&self, z: f64) -> f64 {
        let j = (z - Self::Z0) * (1.0 / Self::STEP);
        if j >= 0.0 {
            self.phi[j.min((Self::N - 1) as f64) as i64 as usize]
        } else {
            0.0
        }
    }
}

fn phi_table() -> &'static PhiTable {
    static TABLE: std::sync::OnceLock<PhiTable> = std::sync::OnceLock::new();
    TABLE.get_or_init(PhiTable::new)
}

/// A seeded noise stream for one run.
#[derive(Clone, Debug)]
pub struct NoiseStream {
    rng: Pcg64,
    pos: u64,
    draws: u64,
}

impl NoiseStream {
    /// The stream for (study seed, noise seed, design point): every part changes the stream;
    /// the same triple always gives the same stream.
    pub fn new(study_seed: u64, noise_seed: u64, point: u64) -> Self {
        let a = mix64(study_seed ^ mix64(noise_seed));
        let b = mix64(a ^ mix64(point.wrapping_add(0x5EED)));
        let state = (u128::from(a) << 64) | u128::from(b);
        let stream = (u128::from(mix64(b)) << 64) | u128::from(mix64(a ^ b));
        NoiseStream {
            rng: Pcg64::new(state, stream),
            pos: 0,
            draws: 0,
        }
    }

    /// Noise of sample `k` (m); samples must be asked in increasing `k`.
    pub fn sample(&mut self, k: u64, ns: &NoiseSettings) -> f64 {
        normal(uniform(self.bits(k))) * ns.sd()
    }

    /// The 64-bit output behind sample `k`; samples must be asked in increasing `k`.
    #[inline]
    pub fn bits(&mut self, k: u64) -> u64 {
        if k > self.pos {
            self.rng.advance(u128::from(k - self.pos));
        }
        let bits = self.rng.next_u64();
        self.pos = k + 1;
        self.draws += 1;
        bits
    }

    /// Random numbers drawn so far.
    pub fn draws(&self) -> u64 {
        self.draws
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_top_bits_give_a_finite_deviate() {
        // Before, u64::MAX rounded to u = 1 and an infinite noise sample.
        let top = uniform(u64::MAX);
        assert!(top < 1.0, "{top}");
        assert!(normal(top).is_finite());
        assert!(normal(uniform(0)).is_finite());
        // Every other value is unchanged: just below the top, the formula is exact.
        let below = u64::MAX - (1 << 11);
        assert_eq!(
            uniform(below),
            ((below >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        );
    }

    #[test]
    fn sample_k_does_not_depend_on_skipped_samples() {
        let ns = NoiseSettings {
            power: 1.0,
            sample_time: 1.0,
        };
        let mut all = NoiseStream::new(1, 2, 3);
        let seq: Vec<f64> = (0..10).map(|k| all.sample(k, &ns)).collect();
        let mut skip = NoiseStream::new(1, 2, 3);
        assert_eq!(skip.sample(7, &ns).to_bits(), seq[7].to_bits());
        assert_eq!(skip.sample(9, &ns).to_bits(), seq[9].to_bits());
        assert_eq!(skip.draws(), 2);
    }

    #[test]
    fn samples_are_standard_normal_scaled() {
        let ns = NoiseSettings {
            power: 4e-6,
            sample_time: 1e-4,
        };
        let mut s = NoiseStream::new(7, 0, 0);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|k| s.sample(k, &ns)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let sd = (4e-6f64 / 1e-4).sqrt();
        assert!(mean.abs() < 4.0 * sd / (n as f64).sqrt());
        assert!(
            (var / (sd * sd) - 1.0).abs() < 0.02,
            "var ratio {}",
            var / (sd * sd)
        );
    }

    #[test]
    fn noisy_peak_equals_drawing_every_sample() {
        // Against the one-at-a-time rule (a later sample must be strictly larger), over blocks
        // that span several flushes, noise from none to far above the signal, and plateaus
        // (equal x) that make ties.
        for case in 0..240u64 {
            let ns = NoiseSettings {
                power: [0.0, 1e-14, 5e-10, 1e-5][(case % 4) as usize],
                sample_time: 1e-3,
            };
            let n = 20 + (case * 7) % 200;
            let xs: Vec<f64> = (0..n)
                .map(|i| {
                    let x = 0.03 * (0.05 * i as f64 + case as f64).sin();
                    if case % 3 == 0 {
                        (x * 100.0).round() / 100.0
                    } else {
                        x
                    }
                })
                .collect();
            let k0 = case * 1000;
            let mut one = NoiseStream::new(5, case, 1);
            let mut want: Option<(f64, f64)> = None;
            for (i, x) in xs.iter().enumerate() {
                let k = k0 + i as u64;
                let c = x + one.sample(k, &ns);
                if !matches!(want, Some((b, _)) if c <= b) {
                    want = Some((c, k as f64 * ns.sample_time));
                }
            }
            let mut batch = NoiseStream::new(5, case, 1);
            let mut peak = NoisyPeak::default();
            let mut got = None;
            for (i, x) in xs.iter().enumerate() {
                peak.push(k0 + i as u64, *x, &mut batch, &ns, &mut got);
            }
            peak.flush(&ns, &mut got);
            let bits = |p: Option<(f64, f64)>| p.map(|(c, t)| (c.to_bits(), t.to_bits()));
            assert_eq!(bits(got), bits(want), "case {case}");
            assert_eq!(batch.draws(), n);
        }
    }

    #[test]
    fn seeds_change_the_stream() {
        let ns = NoiseSettings {
            power: 1.0,
            sample_time: 1.0,
        };
        let a = NoiseStream::new(1, 2, 3).sample(0, &ns);
        for (s, n, p) in [(2, 2, 3), (1, 3, 3), (1, 2, 4)] {
            assert_ne!(a, NoiseStream::new(s, n, p).sample(0, &ns));
        }
    }
}
