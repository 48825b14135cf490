//! The forced scene on the event map of [`crate::sim::phase`] (impact law, chatter and sticking,
//! separation): transient, measurement window, Poincaré sections, outcome.

use super::Finder;
use super::finder::Bracketed;
use super::motion::Forced;
use super::{Harmonic, HarmonicRecord};
use crate::model::System;
use crate::numeric::gauss_legendre;
use crate::sim::driven::{DrivenPhase, Jet};
use crate::sim::noise::NoiseSettings;
use crate::sim::noise::NoiseStream;
use crate::sim::phase::{self, EventMap, Hit, Phase, PhaseSolver, SceneEvents, State, Wall, Watch};
use crate::sim::probe::{NoProbe, Probe};
use crate::sim::record::Outcome;
use crate::sim::request::Request;
use crate::sim::settings::SolverSettings;

/// Most sections the transient test looks back: `3 p + 1` for `p <= 8`.
const HISTORY: usize = 25;
/// Largest period looked for.
const MAX_PERIOD: usize = 8;

/// One Poincaré section `(x, x', y - x, y')`.
type Section = [f64; 4];

/// Runs the harmonic scene on `sys`. Pure: the same inputs give the same bits. `settings`
/// supplies the event tolerance, the chatter threshold and the caps; `req.trace_dt` a sampled
/// trace to the probe (`req.peaks` and `req.t_end` are the free-decay scene's and are not
/// used). The caller has validated `sys`, `settings` and `scene` ([`Harmonic::validate`]).
pub fn simulate_harmonic<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
) -> HarmonicRecord {
    match scene.finder {
        Finder::SafeSteps => {
            simulate_with(sys, settings, req, scene, noise, probe, DrivenPhase::new).0
        }
        Finder::Bracketed => {
            simulate_with(sys, settings, req, scene, noise, probe, Bracketed::new).0
        }
    }
}

/// [`simulate_harmonic`] with unit `i` of several (model.md §14) started at its own
/// `starts[i] = (y_i, w_i)` (m, m/s; inside its cavity, `|y_i - x0| <= d_i / 2`) instead of the
/// system's common `(y0, w0)`; also returns every unit's `(y, w)` at the end. The stroboscopic
/// map of several units ([`crate::orbits::units`]) evaluates through it. With one unit `starts`
/// is not read (the unit starts at `(y0, w0)`): the run is [`simulate_harmonic`]'s, bit for bit.
/// No noise. Pure.
pub fn simulate_harmonic_units<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    starts: &[(f64, f64)],
    probe: &mut P,
) -> (HarmonicRecord, Vec<(f64, f64)>) {
    simulate_units_by_finder(sys, settings, req, scene, None, probe, Some(starts))
}

/// [`simulate_harmonic`] (with its noise), also returning every unit's `(y, w)` (m, m/s) at the
/// run's end, `t_stop` (a section time when `ok`): with several units the record's `end` holds
/// unit 1's only, and the census of several units goes on from the whole state
/// ([`crate::orbits::several`]). The record is [`simulate_harmonic`]'s, bit for bit. Pure.
pub fn simulate_harmonic_ends<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
) -> (HarmonicRecord, Vec<(f64, f64)>) {
    simulate_units_by_finder(sys, settings, req, scene, noise, probe, None)
}

/// [`simulate_from`] with the scene's event finder: the record and every unit's `(y, w)` at the
/// end.
fn simulate_units_by_finder<P: Probe>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
    starts: Option<&[(f64, f64)]>,
) -> (HarmonicRecord, Vec<(f64, f64)>) {
    match scene.finder {
        Finder::SafeSteps => {
            let (rec, _, units) = simulate_from(
                sys,
                settings,
                req,
                scene,
                noise,
                probe,
                DrivenPhase::new,
                starts,
            );
            (rec, units)
        }
        Finder::Bracketed => {
            let (rec, _, units) = simulate_from(
                sys,
                settings,
                req,
                scene,
                noise,
                probe,
                Bracketed::new,
                starts,
            );
            (rec, units)
        }
    }
}

/// [`simulate_harmonic`] with the event finder `make(free, tol_t, max_steps)` builds, and the
/// finder at the end (a test compares two finders on one run through it).
pub(crate) fn simulate_with<P: Probe, S: Stepper>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
    make: impl FnOnce(&Forced, f64, u64) -> S,
) -> (HarmonicRecord, S) {
    let (rec, solver, _) = simulate_from(sys, settings, req, scene, noise, probe, make, None);
    (rec, solver)
}

