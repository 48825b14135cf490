//! The random and record scenes on the event map of [`crate::sim::phase`] (impact law, chatter
//! and sticking, separation): the load interval by interval, each on a fresh clock, and the
//! run's observables.
//!
//! # A whole interval of free flight in one step
//! Most intervals of a run hold no event: no wall is reached and no extremum of `|x|` can beat
//! the largest so far. Such an interval is crossed in one step, outside the event loop: the end
//! state from the free part's propagator over `dt` (a 2 x 2 multiply,
//! [`crate::sim::linear::Propagator`]) plus the particular solution, after a check that cannot
//! pass when an event is in the interval. The check bounds each watched function `g` (the
//! displacement, the gap to each wall, whose inner mass is a cubic) by its cubic Hermite
//! interpolant from both ends: the interpolant lies in the convex hull of its Bézier points
//! `g0, g0 + dt g0'/3, g1 - dt g1'/3, g1`, and `|g - H| <= max |g''''| dt^4 / 384` with
//! `|g''''| = |x''''| <= B4` (the free part's energy bound, [`Oscillator::derivative_bounds`];
//! the particular part and the inner mass's cubic have no fourth derivative). When the hull with
//! that margin keeps `|x|` below the largest `|x|` so far (and so below the threshold, until the
//! first passage) and `y - x` off both walls, the interval has no event to report; otherwise the
//! event loop of [`crate::sim::phase`] takes it with the event finder of
//! [`crate::sim::driven`]. The result is the same motion either way, to rounding. A trace
//! (`trace_dt`) sends every interval through the event loop.
//!
//! Several units (model.md §14) cross the same way while every unit is free, each unit's gap
//! under the same test (its own line and clearance); while one is stuck on its wall the main
//! mass carries it, and the interval goes to the event loop. The event loop searches each free
//! unit's walls on a clone of the solver; a unit whose gap the same test keeps clear from the
//! event loop's point to the interval's end is not searched there
//! ([`SceneEvents::units_clear`]), so an interval with one unit near its wall costs about one
//! search, not `N`.
//!
//! Where `|x|` may pass the largest so far, the interval is still crossed in one step when `x`
//! is monotone on it and no first passage over the threshold is pending: the same hull test on
//! the velocity (its interpolant from `(v, x'')` at both ends, the margin
//! `|x^(5)| dt^4 / 384`) keeps `x'` off zero, so the event loop would find no extremum and
//! stop only at the interval's end. Its end state is then the closed form's, which is what
//! the event loop's limit event evaluates: the same bits as taking it there, one step instead
//! of an interval's set-up (on the seismic showcase's damped design about half of the
//! intervals that went to the event loop).
//!
//! Runs of one design cross their quiet intervals side by side ([`lanes`],
//! [`RandomRun::run_blocks`]): the same test and end state for up to four runs in the same
//! vector instructions, each run handed to its own crossing and the event loop for any other
//! interval; the same records, bit for bit.
//!
//! # Integrals
//! `int x^2` and `int a^2` over a whole interval of free flight are quadratic forms of the
//! interval's `u = (x0, v0, f0, f1)` (start state and the load at both ends, N on the main
//! mass): every motion is linear in `u`, so `int x^2 = u^T Q u` with `Q = int phi phi^T` over the
//! basis motions `phi`, integrated once per run setup by Gauss–Legendre
//! ([`crate::numeric::gauss_legendre_n`]). The run sums `u u^T` over its whole intervals (ten
//! sums, the Gram sum `G`) and adds `sum_ij Q_ij G_ij` for each integral at its end: the same
//! sum of forms, ten multiply-adds an interval instead of two forms. Against a compensated sum
//! of the intervals' forms both orders are off by about 6 rounding units at the median (23 at
//! the 99th percentile, over 1,000 realizations of the seismic showcase's damped design).
//!
//! Any other piece (between events, stuck) is first taken from its two ends: the equation of
//! motion's moments give both integrals from the states at the piece's start and end
//! ([`Ramp::squares_between`], [`super::motion`]), with no evaluation inside it, but with a
//! rounding that grows as the damping shrinks and the load steepens. So each such piece comes
//! with a first-order estimate of its rounding, and is kept only while the estimates of all the
//! pieces kept so far stay within `FROM_ENDS_BUDGET` (4,096 units) of the run's integral so far
//! (a lower bound of its final one): the run's `int x^2` and `int a^2` are then within that
//! share of the quadrature's, their RMS within half of it. Measured (a unit test, 720 RMS over
//! random loads, forces and a white-noise record, free and stuck): 0.8 units off the
//! quadrature at the median, 59 at worst; on the seismic showcase's design 95 % of the pieces
//! are taken from their ends. Without the budget, the white-noise record's RMS were off by up
//! to 45,000 units; an undamped structure (`c = 0`) takes none.
//!
//! The others are integrated on the phase's motion: its particular
//! part plus its free part. On a piece shorter than `TAYLOR_REACH / rho` (every piece of a load
//! interval at the showcase's `dt`) the free part is its Taylor polynomial from the piece's
//! start ([`Oscillator::taylor`]: a remainder below a thousandth of the closed form's rounding,
//! and no exponential, sine or cosine at the nodes) and the piece takes one 5-point
//! Gauss–Legendre rule (its error below a ten-thousandth of the integral's rounding there,
//! [`gauss_legendre_5`]); a longer piece takes the closed form and 8-point Gauss–Legendre on
//! sub-pieces at most 1/16 of the fastest period. All to rounding.

use super::hull::hull;
use super::intensity::{self, OwnIntensity};
use super::load::{GivenNormals, LoadBlock, Normals, Plan, Samples};
use super::motion::Ramp;
use super::{Input, IntensitySpec, RandomRecord, RandomScene};
use crate::model::System;
use crate::numeric::{gauss_legendre_5, gauss_legendre_n};
use crate::sim::driven::{Driven, DrivenPhase};
use crate::sim::linear::{Oscillator, Propagator, TAYLOR_REACH};
use crate::sim::phase::State;
use crate::sim::phase::{
    self, Event, EventMap, Hit, Phase, PhaseSolver, SceneEvents, Wall, Walls, Watch,
};
use crate::sim::probe::{NoProbe, Probe};
use crate::sim::record::Outcome;
use crate::sim::request::Request;
use crate::sim::settings::SolverSettings;

mod lanes;

pub(crate) use lanes::LANES;

/// The rounding budget of the pieces integrated from their ends: their estimates together at
/// most this share of the run's integral so far (module doc).
const FROM_ENDS_BUDGET: f64 = 4096.0 * f64::EPSILON;

/// Solver steps and impacts a run may take per load interval before its caps stop it (the
/// settings' caps hold for runs up to a few thousand intervals; longer runs get caps in
/// proportion, so only a run that chatters or steps without end is stopped).
pub const STEPS_PER_INTERVAL: u64 = 1_000;
pub const IMPACTS_PER_INTERVAL: u64 = 100;

