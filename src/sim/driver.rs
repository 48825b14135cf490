//! The free-decay scene: observables (half-cycle maxima, noise), horizon and outcomes, on the
//! event map of [`super::phase`] (impact law, chatter and sticking, separation), with any of the
//! solvers. A solver only moves the main mass through one smooth phase and reports the first
//! watched event ([`PhaseSolver`]).
//!
//! # Energy
//! The total mechanical energy `(M v^2 + m w^2 + K x^2) / 2` drops at impacts by
//! `mu (1 - e^2) (v - w)^2 / 2` (counted in `energy_impact`) and between events by the viscous
//! work (counted in `energy_viscous` as the drop of energy over each phase piece).

use super::dense::Stepping;
use super::dopri5::Dopri5;
use super::exact::ExactPhase;
use super::linear::Oscillator;
use super::linear::Propagator;
use super::noise::{NoiseStream, NoisyPeak};
use super::phase::{
    Event, PhaseSolver, State, StepCap, Wall, Walls, Watch, chatter_ends, impact, side_of,
};
use super::rk4::Rk4;
use super::{NoiseSettings, Outcome, Probe, Record, Request, SolverKind, SolverSettings};
use crate::model::System;

/// Runs one simulation. Pure: the same inputs give the same bits. `noise` carries the noise
/// settings and the run's own random stream; without it no random number is drawn.
pub fn simulate<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
) -> Record {
    let tol_t = settings.tol * sys.period();
    match settings.kind {
        SolverKind::Exact => {
            let mut solver = ExactPhase::new(tol_t, settings.max_steps);
            Run::new(sys, settings, req, noise, probe).go(&mut solver)
        }
        SolverKind::Rk4 => {
            let mut solver = Stepping::new(Rk4 { h: settings.h }, tol_t, settings.max_steps);
            Run::new(sys, settings, req, noise, probe).go(&mut solver)
        }
        SolverKind::Dopri5 => {
            let inner = Dopri5::new(settings.rtol, settings.atol);
            let mut solver = Stepping::new(inner, tol_t, settings.max_steps);
            Run::new(sys, settings, req, noise, probe).go(&mut solver)
        }
    }
}

enum Phase {
    Free,
    Stuck(Wall),
}

struct Run<'a, P: Probe> {
    sys: &'a System,
    settings: &'a SolverSettings,
    req: &'a Request,
    noise: Option<(&'a NoiseSettings, &'a mut NoiseStream)>,
    probe: &'a mut P,
    free: Oscillator,
    pair: Oscillator,
    period: f64,
    // state
    phase: Phase,
    t: f64,
    s: State,
    // observables
    peaks: Vec<(f64, f64)>,
    running: Option<(f64, f64)>,
    x_side: f64,
    v_side: f64,
    impacts: u64,
    sticks: u64,
    energy: f64,
    energy_impact: f64,
    energy_viscous: f64,
    next_trace: u64,
    next_noise: u64,
    /// Noise samples taken in batches from the solver's closed form (see
    /// [`PhaseSolver::closed_form`]) rather than one solver stop each.
    batch_noise: bool,
    noisy_peak: NoisyPeak,
    /// Propagators over one sample time, of the free main mass and of the stuck pair.
    prop: [Option<Propagator>; 2],
}