/// [`simulate_with`], the units of several started at `starts` when given
/// ([`simulate_harmonic_units`]), with every unit's `(y, w)` at the end.
#[allow(clippy::too_many_arguments)]
fn simulate_from<P: Probe, S: Stepper>(
    sys: &System,
    settings: &SolverSettings,
    req: &Request,
    scene: &Harmonic,
    noise: Option<(&NoiseSettings, &mut NoiseStream)>,
    probe: &mut P,
    make: impl FnOnce(&Forced, f64, u64) -> S,
    starts: Option<&[(f64, f64)]>,
) -> (HarmonicRecord, S, Vec<(f64, f64)>) {
    let omega = scene.omega(sys);
    let (free, pair) = oscillators(sys, scene.F0, omega);
    let tol_t = settings.tol * sys.period();
    let settings = &scaled_caps(settings, scene);
    let map = EventMap::new(sys, settings, free, pair);
    let mut run = Run::new(map, req, scene, noise, probe, omega);
    if let Some(starts) = starts {
        run.map.start_units(starts);
    }
    let mut solver = make(&free, tol_t, settings.max_steps);
    let outcome = phase::run(&mut run, &mut solver);
    let steps = solver.steps();
    let units = run.map.unit_states();
    (run.finish(outcome, steps), solver, units)
}

/// Runs of one forcing period each, one after another (a design-life chain,
/// [`crate::orbits::life`]): `start` the first period's state, then `more(amplitude, end)` after
/// each period that ends `ok` gives the next period's start (`None`: done). Each period is the
/// run [`simulate_harmonic`] makes of `sys` started at its start under `scene`, bit for bit; the
/// oscillators, the caps, the map and the run are built once (about a tenth of a period's cost
/// when built for each). `false` when a period's outcome was not `ok` (its values not handed
/// on). One unit with `m > 0` (the start's `(x0, v0, y0, w0)` of `sys` are not read); `scene`
/// one period from `t = 0` (`n_trans = Some(0)`, `n_meas = 1`), no energies. Pure.
pub(crate) fn simulate_periods(
    sys: &System,
    settings: &SolverSettings,
    scene: &Harmonic,
    start: State,
    more: impl FnMut(f64, &State) -> Option<State>,
) -> bool {
    match scene.finder {
        Finder::SafeSteps => periods_with(sys, settings, scene, start, more, DrivenPhase::new),
        Finder::Bracketed => periods_with(sys, settings, scene, start, more, Bracketed::new),
    }
}

/// [`simulate_periods`] with the event finder `make` builds (anew for each period).
fn periods_with<S: Stepper>(
    sys: &System,
    settings: &SolverSettings,
    scene: &Harmonic,
    mut start: State,
    mut more: impl FnMut(f64, &State) -> Option<State>,
    make: impl Fn(&Forced, f64, u64) -> S,
) -> bool {
    debug_assert!(sys.unit_count() == 1 && sys.m > 0.0);
    debug_assert!(scene.n_trans == Some(0) && scene.n_meas == 1 && !scene.energies);
    let omega = scene.omega(sys);
    let (free, pair) = oscillators(sys, scene.F0, omega);
    let tol_t = settings.tol * sys.period();
    let settings = &scaled_caps(settings, scene);
    let req = Request::default();
    let mut probe = NoProbe;
    let map = EventMap::new(sys, settings, free, pair);
    let mut run = Run::new(map, &req, scene, None, &mut probe, omega);
    loop {
        run.restart(start);
        let mut solver = make(&free, tol_t, settings.max_steps);
        if phase::run(&mut run, &mut solver) != Outcome::Ok {
            return false;
        }
        let amplitude = run.window.as_ref().map_or(f64::NAN, |w| w.amplitude);
        match more(amplitude, &run.map.s) {
            Some(next) => start = next,
            None => return true,
        }
    }
}

/// An event finder of the forced phases ([`Finder`]): today's safe steps
/// ([`DrivenPhase`]) or the brackets of [`super::finder`].
pub(crate) trait Stepper: PhaseSolver<Motion = Forced> {
    /// The phase's motion at `t`, without moving (for quadrature).
    fn at(&self, t: f64) -> Jet;
}

