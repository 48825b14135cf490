//! The steady states of a harmonic study's curves (docs/reduce.md): for each design's ideal
//! case, the attractors the sweep stored at every swept frequency (the `attractors` table) and
//! the periodic branches followed from them along the frequency ([`crate::orbits::response`]),
//! as the `attractors.csv` and `branches` tables.
//!
//! No census runs here: continuation starts from each stored periodic attractor's section
//! (Newton converges at once there). A dataset written before the sweep stored its attractors
//! gets them recomputed, once per design, by the sweep's own census passes
//! ([`crate::orbits::curve::census_passes`]); [`census_starts`] counts the starts that took.
//!
//! The designs are analysed in parallel, by as many threads as the current rayon pool has, and
//! handed over in design order, a batch at a time ([`steady_states_in_batches`]), so the tables
//! are the same for any thread count.

use rayon::prelude::*;

use super::curve::Curve;
use super::summary::HarmonicSummary;
use crate::orbits::attractors::{AttractorRow, SteadyKind};
use crate::orbits::census::CensusSettings;
use crate::orbits::continuation::Param;
use crate::orbits::map::{Forcing, Section};
use crate::orbits::response::{Response, analyse_along, branches, orbit_from_section};
use crate::orbits::{CENSUS_WINDOW, HANDOVER};
use crate::sim::Scene;
use crate::store::table::{Column, Table};
use crate::study::Study;

/// The steady states of every curve of `fs`, in design order: along the frequency when the
/// study sweeps it; otherwise along `F0` when the study sweeps the force (the designs that
/// differ only in `F0` make one curve, analysed as the design of its smallest `F0`). Empty
/// when neither is swept (a "curve" of one point has nothing to follow) or with `starts = 0`.
pub fn steady_states(study: &Study, fs: &HarmonicSummary) -> Vec<Response> {
    let mut all = Vec::new();
    let Ok(()) = steady_states_in_batches::<std::convert::Infallible>(study, fs, |batch| {
        all.extend(batch);
        Ok(())
    });
    all
}

/// Designs whose steady states [`steady_states_in_batches`] hands over at a time, per thread
/// of the pool (a design's branches take 0.4 MB on average on the 41-frequency curves of the
/// 1,000-design study of BENCHMARKS.md, 3.5 MB at most).
pub const BATCH_PER_THREAD: usize = 16;

/// [`steady_states`] a batch of designs at a time, in design order: `each` takes every batch,
/// so the caller holds one batch rather than the study's. A study along `F0` is one batch.
/// Stops at `each`'s first error.
///
/// The designs are analysed by as many threads as the current rayon pool has, each taking the
/// next design when it is done with one (their cost varies a hundredfold: batches analysed in
/// parallel one after the other waited for their slowest design, and the 1,000-design study's
/// `reduce` took 155 s against 135 s); the designs that finish ahead of an earlier one wait for it, so the
/// batches come in design order and the tables are the same for any thread count.
pub fn steady_states_in_batches<E>(
    study: &Study,
    fs: &HarmonicSummary,
    mut each: impl FnMut(Vec<Response>) -> Result<(), E>,
) -> Result<(), E> {
    let Scene::Harmonic(h) = study.scene else {
        return Ok(());
    };
    // The census and the orbits' analysis (model.md §10-12) cover one damper unit: a study
    // of several units reads each frequency's steady state from its run.
    if !study.census() {
        return Ok(());
    }
    if fs.frequency.is_none() {
        let all = along_force(study, &h, fs);
        return if all.is_empty() { Ok(()) } else { each(all) };
    }
    let threads = rayon::current_num_threads().max(1);
    let batch = BATCH_PER_THREAD * threads;
    let n = fs.curves.len();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, Response)>(batch);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let tx = tx.clone();
            let next = &next;
            scope.spawn(move || {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    // A receiver gone (an error in `each`) ends the work too.
                    if i >= n
                        || tx
                            .send((i, along_frequency(study, &h, fs, &fs.curves[i])))
                            .is_err()
                    {
                        break;
                    }
                }
            });
        }
        drop(tx);
        let mut early = std::collections::BTreeMap::new();
        let (mut want, mut ready) = (0, Vec::with_capacity(batch));
        for (i, r) in rx {
            early.insert(i, r);
            while let Some(r) = early.remove(&want) {
                ready.push(r);
                want += 1;
            }
            if ready.len() >= batch {
                each(std::mem::take(&mut ready))?;
            }
        }
        if ready.is_empty() {
            Ok(())
        } else {
            each(ready)
        }
    })
}

