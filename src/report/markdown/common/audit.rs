//! The accuracy audit of the run (`run --audit`, kept in `manifest.json`): points re-run with
//! `exact` at a tight tolerance and the errors of the study's solver against them.

use std::fmt::Write;

use crate::accuracy::{Audit, ErrorStats};
use crate::report::text::fmt_num;

pub fn section(a: &Audit) -> String {
    let mut o = String::from("## Accuracy audit\n\n");
    let _ = writeln!(
        o,
        "{} design points (their ideal case) re-run against the reference ({}); the study's solver is `{}` with {} = {}. Relative errors `|a − b| / |b|`:\n",
        a.points.len(),
        a.reference,
        a.solver,
        a.knob,
        fmt_num(a.knob_value)
    );
    let _ = writeln!(o, "| quantity | max | median | runs |\n|---|---|---|---|");
    let row = |name: &str, e: &ErrorStats| {
        format!("| {name} | {:.2e} | {:.2e} | {} |", e.max, e.median, e.n)
    };
    for (name, e) in [("xmax", &a.xmax), ("t1", &a.t1), ("DI", &a.di)] {
        let _ = writeln!(o, "{}", row(name, e));
    }
    let _ = writeln!(
        o,
        "\nOutcome changed in {} runs, impact count in {}.\n",
        a.outcome_changed, a.impacts_changed
    );
    o
}