impl Stepper for DrivenPhase<Forced> {
    #[inline]
    fn at(&self, t: f64) -> Jet {
        DrivenPhase::at(self, t)
    }
}

impl Stepper for Bracketed<Forced> {
    #[inline]
    fn at(&self, t: f64) -> Jet {
        Bracketed::at(self, t)
    }
}

/// The forced oscillators of the free main mass and of the stuck pair. The census's chaos probe
/// and its shooting run one or a few periods per call on the same system, so the last pair a
/// thread built is kept and handed out again for the same inputs (the same bits either way:
/// about a tenth of a one-period run is building them; a design-life chain builds them once,
/// [`simulate_periods`]).
fn oscillators(sys: &System, f0: f64, omega: f64) -> (Forced, Forced) {
    type Key = [u64; 6];
    thread_local! {
        static LAST: std::cell::Cell<Option<(Key, Forced, Forced)>> =
            const { std::cell::Cell::new(None) };
    }
    let key = [sys.M, sys.m, sys.K, sys.C, f0, omega].map(f64::to_bits);
    LAST.with(|last| match last.get() {
        Some((k, free, pair)) if k == key => (free, pair),
        _ => {
            let free = Forced::new(sys.M, sys.K, sys.C, f0, omega);
            let pair = Forced::new(sys.M + sys.m, sys.K, sys.C, f0, omega);
            last.set(Some((key, free, pair)));
            (free, pair)
        }
    })
}

/// Impacts and steps a forced run may take per forcing period before its caps stop it: the
/// caps of `settings` hold for a run of up to a few thousand periods (a transient and a
/// window); a long window (`n_meas` in the hundreds of thousands) gets caps in proportion, so
/// that only a run that chatters without end, or steps without end, is stopped.
pub const IMPACTS_PER_PERIOD: u64 = 100;
pub const STEPS_PER_PERIOD: u64 = 10_000;

/// `settings` with its impact and step caps raised to [`IMPACTS_PER_PERIOD`] and
/// [`STEPS_PER_PERIOD`] times the longest run the scene can make (its transient budget and its
/// window), when that is more.
fn scaled_caps(settings: &SolverSettings, scene: &Harmonic) -> SolverSettings {
    let periods = scene.n_trans.unwrap_or(scene.n_trans_max) + scene.n_meas;
    SolverSettings {
        max_impacts: settings
            .max_impacts
            .max(IMPACTS_PER_PERIOD.saturating_mul(periods)),
        max_steps: settings
            .max_steps
            .max(STEPS_PER_PERIOD.saturating_mul(periods)),
        ..*settings
    }
}

/// What the measurement window has gathered.
struct Window {
    amplitude: f64,
    impacts: u64,
    sections: Vec<Section>,
    energy_force: f64,
    energy_viscous: f64,
    energy_impact: f64,
    /// Start of the smooth piece not yet integrated.
    piece: f64,
}

struct Run<'a, P: Probe> {
    /// Phase, state, impact and sticking counts, `v`'s sign: the shared event map. Its time
    /// `map.t` is the time since the last section `k_base T_f` (s). The forcing is
    /// `T_f`-periodic, so each period runs on a fresh clock: absolute times near `10^4 T_f`
    /// would leave too few bits for the event tolerance (an ulp of 1000 s is 2e-13 s) and for
    /// the forcing phase.
    map: EventMap<'a, Forced>,
    req: &'a Request,
    scene: &'a Harmonic,
    noise: Option<(&'a NoiseSettings, &'a mut NoiseStream)>,
    probe: &'a mut P,
    omega: f64,
    t_f: f64,
    k_base: u64,
    /// The next section to stop at (section 0 at t = 0: a Limit at t = 0 is handled like every
    /// other section).
    k_next: u64,
    window: Option<Window>,
    history: History,
    n_trans: u64,
    converged: bool,
    next_trace: u64,
    next_noise: u64,
}

impl<'a, P: Probe> Run<'a, P> {
    /// A run on `map` at `t = 0`, before its first section, at the forcing frequency `omega`.
    fn new(
        map: EventMap<'a, Forced>,
        req: &'a Request,
        scene: &'a Harmonic,
        noise: Option<(&'a NoiseSettings, &'a mut NoiseStream)>,
        probe: &'a mut P,
        omega: f64,
    ) -> Self {
        Run {
            map,
            req,
            scene,
            noise,
            probe,
            omega,
            t_f: std::f64::consts::TAU / omega,
            k_base: 0,
            k_next: 0,
            window: None,
            history: History::default(),
            n_trans: 0,
            converged: false,
            next_trace: 0,
            next_noise: 0,
        }
    }