/// One design's random or record scene, prepared once for all its realizations: the
/// oscillators, the propagator over `dt`, the quadratic forms of a whole interval and the load's
/// filter. [`RandomRun::run`] simulates one realization; pure.
#[derive(Clone, Debug)]
pub struct RandomRun {
    sys: System,
    settings: SolverSettings,
    scene: RandomScene,
    plan: Plan,
    free: Oscillator,
    pair: Oscillator,
    prop: Propagator,
    /// Upper triangles (row by row) of `Q` for `int x^2` and `int a^2` over a whole interval.
    qx: [f64; 10],
    qa: [f64; 10],
    segments: u64,
    tol_t: f64,
    /// Longest Gauss–Legendre piece (s).
    h_max: f64,
    /// The longest `rho h` of a piece integrated on its free part's Taylor polynomial
    /// ([`TAYLOR_REACH`]; 0 sends every piece to the closed form, as a test does).
    taylor_reach: f64,
    /// The Hermite interpolant's error per unit `B0 = sqrt(2 E / K)` of the free part's energy:
    /// `c4 dt^4 / 384`, with `B4 = c4 B0` ([`Oscillator::derivative_bounds`]: every bound there
    /// is a constant times the first).
    err4: f64,
    /// The same for the velocity's interpolant: `c5 dt^4 / 384`.
    err5: f64,
    /// Whether a whole interval on which `x` is monotone is crossed in one step although `|x|`
    /// may pass the largest so far ([`Realization::monotone`]; `false` sends it to the event
    /// loop, as a test does).
    monotone: bool,
    /// Whether whole intervals of several units, every unit free, are crossed in one step as
    /// one unit's are, and the event loop skips the search of a unit that surely stays clear of
    /// its walls ([`SceneEvents::units_clear`]); `false` sends every interval of several units
    /// to the event loop with every free unit searched, as a test does.
    units_cross: bool,
    /// Whether a piece's integrals may be taken from its ends within the rounding budget
    /// ([`Ramp::squares_between`], [`FROM_ENDS_BUDGET`]; `false` sends every piece to
    /// quadrature, as a test does).
    moments: bool,
    /// `dt / 3`: the Bézier points' step ([`hull`]).
    third: f64,
    /// The force on the free main mass per unit load (`-M` for ground acceleration, 1 for a
    /// force), `1 / K` and `M / K`.
    free_scale: f64,
    inv_k: f64,
    m_over_k: f64,
}

/// Runs one realization (`normals`; a record draws none) of `scene` on `sys`:
/// [`RandomRun::new`] then [`RandomRun::run`]. The caller has validated `sys`, `settings` and
/// `scene` ([`RandomScene::validate`]).
pub fn simulate_random<N: Normals, P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &RandomScene,
    normals: N,
    probe: &mut P,
) -> RandomRecord {
    RandomRun::new(sys, settings, scene).run(req, normals, probe)
}

impl RandomRun {
    /// Prepares `scene` on `sys` (about as long as a few dozen intervals of a run).
    pub fn new(sys: &System, settings: &SolverSettings, scene: &RandomScene) -> RandomRun {
        let segments = scene.segments();
        let settings = SolverSettings {
            max_impacts: settings
                .max_impacts
                .max(IMPACTS_PER_INTERVAL.saturating_mul(segments)),
            max_steps: settings
                .max_steps
                .max(STEPS_PER_INTERVAL.saturating_mul(segments)),
            ..*settings
        };
        let free = Oscillator::new(sys.M, sys.K, sys.C);
        let pair = Oscillator::new(sys.M + sys.m, sys.K, sys.C);
        let dt = scene.dt;
        let fastest = sys.omega().max(sys.C / sys.M);
        let h_max = (std::f64::consts::TAU / fastest / 16.0).min(dt);
        let contact = scene.input == Input::Force;
        let (qx, qa) = quadratic_forms(&free, dt, h_max, contact);
        // The bounds from (x, v) = (1, 0), where B0 = 1: the constants c_j of B_j = c_j B0.
        let c = free.derivative_bounds(1.0, 0.0);
        RandomRun {
            sys: *sys,
            settings,
            scene: scene.clone(),
            plan: Plan::new(scene),
            free,
            pair,
            prop: free.propagator(dt),
            qx,
            qa,
            segments,
            tol_t: settings.tol * sys.period(),
            h_max,
            taylor_reach: TAYLOR_REACH,
            err4: c[4] * dt.powi(4) / 384.0,
            err5: c[5] * dt.powi(4) / 384.0,
            monotone: true,
            units_cross: true,
            moments: true,
            third: dt / 3.0,
            free_scale: if contact { 1.0 } else { -sys.M },
            inv_k: 1.0 / sys.K,
            m_over_k: sys.M / sys.K,
        }
    }

    /// Standard normals one realization draws (0 for a record): a realization given as a slice
    /// ([`super::GivenNormals`]) needs this many.
    pub fn n_normals(&self) -> usize {
        self.plan.normals(self.segments) as usize
    }

    /// Load intervals of `dt` a run covers (the last one possibly shorter).
    pub fn segments(&self) -> u64 {
        self.segments
    }

    /// One realization. `req.trace_dt` sends a sampled trace to the probe (`peaks` and `t_end`
    /// are free decay's and are not used).
    pub fn run<N: Normals, P: Probe>(
        &self,
        req: &Request,
        normals: N,
        probe: &mut P,
    ) -> RandomRecord {
        self.run_scaled(req, normals, 1.0, probe)
    }

    /// [`RandomRun::run`] with every load value times `gain` (> 0): a stripe's or a capacity
    /// search's scaling of one motion ([`super::ida`]). `gain = 1` is `run`, bit for bit.
    ///
    /// The load's samples are drawn first, then run ([`RandomRun::run_block`]): the same bits as
    /// drawing each as the run reaches it, and cheaper (the crossing's loop then holds no call
    /// to the filter and the normals; BENCHMARKS.md, "Random realizations at half the cost").
    pub fn run_scaled<N: Normals, P: Probe>(
        &self,
        req: &Request,
        normals: N,
        gain: f64,
        probe: &mut P,
    ) -> RandomRecord {
        let block = self.load(normals);
        self.run_block(req, &block, gain, probe)
    }

    /// One realization's load samples at scale 1 ([`LoadBlock`]), drawn from `normals` as a run
    /// draws them, for [`RandomRun::run_block`] and [`RandomRun::own_intensity`] to share.
    pub fn load<N: Normals>(&self, normals: N) -> LoadBlock {
        let mut block = LoadBlock::default();
        self.load_into(normals, &mut block);
        block
    }

    /// [`RandomRun::load`] into `block`, reusing its storage.
    pub fn load_into<N: Normals>(&self, normals: N, block: &mut LoadBlock) {
        Samples::new(&self.plan, self.scene.dt, normals, 1.0)
            .fill(self.segments, &mut block.values);
    }

    /// [`RandomRun::run_scaled`] on the samples of `block` (made by [`RandomRun::load`] from
    /// the same normals): the same record, bit for bit, without drawing the load again.
    pub fn run_block<P: Probe>(
        &self,
        req: &Request,
        block: &LoadBlock,
        gain: f64,
        probe: &mut P,
    ) -> RandomRecord {
        let samples = self.block_samples(block, gain);
        self.run_samples(req, samples, probe, true)
    }

    /// The amplitude `max |x|` (m) of [`RandomRun::run_block`]'s record, bit for bit (NaN for a
    /// run that does not end `ok`), without the integrals `int x^2` and `int a^2` that only its
    /// other fields need: a capacity search's trial runs ([`super::ida`]) read the amplitude
    /// alone. The integrals never act on the motion, so every event and extremum is the same.
    pub fn amplitude_block(&self, req: &Request, block: &LoadBlock, gain: f64) -> f64 {
        let samples = self.block_samples(block, gain);
        self.run_samples(req, samples, &mut NoProbe, false)
            .amplitude
    }

    /// The amplitude of [`RandomRun::run`]'s record from `normals`, bit for bit, without the
    /// integrals ([`RandomRun::amplitude_block`]): subset simulation's runs read nothing else.
    pub fn amplitude<N: Normals>(&self, req: &Request, normals: N) -> f64 {
        self.amplitude_block(req, &self.load(normals), 1.0)
    }

