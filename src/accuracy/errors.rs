//! Error statistics: relative errors of observables against the reference, run by run.

use crate::sim::{Outcome, Record};
pub use crate::store::audit::{Audit, ErrorStats};

/// `|a - b| / |b|` (`|a - b|` when `b = 0`); `None` unless both are finite.
pub fn rel_err(a: f64, b: f64) -> Option<f64> {
    if !a.is_finite() || !b.is_finite() {
        return None;
    }
    let d = (a - b).abs();
    Some(if b == 0.0 { d } else { d / b.abs() })
}

impl ErrorStats {
    /// The statistics of a set of errors.
    pub fn of(errors: Vec<f64>) -> ErrorStats {
        ErrorStats {
            n: errors.len() as u64,
            max: errors.iter().copied().fold(f64::NAN, f64::max),
            median: crate::numeric::median(&errors),
        }
    }
}

/// Observables of one run, as compared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observed {
    pub ok: bool,
    /// The solver finished the run (the peer's chatter guard may stop it).
    pub finished: bool,
    pub xmax: f64,
    pub t1: f64,
    pub di: f64,
    pub impacts: u64,
}

impl From<&Record> for Observed {
    fn from(r: &Record) -> Self {
        Observed {
            ok: r.outcome == Outcome::Ok,
            finished: true,
            xmax: r.xmax,
            t1: r.t1,
            di: r.di,
            impacts: r.impacts,
        }
    }
}

/// What [`compare`] finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    pub xmax: ErrorStats,
    pub t1: ErrorStats,
    pub di: ErrorStats,
    /// Relative error of the impact count (against `max(impacts, 1)`).
    pub impacts: ErrorStats,
    /// Runs whose ok-ness differs from the reference's, or that did not finish.
    pub changed_outcome: u64,
    pub changed_impacts: u64,
    pub unfinished: u64,
    /// Runs compared (the reference's).
    pub runs: u64,
}

/// Error statistics of `got` against `truth`, run by run (the `tradeoff` table). Runs whose
/// outcome differs from the reference are counted, not averaged (their observables may be
/// NaN); the observables are compared where both runs are ok.
pub fn compare(truth: &[Record], got: &[Observed]) -> Comparison {
    let (mut ex, mut et, mut ed, mut ei) = (vec![], vec![], vec![], vec![]);
    let (mut changed_outcome, mut changed_impacts, mut unfinished) = (0, 0, 0);
    for (r, g) in truth.iter().zip(got) {
        if !g.finished {
            unfinished += 1;
        }
        let ref_ok = r.outcome == Outcome::Ok;
        if ref_ok != g.ok || !g.finished {
            changed_outcome += 1;
            if !g.finished {
                continue;
            }
        }
        if r.impacts != g.impacts {
            changed_impacts += 1;
        }
        ei.extend(rel_err(g.impacts as f64, r.impacts.max(1) as f64));
        if ref_ok && g.ok {
            ex.extend(rel_err(g.xmax, r.xmax));
            et.extend(rel_err(g.t1, r.t1));
            ed.extend(rel_err(g.di, r.di));
        }
    }
    Comparison {
        xmax: ErrorStats::of(ex),
        t1: ErrorStats::of(et),
        di: ErrorStats::of(ed),
        impacts: ErrorStats::of(ei),
        changed_outcome,
        changed_impacts,
        unfinished,
        runs: truth.len() as u64,
    }
}

/// The audit of `points` from their `(got, reference)` record pairs, in the same order: every
/// pair where both values are finite counts, whatever the outcomes.
pub fn audit_errors(
    points: &[u64],
    settings: &crate::sim::SolverSettings,
    pairs: &[(Record, Record)],
) -> Audit {
    let errs = |f: fn(&Record) -> f64| {
        ErrorStats::of(
            pairs
                .iter()
                .filter_map(|(a, b)| rel_err(f(a), f(b)))
                .collect(),
        )
    };
    Audit {
        points: points.to_vec(),
        solver: settings.kind.name().to_string(),
        knob: settings.kind.knob().to_string(),
        knob_value: settings.knob_value(),
        tol: settings.tol,
        reference: format!("exact, tol = {:e}", super::REFERENCE_TOL),
        xmax: errs(|r| r.xmax),
        t1: errs(|r| r.t1),
        di: errs(|r| r.di),
        outcome_changed: pairs.iter().filter(|(a, b)| a.outcome != b.outcome).count() as u64,
        impacts_changed: pairs.iter().filter(|(a, b)| a.impacts != b.impacts).count() as u64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_statistics() {
        assert_eq!(rel_err(1.1, 1.0).map(|e| (e * 1e6).round()), Some(1e5));
        assert_eq!(rel_err(0.5, 0.0), Some(0.5));
        assert_eq!(rel_err(f64::NAN, 1.0), None);
        let s = ErrorStats::of(vec![3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.n, s.max, s.median), (4, 10.0, 2.5));
        assert!(ErrorStats::of(vec![]).max.is_nan());
        assert!(ErrorStats::of(vec![]).median.is_nan());
    }
}
