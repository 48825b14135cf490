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
//! are the same for any thread count; no thread runs more than a window ahead of the design
//! awaited, so what waits for a slow design is bounded.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};

use rayon::prelude::*;

use super::curve::Curve;
use super::summary::HarmonicSummary;
use crate::orbits::attractors::{AttractorRow, SteadyKind};
use crate::orbits::census::CensusSettings;
use crate::orbits::continuation::Param;
use crate::orbits::map::{Forcing, Section};
use crate::orbits::response::{Response, analyse_along, branches, orbit_from_section};
use crate::orbits::units_response::{units_branches, units_orbit_from_section};
use crate::orbits::{CENSUS_WINDOW, HANDOVER};
use crate::store::table::{Column, Table};
use crate::study::{CensusKind, Study};

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
/// 1,000-design study of BENCHMARKS.md, 3.5 MB at most; the batch's table copies them once
/// more while it is written, so a smaller batch holds less, and the tables are the same).
pub const BATCH_PER_THREAD: usize = 4;

/// How far past the design awaited a thread may start one, per thread of the pool
/// ([`in_design_order`]'s window): room for the others while one design takes long (their cost
/// varies a hundredfold), and a bound on the designs waiting for it.
pub const WINDOW_PER_THREAD: usize = 16;

/// [`steady_states`] a batch of designs at a time, in design order: `each` takes every batch,
/// so the caller holds one batch rather than the study's. A study along `F0` is one batch.
/// Stops at `each`'s first error.
///
/// The designs are analysed by as many threads as the current rayon pool has, each taking the
/// next design when it is done with one (their cost varies a hundredfold: batches analysed in
/// parallel one after the other waited for their slowest design, and the 1,000-design study's
/// `reduce` took 155 s against 135 s); the designs that finish ahead of an earlier one wait for
/// it, so the batches come in design order and the tables are the same for any thread count.
/// No thread starts a design [`WINDOW_PER_THREAD`] designs a thread or more past the one
/// awaited ([`in_design_order`]): the designs held are at most a batch and a window, however
/// slow one design is.
pub fn steady_states_in_batches<E>(
    study: &Study,
    fs: &HarmonicSummary,
    mut each: impl FnMut(Vec<Response>) -> Result<(), E>,
) -> Result<(), E> {
    let Some(&h) = study.scene.harmonic() else {
        return Ok(());
    };
    // A study of several units has its branches along the frequency only (the continuation
    // of several units moves `r`: [`crate::orbits::units_response`]).
    match study.census_kind() {
        CensusKind::None => return Ok(()),
        CensusKind::Units if fs.frequency.is_none() => return Ok(()),
        _ => {}
    }
    if fs.frequency.is_none() {
        let all = along_force(study, &h, fs);
        return if all.is_empty() { Ok(()) } else { each(all) };
    }
    let threads = rayon::current_num_threads().max(1);
    let batch = BATCH_PER_THREAD * threads;
    in_design_order(
        fs.curves.len(),
        threads,
        batch,
        WINDOW_PER_THREAD * threads,
        |i| along_frequency(study, &h, fs, &fs.curves[i]),
        each,
    )
}

/// `work(i)` for every design `i < n` on `threads` threads, handed to `each` in design order,
/// `batch` at a time (the last batch the rest); stops at `each`'s first error.
///
/// A thread takes the next design when it is done with one, but does not start design `i`
/// while `i >= want + window`, `want` being the first design not yet handed over to the batch
/// being gathered ([`Gate`]): the designs done ahead of a slow one, waiting for it, are fewer
/// than `window`, so what is held is less than `batch + window` designs' results whatever the
/// costs. On any way out (the end, `each`'s error, a panic in `work`) the gate closes and the
/// threads waiting at it end; a panic in `work` is raised again here.
fn in_design_order<T: Send, E>(
    n: usize,
    threads: usize,
    batch: usize,
    window: usize,
    work: impl Fn(usize) -> T + Sync,
    mut each: impl FnMut(Vec<T>) -> Result<(), E>,
) -> Result<(), E> {
    let (threads, batch, window) = (threads.max(1), batch.max(1), window.max(1));
    let next = AtomicUsize::new(0);
    let gate = Gate::default();
    // Every design sent is in `want .. want + window`: the channel never holds more.
    let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, T)>(window);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let tx = tx.clone();
            let (next, gate, work) = (&next, &gate, &work);
            scope.spawn(move || {
                let _closes = ClosesOnPanic(gate);
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    // A receiver gone or the gate closed (an error in `each`) ends the work too.
                    if i >= n || !gate.admit(i, window) || tx.send((i, work(i))).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        let _closes = Closes(&gate);
        let mut early = std::collections::BTreeMap::new();
        let (mut want, mut ready) = (0, Vec::with_capacity(batch));
        for (i, r) in rx {
            early.insert(i, r);
            let was = want;
            while let Some(r) = early.remove(&want) {
                ready.push(r);
                want += 1;
                if ready.len() == batch {
                    gate.advance(want);
                    each(std::mem::replace(&mut ready, Vec::with_capacity(batch)))?;
                }
            }
            if want != was {
                gate.advance(want);
            }
        }
        // Short of `n`, a thread panicked: the scope raises it once the others end.
        if ready.is_empty() || want < n {
            Ok(())
        } else {
            each(ready)
        }
    })
}

