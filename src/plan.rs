//! Plan: a [`Study`] expanded into design points, runs and chunks, each with its identity and
//! seed. Pure and cheap: nothing is materialised, every run is computed from its index.
//!
//! CONTRACT (shared by the sweep engine, the store and the reducer):
//! * design point `p` in `0..n_points`: mixed-radix index over the axes, last axis fastest;
//! * run `(p, c)` with case `c` in `0..n_cases`; its stable `point_id = p * n_cases + c`;
//! * chunk `k` holds design points `k * chunk_points .. min((k + 1) * chunk_points, n_points)`
//!   and all their cases, in `point_id` order; shard `i/N` takes the chunks with `k % N == i`;
//!   a random study whose design points have more realizations than `[run].chunk_realizations`
//!   (`c`) splits each into `B = ceil(n_cases / c)` blocks instead: chunk `k` is block `k % B`
//!   of design point `k / B`, its realizations `(k % B) c .. min((k % B + 1) c, n_cases)`, so
//!   chunks stay contiguous ranges of `point_id` ([`Plan::chunk_runs`]);
//! * the noise stream of a run is `NoiseStream::new(study.seed, noise_seed, p)`: cases sharing
//!   a noise seed at one design point share their noise (as the paper's Table II rows do);
//! * in a harmonic study the frequency axis is the last (the study moves it there) and a chunk
//!   holds a whole number of its curves, so chunk `k` holds whole frequency-response curves:
//!   a design, in the reducer's sense, is a design point without its frequency;
//! * in a random or record study the cases of a design point are its realizations
//!   `0..realizations` ([`crate::study::Study::n_cases`]); realization `c` draws its load's
//!   normals from [`RealizationStream::new`]`(study.seed, 0, c)` ([`Plan::load_stream`]) at
//!   every design point: the same realization number is the same white noise at every design
//!   and intensity (common random numbers: designs are compared on the same loads, and a
//!   fragility curve's intensities scale the same loads), and a run's record is the same bits
//!   whatever the thread count, chunk size, shard or resume.

use crate::model::System;
use crate::sim::Scene;
use crate::sim::noise::NoiseStream;
use crate::sim::random::RealizationStream;
use crate::study::{Case, Study};

/// One run to simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// `point * n_cases + case`.
    pub point_id: u64,
    /// Design point index.
    pub point: u64,
    /// Case index into `Study::cases`.
    pub case: u32,
    /// The system of this run: the design point's axis values over the base, then `dm`, `dd`.
    pub system: System,
    /// The scene of this run: the study's, with the design point's `F0`, `omega` or `r` (a
    /// random study's: its `S0`, filter keys or `scale`).
    pub scene: Scene,
    /// The case (`dm`, `dd`, `noise_seed`, `ideal`); in a random study realization `c` is the
    /// case `dm = dd = 0`, not ideal, `noise_seed = c` for a random load (none for a record).
    pub spec: Case,
}

/// The expansion of a study.
#[derive(Clone, Debug)]
pub struct Plan<'a> {
    pub study: &'a Study,
}

impl<'a> Plan<'a> {
    pub fn new(study: &'a Study) -> Self {
        Plan { study }
    }

    pub fn n_points(&self) -> u64 {
        self.study.n_points()
    }

    pub fn n_cases(&self) -> u64 {
        self.study.n_cases()
    }

    pub fn n_runs(&self) -> u64 {
        self.n_points() * self.n_cases()
    }

    pub fn n_chunks(&self) -> u64 {
        match self.blocks() {
            1 => self.n_points().div_ceil(self.study.run.chunk_points.max(1)),
            b => self.n_points().saturating_mul(b),
        }
    }

    /// Runs of one design point a chunk holds at most: all its cases, or a random study's
    /// `[run].chunk_realizations` when its points have more realizations (module doc).
    pub fn chunk_cases(&self) -> u64 {
        let n = self.n_cases();
        match self.study.scene {
            Scene::Random(_) => n.min(self.study.run.chunk_realizations.max(1)),
            Scene::Free | Scene::Harmonic(_) => n,
        }
    }

