//! The `attractors` table's row: one per run of a harmonic study and steady state its census
//! found (docs/schema.md). The sweep writes these rows beside the runs' points, one part file
//! per chunk; `reduce` reads them back and never runs a census again.

use super::census::{Census, Kind};
use super::map::{Forcing, Section};
use super::units::census::{RestLanding, UnitsCensus};
use super::units::motion::UnitsMotion;
use crate::sim::harmonic::Steady;

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
    /// A section state on the attractor (see [`super::census::Attractor::section`]); with
    /// several units, the structure and the first unit.
    pub section: Section,
    /// With several units, the whole section state the motion can be run again from,
    /// `(x, x', z_1, y_1', ..., z_N, y_N')` (m and m/s; `z_i = y_i - x`, unit `i`'s position in
    /// its cavity, and `y_i'` its velocity);
    /// empty for one unit, whose `section` is whole (the `section_units` column).
    pub section_units: Vec<f64>,
}

/// The kind of a motion that is not periodic, from its probe's largest Lyapunov exponent
/// `lambda ± se` and whether it ran its whole budget without reaching a periodic orbit
/// (`exhausted`): `chaotic` when exhausted and `lambda > 3 se`; `quasi-periodic` when exhausted,
/// `|lambda| <= 3 se` and `|lambda|` below [`super::census::CHAOS_FLOOR`] (zero, and measured
/// to be: a motion on a torus; the section's closed curve is not tested); otherwise
/// `not settled` (a transient still dying out, or an exponent too uncertain to tell).
/// One unit's motion and a motion of several units alike.
fn steady_kind(probe: Option<super::census::ProbeResult>, exhausted: bool) -> SteadyKind {
    match probe {
        Some(p) if p.chaotic() && exhausted => SteadyKind::Chaotic,
        Some(p)
            if exhausted
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
                    Kind::NonPeriodic(w) => (steady_kind(w.probe, w.exhausted), "", f64::NAN),
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
                    section_units: Vec::new(),
                }
            })
            .collect()
    }
}

/// The largest relative excess of a run's own measured amplitude over the steady states its
/// census found that is rounding, not a motion the census missed: the simulator's accuracy on a
/// steady amplitude (1e-9 relative, tests/forced.rs). Above it the floor of
/// [`AttractorRow::of_units_census`] binds.
pub const FLOOR_ROUNDING: f64 = 1e-9;

/// What a run of several units measured itself, for [`AttractorRow::of_units_census`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunWindow {
    /// `max |x|` over the run's measuring window (m), the record's `amplitude`.
    pub amplitude: f64,
    /// That window's length (forcing periods), the record's `n_meas`.
    pub n_meas: u64,
}

