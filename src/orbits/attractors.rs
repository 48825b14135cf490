//! The `attractors` table's row: one per run of a harmonic study and steady state its census
//! found (docs/schema.md). The sweep writes these rows beside the runs' points, one part file
//! per chunk; `reduce` reads them back and never runs a census again.

use super::census::{Census, Kind};
use super::map::Section;

/// What kind of steady state an attractor is (the `kind` column).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SteadyKind {
    /// An impacting periodic orbit, exact.
    Periodic,
    /// The non-impacting family (the inner mass at rest in the clearance).
    Neutral,
    /// A motion that is not periodic with a significantly positive largest Lyapunov exponent.
    Chaotic,
    /// Not periodic, largest Lyapunov exponent zero within its error, section on a closed curve.
    QuasiPeriodic,
    /// Not periodic and not shown to be chaotic or quasi-periodic within the periods run (a
    /// transient still dying out, or too short a measurement to tell).
    NotSettled,
}

impl SteadyKind {
    pub const NAMES: [&'static str; 5] = [
        "periodic",
        "neutral",
        "chaotic",
        "quasi-periodic",
        "not settled",
    ];

    pub fn name(self) -> &'static str {
        match self {
            SteadyKind::Periodic => "periodic",
            SteadyKind::Neutral => "neutral",
            SteadyKind::Chaotic => "chaotic",
            SteadyKind::QuasiPeriodic => "quasi-periodic",
            SteadyKind::NotSettled => "not settled",
        }
    }

    pub fn parse(s: &str) -> Option<SteadyKind> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| match i {
            0 => SteadyKind::Periodic,
            1 => SteadyKind::Neutral,
            2 => SteadyKind::Chaotic,
            3 => SteadyKind::QuasiPeriodic,
            _ => SteadyKind::NotSettled,
        })
    }

    /// A periodic orbit (impacting, or the non-impacting family).
    pub fn periodic(self) -> bool {
        matches!(self, SteadyKind::Periodic | SteadyKind::Neutral)
    }
}

/// The run an attractor belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct RunId {
    pub point_id: u64,
    pub point: u64,
    pub case: u32,
    pub ideal: bool,
    pub r: f64,
    pub omega: f64,
    pub F0: f64,
}

/// One attractor of one run (docs/schema.md, "attractors").
#[derive(Clone, Debug, PartialEq)]
pub struct AttractorRow {
    pub run: RunId,
    /// Index at this run (0: the one reached from the initial state).
    pub attractor: u32,
    pub kind: SteadyKind,
    /// `stable` (an impacting orbit), `neutral` (the family) or `""` (not periodic).
    pub stability: &'static str,
    /// Orbit period in forcing periods; 0 when not periodic.
    pub period: u32,
    /// The design amplitude (m): exact on a periodic orbit; on a motion that is not periodic its
    /// largest amplitude over the design life (`life_amplitude`) when estimated, else its window
    /// maximum.
    pub amplitude: f64,
    /// `max |x|` over the census's measuring window (m); the exact amplitude on a periodic orbit.
    pub window_amplitude: f64,
    pub impacts_per_period: f64,
    /// Census starts that reached it / starts, and their count.
    pub basin_share: f64,
    pub starts: u32,
    /// `start`, `up` or `down` ([`super::census::Origin`]).
    pub origin: &'static str,
    /// Largest Floquet multiplier modulus (periodic; NaN otherwise).
    pub multiplier_max: f64,
    /// Largest Lyapunov exponent per forcing period and per second, and its standard error per
    /// forcing period (0 for a periodic orbit, exact from its multipliers).
    pub lyapunov: f64,
    pub lyapunov_per_s: f64,
    pub lyapunov_se: f64,
    /// The largest amplitude over the design life at the study's quantile, with its 90 %
    /// interval (m); a periodic orbit's amplitude with a zero-width interval.
    pub life_amplitude: f64,
    pub life_lo: f64,
    pub life_hi: f64,
    /// The window reached its cap before the interval met `life_tol`.
    pub life_capped: bool,
    /// Generalized Pareto shape of the per-period maxima's tail, and its end point when bounded
    /// (`xi < 0`) (m); NaN for a periodic orbit.
    pub tail_shape: f64,
    pub tail_end: f64,
    /// Declustered exceedances of the tail's threshold, and the periods measured.
    pub exceedances: u64,
    pub measured_periods: u64,
    /// A section state on the attractor (see [`super::census::Attractor::section`]).
    pub section: Section,
}

