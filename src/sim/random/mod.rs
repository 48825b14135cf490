//! The random and record scenes: the impact damper under a random load generated per
//! realization, or under a recorded accelerogram or force history (docs/model.md §13,
//! docs/scenes.md).
//!
//! # Equations (SI units: m, s, kg, N)
//! The load `q(t)` is given at samples `t_k = k dt` and is linear between them. Under ground
//! acceleration (`input = "base"`, `q = a_g` in m/s^2), with displacements relative to the
//! ground,
//!
//! ```text
//! M x'' + C x' + K x = -M a_g(t)          y'' = -a_g(t)        between impacts,
//! ```
//!
//! and under a force on the main mass (`input = "force"`, `q = F` in N)
//! `M x'' + C x' + K x = F(t)`, `y'' = 0`. Impacts at `|y - x| = d/2` obey the law of §1
//! ([`crate::sim::impact`]; the energy they take is the same in any frame moving with the
//! ground, since momentum is conserved), and the chatter rule of [`crate::sim::phase`] turns an
//! accumulation of impacts into sticking, with the wall's acceleration taken relative to the
//! inner mass's own. While stuck the pair of mass `M + m` feels the load
//! (`(M + m) x'' + C x' + K x = -(M + m) a_g` or `F`) and separates when the contact force would
//! have to pull: on the right wall contact holds while `C x' + K x >= 0` under ground
//! acceleration (the load moves both masses alike and drops out) and while
//! `C x' + K x - F >= 0` under a force; on the left wall the reverse.
//!
//! Between samples and events every motion is in closed form ([`motion`]): the free motion of
//! §2 plus the particular solution of a linear load `f0 + s tau`, which is linear,
//! `x_p = (f0 + s tau) / K - C s / K^2`; the inner mass's is a cubic. Events keep the guarantee
//! of the other scenes: the bounds of [`crate::sim::driven`] bracket every root, so no impact is
//! missed, grazing contacts included, and event times are within `tol * 2 pi sqrt(M/K)`. Each
//! load sample runs on a fresh clock, so a long record keeps full precision in its event times.
//!
//! # Loads ([`load`])
//! * **Random** (`kind = "random"`): band-limited white noise of two-sided spectral density `S0`
//!   ((m/s^2)^2 or N^2 per rad/s): independent standard normals `N_k` scaled to variance
//!   `2 pi S0 / dt`. `white` takes them as the load samples; `kanai-tajimi` passes them (held
//!   over each sample) through `u'' + 2 zeta_g omega_g u' + omega_g^2 u = -w`, load
//!   `-(2 zeta_g omega_g u' + omega_g^2 u)`; `clough-penzien` adds the high-pass
//!   `p'' + 2 zeta_f omega_f p' + omega_f^2 p = a_KT`, load `p''`. Each filter is integrated
//!   exactly per sample by its state-transition matrix. An optional envelope (Jennings et al.
//!   1968) multiplies the load: `(t / t1)^2` before `t1`, 1 to `t2`, `exp(-c (t - t2))` after.
//!   The normals of a realization come from a stream derived from (study seed, design point,
//!   realization) ([`load::RealizationStream`]), drawn as the run goes, or once into a
//!   [`LoadBlock`] that the runs of one motion share (its intensity, its stripe, its capacity
//!   search): the same bits either way, on any thread; no load outlives its realization.
//! * **Record** (`kind = "record"`): the samples of a given accelerogram or force history times
//!   `scale`; past the record's end (a `duration` longer than it) the load is zero and the
//!   motion free.
//!
//! # Observables ([`RandomRecord`])
//! Over `[0, duration]`: `amplitude = max |x|`, exact between samples too (the ends, every zero
//! of `x'`, every impact's kink), and its time `t_peak`; `rms_x = sqrt(int x^2 dt / duration)`
//! and `rms_acc`, the same for the main mass's absolute acceleration (`x'' + a_g` under ground
//! acceleration; the impulses of the impacts, Dirac masses, are not in it: their effect is in
//! `energy_impact`), both integrated exactly per piece between events (a quadratic form of the
//! sample's state and load for a whole sample of free flight, 8-point Gauss–Legendre otherwise);
//! `first_passage_time`, the first time `|x|` exceeds `threshold` (located to the event
//! tolerance); `impacts`, `sticks`, `energy_impact`.
//!
//! The run starts from the system's initial state (a study of these scenes starts at rest by
//! default).

