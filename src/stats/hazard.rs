//! Annual risk over a seismic hazard curve (model.md §13, docs/scenes.md): the mean annual
//! rate of failure `lambda_f` of a design from its fragility and the site's hazard curve, the
//! probability over a number of years, and which intensities contribute.
//!
//! # Equations
//! The hazard curve `lambda(x)` is the annual rate at which the intensity measure exceeds `x`
//! (g): a power law `lambda(x) = k0 x^-k`, or a table of `(x_i, lambda_i)` interpolated
//! linearly in `(ln x, ln lambda)` and continued beyond its ends by its end segments' power
//! laws. With `P(f | x)` the fragility,
//!
//! ```text
//! lambda_f = int_0^inf P(f | x) |d lambda(x)| = int_0^inf lambda(x) dP(f | x)
//!          = E[lambda(C)],                        C the capacity, P(C <= x) = P(f | x),
//! P_f(t years) = 1 - exp(-t lambda_f)    (Poisson occurrences).
//! ```
//!
//! * Over the **empirical** fragility of `n` capacities `c_j` it is exactly
//!   `lambda_f = (1/n) sum_j lambda(c_j)` ([`lambda_f_empirical`]); a censored capacity (the
//!   motion never passed the limit up to `ida_max`) counts at `ida_max`, which bounds its part
//!   from above.
//! * Over the **lognormal** `Phi(ln(x / theta) / beta)` it is
//!   `int lambda(theta e^(beta z)) phi(z) dz`, by composite Simpson over `z` in `[-12, 12]`
//!   (4,800 panels; [`lambda_f_lognormal`]); under a power law it equals Cornell et al.'s (2002)
//!   closed form `k0 theta^-k exp(k^2 beta^2 / 2)` ([`cornell`]), the check of the quadrature.
//! * **Deaggregation over the intensity**: the share of `lambda_f` from intensities up to `x`
//!   is `D(x) = int_0^x P(f | u) |d lambda(u)| / lambda_f`; [`deaggregation`] gives the
//!   intensities where `D` reaches 10 %, 50 % and 90 %.

use serde::Serialize;

use super::fragility::phi_cdf;

/// A site's hazard curve (module doc). Intensities in g, rates per year.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "form", rename_all = "lowercase")]
pub enum Hazard {
    /// `lambda(x) = k0 x^-k`, `k0 > 0` (per year at 1 g), `k > 0`.
    Power { k0: f64, k: f64 },
    /// Rows `(x_i, lambda_i)`, `x` strictly increasing and `> 0`, `lambda` strictly decreasing
    /// and `> 0`, at least two rows.
    Table { im: Vec<f64>, rate: Vec<f64> },
}

/// The hazard a study gives (`[hazard]`): the curve and the years of its probability.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SiteHazard {
    pub curve: Hazard,
    /// `years` (default 50): the exposure of `P_f = 1 - exp(-years lambda_f)`.
    pub years: f64,
    /// Where the curve comes from, as the study says (`source`), for the report.
    pub source: Option<String>,
}

impl Hazard {
    /// The annual rate of exceeding `x` (g).
    pub fn rate(&self, x: f64) -> f64 {
        match self {
            Hazard::Power { k0, k } => k0 * x.powf(-k),
            Hazard::Table { im, rate } => {
                let n = im.len();
                let lx = x.ln();
                // The segment that holds x, or the end one beyond the table.
                let i = match im.iter().position(|&v| v >= x) {
                    Some(0) => 0,
                    Some(i) => i - 1,
                    None => n - 2,
                };
                let (x0, x1) = (im[i].ln(), im[i + 1].ln());
                let (y0, y1) = (rate[i].ln(), rate[i + 1].ln());
                (y0 + (y1 - y0) * (lx - x0) / (x1 - x0)).exp()
            }
        }
    }
}

/// `lambda_f` over the empirical fragility of `capacities` (g; a censored one given at
/// `ida_max`): `(1/n) sum lambda(c_j)`.
pub fn lambda_f_empirical(hazard: &Hazard, capacities: &[f64]) -> f64 {
    if capacities.is_empty() {
        return f64::NAN;
    }
    capacities.iter().map(|&c| hazard.rate(c)).sum::<f64>() / capacities.len() as f64
}

/// `lambda_f` over the lognormal fragility `(theta, beta)`, by quadrature (module doc).
pub fn lambda_f_lognormal(hazard: &Hazard, theta: f64, beta: f64) -> f64 {
    let (a, b, n) = (-12.0, 12.0, 4800usize);
    let h = (b - a) / n as f64;
    let f = |z: f64| {
        hazard.rate(theta * (beta * z).exp()) * (-0.5 * z * z).exp()
            / (2.0 * std::f64::consts::PI).sqrt()
    };
    let mut s = f(a) + f(b);
    for i in 1..n {
        let z = a + i as f64 * h;
        s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(z);
    }
    s * h / 3.0
}