    /// Back to the run [`Run::new`] builds, at `s` ([`simulate_periods`]).
    fn restart(&mut self, s: State) {
        self.map.restart(s);
        self.k_base = 0;
        self.k_next = 0;
        self.window = None;
        self.history = History::default();
        self.n_trans = 0;
        self.converged = false;
        self.next_trace = 0;
        self.next_noise = 0;
    }

    /// Local time of section `k` (`k >= k_base`).
    fn section_time(&self, k: u64) -> f64 {
        (k - self.k_base) as f64 * self.t_f
    }

    /// Absolute time of the local origin, `k_base T_f`.
    fn base(&self) -> f64 {
        self.k_base as f64 * self.t_f
    }

    /// Absolute time now.
    fn now(&self) -> f64 {
        self.base() + self.map.t
    }

    /// Local time of the absolute time `t`.
    fn local(&self, t: f64) -> f64 {
        t - self.base()
    }

    fn section(&self) -> Section {
        let s = &self.map.s;
        if self.map.sys.m > 0.0 {
            [s.x, s.v, s.y - s.x, s.w]
        } else {
            [s.x, s.v, 0.0, 0.0]
        }
    }

    fn measuring(&self) -> bool {
        self.window.is_some()
    }

    /// Amplitude from exact extrema (no noise) or from noisy samples.
    fn exact_extrema(&self) -> bool {
        self.measuring() && self.noise.is_none()
    }

    fn energy(&self) -> f64 {
        self.map.energy()
    }

    /// Longest quadrature piece: 1/16 of the fastest period of the motion (forcing, natural,
    /// or the damping rate `C / M` when heavily over-damped).
    fn quadrature_piece(&self) -> f64 {
        let sys = self.map.sys;
        let fastest = self.omega.max(sys.omega()).max(sys.C / sys.M);
        std::f64::consts::TAU / fastest / 16.0
    }

    fn candidate(&mut self, x: f64) {
        if let Some(win) = &mut self.window
            && (win.amplitude.is_nan() || x.abs() > win.amplitude)
        {
            win.amplitude = x.abs();
        }
    }

    /// Handles section `k`; `true` when the window is complete.
    fn at_section(&mut self, k: u64) -> bool {
        let s = self.section();
        let x = self.map.s.x;
        if let Some(win) = &mut self.window {
            win.sections.push(s);
            if k == self.n_trans + self.scene.n_meas {
                self.candidate(x);
                return true;
            }
            return false;
        }
        // Transient periods run so far (what a run that stops early reports).
        self.n_trans = k;
        let done = match self.scene.n_trans {
            Some(n) => k >= n,
            // The history serves only the convergence test of a transient of open length (a
            // life measurement's one-period runs keep none: no allocation per period).
            None => {
                self.history.push(s, self.map.sys.omega());
                self.converged =
                    transient_converged(&self.history, self.omega, self.scene.trans_tol);
                self.converged || k >= self.scene.n_trans_max
            }
        };
        if done {
            self.n_trans = k;
            self.window = Some(Window {
                amplitude: f64::NAN,
                impacts: 0,
                sections: {
                    // Every section of the window, allocated once (the first 1,024).
                    let mut v = Vec::with_capacity((self.scene.n_meas as usize + 1).min(1024));
                    v.push(s);
                    v
                },
                energy_force: 0.0,
                energy_viscous: 0.0,
                energy_impact: 0.0,
                piece: self.map.t,
            });
            self.map.v_side = self.map.v_sign();
            if self.noise.is_none() {
                self.candidate(x);
            } else if let Some((ns, _)) = &self.noise {
                self.next_noise = (self.now() / ns.sample_time).ceil() as u64;
                // A sample due exactly now is taken by the Limit that follows at once.
            }
        }
        false
    }

