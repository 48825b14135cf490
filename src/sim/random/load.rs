//! The load of one run, sample by sample: white noise through the spectrum's filter and the
//! envelope (a random load), or a record times its scale. A run's samples are made once per
//! realization into a [`LoadBlock`] that its runs share; a pass may also make them as it asks
//! for them (the same bits); the envelope's values at the samples are a table made once per
//! design.
//!
//! # White noise and its filters
//! Sample `k` of the white noise is `sigma N_k`, `sigma = sqrt(2 pi S0 / dt)`, with `N_k` a
//! standard normal: the band-limited white noise whose two-sided density is `S0` below the
//! sampling's Nyquist frequency `pi / dt` (its spectrum is `S0 sinc^2(omega dt / 2)` when held
//! over each sample, `S0 sinc^4(omega dt / 2)` when linear between samples; docs/scenes.md says
//! what that does to the response). A filter `s' = A s + b w`, load `c . s`, is integrated
//! exactly per sample with the white noise held over it: `s_{k+1} = Phi s_k + Gamma w_k`,
//! `Phi = exp(A dt)`, `Gamma = int_0^dt exp(A r) dr b`, both read off the exponential of the
//! augmented matrix `[[A, b], [0, 0]] dt` (Van Loan 1978). The filter starts at rest, so a
//! filtered load starts at 0.
//!
//! * Kanai–Tajimi: `s = (u, u')`, `u'' + 2 zeta_g omega_g u' + omega_g^2 u = -w`, load
//!   `a_g = -(2 zeta_g omega_g u' + omega_g^2 u)`, whose density is `S0 |H_KT|^2`
//!   ([`super::Spectrum::density`]).
//! * Clough–Penzien: `s = (u, u', p, p')` with `p'' + 2 zeta_f omega_f p' + omega_f^2 p = a_KT`,
//!   load `a_g = p'' = a_KT - 2 zeta_f omega_f p' - omega_f^2 p`.
//!
//! # Normals
//! [`RealizationStream`] draws its normals from a PCG-64 stream by Marsaglia and Tsang's
//! ziggurat (Journal of Statistical Software 5 (2000), 256 layers): one 64-bit output gives the
//! layer (8 bits), the sign and a 52-bit uniform, and 98.8 % of the draws end there with one
//! multiplication and one comparison; the rest test the density or, below 0.03 %, draw from the
//! tail beyond `r = 3.654`. The inverse normal CDF it replaced cost a quarter of a run. The
//! normals are a fixed function of (study seed, design point, realization) and their order.
//! [`GivenNormals`] takes them from a slice (subset simulation moves a realization's normals and
//! runs it again, [`crate::stats::subset`]).

use nalgebra::DMatrix;
use rand_core::Rng;
use rand_pcg::Pcg64;

use super::{Envelope, Excitation, RandomLoad, RandomScene, Spectrum};
use crate::numeric::{mix64, open_uniform};

/// A source of standard normal numbers, one per call.
pub trait Normals {
    fn next_normal(&mut self) -> f64;
}

/// The standard normals of one realization: a PCG-64 stream derived from (study seed, design
/// point, realization), through the ziggurat (module doc).
#[derive(Clone, Debug)]
pub struct RealizationStream {
    rng: Pcg64,
}

impl RealizationStream {
    /// The stream of `realization` at design point `point` of a study seeded `study_seed`. A
    /// domain constant keeps it apart from the measurement-noise streams of
    /// [`crate::sim::noise::NoiseStream`] built from the same numbers.
    pub fn new(study_seed: u64, point: u64, realization: u64) -> Self {
        const LOAD: u64 = 0x4C4F_4144_5345_4544; // "LOADSEED"
        let a = mix64(study_seed ^ mix64(LOAD));
        let b = mix64(a ^ mix64(point.wrapping_add(0x5EED)));
        let c = mix64(b ^ mix64(realization ^ LOAD.rotate_left(17)));
        let state = (u128::from(a ^ c) << 64) | u128::from(b);
        let stream = (u128::from(mix64(c)) << 64) | u128::from(mix64(a ^ b ^ c));
        RealizationStream {
            rng: Pcg64::new(state, stream),
        }
    }
}

impl Normals for RealizationStream {
    #[inline]
    fn next_normal(&mut self) -> f64 {
        ziggurat(&mut self.rng)
    }
}

