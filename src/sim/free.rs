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
use super::noise::NoiseSettings;
use super::noise::{NoiseStream, NoisyPeak};
use super::phase::{
    Event, EventMap, Hit, Phase, PhaseSolver, SceneEvents, State, Wall, Watch, run, side_of,
};
use super::probe::Probe;
use super::record::{Outcome, Record};
use super::request::Request;
use super::rk4::Rk4;
use super::settings::{SolverKind, SolverSettings};
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

struct Run<'a, P: Probe> {
    /// Phase, state, impact and sticking counts, `v`'s sign: the shared event map.
    map: EventMap<'a, Oscillator>,
    req: &'a Request,
    noise: Option<(&'a NoiseSettings, &'a mut NoiseStream)>,
    probe: &'a mut P,
    /// Positive half-cycle maxima wanted (at least one).
    want: usize,
    // observables
    peaks: Vec<(f64, f64)>,
    running: Option<(f64, f64)>,
    x_side: f64,
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
        let free = Oscillator::new(sys.M, sys.K, sys.C);
        let pair = Oscillator::new(sys.M + sys.m, sys.K, sys.C);
        let mut map = EventMap::new(sys, settings, free, pair);
        // The sign x has, or is about to have, at t = 0.
        let x_side = side_of(sys.x0, sys.v0, free.accel(sys.x0, sys.v0));
        map.v_side = side_of(sys.v0, free.accel(sys.x0, sys.v0), 0.0);
        let energy = map.energy();
        Run {
            map,
            req,
            noise,
            probe,
            want: req.peaks.max(1),
            peaks: Vec::with_capacity(req.peaks),
            running: (x_side > 0.0).then_some((sys.x0, 0.0)),
            x_side,
            energy,
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
            .unwrap_or(self.map.settings.t_max_periods * self.map.period)
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

    fn candidate(&mut self, x: f64, t: f64) {
        if let Some((best, _)) = self.running
            && x <= best
        {
            return;
        }
        self.running = Some((x, t));
    }

    fn go<S: PhaseSolver<Motion = Oscillator>>(mut self, solver: &mut S) -> Record {
        self.batch_noise = self.noise.is_some() && solver.closed_form().is_some();
        let outcome = run(&mut self, solver);
        self.finish(outcome, solver.steps())
    }

    /// Handles the trace and noise samples due at the current time.
    fn samples(&mut self) {
        let t = self.map.t;
        if let Some(dt) = self.req.trace_dt
            && self.next_trace as f64 * dt <= t
        {
            self.probe.sample(t, &self.map.s);
            self.next_trace += 1;
        }
        if self.x_side > 0.0
            && !self.batch_noise
            && let Some((ns, stream)) = &mut self.noise
        {
            let k = self.next_noise;
            if k as f64 * ns.sample_time <= t {
                let measured = self.map.s.x + stream.sample(k, ns);
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
        // With several units the mass carried varies: the propagator is the phase's own.
        let prop = if self.map.several() {
            osc.propagator(ts)
        } else {
            let slot = usize::from(matches!(self.map.phase, Phase::Stuck(_)));
            *self.prop[slot].get_or_insert_with(|| osc.propagator(ts))
        };
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

    fn outcome_at_horizon(&self) -> Outcome {
        match self.peaks.len() {
            n if n >= self.want => Outcome::Ok,
            n if n >= 2 => Outcome::FewPeaks,
            _ => Outcome::NoSecondPeak,
        }
    }

    /// Books the drop of energy to the state `s` as impact loss (never a gain).
    fn book_impact_loss(&mut self, s: &State) {
        let e = if self.map.several() {
            // The map is at `s` already; every unit's kinetic energy counts.
            self.map.energy()
        } else {
            self.map.sys.energy(s.x, s.v, s.w)
        };
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
            impacts: self.map.impacts,
            sticks: self.map.sticks,
            unit_impacts: self.map.units.iter().map(|u| u.impacts).collect(),
            energy_impact: self.energy_impact,
            energy_viscous: self.energy_viscous,
            t_stop: self.map.t,
            steps,
        }
    }
}

/// Free decay on the event map: half-cycles and their maxima, samples, the horizon.
impl<'a, P: Probe, S: PhaseSolver<Motion = Oscillator>> SceneEvents<'a, S> for Run<'a, P> {
    fn map(&self) -> &EventMap<'a, Oscillator> {
        &self.map
    }

    fn map_mut(&mut self) -> &mut EventMap<'a, Oscillator> {
        &mut self.map
    }

    fn watch(&self) -> Watch {
        let (walls, sep_side) = self.map.contact();
        Watch {
            walls,
            x_side: Some(self.x_side),
            v_side: (self.x_side > 0.0 && !self.noisy()).then_some(self.map.v_side),
            x_floor: 0.0,
            sep_side,
            t_limit: self.t_limit(),
        }
    }

    fn arrived(&mut self, solver: &S, ev: Event) {
        if self.batch_noise {
            // The samples between the last event and this one, on the phase's closed form;
            // at a time limit the sample at the limit itself too.
            self.noise_between(solver, ev == Event::Limit);
        }
    }

    /// Books the viscous loss of the piece just travelled.
    fn synced(&mut self, _solver: &S) {
        let e = self.map.energy();
        // The closed form keeps energy non-increasing up to rounding; never book a gain.
        self.energy_viscous += (self.energy - e).max(0.0);
        self.energy = e.min(self.energy);
        self.probe.energy(self.map.t, e);
    }

    fn at_wall(&mut self) {
        if self.x_side > 0.0 && !self.noisy() {
            self.candidate(self.map.s.x, self.map.t);
        }
    }

    fn impacted(&mut self, hit: &Hit) {
        let t = self.map.t;
        self.book_impact_loss(&hit.after);
        self.probe
            .impact_of(t, hit.unit, hit.wall, &hit.before, &hit.after);
        if hit.stuck {
            let s = self.map.s;
            self.book_impact_loss(&s);
            self.probe.stick(t, hit.wall, &s);
        }
        self.probe.energy(t, self.energy);
    }

    fn separated(&mut self, wall: Wall) {
        self.probe.separate(self.map.t, wall, &self.map.s);
    }

    fn v_zero(&mut self) {
        if self.map.v_side > 0.0 && !self.noisy() {
            self.candidate(self.map.s.x, self.map.t);
        }
    }

    fn x_zero(&mut self) -> Option<Outcome> {
        if self.x_side > 0.0 {
            if let Some((ns, _)) = &self.noise {
                self.noisy_peak.flush(ns, &mut self.running);
            }
            if let Some(peak) = self.running.take() {
                self.peaks.push(peak);
            }
            if self.peaks.len() >= self.want && self.req.t_end.is_none() {
                return Some(Outcome::Ok);
            }
            self.x_side = -1.0;
        } else {
            self.x_side = 1.0;
            self.map.v_side = 1.0;
            if let Some((ns, _)) = &self.noise {
                self.next_noise = (self.map.t / ns.sample_time).ceil() as u64;
            }
        }
        None
    }

    fn limit(&mut self, _solver: &mut S) -> Option<Outcome> {
        let horizon = self.map.t >= self.horizon();
        self.samples();
        horizon.then(|| self.outcome_at_horizon())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::phase::sparing;
    use crate::sim::probe::NoProbe;

    #[test]
    fn several_units_spare_only_searches_that_cannot_win_in_free_decay() {
        // `EventMap::find`'s spared searches, checked at every call against the search of every
        // unit from the same point (as in the harmonic scene's test): at a wall the same bits,
        // elsewhere no sooner.
        let (mut calls, mut walls, mut later) = (0, 0, 0);
        let req = Request {
            peaks: 6,
            ..Request::default()
        };
        for (units, d_spread) in [(2.0, 0.5), (3.0, 0.25), (8.0, 0.75)] {
            for e in [0.9, 0.6, 0.2] {
                for (d, m) in [(0.01, 0.02), (0.004, 0.03), (0.03, 0.01)] {
                    let sys = System {
                        units,
                        d_spread,
                        e,
                        d,
                        m,
                        ..System::TABLE_I
                    };
                    let t = sparing::check(|| {
                        simulate(&sys, &SolverSettings::default(), &req, None, &mut NoProbe);
                    });
                    (calls, walls, later) = (calls + t.calls, walls + t.walls, later + t.later);
                }
            }
        }
        eprintln!("{calls} searches of several units, {walls} at a wall, {later} later");
        assert!(walls > 500 && calls > walls, "{calls} {walls}");
        assert!(later * 20 < calls, "{later} of {calls}");
    }
}