/// How far [`in_design_order`]'s threads may run ahead: the first design not yet handed over
/// (`want`) and whether the work is over (`closed`), with the condition variable the threads
/// wait on. The lock is held only to read or move these, never while a design is analysed
/// or a result sent.
#[derive(Default)]
struct Gate {
    state: Mutex<GateState>,
    moved: Condvar,
}

#[derive(Default)]
struct GateState {
    want: usize,
    closed: bool,
}

impl Gate {
    fn lock(&self) -> MutexGuard<'_, GateState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Waits until design `i` is within `window` of the design awaited; false when the gate
    /// closed instead (checked after every wake-up).
    fn admit(&self, i: usize, window: usize) -> bool {
        let mut s = self.lock();
        while !s.closed && i >= s.want + window {
            s = self.moved.wait(s).unwrap_or_else(PoisonError::into_inner);
        }
        !s.closed
    }

    fn advance(&self, want: usize) {
        self.lock().want = want;
        self.moved.notify_all();
    }

    fn close(&self) {
        self.lock().closed = true;
        self.moved.notify_all();
    }
}

/// Closes its [`Gate`] when dropped: the consumer's guard, on every way out of it.
struct Closes<'a>(&'a Gate);

impl Drop for Closes<'_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

/// Closes its [`Gate`] when its thread panics (the design it held never comes, so the others
/// would wait for it forever); a thread that merely ran out of designs leaves the gate open.
struct ClosesOnPanic<'a>(&'a Gate);

impl Drop for ClosesOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.close();
        }
    }
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
    if study.several_units() {
        return units_curve_states(base, design, values, stored);
    }
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