/// Layers of the ziggurat.
const LAYERS: usize = 256;
/// The start of the tail, `r`, and the area `v` of each layer (and of the base strip with the
/// tail) under `exp(-x^2 / 2)`, Marsaglia and Tsang's values for 256 layers.
const ZIG_R: f64 = 3.654_152_885_361_009;
const ZIG_V: f64 = 0.004_928_673_233_99;

/// The layers' right ends `x_i` (`x_0 = v / f(r)` the base strip's width, `x_1 = r`, ...,
/// `x_256 = 0`) and `f(x_i) = exp(-x_i^2 / 2)`: `x_{i+1} = f^-1(v / x_i + f(x_i))`.
struct Ziggurat {
    x: [f64; LAYERS + 1],
    f: [f64; LAYERS + 1],
}

fn tables() -> &'static Ziggurat {
    static TABLES: std::sync::OnceLock<Ziggurat> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let pdf = |x: f64| (-0.5 * x * x).exp();
        let mut z = Ziggurat {
            x: [0.0; LAYERS + 1],
            f: [0.0; LAYERS + 1],
        };
        z.x[0] = ZIG_V / pdf(ZIG_R);
        z.x[1] = ZIG_R;
        for i in 2..LAYERS {
            let prev = z.x[i - 1];
            z.x[i] = (-2.0 * (ZIG_V / prev + pdf(prev)).ln()).sqrt();
        }
        z.x[LAYERS] = 0.0;
        for i in 0..=LAYERS {
            z.f[i] = pdf(z.x[i]);
        }
        z
    })
}

/// A standard normal from `rng` by the ziggurat (module doc): the common case inline, the
/// rest (1.2 % of the draws) out of line.
#[inline(always)]
fn ziggurat(rng: &mut Pcg64) -> f64 {
    let z = tables();
    let (i, u, x) = layer(z, rng.next_u64());
    if x.abs() < z.x[i + 1] {
        return x;
    }
    ziggurat_rest(rng, z, (i, u, x))
}

/// The layer `i`, the uniform `u` in (-1, 1) from the top 52 bits (disjoint from the layer's
/// 8) and the candidate `x = u x_i` of one 64-bit draw.
#[inline(always)]
fn layer(z: &Ziggurat, bits: u64) -> (usize, f64, f64) {
    let i = (bits & 0xff) as usize;
    // (Through i64: the same value, a cheaper conversion than from u64 on x86-64.)
    let u = 2.0 * ((((bits >> 12) as i64) as f64 + 0.5) * (1.0 / (1u64 << 52) as f64)) - 1.0;
    (i, u, u * z.x[i])
}

/// The ziggurat after a draw `(i, u, x)` outside its layer's rectangle: the tail or the
/// density's test, then new draws until one is accepted.
#[cold]
#[inline(never)]
fn ziggurat_rest(rng: &mut Pcg64, z: &Ziggurat, (mut i, mut u, mut x): (usize, f64, f64)) -> f64 {
    loop {
        if i == 0 {
            // The tail beyond r (Marsaglia 1964).
            loop {
                let a = open_uniform(rng.next_u64()).ln() / ZIG_R;
                let b = open_uniform(rng.next_u64()).ln();
                if -2.0 * b >= a * a {
                    return if u < 0.0 { a - ZIG_R } else { ZIG_R - a };
                }
            }
        }
        let y = z.f[i + 1] + (z.f[i] - z.f[i + 1]) * open_uniform(rng.next_u64());
        if y < (-0.5 * x * x).exp() {
            return x;
        }
        (i, u, x) = layer(z, rng.next_u64());
        if x.abs() < z.x[i + 1] {
            return x;
        }
    }
}

/// Normals from a slice, in order; past its end, zeros (the white noise stops). A run needs
/// [`super::RandomRun::n_normals`] of them.
#[derive(Clone, Debug)]
pub struct GivenNormals<'a> {
    u: &'a [f64],
    i: usize,
}

impl<'a> GivenNormals<'a> {
    pub fn new(u: &'a [f64]) -> Self {
        GivenNormals { u, i: 0 }
    }
}

impl Normals for GivenNormals<'_> {
    #[inline]
    fn next_normal(&mut self) -> f64 {
        let z = self.u.get(self.i).copied().unwrap_or(0.0);
        self.i += 1;
        z
    }
}