    /// Trace and noise samples due now.
    fn samples(&mut self) {
        if let Some(dt) = self.req.trace_dt
            && self.local(self.next_trace as f64 * dt) <= self.map.t
        {
            let now = self.now();
            self.probe.sample(now, &self.map.s);
            self.next_trace += 1;
        }
        let base = self.base();
        if self.measuring()
            && let Some((ns, stream)) = &mut self.noise
        {
            let k = self.next_noise;
            if k as f64 * ns.sample_time - base <= self.map.t {
                let measured = self.map.s.x + stream.sample(k, ns);
                self.next_noise = k + 1;
                self.candidate(measured);
            }
        }
    }

    fn finish(self, outcome: Outcome, steps: u64) -> HarmonicRecord {
        let sys = self.map.sys;
        let scene = self.scene;
        let r = scene.ratio(sys);
        let amplitude_linear = sys.linear_amplitude(scene.F0, r);
        let nan = f64::NAN;
        let ok = outcome == Outcome::Ok;
        let (amplitude, ipp, period, ef, ev, ei) = match (&self.window, ok) {
            (Some(w), true) => (
                w.amplitude,
                w.impacts as f64 / scene.n_meas as f64,
                section_period(&w.sections, self.omega, sys.omega(), scene.period_tol),
                w.energy_force,
                w.energy_viscous,
                w.energy_impact,
            ),
            _ => (nan, nan, 0, nan, nan, nan),
        };
        HarmonicRecord {
            outcome,
            F0: scene.F0,
            omega: self.omega,
            r,
            amplitude,
            impacts_per_period: ipp,
            period,
            amplitude_linear,
            attenuation: amplitude / amplitude_linear,
            n_trans: self.n_trans,
            converged: self.converged,
            n_meas: scene.n_meas,
            energy_force: ef,
            energy_viscous: ev,
            energy_impact: ei,
            impacts: self.map.impacts,
            sticks: self.map.sticks,
            end: self.map.s,
            t_stop: self.now(),
            steps,
            steady: super::Steady::NONE,
        }
    }
}

/// The harmonic scene on the event map: extrema in the window, samples, sections, the window's
/// energies.
impl<'a, P: Probe, S: Stepper> SceneEvents<'a, S> for Run<'a, P> {
    fn map(&self) -> &EventMap<'a, Forced> {
        &self.map
    }

    fn map_mut(&mut self) -> &mut EventMap<'a, Forced> {
        &mut self.map
    }

    fn watch(&self) -> Watch {
        let mut t_limit = self.section_time(self.k_next);
        if let Some(dt) = self.req.trace_dt {
            t_limit = t_limit.min(self.local(self.next_trace as f64 * dt));
        }
        if self.measuring()
            && let Some((ns, _)) = &self.noise
        {
            t_limit = t_limit.min(self.local(self.next_noise as f64 * ns.sample_time));
        }
        // A sample due at a time that rounds to just before now is taken now.
        let t_limit = t_limit.max(self.map.t);
        let (walls, sep_side) = match self.map.phase {
            // `m = 0` is the primary system alone: a massless inner mass cannot act on it (the
            // map carries it along where it started in the cavity).
            Phase::Free if self.map.sys.m == 0.0 => (None, None),
            _ => self.map.contact(),
        };
        Watch {
            walls,
            x_side: None,
            v_side: self.exact_extrema().then_some(self.map.v_side),
            x_floor: self.scene.x_floor,
            sep_side,
            t_limit,
        }
    }

    /// Integrates the window's energies over the smooth piece just travelled.
    fn synced(&mut self, solver: &S) {
        let t = self.map.t;
        let (f0, c) = (self.scene.F0, self.map.sys.C);
        let omega = self.omega;
        let h_max = self.quadrature_piece();
        if let Some(win) = &mut self.window
            && self.scene.energies
        {
            let (wf, wv) = gauss_legendre(win.piece, t, h_max, |tt| {
                let v = solver.at(tt).v;
                (f0 * (omega * tt).cos() * v, c * v * v)
            });
            win.energy_force += wf;
            win.energy_viscous += wv;
            win.piece = t;
        }
        let e = self.energy();
        let now = self.now();
        self.probe.energy(now, e);
    }

    fn at_wall(&mut self) {
        if self.exact_extrema() {
            self.candidate(self.map.s.x);
        }
    }

    /// Probes the impact (and the sticking), and books it in the window: the drop of
    /// `(M x'^2 + m y'^2 + K x^2) / 2` over the impact and any plastic closing.
    fn impacted(&mut self, hit: &Hit) {
        let sys = self.map.sys;
        let e_before = if self.map.several() {
            // One impact of several units: booked once, at its first unit.
            hit.lead.unwrap_or(f64::NAN)
        } else {
            sys.energy(hit.before.x, hit.before.v, hit.before.w)
        };
        let now = self.now();
        self.probe
            .impact_of(now, hit.unit, hit.wall, &hit.before, &hit.after);
        if hit.stuck {
            self.probe.stick(now, hit.wall, &self.map.s);
        }
        let e_after = self.energy();
        if let Some(win) = &mut self.window
            && !e_before.is_nan()
        {
            win.impacts += 1;
            win.energy_impact += e_before - e_after;
        }
        self.probe.energy(now, e_after);
    }

    fn separated(&mut self, wall: Wall) {
        let now = self.now();
        self.probe.separate(now, wall, &self.map.s);
    }

    fn v_zero(&mut self) {
        self.candidate(self.map.s.x);
    }

    fn limit(&mut self, solver: &mut S) -> Option<Outcome> {
        self.samples();
        if self.map.t >= self.section_time(self.k_next) {
            if self.at_section(self.k_next) {
                return Some(Outcome::Ok);
            }
            // A fresh clock for the next period (see `map`).
            self.k_base = self.k_next;
            self.map.t = 0.0;
            if let Some(win) = &mut self.window {
                win.piece = 0.0;
            }
            self.map.begin(solver);
            self.k_next += 1;
        }
        None
    }
}