    /// PGA and `Sa(period, 5 %)` (g) of the motion `block` at scale 1: the same bits as
    /// [`super::own_intensity`] of the normals that made it.
    pub fn own_intensity(&self, period: f64, block: &LoadBlock) -> OwnIntensity {
        let samples = self.block_samples(block, 1.0);
        intensity::of_samples(&self.scene, period, samples)
    }

    /// A motion (its samples `block` at scale 1) at the stripe `im` of the intensity measure
    /// `spec`: its own PGA and Sa ([`RandomRun::own_intensity`]) and the gain that scales it to
    /// the stripe, `im / own` (1 without a stripe or for a motion whose own value is 0). What the
    /// sweep runs a stripe's realization at, and subset simulation each of its samples.
    pub fn at_stripe(
        &self,
        spec: &IntensitySpec,
        im: Option<f64>,
        block: &LoadBlock,
    ) -> (OwnIntensity, f64) {
        let own = self.own_intensity(spec.period, block);
        let i0 = own.of(spec.measure);
        let gain = match im {
            Some(x) if i0 > 0.0 => x / i0,
            _ => 1.0,
        };
        (own, gain)
    }

    /// The load of `block` (made by [`RandomRun::load`]) times `gain`, interval by interval.
    fn block_samples<'b>(
        &'b self,
        block: &'b LoadBlock,
        gain: f64,
    ) -> Samples<'b, GivenNormals<'b>> {
        Samples::from_block(
            &self.plan,
            self.scene.dt,
            block,
            GivenNormals::new(&[]),
            gain,
        )
    }

    /// One run of `samples`; `integrals`: whether to integrate `x^2` and `a^2` (the record's
    /// RMS fields; without them those fields are 0 and nothing else changes).
    fn run_samples<N: Normals, P: Probe>(
        &self,
        req: &Request,
        samples: Samples<'_, N>,
        probe: &mut P,
        integrals: bool,
    ) -> RandomRecord {
        let (mut scene, mut solver) = self.start(req, samples, probe, integrals);
        let load = scene.cross();
        scene.begin_interval(&mut solver, load);
        let outcome = phase::run(&mut scene, &mut solver);
        scene.finish(outcome, &solver)
    }

    /// A run of `samples` at rest before its first interval: its realization and its solver
    /// ([`RandomRun::run_samples`], and each run of [`lanes`]).
    fn start<'a, N: Normals, P: Probe>(
        &'a self,
        req: &'a Request,
        samples: Samples<'a, N>,
        probe: &'a mut P,
        integrals: bool,
    ) -> (Realization<'a, N, P>, DrivenPhase<Ramp>) {
        let free = Ramp::new(self.free, 0.0, 0.0, self.scene.dt, (0.0, 0.0), false);
        let solver = DrivenPhase::new(&free, self.tol_t, self.settings.max_steps);
        let mut scene = Realization::new(self, req, samples, probe, free);
        scene.integrals = integrals;
        (scene, solver)
    }
}

/// The quadratic forms of `int x^2` and `int a^2` (absolute acceleration) over a whole interval
/// of `dt` of the free main mass `free`, in `u = (x0, v0, f0, f1)` (module doc). `contact`: the
/// load is a force on the main mass (it enters the acceleration).
fn quadratic_forms(
    free: &Oscillator,
    dt: f64,
    h_max: f64,
    contact: bool,
) -> ([f64; 10], [f64; 10]) {
    let basis: [Ramp; 4] = [
        Ramp::new(*free, 0.0, 0.0, dt, (0.0, 0.0), contact),
        Ramp::new(*free, 0.0, 0.0, dt, (0.0, 0.0), contact),
        Ramp::new(*free, 1.0, -1.0 / dt, dt, (0.0, 0.0), contact),
        Ramp::new(*free, 0.0, 1.0 / dt, dt, (0.0, 0.0), contact),
    ];
    let starts: [(f64, f64); 4] = [(1.0, 0.0), (0.0, 1.0), (0.0, 0.0), (0.0, 0.0)];
    let free_parts: Vec<(f64, f64)> = basis
        .iter()
        .zip(starts)
        .map(|(r, (x, v))| {
            let (h, g, _) = r.start(0.0, x, v);
            (h, g)
        })
        .collect();
    let sums = gauss_legendre_n(0.0, dt, h_max, |t| {
        let mut x = [0.0; 4];
        let mut a = [0.0; 4];
        for i in 0..4 {
            let (h, g) = free_parts[i];
            let jet = basis[i].jet(0.0, h, g, t);
            x[i] = jet.x;
            a[i] = basis[i].absolute_accel(t, jet.x, jet.v);
        }
        let mut out = [0.0; 20];
        let mut n = 0;
        for i in 0..4 {
            for j in i..4 {
                out[n] = x[i] * x[j];
                out[n + 10] = a[i] * a[j];
                n += 1;
            }
        }
        out
    });
    let mut qx = [0.0; 10];
    let mut qa = [0.0; 10];
    qx.copy_from_slice(&sums[..10]);
    qa.copy_from_slice(&sums[10..]);
    (qx, qa)
}

/// `sum_k u_k^T Q u_k = sum_ij Q_ij G_ij` from the upper triangles of `Q` and of the Gram sum
/// `G = sum_k u_k u_k^T` (module doc).
#[inline]
fn contract(q: &[f64; 10], g: &[f64; 10]) -> f64 {
    let diag = q[0] * g[0] + q[4] * g[4] + q[7] * g[7] + q[9] * g[9];
    let off = q[1] * g[1] + q[2] * g[2] + q[3] * g[3] + q[5] * g[5] + q[6] * g[6] + q[8] * g[8];
    diag + 2.0 * off
}

/// One realization on the event map.
struct Realization<'a, N: Normals, P: Probe> {
    /// Its clock `map.t` is the time since the current interval's start `k dt`.
    map: EventMap<'a, Ramp>,
    run: &'a RandomRun,
    req: &'a Request,
    samples: Samples<'a, N>,
    probe: &'a mut P,
    /// The current interval, its length and its start state.
    k: u64,
    len: f64,
    start: (f64, f64),
    /// The interval so far is one phase of free flight from its start (its integrals are the
    /// quadratic forms).
    clean: bool,
    /// Start of the piece not yet integrated, and of the solver's phase (local times).
    piece: f64,
    phase_start: f64,
    last: Event,
    amplitude: f64,
    t_peak: f64,
    /// Intervals crossed in one step (each counts as a solver step).
    crossed: u64,
    int_x2: f64,
    int_a2: f64,
    first_passage: Option<f64>,
    energy_impact: f64,
    next_trace: u64,
    /// Whether `int_x2` and `int_a2` are integrated ([`RandomRun::run_samples`]).
    integrals: bool,
    /// The Gram sum `sum u u^T` of the whole intervals of free flight, contracted with the
    /// quadratic forms at the end.
    gram: [f64; 10],
    /// The rounding estimates of the pieces integrated from their ends so far.
    err_x2: f64,
    err_a2: f64,
    /// The run's integrals as last read (a lower bound of today's).
    so_far: [f64; 2],
    /// Run among lanes ([`lanes`]): at an interval's end the event loop hands the crossing back
    /// to the lanes (`yielded`) instead of crossing here.
    yield_cross: bool,
    yielded: bool,
}

