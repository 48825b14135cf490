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
//!
//! **Resolution** (`IDA_LEVELS=K1,K2,...`, with `N` a multiple of every `K`): each motion is run
//! at every point of the grid, and the first passage is read on the nested grids that keep
//! every `K`-th point (the capacity, the grid's top, is on all of them). One Markdown table
//! row a level: its step, `first passage / capacity` (geometric mean, median, 5 % quantile,
//! least), the median number of passing windows a motion's grid shows (runs of passing points),
//! and the share of motions whose first passage lies more than 1 % below the coarser level's.
//! A first passage that keeps moving down as the step shrinks is not a converged quantity.

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
    let levels: Vec<u32> = std::env::var("IDA_LEVELS").map_or(Vec::new(), |v| {
        v.split(',')
            .map(|k| k.trim().parse().expect("IDA_LEVELS: K1,K2,..."))
            .collect()
    });
    assert!(
        levels.iter().all(|k| *k > 0 && n % k == 0),
        "N must be a multiple of every level"
    );
    // Per motion and level: (first passage / capacity, passing windows).
    let mut resolution: Vec<Vec<(f64, u32)>> = Vec::new();
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
        let grid = |j: u32| cap.capacity * low.powf(1.0 - f64::from(j) / f64::from(n));
        if !levels.is_empty() {
            let passes: Vec<bool> = (0..=n)
                .map(|j| setup.amplitude_block(req, &block, grid(j) / own) > b)
                .collect();
            resolution.push(
                levels
                    .iter()
                    .map(|&k| first_and_windows(&passes, k, low, n))
                    .collect(),
            );
            continue;
        }
        let smallest = (0..=n)
            .map(grid)
            .find(|im| setup.amplitude_block(req, &block, im / own) > b);
        ratios.push(smallest.map_or(1.0, |s| cap.capacity / s));
    }
    if !levels.is_empty() {
        print_levels(&levels, &resolution, low, n);
        return;
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

/// The first passing point of the nested grid that keeps every `k`-th of `passes` (`low` to 1
/// of the capacity over `n` steps), as a share of the capacity (1 where none passes), and the
/// number of passing windows on that grid.
fn first_and_windows(passes: &[bool], k: u32, low: f64, n: u32) -> (f64, u32) {
    let on: Vec<(usize, bool)> = passes
        .iter()
        .copied()
        .enumerate()
        .step_by(k as usize)
        .collect();
    let first = on
        .iter()
        .find(|p| p.1)
        .map_or(1.0, |p| low.powf(1.0 - p.0 as f64 / f64::from(n)));
    let windows = on.windows(2).filter(|w| !w[0].1 && w[1].1).count() + usize::from(on[0].1);
    (first, windows as u32)
}

/// One Markdown table row's cells a level, finest last (module doc).
fn print_levels(levels: &[u32], resolution: &[Vec<(f64, u32)>], low: f64, n: u32) {
    let mut order: Vec<usize> = (0..levels.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(levels[i]));
    for (rank, &i) in order.iter().enumerate() {
        let mut first: Vec<f64> = resolution.iter().map(|m| m[i].0).collect();
        let mut windows: Vec<u32> = resolution.iter().map(|m| m[i].1).collect();
        let moved = rank.checked_sub(1).map_or(f64::NAN, |c| {
            let coarser = order[c];
            let count = resolution
                .iter()
                .filter(|m| m[i].0 < m[coarser].0 / 1.01)
                .count();
            count as f64 / resolution.len() as f64
        });
        first.sort_by(f64::total_cmp);
        windows.sort_unstable();
        let q = |p: f64| first[((first.len() - 1) as f64 * p) as usize];
        let gm = (first.iter().map(|r| r.ln()).sum::<f64>() / first.len() as f64).exp();
        let step = 100.0 * ((1.0 / low).powf(f64::from(levels[i]) / f64::from(n)) - 1.0);
        println!(
            "{:.3} % | {} | {gm:.4} | {:.4} | {:.4} | {:.4} | {} | {}",
            step,
            first.len(),
            q(0.5),
            q(0.05),
            first[0],
            windows[windows.len() / 2],
            if moved.is_nan() {
                "–".to_string()
            } else {
                format!("{moved:.2}")
            }
        );
    }
}