/// Distance between two sections (m): `sqrt(dx^2 + (dx'/wn)^2 + dz^2 + (dy'/wn)^2)`, velocities
/// scaled by the natural frequency `wn = sqrt(K/M)`. In this norm a decaying free oscillation
/// has differences of steadily shrinking size (nearly `|lambda|^k`), whatever it turns by in a
/// forcing period; with the forcing frequency instead, a slow free part at `r >> 1` would show
/// as differences that come and go with its phase, and fake a converged section.
fn distance(a: &Section, b: &Section, wn: f64) -> f64 {
    let (dx, dv, dz, dw) = (
        a[0] - b[0],
        (a[1] - b[1]) / wn,
        a[2] - b[2],
        (a[3] - b[3]) / wn,
    );
    (dx * dx + dv * dv + dz * dz + dw * dw).sqrt()
}

/// The scale `max(|x|, |x'| / omega)` over sections.
fn scale(sections: &[Section], omega: f64) -> f64 {
    sections
        .iter()
        .map(|s| s[0].abs().max(s[1].abs() / omega))
        .fold(0.0, f64::max)
}

/// The latest [`HISTORY`] sections of a transient, each with its [`distance`]s to the
/// [`MAX_PERIOD`] sections before it, taken once when it arrives (the transient's test reads
/// each up to three times). Empty until the first section: a run of one period (a map
/// evaluation) allocates nothing for it.
#[derive(Default)]
struct History {
    sections: Vec<Section>,
    /// `back[i][p - 1]` = `distance(sections[i], sections[i - p])`.
    back: Vec<[f64; MAX_PERIOD]>,
}

impl History {
    fn push(&mut self, s: Section, wn: f64) {
        if self.sections.len() == HISTORY {
            self.sections.remove(0);
            self.back.remove(0);
        }
        let n = self.sections.len();
        let mut back = [f64::NAN; MAX_PERIOD];
        for p in 1..=MAX_PERIOD.min(n) {
            back[p - 1] = distance(&s, &self.sections[n - p], wn);
        }
        self.sections.push(s);
        self.back.push(back);
    }
}

/// The default transient's test on the latest sections (module doc of [`super`]).
fn transient_converged(history: &History, omega: f64, tol: f64) -> bool {
    let h = &history.sections;
    let back = |i: usize, p: usize| history.back[i][p - 1];
    let n = h.len();
    let Some(last) = n.checked_sub(1) else {
        return false;
    };
    // The scale of the last `p + 1` sections, grown by one section per `p` (a running maximum:
    // the same value as `scale(&h[last - p..], omega)`).
    let mut l = scale(&h[last..], omega);
    for p in 1..=MAX_PERIOD {
        if n < p + 1 {
            break;
        }
        l = l.max(scale(&h[last - p..=last - p], omega));
        let d0 = back(last, p);
        if d0 <= 16.0 * f64::EPSILON * l {
            return true;
        }
        if n < 3 * p + 1 {
            continue;
        }
        let (d1, d2) = (back(last - p, p), back(last - 2 * p, p));
        let rho = (d0 / d1).max(d1 / d2);
        if rho < 1.0 && d0 / (1.0 - rho) <= tol * l {
            return true;
        }
    }
    false
}