impl<'a, N: Normals, P: Probe> Realization<'a, N, P> {
    fn new(
        run: &'a RandomRun,
        req: &'a Request,
        samples: Samples<'a, N>,
        probe: &'a mut P,
        free: Ramp,
    ) -> Self {
        let map = EventMap::new(&run.sys, &run.settings, free, free);
        let x0 = map.s.x;
        let first_passage = run
            .scene
            .threshold
            .and_then(|b| (x0.abs() > b).then_some(0.0));
        Realization {
            map,
            run,
            req,
            samples,
            probe,
            k: 0,
            len: run.scene.dt,
            start: (x0, 0.0),
            clean: false,
            piece: 0.0,
            phase_start: 0.0,
            last: Event::Limit,
            amplitude: x0.abs(),
            t_peak: 0.0,
            crossed: 0,
            int_x2: 0.0,
            int_a2: 0.0,
            first_passage,
            energy_impact: 0.0,
            next_trace: 0,
            integrals: true,
            gram: [0.0; 10],
            err_x2: 0.0,
            err_a2: 0.0,
            so_far: [0.0; 2],
            yield_cross: false,
            yielded: false,
        }
    }

    /// The absolute time of local time `t`.
    fn abs(&self, t: f64) -> f64 {
        self.k as f64 * self.run.scene.dt + t
    }

    /// Crosses whole intervals of free flight in one step each from interval `k` on while no
    /// event can be in them (module doc); returns the load of the first one that might hold an
    /// event (or the last interval, or any interval under a trace), where the event loop goes
    /// on.
    fn cross(&mut self) -> (f64, f64) {
        // Every unit free: with several units (model.md §14) the phase is `Free` only while no
        // unit is stuck, and the main mass then carries its own mass alone. (A crossed interval
        // changes none of these.)
        let eligible = self.map.phase == Phase::Free
            && self.req.trace_dt.is_none()
            && (!self.map.several()
                || (self.run.units_cross && self.map.carried == self.map.sys.M));
        loop {
            let load = self.samples.next();
            if !(eligible && self.k + 1 < self.run.segments && self.whole(load)) {
                return load;
            }
            self.k += 1;
            self.crossed += 1;
        }
    }

    /// Moves the map over the whole interval `k` under the load `(q0, qs)` when no event can be
    /// in it (module doc), adding its integrals; `false`, and nothing moved, when one might.
    fn whole(&mut self, (q0, qs): (f64, f64)) -> bool {
        let run = self.run;
        let sys = &run.sys;
        let dt = run.scene.dt;
        let (f0, s) = (run.free_scale * q0, run.free_scale * qs);
        let p1 = s * run.inv_k;
        let p0 = (f0 - sys.C * p1) * run.inv_k;
        let st = self.map.s;
        let (h0, g0) = (st.x - p0, st.v - p1);
        let (xh, vh) = run.prop.apply(h0, g0);
        let (x1, v1) = (xh + (p0 + p1 * dt), vh + p1);
        // B0 = sqrt(2 E / K) of the free part, whose energy never increases.
        let b0 = (h0 * h0 + run.m_over_k * g0 * g0).sqrt();
        let err = run.err4 * b0;
        let third = run.third;
        let (lo, hi) = hull(st.x, st.v, x1, v1, third);
        // (A NaN bound is not below; `hi` and `lo` are both NaN or neither.)
        let reach = if hi > -lo { hi } else { -lo };
        let top = reach + err;
        let below = top < self.amplitude;
        if !(below
            || (run.monotone && self.monotone(top, (st.v, v1), (h0, g0), (xh, vh), (b0, p1))))
        {
            return false;
        }
        // Where `|x|` may pass the largest so far, the end state is the closed form's, as the
        // event loop would have taken it (its limit event: the same bits with one unit);
        // elsewhere the propagator's.
        let several = self.map.several();
        let (x1, v1) = if below {
            (x1, v1)
        } else {
            let e = run.free.eval_fast(h0, g0, dt);
            (e.x + (p0 + p1 * dt), e.v + p1)
        };
        let (ya, yj) = match run.scene.input {
            Input::Base => (-q0, -qs),
            Input::Force => (0.0, 0.0),
        };
        let line = |y0: f64, w: f64, half_d: f64| Walls {
            t0: 0.0,
            y0,
            w,
            half_d,
            ya,
            yj,
            ya_max: 0.0,
        };
        let ends = ((st.x, st.v), (x1, v1));
        let (y1, w1) = if several {
            // Every unit clear of its walls, then each moved along its line (unit 0 mirrored in
            // the map's state, as the event loop leaves it).
            let clear = self.map.units.iter().all(|u| {
                self.line_clear(&line(u.y, u.w, u.half_d), ends, (dt, third), err)
                    .is_some()
            });
            if !clear {
                return false;
            }
            // (Each line's end evaluated again: a few operations, cheaper than keeping up to
            // 64 of them from the test.)
            for u in &mut self.map.units {
                (u.y, u.w, _, _) = line(u.y, u.w, u.half_d).at(dt);
            }
            (self.map.units[0].y, self.map.units[0].w)
        } else if sys.m > 0.0 {
            match self.line_clear(&line(st.y, st.w, 0.5 * sys.d), ends, (dt, third), err) {
                Some(end) => end,
                None => return false,
            }
        } else {
            // A massless inner mass is carried along where it started in the cavity.
            (x1 + (sys.y0 - sys.x0), v1)
        };
        if self.integrals {
            let u = [st.x, st.v, f0, f0 + s * dt];
            self.gram_add(u);
        }
        self.map.s = State {
            x: x1,
            v: v1,
            y: y1,
            w: w1,
        };
        true
    }

    /// The end `(y1, w1)` of the inner mass's line `walls` at `t1` (local time) when its gap to
    /// the main mass (from `(x0, v0)` at `walls.t0` to `(x1, v1)` at `t1`, at most an interval
    /// apart) stays inside both walls: the gap's Hermite hull ([`hull`], `third` a third of the
    /// span) with the margin `err` (the main mass's fourth-derivative bound over an interval;
    /// the inner mass's line is a cubic) and `1e-12` of the sizes for the rounding. `None` when
    /// a wall might be reached. (Inlined: the crossing's loop calls it at every interval; left
    /// to the compiler with a third caller, the one-unit seismic study took 1.3 times as long.)
    #[inline(always)]
    fn line_clear(
        &self,
        walls: &Walls,
        ((x0, v0), (x1, v1)): ((f64, f64), (f64, f64)),
        (t1, third): (f64, f64),
        err: f64,
    ) -> Option<(f64, f64)> {
        let (y1, w1, _, _) = walls.at(t1);
        let (lo, hi) = hull(walls.y0 - x0, walls.w - v0, y1 - x1, w1 - v1, third);
        let scale = walls.half_d + x0.abs() + x1.abs() + walls.y0.abs() + y1.abs();
        let margin = err + 1e-12 * scale;
        let inside = hi + margin < walls.half_d && lo - margin > -walls.half_d;
        inside.then_some((y1, w1))
    }