impl AttractorRow {
    /// The rows of `units`, the census of several units of run `run` at `f` (model.md §14,
    /// [`super::units::census`]), started from `s0` (the run's end state, `2 + 2N`
    /// components), the run having measured `own` itself. In order, row 0 being where start 0
    /// (the run's own motion) ended:
    ///
    /// * each stable impacting orbit, its exact amplitude, `multiplier_max = |mu|_max` of the
    ///   reduced monodromy matrix and `lyapunov = ln |mu|_max / p` per forcing period (exact,
    ///   `lyapunov_se = 0`);
    /// * `neutral`, when starts reached the non-impacting family: the structure's forced
    ///   response alone, amplitude `F0 / |K - M omega^2 + i C omega|`, `|mu|_max = 1` (each unit
    ///   drifts freely);
    /// * one row per motion that is not periodic ([`super::units::motion`]: the starts that did
    ///   not settle, grouped by where they wander), its kind from its exponent
    ///   ([`super::units::lyapunov`], `lyapunov*`; chaotic, quasi-periodic or `not settled` as
    ///   one unit's, [`steady_kind`]), its state the one its first start ended in: as its window
    ///   amplitude the largest `|x|` over the last 200 periods of each of its starts and, when
    ///   start 0 is one, over the run's own window, so over `max(200, n_meas)` periods at least
    ///   (a lower bound of what the motion reaches); as its amplitude the design-life estimate of
    ///   the race ([`super::race::race_units`]: its 90 % interval and tail in the `life_*` and
    ///   `tail_*` columns, `measured_periods` its periods), never below the window amplitude, or
    ///   without the race the window amplitude.
    ///
    /// **The floor.** The run's attractor is reached by start 0, so the worst row is never below
    /// the run's own measured amplitude: where it would be by more than [`FLOOR_ROUNDING`]
    /// relative (the run's window still held a transient that later settled lower), the row of
    /// start 0's motion carries the run's amplitude and state (a `not settled` row with no start
    /// is added when start 0 settled).
    pub fn of_units_census(
        run: RunId,
        f: &Forcing,
        units: &UnitsCensus,
        s0: &[f64],
        own: RunWindow,
    ) -> Vec<AttractorRow> {
        let n = f64::from(units.starts.max(1));
        let t_f = f.period();
        let mut rows: Vec<AttractorRow> = units
            .attractors
            .iter()
            .map(|a| {
                let o = &a.orbit;
                let mu = o.multiplier_max();
                let lyapunov = mu.ln() / f64::from(o.period.max(1));
                let row = units_row(run, SteadyKind::Periodic, o.amplitude, &o.s);
                AttractorRow {
                    stability: "stable",
                    period: o.period,
                    impacts_per_period: o.impacts_per_period(),
                    basin_share: f64::from(a.starts) / n,
                    starts: a.starts,
                    multiplier_max: mu,
                    lyapunov,
                    lyapunov_per_s: lyapunov / t_f,
                    lyapunov_se: 0.0,
                    life_amplitude: o.amplitude,
                    life_lo: o.amplitude,
                    life_hi: o.amplitude,
                    measured_periods: u64::from(o.period),
                    ..row
                }
            })
            .collect();
        if units.non_impacting > 0 {
            rows.push(neutral_row(run, f, units.non_impacting, n));
        }
        let measured = own.n_meas.max(super::tolerances::CENSUS_WINDOW);
        let first_motion = rows.len();
        for (j, m) in units.motions.iter().enumerate() {
            let mut window = m.window;
            if units.rest == RestLanding::Motion(j) {
                window = window.max(own.amplitude);
            }
            rows.push(motion_row(run, m, window, measured, n, t_f, s0));
        }
        let top = rows.iter().map(|r| r.amplitude).fold(f64::NAN, f64::max);
        if own.amplitude > top * (1.0 + FLOOR_ROUNDING) {
            // Start 0's motion carries the run's amplitude and state, or a row of no start does.
            let (starts, at) = match units.rest {
                RestLanding::Motion(j) => (units.motions[j].starts, Some(first_motion + j)),
                _ => (0, None),
            };
            let row = AttractorRow {
                basin_share: f64::from(starts) / n,
                starts,
                measured_periods: measured,
                ..units_row(run, SteadyKind::NotSettled, own.amplitude, s0)
            };
            match at {
                Some(i) => rows[i] = row,
                None => rows.push(row),
            }
        }
        // Row 0 is where start 0 ended (the run's own motion).
        let rest = match units.rest {
            RestLanding::Orbit(i) => Some(i),
            RestLanding::NonImpacting => rows.iter().position(|r| r.kind == SteadyKind::Neutral),
            RestLanding::Motion(j) => Some(first_motion + j),
            RestLanding::Unsettled => rows.iter().position(|r| !r.kind.periodic()),
        };
        if let Some(i) = rest.filter(|&i| i < rows.len()) {
            let r = rows.remove(i);
            rows.insert(0, r);
        }
        for (i, r) in rows.iter_mut().enumerate() {
            r.attractor = i as u32;
        }
        rows
    }
}

