//! The largest Lyapunov exponent of a motion from the exact tangent map (docs/model.md,
//! "Lyapunov exponent").
//!
//! `lambda_1 = lim (1/n) ln |J_n ... J_1 v|`, `J_k` the Jacobian of one forcing period along the
//! motion (the map's exact Jacobian of [`super::map`]: the segments' state-transition matrices
//! and a saltation matrix at every impact, sticking and separation). Benettin's method applies
//! the product to one vector and renormalises it every period, adding up the logarithms of the
//! growth. The first [`Benettin::burn`] periods are not counted: they turn the vector towards
//! the most unstable direction (on a periodic orbit with a real dominant multiplier `mu`, the
//! growth per orbit period is then exactly `|mu|`, and `lambda_1 = ln |mu| / p` per forcing
//! period). A period whose map is not differentiable (a grazing impact, where the saltation is
//! singular) contributes nothing and is counted in [`Benettin::skipped`]: near grazing the
//! estimates are noisy, not wrong. The standard error is by batch means over 8 batches.
//!
//! Units: per forcing period; divide by `T_f = 2 pi / omega` for per second.

use super::map::Mat4;

/// Benettin's accumulator: a value that a run extends period by period.
#[derive(Clone, Debug, PartialEq)]
pub struct Benettin {
    /// The tangent vector (unit length), in section coordinates.
    pub v: [f64; 4],
    /// Periods not counted at the start.
    pub burn: u64,
    /// Periods seen (counted or not), and periods skipped (no Jacobian).
    pub seen: u64,
    pub skipped: u64,
    /// The counted periods' logarithms of the growth.
    pub logs: Vec<f64>,
}

impl Benettin {
    /// A start with the vector `(1, 1, 1, 1) / 2` (generic: no section coordinate is left out).
    pub fn new(burn: u64) -> Benettin {
        Benettin {
            v: [0.5; 4],
            burn,
            seen: 0,
            skipped: 0,
            logs: Vec::new(),
        }
    }

    /// One period with Jacobian `j` (`None`: not differentiable there).
    pub fn step(&mut self, j: Option<&Mat4>) {
        self.seen += 1;
        let Some(j) = j else {
            self.skipped += 1;
            return;
        };
        let w: [f64; 4] = std::array::from_fn(|r| (0..4).map(|k| j[r][k] * self.v[k]).sum());
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            self.skipped += 1;
            return;
        }
        self.v = w.map(|x| x / norm);
        if self.seen > self.burn {
            self.logs.push(norm.ln());
        }
    }

    /// The exponent per forcing period and its standard error (batch means, 8 batches; NaN with
    /// fewer than 8 counted periods).
    pub fn estimate(&self) -> (f64, f64) {
        batch_means(&self.logs, 8)
    }
}

/// The mean of `x` and its standard error by `batches` batch means.
pub fn batch_means(x: &[f64], batches: usize) -> (f64, f64) {
    let b = x.len() / batches;
    if b == 0 {
        return (f64::NAN, f64::NAN);
    }
    let used = &x[..b * batches];
    let mean = used.iter().sum::<f64>() / used.len() as f64;
    let means: Vec<f64> = used
        .chunks(b)
        .map(|c| c.iter().sum::<f64>() / b as f64)
        .collect();
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (batches - 1) as f64;
    (mean, (var / batches as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::map::eval;
    use crate::orbits::map::tests::table_i as forcing;
    use crate::orbits::shoot::{Newton, orbit_at, solve};

    /// Issue 22: along a periodic orbit, Benettin's exponent from the tangent map equals
    /// `ln |mu_max| / p` from its Floquet multipliers, to 1e-6: issue 16's first design, its
    /// period-1 orbits at r = 0.93 and 0.945 (real dominant multipliers -1.39 and 14.8; the
    /// stable orbits of this design have a complex dominant pair, whose single-vector growth
    /// turns with the pair and averages out only slowly). The state is held on the orbit
    /// (its section, a fixed point of the map), so the product is the monodromy matrix's powers.
    #[test]
    fn along_a_periodic_orbit_lambda_is_the_log_of_the_largest_multiplier_per_period() {
        for r in [0.93, 0.945] {
            let f = forcing(0.005, 0.005, 0.9, 0.1, 0.1, r);
            // Newton from states along a transient, up to the first period-1 orbit with a real
            // dominant multiplier (where it lands depends on the transient's last bits).
            let newton = Newton::default();
            let o = (300..340)
                .filter_map(|n| {
                    let s0 = eval(&f, &[0.002, 0.0, 0.0, 0.3], n, false).end;
                    orbit_at(&f, 1, &solve(&f, 1, &s0, &newton).1?, &newton)
                })
                .find(|o| o.multipliers[0].1 == 0.0 && o.multipliers[0].0.abs() > 1.0)
                .unwrap_or_else(|| panic!("r = {r}: no orbit with a real dominant multiplier"));
            let want = o.multiplier_max().ln() / f64::from(o.period);
            let mut b = Benettin::new(200);
            for _ in 0..264 {
                b.step(eval(&f, &o.s, 1, true).jacobian.as_ref());
            }
            let (lambda, se) = b.estimate();
            assert!((lambda - want).abs() <= 1e-6, "r = {r}: {lambda} vs {want}");
            assert!(se < 1e-9, "{se}");
            assert_eq!(b.skipped, 0);
        }
    }

    /// Issue 22: at the showcase's chaotic point (m = 20 g, d = 20 mm, r = 1.01), the exponent
    /// from the tangent map agrees with a finite-difference estimate from two trajectories of the
    /// same simulator (a neighbour `1e-8 d/2` away, brought back to that distance every
    /// period) within three standard errors, and is significantly positive.
    #[test]
    fn at_a_chaotic_point_the_tangent_map_agrees_with_two_trajectories() {
        let f = forcing(0.02, 0.02, 0.9, 0.1, 0.1, 1.01);
        let start = eval(&f, &[0.005, 0.0, 0.0, 0.2], 500, false).end;
        let n = 2000;
        let mut tangent = Benettin::new(8);
        let mut s = start;
        for _ in 0..n {
            let e = eval(&f, &s, 1, true);
            tangent.step(e.jacobian.as_ref());
            s = e.end;
        }
        let (lt, st) = tangent.estimate();
        let delta = 1e-8 * f.half_gap();
        let (mut a, mut b) = (start, start);
        b[0] += delta;
        let mut logs = Vec::new();
        for k in 0..n {
            a = eval(&f, &a, 1, false).end;
            let bb = eval(&f, &b, 1, false).end;
            let d = crate::orbits::shoot::distance(&f, &a, &bb);
            if k >= 8 {
                logs.push((d / delta).ln());
            }
            b = std::array::from_fn(|i| a[i] + (bb[i] - a[i]) * delta / d);
        }
        let (lf, sf) = batch_means(&logs, 8);
        eprintln!("tangent {lt} +- {st}; two trajectories {lf} +- {sf}");
        assert!(lt > 3.0 * st && lt > 0.1, "not chaotic: {lt} +- {st}");
        assert!(
            (lt - lf).abs() <= 3.0 * st.hypot(sf),
            "tangent {lt} +- {st}, two trajectories {lf} +- {sf}"
        );
    }
}