    /// Whether `x` is monotone over a whole interval whose `|x|` may pass the largest so far
    /// (module doc), so that it holds no extremum to report: `x'` keeps its sign, shown by its
    /// own cubic Hermite interpolant from `(v0, a0)` to `(v1, a1)` (the hull of its Bézier
    /// points, [`hull`]) with the margin `max |x^(5)| dt^4 / 384` (`<= err5 B0`) and `1e-12` of
    /// its sizes for the rounding; and no first passage over the threshold is pending that
    /// `top` (a bound on `|x|` over the interval) does not rule out. `(h0, g0)` and `(xh, vh)`
    /// are the free part at both ends, `p1` the particular velocity.
    fn monotone(
        &self,
        top: f64,
        (v0, v1): (f64, f64),
        (h0, g0): (f64, f64),
        (xh, vh): (f64, f64),
        (b0, p1): (f64, f64),
    ) -> bool {
        let run = self.run;
        let pending = self.first_passage.is_none()
            && run
                .scene
                .threshold
                .is_some_and(|b| top >= b || top.is_nan());
        if pending {
            return false;
        }
        // x'' is the free part's (the particular part is linear in t).
        let (a0, a1) = (run.free.accel(h0, g0), run.free.accel(xh, vh));
        let (lo, hi) = hull(v0, a0, v1, a1, run.third);
        let margin = run.err5 * b0 + 1e-12 * (run.free.wn * b0 + p1.abs());
        lo - margin > 0.0 || hi + margin < 0.0
    }

    /// Starts interval `k` in the event loop: its load `(q0, qs)`, the motions of the free main
    /// mass and of the stuck pair, a fresh clock.
    fn begin_interval(&mut self, solver: &mut DrivenPhase<Ramp>, (q0, qs): (f64, f64)) {
        let run = self.run;
        let (sys, dt) = (&run.sys, run.scene.dt);
        self.len = if self.k + 1 < run.segments {
            dt
        } else {
            let rest = run.scene.duration - self.k as f64 * dt;
            if (rest - dt).abs() <= 1e-9 * dt {
                dt
            } else {
                rest.clamp(0.0, dt)
            }
        };
        // The force on the free main mass and on the pair, and the free inner mass's acceleration.
        let (free_scale, pair_scale, inner, contact) = match run.scene.input {
            Input::Base => (-sys.M, -(sys.M + sys.m), (-q0, -qs), false),
            Input::Force => (1.0, 1.0, (0.0, 0.0), true),
        };
        let motion =
            |osc, scale: f64| Ramp::new(osc, scale * q0, scale * qs, self.len, inner, contact);
        self.map.free = motion(run.free, free_scale);
        self.map.pair = motion(run.pair, pair_scale);
        // With several units the main mass carries its own and the stuck units' mass under the
        // interval's load.
        self.map.carry_anew();
        self.map.t = 0.0;
        self.piece = 0.0;
        self.phase_start = 0.0;
        self.start = (self.map.s.x, self.map.s.v);
        self.clean = self.map.phase == Phase::Free && self.len == dt && !self.map.several();
        self.map.v_side = self.map.v_sign();
        self.map.begin(solver);
    }

    /// Adds a whole interval's `u u^T` to the Gram sum (its upper triangle, row by row).
    #[inline]
    fn gram_add(&mut self, [a, b, c, d]: [f64; 4]) {
        let g = &mut self.gram;
        g[0] += a * a;
        g[1] += a * b;
        g[2] += a * c;
        g[3] += a * d;
        g[4] += b * b;
        g[5] += b * c;
        g[6] += b * d;
        g[7] += c * c;
        g[8] += c * d;
        g[9] += d * d;
    }

    fn candidate(&mut self, x: f64) {
        if x.abs() > self.amplitude {
            self.amplitude = x.abs();
            self.t_peak = self.abs(self.map.t);
        }
    }

    /// Adds the piece from `self.piece` to `t` to the integrals (module doc).
    fn integrate(&mut self, solver: &DrivenPhase<Ramp>, t: f64) {
        let dt = self.run.scene.dt;
        if self.clean && self.piece == 0.0 && t == dt {
            let f = &self.map.free;
            let u = [self.start.0, self.start.1, f.f0, f.f0 + f.s * dt];
            self.gram_add(u);
        } else if t > self.piece {
            let [x2, a2] = match self.ends_integral(solver, t) {
                Some(squares) => squares,
                None => self.quadrature(solver, t),
            };
            self.int_x2 += x2;
            self.int_a2 += a2;
        }
        self.piece = t;
    }

    /// The piece from `self.piece` to `t` integrated from its two ends
    /// ([`Ramp::squares_between`]) when the rounding estimates of every piece so taken, this
    /// one's included, stay within [`FROM_ENDS_BUDGET`] of the run's integral so far (module
    /// doc); `None` otherwise.
    fn ends_integral(&mut self, solver: &DrivenPhase<Ramp>, t: f64) -> Option<[f64; 2]> {
        let (motion, t_phase, h0, g0) = solver.phase();
        if !(self.run.moments && motion.osc.c > 0.0) {
            return None;
        }
        // Its start is the phase's, its end the solver's.
        let t0 = self.piece;
        let start = if t_phase == t0 {
            (t0, h0 + (motion.p0 + motion.p1 * t0), g0 + motion.p1)
        } else {
            let jet = solver.at(t0);
            (t0, jet.x, jet.v)
        };
        let end = match solver.state() {
            (te, x, v) if te == t => (t, x, v),
            _ => {
                let jet = solver.at(t);
                (t, jet.x, jet.v)
            }
        };
        let sq = motion.squares_between(start, end);
        let (err_x2, err_a2) = (self.err_x2 + sq.err_x2, self.err_a2 + sq.err_a2);
        // The run's integrals so far only grow: a total read earlier is a lower bound, read
        // again (ten multiply-adds each) only when it no longer suffices.
        let within = |so_far: [f64; 2]| {
            err_x2 <= FROM_ENDS_BUDGET * (so_far[0] + sq.x2)
                && err_a2 <= FROM_ENDS_BUDGET * (so_far[1] + sq.a2)
        };
        let mut ok = within(self.so_far);
        if !ok {
            let run = self.run;
            self.so_far = [
                self.int_x2 + contract(&run.qx, &self.gram),
                self.int_a2 + contract(&run.qa, &self.gram),
            ];
            ok = within(self.so_far);
        }
        if ok {
            (self.err_x2, self.err_a2) = (err_x2, err_a2);
        }
        ok.then_some([sq.x2, sq.a2])
    }

    /// The piece from `self.piece` to `t` integrated on the phase's motion by Gauss–Legendre
    /// (module doc).
    fn quadrature(&self, solver: &DrivenPhase<Ramp>, t: f64) -> [f64; 2] {
        let motion = *solver.phase().0;
        let t0 = self.piece;
        let squares = |tt: f64, x: f64, v: f64| {
            let a = motion.absolute_accel(tt, x, v);
            [x * x, a * a]
        };
        if (t - t0) * motion.osc.derivative_rate() <= self.run.taylor_reach {
            // The free part as its Taylor polynomial from the piece's start, by 5-point
            // Gauss–Legendre: within this reach its error is far below rounding (module doc).
            let start = solver.at(t0);
            let poly = motion.osc.taylor(start.xh, start.vh);
            gauss_legendre_5(t0, t, |tt| {
                let (xh, vh) = poly.at(tt - t0);
                squares(tt, xh + (motion.p0 + motion.p1 * tt), vh + motion.p1)
            })
        } else {
            gauss_legendre_n(t0, t, self.run.h_max, |tt| {
                let jet = solver.at(tt);
                squares(tt, jet.x, jet.v)
            })
        }
    }

