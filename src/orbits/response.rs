//! Every steady state of one frequency-response curve: the attractor census at each swept
//! frequency, then the periodic attractors followed along the frequency by continuation.
//!
//! The census ([`super::census`]) runs at every swept frequency. Its periodic impacting
//! attractors seed continuation ([`super::continuation`]) in frequency order, then those of two
//! transient sweeps, up and down the frequencies, each frequency starting where the previous
//! one settled (the branches of a hysteresis loop, which fixed starts can all miss); an attractor that
//! lies on a branch already followed (same period and impacts, amplitude within `1e-3` of the
//! branch interpolated at its frequency) seeds nothing, so a curve costs a few branches, not one
//! per frequency. At most [`MAX_BRANCHES`] branches are followed per curve (doubled branches
//! included); the census still reports every attractor. The non-impacting family is a branch of
//! its own, in closed form ([`super::shoot::non_impacting`]): its rows are `neutral` wherever it
//! exists (`A <= d/2`).

use super::census::{Census, CensusSettings, Kind, Landing, census, settle};
use super::continuation::{Branch, ContSettings, Label, Param, follow};
use super::map::{Forcing, Section};
use super::shoot::{Newton, Orbit, Stability, Termination, non_impacting, same_orbit, solve};

/// Most branches followed per curve.
pub const MAX_BRANCHES: usize = 16;

/// One attractor at one frequency.
#[derive(Clone, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct AttractorRow {
    /// The design point of this frequency.
    pub point: u64,
    pub r: f64,
    pub omega: f64,
    /// The force amplitude (N): the curve's parameter in a study along `F0`.
    pub F0: f64,
    /// Index of the attractor at this frequency (0: the one reached from the initial state).
    pub attractor: u32,
    /// `periodic` or `non-periodic`.
    pub kind: &'static str,
    pub period: u32,
    pub amplitude: f64,
    pub impacts_per_period: f64,
    pub basin_share: f64,
    pub starts: u32,
    /// `stable`, `unstable` (never, for an attractor), `neutral` (the non-impacting family) or
    /// `""` for a motion that is not periodic.
    pub stability: &'static str,
}

/// One continuation point.
#[derive(Clone, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct BranchRow {
    /// The design (a point of the design grid, without the frequency).
    pub design: u64,
    pub branch: u32,
    pub r: f64,
    pub omega: f64,
    pub F0: f64,
    pub amplitude: f64,
    pub period: u32,
    pub impacts_per_period: f64,
    pub stable: bool,
    pub stability: &'static str,
    pub multiplier_max: f64,
    pub label: &'static str,
    /// How the branch ended at this end (on its first and last rows; `""` elsewhere).
    pub end: &'static str,
    /// The orbit's section state at forcing phase 0 (not a table column: for starting Newton
    /// on the branch).
    pub s: Section,
}

/// The steady states of one curve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Response {
    /// The design analysed.
    pub design: u64,
    pub attractors: Vec<AttractorRow>,
    pub branches: Vec<BranchRow>,
    /// Forcing periods simulated by the census, by the two sweeps and by continuation.
    pub periods_census: u64,
    pub periods_sweeps: u64,
    pub periods_continuation: u64,
}

/// Analyses the curve of `base` (whose frequency is irrelevant) over `freqs`, each a
/// `(design point, r)`, from the initial section `s0`. `census` gives the census's settings
/// (its `point` is replaced by each frequency's design point).
pub fn analyse(
    base: &Forcing,
    design: u64,
    s0: &Section,
    freqs: &[(u64, f64)],
    settings: &CensusSettings,
) -> Response {
    analyse_along(base, design, s0, freqs, Param::Ratio, settings)
}

/// [`analyse`] along either parameter: `values` are `(design point, value of param)`; the
/// census runs at each value and continuation follows `param` (the frequency ratio, or the
/// force amplitude `F0` at `base`'s frequency).
pub fn analyse_along(
    base: &Forcing,
    design: u64,
    s0: &Section,
    values: &[(u64, f64)],
    param: Param,
    settings: &CensusSettings,
) -> Response {
    let freqs = values;
    let mut out = Response {
        design,
        ..Response::default()
    };
    let mut seeds = Vec::new();
    for &(point, v) in freqs {
        let f = param.at(base, v);
        let c = census(&f, s0, &CensusSettings { point, ..*settings });
        out.periods_census += c.periods;
        push_attractors(&mut out, &c, point, &f);
        for a in &c.attractors {
            if let Kind::Periodic(o) = &a.kind
                && o.impacts > 0
            {
                seeds.push((f.clone(), o.clone()));
            }
        }
    }
    seeds.extend(sweep_seeds(base, &mut out, s0, freqs, param, settings));
    let (lo, hi) = freqs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, r)| {
            (a.min(r), b.max(r))
        });
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return out;
    }
    let step = (hi - lo) / (freqs.len().max(2) - 1) as f64;
    let cont = ContSettings {
        range: (lo, hi),
        h0: (step / lo).max(1e-3),
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 400,
        switch_pd: true,
    };
    let mut branches: Vec<Branch> = Vec::new();
    for (f, orbit) in seeds {
        if branches.len() >= MAX_BRANCHES {
            break;
        }
        if branches.iter().any(|b| covers(b, &f, &orbit, param)) {
            continue;
        }
        for b in follow(&f, &orbit, param, &cont) {
            out.periods_continuation += b.periods;
            if branches.len() < MAX_BRANCHES {
                branches.push(b);
            }
        }
    }
    for (i, b) in branches.iter().enumerate() {
        push_branch(&mut out, design, i as u32, b);
    }
    push_family(
        &mut out,
        design,
        branches.len() as u32,
        base,
        freqs,
        param,
        s0,
    );
    out
}