/// A filter over one sample: `s_{k+1} = Phi s_k + Gamma w_k`, load `out . s` (`dim` states, at
/// most 4; 0 for white noise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Filter {
    dim: usize,
    /// `Phi` by columns, `cols[j][i] = Phi_ij` (zero past `dim`): a step is then four
    /// column-times-scalar sums, which the compiler does two rows at a time.
    cols: [[f64; 4]; 4],
    gamma: [f64; 4],
    out: [f64; 4],
}

impl Filter {
    /// The spectrum's filter over `dt` (module doc).
    pub fn new(spectrum: &Spectrum, dt: f64) -> Filter {
        let kt = |w: f64, z: f64| [-w * w, -2.0 * z * w];
        let (a, out): (Vec<Vec<f64>>, Vec<f64>) = match *spectrum {
            Spectrum::White => (Vec::new(), Vec::new()),
            Spectrum::KanaiTajimi { omega_g, zeta_g } => {
                let [k, c] = kt(omega_g, zeta_g);
                (vec![vec![0.0, 1.0], vec![k, c]], vec![k, c])
            }
            Spectrum::CloughPenzien {
                omega_g,
                zeta_g,
                omega_f,
                zeta_f,
            } => {
                let [k, c] = kt(omega_g, zeta_g);
                let [kf, cf] = kt(omega_f, zeta_f);
                let a = vec![
                    vec![0.0, 1.0, 0.0, 0.0],
                    vec![k, c, 0.0, 0.0],
                    vec![0.0, 0.0, 0.0, 1.0],
                    vec![k, c, kf, cf],
                ];
                (a, vec![k, c, kf, cf])
            }
        };
        let dim = out.len();
        let mut f = Filter {
            dim,
            cols: [[0.0; 4]; 4],
            gamma: [0.0; 4],
            out: [0.0; 4],
        };
        if dim == 0 {
            return f;
        }
        // Van Loan: exp([[A, b], [0, 0]] dt) = [[Phi, Gamma], [0, 1]]; the noise enters u''
        // with the sign -1.
        let mut aug = DMatrix::<f64>::zeros(dim + 1, dim + 1);
        for (i, row) in a.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                aug[(i, j)] = v * dt;
            }
        }
        aug[(1, dim)] = -dt;
        let e = aug.exp();
        for i in 0..dim {
            for j in 0..dim {
                f.cols[j][i] = e[(i, j)];
            }
            f.gamma[i] = e[(i, dim)];
            f.out[i] = out[i];
        }
        f
    }

    /// `s <- Phi s + Gamma w`, each row summed in the order `Phi_i0 s_0 + ... + Phi_i3 s_3 +
    /// Gamma_i w` (the rows past `dim` are zeros and stay zero).
    #[inline]
    fn step(&self, s: &mut [f64; 4], w: f64) {
        let c = &self.cols;
        let mut next = [0.0; 4];
        for (i, n) in next.iter_mut().enumerate() {
            *n = c[0][i] * s[0]
                + c[1][i] * s[1]
                + c[2][i] * s[2]
                + c[3][i] * s[3]
                + self.gamma[i] * w;
        }
        *s = next;
    }

    #[inline]
    fn output(&self, s: &[f64; 4]) -> f64 {
        self.out[0] * s[0] + self.out[1] * s[1] + self.out[2] * s[2] + self.out[3] * s[3]
    }

    /// Normals one run of `n` intervals draws: one per sample for white noise (`n + 1`), one per
    /// interval for a filter (`n`: the load at `t_k` needs the noise before it).
    pub fn normals(&self, segments: u64) -> u64 {
        if self.dim == 0 {
            segments + 1
        } else {
            segments
        }
    }
}

/// What a run's load needs from its scene: the filter, the scale of the white noise, the
/// envelope; or the record's samples and scale.
// One per design point, built once and never moved in a loop: the filter's 240 bytes inline
// are cheaper than a box read at every sample.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub(crate) enum Plan {
    Random {
        filter: Filter,
        sigma: f64,
        envelope: Option<Envelope>,
        /// The envelope at every sample `k dt` of a run, `envelope.at(k dt)` as computed at the
        /// sample (the same bits), made once per design instead of one exponential per sample;
        /// empty without an envelope or past [`ENVELOPE_TABLE_MAX`] samples (then computed).
        table: std::sync::Arc<[f64]>,
    },
    Record {
        values: std::sync::Arc<[f64]>,
        scale: f64,
    },
}