    /// Chunks per design point: 1 unless a random study's points are split into blocks.
    pub fn blocks(&self) -> u64 {
        self.n_cases().div_ceil(self.chunk_cases().max(1)).max(1)
    }

    /// The runs (`point_id`s) of chunk `k`, a contiguous range.
    pub fn chunk_runs(&self, k: u64) -> std::ops::Range<u64> {
        let n = self.n_cases();
        match self.blocks() {
            1 => {
                let p = self.chunk_points(k);
                p.start * n..p.end * n
            }
            b => {
                let (p, block) = (k / b, k % b);
                let c = self.chunk_cases();
                let start = p * n + block * c;
                start..(start + c).min((p + 1) * n)
            }
        }
    }

    /// The axis values of design point `p` (one per axis, in axis order).
    pub fn point_values(&self, p: u64) -> Vec<f64> {
        let mut rest = p;
        let mut vals = vec![0.0; self.study.axes.len()];
        for (i, axis) in self.study.axes.iter().enumerate().rev() {
            let n = axis.values.len() as u64;
            vals[i] = axis.values[(rest % n) as usize];
            rest /= n;
        }
        vals
    }

    /// The system of design point `p` (no perturbation).
    pub fn point_system(&self, p: u64) -> System {
        self.point(p).0
    }

    /// The system and the scene of design point `p` (no perturbation): each axis value lands on
    /// its system key or on the scene's `F0`, `omega` or `r`.
    pub fn point(&self, p: u64) -> (System, Scene) {
        let mut sys = self.study.system;
        let mut scene = self.study.scene.clone();
        // The values of `point_values`, last axis first, without its vector (a run's only
        // allocation in planning); each axis sets its own key, so the order does not matter.
        let mut rest = p;
        for axis in self.study.axes.iter().rev() {
            let n = axis.values.len() as u64;
            let v = axis.values[(rest % n) as usize];
            rest /= n;
            if !sys.set(&axis.key, v) {
                scene.set(&axis.key, v);
            }
        }
        (sys, scene)
    }

    /// Run `(p, c)`.
    pub fn run(&self, p: u64, c: u32) -> RunSpec {
        let spec = match &self.study.scene {
            Scene::Random(r) => Case {
                dm: 0.0,
                dd: 0.0,
                noise_seed: r.draws_normals().then_some(u64::from(c)),
                ideal: false,
            },
            Scene::Free | Scene::Harmonic(_) => self.study.cases[c as usize],
        };
        let (mut system, scene) = self.point(p);
        system.m += spec.dm;
        system.d += spec.dd;
        RunSpec {
            point_id: p * self.n_cases() + u64::from(c),
            point: p,
            case: c,
            system,
            scene,
            spec,
        }
    }

    /// The noise stream of a run, `None` when the run has no noise.
    pub fn noise_stream(&self, run: &RunSpec) -> Option<NoiseStream> {
        match (self.study.noise, run.spec.noise_seed) {
            (Some(_), Some(seed)) => Some(NoiseStream::new(self.study.seed, seed, run.point)),
            _ => None,
        }
    }

    /// The load stream of a run of a random study: its realization's, the same at every design
    /// point (module doc); a record draws nothing from it.
    pub fn load_stream(&self, run: &RunSpec) -> RealizationStream {
        RealizationStream::new(self.study.seed, 0, u64::from(run.case))
    }

    /// A run of a harmonic study as one frequency of its curve
    /// ([`crate::orbits::curve::run_curve`]): its scene, design point and noise stream.
    pub fn curve_frequency(&self, run: &RunSpec) -> crate::orbits::curve::CurveFrequency {
        crate::orbits::curve::CurveFrequency {
            scene: run.scene.harmonic_or_default(),
            point: run.point,
            noise: self.noise_stream(run),
        }
    }

    /// Design points of chunk `k` (whole, or the one point a block belongs to).
    pub fn chunk_points(&self, k: u64) -> std::ops::Range<u64> {
        let b = self.blocks();
        if b > 1 {
            let p = (k / b).min(self.n_points());
            return p..(p + 1).min(self.n_points());
        }
        let per = self.study.run.chunk_points.max(1);
        let start = (k * per).min(self.n_points());
        start..((k + 1) * per).min(self.n_points())
    }
}
