//! Where a motion that is not periodic wanders (the module doc of [`super`], "Starts that
//! wander" and "Merging"): its cloud in the section, the tangent-map probe that measures its
//! largest Lyapunov exponent, and the longer clouds of a second look.

use super::super::lyapunov::Benettin;
use super::super::map::{Forcing, Section, eval};
use crate::sim::Outcome;

/// Periods of each cloud of a second look (module doc, "Merging").
pub const SECOND_LOOK: u64 = 400;

/// The cloud of the motion from `s` over `n` periods; `None` when a period's map failed.
pub(super) fn long_cloud(f: &Forcing, s: &Section, n: u64) -> Option<Cloud> {
    let mut cloud = Cloud::new(f);
    let mut state = *s;
    for _ in 0..n {
        let e = eval(f, &state, 1, false);
        if e.outcome != Outcome::Ok {
            return None;
        }
        state = e.end;
        cloud.add(&state);
    }
    Some(cloud)
}

/// Where a motion wanders in the section: the mean and spread of each section coordinate in
/// the map's scaled units (`x / L`, `x' / (wn L)`, `z / L`, `y' / (wn L)`, `L = d/2`), over the
/// sections sampled.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cloud {
    n: u64,
    sum: [f64; 4],
    sum2: [f64; 4],
    scale: [f64; 4],
}

impl Cloud {
    pub(super) fn new(f: &Forcing) -> Cloud {
        let l = f.half_gap();
        let wl = f.sys.omega() * l;
        Cloud {
            scale: [1.0 / l, 1.0 / wl, 1.0 / l, 1.0 / wl],
            ..Cloud::default()
        }
    }

    pub(super) fn add(&mut self, s: &Section) {
        self.n += 1;
        for (k, x) in s.iter().enumerate() {
            let v = x * self.scale[k];
            self.sum[k] += v;
            self.sum2[k] += v * v;
        }
    }

    /// Mean and standard deviation of coordinate `k`.
    fn stats(&self, k: usize) -> (f64, f64) {
        let n = self.n.max(1) as f64;
        let mean = self.sum[k] / n;
        (mean, (self.sum2[k] / n - mean * mean).max(0.0).sqrt())
    }

    /// Whether two clouds are one ([`same_moments`]). Empty clouds are never one.
    pub fn same(&self, other: &Cloud) -> bool {
        if self.n == 0 || other.n == 0 {
            return false;
        }
        let (a, b): (Vec<_>, Vec<_>) = (0..4).map(|k| (self.stats(k), other.stats(k))).unzip();
        same_moments(&a, &b)
    }
}

/// Whether two samples of motions, each coordinate's `(mean, standard deviation)` in the same
/// scaled units, are one motion: in every coordinate their means differ by less than half the
/// larger spread and their spreads by less than a factor 2 (a chaotic motion sampled over tens
/// of periods; two distinct attractors differ in where they are or how far they reach). One
/// unit's [`Cloud`] and the clouds of several units ([`crate::orbits::units::motion`]) share it.
pub fn same_moments(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(&(ma, sa), &(mb, sb))| {
            let spread = sa.max(sb);
            (ma - mb).abs() <= 0.5 * spread + 1e-9 && sa.max(sb) <= 2.0 * sa.min(sb) + 1e-9
        })
}

/// What the tangent-map probe of a wandering start found.
pub(super) struct ChaosProbe {
    /// Every period's map evaluated `ok`.
    pub(super) ok: bool,
    pub(super) periods: u64,
    pub(super) end: Section,
    /// The largest Lyapunov exponent per forcing period over the probe and its standard error
    /// (batch means over 8 batches).
    pub(super) lambda: f64,
    pub(super) se: f64,
    pub(super) cloud: Cloud,
}

/// The smallest exponent (per forcing period) that counts as chaotic: a motion whose nearby
/// states separate by less than 1 % per period is not told from a slow transient here.
pub const CHAOS_FLOOR: f64 = 0.01;

/// `n` periods from `s` with the tangent map ([`Benettin`], 8 periods of burn-in), the sections
/// gathered into a cloud.
pub(super) fn chaos_probe(f: &Forcing, s: &Section, n: u64) -> ChaosProbe {
    let mut b = Benettin::new(PROBE_BURN);
    let mut s = *s;
    let mut cloud = Cloud::new(f);
    for k in 0..n {
        let e = eval(f, &s, 1, true);
        if e.outcome != Outcome::Ok {
            return ChaosProbe {
                ok: false,
                periods: k + 1,
                end: s,
                lambda: f64::NAN,
                se: f64::NAN,
                cloud,
            };
        }
        s = e.end;
        cloud.add(&s);
        b.step(e.jacobian.as_ref());
    }
    let (lambda, se) = b.estimate();
    ChaosProbe {
        ok: true,
        periods: n,
        end: s,
        lambda,
        se,
        cloud,
    }
}

/// Periods of a probe's tangent vector not counted (it turns towards the most unstable
/// direction first).
pub(super) const PROBE_BURN: u64 = 8;
