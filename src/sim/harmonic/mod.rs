//! The forced (harmonic) scene: steady-state vibration of the impact damper under a harmonic
//! force (model.md §8; Masri & Caughey 1966, Masri 1973).
//!
//! # Equations (SI units: m, s, kg, N)
//! Between impacts
//!
//! ```text
//! M x'' + C x' + K x = F0 cos(omega t)        y'' = 0
//! ```
//!
//! with `t` the time from the start of the run (forcing phase 0 at `t = 0`). Impacts at
//! `|y - x| = d/2` obey the same law as free decay ([`crate::sim::impact`], eq. 3–4), and the
//! same chatter rule turns an accumulation of impacts into sticking ([`crate::sim::phase`]). While
//! stuck on a wall the pair of mass `M + m` feels the force,
//! `(M + m) x'' + C x' + K x = F0 cos(omega t)`, and separates when the contact force would
//! have to pull: on the right wall contact holds while `C x' + K x - F0 cos(omega t) >= 0`, on
//! the left wall while it is `<= 0`.
//!
//! Each phase moves in closed form (see [`motion`]): the free motion of §2 (every damping
//! regime, accurate at `C = 0` and across `zeta = 1`) plus the particular solution
//! `P cos(omega t) + Q sin(omega t)`, `P = F0 (K - M omega^2) / D`, `Q = F0 C omega / D`,
//! `D = (K - M omega^2)^2 + (C omega)^2` (with `M + m` for the stuck pair).
//!
//! # Event brackets
//! The free part's energy never increases and the particular part has `|x_p^(j)| <= A omega^j`
//! (`A = sqrt(P^2 + Q^2)`), so `|x^(j)| <= B_j(free energy now) + A omega^j` for the rest of the
//! phase. That bounds the second and fourth derivatives of every watched function (the gaps to
//! the walls, `x'`, the contact force), and the safe step of [`crate::sim::exact`] cannot step
//! over a root: no impact is missed, grazing contacts included, and event times are within
//! `tol * 2 pi sqrt(M/K)` of the true roots (see the event finder, [`crate::sim::driven`]).
//!
//! # Ranges
//! `F0 > 0` (N); `omega > 0` (rad/s) or `r = omega / sqrt(K/M) > 0`, not both. Resonance
//! without damping is refused: the dynamic stiffness `|K - M omega^2 + i C omega|` (and with
//! `m > 0` the pair's, `|K - (M + m) omega^2 + i C omega|`) must be at least
//! [`motion::RESONANCE_FLOOR`]` K = 1e-6 K`, since below it the particular amplitude exceeds
//! `10^6 X_st` and cancels against the free part (the secular `t sin(omega t)` growth of exact
//! resonance has no steady state to measure). `n_meas` in `[1, 10^6]`, `n_trans` in
//! `[0, 10^8]`, `n_trans_max` in `[1, 10^8]`, `trans_tol` in `[1e-15, 1e-2]`, `period_tol`
//! in `[1e-15, 0.1]`.
//!
//! # Steady state
//! The Poincaré section is the state `S_k = (x, x', y - x, y')` at `t = k T_f`,
//! `T_f = 2 pi / omega`. Each period runs on a fresh clock (the force is `T_f`-periodic), so
//! event times keep full precision over thousands of periods. With `m = 0` the scene is the
//! primary system alone: a massless inner mass cannot act on the main mass, so it is not
//! simulated (no walls, no impacts; it is carried along at its initial place in the cavity)
//! and the section is `(x, x')`; free decay keeps simulating it, to no effect either.
//! Distances between sections are `sqrt(dx^2 + (dx'/wn)^2 + dz^2 + (dy'/wn)^2)` with
//! `wn = sqrt(K/M)` (in this norm a decaying free oscillation shrinks steadily from section to
//! section, whatever it turns by in a period), compared with the scale `L`, the largest
//! `max(|x|, |x'|/omega)` of the sections compared (about the steady amplitude).
//!
//! * **Transient.** `n_trans` periods when given. Otherwise the run stops the transient at the
//!   first section `k` at which, for some `p` in `1..=8`, the `p`-step differences
//!   `d_k = |S_k - S_{k-p}|` contract geometrically (`rho = max(d_k / d_{k-p},
//!   d_{k-p} / d_{k-2p}) < 1`) and the predicted remaining distance to the periodic orbit
//!   `d_k / (1 - rho)` is at most `trans_tol * L` (or `d_k` is at rounding level,
//!   `16 eps L`); at the latest after `n_trans_max` periods. The count used is recorded
//!   (`n_trans`) with whether the test passed (`converged`).
//! * **Measurement** over the next `n_meas` periods: `amplitude = max |x|` over the window,
//!   exact (at the window's ends, at every zero of `x'` and at every impact, where `x` has a
//!   kink); with noise, the largest `|x(k Ts) + noise_k|` of the samples in the window.
//!   `impacts_per_period` = impacts in the window / `n_meas`. `period` = the smallest `p` in
//!   `1..=8` with `|S_{j+p} - S_j| <= period_tol * L` for every pair of sections in the
//!   window, each of the `p` phases compared at least once (so `p <= (n_meas + 1) / 2`);
//!   0 when none (quasi-periodic or chaotic motion, or a transient not yet over). `amplitude_linear = X_st / sqrt((1 - r^2)^2 + (2 zeta r)^2)`, `X_st = F0 / K`, the
//!   primary system without the inner mass; `attenuation = amplitude / amplitude_linear`.
//! * **Energy** over the window: the work of the force `int F0 cos(omega t) x' dt`, the viscous
//!   loss `int C x'^2 dt` (both by 8-point Gauss–Legendre on pieces at most 1/16 of the fastest
//!   period of the motion, accurate to rounding) and the impact loss (the drop of
//!   `(M x'^2 + m y'^2 + K x^2) / 2` at each impact and plastic closing). On a periodic orbit
//!   the work equals the two losses.