mod hull;
pub mod ida;
pub mod intensity;
pub mod load;
pub mod measure;
pub(crate) mod motion;
mod run;

use std::sync::Arc;

use serde::Serialize;

use crate::model::{RangeError, fmt_value};

pub use ida::Capacity;
pub use intensity::own_intensity;
pub use load::{GivenNormals, LoadBlock, Normals, RealizationStream};
pub use measure::{IntensitySpec, Measure, OwnIntensity};
pub(crate) use run::LANES;
pub use run::{RandomRun, simulate_random};

/// Where the load acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Input {
    /// Ground acceleration `a_g` (m/s^2); displacements relative to the ground.
    Base,
    /// A force `F` on the main mass (N).
    Force,
}

impl Input {
    pub const NAMES: [&'static str; 2] = ["base", "force"];

    pub fn name(self) -> &'static str {
        match self {
            Input::Base => "base",
            Input::Force => "force",
        }
    }

    pub fn parse(s: &str) -> Option<Input> {
        match s {
            "base" => Some(Input::Base),
            "force" => Some(Input::Force),
            _ => None,
        }
    }
}

/// The spectrum of a random load (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "spectrum", rename_all = "kebab-case")]
pub enum Spectrum {
    /// Band-limited white noise, linear between samples.
    White,
    /// Kanai–Tajimi: white noise through the soil filter `(omega_g (rad/s), zeta_g)`.
    KanaiTajimi { omega_g: f64, zeta_g: f64 },
    /// Clough–Penzien: Kanai–Tajimi and the high-pass filter `(omega_f (rad/s), zeta_f)`.
    CloughPenzien {
        omega_g: f64,
        zeta_g: f64,
        omega_f: f64,
        zeta_f: f64,
    },
}

impl Spectrum {
    pub const NAMES: [&'static str; 3] = ["white", "kanai-tajimi", "clough-penzien"];

    pub fn name(&self) -> &'static str {
        match self {
            Spectrum::White => "white",
            Spectrum::KanaiTajimi { .. } => "kanai-tajimi",
            Spectrum::CloughPenzien { .. } => "clough-penzien",
        }
    }

    /// The two-sided spectral density of the load at `omega` (rad/s) per unit `S0`, of the
    /// continuous process (before sampling): 1 for white noise,
    /// `(omega_g^4 + 4 zeta_g^2 omega_g^2 omega^2) / ((omega_g^2 - omega^2)^2 +
    /// 4 zeta_g^2 omega_g^2 omega^2)` for Kanai–Tajimi, times
    /// `omega^4 / ((omega_f^2 - omega^2)^2 + 4 zeta_f^2 omega_f^2 omega^2)` for Clough–Penzien.
    pub fn density(&self, omega: f64) -> f64 {
        let kt = |wg: f64, zg: f64| {
            let (w2, g2) = (omega * omega, wg * wg);
            let c = 4.0 * zg * zg * g2 * w2;
            (g2 * g2 + c) / ((g2 - w2).powi(2) + c)
        };
        match *self {
            Spectrum::White => 1.0,
            Spectrum::KanaiTajimi { omega_g, zeta_g } => kt(omega_g, zeta_g),
            Spectrum::CloughPenzien {
                omega_g,
                zeta_g,
                omega_f,
                zeta_f,
            } => {
                let (w2, f2) = (omega * omega, omega_f * omega_f);
                let hp = w2 * w2 / ((f2 - w2).powi(2) + 4.0 * zeta_f * zeta_f * f2 * w2);
                kt(omega_g, zeta_g) * hp
            }
        }
    }
}