/// The row of motion `m` of a census of several units (of `n` starts, forcing period `t_f`, s):
/// window amplitude `window` (m), its design life when the race measured it, its exponent and
/// its kind from it, its first state (`s0`, the run's end, when it has none).
fn motion_row(
    run: RunId,
    m: &UnitsMotion,
    window: f64,
    measured: u64,
    n: f64,
    t_f: f64,
    s0: &[f64],
) -> AttractorRow {
    // Over the design life (the race's estimate; its largest value measured when it has none,
    // a lower bound), never below the census's windows.
    let life = m.life.and_then(|l| l.estimate);
    let amp = m.life.map_or(window, |l| {
        life.map_or(l.window_max, |e| e.amplitude).max(window)
    });
    let on = m.states.first().map_or(s0, Vec::as_slice);
    let mut row = AttractorRow {
        basin_share: f64::from(m.starts) / n,
        starts: m.starts,
        measured_periods: measured,
        window_amplitude: window,
        ..units_row(run, SteadyKind::NotSettled, amp, on)
    };
    if let Some(p) = m.probe {
        row.kind = steady_kind(Some(p), true);
        row.lyapunov = p.lambda;
        row.lyapunov_per_s = p.lambda / t_f;
        row.lyapunov_se = p.se;
    }
    if let Some(l) = m.life {
        row.life_amplitude = life.map_or(f64::NAN, |e| e.amplitude);
        row.life_lo = life.map_or(f64::NAN, |e| e.lo);
        row.life_hi = life.map_or(f64::NAN, |e| e.hi);
        row.life_capped = l.capped;
        row.tail_shape = life.map_or(f64::NAN, |e| e.xi);
        row.tail_end = life.map_or(f64::NAN, |e| e.end_point);
        row.exceedances = life.map_or(0, |e| e.exceedances);
        row.measured_periods = l.measured;
    }
    row
}

/// The first four components of a section state of several units: the structure and unit 1
/// (the `section_*` columns).
pub fn section_of(s: &[f64]) -> Section {
    let at = |k: usize| s.get(k).copied().unwrap_or(f64::NAN);
    [at(0), at(1), at(2), at(3)]
}

/// A row of the census of several units with `kind`, design and window amplitude `amplitude`
/// (m) and the whole section state `s`, every other column that of a motion that is not
/// periodic.
fn units_row(run: RunId, kind: SteadyKind, amplitude: f64, s: &[f64]) -> AttractorRow {
    AttractorRow {
        run,
        attractor: 0,
        kind,
        stability: "",
        period: 0,
        amplitude,
        window_amplitude: amplitude,
        impacts_per_period: f64::NAN,
        basin_share: 0.0,
        starts: 0,
        origin: "start",
        multiplier_max: f64::NAN,
        lyapunov: f64::NAN,
        lyapunov_per_s: f64::NAN,
        lyapunov_se: f64::NAN,
        life_amplitude: f64::NAN,
        life_lo: f64::NAN,
        life_hi: f64::NAN,
        life_capped: false,
        tail_shape: f64::NAN,
        tail_end: f64::NAN,
        exceedances: 0,
        measured_periods: 0,
        section: section_of(s),
        section_units: s.to_vec(),
    }
}

/// The non-impacting family's amplitude at `f` (m): the structure's forced response alone,
/// `sqrt(P^2 + Q^2)` of [`crate::sim::harmonic::motion::particular`], as its row carries it.
pub fn neutral_amplitude(f: &Forcing) -> f64 {
    let sys = &f.sys;
    let (p, q) = crate::sim::harmonic::motion::particular(sys.M, sys.K, sys.C, f.F0, f.omega);
    p.hypot(q)
}

/// The non-impacting family's row: the structure's forced response alone
/// (`x = P cos(omega t) + Q sin(omega t)`, amplitude `sqrt(P^2 + Q^2)`), the units at rest in
/// their cavities relative to the ground; `starts` of `n` reached it.
fn neutral_row(run: RunId, f: &Forcing, starts: u32, n: f64) -> AttractorRow {
    let sys = &f.sys;
    let (p, q) = crate::sim::harmonic::motion::particular(sys.M, sys.K, sys.C, f.F0, f.omega);
    let amp = p.hypot(q);
    // Every unit at rest relative to the ground: `z_i = -x`, `z_i' = 0`.
    let mut at_rest = vec![p, f.omega * q];
    for _ in 0..super::units::map::unit_count(f) {
        at_rest.extend([-p, 0.0]);
    }
    AttractorRow {
        stability: "neutral",
        period: 1,
        impacts_per_period: 0.0,
        basin_share: f64::from(starts) / n,
        starts,
        multiplier_max: 1.0,
        lyapunov: 0.0,
        lyapunov_per_s: 0.0,
        lyapunov_se: 0.0,
        life_amplitude: amp,
        life_lo: amp,
        life_hi: amp,
        measured_periods: 1,
        ..units_row(run, SteadyKind::Neutral, amp, &at_rest)
    }
}