impl<'a, P: Probe> Run<'a, P> {
    fn new(
        sys: &'a System,
        settings: &'a SolverSettings,
        req: &'a Request,
        noise: Option<(&'a NoiseSettings, &'a mut NoiseStream)>,
        probe: &'a mut P,
    ) -> Self {
        let s = State {
            x: sys.x0,
            v: sys.v0,
            y: sys.y0,
            w: sys.w0,
        };
        let free = Oscillator::new(sys.M, sys.K, sys.C);
        // The sign x has, or is about to have, at t = 0.
        let x_side = side_of(sys.x0, sys.v0, free.accel(sys.x0, sys.v0));
        let v_side = side_of(sys.v0, free.accel(sys.x0, sys.v0), 0.0);
        Run {
            sys,
            settings,
            req,
            noise,
            probe,
            free,
            pair: Oscillator::new(sys.M + sys.m, sys.K, sys.C),
            period: sys.period(),
            phase: Phase::Free,
            t: 0.0,
            s,
            peaks: Vec::with_capacity(req.peaks),
            running: (x_side > 0.0).then_some((sys.x0, 0.0)),
            x_side,
            v_side,
            impacts: 0,
            sticks: 0,
            energy: sys.energy(sys.x0, sys.v0, sys.w0),
            energy_impact: 0.0,
            energy_viscous: 0.0,
            next_trace: 0,
            // A sample exactly at a zero of x is not inside a positive half-cycle.
            next_noise: u64::from(sys.x0 == 0.0),
            batch_noise: false,
            noisy_peak: NoisyPeak::default(),
            prop: [None; 2],
        }
    }

    fn horizon(&self) -> f64 {
        self.req
            .t_end
            .unwrap_or(self.settings.t_max_periods * self.period)
    }

    fn noisy(&self) -> bool {
        self.noise.is_some()
    }

    /// Next time the loop must stop for a sample or the horizon.
    fn t_limit(&self) -> f64 {
        let mut lim = self.horizon();
        if let Some(dt) = self.req.trace_dt {
            lim = lim.min(self.next_trace as f64 * dt);
        }
        if let Some((ns, _)) = &self.noise
            && self.x_side > 0.0
            && !self.batch_noise
        {
            lim = lim.min(self.next_noise as f64 * ns.sample_time);
        }
        lim
    }

    fn watch(&self) -> Watch {
        let (walls, sep_side) = match self.phase {
            Phase::Free => (
                Some(Walls {
                    t0: self.t,
                    y0: self.s.y,
                    w: self.s.w,
                    half_d: 0.5 * self.sys.d,
                }),
                None,
            ),
            Phase::Stuck(wall) => (None, Some(wall.sign())),
        };
        Watch {
            walls,
            x_side: Some(self.x_side),
            v_side: (self.x_side > 0.0 && !self.noisy()).then_some(self.v_side),
            sep_side,
            t_limit: self.t_limit(),
        }
    }

    fn begin_phase<S: PhaseSolver<Motion = Oscillator>>(&self, solver: &mut S) {
        let osc = match self.phase {
            Phase::Free => &self.free,
            Phase::Stuck(_) => &self.pair,
        };
        solver.begin(osc, self.t, self.s.x, self.s.v);
    }

    /// Brings the run's state to the solver's current point, booking the viscous loss.
    fn sync<S: PhaseSolver<Motion = Oscillator>>(&mut self, solver: &S, walls: &Option<Walls>) {
        let (t, x, v) = solver.state();
        self.t = t;
        self.s.x = x;
        self.s.v = v;
        match (&self.phase, walls) {
            (Phase::Free, Some(wl)) => {
                self.s.y = wl.y0 + wl.w * (t - wl.t0);
            }
            (Phase::Stuck(wall), _) => {
                self.s.y = x + wall.sign() * 0.5 * self.sys.d;
                self.s.w = v;
            }
            _ => {}
        }
        let e = self.sys.energy(self.s.x, self.s.v, self.s.w);
        // The closed form keeps energy non-increasing up to rounding; never book a gain.
        self.energy_viscous += (self.energy - e).max(0.0);
        self.energy = e.min(self.energy);
        self.probe.energy(t, e);
    }

    fn candidate(&mut self, x: f64, t: f64) {
        if let Some((best, _)) = self.running
            && x <= best
        {
            return;
        }
        self.running = Some((x, t));
    }