/// Jennings et al.'s (1968) envelope: `(t / t1)^2` for `t < t1`, 1 on `[t1, t2]`,
/// `exp(-c (t - t2))` after `t2`. Times in s, `c` in 1/s.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Envelope {
    pub t1: f64,
    pub t2: f64,
    pub c: f64,
}

impl Envelope {
    /// The envelope's value at `t >= 0`.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        if t < self.t1 {
            let r = t / self.t1;
            r * r
        } else if t <= self.t2 {
            1.0
        } else {
            (-self.c * (t - self.t2)).exp()
        }
    }
}

/// A random load (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct RandomLoad {
    pub spectrum: Spectrum,
    /// Two-sided spectral density of the white noise, `> 0` ((m/s^2)^2 or N^2 per rad/s).
    pub S0: f64,
    pub envelope: Option<Envelope>,
}

/// A recorded load: its samples at the scene's `dt` from `t = 0` (m/s^2 or N) and a factor.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Recorded {
    /// The samples as read, shared by every run of a study.
    #[serde(skip)]
    pub values: Arc<[f64]>,
    /// The factor applied to every sample (the intensity a fragility study sweeps), `> 0`.
    pub scale: f64,
}

/// One record of a suite ([`Suite`]): its file's name, its samples (m/s^2 or N) at its own `dt`
/// from `t = 0`, and the run's length.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuiteRecord {
    /// The record's file name, as the study's folder or list gives it.
    pub name: String,
    /// Its sample interval (s), in `[1e-6, 1]`.
    pub dt: f64,
    /// The run's length (s): the record's own, or the study's `duration`.
    pub duration: f64,
    #[serde(skip)]
    pub values: Arc<[f64]>,
}

/// A suite of records (`[scene] records = [...]` or a folder): realization `c` of a design is
/// record `c` (in the order the study lists them, a folder's by file name), each run at its own
/// `dt` and length, all at the same factor `scale` (or, under an intensity measure, each
/// scaled to the stripe).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Suite {
    #[serde(serialize_with = "as_slice")]
    pub records: Arc<[SuiteRecord]>,
    /// The factor applied to every record's samples, `> 0`.
    pub scale: f64,
}

/// Serializes a shared slice as a sequence.
fn as_slice<S: serde::Serializer>(v: &Arc<[SuiteRecord]>, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&v[..], s)
}

/// What loads the structure.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Excitation {
    Random(RandomLoad),
    Record(Recorded),
    Suite(Suite),
}

/// The random or record scene's settings. Every field documents its unit and valid range.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RandomScene {
    /// Ground acceleration or a force on the main mass.
    pub input: Input,
    pub excitation: Excitation,
    /// The load's sample interval (s), in `[1e-6, 1]`.
    pub dt: f64,
    /// The run's length (s), in `(0, 1e6]`, at most `1e8` samples.
    pub duration: f64,
    /// The limit of `|x|` for the first passage (m), `> 0`; `None`: no first passage measured.
    pub threshold: Option<f64>,
    /// The intensity measure the study states stripes, capacities and hazard in (ground
    /// acceleration only); `None`: the load as given (`S0`, or a record's `scale`).
    pub intensity: Option<IntensitySpec>,
    /// A stripe: each motion scaled so that its own intensity measure equals this (g, `> 0`);
    /// `None`: each motion at scale 1. Only with `intensity`.
    pub im: Option<f64>,
}

/// Most load samples of one run (`duration / dt`).
pub const MAX_SAMPLES: f64 = 1e8;

impl RandomScene {
    /// The keys a study may sweep besides the system's: the random load's intensity and
    /// filters, the record's scale.
    pub const AXES: [&'static str; 7] = [
        "S0", "omega_g", "zeta_g", "omega_f", "zeta_f", "scale", "im",
    ];