/// A run's census summary ([`Steady`]) from its attractor rows (row 0 the one reached from the
/// run's own state), `starts` starts and `periods` forcing periods simulated: the worst row
/// (the first of the largest design amplitude), its period, impacts, basin share, kind,
/// exponent, window amplitude and life interval, and row 0's amplitude and period. The one-unit
/// census ([`super::steady_of`]) and that of several units share it. [`Steady::NONE`] without
/// rows.
pub fn steady_of_rows(rows: &[AttractorRow], starts: u32, periods: u64) -> Steady {
    let Some(worst) = rows
        .iter()
        .reduce(|a, b| if b.amplitude > a.amplitude { b } else { a })
    else {
        return Steady::NONE;
    };
    let rest = &rows[0];
    Steady {
        starts,
        attractors: rows.len() as u32,
        amplitude_worst: worst.amplitude,
        worst_period: worst.period,
        worst_impacts_per_period: worst.impacts_per_period,
        worst_basin_share: worst.basin_share,
        rest_amplitude: rest.amplitude,
        rest_period: rest.period,
        census_periods: periods,
        worst_kind: worst.kind.name(),
        worst_lyapunov: worst.lyapunov,
        worst_window_amplitude: worst.window_amplitude,
        worst_life_lo: worst.life_lo,
        worst_life_hi: worst.life_hi,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::map::tests::table_i;
    use crate::orbits::shoot::Stability;
    use crate::orbits::units::census::UnitsAttractor;
    use crate::orbits::units::shoot::UnitsOrbit;

    const RUN: RunId = RunId {
        point_id: 7,
        point: 7,
        case: 0,
        ideal: true,
        r: 1.0,
        omega: 63.2,
        F0: 0.1,
    };

    /// Two units, a census whose start 0 landed on a period-1 orbit of `amplitude` and whose
    /// other start did not settle (its window maximum `wander`).
    fn census(amplitude: f64, wander: f64) -> (Forcing, UnitsCensus) {
        let mut f = table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
        f.sys.units = 2.0;
        f.sys.d_spread = 0.2;
        let orbit = UnitsOrbit {
            s: vec![amplitude, 0.0, 0.001, 0.0, -0.002, 0.0],
            period: 1,
            amplitude,
            impacts: 4,
            multipliers: vec![(0.5, 0.0), (0.1, 0.2)],
            stability: Stability::Stable,
            groups: vec![vec![0], vec![1]],
            relative_modes: 0,
            free_modes: 0,
            monodromy: nalgebra::DMatrix::identity(2, 2),
            exact: true,
        };
        let c = UnitsCensus {
            attractors: vec![UnitsAttractor {
                orbit,
                starts: 1,
                first: 0,
                iterations: 3,
            }],
            starts: 2,
            non_impacting: 0,
            motions: vec![UnitsMotion {
                starts: 1,
                first: 1,
                window: wander,
                ..UnitsMotion::default()
            }],
            periods: 4000,
            rest: RestLanding::Orbit(0),
        };
        (f, c)
    }

    fn own(amplitude: f64) -> RunWindow {
        RunWindow {
            amplitude,
            n_meas: 400,
        }
    }

    #[test]
    fn an_orbit_a_wandering_start_and_the_exact_columns() {
        let (f, c) = census(0.004, 0.003);
        let s0 = [0.004, 0.0, 0.001, 0.0, -0.002, 0.0];
        let rows = AttractorRow::of_units_census(RUN, &f, &c, &s0, own(0.004));
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].kind, SteadyKind::Periodic);
        assert_eq!(rows[0].amplitude, 0.004);
        assert_eq!(rows[0].multiplier_max, 0.5);
        assert_eq!(rows[0].lyapunov, 0.5f64.ln());
        assert_eq!(rows[0].basin_share, 0.5);
        assert_eq!(rows[1].kind, SteadyKind::NotSettled);
        assert_eq!(rows[1].amplitude, 0.003);
        assert_eq!(rows[1].measured_periods, 400);
        assert_eq!([rows[0].attractor, rows[1].attractor], [0, 1]);
        let st = steady_of_rows(&rows, c.starts, c.periods);
        assert_eq!(st.amplitude_worst, 0.004);
        assert_eq!(st.worst_kind, "periodic");
        assert_eq!(st.rest_amplitude, 0.004);
    }

    /// Issue 68, the floor: the run from rest measured 0.467 cm over its window while its
    /// start 0 settled on an orbit of 0.439 cm later; the worst steady amplitude is the run's,
    /// carried by the `not settled` row. Fails when the floor is removed.
    #[test]
    fn the_worst_amplitude_is_never_below_the_run_from_rest() {
        let (f, c) = census(0.00439, 0.003);
        let s0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let rows = AttractorRow::of_units_census(RUN, &f, &c, &s0, own(0.00467));
        let st = steady_of_rows(&rows, c.starts, c.periods);
        assert_eq!(st.amplitude_worst, 0.00467);
        assert_eq!(st.worst_kind, "not settled");
        // The orbit keeps its exact amplitude and stays the run's own (row 0).
        assert_eq!(rows[0].amplitude, 0.00439);
        assert_eq!(st.rest_amplitude, 0.00439);
        // Start 0 settled, so the floor is a row of its own, with no start, beside the motion's.
        assert_eq!(rows.len(), 3);
        assert_eq!((rows[1].starts, rows[1].amplitude), (1, 0.003));
        assert_eq!((rows[2].starts, rows[2].amplitude), (0, 0.00467));
        // Every start settled: the floor adds a row of its own, with no start.
        let (f, mut c) = census(0.00439, f64::NAN);
        c.motions.clear();
        let rows = AttractorRow::of_units_census(RUN, &f, &c, &s0, own(0.00467));
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1].starts, 0);
        assert_eq!(steady_of_rows(&rows, 2, 0).amplitude_worst, 0.00467);
        // Within rounding of the orbit the floor does not bind.
        let rows = AttractorRow::of_units_census(RUN, &f, &c, &s0, own(0.00439 * (1.0 + 1e-12)));
        assert_eq!(rows.len(), 1);
    }

    /// Start 0 that did not settle: its row is row 0 and carries the run's window when that
    /// is the larger.
    #[test]
    fn a_run_that_does_not_settle_carries_its_own_window() {
        let (f, mut c) = census(0.004, 0.0041);
        c.rest = RestLanding::Motion(0);
        c.attractors[0].first = 1;
        c.motions[0].first = 0;
        let s0 = [0.0; 6];
        let rows = AttractorRow::of_units_census(RUN, &f, &c, &s0, own(0.005));
        assert_eq!(rows[0].kind, SteadyKind::NotSettled);
        assert_eq!(rows[0].amplitude, 0.005);
        assert_eq!(rows[1].kind, SteadyKind::Periodic);
        let st = steady_of_rows(&rows, c.starts, c.periods);
        assert_eq!((st.amplitude_worst, st.rest_amplitude), (0.005, 0.005));
    }

    /// Two motions that are not periodic stay two rows (issue 68): each its own starts, window,
    /// state and exponent's kind, start 0's first; the run's window raises only its own.
    #[test]
    fn two_motions_that_are_not_periodic_are_two_rows() {
        let (f, mut c) = census(0.004, 0.0043);
        c.starts = 4;
        c.motions[0].states = vec![vec![1.0; 6]];
        c.motions.push(UnitsMotion {
            starts: 2,
            first: 2,
            window: 0.0082,
            states: vec![vec![2.0; 6], vec![3.0; 6]],
            probe: Some(crate::orbits::census::ProbeResult {
                lambda: 0.8,
                se: 0.05,
                periods: 512,
            }),
            ..UnitsMotion::default()
        });
        c.rest = RestLanding::Motion(0);
        let s0 = [0.0; 6];
        let rows = AttractorRow::of_units_census(RUN, &f, &c, &s0, own(0.0045));
        assert_eq!(rows.len(), 3);
        assert_eq!((rows[0].kind, rows[0].starts), (SteadyKind::NotSettled, 1));
        assert_eq!((rows[0].amplitude, rows[0].section_units[0]), (0.0045, 1.0));
        assert_eq!(rows[1].kind, SteadyKind::Periodic);
        assert_eq!((rows[2].kind, rows[2].starts), (SteadyKind::Chaotic, 2));
        assert_eq!((rows[2].amplitude, rows[2].section_units[0]), (0.0082, 2.0));
        assert_eq!((rows[2].lyapunov, rows[2].basin_share), (0.8, 0.5));
        assert_eq!(steady_of_rows(&rows, 4, 0).amplitude_worst, 0.0082);
    }
}