mod finder;
pub mod motion;
mod steady;

use serde::Serialize;

use crate::model::{RangeError, System, fmt_value};

pub(crate) use steady::simulate_periods;
#[cfg(test)]
pub(crate) use steady::{Stepper, simulate_with};
pub use steady::{simulate_harmonic, simulate_harmonic_ends, simulate_harmonic_units};

/// The forcing frequency, given directly or as a ratio to `sqrt(K/M)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Drive {
    /// `omega` (rad/s).
    Omega(f64),
    /// `r = omega / sqrt(K/M)`.
    Ratio(f64),
}

/// The harmonic scene's settings. Every field documents its unit, default and valid range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Harmonic {
    /// Force amplitude `F0` (N), `> 0`. Default 1.
    pub F0: f64,
    /// Forcing frequency: `omega` (rad/s) or `r`, either `> 0`. Default `r = 1`.
    pub drive: Drive,
    /// Transient length in forcing periods, or `None` (default) to stop it when the Poincaré
    /// section has converged (module doc). Range `[0, 10^8]`.
    pub n_trans: Option<u64>,
    /// Longest default transient (periods). Default `2000`, range `[1, 10^8]`.
    pub n_trans_max: u64,
    /// Measurement window (periods). Default `20`, range `[1, 10^6]`.
    pub n_meas: u64,
    /// Convergence of the default transient: the predicted distance to the periodic orbit,
    /// relative to the section scale. Default `1e-10`, range `[1e-15, 1e-2]`.
    pub trans_tol: f64,
    /// Sections that agree to `period_tol` times the section scale repeat. Default `1e-6`,
    /// range `[1e-15, 0.1]`.
    pub period_tol: f64,
    /// Starts of the attractor census per frequency point (the study's initial state and
    /// `starts - 1` seeded ones, [`crate::orbits::census`]). Default 8, range `[1, 1000]`.
    pub starts: u32,
    /// Which steady amplitude is the design quantity. Default [`DesignPeak::Worst`].
    pub design_peak: DesignPeak,
    /// How a steady state that is not periodic gets its design amplitude. Default
    /// [`NonPeriodicPeak::Life`].
    pub nonperiodic_peak: NonPeriodicPeak,
    /// The design life (s of operation) over which a steady state that is not periodic reaches
    /// its design amplitude (docs/scenes.md). Default `3.6e6` (1000 hours), range
    /// `[1, 1e12]`.
    pub design_life: f64,
    /// The quantile of the largest amplitude over the design life that is the design amplitude.
    /// Default 0.5 (its median), range `[0.01, 0.99]`.
    pub life_quantile: f64,
    /// The 90 % interval's half-width, relative to the estimate, at which a life measurement
    /// stops growing. Default 0.05, range `[0.001, 1]`.
    pub life_tol: f64,
    /// The longest life measurement of one steady state (forcing periods). Default 1,024,000
    /// (2,000 doubled nine times: the slowest tails validated need some 5 * 10^5 periods for
    /// 5 %, `results/life_validation.md`), range `[2000, 10^8]`.
    pub life_max_periods: u64,
    /// Where the race measures the design lives of a curve's motions that are not periodic.
    /// Default [`LifeCurve::Decisions`]; `"whole"` measures every frequency of the ideal curve
    /// as long as its peak, at several times the cost.
    #[serde(skip_serializing_if = "LifeCurve::is_default")]
    pub life_curve: LifeCurve,
    /// Integrate the window's energies (default `true`; no study key). The steady-state
    /// solvers of [`crate::orbits`] evaluate the stroboscopic map without them.
    #[serde(skip)]
    pub energies: bool,
    /// Extrema of `x` whose `|x|` stays below this are not located (m, default 0: every one
    /// is; no study key). The window's amplitude is then exact when it is at least `x_floor`,
    /// and some value below `x_floor` otherwise. A design-life measurement
    /// ([`crate::orbits::life`]) sets it below the part of the per-period maxima its estimate
    /// uses: watching `v` costs about half of a chaotic motion's steps.
    #[serde(skip)]
    pub x_floor: f64,
    /// The event finder (no study key; default [`Finder::DEFAULT`]).
    #[serde(skip)]
    pub finder: Finder,
}

