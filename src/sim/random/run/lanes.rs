//! Realizations of one design crossed side by side: the whole-interval crossing of
//! [`super::Realization::whole`] for up to [`LANES`] runs at once, each run on its own interval,
//! in arrays the compiler keeps in vector registers (four `f64` to an AVX register).
//!
//! A run's crossing is a chain: each interval starts where the last one ended, so one run
//! cannot be spread over lanes. Runs of one design share every constant of the test (the
//! propagator, the bounds, the clearance), so `LANES` runs can take their next intervals in
//! the same instructions. Each lane does exactly the operations of
//! [`super::Realization::whole`]'s common case (the interval's `|x|` stays below the largest so
//! far, one unit whose gap stays off both walls), in the same order, so an interval the lanes
//! cross ends in the same state, with the same Gram sum, bit for bit. Any other interval (a
//! wall or a new largest `|x|` possible, a NaN, the run's last interval) leaves the lanes: that
//! run alone goes on as [`super::RandomRun::run_block`] runs it, through its own crossing and
//! the event loop, to the end of its next interval, then comes back. So each record is
//! `run_block`'s, bit for bit, whatever the runs beside it
//! (`runs_side_by_side_are_each_run_alone` below).

use super::{LoadBlock, Ramp, Request};
use super::{NoProbe, Outcome, Phase, RandomRecord, RandomRun, Realization, State};
use crate::sim::driven::DrivenPhase;
use crate::sim::phase;
use crate::sim::random::Input;
use crate::sim::random::load::GivenNormals;

/// Runs crossed side by side (four `f64` lanes of an AVX register).
pub(crate) const LANES: usize = 4;

/// The crossing state of the lanes: each lane's main and inner mass, the largest `|x|` so far,
/// its Gram sum and its next interval.
#[derive(Default)]
struct Soa {
    x: [f64; LANES],
    v: [f64; LANES],
    y: [f64; LANES],
    w: [f64; LANES],
    amp: [f64; LANES],
    gram: [[f64; LANES]; 10],
    k: [u64; LANES],
}