/// The steady states of one design's curve along the frequency (what an earlier analysis shard
/// computed, when it did; nothing for a design another shard computes).
fn along_frequency(
    study: &Study,
    h: &crate::sim::Harmonic,
    fs: &HarmonicSummary,
    c: &Curve,
) -> Response {
    let plan = &fs.analysis;
    if let Some(b) = plan.prior.branches_of(c.design) {
        return Response {
            design: c.design,
            attractors: c.attractors.clone().unwrap_or_default(),
            branches: b,
            ..Response::default()
        };
    }
    if !plan.computes_design(c.design) {
        return Response {
            design: c.design,
            ..Response::default()
        };
    }
    let sys = c.system;
    let base = Forcing {
        sys,
        F0: c.f0,
        omega: sys.omega(),
        settings: study.solver,
    };
    let values: Vec<(u64, f64)> = c
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            (
                c.design * study.curve_points() + i as u64,
                p.omega / sys.omega(),
            )
        })
        .collect();
    curve_states(
        study,
        h,
        &base,
        c.design,
        &values,
        Param::Ratio,
        c.attractors.as_deref(),
    )
}

/// Whether `r` holds the steady states the report draws for design `anchor`: its own curve's
/// along the frequency; along `F0`, its group's ([`force_group`]).
pub fn draws_anchor(fs: &HarmonicSummary, anchor: u64, r: &Response) -> bool {
    if fs.frequency.is_some() {
        return r.design == anchor;
    }
    let key = fs.curve(anchor).map(force_group);
    key.is_some() && fs.curve(r.design).map(force_group) == key
}

/// What the bifurcation curves need of a design's steady states once its rows are written
/// ([`super::bifurcations::curves`]): its located points with multipliers, no attractors.
pub fn located_only(r: Response) -> Response {
    let mut branches: Vec<_> = r
        .branches
        .into_iter()
        .filter(|b| b.located && b.multiplier_max.is_finite())
        .collect();
    // The filter reuses the whole table's allocation: give it back.
    branches.shrink_to_fit();
    Response {
        attractors: Vec::new(),
        branches,
        ..r
    }
}

/// The steady states of one curve (`values`: its points as `(design point, value of param)`):
/// the stored attractors (or, for an older dataset, the census recomputed) and the branches
/// followed from their periodic impacting orbits.
fn curve_states(
    study: &Study,
    h: &crate::sim::Harmonic,
    base: &Forcing,
    design: u64,
    values: &[(u64, f64)],
    param: Param,
    stored: Option<&[AttractorRow]>,
) -> Response {
    let s0 = initial_section(&base.sys);
    let Some(rows) = stored else {
        CENSUS_STARTS.fetch_add(
            u64::from(h.starts) * values.len() as u64,
            std::sync::atomic::Ordering::Relaxed,
        );
        return analyse_along(base, design, &s0, values, param, &census_settings(study, h));
    };
    let mut seeds = Vec::new();
    for &(point, v) in values {
        let f = param.at(base, v);
        for a in rows.iter().filter(|a| a.run.point == point) {
            if a.kind == SteadyKind::Periodic
                && let Some(o) = orbit_from_section(&f, &a.section, a.period)
            {
                seeds.push((f.clone(), o));
            }
        }
    }
    let (branches, periods) = branches(base, design, &s0, values, param, seeds);
    Response {
        design,
        attractors: rows.to_vec(),
        branches,
        periods_census: 0,
        periods_continuation: periods,
    }
}

/// Census starts `reduce` ran in this process (only for datasets written before the sweep stored
/// its attractors): a reduction of a current dataset runs none.
static CENSUS_STARTS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Census starts the steady-state analysis has run in this process ([`CENSUS_STARTS`]).
pub fn census_starts() -> u64 {
    CENSUS_STARTS.load(std::sync::atomic::Ordering::Relaxed)
}

fn initial_section(sys: &crate::model::System) -> Section {
    [sys.x0, sys.v0, sys.y0 - sys.x0, sys.w0]
}

/// The key of a one-point curve's group along `F0`: the bits of its ideal system (with its
/// initial state) and its frequency; curves with the same key differ only in `F0`.
pub fn force_group(c: &Curve) -> Vec<u64> {
    let s = &c.system;
    let omega = c.points.first().map_or(f64::NAN, |p| p.omega);
    [s.M, s.m, s.K, s.C, s.e, s.d, s.x0, s.v0, s.y0, s.w0, omega]
        .iter()
        .map(|v| v.to_bits())
        .collect()
}