    /// Samples (intervals of `dt`) the run covers: `ceil(duration / dt)`, the last one possibly
    /// shorter.
    pub fn segments(&self) -> u64 {
        let n = self.duration / self.dt;
        // A duration that is a whole number of samples up to rounding is that number.
        let r = n.round();
        if (n - r).abs() <= 1e-9 * r.max(1.0) {
            r.max(1.0) as u64
        } else {
            n.ceil() as u64
        }
    }

    /// A scene that stands for none: white noise of unit density over one sample of the default
    /// `dt`, valid. For a caller that must return a random scene where a study has none.
    pub fn placeholder() -> RandomScene {
        RandomScene {
            input: Input::Base,
            excitation: Excitation::Random(RandomLoad {
                spectrum: Spectrum::White,
                S0: 1.0,
                envelope: None,
            }),
            dt: 0.005,
            duration: 0.005,
            threshold: None,
            intensity: None,
            im: None,
        }
    }

    /// Whether a realization draws standard normals (a random load), or none (a record).
    pub fn draws_normals(&self) -> bool {
        matches!(self.excitation, Excitation::Random(_))
    }

    /// The scene realization `case` runs: a suite's record `case` as one record (its samples,
    /// `dt` and length, at the suite's scale); any other scene as it is. A case past the suite's
    /// end (never planned) runs its last record.
    pub fn for_case(&self, case: u32) -> std::borrow::Cow<'_, RandomScene> {
        let Excitation::Suite(suite) = &self.excitation else {
            return std::borrow::Cow::Borrowed(self);
        };
        let i = (case as usize).min(suite.records.len().saturating_sub(1));
        let Some(rec) = suite.records.get(i) else {
            return std::borrow::Cow::Borrowed(self);
        };
        std::borrow::Cow::Owned(RandomScene {
            excitation: Excitation::Record(Recorded {
                values: rec.values.clone(),
                scale: suite.scale,
            }),
            dt: rec.dt,
            duration: rec.duration,
            ..self.clone()
        })
    }

    /// The suite's records, empty for a random load or one record.
    pub fn suite(&self) -> &[SuiteRecord] {
        match &self.excitation {
            Excitation::Suite(s) => &s.records,
            _ => &[],
        }
    }

    /// The value of a sweepable key ([`RandomScene::AXES`]) if this scene's load has it.
    pub fn get(&self, key: &str) -> Option<f64> {
        if key == "im" {
            return self.im;
        }
        match (&self.excitation, key) {
            (Excitation::Random(r), "S0") => Some(r.S0),
            (Excitation::Record(r), "scale") => Some(r.scale),
            (Excitation::Suite(s), "scale") => Some(s.scale),
            (Excitation::Random(r), _) => match (r.spectrum, key) {
                (Spectrum::KanaiTajimi { omega_g, .. }, "omega_g")
                | (Spectrum::CloughPenzien { omega_g, .. }, "omega_g") => Some(omega_g),
                (Spectrum::KanaiTajimi { zeta_g, .. }, "zeta_g")
                | (Spectrum::CloughPenzien { zeta_g, .. }, "zeta_g") => Some(zeta_g),
                (Spectrum::CloughPenzien { omega_f, .. }, "omega_f") => Some(omega_f),
                (Spectrum::CloughPenzien { zeta_f, .. }, "zeta_f") => Some(zeta_f),
                _ => None,
            },
            _ => None,
        }
    }

    /// Sets a sweepable key ([`RandomScene::AXES`]) that applies to this scene's load; `false`
    /// for any other key.
    pub fn set(&mut self, key: &str, value: f64) -> bool {
        if key == "im" {
            self.im = Some(value);
            return true;
        }
        match (&mut self.excitation, key) {
            (Excitation::Random(r), "S0") => r.S0 = value,
            (Excitation::Random(r), _) => return set_filter(&mut r.spectrum, key, value),
            (Excitation::Record(r), "scale") => r.scale = value,
            (Excitation::Suite(s), "scale") => s.scale = value,
            _ => return false,
        }
        true
    }

    /// Checks every range; the error names the key, the value and what is allowed.
    pub fn validate(&self) -> Result<(), RangeError> {
        let positive = |key: &str, v: f64, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(RangeError::new(
                    key,
                    v,
                    format!("{what} must be a finite number > 0"),
                ))
            }
        };
        within("dt", self.dt, 1e-6, 1.0, "the load's sample interval (s)")?;
        if !(self.duration.is_finite() && self.duration > 0.0 && self.duration <= 1e6) {
            return Err(RangeError::new(
                "duration",
                self.duration,
                "the run's length (s) must be in (0, 1000000]",
            ));
        }
        if self.duration / self.dt > MAX_SAMPLES {
            return Err(RangeError::new(
                "duration",
                self.duration,
                format!(
                    "duration / dt = {} load samples; at most {} per run",
                    fmt_value(self.duration / self.dt),
                    fmt_value(MAX_SAMPLES)
                ),
            ));
        }
        if let Some(b) = self.threshold {
            positive("threshold", b, "the limit of |x| (m)")?;
        }
        if let Some(spec) = &self.intensity {
            spec.validate(self)?;
        }
        if let Some(im) = self.im {
            if self.intensity.is_none() {
                return Err(RangeError::new(
                    "im",
                    im,
                    "a stripe's intensity (g) needs [scene] intensity = \"pga\" or \"sa\"",
                ));
            }
            within("im", im, 1e-6, 1e3, "a stripe's intensity (g)")?;
        }
        match &self.excitation {
            Excitation::Random(r) => r.validate(),
            Excitation::Record(r) => positive("scale", r.scale, "the record's factor"),
            Excitation::Suite(s) => positive("scale", s.scale, "the records' factor"),
        }
    }
}