    /// The first passage of `|x|` over the threshold, when it happened since the solver's
    /// phase began: `|x|` was at most the threshold there and no extremum above it came before
    /// now (it would have been an event), so `|x| - b` changes sign once; bisection to the
    /// event tolerance.
    fn passage(&mut self, solver: &DrivenPhase<Ramp>) {
        let (Some(b), None) = (self.run.scene.threshold, self.first_passage) else {
            return;
        };
        if self.map.s.x.abs() <= b {
            return;
        }
        let (mut lo, mut hi) = (self.phase_start, self.map.t);
        while hi - lo > self.run.tol_t {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if solver.at(mid).x.abs() > b {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        self.first_passage = Some(self.abs(hi));
    }

    /// The record of a run that ended with `outcome`, its event loop's `solver` (each crossed
    /// interval counts as a step).
    fn finish(self, outcome: Outcome, solver: &DrivenPhase<Ramp>) -> RandomRecord {
        let steps = solver.steps() + self.crossed;
        let ok = outcome == Outcome::Ok;
        let nan = f64::NAN;
        let duration = self.run.scene.duration;
        let keep = |v: f64| if ok { v } else { nan };
        RandomRecord {
            outcome,
            amplitude: keep(self.amplitude),
            t_peak: keep(self.t_peak),
            rms_x: keep(((self.int_x2 + contract(&self.run.qx, &self.gram)) / duration).sqrt()),
            rms_acc: keep(((self.int_a2 + contract(&self.run.qa, &self.gram)) / duration).sqrt()),
            first_passage_time: self.first_passage,
            impacts: self.map.impacts,
            sticks: self.map.sticks,
            energy_impact: keep(self.energy_impact),
            samples: self.k + 1,
            t_stop: self.abs(self.map.t),
            steps,
        }
    }
}

impl<'a, N: Normals, P: Probe> SceneEvents<'a, DrivenPhase<Ramp>> for Realization<'a, N, P> {
    fn map(&self) -> &EventMap<'a, Ramp> {
        &self.map
    }

