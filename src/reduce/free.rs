//! The free-decay scene's reduction (model.md §3–6): each run's largest positive peak `xmax` is
//! the response ([`XMAX`]) and its damping inclination `DI` the damping quantity ([`DI`]); the
//! core ([`crate::reduce::common`]) does the rest over the design points, its jumps located with
//! extra simulations of the study's ideal case at the bisection's midpoints
//! ([`SimulatedIdeal`]).

use crate::reduce::common::{Damping, IdealCase, Options, Reducer, Response, Run, Summary};
use crate::sim::Outcome;
use crate::store::RunRow;
use crate::study::Study;

/// The free-decay scene's response: the largest positive half-cycle maximum (model.md §3).
pub const XMAX: Response = Response {
    name: "xmax",
    unit: "m",
    description: "largest positive peak",
};

/// The free-decay scene's damping quantity: eq. 5, `(X1 - X2) / (t2 - t1)` (model.md §3).
pub const DI: Damping = Damping {
    name: "di",
    symbol: "DI",
    title: "Damping inclination",
    unit: "m/s",
    description: "damping inclination",
};

/// The reducer's options for a free-decay study: the study's own, with `xmax` as the response
/// and DI as the damping quantity.
pub fn options(study: &Study) -> Options {
    Options::of_study(study, XMAX, DI)
}

/// A stored run as the reducer needs it: the store's row converted to the reducer's own, the
/// free-decay scene's response (`xmax`) and damping inclination picked out.
pub fn run_of(r: &RunRow) -> Run {
    Run {
        point: r.point,
        case: r.case,
        ideal: r.ideal,
        dm: r.dm,
        dd: r.dd,
        noise_seed: r.noise_seed,
        outcome: r.record.outcome,
        response: r.record.xmax,
        di: r.record.di,
    }
}

/// The study's ideal case, simulated at any design: the base system with the axis values set,
/// no perturbation, no noise, the study's solver and request.
pub struct SimulatedIdeal<'a> {
    pub study: &'a Study,
}

impl IdealCase for SimulatedIdeal<'_> {
    fn at(&self, values: &[f64]) -> Option<[f64; 2]> {
        let mut sys = self.study.system;
        for (axis, v) in self.study.axes.iter().zip(values) {
            sys.set(&axis.key, *v);
        }
        sys.validate().ok()?;
        let s = self.study;
        let rec = crate::sim::simulate(&sys, &s.solver, &s.request, None, &mut crate::sim::NoProbe);
        (rec.outcome == Outcome::Ok).then_some([rec.xmax, rec.di])
    }
}

/// Everything that needs the whole sweep ([`Reducer::finish_with`]), with the study's ideal case
/// simulated where the jumps are located ([`SimulatedIdeal`]).
pub fn finish(r: Reducer) -> Summary {
    let study = r.study();
    r.finish_with(&SimulatedIdeal { study })
}

/// Reduces a stream of chunks of a free-decay study in one go.
pub fn reduce<I, E>(study: &Study, options: Options, chunks: I) -> Result<Summary, E>
where
    I: IntoIterator<Item = Result<Vec<Run>, E>>,
{
    let mut r = Reducer::new(study, options);
    for chunk in chunks {
        r.push(chunk?);
    }
    Ok(finish(r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::testing::*;

    #[test]
    fn a_missing_point_is_left_out_not_invented() {
        let s = study(vec![("e", vec![0.5, 0.6, 0.7, 0.8])], 2);
        let mut rows = Vec::new();
        for p in [0u64, 1, 3] {
            for c in 0..2 {
                rows.push(row(&s, p, c, Outcome::Ok, 0.028, 0.02));
            }
        }
        let sum = reduce::<_, ()>(&s, options(&s), [Ok(rows)]).unwrap();
        assert_eq!(sum.n_points_planned, 4);
        let found: Vec<u64> = sum.points.iter().map(|p| p.point).collect();
        assert_eq!(found, vec![0, 1, 3]);
        let md = crate::report::markdown::report(&s, &sum, &[], None);
        assert!(
            md.contains("3 of 4 design points") && md.contains("incomplete"),
            "{md}"
        );
    }
}