/// [`IntensitySpec`]'s check needs the scene; it lives here so that [`measure`] stays a leaf.
impl IntensitySpec {
    /// Checks the ranges for a scene sampled at `dt`; the error names the key.
    pub fn validate(&self, scene: &RandomScene) -> Result<(), RangeError> {
        if scene.input != Input::Base {
            return Err(RangeError::new(
                "intensity",
                f64::NAN,
                "an intensity measure (pga or sa) is a ground motion's: it needs input = \"base\"",
            ));
        }
        // A suite's coarsest record bounds it.
        let dt = scene.suite().iter().map(|r| r.dt).fold(scene.dt, f64::max);
        let lo = (8.0 * dt).max(0.01);
        if !(self.period.is_finite() && self.period >= lo && self.period <= 100.0) {
            return Err(RangeError::new(
                "T",
                self.period,
                format!(
                    "the period of Sa (s) must be in [{}, 100] (at least 0.01 s and 8 dt)",
                    crate::model::fmt_value(lo)
                ),
            ));
        }
        if !(self.ida_tol.is_finite() && (1e-6..=0.5).contains(&self.ida_tol)) {
            return Err(RangeError::new(
                "ida_tol",
                self.ida_tol,
                "a capacity's relative tolerance must be in [1e-6, 0.5]",
            ));
        }
        if !(self.ida_max.is_finite() && self.ida_max > 0.0 && self.ida_max <= 1000.0) {
            return Err(RangeError::new(
                "ida_max",
                self.ida_max,
                "the largest intensity a capacity search tries (g) must be in (0, 1000]",
            ));
        }
        Ok(())
    }
}