    fn map_mut(&mut self) -> &mut EventMap<'a, Ramp> {
        &mut self.map
    }

    fn watch(&self) -> Watch {
        let mut t_limit = self.len;
        if let Some(dt) = self.req.trace_dt {
            t_limit = t_limit.min(self.next_trace as f64 * dt - self.abs(0.0));
        }
        let (walls, sep_side) = match self.map.phase {
            // `m = 0` is the structure alone: a massless inner mass cannot act on it.
            Phase::Free if self.map.sys.m == 0.0 => (None, None),
            _ => self.map.contact(),
        };
        Watch {
            walls,
            x_side: None,
            v_side: Some(self.map.v_side),
            x_floor: self.amplitude,
            sep_side,
            t_limit: t_limit.max(self.map.t),
        }
    }

    fn arrived(&mut self, _solver: &DrivenPhase<Ramp>, ev: Event) {
        self.last = ev;
    }

    /// Integrates a piece that ends here (a phase's end, the interval's end), looks for the
    /// first passage. (The probe's `energy` is reported after impacts only.)
    fn synced(&mut self, solver: &DrivenPhase<Ramp>) {
        let t = self.map.t;
        let ends = match self.last {
            Event::Wall(_) | Event::Separation => true,
            Event::Limit => t >= self.len,
            _ => false,
        };
        if ends && self.integrals {
            self.integrate(solver, t);
        }
        self.passage(solver);
    }

    fn at_wall(&mut self) {
        self.candidate(self.map.s.x);
    }

    fn impacted(&mut self, hit: &Hit) {
        let sys = self.map.sys;
        let s = &self.map.s;
        let (e_before, e_after) = if self.map.several() {
            // One impact of several units: booked once, at its first unit.
            let after = self.map.energy();
            (hit.lead.unwrap_or(after), after)
        } else {
            (
                sys.energy(hit.before.x, hit.before.v, hit.before.w),
                sys.energy(s.x, s.v, s.w),
            )
        };
        self.energy_impact += e_before - e_after;
        let now = self.abs(self.map.t);
        self.probe
            .impact_of(now, hit.unit, hit.wall, &hit.before, &hit.after);
        if hit.stuck {
            self.probe.stick(now, hit.wall, &self.map.s);
        }
        self.probe.energy(now, e_after);
        self.clean = false;
        self.phase_start = self.map.t;
    }

    fn separated(&mut self, wall: Wall) {
        let now = self.abs(self.map.t);
        self.probe.separate(now, wall, &self.map.s);
        self.clean = false;
        self.phase_start = self.map.t;
    }

    fn v_zero(&mut self) {
        self.candidate(self.map.s.x);
    }

    /// The free units whose gap stays inside their walls until the watch's limit (at most the
    /// interval's end), by the crossing's test ([`Realization::line_clear`]) from the map's
    /// state now: their searches are skipped. Only while no unit is stuck (the main mass then
    /// moves as the free oscillator whose bounds the margin takes).
    fn units_clear(&self, watch: &Watch) -> u64 {
        let (map, run) = (&self.map, self.run);
        if !run.units_cross || map.carried != map.sys.M || map.units.len() > 64 {
            return 0;
        }
        let (t, t1) = (map.t, watch.t_limit);
        if t1 <= t || t1.is_nan() {
            return 0;
        }
        let s = map.s;
        let (h, g, _) = map.carrying.start(t, s.x, s.v);
        let end = map.carrying.jet(t, h, g, t1);
        let err = run.err4 * (h * h + run.m_over_k * g * g).sqrt();
        let ends = ((s.x, s.v), (end.x, end.v));
        let span = (t1, (t1 - t) / 3.0);
        let mut clear = 0u64;
        for (i, u) in map.units.iter().enumerate() {
            if u.stuck.is_some() {
                continue;
            }
            let walls = map.line_of(u);
            if self.line_clear(&walls, ends, span, err).is_some() {
                clear |= 1 << i;
            }
        }
        clear
    }

    fn limit(&mut self, solver: &mut DrivenPhase<Ramp>) -> Option<Outcome> {
        if let Some(dt) = self.req.trace_dt
            && self.next_trace as f64 * dt - self.abs(0.0) <= self.map.t
        {
            let now = self.abs(self.map.t);
            self.probe.sample(now, &self.map.s);
            self.next_trace += 1;
        }
        if self.map.t >= self.len {
            if self.k + 1 >= self.run.segments {
                self.candidate(self.map.s.x);
                return Some(Outcome::Ok);
            }
            self.k += 1;
            if self.yield_cross {
                self.yielded = true;
                return Some(Outcome::Ok);
            }
            let load = self.cross();
            self.begin_interval(solver, load);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::sim::random::{
        Envelope, Excitation, IntensitySpec, Measure, RandomLoad, RealizationStream, Recorded,
        Spectrum, own_intensity,
    };

    pub(super) fn seismic() -> RandomScene {
        RandomScene {
            input: Input::Base,
            excitation: Excitation::Random(RandomLoad {
                spectrum: Spectrum::CloughPenzien {
                    omega_g: 15.708,
                    zeta_g: 0.6,
                    // The showcase's, a tenth of omega_g (not pi / 2).
                    #[allow(clippy::approx_constant)]
                    omega_f: 1.5708,
                    zeta_f: 0.6,
                },
                S0: 0.005,
                envelope: Some(Envelope {
                    t1: 2.0,
                    t2: 12.0,
                    c: 0.3,
                }),
            }),
            dt: 0.005,
            duration: 5.0,
            threshold: Some(0.01),
            intensity: Some(IntensitySpec {
                measure: Measure::Sa,
                period: 0.4,
                ida_tol: 0.01,
                ida_max: 10.0,
            }),
            im: Some(0.2),
        }
    }

    pub(super) fn damped() -> System {
        System {
            M: 1.0,
            m: 0.1,
            K: 246.7,
            C: 0.628,
            d: 0.005,
            e: 0.6,
            x0: 0.0,
            v0: 0.0,
            y0: 0.0,
            w0: 0.0,
            units: 1.0,
            d_spread: 0.0,
            table: None,
        }
    }

    /// The seismic scene with a record of 700 samples (its end inside the run) for its load.
    pub(super) fn record() -> RandomScene {
        RandomScene {
            excitation: Excitation::Record(Recorded {
                values: (0..700)
                    .map(|k| ((k * 7919) % 101) as f64 * 0.01 - 0.5)
                    .collect(),
                scale: 1.3,
            }),
            ..seismic()
        }
    }

    #[test]
    fn a_motion_drawn_once_runs_as_if_drawn_for_each_run() {
        // Issue 69: the intensity and every run of one motion from its samples drawn once are
        // the bits of drawing them again for each, at scale 1 and at a stripe's and a capacity
        // search's gains, with an envelope (its table) and without, for a random load and a
        // record (its end inside the run).
        let mut flat = seismic();
        if let Excitation::Random(r) = &mut flat.excitation {
            r.envelope = None;
        }
        let settings = SolverSettings::default();
        let req = Request::default();
        for scene in [seismic(), flat, record()] {
            let run = RandomRun::new(&damped(), &settings, &scene);
            for r in 0..6 {
                let stream = || RealizationStream::new(3, 0, r);
                let block = run.load(stream());
                let a = run.own_intensity(0.4, &block);
                let b = own_intensity(&scene, 0.4, stream());
                assert_eq!(
                    (a.pga.to_bits(), a.sa.to_bits()),
                    (b.pga.to_bits(), b.sa.to_bits())
                );
                for gain in [1.0, 0.2 / a.sa, 3.7] {
                    let x = run.run_block(&req, &block, gain, &mut NoProbe);
                    // A capacity search's trial: the amplitude alone, the same bits.
                    let amplitude = run.amplitude_block(&req, &block, gain);
                    assert_eq!(amplitude.to_bits(), x.amplitude.to_bits());
                    // Each sample drawn as the run reaches it: the same bits.
                    let streamed = |integrals| {
                        let samples = Samples::new(&run.plan, run.scene.dt, stream(), gain);
                        run.run_samples(&req, samples, &mut NoProbe, integrals)
                    };
                    if gain == 1.0 {
                        let plain = run.amplitude(&req, stream());
                        assert_eq!(plain.to_bits(), x.amplitude.to_bits());
                        assert_eq!(streamed(false).amplitude.to_bits(), x.amplitude.to_bits());
                    }
                    assert_eq!(
                        format!("{x:?}"),
                        format!("{:?}", run.run_scaled(&req, stream(), gain, &mut NoProbe))
                    );
                    let y = streamed(true);
                    assert_eq!(format!("{x:?}"), format!("{y:?}"));
                    assert_eq!(x.rms_x.to_bits(), y.rms_x.to_bits());
                    assert_eq!(x.amplitude.to_bits(), y.amplitude.to_bits());
                }
            }
        }
    }

    /// Runs each of `designs` (`(m, d)`) under three 20-s scenes (ground acceleration and a force
    /// from the random load, a record) at gains 1, 4 and 12 on 10 realizations of stream `seed`,
    /// by `first` and `other` of its `RandomRun`, and hands both records to `check`.
    fn against(
        designs: &[(f64, f64)],
        seed: u64,
        (first, other): (
            impl Fn(&RandomRun) -> RandomRun,
            impl Fn(&RandomRun) -> RandomRun,
        ),
        mut check: impl FnMut(&RandomRecord, &RandomRecord),
    ) {
        let force = RandomScene {
            input: Input::Force,
            ..seismic()
        };
        let settings = SolverSettings::default();
        let req = Request::default();
        let long = |s: RandomScene| RandomScene {
            duration: 20.0,
            ..s
        };
        for scene in [seismic(), force, record()].map(long) {
            for &(m, d) in designs {
                let run = RandomRun::new(&System { m, d, ..damped() }, &settings, &scene);
                let second = other(&run);
                let run = first(&run);
                for r in 0..10 {
                    let block = run.load(RealizationStream::new(seed, 0, r));
                    for gain in [1.0, 4.0, 12.0] {
                        let x = run.run_block(&req, &block, gain, &mut NoProbe);
                        let y = second.run_block(&req, &block, gain, &mut NoProbe);
                        check(&x, &y);
                    }
                }
            }
        }
    }

    #[test]
    fn pieces_on_the_taylor_polynomial_are_the_closed_forms_to_rounding() {
        // Issue 69: the pieces between events integrate `x^2` and `A^2` on the free part's
        // Taylor polynomial by one 5-point rule; against the closed form at every node of the
        // 8-point rule (what every piece took before), the same motion bit for bit and the
        // run's RMS within a few rounding units, under ground acceleration and a force, a random
        // load and a record, pieces free and stuck. (Both by quadrature: the pieces' integrals
        // from their ends off.)
        let (mut worst, mut impacts) = (0.0f64, 0u64);
        let designs = [(0.1, 0.005), (0.3, 0.002), (0.05, 0.02)];
        let taylor = |run: &RandomRun| RandomRun {
            moments: false,
            ..run.clone()
        };
        let closed = |run: &RandomRun| RandomRun {
            taylor_reach: 0.0,
            ..taylor(run)
        };
        against(&designs, 5, (taylor, closed), |x, y| {
            let motion = |r: &RandomRecord| {
                (
                    r.amplitude.to_bits(),
                    r.t_peak.to_bits(),
                    r.impacts,
                    r.steps,
                )
            };
            assert_eq!(motion(x), motion(y));
            impacts += x.impacts;
            for (a, b) in [(x.rms_x, y.rms_x), (x.rms_acc, y.rms_acc)] {
                worst = worst.max((a - b).abs() / b);
            }
        });
        eprintln!("Taylor against the closed form: {impacts} impacts, RMS off by {worst:e}");
        assert!(impacts > 10_000, "{impacts}");
        assert!(worst <= 64.0 * f64::EPSILON, "{worst:e}");
    }

    #[test]
    fn intervals_where_x_is_monotone_cross_as_the_event_loop_takes_them() {
        // Issue 69: a whole interval whose |x| may pass the largest so far but on which x is
        // monotone is crossed in one step with the closed form's end state; against sending it
        // to the event loop (what every such interval took before), every field of the record
        // the same bits but the steps, which are fewer. Ground acceleration and a force, a random
        // load and a record, the structure alone and three dampers, at three gains (a threshold
        // in the scene: its first passage is pending until it happens).
        let (mut fewer, mut runs) = (0u64, 0u64);
        let designs = [(0.0, 0.005), (0.1, 0.005), (0.3, 0.002), (0.05, 0.02)];
        let looped = |run: &RandomRun| RandomRun {
            monotone: false,
            ..run.clone()
        };
        against(&designs, 7, (RandomRun::clone, looped), |x, y| {
            assert!(x.steps <= y.steps, "{} > {}", x.steps, y.steps);
            fewer += y.steps - x.steps;
            runs += 1;
            let steps = y.steps;
            assert_eq!(
                format!("{:?}", RandomRecord { steps, ..x.clone() }),
                format!("{y:?}")
            );
            for (a, b) in [(x.rms_x, y.rms_x), (x.rms_acc, y.rms_acc)] {
                assert_eq!(a.to_bits(), b.to_bits());
            }
        });
        eprintln!("monotone intervals: {fewer} steps fewer over {runs} runs");
        assert!(fewer > runs, "{fewer} over {runs} runs");
    }

    #[test]
    fn several_units_spare_only_searches_that_cannot_win_under_random_loads() {
        // `EventMap::find`'s spared searches, checked at every call against the search of every
        // unit from the same point (as in the harmonic scene's test): at a wall the same bits,
        // elsewhere no sooner. The crossing is off, so that every interval of several units
        // goes through the event loop.
        use crate::sim::phase::sparing;
        let (mut calls, mut walls, mut later) = (0, 0, 0);
        let req = Request::default();
        for scene in [seismic(), record()] {
            for (units, d_spread) in [(2.0, 0.5), (8.0, 0.5), (4.0, 0.0)] {
                let sys = System {
                    units,
                    d_spread,
                    w0: 0.05,
                    ..damped()
                };
                let run = RandomRun {
                    units_cross: false,
                    ..RandomRun::new(&sys, &SolverSettings::default(), &scene)
                };
                for r in 0..4 {
                    let block = run.load(RealizationStream::new(5, 0, r));
                    let t = sparing::check(|| {
                        run.run_block(&req, &block, 4.0, &mut NoProbe);
                    });
                    (calls, walls, later) = (calls + t.calls, walls + t.walls, later + t.later);
                }
            }
        }
        eprintln!("{calls} searches of several units, {walls} at a wall, {later} later");
        assert!(walls > 2_000 && calls > walls, "{calls} {walls}");
        assert!(later * 20 < calls, "{later} of {calls}");
    }

    #[test]
    fn intervals_of_several_units_cross_as_one_units_do_to_rounding() {
        // Whole intervals of several units, every unit free, are crossed in one step (each
        // unit's gap under the same hull test as one unit's) instead of going through the
        // event loop, one search per unit, and in the event loop a unit the same test keeps
        // clear until the interval's end is not searched. The same motion to rounding: against
        // the event loop, 1-s runs (200 intervals, the units set off toward a wall) of 2, 4 and
        // 8 units, equal and spread clearances, under ground acceleration, a force and a record
        // at three gains: the same impacts and sticks, every other field within 1e-9 of the
        // event loop's, and fewer steps in all (the event loop spares searches too,
        // `EventMap::find`, so a run may take a few more). (Not the same bits: the event loop
        // re-bases each unit's line at every event it stops at, the crossing takes it from the
        // interval's start. Impacts amplify the difference: over 2-s runs a chatter sequence
        // at gain 4 ends with one stick more.)
        let (mut fewer, mut runs, mut impacts, mut worst) = (0i64, 0u64, 0u64, 0.0f64);
        let settings = SolverSettings::default();
        let req = Request::default();
        let short = |s: RandomScene| RandomScene { duration: 1.0, ..s };
        let force = RandomScene {
            input: Input::Force,
            ..seismic()
        };
        for scene in [seismic(), force, record()].map(short) {
            for (units, d_spread, m, d) in [
                (2.0, 0.0, 0.1, 0.01),
                (4.0, 0.5, 0.1, 0.01),
                (8.0, 0.5, 0.1, 0.02),
                (8.0, 0.0, 0.2, 0.005),
            ] {
                // The units set off toward a wall: impacts from the start.
                let sys = System {
                    m,
                    d,
                    units,
                    d_spread,
                    w0: 0.05,
                    ..damped()
                };
                let run = RandomRun::new(&sys, &settings, &scene);
                let looped = RandomRun {
                    units_cross: false,
                    ..run.clone()
                };
                for r in 0..10 {
                    let block = run.load(RealizationStream::new(11, 0, r));
                    for gain in [1.0, 4.0, 12.0] {
                        let x = run.run_block(&req, &block, gain, &mut NoProbe);
                        let y = looped.run_block(&req, &block, gain, &mut NoProbe);
                        let at = format!("{units} units, spread {d_spread}, run {r}, gain {gain}");
                        assert_eq!(
                            (x.outcome, x.impacts, x.sticks),
                            (y.outcome, y.impacts, y.sticks),
                            "{at}"
                        );
                        fewer += y.steps as i64 - x.steps as i64;
                        runs += 1;
                        impacts += x.impacts;
                        let pairs = [
                            (x.amplitude, y.amplitude),
                            (x.t_peak, y.t_peak),
                            (x.rms_x, y.rms_x),
                            (x.rms_acc, y.rms_acc),
                            (x.energy_impact, y.energy_impact),
                            (
                                x.first_passage_time.unwrap_or(0.0),
                                y.first_passage_time.unwrap_or(0.0),
                            ),
                        ];
                        for (a, b) in pairs {
                            let rel = (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
                            assert!(rel <= 1e-9, "{at}: {a} against {b}");
                            worst = worst.max(rel);
                        }
                    }
                }
            }
        }
        eprintln!(
            "several units: {fewer} steps fewer over {runs} runs, {impacts} impacts, \
             worst relative {worst:.2e}"
        );
        assert!(impacts > 5 * runs, "{impacts} impacts over {runs} runs");
        assert!(fewer > runs as i64, "{fewer} steps fewer over {runs} runs");
    }

    #[test]
    fn pieces_integrated_from_their_ends_are_the_quadratures_to_rounding() {
        // Issue 69: the pieces between events take `int x^2` and `int A^2` from their two ends
        // (the equation of motion's moments, `Ramp::squares_between`) within the rounding
        // budget; against the 5-point rule on the Taylor polynomial (what every piece took
        // before), the same motion bit for bit and the run's RMS within the budget (half of
        // `FROM_ENDS_BUDGET`, a square root's), under ground acceleration and a force, a random
        // load and a record of white noise (steep ramps, where the moments lose the most),
        // pieces free and stuck, the structure alone among the designs. Without the budget (every
        // piece from its ends) the record's RMS were off by up to 45,000 units.
        let (mut errors, mut impacts) = (Vec::new(), 0u64);
        let designs = [(0.1, 0.005), (0.3, 0.002), (0.05, 0.02), (0.0, 0.01)];
        let quadrature = |run: &RandomRun| RandomRun {
            moments: false,
            ..run.clone()
        };
        against(&designs, 11, (RandomRun::clone, quadrature), |x, y| {
            let rms = (y.rms_x, y.rms_acc);
            assert_eq!(
                format!(
                    "{:?}",
                    RandomRecord {
                        rms_x: rms.0,
                        rms_acc: rms.1,
                        ..x.clone()
                    }
                ),
                format!("{y:?}")
            );
            impacts += x.impacts;
            for (a, b) in [(x.rms_x, rms.0), (x.rms_acc, rms.1)] {
                errors.push((a - b).abs() / b / f64::EPSILON);
            }
        });
        errors.sort_by(f64::total_cmp);
        let at = |q: f64| errors[((errors.len() - 1) as f64 * q) as usize];
        let moved = errors.iter().filter(|&&e| e > 0.0).count();
        eprintln!(
            "from the ends against quadrature: {impacts} impacts, {} RMS ({moved} moved), off by \
             {} (median), {} (99 %), {} (worst) rounding units",
            errors.len(),
            at(0.5),
            at(0.99),
            at(1.0)
        );
        assert!(impacts > 10_000, "{impacts}");
        // The pieces are taken from their ends (else nothing would move) ...
        assert!(2 * moved > errors.len(), "{moved} of {}", errors.len());
        // ... within the budget, with the quadrature's own few units.
        assert_eq!(FROM_ENDS_BUDGET, 4096.0 * f64::EPSILON);
        assert!(at(1.0) <= 2048.0 + 16.0, "{}", at(1.0));
    }
}
