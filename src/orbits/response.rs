//! Every steady state of one frequency-response curve: the attractor census at each swept
//! frequency, then the periodic attractors followed along the frequency by continuation.
//!
//! The census ([`super::census`]) runs at every swept frequency, in the up and down passes of
//! [`super::curve`] (each frequency also continues its neighbours' attractors: the transient
//! sweeps up and down the band, which reach the branches of a hysteresis loop that fixed starts
//! can all miss). A sweep stores those attractors; `reduce` follows branches from them
//! ([`branches`]) without a census. Periodic impacting attractors seed continuation
//! ([`super::continuation`]) in frequency order; an attractor that
//! lies on a branch already followed (same period and impacts, amplitude within `1e-3` of the
//! branch interpolated at its frequency) seeds nothing, so a curve costs a few branches, not one
//! per frequency. At most [`MAX_BRANCHES`] branches are followed per curve (doubled branches
//! included); the census still reports every attractor. The non-impacting family is a branch of
//! its own, in closed form ([`super::shoot::non_impacting`]): its rows are `neutral` wherever it
//! exists (`A <= d/2`).

use super::attractors::{AttractorRow, RunId};
use super::census::{Census, CensusSettings, Kind};
use super::continuation::{Branch, ContSettings, Param, follow};
use super::curve::census_passes;
use super::label::Label;
use super::map::{Forcing, Section};
use super::shoot::{
    Newton, Orbit, Stability, Termination, non_impacting, orbit_at, same_orbit, solve,
};

/// Most branches followed per curve.
pub const MAX_BRANCHES: usize = 16;

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
    /// The Floquet multipliers `(re, im)`, by decreasing modulus.
    pub multipliers: [(f64, f64); 4],
    /// The smallest approach speed of an impact over the orbit (m/s; `inf` without impacts).
    pub min_impact_speed: f64,
    pub label: &'static str,
    /// The row is the located point of its label (docs/model.md, §12); a label on a row that is
    /// not located sits on the first point past a change that could not be solved for (the map
    /// is not smooth there).
    pub located: bool,
    /// How the branch ended at this end (on its first and last rows; `""` elsewhere).
    pub end: &'static str,
    /// Where the branch ends at a grazing (`end = "grazing_end"`), what the motion becomes
    /// there: `chaos`, `jump` or `none` ([`super::continuation::GrazingOutcome`]); `""`
    /// elsewhere.
    pub grazing_outcome: &'static str,
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
    /// Forcing periods simulated by the census (its up and down passes) and by continuation.
    pub periods_census: u64,
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
/// census runs at each value, in the up and down passes of a sweep's curve
/// ([`super::curve::census_passes`], every start from `s0`), and continuation follows `param`
/// (the frequency ratio, or the force amplitude `F0` at `base`'s frequency) from every periodic
/// impacting attractor ([`branches`]).
pub fn analyse_along(
    base: &Forcing,
    design: u64,
    s0: &Section,
    values: &[(u64, f64)],
    param: Param,
    settings: &CensusSettings,
) -> Response {
    let points: Vec<_> = values
        .iter()
        .map(|&(point, v)| {
            Some((
                param.at(base, v),
                CensusSettings { point, ..*settings },
                *s0,
            ))
        })
        .collect();
    let censuses = census_passes(&points);
    let mut out = Response {
        design,
        ..Response::default()
    };
    let mut seeds = Vec::new();
    for (&(point, v), c) in values.iter().zip(&censuses) {
        let Some(c) = c else { continue };
        let f = param.at(base, v);
        out.periods_census += c.periods;
        push_attractors(&mut out, c, point, &f);
        for a in &c.attractors {
            if let Kind::Periodic(o) = &a.kind
                && o.impacts > 0
            {
                seeds.push((f.clone(), o.clone()));
            }
        }
    }
    let (branches, periods) = branches(base, design, s0, values, param, seeds);
    out.branches = branches;
    out.periods_continuation = periods;
    out
}

/// The periodic branches of one curve: every seed (a periodic impacting attractor at a point of
/// the curve, in the curve's order) followed along `param` over the range of `values`, unless it
/// lies on a branch already followed (module doc), at most [`MAX_BRANCHES`]; then the
/// non-impacting family in closed form (placed at `s0`'s inner-mass position). Returns the rows
/// and the forcing periods continuation simulated.
pub fn branches(
    base: &Forcing,
    design: u64,
    s0: &Section,
    values: &[(u64, f64)],
    param: Param,
    seeds: Vec<(Forcing, Box<Orbit>)>,
) -> (Vec<BranchRow>, u64) {
    let mut out = Response::default();
    let Some((lo, hi, h0)) = curve_steps(values) else {
        return (Vec::new(), 0);
    };
    let cont = ContSettings {
        range: (lo, hi),
        h0,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 2000,
        switch_pd: true,
    };
    let mut followed: Vec<Branch> = Vec::new();
    for (f, orbit) in seeds {
        if followed.len() >= MAX_BRANCHES {
            break;
        }
        if followed.iter().any(|b| covers(b, &f, &orbit, param)) {
            continue;
        }
        for b in follow(&f, &orbit, param, &cont) {
            out.periods_continuation += b.periods;
            if followed.len() < MAX_BRANCHES {
                followed.push(b);
            }
        }
    }
    for (i, b) in followed.iter().enumerate() {
        push_branch(&mut out, design, i as u32, b);
    }
    push_family(
        &mut out,
        design,
        followed.len() as u32,
        base,
        values,
        param,
        s0,
    );
    branch_points_met(&mut out.branches);
    (out.branches, out.periods_continuation)
}

