//! The reference set of runs and the ladder of solver settings measured on it.

use crate::model::System;
use crate::sim::{self, NoProbe, Record, Request, SolverKind, SolverSettings};

/// At most this many reference runs from a study (evenly spaced design points).
pub const MAX_STUDY_POINTS: usize = 64;

/// The reference set: systems run with one request.
#[derive(Clone, Debug)]
pub struct Reference {
    /// What the set is, for the table's heading.
    pub label: String,
    pub systems: Vec<System>,
    pub request: Request,
    /// Settings other than the knobs (caps, chatter tolerance), shared by every setting.
    pub base: SolverSettings,
}

impl Reference {
    /// The paper's Table I system for `e = 0.45 + 0.01 i`, `i = 0..=50` (computed from the index).
    pub fn paper() -> Reference {
        Reference::paper_step(1)
    }

    /// The paper set, every `stride`-th `e` of it.
    pub fn paper_step(stride: usize) -> Reference {
        let systems = (0..=50)
            .step_by(stride.max(1))
            .map(|i| System {
                e: 0.45 + 0.01 * i as f64,
                ..System::TABLE_I
            })
            .collect();
        Reference {
            label: "Table I system, e = 0.45..0.95".into(),
            systems,
            request: Request::default(),
            base: SolverSettings::default(),
        }
    }

    /// A study's design points (ideal case), at most [`MAX_STUDY_POINTS`] of them evenly spaced.
    pub fn study(study: &crate::study::Study) -> Reference {
        let plan = crate::plan::Plan::new(study);
        let n = plan.n_points();
        let take = (n as usize).min(MAX_STUDY_POINTS) as u64;
        let systems = (0..take)
            .map(|i| {
                let p = if take <= 1 {
                    0
                } else {
                    i * (n - 1) / (take - 1)
                };
                plan.point_system(p)
            })
            .collect();
        Reference {
            label: format!("study {}: {take} of {n} design points", study.name),
            systems,
            request: Request {
                trace_dt: None,
                ..study.request
            },
            base: study.solver,
        }
    }

    /// Median undamped period of the set (s).
    pub fn period(&self) -> f64 {
        let periods: Vec<f64> = self.systems.iter().map(|s| s.period()).collect();
        crate::numeric::median(&periods)
    }

    /// Median amplitude scale `|x0| + |v0| / omega` of the set (m).
    pub fn amplitude(&self) -> f64 {
        let amps: Vec<f64> = self
            .systems
            .iter()
            .map(|s| s.x0.abs() + s.v0.abs() / s.omega())
            .collect();
        crate::numeric::median(&amps)
    }

    /// Runs every system with `settings`.
    pub fn run(&self, settings: &SolverSettings) -> Vec<Record> {
        self.systems
            .iter()
            .map(|s| sim::simulate(s, settings, &self.request, None, &mut NoProbe))
            .collect()
    }

    /// The reference records: `exact` at its tightest tolerance.
    pub fn truth(&self) -> Vec<Record> {
        self.run(&super::reference_settings(&self.base))
    }
}

/// The knob ladder of every solver (`quick`: a shorter one):
///
/// | solver | knob | ladder |
/// |---|---|---|
/// | `exact` | `tol` | `1e-4, 1e-6, ..., 1e-12` |
/// | `rk4` | `h` | `T/50, T/100, ..., T/6400` (`T` the undamped period) |
/// | `dopri5` | `rtol` | `1e-3, 1e-4, ..., 1e-11`, with `atol = rtol * A` (`A = |x0| + |v0| / omega`) |
pub fn ladder(reference: &Reference, quick: bool) -> Vec<(SolverSettings, String)> {
    let base = reference.base;
    let period = reference.period();
    let amp = reference.amplitude();
    let mut out = Vec::new();
    let tols: &[i32] = if quick {
        &[4, 8, 12]
    } else {
        &[4, 6, 8, 10, 12]
    };
    for &k in tols {
        let tol = 10f64.powi(-k);
        out.push((
            SolverSettings {
                kind: SolverKind::Exact,
                tol,
                ..base
            },
            format!("tol = 1e-{k}"),
        ));
    }
    let divs: &[u32] = if quick {
        &[50, 200, 800, 3200]
    } else {
        &[50, 100, 200, 400, 800, 1600, 3200, 6400]
    };
    for &n in divs {
        out.push((
            SolverSettings {
                kind: SolverKind::Rk4,
                h: period / f64::from(n),
                ..base
            },
            format!("h = T/{n}"),
        ));
    }
    let rtols: &[i32] = if quick {
        &[3, 6, 9]
    } else {
        &[3, 4, 5, 6, 7, 8, 9, 10, 11]
    };
    for &k in rtols {
        let rtol = 10f64.powi(-k);
        out.push((
            SolverSettings {
                kind: SolverKind::Dopri5,
                rtol,
                atol: rtol * amp,
                ..base
            },
            format!("rtol = 1e-{k}"),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_reference_has_51_runs_from_the_index() {
        let r = Reference::paper();
        assert_eq!(r.systems.len(), 51);
        assert_eq!(r.systems[0].e, 0.45);
        assert_eq!(r.systems[50].e, 0.45 + 0.01 * 50.0);
        assert_eq!(Reference::paper_step(5).systems.len(), 11);
    }
}
