//! Jumps along the axes: decided by a tolerance in the quantity's own units, located by
//! bisection with extra simulations of the ideal case, classed as a step or a kink.
//!
//! The quantities are the ideal case's (noise-free, unperturbed: the design's own behaviour,
//! which noise would blur): the response (`xmax` in the free-decay scene) and DI. Along every
//! line of the grid along an axis (the other axes fixed):
//!
//! 1. **Candidates.** With `Δ_i = q_{i+1} - q_i` and the slopes `s_i = Δ_i / h_i`:
//!    * a *step candidate* in interval `i` when the change is not explained by the trend on
//!      either side: `min(|Δ_i - s_{i-1} h_i|, |Δ_i - s_{i+1} h_i|) >= step_tol` (the
//!      quantity's units; only the existing neighbours enter, `|Δ_i|` with none);
//!    * a *kink candidate* around interval `i` (the response only) when the slope across it
//!      changes by `|s_{i+1} - s_{i-1}| >= kink_slope · S`, `S` the typical slope: the median
//!      `|s|` over every line along the axis. The interval itself is skipped, so a kink
//!      anywhere inside it, or on its ends, counts in full; the kink may also sit in the
//!      intervals either side (it bends `s_{i-1}` or `s_{i+1}`), so the candidate spans all
//!      three.
//!
//!    Overlapping or touching candidates make one candidate span. A smooth trend changes by
//!    `O(h)` between neighbours and its slope by `O(h)` across one, so a finer grid gives fewer
//!    candidates, never more: refining does not invent jumps.
//! 2. **Location.** Bisection of the span with the ideal case simulated at the midpoint `m`,
//!    each side judging whether `q(m)` follows its own trend ([`locate()`] has the rule). It stops
//!    when the bracket is at most `locate · h` wide (`locate` defaults to 1/100 of the grid
//!    step): `location` is its middle, `location_tol` half its width.
//! 3. **Class.** On the final bracket `[a, b]`: a **step** when the change stays and is not
//!    the trend's, `min |q(b) - q(a) - s (b - a)| >= step_tol` over the secants `s` either
//!    side (size: `q(b) - q(a)`, the quantity's units). At a wider bracket (at most ten
//!    tolerances) a change of `step_tol` is a step only when it persists as the bracket is cut
//!    into eight and the part with the largest change cut again, down to the tolerance: a
//!    steep or hard-curving smooth stretch does not. Otherwise a
//!    **kink** (response only) when only the slope changes, `|s_R - s_L| >= kink_slope · S`
//!    with the secants either side at the bracket's scale (size: `s_R - s_L`, the quantity's
//!    units per axis unit). A kink of the square-root kind (a grazing impact) has an ever
//!    steeper side and is a kink; a corner rounded over more than the tolerance is reported at
//!    the finest bracket, at most ten tolerances wide, that still classes. Otherwise the whole
//!    span is cut the same way, following its largest change: the bisection follows the
//!    sides' trends, and a quantity with several steps close together (DI, where the second
//!    peak changes identity again and again) can lead it off its steps. A candidate with no
//!    step there either was a steep but smooth stretch and is dropped.
//!
//! DI gets steps only: DI = (X1 - X2)/(t2 - t1) depends on the impacts of the second
//! half-cycle and its slope changes at every grazing impact there (hundreds of times along e in
//! the paper's study at a step of 1e-4), so a kink of DI says nothing about the design.

use rayon::prelude::*;

mod locate;

pub use locate::{JumpKind, Outcome, UNRESOLVED, locate};

use super::grid::Grid;
use super::stats::median;

/// A quantity jumps are looked for in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Quantity {
    /// The per-point response (the ideal case's `xmax` in the free-decay scene).
    Response,
    /// The ideal case's damping inclination.
    Di,
}

impl Quantity {
    pub const ALL: [Quantity; 2] = [Quantity::Response, Quantity::Di];

    pub fn index(self) -> usize {
        self as usize
    }
}

/// The settings of jump finding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JumpSettings {
    /// Step tolerance per quantity ([`Quantity::index`]), in the quantity's units.
    pub step_tol: [f64; 2],
    /// A kink changes the slope by at least this many typical slopes (response only).
    pub kink_slope: f64,
    /// Location tolerance as a fraction of the grid step.
    pub locate: f64,
}

/// The ideal case simulated anywhere in the design space (not only on the grid).
pub trait IdealCase: Sync {
    /// `[response, DI]` of the ideal case at the design with these axis values (one per axis,
    /// in axis order); `None` when that run does not end `ok` or the design is not valid;
    /// [`UNRESOLVED`] for a quantity known there only as an estimate.
    fn at(&self, values: &[f64]) -> Option<[f64; 2]>;