/// A study at one frequency that sweeps `F0`: its one-point curves grouped by everything but
/// `F0` (the ideal system and the frequency), each group followed along `F0`.
fn along_force(study: &Study, h: &crate::sim::Harmonic, fs: &HarmonicSummary) -> Vec<Response> {
    if !study
        .axes
        .iter()
        .any(|a| a.key == "F0" && a.values.len() >= 2)
    {
        return Vec::new();
    }
    let key = force_group;
    let mut groups: Vec<(Vec<u64>, Vec<&Curve>)> = Vec::new();
    for c in &fs.curves {
        let k = key(c);
        match groups.iter_mut().find(|g| g.0 == k) {
            Some(g) => g.1.push(c),
            None => groups.push((k, vec![c])),
        }
    }
    let plan = &fs.analysis;
    groups
        .par_iter()
        .filter(|g| g.1.len() >= 2)
        .map(|(_, cs)| {
            let mut cs = cs.clone();
            cs.sort_by(|a, b| a.f0.total_cmp(&b.f0));
            let first = cs[0];
            if let Some(b) = plan.prior.branches_of(first.design) {
                return Response {
                    design: first.design,
                    attractors: cs
                        .iter()
                        .flat_map(|c| c.attractors.clone().unwrap_or_default())
                        .collect(),
                    branches: b,
                    ..Response::default()
                };
            }
            if !plan.computes_design(first.design) {
                return Response {
                    design: first.design,
                    ..Response::default()
                };
            }
            let sys = first.system;
            let base = Forcing {
                sys,
                F0: first.f0,
                omega: first.points.first().map_or(sys.omega(), |p| p.omega),
                settings: study.solver,
            };
            let values: Vec<(u64, f64)> = cs.iter().map(|c| (c.design, c.f0)).collect();
            let stored: Option<Vec<AttractorRow>> = cs
                .iter()
                .map(|c| c.attractors.clone())
                .collect::<Option<Vec<_>>>()
                .map(|v| v.concat());
            curve_states(
                study,
                h,
                &base,
                first.design,
                &values,
                Param::Force,
                stored.as_deref(),
            )
        })
        .collect()
}

fn census_settings(study: &Study, h: &crate::sim::Harmonic) -> CensusSettings {
    CensusSettings {
        starts: h.starts,
        max_periods: h.n_trans_max,
        handover: HANDOVER,
        window: CENSUS_WINDOW,
        seed: study.seed,
        point: 0,
        spent0: 0,
    }
}

/// `attractors.csv`: the ideal case's rows of the attractors table, every column of
/// docs/schema.md ("attractors").
pub fn attractors_table(responses: &[Response]) -> Table {
    let rows: Vec<&AttractorRow> = responses.iter().flat_map(|r| &r.attractors).collect();
    attractor_rows_table(&rows)
}

/// The attractors table of `rows`, in the column order of the sweep's parts.
pub fn attractor_rows_table(rows: &[&AttractorRow]) -> Table {
    let mut t = Table::default();
    let f = |g: &dyn Fn(&AttractorRow) -> f64| Column::F64(rows.iter().map(|a| g(a)).collect());
    let u =
        |g: &dyn Fn(&AttractorRow) -> u64| Column::U64(rows.iter().map(|a| Some(g(a))).collect());
    let s = |g: &dyn Fn(&AttractorRow) -> &str| {
        Column::Str(rows.iter().map(|a| g(a).to_string()).collect())
    };
    t.push("point_id", u(&|a| a.run.point_id));
    t.push("point", u(&|a| a.run.point));
    t.push("case", u(&|a| u64::from(a.run.case)));
    t.push(
        "ideal",
        Column::Bool(rows.iter().map(|a| a.run.ideal).collect()),
    );
    t.push("r", f(&|a| a.run.r));
    t.push("omega", f(&|a| a.run.omega));
    t.push("F0", f(&|a| a.run.F0));
    t.push("attractor", u(&|a| u64::from(a.attractor)));
    t.push("kind", s(&|a| a.kind.name()));
    t.push("stability", s(&|a| a.stability));
    t.push("origin", s(&|a| a.origin));
    t.push("period", u(&|a| u64::from(a.period)));
    t.push("starts", u(&|a| u64::from(a.starts)));
    t.push(
        "life_capped",
        Column::Bool(rows.iter().map(|a| a.life_capped).collect()),
    );
    t.push("exceedances", u(&|a| a.exceedances));
    t.push("measured_periods", u(&|a| a.measured_periods));
    for (name, g) in crate::store::attractors::F64_COLUMNS {
        t.push(name, Column::F64(rows.iter().map(|a| g(a)).collect()));
    }
    t
}