impl Plan {
    pub fn new(scene: &RandomScene) -> Plan {
        match &scene.excitation {
            Excitation::Random(RandomLoad {
                spectrum,
                S0,
                envelope,
            }) => Plan::Random {
                filter: Filter::new(spectrum, scene.dt),
                sigma: (std::f64::consts::TAU * S0 / scene.dt).sqrt(),
                envelope: *envelope,
                table: envelope_table(envelope.as_ref(), scene.dt, scene.segments()),
            },
            Excitation::Record(r) => Plan::Record {
                values: r.values.clone(),
                scale: r.scale,
            },
            // A run takes one record of a suite ([`RandomScene::for_case`]); a suite as a whole
            // stands for its first.
            Excitation::Suite(_) => match &scene.for_case(0).excitation {
                Excitation::Record(r) => Plan::Record {
                    values: r.values.clone(),
                    scale: r.scale,
                },
                _ => Plan::Record {
                    values: std::sync::Arc::from(Vec::new()),
                    scale: 1.0,
                },
            },
        }
    }

    /// Normals a run of `segments` intervals draws (none for a record).
    pub fn normals(&self, segments: u64) -> u64 {
        match self {
            Plan::Random { filter, .. } => filter.normals(segments),
            Plan::Record { .. } => 0,
        }
    }
}

/// Most samples an envelope table holds (8 MB): a longer run computes its envelope per sample.
pub(crate) const ENVELOPE_TABLE_MAX: u64 = 1 << 20;

/// The envelope at samples `0..=segments` of `dt` (empty without an envelope or past
/// [`ENVELOPE_TABLE_MAX`]): `e.at(k dt)` with `k dt` formed as [`Samples`] forms it.
fn envelope_table(envelope: Option<&Envelope>, dt: f64, segments: u64) -> std::sync::Arc<[f64]> {
    match envelope {
        Some(e) if segments < ENVELOPE_TABLE_MAX => {
            (0..=segments).map(|k| e.at(k as f64 * dt)).collect()
        }
        _ => std::sync::Arc::from(Vec::new()),
    }
}

/// One realization's load samples at scale 1, made once and read by every run of the same
/// motion ([`super::RandomRun::load`]): its own intensity measures, its run at a stripe and the
/// runs of its capacity search, instead of drawing and filtering the noise again for each. Sample
/// `k` is the load at `t_k = k dt` (m/s^2 or N), the same bits as a run draws it; past the last
/// sample the load is zero, as past a record's end.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadBlock {
    pub(crate) values: Vec<f64>,
}

impl LoadBlock {
    /// The samples (m/s^2 or N).
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

/// The load of one run, interval by interval: [`Samples::next`] gives the load over interval `k`
/// (from `t_k` to `t_{k+1}`) as its value at `t_k` and its slope.
pub(crate) struct Samples<'a, N: Normals> {
    plan: &'a Plan,
    dt: f64,
    normals: N,
    /// The filter's state at `t_k`.
    state: [f64; 4],
    /// The random load's sample at `t_k`.
    q: f64,
    /// The next interval.
    k: u64,
    /// The factor on every load value (a stripe's or a capacity search's scale; 1 leaves the
    /// bits as they are).
    gain: f64,
    /// The samples made beforehand ([`LoadBlock`]), read in place of the plan's.
    block: Option<&'a [f64]>,
}

impl<'a, N: Normals> Samples<'a, N> {
    pub fn new(plan: &'a Plan, dt: f64, normals: N, gain: f64) -> Self {
        let mut s = Samples {
            plan,
            dt,
            normals,
            state: [0.0; 4],
            q: 0.0,
            k: 0,
            gain,
            block: None,
        };
        if let Plan::Random { .. } = plan {
            s.q = s.random_sample(0);
        }
        s
    }

    /// The samples `block` (at scale 1) times `gain`: the same pairs as the run that made them
    /// ([`Samples::fill`]) would draw, bit for bit.
    pub fn from_block(
        plan: &'a Plan,
        dt: f64,
        block: &'a LoadBlock,
        normals: N,
        gain: f64,
    ) -> Self {
        Samples {
            plan,
            dt,
            normals,
            state: [0.0; 4],
            q: 0.0,
            k: 0,
            gain,
            block: Some(&block.values),
        }
    }

