//! `impactsweep simulate`: one run of one system, printed for a person or as JSON, with an
//! optional sampled trace for waveform plots.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

pub use crate::api::realization::RandomSetup;
pub use crate::api::setup::{Setup, forced_json, record_json, trace_scene};
use crate::error::InputError;
use crate::model::{System, fmt_value};
use crate::sim::random::{Excitation, Input, RandomScene, RealizationRecord};
use crate::sim::{HarmonicRecord, NoProbe, Record, Request, SceneRecord, SolverKind, State};

/// What `simulate` was asked.
#[derive(Clone, Debug, Default)]
pub struct SimulateArgs {
    /// `KEY=VALUE` settings, applied in order over the Table I defaults.
    pub sets: Vec<String>,
    pub json: bool,
    pub trace: Option<PathBuf>,
    pub dt: Option<f64>,
    pub t_end: Option<f64>,
}

fn write_trace(path: &Path, rows: &[(f64, State)]) -> anyhow::Result<()> {
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut out = std::io::BufWriter::new(file);
    writeln!(out, "t,x,y")?;
    for (t, s) in rows {
        writeln!(out, "{t:e},{:e},{:e}", s.x, s.y)?;
    }
    out.flush()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

/// A length in cm for a person, `-` when unknown.
fn cm(v: f64) -> String {
    if v.is_nan() {
        "-".to_string()
    } else {
        format!("{:.4} cm", v * 100.0)
    }
}

/// The summary's first line: the system's parameters with units.
fn system_line(s: &System) -> String {
    format!(
        "system   M = {} kg, m = {} kg, K = {} N/m, C = {} N s/m, d = {} m, e = {}\n",
        fmt_value(s.M),
        fmt_value(s.m),
        fmt_value(s.K),
        fmt_value(s.C),
        fmt_value(s.d),
        fmt_value(s.e)
    ) + &units_line(s)
}

/// With several units: how the inner mass is split and each unit's clearance.
fn units_line(s: &System) -> String {
    if s.unit_count() < 2 {
        return String::new();
    }
    if let Some(table) = s.table {
        let each: Vec<String> = table
            .units()
            .iter()
            .map(|u| {
                format!(
                    "m = {} kg, d = {} m, e = {}",
                    fmt_value(u.m),
                    fmt_value(u.d),
                    fmt_value(u.e)
                )
            })
            .collect();
        return format!(
            "units    {} from [[system.unit]] (m is their total, d the largest, e the \
             mass-weighted mean): {}\n",
            s.unit_count(),
            each.join("; ")
        );
    }
    let d: Vec<String> = s.unit_list().iter().map(|u| fmt_value(u.d)).collect();
    format!(
        "units    {} of m/{} = {} kg each, d_spread = {}: d = {} m\n",
        s.unit_count(),
        s.unit_count(),
        fmt_value(s.m / s.units),
        fmt_value(s.d_spread),
        d.join(", ")
    )
}

/// A short summary of a forced run for a person, with units.
pub fn forced_text(setup: &Setup, rec: &HarmonicRecord) -> String {
    let s = &setup.system;
    let mut out = String::new();
    out.push_str(&system_line(s));
    out.push_str(&format!(
        "force    F0 = {} N, omega = {} rad/s (r = {})\n",
        fmt_value(rec.F0),
        fmt_value(rec.omega),
        fmt_value(rec.r)
    ));
    out.push_str(&format!("outcome  {}\n", rec.outcome));
    out.push_str(&format!(
        "periods  {} transient ({}), then measured\n",
        rec.n_trans,
        if rec.converged {
            "the section converged"
        } else {
            "not converged: fixed or capped"
        }
    ));
    out.push_str(&format!(
        "amplitude {} (linear system {}, attenuation {:.4})\n",
        cm(rec.amplitude),
        cm(rec.amplitude_linear),
        rec.attenuation
    ));
    out.push_str(&format!(
        "impacts  {:.3} per period, period {}\n",
        rec.impacts_per_period,
        if rec.period == 0 {
            "0 (none of 1..8 repeats)".to_string()
        } else {
            rec.period.to_string()
        }
    ));
    out.push_str(&format!(
        "energy   per window: {:.4e} J by the force, {:.4e} J in impacts, {:.4e} J in the damper\n",
        rec.energy_force, rec.energy_impact, rec.energy_viscous
    ));
    let st = &rec.steady;
    if st.starts > 0 {
        let period = |p: u32| {
            if p == 0 {
                "not periodic".to_string()
            } else {
                format!("period {p}")
            }
        };
        let impacts = if st.worst_impacts_per_period.is_nan() {
            String::new()
        } else {
            format!(", {:.3} impacts per period", st.worst_impacts_per_period)
        };
        out.push_str(&format!(
            "census   {} starts, {} attractors; worst {} ({}{impacts}, basin share {:.2}); from \
             the initial state {} ({})\n",
            st.starts,
            st.attractors,
            cm(st.amplitude_worst),
            period(st.worst_period),
            st.worst_basin_share,
            cm(st.rest_amplitude),
            period(st.rest_period)
        ));
        if st.worst_period == 0 {
            out.push_str(&worst_line(st));
        }
    }
    out.push_str(&format!("stopped  at t = {:.5} s\n", rec.t_stop));
    out
}

/// The census's worst steady state when it is not periodic: its kind, its window amplitude and
/// its design life, or that it has none.
fn worst_line(st: &crate::sim::harmonic::Steady) -> String {
    let lyapunov = if st.worst_lyapunov.is_nan() {
        String::new()
    } else {
        format!(
            " (largest Lyapunov exponent {:.3} per period)",
            st.worst_lyapunov
        )
    };
    let life = if !st.worst_life_lo.is_nan() {
        format!(
            ", {} to {} (90 %) over the design life",
            cm(st.worst_life_lo),
            cm(st.worst_life_hi)
        )
    } else {
        " (a lower bound: no design-life estimate)".to_string()
    };
    format!(
        "worst    {}{lyapunov}: {} over the census window{life}\n",
        st.worst_kind,
        cm(st.worst_window_amplitude)
    )
}

/// A short summary for a person, with units.
pub fn record_text(setup: &Setup, rec: &Record) -> String {
    let s = &setup.system;
    let mut out = String::new();
    out.push_str(&system_line(s));
    out.push_str(&format!(
        "start    x0 = {} m, v0 = {} m/s, y0 = {} m, w0 = {} m/s\n",
        fmt_value(s.x0),
        fmt_value(s.v0),
        fmt_value(s.y0),
        fmt_value(s.w0)
    ));
    out.push_str(&format!(
        "solver   {} ({} = {}{})\n",
        setup.solver.kind.name(),
        setup.solver.kind.knob(),
        fmt_value(setup.solver.knob_value()),
        match setup.solver.kind {
            SolverKind::Exact => " of the period",
            SolverKind::Rk4 => " s",
            SolverKind::Dopri5 => "",
        }
    ));
    out.push_str(&format!("outcome  {}\n", rec.outcome));
    out.push_str(&format!(
        "X1       {} at t1 = {}\n",
        cm(rec.x1),
        sec(rec.t1)
    ));
    out.push_str(&format!(
        "X2       {} at t2 = {}\n",
        cm(rec.x2),
        sec(rec.t2)
    ));
    out.push_str(&format!("xmax     {}\n", cm(rec.xmax)));
    out.push_str(&format!(
        "DI       {}\n",
        if rec.di.is_nan() {
            "-".to_string()
        } else {
            format!("{:.5} m/s", rec.di)
        }
    ));
    out.push_str(&format!(
        "impacts  {} ({} sticking phases){}\n",
        rec.impacts,
        rec.sticks,
        if rec.unit_impacts.is_empty() {
            String::new()
        } else {
            let each: Vec<String> = rec.unit_impacts.iter().map(u64::to_string).collect();
            format!("; by unit {}", each.join(", "))
        }
    ));
    out.push_str(&format!(
        "energy   {:.4e} J lost in impacts, {:.4e} J in the damper (of {:.4e} J)\n",
        rec.energy_impact,
        rec.energy_viscous,
        s.energy(s.x0, s.v0, s.w0)
    ));
    out.push_str(&format!("stopped  at t = {}\n", sec(rec.t_stop)));
    out
}

/// `simulate --study`: realization `case` of design point `point` of a random or record study,
/// as its sweep stores it, printed as one JSON object (the load's values at the point, the
/// motion's own intensity measures and capacity where the study has them, the record); with
/// `trace` its displacements `t,x,y` every `dt` (and at every impact) at the stripe's scale.
pub fn realization(
    study: &Path,
    point: u64,
    case: u32,
    trace: Option<PathBuf>,
    dt: f64,
) -> anyhow::Result<()> {
    let s = crate::study::Study::load(study)?;
    if s.scene.random().is_none() {
        return Err(InputError::new(format!(
            "{}: --study runs one realization of a random or record study ([scene] kind = \
             \"random\" or \"record\"); for this study use impactsweep run",
            study.display()
        ))
        .into());
    }
    let plan = crate::plan::Plan::new(&s);
    if !(dt.is_finite() && dt > 0.0) {
        return Err(
            InputError::new(format!("--dt {dt}: the trace interval (s) must be > 0")).into(),
        );
    }
    let Some((row, rows)) =
        crate::sweep::random::one_realization(&plan, point, case, trace.as_ref().map(|_| dt))
    else {
        return Err(InputError::new(format!(
            "--point {point} --realization {case}: the study has points 0 to {} and \
             realizations 0 to {}",
            plan.n_points().saturating_sub(1),
            plan.n_cases().saturating_sub(1)
        ))
        .into());
    };
    let mut json = serde_json::to_value(&row)?;
    if let serde_json::Value::Object(map) = &mut json {
        map.insert("point".into(), point.into());
        map.insert("case".into(), case.into());
    }
    println!("{json}");
    if let Some(path) = trace {
        write_trace(&path, &rows)?;
    }
    Ok(())
}

/// `simulate --set scene=random` (or `record`): the realization the keys name, as the sweep
/// of their one-point study stores it ([`RandomSetup`]), printed for a person or as JSON; with
/// `--trace` its displacements every `--dt` (and at every impact) at the stripe's scale.
fn random_run(r: &RandomSetup, args: &SimulateArgs) -> anyhow::Result<()> {
    if let Some(t_end) = args.t_end {
        return Err(InputError::new(format!(
            "--t-end {}: a free-decay option; a random or record run lasts its duration (--set \
             duration=...)",
            fmt_value(t_end)
        ))
        .into());
    }
    let dt = args.dt.unwrap_or(1e-4);
    if !(dt.is_finite() && dt > 0.0) {
        return Err(
            InputError::new(format!("--dt {dt}: the trace interval (s) must be > 0")).into(),
        );
    }
    let (row, rows) = r.run(args.trace.as_ref().map(|_| dt))?;
    if args.json {
        println!("{}", r.json(&row));
    } else {
        print!("{}", realization_text(r, &row));
    }
    if let Some(path) = &args.trace {
        write_trace(path, &rows)?;
        if !args.json {
            println!("trace    {}", path.display());
        }
    }
    Ok(())
}

/// A value in g for a person, `-` when absent.
fn in_g(v: Option<f64>) -> String {
    v.map_or("-".to_string(), |v| format!("{v:.5} g"))
}

/// A realization's row for a person, with units.
pub fn realization_text(r: &RandomSetup, row: &RealizationRecord) -> String {
    let scene = r.scene();
    let mut out = system_line(&r.system());
    let keys: Vec<String> = RandomScene::AXES
        .iter()
        .zip(row.load)
        .filter_map(|(k, v)| v.map(|v| format!("{k} = {}", fmt_value(v))))
        .collect();
    let load = match &scene.excitation {
        Excitation::Random(l) => format!("random, {} spectrum", l.spectrum.name()),
        Excitation::Record(_) | Excitation::Suite(_) => "record".to_string(),
    };
    out.push_str(&format!(
        "load     {load} on the {}: {}; dt = {} s, duration = {} s\n",
        match scene.input {
            Input::Base => "ground",
            Input::Force => "main mass",
        },
        keys.join(", "),
        fmt_value(scene.dt),
        fmt_value(scene.duration)
    ));
    out.push_str(&format!(
        "run      realization {} of seed {}\n",
        r.realization, r.study.seed
    ));
    if let Some(own) = row.own {
        out.push_str(&format!(
            "motion   PGA {}, Sa {} (its own, at scale 1)\n",
            in_g(Some(own.pga)),
            in_g(Some(own.sa))
        ));
    }
    let rec = &row.record;
    out.push_str(&format!("outcome  {}\n", rec.outcome));
    out.push_str(&format!(
        "amplitude {} at t = {}\n",
        cm(rec.amplitude),
        sec(rec.t_peak)
    ));
    out.push_str(&format!(
        "rms      x {}, acceleration {:.5} m/s^2\n",
        cm(rec.rms_x),
        rec.rms_acc
    ));
    match scene.threshold {
        Some(b) => out.push_str(&format!(
            "passage  threshold {}: {}\n",
            cm(b),
            rec.first_passage_time
                .map_or("never passed".to_string(), |t| format!(
                    "first passed at t = {}",
                    sec(t)
                ))
        )),
        None => out.push_str("passage  - (no threshold)\n"),
    }
    if let Some(c) = row.capacity {
        out.push_str(&format!(
            "capacity {} ({} runs{}{})\n",
            in_g(Some(c.capacity)),
            c.runs,
            if c.censored {
                ", censored at ida_max"
            } else {
                ""
            },
            if c.resurrected { ", resurrected" } else { "" }
        ));
    }
    out.push_str(&format!(
        "impacts  {} ({} sticking phases), {:.4e} J lost in impacts\n",
        rec.impacts, rec.sticks, rec.energy_impact
    ));
    out.push_str(&format!(
        "stopped  at t = {} ({} load samples, {} steps)\n",
        sec(rec.t_stop),
        rec.samples,
        rec.steps
    ));
    out
}

/// A time in s for a person, `-` when unknown.
fn sec(v: f64) -> String {
    if v.is_nan() {
        "-".to_string()
    } else {
        format!("{v:.5} s")
    }
}

/// The `simulate` command.
pub fn run(args: &SimulateArgs) -> anyhow::Result<()> {
    let mut setup = Setup::default();
    setup.apply(&args.sets)?;
    if let Some(r) = &setup.random {
        return random_run(r, args);
    }
    if let Some(t_end) = args.t_end {
        setup.request.t_end = Some(t_end);
    }
    let dt = args.dt.unwrap_or(1e-4);
    let check = Request {
        trace_dt: Some(dt),
        ..setup.request
    };
    check
        .validate()
        .map_err(|e| InputError::new(format!("--{e}")))?;
    if setup.scene.harmonic().is_some()
        && let Some(t_end) = args.t_end
    {
        return Err(InputError::new(format!(
            "--t-end {}: a free-decay option; the harmonic scene runs n_trans + n_meas forcing \
             periods",
            fmt_value(t_end)
        ))
        .into());
    }
    let rec = match &args.trace {
        Some(path) => {
            let (rec, rows) = trace_scene(&setup, dt);
            write_trace(path, &rows)?;
            rec
        }
        None => setup.run_scene(&mut NoProbe),
    };
    match (&rec, args.json) {
        (SceneRecord::Free(rec), true) => println!("{}", record_json(&setup, rec)),
        (SceneRecord::Free(rec), false) => print!("{}", record_text(&setup, rec)),
        (SceneRecord::Harmonic(rec), true) => println!("{}", forced_json(&setup, rec)),
        (SceneRecord::Harmonic(rec), false) => print!("{}", forced_text(&setup, rec)),
        // A random or record setup ran above; a random record as JSON.
        (SceneRecord::Random(rec), _) => {
            println!("{}", serde_json::to_string(rec).unwrap_or_default())
        }
    }
    if let (Some(path), false) = (&args.trace, args.json) {
        println!("trace    {}", path.display());
    }
    Ok(())
}
