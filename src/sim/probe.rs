//! Observers of a run's events ([`Probe`], [`TraceProbe`], [`NoProbe`]). Below the scenes and
//! above the event map's types ([`State`], [`Wall`]); re-exported by [`crate::sim`].

use super::phase::{State, Wall};

/// Observer of a run's events, for traces and tests. Every method defaults to doing nothing, so
/// a sweep pays nothing for it.
pub trait Probe {
    /// An impact at `t` on `wall`: the state just before, as located (its `y - x` is within the
    /// event tolerance of the wall), and just after (inner mass exactly on the wall).
    fn impact(&mut self, _t: f64, _wall: Wall, _before: &State, _after: &State) {}
    /// The same for unit `unit` of several (model.md §14): `before` and `after` hold the main
    /// mass's state and that unit's. By default [`Probe::impact`].
    fn impact_of(&mut self, t: f64, _unit: usize, wall: Wall, before: &State, after: &State) {
        self.impact(t, wall, before, after);
    }
    /// A sticking phase begins at `t` on `wall` (after the plastic closing of a chatter).
    fn stick(&mut self, _t: f64, _wall: Wall, _state: &State) {}
    /// The inner mass leaves `wall` at `t`.
    fn separate(&mut self, _t: f64, _wall: Wall, _state: &State) {}
    /// A trace sample (only with [`Request::trace_dt`](super::request::Request::trace_dt)).
    fn sample(&mut self, _t: f64, _state: &State) {}
    /// Any event, with the total mechanical energy after it (J).
    fn energy(&mut self, _t: f64, _energy: f64) {}
}

/// Collects trace rows: samples every [`Request::trace_dt`](super::request::Request::trace_dt) and the state before every impact.
#[derive(Default)]
pub struct TraceProbe {
    pub rows: Vec<(f64, State)>,
}

impl Probe for TraceProbe {
    fn impact(&mut self, t: f64, _wall: Wall, before: &State, _after: &State) {
        self.rows.push((t, *before));
    }
    fn sample(&mut self, t: f64, state: &State) {
        self.rows.push((t, *state));
    }
}

/// A probe that observes nothing.
pub struct NoProbe;
impl Probe for NoProbe {}