    /// The 90 % intervals `[lo, hi]` of `[response, DI]` at the grid design with these axis
    /// values when they are statistical estimates rather than exact values (a forced design
    /// whose peak is carried by a motion that is not periodic: its amplitude over the design
    /// life is estimated from a finite run); `None` when they are exact (the default).
    fn interval(&self, _values: &[f64]) -> Option<[[f64; 2]; 2]> {
        None
    }
}

/// A located jump.
#[derive(Clone, Debug, PartialEq)]
pub struct Jump {
    /// The axis it is along.
    pub axis: usize,
    pub quantity: Quantity,
    pub kind: JumpKind,
    /// Where it is along the axis, and half the width of the bracket it was located to.
    pub location: f64,
    pub location_tol: f64,
    /// The grid points either side of it on its line (`below < above` in the point index).
    pub below: u64,
    pub above: u64,
    /// A step: `q(b) - q(a)` (the quantity's units). A kink: the change of slope (the
    /// quantity's units per axis unit).
    pub size: f64,
}

impl Jump {
    /// The grid values of its axis around its interval `location ± location_tol`: the largest
    /// at or below it and the smallest at or above it (the two either side for a jump located
    /// within one grid step; further apart for a step reported at a wider bracket).
    pub fn grid_span(&self, grid: &Grid) -> (f64, f64) {
        let xs = &grid.axes[self.axis].1;
        let (first, last) = (xs[0], xs[xs.len() - 1]);
        // The bracket's ends are grid values rounded through `location ± location_tol`.
        let slack = 1e-9 * (last - first).abs();
        let (lo, hi) = (
            self.location - self.location_tol + slack,
            self.location + self.location_tol - slack,
        );
        (
            xs.iter()
                .copied()
                .filter(|&x| x <= lo)
                .fold(first, f64::max),
            xs.iter().copied().filter(|&x| x >= hi).fold(last, f64::min),
        )
    }
}

/// What [`find`] returns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Found {
    pub jumps: Vec<Jump>,
    /// Candidate spans examined, and how many were steep smooth stretches (dropped) or could
    /// not be followed (a simulation inside did not end ok).
    pub candidates: usize,
    pub dropped: usize,
    pub failed: usize,
    /// Candidates whose every point is a statistical estimate ([`IdealCase::interval`]):
    /// `estimated_steps` of them were steps between two neighbours whose intervals part
    /// (reported at that grid interval, not bisected), the others had no such neighbours
    /// (dropped: not resolved by the estimates, or a trend).
    pub estimated: usize,
    pub estimated_steps: usize,
    /// Steps whose bisection stopped at a midpoint known only as an estimate ([`UNRESOLVED`]),
    /// reported at the bracket it reached.
    pub stopped_steps: usize,
    /// Extra simulations of the ideal case.
    pub sims: u64,
    /// The typical slope `S` of the response along each axis (response units per axis unit).
    pub typical_slope: Vec<f64>,
}

/// How a candidate was decided: between estimates (not bisected), by a bisection stopped at an
/// estimate, or by a whole bisection.
#[derive(Clone, Copy, PartialEq)]
enum Via {
    Estimates,
    Stopped,
    Bisection,
}

/// One candidate span: axis, quantity, the line's first point, grid indices `i < j`.
struct Candidate {
    axis: usize,
    quantity: Quantity,
    line: u64,
    i: usize,
    j: usize,
}

/// Finds, locates and classes the jumps. `q[p]` holds `[response, DI]` of the ideal case at
/// grid point `p` (NaN when unknown or the point is missing).
pub fn find(grid: &Grid, q: &[[f64; 2]], settings: &JumpSettings, ideal: &dyn IdealCase) -> Found {
    let mut found = Found::default();
    let cands = candidates(grid, q, settings, &mut found.typical_slope);
    found.candidates = cands.len();
    let located: Vec<(Outcome, u32, Via)> = cands
        .par_iter()
        .map(|c| locate_candidate(c, grid, q, settings, found.typical_slope[c.axis], ideal))
        .collect();
    for (c, (outcome, sims, via)) in cands.iter().zip(located) {
        found.record(grid, c, outcome, sims, via);
    }
    found
}

