//! The lognormal fragility fit (issue 44, `stats::fragility`) on data drawn from a known curve:
//! over many seeds the maximum-likelihood estimates centre on the truth and the 95 % intervals
//! hold it at about their nominal rate.

use impactsweep::stats::fragility::{Counts, FitOutcome, fit};
use rand_core::Rng;
use rand_pcg::Pcg64;
use statrs::distribution::{ContinuousCDF, Normal};

/// Binomial counts at ten intensities from 0.3 to 3 times `theta` (log-spaced), `n` runs each.
fn draw(theta: f64, beta: f64, n: u64, seed: u64) -> Vec<Counts> {
    let normal = Normal::standard();
    let mut rng = Pcg64::new((u128::from(seed) << 64) | 0xF4A6_1117, 0xDA7A);
    (0..10)
        .map(|j| {
            let im = theta * 0.3 * 10f64.powf(j as f64 / 9.0);
            let p = normal.cdf((im / theta).ln() / beta);
            let exceed = (0..n)
                .filter(|_| ((rng.next_u64() >> 11) as f64) / (1u64 << 53) as f64 <= p)
                .count() as u64;
            Counts { im, n, exceed }
        })
        .collect()
}

/// 1,000 data sets of 10 intensities x 40 runs from `theta = 0.8`, `beta = 0.5`: the 95 %
/// intervals of `theta` and `beta` hold the truth in [0.92, 0.97] of the sets (nominal 0.95;
/// the coverage's own sampling error is 0.007; the profile-likelihood interval, like the Wald
/// interval it replaced (93.8 % here), is asymptotic: with 400 runs per set it may cover a point
/// or two under its nominal rate), and
/// the mean of `ln theta` is within 3 standard errors of the truth.
#[test]
fn intervals_cover_the_curve_at_their_nominal_rate() {
    let (theta, beta) = (0.8, 0.5);
    let sets = 1000;
    let (mut in_theta, mut in_beta, mut fitted) = (0, 0, 0);
    let mut ln_thetas = Vec::new();
    for seed in 0..sets {
        let f = fit(&draw(theta, beta, 40, seed));
        if f.outcome != FitOutcome::Ok {
            continue;
        }
        fitted += 1;
        ln_thetas.push(f.theta.ln());
        if f.theta_lo <= theta && theta <= f.theta_hi {
            in_theta += 1;
        }
        if f.beta_lo <= beta && beta <= f.beta_hi {
            in_beta += 1;
        }
    }
    let (ct, cb) = (
        in_theta as f64 / fitted as f64,
        in_beta as f64 / fitted as f64,
    );
    let k = ln_thetas.len() as f64;
    let mean = ln_thetas.iter().sum::<f64>() / k;
    let sd = (ln_thetas.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
    eprintln!(
        "{fitted} of {sets} sets fitted; theta inside its 95 % interval in {:.1} %, beta in \
         {:.1} %; mean ln theta {mean:.4} (truth {:.4}, sd {sd:.4})",
        100.0 * ct,
        100.0 * cb,
        theta.ln()
    );
    assert_eq!(fitted, sets);
    assert!((0.92..=0.97).contains(&ct), "{ct}");
    assert!((0.92..=0.97).contains(&cb), "{cb}");
    assert!((mean - theta.ln()).abs() <= 3.0 * sd / k.sqrt());
}

/// Few runs, as a record suite gives at its stripes (6 intensities from 0.3 to 3 times
/// `theta = 0.8` x 6 runs, `beta = 0.4`; 2,000 sets): the likelihood is far from quadratic and
/// the counts often come close to separating. The profile-likelihood intervals hold `theta` in
/// [0.92, 0.98] of the fitted sets (nominal 0.95, sampling error 0.005) and `beta` in
/// [0.90, 0.98] (a little under nominal at 36 runs: the estimate of `beta` runs low with few
/// runs), and reach past a thousandth or a thousand times `theta` in at most a tenth as many sets
/// as the Wald intervals `exp(+-1.96 se)` of the same fits, printed beside them, which do so in
/// over a hundred.
#[test]
fn profile_intervals_hold_with_few_runs() {
    let (theta, beta) = (0.8, 0.4);
    let sets = 2000;
    let (mut fitted, mut in_t, mut in_b, mut wald_t, mut wald_b, mut wild) = (0, 0, 0, 0, 0, 0);
    let mut wild_profile = 0;
    for seed in 0..sets {
        // Six of the ten intensities, spread from 0.3 to 3 times theta.
        let counts: Vec<Counts> = draw(theta, beta, 6, 10_000 + seed)
            .into_iter()
            .enumerate()
            .filter(|(j, _)| [0, 2, 4, 6, 8, 9].contains(j))
            .map(|(_, c)| c)
            .collect();
        let f = fit(&counts);
        if f.outcome != FitOutcome::Ok {
            continue;
        }
        fitted += 1;
        in_t += usize::from(f.theta_lo <= theta && theta <= f.theta_hi);
        in_b += usize::from(f.beta_lo <= beta && beta <= f.beta_hi);
        let z = 1.959_963_984_540_054;
        let (wl, wh) = (
            f.theta * (-z * f.se_ln_theta).exp(),
            f.theta * (z * f.se_ln_theta).exp(),
        );
        wald_t += usize::from(wl <= theta && theta <= wh);
        wald_b += usize::from(
            f.beta * (-z * f.se_ln_beta).exp() <= beta && beta <= f.beta * (z * f.se_ln_beta).exp(),
        );
        wild += usize::from(wl < 1e-3 * theta || wh > 1e3 * theta);
        wild_profile += usize::from(f.theta_lo < 1e-3 * theta || f.theta_hi > 1e3 * theta);
        assert!(f.theta_lo <= f.theta && f.theta <= f.theta_hi, "{f:?}");
        assert!(f.beta_lo <= f.beta && f.beta <= f.beta_hi, "{f:?}");
    }
    let rate = |k: usize| k as f64 / fitted as f64;
    eprintln!(
        "{fitted} of {sets} sets fitted; profile: theta {:.3}, beta {:.3}; Wald: theta {:.3}, \
         beta {:.3}, theta's reaching past 1e-3 or 1e3 times the truth in {wild} (profile: \
         {wild_profile})",
        rate(in_t),
        rate(in_b),
        rate(wald_t),
        rate(wald_b)
    );
    assert!(fitted >= sets / 2, "{fitted}");
    assert!((0.92..=0.98).contains(&rate(in_t)), "{}", rate(in_t));
    assert!((0.90..=0.98).contains(&rate(in_b)), "{}", rate(in_b));
    assert!(
        wild >= 100 && wild_profile * 10 <= wild,
        "{wild} {wild_profile}"
    );
}