/// Smallest `p` in `1..=8` whose sections repeat over the whole window, else 0. Every one of
/// the `p` phases must be compared at least once (`n >= 2p - 1` for `n + 1` sections).
fn section_period(w: &[Section], omega: f64, wn: f64, tol: f64) -> u32 {
    let l = scale(w, omega);
    let n = w.len().saturating_sub(1);
    (1..=MAX_PERIOD.min(n.div_ceil(2)))
        .find(|&p| (0..=n - p).all(|j| distance(&w[j + p], &w[j], wn) <= tol * l))
        .map_or(0, |p| p as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::harmonic::Drive;

    #[test]
    fn several_units_spare_only_searches_that_cannot_win() {
        // `EventMap::find` spares the searches of units that cannot stop first; checked at every
        // call against the search of every unit from the same point. Where that one stops at a
        // wall, the spared one is the same bits (the state, the event, every unit's hit); where
        // it stops at an extremum or the period's end, the spared one stops no sooner (another
        // clone's placing of the same extremum, or one under the floor reported at the end of
        // another step). 2, 4 and 8 units, equal and spread clearances, chaotic and periodic
        // points, every extremum located and the design life's floor.
        use crate::sim::phase::sparing;
        let (mut calls, mut walls, mut later, mut worst) = (0, 0, 0, 0.0f64);
        let settings = SolverSettings::default();
        for (units, d_spread) in [(2.0, 0.5), (4.0, 0.25), (8.0, 0.5), (8.0, 0.0)] {
            for (d, r) in [(0.01, 0.97), (0.01, 1.0), (0.005, 0.9), (0.02, 1.1)] {
                for x_floor in [0.0, 0.6 * d] {
                    let sys = System {
                        m: 0.01,
                        d,
                        units,
                        d_spread,
                        e: 0.8,
                        x0: 0.003,
                        v0: 0.05,
                        ..System::TABLE_I
                    };
                    let scene = Harmonic {
                        F0: 0.1,
                        drive: Drive::Ratio(r),
                        n_trans: Some(150),
                        n_meas: 50,
                        energies: false,
                        x_floor,
                        ..Harmonic::default()
                    };
                    let req = Request::default();
                    let t = sparing::check(|| {
                        simulate_harmonic(&sys, &settings, &req, &scene, None, &mut NoProbe);
                    });
                    (calls, walls, later) = (calls + t.calls, walls + t.walls, later + t.later);
                    worst = worst.max(t.worst_later);
                }
            }
        }
        eprintln!(
            "{calls} searches of several units, {walls} at a wall (the same bits), {later} \
             stopping later at an event of the scene (at most {worst:.2e} of the watch's span)"
        );
        assert!(walls > 20_000 && calls > walls, "{calls} {walls}");
        assert!(later * 20 < calls, "{later} of {calls}");
    }

    #[test]
    fn period_of_a_repeating_sequence() {
        let a = [1.0, 0.0, 0.0, 0.0];
        let b = [-1.0, 0.0, 0.0, 0.0];
        let c = [0.5, 0.0, 0.0, 0.0];
        assert_eq!(section_period(&[a, a, a], 1.0, 1.0, 1e-9), 1);
        assert_eq!(section_period(&[a, b, a, b, a], 1.0, 1.0, 1e-9), 2);
        assert_eq!(section_period(&[a, b, c, a, b, c, a], 1.0, 1.0, 1e-9), 3);
        assert_eq!(section_period(&[a, b, c, b, a], 1.0, 1.0, 1e-9), 0);
    }

    #[test]
    fn a_geometric_transient_converges_once_its_tail_is_small() {
        // x_k = 1 + 0.5^k (a contraction toward 1): the tail after k is 0.5^k.
        let history = |n: i32| {
            let mut h = History::default();
            for k in 0..n {
                h.push([1.0 + 0.5f64.powi(k), 0.0, 0.0, 0.0], 1.0);
            }
            h
        };
        assert!(!transient_converged(&history(10), 1.0, 1e-4));
        assert!(transient_converged(&history(25), 1.0, 1e-6));
    }
}