    /// Moves on `n` intervals of a block's samples (the lanes' crossing of
    /// [`super::run`] reads them in place, as [`Samples::next`] would).
    pub(crate) fn skip(&mut self, n: u64) {
        debug_assert!(self.block.is_some());
        self.k += n;
    }

    /// Writes the samples `t_0 .. t_segments` at scale 1 into `out` (emptied first): a record's
    /// up to its end, a random load's all of them, drawn as [`Samples::next`] draws them.
    pub fn fill(mut self, segments: u64, out: &mut Vec<f64>) {
        out.clear();
        match self.plan {
            Plan::Record { values, scale } => {
                let n = values.len().min(segments.saturating_add(1) as usize);
                out.extend(values[..n].iter().map(|a| a * scale));
            }
            Plan::Random { filter, .. } if filter.dim > 0 => self.fill_filtered(segments, out),
            Plan::Random { .. } => {
                out.reserve(segments as usize + 1);
                out.push(self.q);
                for k in 1..=segments {
                    let q = self.random_sample(k);
                    out.push(q);
                }
            }
        }
    }

    /// [`Samples::fill`] of a filtered load in two passes over `out`: the filter's inputs
    /// `sigma w_k` first, then the filter, its output and the envelope, each sample in place of
    /// its input. The same arithmetic in the same order as [`Samples::random_sample`] (the same
    /// bits), but the filter's state stays in registers: in one loop the ziggurat's out-of-line
    /// call kept it in memory, a store and a load on its chain at every sample (BENCHMARKS.md,
    /// "Random realizations at half the cost", stop 92).
    fn fill_filtered(&mut self, segments: u64, out: &mut Vec<f64>) {
        let Plan::Random {
            filter,
            sigma,
            envelope,
            table,
        } = self.plan
        else {
            unreachable!("fill_filtered is called for a random load alone");
        };
        out.reserve(segments as usize + 1);
        out.push(self.q);
        for _ in 0..segments {
            out.push(sigma * self.normals.next_normal());
        }
        let mut s = self.state;
        let dt = self.dt;
        match envelope {
            Some(e) => {
                for (k, q) in out.iter_mut().enumerate().skip(1) {
                    filter.step(&mut s, *q);
                    let at = table.get(k).copied().unwrap_or_else(|| e.at(k as f64 * dt));
                    *q = filter.output(&s) * at;
                }
            }
            None => {
                for q in out.iter_mut().skip(1) {
                    filter.step(&mut s, *q);
                    *q = filter.output(&s);
                }
            }
        }
        self.state = s;
    }

    /// The random load's sample at `t_k`, `k` in increasing order from 0 (it draws the normal
    /// that reaches it: white noise's own, or the filter's input over the interval before).
    /// (Inline: the loops that draw samples then hold no call.)
    #[inline(always)]
    fn random_sample(&mut self, k: u64) -> f64 {
        let Plan::Random {
            filter,
            sigma,
            envelope,
            table,
        } = self.plan
        else {
            return 0.0;
        };
        let raw = if filter.dim == 0 {
            sigma * self.normals.next_normal()
        } else {
            if k > 0 {
                let w = sigma * self.normals.next_normal();
                filter.step(&mut self.state, w);
            }
            filter.output(&self.state)
        };
        match envelope {
            Some(e) => {
                raw * table
                    .get(k as usize)
                    .copied()
                    .unwrap_or_else(|| e.at(k as f64 * self.dt))
            }
            None => raw,
        }
    }

    /// The load over the next interval: its value at the start and its slope (per s). A
    /// record's interval `k` runs from `scale v_k` to `scale v_{k+1}`; from its last sample on
    /// the load is zero (free motion). Both times the gain.
    #[inline]
    pub fn next(&mut self) -> (f64, f64) {
        let (q0, s) = self.next_unscaled();
        // Times 1 is exact: gain 1 leaves every bit, without a branch.
        (q0 * self.gain, s * self.gain)
    }

