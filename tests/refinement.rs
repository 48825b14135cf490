//! Issue 10: the reducer is stable under refinement. The paper's study (configs/paper.toml's
//! system, cases, noise and strength) at e steps 0.01, 0.001 and 0.0001 gives the same sequence
//! of zone classes along e with boundaries within the coarse step (of the coarse grid's bracket
//! of each boundary), and the same located jumps
//! within their tolerances: the two changes of the first peak, near e = 0.746 (the paper's jump
//! between 0.73 and 0.77) and near e = 0.799, each a kink located to 1/100 of its grid step.
//!
//! Cost: 51 + 501 + 5,001 design points x 12 cases = 66,636 runs plus a few dozen extra
//! simulations, a few seconds on two cores with the test profile's optimisation.

use impactsweep::reduce::testing::{paper_study, reduce_simulated};
use impactsweep::reduce::{JumpKind, Quantity, Summary};
use impactsweep::study::Study;

fn paper_at(step: f64) -> (Study, Summary) {
    let mut s = paper_study();
    let n = (0.5 / step).round() as usize;
    // From the index, never accumulated (the study's own linspace rule).
    s.axes[0].values = (0..=n).map(|i| 0.45 + 0.5 * i as f64 / n as f64).collect();
    s.run.chunk_points = 1000;
    let sum = reduce_simulated(&s);
    (s, sum)
}

/// The zones along e: (class label, first e, last e), in order.
fn zones(s: &Summary) -> Vec<(String, f64, f64)> {
    s.zones
        .iter()
        .map(|z| (z.label().to_string(), z.ranges[0].0, z.ranges[0].1))
        .collect()
}

#[test]
fn issue_10_the_paper_study_is_stable_under_refinement() {
    let grids: Vec<(f64, Summary)> = [0.01, 0.001, 0.0001]
        .into_iter()
        .map(|step| (step, paper_at(step).1))
        .collect();
    let (coarse_step, coarse) = (&grids[0].0, &grids[0].1);
    let zc = zones(coarse);
    // The coarse grid: the paper's three kinds of zone, two zones around the first peak's
    // changes.
    let labels: Vec<&str> = zc.iter().map(|z| z.0.as_str()).collect();
    assert_eq!(
        labels,
        [
            "strong damping, reliable",
            "reliable, weak damping",
            "around a jump",
            "reliable, weak damping",
            "around a jump",
            "reliable, weak damping",
        ],
        "{zc:?}"
    );
    // The two changes of the first peak, located with their tolerance: kinks of the ideal xmax.
    let located = |s: &Summary| -> Vec<(Quantity, JumpKind, f64, f64)> {
        s.jumps
            .iter()
            .map(|j| (j.quantity, j.kind, j.location, j.location_tol))
            .collect()
    };
    let jc = located(coarse);
    assert_eq!(jc.len(), 2, "{jc:?}");
    for (j, near) in jc.iter().zip([0.746, 0.799]) {
        assert_eq!((j.0, j.1), (Quantity::Response, JumpKind::Kink), "{j:?}");
        assert!((j.2 - near).abs() < 2e-3, "{j:?}");
        assert!(j.3 <= coarse_step / 200.0 + 1e-12, "{j:?}");
    }
    for (step, fine) in &grids[1..] {
        let zf = zones(fine);
        let lf: Vec<&str> = zf.iter().map(|z| z.0.as_str()).collect();
        assert_eq!(lf, labels, "e step {step}: {zf:?}");
        // A grid knows a boundary only to lie between the last point of one zone and the first
        // of the next: the fine grid's bracket is within the coarse step of the coarse grid's.
        // (A zone around a jump holds the grid points either side of it, so its edges sit up to
        // a step and a half from the jump on any grid: the jump itself is compared below.)
        for k in 0..zc.len() - 1 {
            let (c0, c1) = (zc[k].2, zc[k + 1].1);
            let (f0, f1) = (zf[k].2, zf[k + 1].1);
            let gap = (f0 - c1).max(c0 - f1).max(0.0);
            assert!(
                gap <= coarse_step + 1e-12,
                "e step {step}, boundary {k}: {c0}..{c1} against {f0}..{f1}"
            );
        }
        // The same jumps, each within the sum of both tolerances, located to step / 100.
        let jf = located(fine);
        assert_eq!(jf.len(), jc.len(), "e step {step}: {jf:?}");
        for (a, b) in jc.iter().zip(&jf) {
            assert_eq!((a.0, a.1), (b.0, b.1), "e step {step}");
            assert!(
                (a.2 - b.2).abs() <= a.3 + b.3,
                "e step {step}: {a:?} against {b:?}"
            );
            assert!(b.3 <= step / 200.0 + 1e-15, "e step {step}: {b:?}");
        }
        // Finer grids ask for no more extra simulations per jump.
        assert!(
            fine.jump_stats.sims <= 4 * coarse.jump_stats.sims,
            "{:?} against {:?}",
            fine.jump_stats,
            coarse.jump_stats
        );
    }
}