/// Each lane's next interval when `can`, its load the samples `a` to `b` times `gain`
/// (`Samples::next`'s operations): crossed (its state, Gram sum and interval moved on) where
/// [`super::Realization::whole`]'s common case passes it, the same operations in the same
/// order. A lane that does not pass is left as it was. Returns a bit for each lane that
/// passed, and one for each lane whose interval `whole` would refuse on the same test (its
/// `|x|` below the largest so far, a wall within reach: the event loop takes it).
/// (One loop over the lanes without a branch, which the compiler turns into vector
/// operations.)
#[inline(always)]
fn step(
    run: &RandomRun,
    integrals: bool,
    s: &mut Soa,
    (a, b, gain): Load,
    can: &[bool; LANES],
) -> (u32, u32) {
    let (dt, third, half_d) = (run.scene.dt, run.third, 0.5 * run.sys.d);
    let base = run.scene.input == Input::Base;
    let min = |a: f64, b: f64| if a < b { a } else { b };
    let max = |a: f64, b: f64| if a > b { a } else { b };
    let mut pass = [false; LANES];
    let mut wall = [false; LANES];
    for i in 0..LANES {
        let (q0, qs) = (a[i] * gain[i], ((b[i] - a[i]) / dt) * gain[i]);
        let (f0, sl) = (run.free_scale * q0, run.free_scale * qs);
        let p1 = sl * run.inv_k;
        let p0 = (f0 - run.sys.C * p1) * run.inv_k;
        let (x0, v0) = (s.x[i], s.v[i]);
        let (h0, g0) = (x0 - p0, v0 - p1);
        let (xh, vh) = (
            run.prop.xx * h0 + run.prop.xv * g0,
            run.prop.vx * h0 + run.prop.vv * g0,
        );
        let (x1, v1) = (xh + (p0 + p1 * dt), vh + p1);
        let b0 = (h0 * h0 + run.m_over_k * g0 * g0).sqrt();
        let err = run.err4 * b0;
        // The displacement's hull (`hull`, without a NaN).
        let (p, q) = (x0 + third * v0, x1 - third * v1);
        let nan_x = ((x0 + p) + (q + x1)).is_nan();
        let lo = min(min(x0, p), min(q, x1));
        let hi = max(max(x0, p), max(q, x1));
        let reach = if hi > -lo { hi } else { -lo };
        let below = reach + err < s.amp[i];
        // The inner mass's line over the interval (`Walls::at` from local time 0).
        let (ya, yj) = if base { (-q0, -qs) } else { (0.0, 0.0) };
        let (y0, w0) = (s.y[i], s.w[i]);
        let tau = dt - 0.0;
        let line = ya == 0.0 && yj == 0.0;
        let y1 = if line {
            y0 + w0 * tau
        } else {
            y0 + tau * (w0 + tau * (0.5 * ya + tau * yj / 6.0))
        };
        let w1 = if line {
            w0
        } else {
            w0 + tau * (ya + 0.5 * tau * yj)
        };
        // The gap's hull and margin (`line_clear`).
        let (g0, d0, g1, d1) = (y0 - x0, w0 - v0, y1 - x1, w1 - v1);
        let (p, q) = (g0 + third * d0, g1 - third * d1);
        let nan_g = ((g0 + p) + (q + g1)).is_nan();
        let lo = min(min(g0, p), min(q, g1));
        let hi = max(max(g0, p), max(q, g1));
        let scale = half_d + x0.abs() + x1.abs() + y0.abs() + y1.abs();
        let margin = err + 1e-12 * scale;
        let inside = (hi + margin < half_d) & (lo - margin > -half_d);
        // Decided by the same test as the run alone's (no NaN, `|x|` below): crossed, or a wall
        // within reach.
        let decided = can[i] & below & !nan_x & !nan_g;
        let ok = decided & inside;
        pass[i] = ok;
        wall[i] = decided & !inside;
        let keep = |new: f64, old: f64| if ok { new } else { old };
        if integrals {
            // `gram_add`'s upper triangle, row by row, of `u = (x0, v0, f0, f1)`.
            let u = [x0, v0, f0, f0 + sl * dt];
            let g = &mut s.gram;
            g[0][i] = keep(g[0][i] + u[0] * u[0], g[0][i]);
            g[1][i] = keep(g[1][i] + u[0] * u[1], g[1][i]);
            g[2][i] = keep(g[2][i] + u[0] * u[2], g[2][i]);
            g[3][i] = keep(g[3][i] + u[0] * u[3], g[3][i]);
            g[4][i] = keep(g[4][i] + u[1] * u[1], g[4][i]);
            g[5][i] = keep(g[5][i] + u[1] * u[2], g[5][i]);
            g[6][i] = keep(g[6][i] + u[1] * u[3], g[6][i]);
            g[7][i] = keep(g[7][i] + u[2] * u[2], g[7][i]);
            g[8][i] = keep(g[8][i] + u[2] * u[3], g[8][i]);
            g[9][i] = keep(g[9][i] + u[3] * u[3], g[9][i]);
        }
        s.x[i] = keep(x1, x0);
        s.v[i] = keep(v1, v0);
        s.y[i] = keep(y1, y0);
        s.w[i] = keep(w1, w0);
        s.k[i] += u64::from(ok);
    }
    (mask(&pass), mask(&wall))
}

/// The lanes set in `b`, a bit each.
fn mask(b: &[bool; LANES]) -> u32 {
    b.iter()
        .enumerate()
        .fold(0, |m, (i, &p)| m | (u32::from(p) << i))
}

/// The lanes' loads: the samples at each lane's interval start and end, and its gain.
type Load<'l> = (&'l [f64; LANES], &'l [f64; LANES], &'l [f64; LANES]);

/// Where a run of the lanes is.
#[derive(Clone, Copy, PartialEq)]
enum Stage {
    /// At the start of interval `k`, to be crossed.
    Crossing,
    /// Ended with this outcome.
    Done(Outcome),
}

/// One run of the lanes: its realization, its solver, its stage.
struct Lane<'a> {
    scene: Realization<'a, GivenNormals<'a>, NoProbe>,
    solver: DrivenPhase<Ramp>,
    stage: Stage,
}

impl<'a> Lane<'a> {
    /// Whether the lanes may cross this run's intervals: a run of one unit in free flight.
    fn in_lanes(&self) -> bool {
        self.stage == Stage::Crossing
            && self.scene.map.phase == Phase::Free
            && !self.scene.map.several()
    }

    /// The run alone from the start of its interval `k`: its own crossing (`to_loop`: known to
    /// refuse interval `k`, so only its load read), then the event loop to the end of the next
    /// interval it takes (or of the run), as [`RandomRun::run_samples`] goes on.
    fn alone(&mut self, to_loop: bool) {
        let load = if to_loop {
            self.scene.samples.next()
        } else {
            self.scene.cross()
        };
        self.scene.begin_interval(&mut self.solver, load);
        self.scene.yielded = false;
        let outcome = phase::run(&mut self.scene, &mut self.solver);
        if !self.scene.yielded {
            self.stage = Stage::Done(outcome);
        }
    }
}

