//! What the reducer knows of one design point: the runs it reads ([`Run`]), the response and
//! damping quantity a scene names ([`Response`], [`Damping`]) and the statistics of the point
//! ([`PointStats`]).

use super::class::Class;
use super::stats::LogNormal;
use crate::sim::Outcome;

/// The per-point response: the one quantity from which stress, R and the ranking follow. Each
/// scene names its own (the largest positive peak `xmax` in the free-decay scene,
/// [`crate::reduce::free::XMAX`]; the peak amplitude over the band in the harmonic one).
/// Summary columns are named after it (`xmax_mean`, `xmax_sd`, …).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Response {
    /// Column prefix and name in the report.
    pub name: &'static str,
    /// Its unit (SI).
    pub unit: &'static str,
    /// What it is, for a person.
    pub description: &'static str,
}

/// The per-point damping quantity: the second criterion of perfectibility (eq. 11), of the
/// "strong damping" class and of the Pareto set, beside R. Each scene names its own: the damping
/// inclination `DI` in the free-decay scene ([`crate::reduce::free::DI`]), the peak reduction in
/// the harmonic one.
/// Summary columns are named after it (`di`, `di_ideal`, `di_sd`, zones' `mean_di`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Damping {
    /// Column name and prefix.
    pub name: &'static str,
    /// How the report and the charts write it (`DI`), and its name as a chart's title starts
    /// (`Damping inclination`).
    pub symbol: &'static str,
    pub title: &'static str,
    /// Its unit (SI; `1` for a ratio).
    pub unit: &'static str,
    /// What it is, for a person.
    pub description: &'static str,
}

impl Damping {
    /// Its symbol with its unit, as an axis or a table column is labelled: `DI (m/s)`, `PR (–)`
    /// for a ratio.
    pub fn label(&self) -> String {
        let unit = if self.unit == "1" { "–" } else { self.unit };
        format!("{} ({unit})", self.symbol)
    }

    /// A value with its unit: `0.01234 m/s`, or the number alone for a ratio.
    pub fn with_unit(&self, value: &str) -> String {
        if self.unit == "1" {
            value.to_string()
        } else {
            format!("{value} {}", self.unit)
        }
    }
}

/// One run as the reducer needs it: its identity, its case and the observables the statistics
/// use. The store's rows are converted to this; the reducer knows nothing else of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Run {
    pub point: u64,
    pub case: u32,
    pub ideal: bool,
    /// The case's change of the inner mass (kg) and of the clearance (m), and its noise seed.
    pub dm: f64,
    pub dd: f64,
    pub noise_seed: Option<u64>,
    pub outcome: Outcome,
    /// The response ([`Response`], in its unit): `xmax` in the free-decay scene (m).
    pub response: f64,
    /// The damping quantity ([`Damping`], in its unit): DI in the free-decay scene (m/s).
    pub di: f64,
}

/// The response over the ok cases of a design point: mean, SD (N - 1), five-number summary,
/// and the ideal case's value (NaN when it did not end `ok`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResponseStats {
    pub mean: f64,
    pub sd: f64,
    pub min: f64,
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    pub max: f64,
    pub ideal: f64,
}

/// The summary of one design point. The first block is computed from its own runs; the last
/// (`perfectibility` to `zone`) needs the whole sweep and is filled by
/// [`super::Reducer::finish_with`]. Its axis values are [`super::Summary::values`].
#[derive(Clone, Debug, PartialEq)]
pub struct PointStats {
    /// Design point index.
    pub point: u64,
    /// Runs found for this point, and how many ended `ok` (the statistics use only those).
    pub n_cases: u32,
    pub n_ok: u32,
    /// Runs per outcome, in [`Outcome::ALL`] order.
    pub outcomes: [u32; 6],
    /// Every case ended `ok`.
    pub all_ok: bool,
    /// The response over the ok cases.
    pub response: ResponseStats,
    /// Stress (eq. 10, Pa) as a lognormal variable.
    pub stress: LogNormal,
    /// `beta = (mu_ln_S - mu_ln_s) / sqrt(sigma_ln_S^2 + sigma_ln_s^2)`; `R = Phi(beta)`.
    pub reliability_index: f64,
    /// Reliability, eq. 6.
    pub reliability: f64,
    /// Bootstrap confidence interval of `R`.
    pub reliability_lo: f64,
    pub reliability_hi: f64,
    /// `C_n` of eq. 7 and the safety factor `mu_n`.
    pub cn: f64,
    pub safety_factor: f64,
    /// Anderson–Darling on the log of the response: corrected statistic and p-value.
    pub ad_stat: f64,
    pub ad_p: f64,
    /// The damping quantity ([`Damping`]; DI in m/s in the free-decay scene) as the ranking
    /// uses it ([`crate::reduce::Options::di_source`]), the ideal case's, and its SD over the ok
    /// cases.
    pub di: f64,
    pub di_ideal: f64,
    pub di_sd: f64,
    /// Eq. 11 (%), rank (1 = best; `None` when R or DI is unknown), Pareto-optimal on (R, DI).
    pub perfectibility: f64,
    pub rank: Option<u64>,
    pub pareto: bool,
    /// Its class, and its zone: an index into [`super::Summary::zones`],
    /// [`super::regions::NO_REGION`] when it is in none (outside every declared zone).
    pub class: Class,
    pub zone: u32,
    /// Its whole ±1-step neighbourhood lies in recommended zones ([`super::recommend`]).
    pub robust: bool,
}