    #[inline]
    fn next_unscaled(&mut self) -> (f64, f64) {
        let k = self.k;
        self.k += 1;
        if let Some(values) = self.block {
            // As a record's interval k at scale 1: the same pair as when the samples were drawn.
            let i = k as usize;
            return match (values.get(i), values.get(i + 1)) {
                (Some(&q0), Some(&q1)) => (q0, (q1 - q0) / self.dt),
                _ => (0.0, 0.0),
            };
        }
        match self.plan {
            Plan::Record { values, scale } => {
                let i = k as usize;
                match (values.get(i), values.get(i + 1)) {
                    (Some(a), Some(b)) => {
                        let (q0, q1) = (a * scale, b * scale);
                        (q0, (q1 - q0) / self.dt)
                    }
                    _ => (0.0, 0.0),
                }
            }
            Plan::Random { .. } => {
                let q0 = self.q;
                let q1 = self.random_sample(k + 1);
                self.q = q1;
                (q0, (q1 - q0) / self.dt)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ziggurat_closes_at_the_top_and_its_normals_have_the_normal_law() {
        // The recurrence must land at f(x_255) + v / x_255 = 1 (the top layer's height): the
        // published r and v close the ziggurat.
        let z = tables();
        let top = z.f[LAYERS - 1] + ZIG_V / z.x[LAYERS - 1];
        assert!((top - 1.0).abs() < 1e-9, "{top}");
        assert!(z.x.windows(2).skip(1).all(|w| w[0] > w[1]));
        // 10^6 normals against the normal law: the share below each of 13 points within 4.5
        // binomial standard errors, and both tails beyond 3.5 and 4.
        let mut s = RealizationStream::new(1, 2, 3);
        let n = 1_000_000;
        let xs: Vec<f64> = (0..n).map(|_| s.next_normal()).collect();
        let phi = |z: f64| 0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2);
        for z in [
            -4.0, -3.5, -3.0, -2.0, -1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 3.0, 3.7,
        ] {
            let share = xs.iter().filter(|&&x| x < z).count() as f64 / n as f64;
            let p = phi(z);
            let se = (p * (1.0 - p) / n as f64).sqrt();
            assert!((share - p).abs() <= 4.5 * se, "z = {z}: {share} vs {p}");
        }
    }

    #[test]
    fn a_stream_is_standard_normal_and_seeded() {
        let mut s = RealizationStream::new(7, 3, 11);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| s.next_normal()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        // 4.5 standard errors: the mean's is 1/sqrt(n), the variance's sqrt(2/n).
        assert!(mean.abs() < 4.5 / (n as f64).sqrt(), "{mean}");
        assert!((var - 1.0).abs() < 4.5 * (2.0 / n as f64).sqrt(), "{var}");
        let first = |a, b, c| RealizationStream::new(a, b, c).next_normal().to_bits();
        assert_eq!(first(7, 3, 11), xs[0].to_bits());
        for (a, b, c) in [(8, 3, 11), (7, 4, 11), (7, 3, 12)] {
            assert_ne!(first(a, b, c), xs[0].to_bits());
        }
    }

    #[test]
    fn the_kanai_tajimi_filter_matches_its_oscillator() {
        // u'' + 2 z w u' + w^2 u = -w_in: Phi is the free oscillator's propagator and Gamma its
        // response to a held unit input from rest, (u, u') = -(1 - propagated (1, 0)) / w^2
        // shifted: u_p = -1 / w^2.
        let (w, z, dt) = (15.7, 0.6, 0.005);
        let f = Filter::new(
            &Spectrum::KanaiTajimi {
                omega_g: w,
                zeta_g: z,
            },
            dt,
        );
        let osc = crate::sim::linear::Oscillator::new(1.0, w * w, 2.0 * z * w);
        let p = osc.propagator(dt);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs().max(1e-3);
        assert!(close(f.cols[0][0], p.xx) && close(f.cols[1][0], p.xv));
        assert!(close(f.cols[0][1], p.vx) && close(f.cols[1][1], p.vv));
        let up = -1.0 / (w * w);
        let (x, v) = p.apply(-up, 0.0);
        assert!(
            close(f.gamma[0], x + up) && close(f.gamma[1], v),
            "{:?}",
            f.gamma
        );
    }

    #[test]
    fn a_record_ends_in_free_motion() {
        let plan = Plan::Record {
            values: vec![1.0, 3.0, 2.0].into(),
            scale: 2.0,
        };
        let mut s = Samples::new(&plan, 0.5, GivenNormals::new(&[]), 1.0);
        assert_eq!(s.next(), (2.0, 8.0));
        assert_eq!(s.next(), (6.0, -4.0));
        assert_eq!(s.next(), (0.0, 0.0));
        assert_eq!(s.next(), (0.0, 0.0));
    }
}