/// Which event finder moves the harmonic scene's phases (issue 69). Both locate every event
/// of the same motion with the same guarantee (no missed or grazing impact); they differ in
/// where an impact is declared and in cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Finder {
    /// Safe steps to within the event tolerance of every event (`crate::sim::driven`): an
    /// impact is declared where the wall's safe step falls below `tol * period`, up to that
    /// before its root. The reference: every committed record was made with it.
    SafeSteps,
    /// Safe steps in the far field, each impact then bracketed once by the quartic model of its
    /// gap and polished to its root to rounding (`finder` module doc): about half the
    /// evaluations a period on the design life's slow tails.
    Bracketed,
}

impl Finder {
    /// The finder [`Harmonic::default`] takes. The lead's switch: `Bracketed` changes the bits
    /// of every record (each impact moves from up to `tol * period` before its root to the
    /// root), so the committed showcases would be regenerated with it.
    pub const DEFAULT: Finder = Finder::SafeSteps;
}

/// Which steady state carries a design's peak.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DesignPeak {
    /// The worst steady amplitude over every attractor the census found.
    Worst,
    /// The steady state reached from the study's initial state (one start).
    FromRest,
}

impl DesignPeak {
    pub const NAMES: [&'static str; 2] = ["worst", "from_rest"];

    pub fn name(self) -> &'static str {
        match self {
            DesignPeak::Worst => "worst",
            DesignPeak::FromRest => "from_rest",
        }
    }

    pub fn parse(s: &str) -> Option<DesignPeak> {
        match s {
            "worst" => Some(DesignPeak::Worst),
            "from_rest" => Some(DesignPeak::FromRest),
            _ => None,
        }
    }
}

