//! The run's own noise stream (model.md §4): sample `k` of the measured displacement gets
//! `sqrt(P / Ts) * N_k`, with `N_k` a standard normal built from the `k`-th 64-bit output of a
//! PCG-64 stream by the inverse normal CDF. One output per sample, so sample `k` depends only on
//! the stream and `k`: the generator jumps over samples outside positive half-cycles
//! (`Pcg64::advance`, O(log k)) instead of drawing them, and a run draws exactly the samples it
//! reads.

use rand_core::Rng;
use rand_pcg::Pcg64;

use super::NoiseSettings;

/// A seeded noise stream for one run.
#[derive(Clone, Debug)]
pub struct NoiseStream {
    rng: Pcg64,
    pos: u64,
    draws: u64,
}

/// SplitMix64 finaliser: a bijective 64-bit mixer (Steele, Lea & Flood 2014).
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
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
        if k > self.pos {
            self.rng.advance(u128::from(k - self.pos));
        }
        let bits = self.rng.next_u64();
        self.pos = k + 1;
        self.draws += 1;
        // Uniform in (0, 1), never 0 or 1.
        let u = ((bits >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64);
        let z = -std::f64::consts::SQRT_2 * statrs::function::erf::erfc_inv(2.0 * u);
        z * (ns.power / ns.sample_time).sqrt()
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
