//! The steady states of a harmonic study's curves (docs/reduce.md): for each design's ideal
//! case, the attractor census at every swept frequency and the periodic branches followed
//! along the frequency ([`crate::orbits::response`]), as the `attractors` and `branches` tables.
//!
//! The designs are analysed in parallel on the current rayon pool and collected in design
//! order, so the tables are the same for any thread count. The census's starts are seeded by
//! the study seed and each frequency's design point, as in the sweep, so the table's census of
//! an ideal run draws the starts the sweep drew (its start 0 runs from the initial state here,
//! where the sweep went on from its run's end: the same trajectory).

use rayon::prelude::*;

use super::forced::{Curve, ForcedSummary};
use super::table::{Column, Table};
use crate::orbits::census::CensusSettings;
use crate::orbits::continuation::Param;
use crate::orbits::map::Forcing;
use crate::orbits::response::{Response, analyse, analyse_along};
use crate::orbits::{CENSUS_WINDOW, HANDOVER};
use crate::sim::Scene;
use crate::study::Study;

/// The steady states of every curve of `fs`, in design order: along the frequency when the
/// study sweeps it; otherwise along `F0` when the study sweeps the force (the designs that
/// differ only in `F0` make one curve, analysed as the design of its smallest `F0`). Empty
/// when neither is swept (a "curve" of one point has nothing to follow) or with `starts = 0`.
pub fn steady_states(study: &Study, fs: &ForcedSummary) -> Vec<Response> {
    let Scene::Harmonic(h) = study.scene else {
        return Vec::new();
    };
    if h.starts == 0 {
        return Vec::new();
    }
    if fs.frequency.is_none() {
        return along_force(study, &h, fs);
    }
    let n_f = study.curve_points();
    fs.curves
        .par_iter()
        .map(|c| curve(study, &h, c, n_f))
        .collect()
}

/// A study at one frequency that sweeps `F0`: its one-point curves grouped by everything but
/// `F0` (the ideal system and the frequency), each group followed along `F0`.
fn along_force(study: &Study, h: &crate::sim::Harmonic, fs: &ForcedSummary) -> Vec<Response> {
    if !study
        .axes
        .iter()
        .any(|a| a.key == "F0" && a.values.len() >= 2)
    {
        return Vec::new();
    }
    let key = |c: &Curve| -> Vec<u64> {
        let s = &c.system;
        let omega = c.points.first().map_or(f64::NAN, |p| p.omega);
        [s.M, s.m, s.K, s.C, s.e, s.d, s.x0, s.v0, s.y0, s.w0, omega]
            .iter()
            .map(|v| v.to_bits())
            .collect()
    };
    let mut groups: Vec<(Vec<u64>, Vec<&Curve>)> = Vec::new();
    for c in &fs.curves {
        let k = key(c);
        match groups.iter_mut().find(|g| g.0 == k) {
            Some(g) => g.1.push(c),
            None => groups.push((k, vec![c])),
        }
    }
    groups
        .par_iter()
        .filter(|g| g.1.len() >= 2)
        .map(|(_, cs)| {
            let mut cs = cs.clone();
            cs.sort_by(|a, b| a.f0.total_cmp(&b.f0));
            let first = cs[0];
            let sys = first.system;
            let base = Forcing {
                sys,
                F0: first.f0,
                omega: first.points.first().map_or(sys.omega(), |p| p.omega),
                settings: study.solver,
            };
            let values: Vec<(u64, f64)> = cs.iter().map(|c| (c.design, c.f0)).collect();
            let s0 = [sys.x0, sys.v0, sys.y0 - sys.x0, sys.w0];
            analyse_along(
                &base,
                first.design,
                &s0,
                &values,
                Param::Force,
                &census_settings(study, h),
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
    }
}

fn curve(study: &Study, h: &crate::sim::Harmonic, c: &Curve, n_f: u64) -> Response {
    let sys = c.system;
    let base = Forcing {
        sys,
        F0: c.f0,
        omega: sys.omega(),
        settings: study.solver,
    };
    let freqs: Vec<(u64, f64)> = c
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| (c.design * n_f + i as u64, p.omega / sys.omega()))
        .collect();
    let s0 = [sys.x0, sys.v0, sys.y0 - sys.x0, sys.w0];
    analyse(&base, c.design, &s0, &freqs, &census_settings(study, h))
}

/// `attractors`: one row per design point (design and frequency) and attractor.
pub fn attractors_table(responses: &[Response]) -> Table {
    let rows: Vec<_> = responses.iter().flat_map(|r| &r.attractors).collect();
    let mut t = Table::default();
    let f = |g: &dyn Fn(&crate::orbits::response::AttractorRow) -> f64| {
        Column::F64(rows.iter().map(|a| g(a)).collect())
    };
    let u = |g: &dyn Fn(&crate::orbits::response::AttractorRow) -> u64| {
        Column::U64(rows.iter().map(|a| Some(g(a))).collect())
    };
    t.push("point", u(&|a| a.point));
    t.push("r", f(&|a| a.r));
    t.push("omega", f(&|a| a.omega));
    t.push("F0", f(&|a| a.F0));
    t.push("attractor", u(&|a| u64::from(a.attractor)));
    t.push(
        "kind",
        Column::Str(rows.iter().map(|a| a.kind.to_string()).collect()),
    );
    t.push("period", u(&|a| u64::from(a.period)));
    t.push("amplitude", f(&|a| a.amplitude));
    t.push("impacts_per_period", f(&|a| a.impacts_per_period));
    t.push("basin_share", f(&|a| a.basin_share));
    t.push("starts", u(&|a| u64::from(a.starts)));
    t.push(
        "stability",
        Column::Str(rows.iter().map(|a| a.stability.to_string()).collect()),
    );
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
    t.push("label", s(&|b| b.label));
    t.push("end", s(&|b| b.end));
    t
}