/// The kind of a motion that is not periodic, from its probe's largest Lyapunov exponent
/// `lambda ± se` and whether it ran its whole budget without reaching a periodic orbit
/// (`exhausted`): `chaotic` when exhausted and `lambda > 3 se`; `quasi-periodic` when exhausted,
/// `|lambda| <= 3 se` and `|lambda|` below [`super::census::CHAOS_FLOOR`] (zero, and measured
/// to be: a motion on a torus; the section's closed curve is not tested); otherwise
/// `not settled` (a transient still dying out, or an exponent too uncertain to tell).
fn steady_kind(w: &super::census::Wandering) -> SteadyKind {
    match w.probe {
        Some(p) if p.chaotic() && w.exhausted => SteadyKind::Chaotic,
        Some(p)
            if w.exhausted
                && p.lambda.abs() <= 3.0 * p.se
                && p.lambda.abs() < super::census::CHAOS_FLOOR =>
        {
            SteadyKind::QuasiPeriodic
        }
        _ => SteadyKind::NotSettled,
    }
}

impl AttractorRow {
    /// The rows of `census`, the census of run `run` at forcing period `t_f` (s).
    pub fn of_census(run: RunId, census: &Census, t_f: f64) -> Vec<AttractorRow> {
        census
            .attractors
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let (kind, stability, mu) = match &a.kind {
                    Kind::Periodic(o) if o.impacts == 0 => {
                        (SteadyKind::Neutral, "neutral", o.multiplier_max())
                    }
                    Kind::Periodic(o) => (SteadyKind::Periodic, "stable", o.multiplier_max()),
                    Kind::NonPeriodic(w) => (steady_kind(w), "", f64::NAN),
                };
                // A periodic orbit's exponent is exact: ln|mu_max| / p per forcing period.
                let (lyapunov, se) = match &a.kind {
                    Kind::Periodic(_) => (mu.ln() / f64::from(a.period.max(1)), 0.0),
                    Kind::NonPeriodic(w) => {
                        w.probe.map_or((f64::NAN, f64::NAN), |p| (p.lambda, p.se))
                    }
                };
                let periodic = kind.periodic();
                let summary = match &a.kind {
                    Kind::NonPeriodic(w) => w.life,
                    Kind::Periodic(_) => None,
                };
                let life = summary.and_then(|s| s.estimate);
                let exact = if periodic { a.amplitude } else { f64::NAN };
                AttractorRow {
                    run,
                    attractor: i as u32,
                    kind,
                    stability,
                    period: a.period,
                    amplitude: a.amplitude,
                    window_amplitude: a.window_amplitude,
                    impacts_per_period: a.impacts_per_period,
                    basin_share: census.share(i),
                    starts: a.starts,
                    origin: a.origin.name(),
                    multiplier_max: mu,
                    lyapunov,
                    lyapunov_per_s: lyapunov / t_f,
                    lyapunov_se: se,
                    // A periodic orbit's life amplitude is its amplitude; a motion the race did
                    // not measure has none (NaN).
                    life_amplitude: life.map_or(exact, |l| l.amplitude),
                    life_lo: life.map_or(exact, |l| l.lo),
                    life_hi: life.map_or(exact, |l| l.hi),
                    life_capped: summary.is_some_and(|s| s.capped),
                    tail_shape: life.map_or(f64::NAN, |l| l.xi),
                    tail_end: life.map_or(f64::NAN, |l| l.end_point),
                    exceedances: life.map_or(0, |l| l.exceedances),
                    measured_periods: match summary {
                        Some(s) => s.measured,
                        None if periodic => u64::from(a.period),
                        None => 0,
                    },
                    section: a.section,
                }
            })
            .collect()
    }
}