/// Every candidate span of every line of every axis, in axis, line and quantity order; the
/// typical slope of the response along each axis is pushed onto `typicals` (NaN for an
/// axis of one value).
fn candidates(
    grid: &Grid,
    q: &[[f64; 2]],
    settings: &JumpSettings,
    typicals: &mut Vec<f64>,
) -> Vec<Candidate> {
    let mut cands = Vec::new();
    for a in 0..grid.n_axes() {
        let xs = &grid.axes[a].1;
        let n = xs.len();
        // The number of damper units is a count: no design lies between two of them and it
        // has no small error, so a jump along it means nothing (model.md §14).
        if n < 2 || grid.axes[a].0 == "units" {
            typicals.push(f64::NAN);
            continue;
        }
        // The typical slope of the response along this axis.
        let mut slopes = Vec::new();
        for start in grid.line_starts(a) {
            let ys = line_values(grid, q, a, start, 0);
            slopes.extend(
                (0..n - 1)
                    .map(|i| ((ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i])).abs())
                    .filter(|s| s.is_finite()),
            );
        }
        let typical = typical_slope(&slopes, grid, q, a);
        typicals.push(typical);
        for start in grid.line_starts(a) {
            for quantity in Quantity::ALL {
                let ys = line_values(grid, q, a, start, quantity.index());
                let kink = kink_threshold(quantity, settings, typical);
                for (i, j) in candidate_spans(xs, &ys, settings.step_tol[quantity.index()], kink) {
                    cands.push(Candidate {
                        axis: a,
                        quantity,
                        line: start,
                        i,
                        j,
                    });
                }
            }
        }
    }
    cands
}

/// Quantity `k` along the line of axis `a` that starts at grid point `start`.
fn line_values(grid: &Grid, q: &[[f64; 2]], a: usize, start: u64, k: usize) -> Vec<f64> {
    let stride = grid.stride(a);
    (0..grid.axes[a].1.len())
        .map(|i| q[(start + i as u64 * stride) as usize][k])
        .collect()
}

/// Locates one candidate: between the estimates when every point of its span is one, else by
/// bisection on the ideal case ([`locate()`]); its outcome, the simulations it made, and how.
fn locate_candidate(
    c: &Candidate,
    grid: &Grid,
    q: &[[f64; 2]],
    settings: &JumpSettings,
    typical: f64,
    ideal: &dyn IdealCase,
) -> (Outcome, u32, Via) {
    let xs = &grid.axes[c.axis].1;
    let ys = line_values(grid, q, c.axis, c.line, c.quantity.index());
    let mut values = grid.values(c.line);
    let k = c.quantity.index();
    if let Some(out) = between_estimates(c, (xs, &ys), &mut values, ideal, settings.step_tol[k]) {
        return (out, 0, Via::Estimates);
    }
    let f = |x: f64| {
        values[c.axis] = x;
        ideal.at(&values).map(|v| v[k])
    };
    let h = (xs[c.j] - xs[c.i]) / (c.j - c.i) as f64;
    let (outcome, sims, stopped) = locate(
        xs,
        &ys,
        (c.i, c.j),
        f,
        settings.step_tol[k],
        kink_threshold(c.quantity, settings, typical),
        settings.locate * h,
    );
    let via = if stopped {
        Via::Stopped
    } else {
        Via::Bisection
    };
    (outcome, sims, via)
}

impl Found {
    /// Counts a located candidate, and keeps it when it is a jump.
    fn record(&mut self, grid: &Grid, c: &Candidate, outcome: Outcome, sims: u32, via: Via) {
        self.sims += u64::from(sims);
        let jump = matches!(outcome, Outcome::Jump { .. });
        match via {
            Via::Estimates => {
                self.estimated += 1;
                self.estimated_steps += usize::from(jump);
            }
            Via::Stopped => self.stopped_steps += usize::from(jump),
            Via::Bisection => {}
        }
        match outcome {
            Outcome::Jump {
                kind,
                location,
                tol,
                size,
            } => {
                let xs = &grid.axes[c.axis].1;
                // The grid points either side of the location on the line.
                let above = xs[c.i..=c.j]
                    .iter()
                    .position(|&x| x > location)
                    .map_or(c.j, |k| c.i + k)
                    .max(c.i + 1);
                let stride = grid.stride(c.axis);
                self.jumps.push(Jump {
                    axis: c.axis,
                    quantity: c.quantity,
                    kind,
                    location,
                    location_tol: tol,
                    below: c.line + (above - 1) as u64 * stride,
                    above: c.line + above as u64 * stride,
                    size,
                });
            }
            Outcome::Smooth => self.dropped += 1,
            Outcome::Failed => self.failed += 1,
        }
    }
}

