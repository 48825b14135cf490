//! `impactsweep tradeoff`: what each solver setting costs and how wrong it is (issue 5).
//!
//! On a reference set of runs (a study's design points, ideal case; by default the paper's
//! Table I system for `e = 0.45, 0.46, ..., 0.95`), every solver runs over a ladder of its
//! accuracy knob ([`crate::accuracy::ladder`]); each setting's median time per run and its
//! error against `exact` at `tol = 1e-14` are measured by [`crate::accuracy::measure_all`] (the
//! timing harness and the error statistics are documented there).
//!
//! The result is printed, written to `OUT/tradeoff.parquet` (via [`crate::store::tradeoff`]),
//! `OUT/tradeoff.md` and a log-log chart `OUT/tradeoff.svg`/`.png` (via
//! [`crate::report::tradeoff_chart`]). The SciPy peer (`scripts/peer_scipy.py`) joins the table and
//! chart when its JSON is found (`--peer FILE`, or `OUT/peer_scipy.json`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;

use crate::accuracy::{
    self, DI_GOAL, ErrorStats, PeerFile, REFERENCE_TOL, Reference, Row, Timing, fmt_err, fmt_time,
};
use crate::sim::SolverKind;

/// `impactsweep tradeoff [STUDY.toml] [--out DIR]`.
#[derive(Clone, Debug, Default)]
pub struct TradeoffArgs {
    pub study: Option<PathBuf>,
    pub out: PathBuf,
    pub quick: bool,
    /// The SciPy peer's JSON (default: `OUT/peer_scipy.json` when present).
    pub peer: Option<PathBuf>,
}

/// The table as markdown.
pub fn table(reference: &Reference, rows: &[Row]) -> String {
    let mut out = format!(
        "Reference: {} ({} runs), against exact at tol = {REFERENCE_TOL:e}. Errors are relative; \
         max / median over the runs. Times are medians per run over interleaved rounds, single \
         thread; settings are ranked by CPU time.\n\n",
        reference.label,
        reference.systems.len()
    );
    out.push_str("| solver | setting | CPU/run | wall/run | steps/run | xmax err | t1 err | DI err | impacts err | changed outcome | changed impacts | DI < 0.1 % |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let pair = |s: &ErrorStats| format!("{} / {}", fmt_err(s.max), fmt_err(s.median));
        let steps = if r.steps_per_run.is_nan() {
            "-".to_string()
        } else {
            format!("{:.0}", r.steps_per_run)
        };
        let goal = if r.cheapest {
            "cheapest"
        } else if r.meets_goal() {
            "yes"
        } else {
            "no"
        };
        let changed = if r.unfinished > 0 {
            format!("{} ({} unfinished)", r.changed_outcome, r.unfinished)
        } else {
            r.changed_outcome.to_string()
        };
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.solver,
            r.setting,
            fmt_time(r.cpu_per_run),
            fmt_time(r.time_per_run),
            steps,
            pair(&r.xmax),
            pair(&r.t1),
            pair(&r.di),
            pair(&r.impacts),
            changed,
            r.changed_impacts,
            goal
        ));
    }
    out.push('\n');
    for r in rows.iter().filter(|r| r.cheapest) {
        out.push_str(&format!(
            "Cheapest {} with DI error under 0.1 %: {} ({} CPU per run, max DI error {}).\n",
            r.solver,
            r.setting,
            fmt_time(r.cpu_per_run),
            fmt_err(r.di.max)
        ));
    }
    let mut solvers: Vec<&str> = rows.iter().map(|r| r.solver.as_str()).collect();
    solvers.dedup();
    for s in solvers {
        if !rows.iter().any(|r| r.solver == s && r.cheapest) {
            out.push_str(&format!(
                "No {s} setting measured keeps the DI error under 0.1 % on every run.\n"
            ));
        }
    }
    out
}

/// One chart series per solver: (time per run, max DI error) along its ladder.
pub fn chart_series(rows: &[Row]) -> Vec<crate::report::tradeoff_chart::Series> {
    let mut out: Vec<crate::report::tradeoff_chart::Series> = Vec::new();
    for r in rows {
        let point = (r.cpu_per_run, r.di.max);
        let peer = !SolverKind::ALL.iter().any(|k| k.name() == r.solver);
        let name = if peer && r.unfinished > 0 {
            format!(
                "{} {} ({} of {} runs unfinished: chatter)",
                r.solver, r.setting, r.unfinished, r.runs
            )
        } else if peer {
            format!("{} {}", r.solver, r.setting)
        } else {
            r.solver.clone()
        };
        match out.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push(point),
            None => out.push(crate::report::tradeoff_chart::Series {
                name,
                points: vec![point],
                peer,
            }),
        }
    }
    out
}

/// The `tradeoff` command.
pub fn tradeoff(args: &TradeoffArgs) -> anyhow::Result<()> {
    let reference = match &args.study {
        Some(path) => Reference::study(&crate::study::Study::load(path)?),
        None => Reference::paper(),
    };
    let timing = if args.quick {
        Timing::QUICK
    } else {
        Timing::FULL
    };
    let started = Instant::now();
    let truth = reference.truth();
    let mut rows = accuracy::measure_all(
        &reference,
        &truth,
        &accuracy::ladder(&reference, args.quick),
        timing,
    );
    let peer_path = args
        .peer
        .clone()
        .or_else(|| Some(args.out.join("peer_scipy.json")).filter(|p| p.exists()));
    if let Some(path) = &peer_path {
        let peer = PeerFile::load(path)?;
        let extra = accuracy::peer_rows(&peer, &reference, &truth);
        if extra.is_empty() {
            eprintln!(
                "note: {} does not cover this reference set; the peer is left out",
                path.display()
            );
        }
        rows.extend(extra);
    }
    accuracy::mark_cheapest(&mut rows);
    let text = table(&reference, &rows);
    print!("{text}");
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let md = args.out.join("tradeoff.md");
    std::fs::write(&md, &text).with_context(|| format!("writing {}", md.display()))?;
    crate::store::tradeoff::write(&args.out.join("tradeoff.parquet"), &rows)?;
    crate::report::tradeoff_chart::draw(
        &chart_series(&rows),
        DI_GOAL,
        (
            "median CPU time per run (s)",
            "max relative error in DI over the runs",
        ),
        &args.out.join("tradeoff"),
    )?;
    println!(
        "wrote {}/tradeoff.{{parquet,md,svg,png}} in {:.1} s",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
