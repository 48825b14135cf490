//! The percentile bootstrap over a design's motions (model.md §13, docs/scenes.md): the one
//! resampling that the capacities' fragility ([`super::capacity`]) and the stripes' annual
//! risk ([`crate::reduce::random::stripes`]) share.
//!
//! [`RESAMPLES`] resamples of the `n` motions, each `n` indices drawn with replacement
//! (`u mod n` of a PCG-64 stream seeded from `seed` alone); a statistic of each resample; the
//! 2.5 % and 97.5 % quantiles of each of its values (NaN values left out). The stream depends on
//! the seed and `n` only, so designs with the same motions resample the same motions (common
//! random numbers), and a study of one design alone reproduces its intervals.

use rand_core::Rng;
use rand_pcg::Pcg64;

use crate::numeric::{mix64, quantile};

/// Bootstrap resamples.
pub const RESAMPLES: usize = 400;

/// The percentile bootstrap (module doc) of `stat` over resamples of `n` motions seeded by
/// `seed`: `stat` gets each resample's indices (`0..n`, with repeats) and returns its values;
/// the result is `(lo, hi)` of each value. Empty when `n` is 0.
pub fn percentile(
    n: usize,
    seed: u64,
    mut stat: impl FnMut(&[usize]) -> Vec<f64>,
) -> Vec<(f64, f64)> {
    let mut rng = Pcg64::new(
        u128::from(mix64(seed)) << 64 | u128::from(mix64(seed ^ 0xB007)),
        0xa02b_dbf7_bb3c_0a7a_c28f_a16a_64ab_f96b,
    );
    let mut draws: Vec<Vec<f64>> = Vec::with_capacity(RESAMPLES);
    let mut idx = vec![0usize; n];
    if n > 0 {
        for _ in 0..RESAMPLES {
            for i in idx.iter_mut() {
                *i = (rng.next_u64() % n as u64) as usize;
            }
            draws.push(stat(&idx));
        }
    }
    let k = draws.first().map_or(0, Vec::len);
    (0..k)
        .map(|k| {
            let v: Vec<f64> = draws.iter().map(|d| d[k]).filter(|x| !x.is_nan()).collect();
            if v.is_empty() {
                (f64::NAN, f64::NAN)
            } else {
                (quantile(&v, 0.025), quantile(&v, 0.975))
            }
        })
        .collect()
}