impl RandomRun {
    /// [`RandomRun::run_block`] of each `(block, gain)` in `runs`, with no probe: the same
    /// records bit for bit, up to [`LANES`] runs crossing their intervals side by side (module
    /// doc). A trace, a massless inner mass or several units run each alone.
    pub fn run_blocks(&self, req: &Request, runs: &[(&LoadBlock, f64)]) -> Vec<RandomRecord> {
        self.side_by_side(req, runs, true)
    }

    /// [`RandomRun::amplitude_block`] of each `(block, gain)` in `runs`, the runs side by side
    /// as in [`RandomRun::run_blocks`]: the same amplitudes bit for bit (a capacity search's
    /// trials of several motions).
    pub fn amplitude_blocks(&self, req: &Request, runs: &[(&LoadBlock, f64)]) -> Vec<f64> {
        self.side_by_side(req, runs, false)
            .iter()
            .map(|r| r.amplitude)
            .collect()
    }

    /// The runs of `runs`, with the integrals or without ([`RandomRun::run_samples`]).
    fn side_by_side(
        &self,
        req: &Request,
        runs: &[(&LoadBlock, f64)],
        integrals: bool,
    ) -> Vec<RandomRecord> {
        // (Several units never enter the lanes: `Lane::in_lanes`.)
        if req.trace_dt.is_some() || self.sys.m == 0.0 || runs.len() < 2 {
            return runs
                .iter()
                .map(|&(block, gain)| {
                    let samples = self.block_samples(block, gain);
                    self.run_samples(req, samples, &mut NoProbe, integrals)
                })
                .collect();
        }
        runs.chunks(LANES)
            .flat_map(|group| self.run_lanes(req, group, integrals))
            .collect()
    }

    /// Up to [`LANES`] runs side by side.
    fn run_lanes(
        &self,
        req: &Request,
        runs: &[(&LoadBlock, f64)],
        integrals: bool,
    ) -> Vec<RandomRecord> {
        debug_assert!(runs.len() <= LANES);
        let mut probes: Vec<NoProbe> = runs.iter().map(|_| NoProbe).collect();
        let mut lanes: Vec<Lane<'_>> = runs
            .iter()
            .zip(probes.iter_mut())
            .map(|(&(block, gain), probe)| {
                let samples = self.block_samples(block, gain);
                let (mut scene, solver) = self.start(req, samples, probe, integrals);
                scene.yield_cross = true;
                Lane {
                    scene,
                    solver,
                    stage: Stage::Crossing,
                }
            })
            .collect();
        // Each lane's samples and gain (an idle lane's empty).
        let mut values: [&[f64]; LANES] = [&[]; LANES];
        let mut gains = [0.0; LANES];
        for (i, &(block, gain)) in runs.iter().enumerate() {
            (values[i], gains[i]) = (&block.values, gain);
        }
        let mut s = Soa::default();
        let mut on = [false; LANES];
        for (i, lane) in lanes.iter_mut().enumerate() {
            on[i] = enter(lane, &mut s, i);
        }
        while on.iter().any(|&b| b) {
            // Each lane's interval's samples, read as `Samples::next` reads them.
            let (mut a, mut b) = ([0.0; LANES], [0.0; LANES]);
            let mut can = [false; LANES];
            let mut last = [false; LANES];
            for i in 0..LANES {
                let j = s.k[i] as usize;
                last[i] = on[i] && s.k[i] + 1 >= self.segments;
                if on[i] && !last[i] && j + 1 < values[i].len() {
                    (a[i], b[i]) = (values[i][j], values[i][j + 1]);
                    can[i] = true;
                }
            }
            let (pass, wall) = step(self, integrals, &mut s, (&a, &b, &gains), &can);
            // The run's last interval and a wall within reach go to the event loop as the
            // run's own crossing sends them (it would test them again and refuse); any other
            // refusal is the run's own crossing's to decide.
            let to_loop = wall | mask(&last);
            let mut left = mask(&on) & !pass;
            while left != 0 {
                let i = left.trailing_zeros() as usize;
                left &= left - 1;
                let lane = &mut lanes[i];
                leave(lane, &s, i);
                lane.alone(to_loop & (1 << i) != 0);
                on[i] = enter(lane, &mut s, i);
            }
        }
        lanes
            .into_iter()
            .map(|lane| {
                let Stage::Done(outcome) = lane.stage else {
                    unreachable!("every lane runs to its end");
                };
                lane.scene.finish(outcome, &lane.solver)
            })
            .collect()
    }
}