/// A candidate whose every grid point is a statistical estimate ([`IdealCase::interval`]): no
/// bisection, since a midpoint's estimate carries the same statistical error as the grid's and
/// a bisection on it follows that noise. A step is looked for between neighbours, in each
/// interval `[x_k, x_{k+1}]` of the span: a step there when the two points' intervals do not
/// overlap and the change `Δ_k` is not the trend's, `min |Δ_k - s h_k| >= step_tol` over the
/// secants `s` of the intervals either side (the candidates' own rule; `|Δ_k|` with none).
/// The largest such change is the step, reported at its interval's middle with half the
/// interval as `location_tol`. Otherwise the span is [`Outcome::Smooth`], dropped: a change
/// within the intervals is not resolved by the estimates, and a trend across a long span, or a
/// bend (a kink candidate's span), is not a step however far its ends lie apart. `None` when a
/// point of the span is exact: the candidate is bisected as usual.
fn between_estimates(
    c: &Candidate,
    (xs, ys): (&[f64], &[f64]),
    values: &mut [f64],
    ideal: &dyn IdealCase,
    step_tol: f64,
) -> Option<Outcome> {
    let k = c.quantity.index();
    let mut intervals = Vec::with_capacity(c.j + 1 - c.i);
    for &x in &xs[c.i..=c.j] {
        values[c.axis] = x;
        intervals.push(ideal.interval(values)?[k]);
    }
    let secant = |a: usize| (ys[a + 1] - ys[a]) / (xs[a + 1] - xs[a]);
    let mut step: Option<(usize, f64)> = None;
    for (n, pair) in intervals.windows(2).enumerate() {
        let (a, b) = (pair[0], pair[1]);
        if a[0] <= b[1] && b[0] <= a[1] {
            continue;
        }
        let i = c.i + n;
        let (change, h) = (ys[i + 1] - ys[i], xs[i + 1] - xs[i]);
        let left = (i > 0).then(|| (change - secant(i - 1) * h).abs());
        let right = (i + 2 < xs.len()).then(|| (change - secant(i + 1) * h).abs());
        let beyond = match (left, right) {
            (Some(l), Some(r)) => l.min(r),
            (Some(one), None) | (None, Some(one)) => one,
            (None, None) => change.abs(),
        };
        if beyond >= step_tol && step.is_none_or(|(_, s)| change.abs() > s.abs()) {
            step = Some((i, change));
        }
    }
    Some(match step {
        Some((i, size)) => Outcome::Jump {
            kind: JumpKind::Step,
            location: 0.5 * (xs[i] + xs[i + 1]),
            tol: 0.5 * (xs[i + 1] - xs[i]),
            size,
        },
        None => Outcome::Smooth,
    })
}

/// The median `|slope|`, floored so that a flat response (slope 0 almost everywhere) does not
/// make every rounding a kink: at least `1e-9 · median |q| / span` of the axis.
fn typical_slope(slopes: &[f64], grid: &Grid, q: &[[f64; 2]], a: usize) -> f64 {
    let xs = &grid.axes[a].1;
    let span = (xs[xs.len() - 1] - xs[0]).abs();
    let level: Vec<f64> = q.iter().map(|v| v[0].abs()).collect();
    let floor = 1e-9 * median(&level) / span;
    let s = median(slopes);
    if s.is_finite() { s.max(floor) } else { floor }
}

fn kink_threshold(quantity: Quantity, s: &JumpSettings, typical: f64) -> Option<f64> {
    (quantity == Quantity::Response && typical.is_finite()).then_some(s.kink_slope * typical)
}

/// Candidate spans `(i, j)` (grid indices, `i < j`) along one line: see the module doc.
/// `kink` is the slope-change threshold, `None` for steps only.
pub fn candidate_spans(
    xs: &[f64],
    ys: &[f64],
    step_tol: f64,
    kink: Option<f64>,
) -> Vec<(usize, usize)> {
    let n = xs.len();
    if n < 2 {
        return Vec::new();
    }
    let s: Vec<f64> = (0..n - 1)
        .map(|i| (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]))
        .collect();
    // Each flag gives a span of grid indices that holds the jump: a step flag its interval, a
    // kink flag the interval and one either side (the slope change that raised it may sit in
    // any of the three). Overlapping or touching spans are one.
    let mut flags: Vec<(usize, usize)> = Vec::new();
    for i in 0..n - 1 {
        if !s[i].is_finite() {
            continue;
        }
        let h = xs[i + 1] - xs[i];
        let d = ys[i + 1] - ys[i];
        let sides = [i.checked_sub(1).map(|k| s[k]), s.get(i + 1).copied()];
        let excess = sides
            .iter()
            .flatten()
            .filter(|t| t.is_finite())
            .map(|t| (d - t * h).abs())
            .fold(f64::INFINITY, f64::min);
        let excess = if excess.is_finite() { excess } else { d.abs() };
        if excess >= step_tol {
            flags.push((i, i + 1));
        }
        if kink.is_some_and(|thr| i >= 1 && i + 1 < n - 1 && (s[i + 1] - s[i - 1]).abs() >= thr) {
            flags.push((i - 1, (i + 2).min(n - 1)));
        }
    }
    flags.sort_unstable();
    let mut spans: Vec<(usize, usize)> = Vec::new();
    for (a, b) in flags {
        match spans.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => spans.push((a, b)),
        }
    }
    spans
}