/// Cornell et al.'s closed form of `lambda_f` for a lognormal fragility under a power law,
/// `k0 theta^-k exp(k^2 beta^2 / 2)`.
pub fn cornell(k0: f64, k: f64, theta: f64, beta: f64) -> f64 {
    k0 * theta.powf(-k) * (0.5 * k * k * beta * beta).exp()
}

/// The probability of at least one failure in `years`, `1 - exp(-years lambda_f)`.
pub fn p_years(lambda_f: f64, years: f64) -> f64 {
    -(-years * lambda_f).exp_m1()
}

/// The intensities (g) at which `lambda_f`'s deaggregation over the intensity reaches 10 %,
/// 50 % and 90 % (module doc), for the fragility `p(x)` over a grid of 2,000 intensities
/// spaced evenly in `ln x` over `[lo, hi]` (g) that holds the fragility's rise.
pub fn deaggregation(hazard: &Hazard, p: impl Fn(f64) -> f64, lo: f64, hi: f64) -> [f64; 3] {
    let n = 2000usize;
    let (a, b) = (lo.ln(), hi.ln());
    let xs: Vec<f64> = (0..=n)
        .map(|i| (a + (b - a) * i as f64 / n as f64).exp())
        .collect();
    // The share in each cell: P(f) at its middle times the rate's drop over it.
    let mut cum = Vec::with_capacity(n);
    let mut total = 0.0;
    for w in xs.windows(2) {
        let mid = (w[0] * w[1]).sqrt();
        total += p(mid) * (hazard.rate(w[0]) - hazard.rate(w[1]));
        cum.push((w[1], total));
    }
    // Beyond hi: all of it (P(f) ~ 1 there).
    total += p(hi) * hazard.rate(hi);
    [0.1, 0.5, 0.9].map(|q| {
        cum.iter()
            .find(|(_, c)| *c >= q * total)
            .map_or(f64::NAN, |(x, _)| *x)
    })
}

/// The lognormal fragility `Phi(ln(x / theta) / beta)` at `x`.
pub fn lognormal_p(x: f64, theta: f64, beta: f64) -> f64 {
    phi_cdf((x / theta).ln() / beta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quadrature_meets_cornells_closed_form() {
        for (k0, k, theta, beta) in [
            (1e-4, 2.0, 0.5, 0.3),
            (4e-4, 3.0, 1.2, 0.5),
            (1e-3, 1.5, 0.2, 0.8),
        ] {
            let h = Hazard::Power { k0, k };
            let q = lambda_f_lognormal(&h, theta, beta);
            let c = cornell(k0, k, theta, beta);
            assert!((q / c - 1.0).abs() < 1e-9, "{q} vs {c}");
        }
    }

    #[test]
    fn a_table_interpolates_in_logs_and_extends_its_ends() {
        let h = Hazard::Table {
            im: vec![0.1, 1.0],
            rate: vec![1e-2, 1e-4],
        };
        // Slope -2 in log-log: a power law 1e-4 x^-2 everywhere.
        for x in [0.01, 0.1, 0.3, 1.0, 5.0] {
            let r = h.rate(x);
            assert!((r / (1e-4 * x.powi(-2)) - 1.0).abs() < 1e-12, "{x}: {r}");
        }
    }

    #[test]
    fn the_empirical_rate_is_the_mean_rate_of_the_capacities() {
        let h = Hazard::Power { k0: 1e-4, k: 2.0 };
        let l = lambda_f_empirical(&h, &[0.5, 1.0]);
        assert!((l - 0.5 * (4e-4 + 1e-4)).abs() < 1e-18);
        assert!((p_years(1e-3, 50.0) - (1.0 - (-0.05f64).exp())).abs() < 1e-15);
    }

    #[test]
    fn a_sharp_fragilitys_deaggregation_follows_the_hazard_above_its_median() {
        // P(f | x) a step at theta: the share from intensities up to x > theta is
        // 1 - (x / theta)^-k, so D reaches 10, 50, 90 % at theta 0.9^(-1/k), 0.5^(-1/k),
        // 0.1^(-1/k).
        let (k, theta) = (2.5, 1.0);
        let h = Hazard::Power { k0: 1e-4, k };
        let d = deaggregation(&h, |x| lognormal_p(x, theta, 0.002), 1e-3, 1e2);
        for (got, q) in d.iter().zip([0.9f64, 0.5, 0.1]) {
            let want = theta * q.powf(-1.0 / k);
            assert!((got / want - 1.0).abs() < 0.01, "{got} vs {want}");
        }
    }
}