/// How a steady state that is not periodic gets its design amplitude (`[scene]
/// nonperiodic_peak`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NonPeriodicPeak {
    /// Its largest amplitude over the design life, estimated from 2,000 to `life_max_periods`
    /// periods where it can still carry a curve's peak ([`crate::orbits::race`]).
    Life,
    /// The largest `|x|` over the census's 200-period window: a lower bound of what the motion
    /// reaches, without a design-life measurement (the periodic steady states are the same).
    Window,
}

impl NonPeriodicPeak {
    pub const NAMES: [&'static str; 2] = ["life", "window"];

    pub fn parse(s: &str) -> Option<NonPeriodicPeak> {
        match s {
            "life" => Some(NonPeriodicPeak::Life),
            "window" => Some(NonPeriodicPeak::Window),
            _ => None,
        }
    }
}

/// Where a curve's race ([`crate::orbits::race`]) measures the design lives of its motions that
/// are not periodic (`[scene] life_curve`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LifeCurve {
    /// Only where a value can change a decision: the curve's peak, where the damper helps, a
    /// dip beside the peak. A frequency far below the peak keeps its first estimate (2,000 to
    /// 64,000 periods) and its wide interval.
    Decisions,
    /// Also every other frequency of the ideal curve (the one the report draws): each motion
    /// that could carry a frequency's value is measured until it is settled (`life_tol` at three
    /// successive windows) or reaches `life_max_periods`, so the frequency-response charts draw
    /// every value measured as long as the peak's. The perturbed cases' curves, which
    /// serve only their peaks, race as with `Decisions`.
    Whole,
}

impl LifeCurve {
    pub const NAMES: [&'static str; 2] = ["decisions", "whole"];

    pub fn parse(s: &str) -> Option<LifeCurve> {
        match s {
            "decisions" => Some(LifeCurve::Decisions),
            "whole" => Some(LifeCurve::Whole),
            _ => None,
        }
    }

    /// Whether this is the default (the scene's serialised form leaves it out then).
    pub fn is_default(&self) -> bool {
        *self == LifeCurve::Decisions
    }
}

impl Default for Harmonic {
    fn default() -> Self {
        Harmonic {
            F0: 1.0,
            drive: Drive::Ratio(1.0),
            n_trans: None,
            n_trans_max: 2_000,
            n_meas: 20,
            trans_tol: 1e-10,
            period_tol: 1e-6,
            starts: 8,
            design_peak: DesignPeak::Worst,
            nonperiodic_peak: NonPeriodicPeak::Life,
            design_life: 3.6e6,
            life_quantile: 0.5,
            life_tol: 0.05,
            life_max_periods: 1_024_000,
            life_curve: LifeCurve::Decisions,
            energies: true,
            x_floor: 0.0,
            finder: Finder::DEFAULT,
        }
    }
}

impl Harmonic {
    /// The keys `simulate --set` accepts for this scene (besides `scene`).
    pub const KEYS: [&'static str; 13] = [
        "F0",
        "omega",
        "r",
        "n_trans",
        "n_trans_max",
        "n_meas",
        "trans_tol",
        "period_tol",
        "starts",
        "design_life",
        "life_quantile",
        "life_tol",
        "life_max_periods",
    ];

    /// The forcing frequency `omega` (rad/s) for this system.
    pub fn omega(&self, sys: &System) -> f64 {
        match self.drive {
            Drive::Omega(w) => w,
            Drive::Ratio(r) => r * sys.omega(),
        }
    }

    /// The frequency ratio `r = omega / sqrt(K/M)` for this system.
    pub fn ratio(&self, sys: &System) -> f64 {
        match self.drive {
            Drive::Omega(w) => w / sys.omega(),
            Drive::Ratio(r) => r,
        }
    }