/// The points of the jump's line whose ±1-step neighbourhood along the axis reaches the
/// jump's location interval: "around the jump" (the two either side of a jump between grid
/// points, three when it sits on one).
pub fn around(grid: &Grid, jump: &Jump) -> Vec<u64> {
    let a = jump.axis;
    let xs = &grid.axes[a].1;
    let n = xs.len();
    let (lo, hi) = (
        jump.location - jump.location_tol,
        jump.location + jump.location_tol,
    );
    (0..n)
        .filter(|&k| {
            let left = xs[k.saturating_sub(1)];
            let right = xs[(k + 1).min(n - 1)];
            left <= hi && right >= lo
        })
        .map(|k| grid.with_index(jump.below, a, k))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_1d(step: f64, lo: f64, hi: f64) -> Vec<f64> {
        let n = ((hi - lo) / step).round() as usize;
        (0..=n).map(|i| lo + i as f64 * step).collect()
    }

    /// A function of one axis as an ideal case (DI unused: NaN).
    struct Fun<F: Fn(f64) -> f64 + Sync>(F);

    impl<F: Fn(f64) -> f64 + Sync> IdealCase for Fun<F> {
        fn at(&self, v: &[f64]) -> Option<[f64; 2]> {
            Some([(self.0)(v[0]), f64::NAN])
        }
    }

    fn run(f: impl Fn(f64) -> f64 + Sync, step: f64) -> Found {
        let xs = grid_1d(step, 0.0, 1.0);
        let q: Vec<[f64; 2]> = xs.iter().map(|&x| [f(x), f64::NAN]).collect();
        let grid = Grid::new(vec![("x".into(), xs)]);
        let settings = JumpSettings {
            step_tol: [0.05, 0.05],
            kink_slope: 1.5,
            locate: 0.01,
        };
        find(&grid, &q, &settings, &Fun(f))
    }

    // A smooth trend (slope about 0.3) with a step of 0.2 at 0.4567 and a kink at 0.7321
    // (slope +0.3 -> -0.9).
    fn step_and_kink(x: f64) -> f64 {
        let smooth = 0.3 * x + 0.05 * (3.0 * x).sin();
        let step = if x > 0.4567 { 0.2 } else { 0.0 };
        let kink = if x > 0.7321 { -1.2 * (x - 0.7321) } else { 0.0 };
        smooth + step + kink
    }

    /// Estimates everywhere: each grid value of the second quantity (steps only, no kinks)
    /// known within `±half` (the response unused: NaN); `at` counts the simulations asked for.
    struct Estimated<F: Fn(f64) -> f64 + Sync> {
        f: F,
        half: f64,
        asked: std::sync::atomic::AtomicU64,
    }

    impl<F: Fn(f64) -> f64 + Sync> IdealCase for Estimated<F> {
        fn at(&self, v: &[f64]) -> Option<[f64; 2]> {
            self.asked
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            Some([f64::NAN, (self.f)(v[0])])
        }

        fn interval(&self, v: &[f64]) -> Option<[[f64; 2]; 2]> {
            let y = (self.f)(v[0]);
            Some([[f64::NAN; 2], [y - self.half, y + self.half]])
        }
    }

    /// Estimates everywhere of the response (kinks and steps): `at` never resolves, each
    /// grid value known within `±half` (DI unused: NaN).
    struct ResponseEstimates<F: Fn(f64) -> f64 + Sync>(F, f64);

    impl<F: Fn(f64) -> f64 + Sync> IdealCase for ResponseEstimates<F> {
        fn at(&self, _v: &[f64]) -> Option<[f64; 2]> {
            Some([UNRESOLVED, UNRESOLVED])
        }

        fn interval(&self, v: &[f64]) -> Option<[[f64; 2]; 2]> {
            let y = (self.0)(v[0]);
            Some([[y - self.1, y + self.1], [f64::NAN; 2]])
        }
    }

    #[test]
    fn between_estimates_a_bend_smaller_than_the_step_tolerance_is_no_step() {
        // A kink candidate spanning a four-value axis between estimates whose ends' intervals
        // do not overlap, but whose change end to end is below the step tolerance (the
        // multi-unit showcase's peaks along d_spread, stop 106): dropped, not a step.
        fn bend(x: f64) -> f64 {
            if x < 0.5 {
                -0.2 * x
            } else {
                -0.1 + 0.3 * (x - 0.5)
            }
        }
        let bent = ResponseEstimates(bend, 1e-4);
        let xs = vec![0.0, 0.25, 0.5, 0.75];
        let grid = Grid::new(vec![("x".into(), xs.clone())]);
        let settings = JumpSettings {
            step_tol: [0.5, 0.5],
            kink_slope: 1.5,
            locate: 0.01,
        };
        let q: Vec<[f64; 2]> = xs.iter().map(|&x| [bend(x), f64::NAN]).collect();
        let found = find(&grid, &q, &settings, &bent);
        assert_eq!((found.candidates, found.estimated), (1, 1), "{found:?}");
        assert!(found.jumps.is_empty(), "{:?}", found.jumps);
        assert_eq!((found.dropped, found.sims), (1, 0));
        // With a tolerance below the change between two neighbours beyond the trend before
        // it (0.075 + 0.05 over [0.5, 0.75]), that interval is a step: at the grid's
        // resolution a bend that sharp is not told from a step.
        let small = JumpSettings {
            step_tol: [0.02, 0.02],
            ..settings
        };
        let found = find(&grid, &q, &small, &bent);
        assert_eq!(found.jumps.len(), 1, "{found:?}");
        assert_eq!(found.jumps[0].kind, JumpKind::Step);
    }

    #[test]
    fn between_estimates_a_trend_across_a_long_span_is_no_step() {
        // A ramp between two flats, every point an estimate within +-0.005: its two bends are
        // kink candidates that touch and make one span over [0.1, 0.9], whose ends' intervals
        // lie 0.08 apart, beyond the step tolerance (0.05). No two neighbours part by more
        // than 0.02, so there is no step: the span is dropped. (Judged by its ends alone,
        // stop 106's rule, it was a "step" of 0.08.)
        fn ramp(x: f64) -> f64 {
            0.2 * (x.clamp(0.3, 0.7) - 0.3)
        }
        let xs = grid_1d(0.1, 0.0, 1.0);
        let grid = Grid::new(vec![("x".into(), xs.clone())]);
        let settings = JumpSettings {
            step_tol: [0.05, 0.05],
            kink_slope: 1.5,
            locate: 0.01,
        };
        let q: Vec<[f64; 2]> = xs.iter().map(|&x| [ramp(x), f64::NAN]).collect();
        let found = find(&grid, &q, &settings, &ResponseEstimates(ramp, 5e-3));
        assert_eq!((found.candidates, found.estimated), (1, 1), "{found:?}");
        assert!(found.jumps.is_empty(), "{:?}", found.jumps);
        assert_eq!((found.dropped, found.sims), (1, 0));
        // A step of 0.1 put into the ramp at 0.55 is found there, to its grid interval.
        fn stepped(x: f64) -> f64 {
            ramp(x) + if x > 0.55 { 0.1 } else { 0.0 }
        }
        let q: Vec<[f64; 2]> = xs.iter().map(|&x| [stepped(x), f64::NAN]).collect();
        let found = find(&grid, &q, &settings, &ResponseEstimates(stepped, 5e-3));
        assert_eq!(found.jumps.len(), 1, "{found:?}");
        let j = &found.jumps[0];
        assert_eq!(j.kind, JumpKind::Step);
        assert!((j.location - 0.55).abs() < 1e-12 && (j.location_tol - 0.05).abs() < 1e-12);
        assert!((j.size - (stepped(0.6) - stepped(0.5))).abs() < 1e-12);
    }

    #[test]
    fn between_estimates_a_step_beyond_the_intervals_is_kept_at_grid_width_and_one_within_is_dropped()
     {
        let xs = grid_1d(0.1, 0.0, 1.0);
        let grid = Grid::new(vec![("x".into(), xs.clone())]);
        let settings = JumpSettings {
            step_tol: [0.03, 0.03],
            kink_slope: 1.5,
            locate: 0.01,
        };
        // A step of 0.2 at 0.4567 (beyond intervals of +-0.05) and one of 0.04 at 0.8567 (a
        // candidate by the step tolerance, but within intervals of +-0.05).
        let f = |x: f64| {
            0.1 * x + if x > 0.4567 { 0.2 } else { 0.0 } + if x > 0.8567 { 0.04 } else { 0.0 }
        };
        let q: Vec<[f64; 2]> = xs.iter().map(|&x| [f64::NAN, f(x)]).collect();
        let ideal = Estimated {
            f,
            half: 0.05,
            asked: Default::default(),
        };
        let found = find(&grid, &q, &settings, &ideal);
        assert_eq!(found.candidates, 2, "{found:?}");
        assert_eq!((found.estimated, found.estimated_steps), (2, 1));
        assert_eq!(found.dropped, 1);
        assert_eq!(found.jumps.len(), 1);
        let j = &found.jumps[0];
        assert_eq!(j.kind, JumpKind::Step);
        assert_eq!(j.quantity, Quantity::Di);
        assert!((j.location - 0.45).abs() < 1e-12 && (j.location_tol - 0.05).abs() < 1e-12);
        assert!((j.size - (f(0.5) - f(0.4))).abs() < 1e-12);
        // Nothing bisected: no simulation asked for.
        assert_eq!(found.sims, 0);
        assert_eq!(ideal.asked.load(std::sync::atomic::Ordering::Relaxed), 0);
        // The same function known exactly is bisected and located to 1/100 of the step.
        struct Exact<F: Fn(f64) -> f64 + Sync>(F);
        impl<F: Fn(f64) -> f64 + Sync> IdealCase for Exact<F> {
            fn at(&self, v: &[f64]) -> Option<[f64; 2]> {
                Some([f64::NAN, (self.0)(v[0])])
            }
        }
        let exact = find(&grid, &q, &settings, &Exact(f));
        assert_eq!(exact.jumps.len(), 2, "{exact:?}");
        assert!(exact.jumps.iter().all(|j| j.location_tol <= 0.0005 + 1e-12));
    }

    #[test]
    fn a_bisection_stops_at_an_unresolved_midpoint_with_the_bracket_it_reached() {
        // DI slot (steps only). A step of 0.2 at 0.4567; the midpoints in (0.42, 0.48) are
        // estimates.
        struct Partly;
        impl IdealCase for Partly {
            fn at(&self, v: &[f64]) -> Option<[f64; 2]> {
                let x = v[0];
                let y = if x > 0.42 && x < 0.48 {
                    UNRESOLVED
                } else {
                    0.1 * x + if x > 0.4567 { 0.2 } else { 0.0 }
                };
                Some([f64::NAN, y])
            }
        }
        let xs = grid_1d(0.1, 0.0, 1.0);
        let q: Vec<[f64; 2]> = xs
            .iter()
            .map(|&x| [f64::NAN, Partly.at(&[x]).unwrap()[1]])
            .collect();
        let grid = Grid::new(vec![("x".into(), xs)]);
        let settings = JumpSettings {
            step_tol: [0.05, 0.05],
            kink_slope: 1.5,
            locate: 0.01,
        };
        let found = find(&grid, &q, &settings, &Partly);
        assert_eq!(found.jumps.len(), 1, "{found:?}");
        let j = &found.jumps[0];
        assert_eq!(j.kind, JumpKind::Step);
        // The first midpoint, 0.45, is an estimate: the bracket [0.4, 0.5] is the location.
        assert!((j.location - 0.45).abs() < 1e-12 && (j.location_tol - 0.05).abs() < 1e-12);
        assert_eq!(found.sims, 1);
        assert_eq!(found.failed, 0);
    }

    #[test]
    fn a_step_and_a_kink_are_located_within_their_tolerance_at_every_grid_step() {
        for step in [0.01, 0.001, 0.0001] {
            let found = run(step_and_kink, step);
            let kinds: Vec<(JumpKind, f64)> =
                found.jumps.iter().map(|j| (j.kind, j.location)).collect();
            assert_eq!(found.jumps.len(), 2, "step {step}: {kinds:?}");
            let s = &found.jumps[0];
            assert_eq!(s.kind, JumpKind::Step);
            assert!((s.location - 0.4567).abs() <= s.location_tol, "{s:?}");
            assert!(s.location_tol <= 0.005 * step + 1e-15);
            assert!((s.size - 0.2).abs() < 0.01, "{s:?}");
            let k = &found.jumps[1];
            assert_eq!(k.kind, JumpKind::Kink);
            assert!((k.location - 0.7321).abs() <= k.location_tol, "{k:?}");
            assert!((k.size + 1.2).abs() < 0.05, "{k:?}");
            // About log2(100) simulations per candidate.
            assert!(found.sims <= 10 * found.candidates as u64, "{found:?}");
        }
    }

    #[test]
    fn a_square_root_corner_is_a_kink_and_smooth_curves_have_none() {
        // Grazing: the slope is unbounded on one side of the corner, either side.
        let right = |x: f64| 0.2 * x - 0.1 * (x - 0.61234).max(0.0).sqrt();
        let left = |x: f64| 0.2 * x - 0.1 * (0.61234 - x).max(0.0).sqrt();
        for step in [0.01, 0.001, 0.0001] {
            for (side, found) in [("right", run(right, step)), ("left", run(left, step))] {
                assert_eq!(found.jumps.len(), 1, "{side} {step}: {found:?}");
                let j = &found.jumps[0];
                assert_eq!(j.kind, JumpKind::Kink);
                assert!(
                    (j.location - 0.61234).abs() <= j.location_tol,
                    "{step}: {j:?}"
                );
            }
        }
        // A strongly curved but smooth function: candidates may appear, none survive.
        let found = run(|x| (8.0 * x).sin() * (1.0 + x), 0.01);
        assert!(found.jumps.is_empty(), "{found:?}");
        assert_eq!(found.dropped, found.candidates);
        // A straight line: not even a candidate.
        let found = run(|x| 2.0 * x + 1.0, 0.01);
        assert_eq!((found.candidates, found.sims), (0, 0));
    }

    #[test]
    fn a_hard_curving_smooth_stretch_is_not_a_step_at_any_bracket_and_a_real_step_in_it_is() {
        // DI along m on the README's three-value grid (0.01, 0.02, 0.03 kg) curves hard: its
        // change across a bracket ten tolerances wide passes step_tol, across the finest not.
        let smooth = |x: f64| 0.025 + 0.8 * (x - 0.01) + 40.0 * (x - 0.01).powi(2);
        let (step_tol, tol) = (4e-4, 1e-4);
        let xs = [0.01, 0.02, 0.03];
        let ys: Vec<f64> = xs.iter().map(|&x| smooth(x)).collect();
        let (outcome, _, _) = locate(&xs, &ys, (0, 1), |x| Some(smooth(x)), step_tol, None, tol);
        assert_eq!(outcome, Outcome::Smooth);
        // A real step on the same curve (inside the grid, where both sides have a trend) is
        // still a step, at the finest bracket.
        let stepped = |x: f64| smooth(x) + if x > 0.0137 { 1e-2 } else { 0.0 };
        let xs = [0.0, 0.01, 0.02, 0.03, 0.04];
        let ys: Vec<f64> = xs.iter().map(|&x| stepped(x)).collect();
        let (outcome, _, _) = locate(&xs, &ys, (1, 2), |x| Some(stepped(x)), step_tol, None, tol);
        let Outcome::Jump {
            kind,
            location,
            tol: lt,
            size,
        } = outcome
        else {
            panic!("no step: {outcome:?}");
        };
        assert_eq!(kind, JumpKind::Step);
        assert!(
            (location - 0.0137).abs() <= lt && lt <= tol,
            "{location} ± {lt}"
        );
        assert!((size - 1e-2).abs() < 1e-4, "{size}");
        // Two steps close together, up then down by more: whichever the search settles on, it
        // is one of them, to the tolerance.
        let two = |x: f64| {
            smooth(x) + if x > 0.0137 { 1e-2 } else { 0.0 } - if x > 0.0142 { 1.5e-2 } else { 0.0 }
        };
        let ys: Vec<f64> = xs.iter().map(|&x| two(x)).collect();
        let (outcome, _, _) = locate(&xs, &ys, (1, 2), |x| Some(two(x)), step_tol, None, tol);
        let Outcome::Jump {
            kind,
            location,
            tol: lt,
            ..
        } = outcome
        else {
            panic!("no step: {outcome:?}");
        };
        assert_eq!(kind, JumpKind::Step);
        assert!(
            [0.0137, 0.0142]
                .iter()
                .any(|x| (location - x).abs() <= lt && lt <= tol),
            "{location} ± {lt}"
        );
    }

    #[test]
    fn a_step_below_the_tolerance_is_not_a_jump() {
        let found = run(|x| 0.3 * x + if x > 0.5 { 0.04 } else { 0.0 }, 0.01);
        assert!(found.jumps.is_empty(), "{found:?}");
    }

    #[test]
    fn around_marks_the_points_either_side() {
        let grid = Grid::new(vec![("x".into(), vec![0.0, 0.1, 0.2, 0.3, 0.4])]);
        let mut j = Jump {
            axis: 0,
            quantity: Quantity::Response,
            kind: JumpKind::Step,
            location: 0.15,
            location_tol: 0.0005,
            below: 1,
            above: 2,
            size: 1.0,
        };
        assert_eq!(around(&grid, &j), vec![1, 2]);
        // On a grid point: that point and both neighbours.
        j.location = 0.2;
        assert_eq!(around(&grid, &j), vec![1, 2, 3]);
    }
}
