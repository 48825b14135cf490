//! How far below a capacity found by the search (`sim::random::ida`) the same motion already
//! passes the limit: for each realization of design point 0 of a random study with a design
//! stripe, the capacity as the sweep stores it, then its motion run at `N` intensities on a
//! geometric grid from `LOW` times that capacity up to it, and the smallest one at which
//! `max |x|` passes the limit. Where `max |x|` is monotone in the gain, that is the capacity to
//! the grid's step; where it folds back, the search may report a later crossing. Prints the
//! quantiles of `capacity / smallest passing` (1 where none below passes) as the cells of one
//! Markdown table row (`scripts/ida_scan.sh` writes `results/ida_scan.md` from them).
//!
//! `cargo run --release --example ida_scan -- STUDY.toml [REALIZATIONS] [N] [LOW]`
//! (defaults 300, 140, 0.5: a grid step of 0.5 %)

use impactsweep::plan::Plan;
use impactsweep::sim::random::RandomRun;
use impactsweep::study::Study;
use impactsweep::sweep::random::one_realization;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .expect("usage: ida_scan STUDY.toml [REALIZATIONS] [N] [LOW]");
    let arg = |i: usize, default: f64| args.get(i).map_or(default, |a| a.parse().unwrap());
    let (count, n, low) = (arg(2, 300.0) as u32, arg(3, 140.0) as u32, arg(4, 0.5));
    let study = Study::load(std::path::Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    let plan = Plan::new(&study);
    let (mut ratios, mut runs) = (Vec::new(), 0u32);
    for case in 0..count.min(plan.n_cases() as u32) {
        let (row, _) = one_realization(&plan, 0, case, None).expect("a random study");
        let Some(cap) = row.capacity else {
            panic!(
                "realization {case} has no capacity: the study needs a design stripe and a limit"
            )
        };
        if cap.censored || !cap.capacity.is_finite() {
            continue;
        }
        runs += cap.runs;
        let run = plan.run(0, case);
        let scene = run.scene.random().expect("a random study").for_case(case);
        let setup = RandomRun::new(&run.system, &plan.study.solver, &scene);
        let block = setup.load(plan.load_stream(&run));
        let spec = scene.intensity.expect("an intensity measure");
        let own = setup.own_intensity(spec.period, &block).of(spec.measure);
        let b = scene.threshold.expect("a limit");
        let req = &plan.study.request;
        let smallest = (0..=n)
            .map(|j| cap.capacity * low.powf(1.0 - f64::from(j) / f64::from(n)))
            .find(|im| setup.amplitude_block(req, &block, im / own) > b);
        ratios.push(smallest.map_or(1.0, |s| cap.capacity / s));
    }
    ratios.sort_by(f64::total_cmp);
    let q = |p: f64| ratios[((ratios.len() - 1) as f64 * p) as usize];
    let over = |x: f64| ratios.iter().filter(|&&r| r > x).count() as f64 / ratios.len() as f64;
    let gm = (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp();
    // One Markdown table row's cells (scripts/ida_scan.sh writes the rest).
    println!(
        "{} | {runs} | {:.4} | {:.4} | {:.4} | {:.4} | {:.3} | {:.3} | {:.3} | {gm:.4}",
        ratios.len(),
        q(0.5),
        q(0.9),
        q(0.99),
        q(1.0),
        over(1.01),
        over(1.05),
        over(1.1)
    );
}
