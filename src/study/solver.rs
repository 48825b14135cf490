//! `[solver]`: the solver, its accuracy knob and its caps ([`SolverSettings::validate`]).

use serde::Deserialize;

use super::context::{Cx, range_value};
use crate::error::InputError;
use crate::sim::{SolverKind, SolverSettings};

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSolver {
    kind: Option<String>,
    tol: Option<f64>,
    chatter_tol: Option<f64>,
    max_impacts: Option<u64>,
    max_steps: Option<u64>,
    t_max_periods: Option<f64>,
    h: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
}

/// The validated `[solver]`.
pub(super) fn solver(cx: &Cx, raw: &RawSolver) -> Result<SolverSettings, InputError> {
    let mut solver = SolverSettings::default();
    let rs = raw;
    if let Some(k) = &rs.kind {
        solver.kind = SolverKind::parse(k).ok_or_else(|| {
            let names: Vec<&str> = SolverKind::ALL.iter().map(|k| k.name()).collect();
            cx.err(
                "[solver].kind",
                format!("{k:?}"),
                format!("unknown solver; allowed: {}", names.join(", ")),
            )
        })?;
    }
    if let Some(v) = rs.tol {
        solver.tol = v;
    }
    if let Some(v) = rs.chatter_tol {
        solver.chatter_tol = v;
    }
    if let Some(v) = rs.max_impacts {
        solver.max_impacts = v;
    }
    if let Some(v) = rs.max_steps {
        solver.max_steps = v;
    }
    if let Some(v) = rs.t_max_periods {
        solver.t_max_periods = v;
    }
    for (v, slot) in [
        (rs.h, &mut solver.h),
        (rs.rtol, &mut solver.rtol),
        (rs.atol, &mut solver.atol),
    ] {
        if let Some(v) = v {
            *slot = v;
        }
    }
    solver
        .validate()
        .map_err(|e| cx.err(&format!("[solver].{}", e.key), range_value(&e), e.allowed))?;
    Ok(solver)
}