    /// The keys a study may sweep (`[sweep].F0`, `omega`, `r`): a study over them is a family of
    /// frequency-response curves.
    pub const AXES: [&'static str; 3] = ["F0", "omega", "r"];

    /// Sets a sweepable key ([`Harmonic::AXES`]): `F0`, or the drive as `omega` or `r`. Returns
    /// `false` for any other key.
    pub fn set(&mut self, key: &str, value: f64) -> bool {
        match key {
            "F0" => self.F0 = value,
            "omega" => self.drive = Drive::Omega(value),
            "r" => self.drive = Drive::Ratio(value),
            _ => return false,
        }
        true
    }

    /// Checks every range and resonance without damping against `sys` (module doc); the error
    /// names the key, the value and what is allowed.
    pub fn validate(&self, sys: &System) -> Result<(), RangeError> {
        self.check_ranges()?;
        self.check_resonance(sys)
    }

    /// Checks every range that does not depend on the system (all but resonance).
    pub fn check_ranges(&self) -> Result<(), RangeError> {
        let check = |key: &str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && v >= lo && v <= hi {
                Ok(())
            } else {
                Err(RangeError::new(
                    key,
                    v,
                    format!("must be in [{}, {}]", fmt_value(lo), fmt_value(hi)),
                ))
            }
        };
        if !(self.F0.is_finite() && self.F0 > 0.0) {
            return Err(RangeError::new(
                "F0",
                self.F0,
                "the force amplitude must be a finite number > 0 (N)",
            ));
        }
        let (key, value) = match self.drive {
            Drive::Omega(w) => ("omega", w),
            Drive::Ratio(r) => ("r", r),
        };
        if !(value.is_finite() && value > 0.0) {
            let what = if key == "omega" {
                "the forcing frequency must be a finite number > 0 (rad/s)"
            } else {
                "the frequency ratio omega / sqrt(K/M) must be a finite number > 0"
            };
            return Err(RangeError::new(key, value, what));
        }
        if let Some(n) = self.n_trans {
            check("n_trans", n as f64, 0.0, 1e8)?;
        }
        check("n_trans_max", self.n_trans_max as f64, 1.0, 1e8)?;
        check("n_meas", self.n_meas as f64, 1.0, 1e6)?;
        check("trans_tol", self.trans_tol, 1e-15, 1e-2)?;
        check("period_tol", self.period_tol, 1e-15, 0.1)?;
        check("starts", f64::from(self.starts), 1.0, 1000.0)?;
        check("design_life", self.design_life, 1.0, 1e12)?;
        check("life_quantile", self.life_quantile, 0.01, 0.99)?;
        check("life_tol", self.life_tol, 1e-3, 1.0)?;
        check(
            "life_max_periods",
            self.life_max_periods as f64,
            2000.0,
            1e8,
        )
    }