/// The range `(lo, hi)` of a curve's values (`(point, value)`) and the continuation's first
/// step `h0`: one step of the curve relative to `lo`, at least `1e-3`. `None` for a curve of one
/// value.
pub fn curve_steps(values: &[(u64, f64)]) -> Option<(f64, f64, f64)> {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, r)| {
            (a.min(r), b.max(r))
        });
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let step = (hi - lo) / (values.len().max(2) - 1) as f64;
    Some((lo, hi, (step / lo).max(1e-3)))
}

/// A bifurcation seen from the branch born there. Where the symmetric orbit's branch has a
/// located `BP`, the asymmetric pair born there turns back in the parameter (its two halves are
/// mirror images with the same amplitude), so along it the point is located as a fold; where a
/// branch of period `p` has a located `PD`, the doubled branch (of `P^{2p}`, whose two halves are
/// one orbit shifted by `p` periods) turns back there too. Such an `SN` (the same parameter to
/// `1e-4` relative, the same amplitude to `1e-3` relative, near the degenerate point where the
/// corrector is least accurate, and the period of a `BP` or twice that of a `PD`) is relabelled
/// with the other branch's label.
fn branch_points_met(rows: &mut [BranchRow]) {
    let marks: Vec<(u32, f64, f64, f64, u32, &'static str)> = rows
        .iter()
        .filter(|b| b.label == Label::BP.name() || b.label == Label::PD.name())
        .map(|b| {
            let p = if b.label == Label::PD.name() {
                2 * b.period
            } else {
                b.period
            };
            (b.branch, b.r, b.F0, b.amplitude, p, b.label)
        })
        .collect();
    let near = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * a.abs().max(b.abs());
    for b in rows.iter_mut().filter(|b| b.label == Label::SN.name()) {
        if let Some(m) = marks.iter().find(|&&(br, r, f0, amp, p, _)| {
            br != b.branch
                && near(r, b.r, 1e-4)
                && near(f0, b.F0, 1e-4)
                && near(amp, b.amplitude, 1e-3)
                && p == b.period
        }) {
            b.label = m.5;
        }
    }
}

/// The periodic impacting orbit at `f` whose section `s` a stored attractor gives (its period
/// `p`): Newton from there (it converges at once: the section is the orbit's to Newton's
/// tolerance) and the orbit's multipliers; `None` when it no longer converges to a stable
/// impacting orbit.
pub fn orbit_from_section(f: &Forcing, s: &Section, p: u32) -> Option<Box<Orbit>> {
    let newton = Newton::default();
    let p = u64::from(p.max(1));
    match solve(f, p, s, &newton) {
        (Termination::Converged { .. }, Some(st)) => {
            let o = orbit_at(f, p, &st, &newton)?;
            (o.stability == Stability::Stable).then(|| Box::new(o))
        }
        _ => None,
    }
}

/// The census's rows for the design point `point` (its ideal case; `point_id = point`).
fn push_attractors(out: &mut Response, c: &Census, point: u64, f: &Forcing) {
    let run = RunId {
        point_id: point,
        point,
        case: 0,
        ideal: true,
        r: f.ratio(),
        omega: f.omega,
        F0: f.F0,
    };
    out.attractors
        .extend(AttractorRow::of_census(run, c, f.period()));
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
        let (end, outcome) = if k == 0 {
            (b.ends.0.name(), b.outcomes.0)
        } else if k + 1 == n {
            (b.ends.1.name(), b.outcomes.1)
        } else {
            ("", None)
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
            multipliers: p.multipliers,
            min_impact_speed: p.min_impact_speed,
            label: p.label.name(),
            located: p.located,
            end,
            grazing_outcome: outcome.map_or("", |o| o.name()),
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
                    multipliers: std::array::from_fn(|i| {
                        o.multipliers
                            .get(i)
                            .copied()
                            .unwrap_or((f64::NAN, f64::NAN))
                    }),
                    min_impact_speed: o.min_impact_speed,
                    label: "",
                    located: false,
                    end: "",
                    grazing_outcome: "",
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