impl RandomLoad {
    /// Checks `S0`, the filters and the envelope.
    pub fn validate(&self) -> Result<(), RangeError> {
        if !(self.S0.is_finite() && self.S0 > 0.0 && self.S0 <= 1e12) {
            return Err(RangeError::new(
                "S0",
                self.S0,
                "the two-sided spectral density must be in (0, 1e12] ((m/s^2)^2 or N^2 per rad/s)",
            ));
        }
        let omega = |key: &str, v: f64| within(key, v, 1e-3, 1e5, "a filter frequency (rad/s)");
        let zeta = |key: &str, v: f64| within(key, v, 1e-3, 10.0, "a filter damping ratio");
        match self.spectrum {
            Spectrum::White => {}
            Spectrum::KanaiTajimi { omega_g, zeta_g } => {
                omega("omega_g", omega_g)?;
                zeta("zeta_g", zeta_g)?;
            }
            Spectrum::CloughPenzien {
                omega_g,
                zeta_g,
                omega_f,
                zeta_f,
            } => {
                omega("omega_g", omega_g)?;
                zeta("zeta_g", zeta_g)?;
                omega("omega_f", omega_f)?;
                zeta("zeta_f", zeta_f)?;
            }
        }
        if let Some(e) = &self.envelope {
            within(
                "envelope.t1",
                e.t1,
                0.0,
                1e6,
                "the envelope's rise time (s)",
            )?;
            if !(e.t2.is_finite() && e.t2 >= e.t1 && e.t2 <= 1e6) {
                return Err(RangeError::new(
                    "envelope.t2",
                    e.t2,
                    format!(
                        "the envelope's plateau end (s) must be at least its rise t1 = {} and at \
                         most 1e6",
                        fmt_value(e.t1)
                    ),
                ));
            }
            within(
                "envelope.c",
                e.c,
                0.0,
                1e6,
                "the envelope's decay rate (1/s)",
            )?;
        }
        Ok(())
    }
}

/// `lo <= v <= hi`, finite; the error says what the value is and the range.
fn within(key: &str, v: f64, lo: f64, hi: f64, what: &str) -> Result<(), RangeError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(RangeError::new(
            key,
            v,
            format!("{what} must be in [{}, {}]", fmt_value(lo), fmt_value(hi)),
        ))
    }
}

/// Sets one of the filters' keys on `spectrum` if it has it.
fn set_filter(spectrum: &mut Spectrum, key: &str, value: f64) -> bool {
    let slot = match (spectrum, key) {
        (Spectrum::KanaiTajimi { omega_g, .. }, "omega_g") => omega_g,
        (Spectrum::KanaiTajimi { zeta_g, .. }, "zeta_g") => zeta_g,
        (Spectrum::CloughPenzien { omega_g, .. }, "omega_g") => omega_g,
        (Spectrum::CloughPenzien { zeta_g, .. }, "zeta_g") => zeta_g,
        (Spectrum::CloughPenzien { omega_f, .. }, "omega_f") => omega_f,
        (Spectrum::CloughPenzien { zeta_f, .. }, "zeta_f") => zeta_f,
        _ => return false,
    };
    *slot = value;
    true
}

/// The result of one run of the random or record scene. Displacements in m, times in s,
/// accelerations in m/s^2, energies in J. Every observable over the duration is NaN unless the
/// outcome is `ok`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RandomRecord {
    pub outcome: crate::sim::record::Outcome,
    /// `max |x|` over `[0, duration]`, exact between samples too.
    pub amplitude: f64,
    /// When `|x|` reaches `amplitude` (the first time, to the event tolerance).
    pub t_peak: f64,
    /// `sqrt(int_0^T x^2 dt / T)`, `T` the duration.
    pub rms_x: f64,
    /// `sqrt(int_0^T a^2 dt / T)` of the main mass's absolute acceleration (impulses aside).
    pub rms_acc: f64,
    /// The first time `|x|` exceeds the threshold, `None` when it never does before the run
    /// stops (or no threshold is set). Kept when found before a cap stopped the run.
    pub first_passage_time: Option<f64>,
    /// Impacts (a chatter sequence ended by sticking counts its impacts) and sticking phases.
    pub impacts: u64,
    pub sticks: u64,
    /// Energy taken by the impacts and plastic closings (J).
    pub energy_impact: f64,
    /// Load samples the run used, time it stopped (s), solver steps.
    pub samples: u64,
    pub t_stop: f64,
    pub steps: u64,
}

