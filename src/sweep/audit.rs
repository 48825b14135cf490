//! The accuracy audit of a sweep (`[run].audit` / `run --audit K`): shard 0 re-runs the ideal
//! case of `K` design points chosen from the study seed with the reference solver (`exact` at
//! `tol = 1e-14`) and records the study solver's relative error in `xmax`, `t1` and `di` (max
//! and median) and how many runs changed outcome or impact count ([`Audit`], the manifest's
//! `"audit"`). The statistics are [`crate::accuracy`]'s.

use rayon::prelude::*;

use crate::accuracy::{self, Audit};
use crate::plan::Plan;
use crate::sim::noise::mix64;
use crate::sim::{NoProbe, Record, simulate};

/// `k` distinct design points out of `n`, chosen from the study seed alone, sorted.
pub fn audit_points(seed: u64, n: u64, k: u64) -> Vec<u64> {
    if k >= n {
        return (0..n).collect();
    }
    let key = mix64(seed ^ 0xA0D1_7A0D_17A0_D170);
    let mut chosen = std::collections::BTreeSet::new();
    let mut j = 0u64;
    while (chosen.len() as u64) < k {
        chosen.insert(mix64(key ^ mix64(j)) % n);
        j += 1;
    }
    chosen.into_iter().collect()
}

/// Re-runs the ideal case of `points` with the study's solver and with the reference (on the
/// current rayon pool), and measures the difference.
pub fn run_audit(plan: &Plan, points: &[u64]) -> Audit {
    let study = plan.study;
    let reference = accuracy::reference_settings(&study.solver);
    let ideal = study.cases.iter().position(|c| c.ideal).unwrap_or(0) as u32;
    let pairs: Vec<(Record, Record)> = points
        .par_iter()
        .map(|&p| {
            let run = plan.run(p, ideal);
            let got = simulate(
                &run.system,
                &study.solver,
                &study.request,
                None,
                &mut NoProbe,
            );
            let want = simulate(&run.system, &reference, &study.request, None, &mut NoProbe);
            (got, want)
        })
        .collect();
    accuracy::audit_errors(points, &study.solver, &pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn audit_points_are_distinct_sorted_and_seeded() {
        let a = audit_points(7, 1000, 20);
        assert_eq!(a.len(), 20);
        assert!(a.windows(2).all(|w| w[0] < w[1]) && a[19] < 1000);
        assert_eq!(a, audit_points(7, 1000, 20));
        assert_ne!(a, audit_points(8, 1000, 20));
        assert_eq!(audit_points(7, 5, 20), vec![0, 1, 2, 3, 4]);
    }
}