    /// Refuses resonance without damping on `sys`: the dynamic stiffness of the main mass (and
    /// of the stuck pair when `m > 0`) at `omega` below `1e-6 K` (module doc). The error names
    /// the frequency key (`omega` or `r`) and its value.
    pub fn check_resonance(&self, sys: &System) -> Result<(), RangeError> {
        let (key, value) = match self.drive {
            Drive::Omega(w) => ("omega", w),
            Drive::Ratio(r) => ("r", r),
        };
        let omega = self.omega(sys);
        // K / 10^6, so that the message shows 4e-4, not 3.9999999999999996e-4.
        let floor = sys.K / (1.0 / motion::RESONANCE_FLOOR);
        let masses: &[(f64, &str)] = if sys.m > 0.0 {
            &[(sys.M, "M"), (sys.M + sys.m, "(M + m)")]
        } else {
            &[(sys.M, "M")]
        };
        for &(mass, name) in masses {
            let z = motion::dynamic_stiffness(mass, sys.K, sys.C, omega);
            if z.is_nan() || z < floor {
                return Err(RangeError::new(
                    key,
                    value,
                    format!(
                        "resonance without damping: |K - {name} omega^2 + i C omega| = {} N/m is \
                         below 1e-6 K = {} N/m, the steady amplitude is unbounded; move {key} or \
                         give C > 0",
                        fmt_value(z),
                        fmt_value(floor)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The result of one forced run. Displacements in m, energies in J, times in s.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct HarmonicRecord {
    pub outcome: crate::sim::record::Outcome,
    /// The force amplitude (N), the forcing frequency (rad/s) and its ratio to `sqrt(K/M)`.
    pub F0: f64,
    pub omega: f64,
    pub r: f64,
    /// `max |x|` over the measurement window (NaN unless `ok`).
    pub amplitude: f64,
    /// Impacts in the window / `n_meas`.
    pub impacts_per_period: f64,
    /// Smallest repeat of the Poincaré section in `1..=8`, 0 when none.
    pub period: u32,
    /// `X_st / sqrt((1 - r^2)^2 + (2 zeta r)^2)`: the primary system alone.
    pub amplitude_linear: f64,
    /// `amplitude / amplitude_linear`.
    pub attenuation: f64,
    /// Transient periods used (on a run that stopped before its window, the periods it ran).
    pub n_trans: u64,
    /// Whether the default transient stopped by convergence (`false` at the cap, and when
    /// `n_trans` was given).
    pub converged: bool,
    /// The measurement window (forcing periods), [`Harmonic::n_meas`].
    pub n_meas: u64,
    /// Over the window: work of the force, viscous loss, impact loss (J).
    pub energy_force: f64,
    pub energy_viscous: f64,
    pub energy_impact: f64,
    /// The state at `t_stop` (a section time when `ok`): a converged run ends on its orbit, and
    /// the next run of a frequency sweep can start from it to follow a branch.
    pub end: crate::sim::phase::State,
    /// Over the whole run.
    pub impacts: u64,
    pub sticks: u64,
    pub t_stop: f64,
    pub steps: u64,
    /// The attractor census at this frequency ([`Steady`]); empty (`starts = 0`, NaN) until
    /// [`crate::orbits::forced_run`] fills it.
    pub steady: Steady,
}

/// What the attractor census found at one frequency point ([`crate::orbits::census`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Steady {
    /// Starts run (0: no census).
    pub starts: u32,
    /// Distinct attractors found.
    pub attractors: u32,
    /// The largest steady amplitude over them (m): exact on a periodic orbit, the largest over
    /// the census window on a motion that is not periodic.
    pub amplitude_worst: f64,
    /// The worst attractor's period (forcing periods; 0 when not periodic), its impacts per
    /// forcing period (over whole orbit periods) and its basin share (starts reaching it /
    /// starts).
    pub worst_period: u32,
    pub worst_impacts_per_period: f64,
    pub worst_basin_share: f64,
    /// The attractor reached from the study's initial state: its amplitude (m) and period.
    pub rest_amplitude: f64,
    pub rest_period: u32,
    /// Forcing periods the census simulated in all.
    pub census_periods: u64,
    /// The worst attractor's kind (`periodic`, `neutral`, `chaotic`, `quasi-periodic`,
    /// `not settled`; empty without a census), its largest Lyapunov exponent per forcing
    /// period, its largest displacement over the census window (m) and the 90 % interval of its
    /// amplitude over the design life (m; equal to `amplitude_worst` when periodic, NaN when
    /// not measured).
    pub worst_kind: &'static str,
    pub worst_lyapunov: f64,
    pub worst_window_amplitude: f64,
    pub worst_life_lo: f64,
    pub worst_life_hi: f64,
}

impl Steady {
    /// No census.
    pub const NONE: Steady = Steady {
        starts: 0,
        attractors: 0,
        amplitude_worst: f64::NAN,
        worst_period: 0,
        worst_impacts_per_period: f64::NAN,
        worst_basin_share: f64::NAN,
        rest_amplitude: f64::NAN,
        rest_period: 0,
        census_periods: 0,
        worst_kind: "",
        worst_lyapunov: f64::NAN,
        worst_window_amplitude: f64::NAN,
        worst_life_lo: f64::NAN,
        worst_life_hi: f64::NAN,
    };
}