/// One realization as the sweep stores it: the values of the load's sweepable keys at its
/// design point ([`RandomScene::AXES`] order, `None` where the scene's load has no such key;
/// units as there; under an intensity measure `scale` is the factor the run applied to its
/// motion, `im / own`) beside the run's [`RandomRecord`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RealizationRecord {
    pub load: [Option<f64>; 7],
    /// The motion's own intensity measures at scale 1 (g), where the study sets an intensity
    /// measure.
    pub own: Option<OwnIntensity>,
    /// The motion's capacity by incremental dynamic analysis, at the design stripe of a study
    /// with an intensity measure and a threshold ([`ida`]).
    pub capacity: Option<Capacity>,
    pub record: RandomRecord,
}

impl RealizationRecord {
    /// `record` of a run of `scene` at scale 1 without an intensity measure.
    pub fn new(scene: &RandomScene, record: RandomRecord) -> Self {
        RealizationRecord {
            load: RandomScene::AXES.map(|k| scene.get(k)),
            own: None,
            capacity: None,
            record,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_envelope_rises_holds_and_decays() {
        let e = Envelope {
            t1: 2.0,
            t2: 10.0,
            c: 0.5,
        };
        assert_eq!(e.at(0.0), 0.0);
        assert_eq!(e.at(1.0), 0.25);
        assert_eq!(e.at(2.0), 1.0);
        assert_eq!(e.at(10.0), 1.0);
        assert!((e.at(12.0) - (-1.0f64).exp()).abs() < 1e-15);
        let flat = Envelope {
            t1: 0.0,
            t2: 5.0,
            c: 1.0,
        };
        assert_eq!(flat.at(0.0), 1.0);
    }

    #[test]
    fn segments_count_whole_samples_and_a_last_short_one() {
        let mut s = RandomScene {
            duration: 20.0,
            ..RandomScene::placeholder()
        };
        assert_eq!(s.segments(), 4000);
        s.duration = 20.001;
        assert_eq!(s.segments(), 4001);
        s.dt = 0.01;
        s.duration = 0.3;
        assert_eq!(s.segments(), 30);
    }

    #[test]
    fn sweepable_keys_land_on_their_load() {
        let mut s = RandomScene {
            input: Input::Base,
            excitation: Excitation::Random(RandomLoad {
                spectrum: Spectrum::KanaiTajimi {
                    omega_g: 15.0,
                    zeta_g: 0.6,
                },
                S0: 1.0,
                envelope: None,
            }),
            dt: 0.005,
            duration: 1.0,
            threshold: None,
            intensity: None,
            im: None,
        };
        assert!(s.set("S0", 0.2) && s.set("omega_g", 12.0));
        assert!(!s.set("omega_f", 1.0) && !s.set("scale", 2.0) && !s.set("M", 1.0));
        let Excitation::Random(r) = &s.excitation else {
            panic!()
        };
        assert_eq!(r.S0, 0.2);
        assert_eq!(
            r.spectrum,
            Spectrum::KanaiTajimi {
                omega_g: 12.0,
                zeta_g: 0.6
            }
        );
    }

    #[test]
    fn the_kanai_tajimi_density_is_one_at_zero_and_decays() {
        let kt = Spectrum::KanaiTajimi {
            omega_g: 15.0,
            zeta_g: 0.6,
        };
        assert!((kt.density(0.0) - 1.0).abs() < 1e-15);
        assert!(kt.density(15.0) > 1.0);
        assert!(kt.density(1e4) < 1e-3);
        let cp = Spectrum::CloughPenzien {
            omega_g: 15.0,
            zeta_g: 0.6,
            omega_f: 1.5,
            zeta_f: 0.6,
        };
        assert_eq!(cp.density(0.0), 0.0);
        assert!((cp.density(100.0) / kt.density(100.0) - 1.0).abs() < 1e-3);
    }
}