    fn go<S: PhaseSolver<Motion = Oscillator>>(mut self, solver: &mut S) -> Record {
        let want = self.req.peaks.max(1);
        self.batch_noise = self.noise.is_some() && solver.closed_form().is_some();
        self.begin_phase(solver);
        let outcome = loop {
            let watch = self.watch();
            let ev = match solver.next_event(&watch) {
                Ok(ev) => ev,
                Err(StepCap) => {
                    self.sync(solver, &watch.walls);
                    break Outcome::StepCap;
                }
            };
            if self.batch_noise {
                // The samples between the last event and this one, on the phase's closed form;
                // at a time limit the sample at the limit itself too.
                self.noise_between(solver, ev == Event::Limit);
            }
            self.sync(solver, &watch.walls);
            match ev {
                Event::NonFinite => break Outcome::NonFinite,
                Event::Wall(wall) => {
                    if self.x_side > 0.0 && !self.noisy() {
                        self.candidate(self.s.x, self.t);
                    }
                    if self.impacts >= self.settings.max_impacts {
                        break Outcome::EventCap;
                    }
                    self.collide(wall);
                    // The impact changed v discontinuously; re-read its sign, or a maximum that
                    // follows an impact reversing v inside a positive half-cycle goes unwatched
                    // (found at e = 0.80..0.83 by a dense-trace test and by the SciPy peer;
                    // regression tests in tests/simulator.rs and tests/solvers.rs).
                    self.v_side = self.v_sign();
                    self.begin_phase(solver);
                }
                Event::Separation => {
                    if let Phase::Stuck(wall) = self.phase {
                        self.probe.separate(self.t, wall, &self.s);
                    }
                    self.phase = Phase::Free;
                    self.begin_phase(solver);
                }
                Event::VZero => {
                    if self.v_side > 0.0 && !self.noisy() {
                        self.candidate(self.s.x, self.t);
                    }
                    self.v_side = -self.v_side;
                }
                Event::XZero => {
                    if self.x_side > 0.0 {
                        if let Some((ns, _)) = &self.noise {
                            self.noisy_peak.flush(ns, &mut self.running);
                        }
                        if let Some(peak) = self.running.take() {
                            self.peaks.push(peak);
                        }
                        if self.peaks.len() >= want && self.req.t_end.is_none() {
                            break Outcome::Ok;
                        }
                        self.x_side = -1.0;
                    } else {
                        self.x_side = 1.0;
                        self.v_side = 1.0;
                        if let Some((ns, _)) = &self.noise {
                            self.next_noise = (self.t / ns.sample_time).ceil() as u64;
                        }
                    }
                }
                Event::Limit => {
                    let horizon = self.t >= self.horizon();
                    self.samples();
                    if horizon {
                        break self.outcome_at_horizon(want);
                    }
                }
            }
        };
        self.finish(outcome, solver.steps())
    }

    /// The sign `v` has now or is about to take, in the current phase.
    fn v_sign(&self) -> f64 {
        let osc = match self.phase {
            Phase::Free => &self.free,
            Phase::Stuck(_) => &self.pair,
        };
        side_of(self.s.v, osc.accel(self.s.x, self.s.v), 0.0)
    }

    /// Handles the trace and noise samples due at the current time.
    fn samples(&mut self) {
        if let Some(dt) = self.req.trace_dt
            && self.next_trace as f64 * dt <= self.t
        {
            self.probe.sample(self.t, &self.s);
            self.next_trace += 1;
        }
        if self.x_side > 0.0
            && !self.batch_noise
            && let Some((ns, stream)) = &mut self.noise
        {
            let k = self.next_noise;
            if k as f64 * ns.sample_time <= self.t {
                let measured = self.s.x + stream.sample(k, ns);
                let t = self.t;
                self.next_noise = k + 1;
                self.candidate(measured, t);
            }
        }
    }