/// Puts `lane` into lane `i` of `s` where the lanes may cross its intervals (running it alone
/// until then, or to its end); whether it is in.
fn enter(lane: &mut Lane<'_>, s: &mut Soa, i: usize) -> bool {
    while lane.stage == Stage::Crossing && !lane.in_lanes() {
        lane.alone(false);
    }
    if lane.stage != Stage::Crossing {
        return false;
    }
    let scene = &lane.scene;
    let st = scene.map.s;
    (s.x[i], s.v[i], s.y[i], s.w[i]) = (st.x, st.v, st.y, st.w);
    s.amp[i] = scene.amplitude;
    for (n, g) in scene.gram.iter().enumerate() {
        s.gram[n][i] = *g;
    }
    s.k[i] = scene.k;
    true
}

/// Hands lane `i` of `s` back to its run: the state, Gram sum and intervals it crossed.
fn leave(lane: &mut Lane<'_>, s: &Soa, i: usize) {
    let scene = &mut lane.scene;
    scene.map.s = State {
        x: s.x[i],
        v: s.v[i],
        y: s.y[i],
        w: s.w[i],
    };
    for (n, g) in scene.gram.iter_mut().enumerate() {
        *g = s.gram[n][i];
    }
    let crossed = s.k[i] - scene.k;
    scene.k = s.k[i];
    scene.crossed += crossed;
    scene.samples.skip(crossed);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::System;
    use crate::sim::random::{RandomScene, RealizationStream};
    use crate::sim::settings::SolverSettings;

    /// Every record of runs crossed side by side is the run alone, bit for bit: designs from
    /// long free flights to chatter and sticking and the extremes of `e`, `C`, `d` and `m`,
    /// under ground acceleration and a force, a record, at three gains, in groups of one to
    /// nine runs; and each amplitude alone (a capacity search's trials).
    #[test]
    fn runs_side_by_side_are_each_run_alone() {
        let settings = SolverSettings::default();
        let req = Request::default();
        let scenes = [
            super::super::tests::seismic(),
            super::super::tests::record(),
            RandomScene {
                input: Input::Force,
                ..super::super::tests::seismic()
            },
        ];
        let base = super::super::tests::damped();
        let design = |m, d| System { m, d, ..base };
        let designs = [
            design(0.1, 0.01),
            design(0.05, 0.02),
            design(0.2, 0.005),
            design(0.2, 0.04),
            design(0.4, 0.001),
            // The extremes: a clearance of a micron (chatter and sticking), a plastic and an
            // elastic impact, no damping, an inner mass far heavier than the structure.
            design(0.1, 1e-6),
            System {
                e: 0.0,
                ..design(0.1, 0.01)
            },
            System {
                e: 1.0,
                ..design(0.1, 0.01)
            },
            System {
                C: 0.0,
                ..design(0.1, 0.01)
            },
            design(50.0, 0.01),
        ];
        let mut compared = 0;
        for scene in &scenes {
            for sys in &designs {
                let (m, d) = (sys.m, sys.d);
                let run = RandomRun::new(sys, &settings, scene);
                let blocks: Vec<LoadBlock> = (0..9)
                    .map(|r| run.load(RealizationStream::new(7, 0, r)))
                    .collect();
                for (n, gain) in [(1, 1.0), (3, 1.0), (4, 2.5), (5, 0.7), (9, 1.0)] {
                    let runs: Vec<(&LoadBlock, f64)> =
                        blocks[..n].iter().map(|b| (b, gain)).collect();
                    let together = run.run_blocks(&req, &runs);
                    for (&(block, gain), got) in runs.iter().zip(&together) {
                        let alone = run.run_block(&req, block, gain, &mut NoProbe);
                        assert_eq!(
                            format!("{got:?}"),
                            format!("{alone:?}"),
                            "m = {m}, d = {d}, gain {gain}, {n} runs"
                        );
                        compared += 1;
                    }
                    let amplitudes = run.amplitude_blocks(&req, &runs);
                    for (&(block, gain), got) in runs.iter().zip(&amplitudes) {
                        let alone = run.amplitude_block(&req, block, gain);
                        assert_eq!(got.to_bits(), alone.to_bits());
                    }
                }
            }
        }
        assert_eq!(compared, 3 * designs.len() * 22);
    }
}