/// [`curve_states`] of several units (along the frequency): the stored attractors and the
/// branches followed from their stable periodic impacting orbits, each from its whole section
/// state (`section_units`). A dataset written before the sweep stored the attractors of several
/// units has neither (no census runs here).
fn units_curve_states(
    base: &Forcing,
    design: u64,
    values: &[(u64, f64)],
    stored: Option<&[AttractorRow]>,
) -> Response {
    let Some(rows) = stored else {
        return Response {
            design,
            ..Response::default()
        };
    };
    let mut seeds = Vec::new();
    for &(point, r) in values {
        let f = base.at_ratio(r);
        for a in rows.iter().filter(|a| a.run.point == point) {
            if a.kind == SteadyKind::Periodic
                && let Some(o) = units_orbit_from_section(&f, &a.section_units, a.period)
            {
                seeds.push((f.clone(), o));
            }
        }
    }
    let (branches, periods) = units_branches(design, values, seeds);
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
            let sample = |x: f64| SectionSample {
                r: a.run.r,
                attractor: a.attractor,
                kind: a.kind,
                x,
            };
            let mut out = Vec::with_capacity(n as usize);
            if !a.section_units.is_empty() {
                // Several units: the whole state, run by their own map.
                let mut s = a.section_units.clone();
                for _ in 0..n {
                    out.push(sample(s[0]));
                    let e = crate::orbits::units::map::eval(&f, &s, 1);
                    if e.outcome != crate::sim::Outcome::Ok {
                        break;
                    }
                    s = e.end;
                }
                return out;
            }
            let mut s = a.section;
            for _ in 0..n {
                out.push(sample(s[0]));
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::AtomicBool;
    use std::time::{Duration, Instant};

    /// `f()` on its own thread, failing the test if it takes longer than `secs` (a hang).
    fn within<R: Send + 'static>(secs: u64, f: impl FnOnce() -> R + Send + 'static) -> R {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _ = tx.send(std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)));
        });
        match rx.recv_timeout(Duration::from_secs(secs)) {
            Ok(Ok(r)) => r,
            Ok(Err(panic)) => std::panic::resume_unwind(panic),
            Err(_) => panic!("no answer in {secs} s: a hang"),
        }
    }

    /// The batches of `in_design_order` over `n` designs whose `work` sleeps `cost(i)` ms.
    fn batches(
        n: usize,
        threads: usize,
        batch: usize,
        window: usize,
        cost: fn(usize) -> u64,
    ) -> Vec<Vec<usize>> {
        let mut out = Vec::new();
        let Ok(()) = in_design_order::<_, std::convert::Infallible>(
            n,
            threads,
            batch,
            window,
            |i| {
                std::thread::sleep(Duration::from_millis(cost(i)));
                i
            },
            |b| {
                out.push(b);
                Ok(())
            },
        );
        out
    }

    #[test]
    fn designs_come_in_order_in_whole_batches_for_any_thread_count() {
        // Costs that vary, so that threads finish out of order.
        let cost: fn(usize) -> u64 = |i| [0, 3, 1, 0, 5, 0, 2][i % 7];
        let want: Vec<Vec<usize>> = (0..53)
            .collect::<Vec<_>>()
            .chunks(8)
            .map(<[usize]>::to_vec)
            .collect();
        for threads in [1, 2, 3, 8] {
            for window in [1, 3, 8, 64] {
                let got = within(60, move || batches(53, threads, 8, window, cost));
                assert_eq!(got, want, "{threads} threads, window {window}");
            }
        }
        assert!(within(10, move || batches(0, 2, 8, 8, cost)).is_empty());
    }

    #[test]
    fn a_slow_first_design_holds_the_others_within_the_window() {
        // Design 0 takes 300 ms, the others none: without the window the other threads would
        // do all 400 while it runs, and every result would wait for it.
        const N: usize = 400;
        const WINDOW: usize = 6;
        let first_done = AtomicBool::new(false);
        let (ahead, handed) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let mut order: Vec<usize> = Vec::new();
        let Ok(()) = in_design_order::<usize, std::convert::Infallible>(
            N,
            3,
            4,
            WINDOW,
            |i| {
                if i == 0 {
                    std::thread::sleep(Duration::from_millis(300));
                    first_done.store(true, Ordering::SeqCst);
                } else if i >= WINDOW {
                    // Started only once design 0 was handed over.
                    assert!(first_done.load(Ordering::SeqCst), "design {i} ran ahead");
                }
                // At most a batch being gathered plus the window past the designs handed over.
                let h = handed.load(Ordering::SeqCst);
                ahead.fetch_max(i - h.min(i), Ordering::SeqCst);
                i
            },
            |b| {
                order.extend(&b);
                handed.fetch_add(b.len(), Ordering::SeqCst);
                Ok(())
            },
        );
        assert_eq!(order, (0..N).collect::<Vec<_>>());
        assert!(ahead.into_inner() < 4 + WINDOW);
    }

    #[test]
    fn an_error_of_the_consumer_ends_the_workers_at_once() {
        // Many slow designs: the first batch's error must not wait for them, nor leave a thread
        // waiting at the gate for designs that no one will hand over.
        for (threads, window) in [(1, 1), (2, 2), (4, 8), (8, 3)] {
            let started = Arc::new(AtomicUsize::new(0));
            let s = started.clone();
            let t0 = Instant::now();
            let got = within(20, move || {
                in_design_order(
                    100_000,
                    threads,
                    4,
                    window,
                    |i| {
                        s.fetch_add(1, Ordering::SeqCst);
                        std::thread::sleep(Duration::from_millis(5));
                        i
                    },
                    |b: Vec<usize>| if b[0] == 4 { Err(b[0]) } else { Ok(()) },
                )
            });
            assert_eq!(got, Err(4));
            assert!(t0.elapsed() < Duration::from_secs(5), "{:?}", t0.elapsed());
            // The second batch's 4, the window past them and one design a thread at most.
            assert!(started.load(Ordering::SeqCst) <= 8 + window + threads);
        }
    }

    #[test]
    fn a_panic_in_the_work_is_raised_not_waited_for() {
        let got = within(20, || {
            std::panic::catch_unwind(|| {
                batches(
                    1_000,
                    3,
                    4,
                    4,
                    |i| if i == 5 { panic!("design 5") } else { 1 },
                )
            })
        });
        assert!(got.is_err());
    }
}
