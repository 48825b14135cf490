use super::*;

use crate::sim::noise::mix64;

/// A uniform number in (0, 1) from a seed and an index.
fn unif(seed: u64, i: u64) -> f64 {
    ((mix64(seed ^ mix64(i)) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

fn gpd_sample(seed: u64, n: usize, sigma: f64, xi: f64) -> Vec<f64> {
    (0..n as u64)
        .map(|i| {
            let p = unif(seed, i);
            sigma * growth(1.0 / p, xi)
        })
        .collect()
}

#[test]
fn gpd_fit_recovers_known_laws_and_the_exponential_limit() {
    for (sigma, xi) in [(0.5, -0.3), (1.0, 0.0), (2.0, 0.2)] {
        let y = gpd_sample(3, 4000, sigma, xi);
        let fit = fit_gpd(&y, (-XI_MAX, XI_MAX)).unwrap();
        assert!((fit.gpd.xi - xi).abs() < 4.0 * fit.xi_se, "{fit:?} vs {xi}");
        assert!(
            (fit.gpd.sigma / sigma - 1.0).abs() < 0.1,
            "{fit:?} vs {sigma}"
        );
    }
    // xi -> 0: the likelihood is continuous.
    let y = gpd_sample(4, 100, 1.0, 0.0);
    let a = Gpd {
        sigma: 1.0,
        xi: 0.0,
    }
    .nll(&y);
    let b = Gpd {
        sigma: 1.0,
        xi: 1e-7,
    }
    .nll(&y);
    assert!((a - b).abs() < 1e-4 * a.abs(), "{a} {b}");
}

#[test]
fn declustering_keeps_one_maximum_per_run() {
    let z = [0.0, 2.0, 3.0, 0.0, 2.5, 0.0, 0.0, 0.0, 4.0, 0.0];
    assert_eq!(decluster(&z, 1.0, 1), vec![3.0, 2.5, 4.0]);
    assert_eq!(decluster(&z, 1.0, 2), vec![3.0, 4.0]);
    assert_eq!(decluster(&z, 1.0, 5), vec![4.0]);
}

/// Coverage of the 90 % profile-likelihood interval of the life quantile on excesses of a
/// known law: 200 seeds, each 150 excesses (a rate of 0.05 per period over 3000 periods),
/// a life of 10^6 periods, the median of its maximum.
#[test]
fn pot_interval_covers_the_true_life_quantile_at_its_nominal_rate() {
    // Any shape allowed (a heavy tail among them), and the bounded fit on a bounded law.
    for (sigma, xi, xi_max) in [(1.0, -0.2, XI_MAX), (1.0, 0.1, XI_MAX), (1.0, -0.2, 0.0)] {
        let life = Life {
            n_life: 1e6,
            q: 0.5,
            xi_min: -XI_MAX,
            xi_max,
        };
        let nu = 0.05;
        let truth = sigma * growth(life.m(nu), xi);
        let mut covered = 0;
        let seeds = 200;
        for seed in 0..seeds {
            let y = gpd_sample(1000 + seed, 150, sigma, xi);
            let fit = fit_gpd(&y, (-XI_MAX, xi_max)).unwrap();
            let est = life_from_excesses(&y, 0.0, nu, life, fit).unwrap();
            if est.lo <= truth && truth <= est.hi {
                covered += 1;
            }
        }
        let rate = covered as f64 / seeds as f64;
        eprintln!("GPD xi {xi} (fitted in [-0.95, {xi_max}]): coverage {rate}");
        assert!((0.80..=0.97).contains(&rate), "xi {xi}: coverage {rate}");
    }
}

/// The same for block maxima of a known GEV law: 200 seeds of 60 blocks of 100 periods.
#[test]
fn gev_interval_covers_the_true_life_quantile_at_its_nominal_rate() {
    let (mu, sigma, xi) = (10.0, 1.0, -0.15);
    let life = Life {
        n_life: 1e6,
        q: 0.5,
        xi_min: -XI_MAX,
        xi_max: XI_MAX,
    };
    let block = 100;
    let y = -(life.q.ln()) * block as f64 / life.n_life;
    let truth = mu + sigma * growth(1.0 / y, xi);
    let mut covered = 0;
    let seeds = 200;
    for seed in 0..seeds {
        let x: Vec<f64> = (0..60)
            .map(|i| {
                let p = unif(5000 + seed, i);
                mu + sigma * growth(1.0 / -p.ln(), xi)
            })
            .collect();
        let est = life_gev(&x, block, life).unwrap();
        if est.lo <= truth && truth <= est.hi {
            covered += 1;
        }
    }
    let rate = covered as f64 / seeds as f64;
    eprintln!("GEV: coverage {rate}");
    assert!((0.80..=0.97).contains(&rate), "coverage {rate}");
}

/// The bounded estimate on per-period values of a known bounded law, `z = 1 - U^(1/alpha)`
/// (`P(z > 1 - s) = s^alpha`, a shape of `-1/alpha`), independent periods: over 100 samples of
/// 100,000 periods, the median of the largest of `N` periods, `1 - (1 - 0.5^(1/N))^(1/alpha)`,
/// lies in the 90 % interval at least at the nominal rate less a margin for 100 draws, and the
/// estimate is within 5 % of it in every sample (issue 43's bound; an extrapolation by 10 and
/// 100 times; measured: at most 2.7 %. From 20,000 periods the worst of 100 samples is 5.4 %
/// at 500 times, with the interval still holding the truth in 96 of 100).
#[test]
fn bounded_estimate_covers_the_life_quantile_of_a_known_bounded_law() {
    for alpha in [2.5, 3.0] {
        for n_life in [1e6, 1e7] {
            let truth = 1.0 - (1.0 - 0.5f64.powf(1.0 / n_life)).powf(1.0 / alpha);
            let life = Life::bounded(n_life, 0.5);
            let (mut covered, mut worst) = (0, 0.0f64);
            let seeds = 100;
            for seed in 0..seeds {
                let z: Vec<f64> = (0..100_000u64)
                    .map(|i| 1.0 - unif(9000 + seed, i).powf(1.0 / alpha))
                    .collect();
                let est = life_pot(&[z.as_slice()], 1, life).unwrap();
                covered += usize::from(est.lo <= truth && truth <= est.hi);
                worst = worst.max((est.amplitude / truth - 1.0).abs());
            }
            let rate = covered as f64 / seeds as f64;
            eprintln!("alpha {alpha} N {n_life}: coverage {rate}, worst error {worst}");
            assert!(rate >= 0.84, "alpha {alpha} N {n_life}: coverage {rate}");
            assert!(
                worst <= 0.05,
                "alpha {alpha} N {n_life}: worst error {worst}"
            );
        }
    }
}

#[test]
fn the_estimate_keeps_the_highest_clusters_and_the_band_grows_with_the_sample() {
    assert_eq!(tail_sizes(), [12, 25, 50]);
    assert_eq!(band_sizes(2000), [12, 25, 50]);
    assert_eq!(band_sizes(40_000), [25, 50, 100]);
    assert_eq!(band_sizes(1_000_000), [50, 100, 200]);
}

#[test]
fn the_upper_order_statistics_give_the_full_sorts_quantiles_bit_for_bit() {
    for n in [0usize, 1, 2, 7, 1000, 54_321] {
        // Ties on purpose: a coarse grid of values.
        let values: Vec<f64> = (0..n as u64)
            .map(|i| (unif(9, i) * 500.0).round() / 7.0)
            .collect();
        let mut sorted = values.clone();
        sorted.sort_unstable_by(f64::total_cmp);
        for q_min in [0.0, 0.5, 0.93, 0.999, 1.0] {
            let upper = Upper::new(values.clone(), q_min);
            assert_eq!(upper.len(), n);
            for q in [q_min, 0.5 * (q_min + 1.0), 0.9999, 1.0]
                .into_iter()
                .filter(|&q| q >= q_min)
            {
                let (a, b) = (
                    upper.quantile(q),
                    crate::numeric::quantile_sorted(&sorted, q),
                );
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "n = {n}, q_min = {q_min}, q = {q}"
                );
            }
            if n > 10 && q_min > 0.5 {
                assert!(upper.quantile(0.25).is_nan(), "below q_min");
            }
        }
    }
}

#[test]
fn the_posterior_median_is_integrated_finely_enough_and_meets_the_likelihood_on_large_samples() {
    let bounded = (XI_BOUNDED, 0.0);
    for prior in [ShapePrior::Jeffreys, ShapePrior::Flat] {
        let grid = PosteriorGrid {
            prior,
            ..POSTERIOR_GRID
        };
        let fine = PosteriorGrid {
            shapes: 201,
            scales: 361,
            width: 3.0,
            prior,
        };
        for (k, xi) in [(12, -0.45), (25, -0.35), (50, -0.2), (4000, -0.3)] {
            let y = gpd_sample(77 + k as u64, k, 0.01, xi);
            let fit = fit_gpd(&y, bounded).unwrap();
            let m = 1e5;
            let z = |g| posterior_median(&y, 1.0, m, fit.gpd, bounded, g);
            let (a, b) = (z(grid), z(fine));
            assert!(
                (a / b - 1.0).abs() < 2e-3,
                "{prior:?}, k = {k}: {a} against {b}"
            );
            if k == 4000 {
                // The posterior concentrates on the likelihood's maximum.
                let ml = 1.0 + fit.gpd.sigma * growth(m, fit.gpd.xi);
                assert!((a / ml - 1.0).abs() < 2e-3, "{prior:?}: {a} against {ml}");
            }
        }
    }
}

/// The posterior's quantiles are ordered, its median is [`posterior_median`]'s, and they close in
/// on the likelihood's quantile as the sample grows.
#[test]
fn posterior_quantiles_bracket_the_median_and_narrow_with_the_sample() {
    let bounded = (XI_BOUNDED, 0.0);
    let m = 1e5;
    let width = |k: usize| {
        let y = gpd_sample(91 + k as u64, k, 0.01, -0.3);
        let fit = fit_gpd(&y, bounded).unwrap();
        let [lo, mid, hi] = posterior_quantiles(
            &y,
            1.0,
            m,
            fit.gpd,
            bounded,
            POSTERIOR_GRID,
            [0.05, 0.5, 0.95],
        );
        let median = posterior_median(&y, 1.0, m, fit.gpd, bounded, POSTERIOR_GRID);
        assert!(lo < mid && mid < hi, "k = {k}: {lo} {mid} {hi}");
        assert_eq!(mid.to_bits(), median.to_bits());
        (hi - lo) / mid
    };
    let (small, large) = (width(25), width(4000));
    assert!(large < 0.25 * small, "{small} against {large}");
}

/// The point value on a bounded law whose excesses are exactly generalized Pareto (the law of
/// the test above, alpha = 2.5: shape -0.4), 100 samples of 20,000 periods, the fit on the 25
/// highest, a life of 10^7 periods. The likelihood's quantile runs low (its shape piles at the
/// bound -1/2; measured median -0.8 %), the posterior median under a flat shape prior as far high
/// (+0.9 %); Jeffreys's prior centres it (-0.1 %) and narrows its spread (90 % of the errors within
/// 1.4 %, against 2.1 % and 2.3 %).
#[test]
fn the_jeffreys_posterior_median_is_centred_where_the_likelihood_runs_low() {
    let alpha = 2.5;
    let n_life = 1e7;
    let truth = 1.0 - (1.0 - 0.5f64.powf(1.0 / n_life)).powf(1.0 / alpha);
    let life = Life::bounded(n_life, 0.5);
    let flat = PosteriorGrid {
        prior: ShapePrior::Flat,
        ..POSTERIOR_GRID
    };
    // Errors of the likelihood's quantile, the flat prior's and Jeffreys's.
    let mut errors = [Vec::new(), Vec::new(), Vec::new()];
    for seed in 0..100 {
        let z: Vec<f64> = (0..20_000u64)
            .map(|i| 1.0 - unif(7000 + seed, i).powf(1.0 / alpha))
            .collect();
        let upper = Upper::for_fits(z.clone(), [TAIL_CLUSTERS]);
        let e = fit_top(
            &[z.as_slice()],
            &upper,
            TAIL_CLUSTERS,
            1,
            life,
            Point::Likelihood,
        )
        .unwrap();
        let y: Vec<f64> = decluster(&z, e.threshold, 1)
            .iter()
            .map(|v| v - e.threshold)
            .collect();
        let m = life.m(y.len() as f64 / z.len() as f64);
        let gpd = Gpd {
            sigma: e.sigma,
            xi: e.xi,
        };
        let post = |g| posterior_median(&y, e.threshold, m, gpd, (life.xi_min, life.xi_max), g);
        for (out, a) in errors
            .iter_mut()
            .zip([e.amplitude, post(flat), post(POSTERIOR_GRID)])
        {
            out.push(a / truth - 1.0);
        }
    }
    let median = |e: &[f64]| crate::numeric::median(e);
    let p90 = |e: &[f64]| {
        let mut a: Vec<f64> = e.iter().map(|x| x.abs()).collect();
        a.sort_by(f64::total_cmp);
        a[89]
    };
    let [ml, flat, jeffreys] = &errors;
    eprintln!(
        "median error: likelihood {:+.4}, flat {:+.4}, Jeffreys {:+.4}; 90 % within {:.4}, {:.4}, {:.4}",
        median(ml),
        median(flat),
        median(jeffreys),
        p90(ml),
        p90(flat),
        p90(jeffreys)
    );
    assert!(
        median(ml) < -0.005 && median(flat) > 0.005,
        "the two biases"
    );
    assert!(median(jeffreys).abs() < 0.004, "Jeffreys's median error");
    assert!(p90(jeffreys) < p90(ml).min(p90(flat)), "Jeffreys's spread");
}

/// A design-life measurement's floor for its next window (`floor_for`) lies at or under the last
/// estimate's lowest threshold and under every threshold of the next estimate: 200 samples of a
/// bounded law whose large values come in build-ups, each measured to `n` periods and then
/// doubled, as the race's windows grow.
#[test]
fn the_next_windows_floor_lies_under_its_thresholds() {
    let life = Life::bounded(1e7, 0.5);
    for seed in 0..200u64 {
        let n = [8_000usize, 64_000, 128_000][(seed % 3) as usize];
        // Each period's maximum is the larger of a fresh draw and most of the last one.
        let mut last = 0.0f64;
        let z: Vec<f64> = (0..2 * n as u64)
            .map(|i| {
                last = (1.0 - unif(7000 + seed, i).powf(1.0 / 3.0)).max(0.97 * last);
                last
            })
            .collect();
        let first = life_pot(&[&z[..n]], 3, life).unwrap();
        let floor = floor_for(&[&z[..n]], 3, 2 * n).unwrap();
        assert!(floor <= first.lowest_threshold, "seed {seed}");
        let next = life_pot(&[z.as_slice()], 3, life).unwrap();
        assert!(floor <= next.lowest_threshold, "seed {seed}");
    }
}