/// `branches`: one row per continuation point.
pub fn branches_table(responses: &[Response]) -> Table {
    let rows: Vec<_> = responses.iter().flat_map(|r| &r.branches).collect();
    let mut t = Table::default();
    let f = |g: &dyn Fn(&crate::orbits::response::BranchRow) -> f64| {
        Column::F64(rows.iter().map(|a| g(a)).collect())
    };
    let u = |g: &dyn Fn(&crate::orbits::response::BranchRow) -> u64| {
        Column::U64(rows.iter().map(|a| Some(g(a))).collect())
    };
    let s = |g: &dyn Fn(&crate::orbits::response::BranchRow) -> &'static str| {
        Column::Str(rows.iter().map(|a| g(a).to_string()).collect())
    };
    t.push("point", u(&|b| b.design));
    t.push("branch", u(&|b| u64::from(b.branch)));
    t.push("r", f(&|b| b.r));
    t.push("omega", f(&|b| b.omega));
    t.push("F0", f(&|b| b.F0));
    t.push("amplitude", f(&|b| b.amplitude));
    t.push("period", u(&|b| u64::from(b.period)));
    t.push("impacts_per_period", f(&|b| b.impacts_per_period));
    t.push(
        "stable",
        Column::Bool(rows.iter().map(|b| b.stable).collect()),
    );
    t.push("stability", s(&|b| b.stability));
    t.push("multiplier_max", f(&|b| b.multiplier_max));
    for k in 0..4 {
        t.push(format!("mu{}_re", k + 1), f(&|b| b.multipliers[k].0));
        t.push(format!("mu{}_im", k + 1), f(&|b| b.multipliers[k].1));
    }
    t.push("min_impact_speed", f(&|b| b.min_impact_speed));
    t.push("label", s(&|b| b.label));
    t.push(
        "located",
        Column::Bool(rows.iter().map(|b| b.located).collect()),
    );
    t.push("end", s(&|b| b.end));
    t.push("grazing_outcome", s(&|b| b.grazing_outcome));
    t
}

/// Forcing periods sampled on each attractor that is not periodic for the bifurcation diagram
/// ([`section_samples`]); a periodic orbit of period `p` gives its `p` points.
pub const SECTION_SAMPLES: u64 = 200;

/// One point of a bifurcation diagram: the main mass's displacement `x(kT)` (m) at the start of
/// a forcing period, on attractor `attractor` of the census at frequency ratio `r`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionSample {
    pub r: f64,
    pub attractor: u32,
    pub kind: SteadyKind,
    pub x: f64,
}

/// The bifurcation diagram of curve `c` (the Poincaré section `x(kT)` of every stored attractor
/// against `r`): `p` consecutive sections of a periodic orbit of period `p`, and
/// [`SECTION_SAMPLES`] of a motion that is not periodic, each from the attractor's stored
/// section. Pure; the attractors run in parallel and come back in table order.
pub fn section_samples(study: &Study, c: &Curve) -> Vec<SectionSample> {
    let Some(rows) = c.attractors.as_deref() else {
        return Vec::new();
    };
    let base = Forcing {
        sys: c.system,
        F0: c.f0,
        omega: c.system.omega(),
        settings: study.solver,
    };
    rows.par_iter()
        .flat_map_iter(|a| {
            let f = base.at_ratio(a.run.r);
            let n = if a.kind.periodic() {
                u64::from(a.period.max(1))
            } else {
                SECTION_SAMPLES
            };
            let mut s = a.section;
            let mut out = Vec::with_capacity(n as usize);
            for _ in 0..n {
                out.push(SectionSample {
                    r: a.run.r,
                    attractor: a.attractor,
                    kind: a.kind,
                    x: s[0],
                });
                let e = crate::orbits::map::eval(&f, &s, 1, false);
                if e.outcome != crate::sim::Outcome::Ok {
                    break;
                }
                s = e.end;
            }
            out
        })
        .collect()
}
