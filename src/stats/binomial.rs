//! A binomial proportion and its exact (Clopper–Pearson) confidence interval: the Monte Carlo
//! estimate of a failure probability from `k` exceedances in `n` independent runs.
//!
//! ```text
//! p = k / n,
//! lo = B^-1(alpha/2; k, n - k + 1)        (0 when k = 0),
//! hi = B^-1(1 - alpha/2; k + 1, n - k)    (1 when k = n),
//! ```
//!
//! with `B^-1(q; a, b)` the quantile of the beta distribution and `alpha = 1 - confidence`
//! (Clopper and Pearson, Biometrika 26 (1934) 404–413). The interval inverts the two one-sided
//! binomial tests, so it covers the true `p` at least at the nominal rate for every `p` and `n`
//! (conservative): chosen over Wilson's because the failure probabilities of interest sit near
//! 0, where Wilson's covers less than nominal for small `n p`.

use statrs::distribution::{Beta, ContinuousCDF};

/// A proportion `k / n` with its two-sided interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proportion {
    pub p: f64,
    pub lo: f64,
    pub hi: f64,
}

/// `k` successes in `n` trials and the Clopper–Pearson interval at `confidence` (in (0, 1));
/// all NaN when `n = 0` or `k > n`.
pub fn clopper_pearson(k: u64, n: u64, confidence: f64) -> Proportion {
    let nan = Proportion {
        p: f64::NAN,
        lo: f64::NAN,
        hi: f64::NAN,
    };
    if n == 0 || k > n || !(confidence > 0.0 && confidence < 1.0) {
        return nan;
    }
    let alpha = 1.0 - confidence;
    let (kf, nf) = (k as f64, n as f64);
    let quantile = |q: f64, a: f64, b: f64| Beta::new(a, b).map_or(f64::NAN, |d| d.inverse_cdf(q));
    let lo = if k == 0 {
        0.0
    } else {
        quantile(alpha / 2.0, kf, nf - kf + 1.0)
    };
    let hi = if k == n {
        1.0
    } else {
        quantile(1.0 - alpha / 2.0, kf + 1.0, nf - kf)
    };
    Proportion { p: kf / nf, lo, hi }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_have_closed_forms() {
        // k = 0: hi = 1 - (alpha/2)^(1/n); k = n: lo = (alpha/2)^(1/n).
        let p = clopper_pearson(0, 10, 0.95);
        assert_eq!((p.p, p.lo), (0.0, 0.0));
        assert!((p.hi - (1.0 - 0.025f64.powf(0.1))).abs() < 1e-9, "{p:?}");
        let p = clopper_pearson(10, 10, 0.95);
        assert_eq!((p.p, p.hi), (1.0, 1.0));
        assert!((p.lo - 0.025f64.powf(0.1)).abs() < 1e-9, "{p:?}");
        assert!(clopper_pearson(1, 0, 0.95).p.is_nan());
    }

    #[test]
    fn five_of_ten_is_the_textbook_interval() {
        // Clopper–Pearson 95 % for 5/10: (0.1871, 0.8129) (e.g. R's binom.test).
        let p = clopper_pearson(5, 10, 0.95);
        assert!(
            (p.lo - 0.187_086).abs() < 1e-5 && (p.hi - 0.812_914).abs() < 1e-5,
            "{p:?}"
        );
    }

    #[test]
    fn it_covers_at_least_nominally() {
        // The exact coverage at p = 0.02, n = 200: sum of the binomial probabilities of the k
        // whose interval holds p; Clopper–Pearson's is at least 95 %.
        use statrs::distribution::{Binomial, Discrete};
        let (p, n) = (0.02, 200u64);
        let b = Binomial::new(p, n).unwrap();
        let cover: f64 = (0..=n)
            .filter(|&k| {
                let ci = clopper_pearson(k, n, 0.95);
                ci.lo <= p && p <= ci.hi
            })
            .map(|k| b.pmf(k))
            .sum();
        assert!(cover >= 0.95, "{cover}");
    }
}