/// The periodic impacting orbits two transient sweeps land on: up and then down the swept
/// frequencies, each frequency starting where the previous one settled ([`settle`]), the first
/// from `s0`. Inside a hysteresis loop each sweep stays on its own branch until that branch
/// ends, so they reach orbits whose basins the census's fixed starts may all miss.
fn sweep_seeds(
    base: &Forcing,
    out: &mut Response,
    s0: &Section,
    freqs: &[(u64, f64)],
    param: Param,
    settings: &CensusSettings,
) -> Vec<(Forcing, Box<Orbit>)> {
    let newton = Newton::default();
    let up: Vec<f64> = freqs.iter().map(|f| f.1).collect();
    let down: Vec<f64> = up.iter().rev().copied().collect();
    let mut seeds = Vec::new();
    for rs in [up, down] {
        let mut s = *s0;
        for v in rs {
            let f = param.at(base, v);
            let st = settle(&f, &s, settings, &newton);
            out.periods_sweeps += st.periods;
            s = st.end;
            if let Landing::Orbit(o) = st.landing
                && o.impacts > 0
            {
                seeds.push((f, Box::new(o)));
            }
        }
    }
    seeds
}

fn push_attractors(out: &mut Response, c: &Census, point: u64, f: &Forcing) {
    for (i, a) in c.attractors.iter().enumerate() {
        let stability = match &a.kind {
            Kind::Periodic(o) => o.stability.name(),
            Kind::NonPeriodic => "",
        };
        out.attractors.push(AttractorRow {
            point,
            r: f.ratio(),
            omega: f.omega,
            F0: f.F0,
            attractor: i as u32,
            kind: a.kind_name(),
            period: a.period,
            amplitude: a.amplitude,
            impacts_per_period: a.impacts_per_period,
            basin_share: c.share(i),
            starts: a.starts,
            stability,
        });
    }
}

/// Whether branch `b` passes through `orbit` (a fixed point at `f`): two consecutive points of
/// the branch with the orbit's period and impacts bracket its frequency, and either the
/// branch's amplitude interpolated there is within `1e-3` of the orbit's, or Newton at `f`'s
/// frequency from the branch's section interpolated there converges to the same orbit
/// ([`same_orbit`]).
pub fn covers(b: &Branch, f: &Forcing, orbit: &Orbit, param: Param) -> bool {
    let r = param.get(f);
    let p = u64::from(orbit.period);
    b.points.windows(2).any(|w| {
        let (a, c) = (&w[0], &w[1]);
        let alike = |q: &super::continuation::BranchPoint| {
            q.period == orbit.period && q.impacts == orbit.impacts
        };
        if !alike(a) || !alike(c) {
            return false;
        }
        let (lo, hi) = if a.value(param) <= c.value(param) {
            (a, c)
        } else {
            (c, a)
        };
        let (l, h) = (lo.value(param), hi.value(param));
        if r < l || r > h {
            return false;
        }
        let t = if h > l { (r - l) / (h - l) } else { 0.0 };
        let amp = lo.amplitude + t * (hi.amplitude - lo.amplitude);
        if (amp - orbit.amplitude).abs() <= 1e-3 * orbit.amplitude {
            return true;
        }
        let s: Section = std::array::from_fn(|k| lo.s[k] + t * (hi.s[k] - lo.s[k]));
        matches!(
            solve(f, p, &s, &Newton::default()),
            (Termination::Converged { .. }, Some(st)) if same_orbit(f, &st.s, &orbit.s, p)
        )
    })
}

fn push_branch(out: &mut Response, design: u64, branch: u32, b: &Branch) {
    let n = b.points.len();
    for (k, p) in b.points.iter().enumerate() {
        let end = if k == 0 {
            b.ends.0.name()
        } else if k + 1 == n {
            b.ends.1.name()
        } else {
            ""
        };
        out.branches.push(BranchRow {
            design,
            branch,
            r: p.r,
            omega: p.omega,
            F0: p.F0,
            amplitude: p.amplitude,
            period: p.period,
            impacts_per_period: p.impacts_per_period(),
            stable: p.stable,
            stability: if p.stable { "stable" } else { "unstable" },
            multiplier_max: p.multiplier_max,
            label: p.label.name(),
            end,
            s: p.s,
        });
    }
}

/// The non-impacting family at the swept frequencies where it exists, as one branch per
/// stretch (closed form; `neutral`).
fn push_family(
    out: &mut Response,
    design: u64,
    first: u32,
    base: &Forcing,
    freqs: &[(u64, f64)],
    param: Param,
    s0: &Section,
) {
    let mut branch = first;
    let mut open = false;
    for &(_, v) in freqs {
        let f = param.at(base, v);
        let r = f.ratio();
        match non_impacting(&f, s0[0] + s0[2]) {
            Some(o) if f.sys.m > 0.0 => {
                out.branches.push(BranchRow {
                    design,
                    branch,
                    r,
                    omega: f.omega,
                    F0: f.F0,
                    amplitude: o.amplitude,
                    period: 1,
                    impacts_per_period: 0.0,
                    stable: false,
                    stability: Stability::Neutral.name(),
                    multiplier_max: o.multiplier_max(),
                    label: "",
                    end: "",
                    s: o.s,
                });
                open = true;
            }
            _ => {
                if open {
                    if let Some(last) = out.branches.last_mut() {
                        last.label = Label::NI.name();
                        last.end = "impacts_begin";
                    }
                    branch += 1;
                }
                open = false;
            }
        }
    }
}