    /// Takes the noise samples due from the run's time up to the solver's (before it, or up to
    /// and including it with `inclusive`), inside a positive half-cycle: the phase's closed form
    /// at the first sample and at every 64th, the constant propagator over one sample time in
    /// between (one 2 x 2 multiply a sample; the chain's rounding stays below 64 ulps).
    fn noise_between<S: PhaseSolver<Motion = Oscillator>>(&mut self, solver: &S, inclusive: bool) {
        let Some((ns, stream)) = &mut self.noise else {
            return;
        };
        if self.x_side <= 0.0 {
            return;
        }
        let Some((osc, t0, x0, v0)) = solver.closed_form() else {
            return;
        };
        let (t_end, _, _) = solver.state();
        let ts = ns.sample_time;
        let mut k = self.next_noise;
        // k as f64 * ts is the sample's time; through i64, the same value and a cheaper
        // conversion on x86-64 (k < 2^63).
        let due = |k: u64| {
            let t = (k as i64) as f64 * ts;
            t < t_end || (inclusive && t == t_end)
        };
        if !due(k) {
            return;
        }
        let slot = usize::from(matches!(self.phase, Phase::Stuck(_)));
        let prop = *self.prop[slot].get_or_insert_with(|| osc.propagator(ts));
        let (mut x, mut v) = (0.0, 0.0);
        let mut i = 0u32;
        while due(k) {
            if i.is_multiple_of(64) {
                let kin = osc.eval(x0, v0, (k as i64) as f64 * ts - t0);
                (x, v) = (kin.x, kin.v);
            } else {
                (x, v) = prop.apply(x, v);
            }
            self.noisy_peak.push(k, x, stream, ns, &mut self.running);
            k += 1;
            i += 1;
        }
        self.next_noise = k;
    }

    fn outcome_at_horizon(&self, want: usize) -> Outcome {
        match self.peaks.len() {
            n if n >= want => Outcome::Ok,
            n if n >= 2 => Outcome::FewPeaks,
            _ => Outcome::NoSecondPeak,
        }
    }

    /// Applies the impact law on `wall`, then decides between rebound and sticking.
    fn collide(&mut self, wall: Wall) {
        let sys = self.sys;
        let sign = wall.sign();
        // The probe sees the state as located; then the inner mass is put exactly on the wall
        // (the event is within tolerance of it) so the next phase starts from the wall.
        let before = self.s;
        self.s.y = self.s.x + sign * 0.5 * sys.d;
        let (va, wa) = impact(sys.M, sys.m, sys.e, before.v, before.w);
        self.s.v = va;
        self.s.w = wa;
        self.impacts += 1;
        self.book_impact_loss();
        self.probe.impact(self.t, wall, &before, &self.s);
        // Speed away from the wall and the wall's acceleration toward the inner mass.
        let u = (sign * (self.s.v - self.s.w)).max(0.0);
        let a = -sign * self.free.accel(self.s.x, self.s.v);
        if chatter_ends(u, a, sys.e, self.settings, self.period) {
            let common = (sys.M * self.s.v + sys.m * self.s.w) / (sys.M + sys.m);
            self.s.v = common;
            self.s.w = common;
            self.book_impact_loss();
            self.sticks += 1;
            self.phase = Phase::Stuck(wall);
            self.probe.stick(self.t, wall, &self.s);
        } else {
            self.phase = Phase::Free;
        }
        self.probe.energy(self.t, self.energy);
    }

    fn book_impact_loss(&mut self) {
        let e = self.sys.energy(self.s.x, self.s.v, self.s.w);
        self.energy_impact += (self.energy - e).max(0.0);
        self.energy = e.min(self.energy);
    }

    fn finish(self, outcome: Outcome, steps: u64) -> Record {
        let nan = f64::NAN;
        let (x1, t1) = self.peaks.first().copied().unwrap_or((nan, nan));
        let (x2, t2) = self.peaks.get(1).copied().unwrap_or((nan, nan));
        let xmax = self
            .peaks
            .iter()
            .map(|p| p.0)
            .fold(nan, |m: f64, x| if m.is_nan() || x > m { x } else { m });
        Record {
            outcome,
            x1,
            t1,
            x2,
            t2,
            xmax,
            di: (x1 - x2) / (t2 - t1),
            peaks: self.peaks,
            impacts: self.impacts,
            sticks: self.sticks,
            energy_impact: self.energy_impact,
            energy_viscous: self.energy_viscous,
            t_stop: self.t,
            steps,
        }
    }
}
