//! `[study]`: the name (it names the output directory), the seed, and what each run must
//! produce (`outputs`, `peaks`, `t_end`: the free-decay scene's horizon; the other scenes refuse
//! them, each with its reason).

use serde::Deserialize;

use super::context::{Cx, range_value};
use crate::error::InputError;
use crate::sim::Request;

/// The outputs a study may ask for in `[study].outputs`, with the number of positive
/// half-cycle maxima each needs (the horizon follows from the largest). `xmax` is the larger of
/// the first two maxima (model.md §3), so it needs two.
pub const OUTPUTS: [(&str, usize); 10] = [
    ("x1", 1),
    ("t1", 1),
    ("x2", 2),
    ("t2", 2),
    ("xmax", 2),
    ("di", 2),
    ("impacts", 1),
    ("sticks", 1),
    ("energy_impact", 1),
    ("energy_viscous", 1),
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHeader {
    pub(super) name: String,
    pub(super) seed: Option<u64>,
    pub(super) outputs: Option<Vec<String>>,
    pub(super) peaks: Option<u64>,
    pub(super) t_end: Option<f64>,
}

impl RawHeader {
    /// Refuses the free-decay scene's keys (`outputs`, `peaks`, `t_end`) in another scene's
    /// study: `why` gives, in that order, the reason for each.
    pub(super) fn refuse_free_keys(
        &self,
        cx: &Cx,
        why: [(&str, &str); 3],
    ) -> Result<(), InputError> {
        let given = [
            self.outputs.is_some(),
            self.peaks.is_some(),
            self.t_end.is_some(),
        ];
        for ((key, why), given) in why.into_iter().zip(given) {
            if given {
                return Err(cx.err(&format!("[study].{key}"), cx.source("study", key), why));
            }
        }
        Ok(())
    }
}

/// `[study]`: the name (it names the output directory) and what each run must produce (the
/// outputs set the horizon: how many peaks a run needs).
pub(super) fn header(cx: &Cx, h: &RawHeader) -> Result<Request, InputError> {
    let name_ok = !h.name.is_empty()
        && h.name != "."
        && h.name != ".."
        && h.name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-'));
    if !name_ok {
        return Err(cx.err(
            "[study].name",
            format!("{:?}", h.name),
            "the name must match [A-Za-z0-9_.-]+ and not be . or .. (it names the output directory)",
        ));
    }
    let mut need = 2;
    if let Some(outputs) = &h.outputs {
        if outputs.is_empty() {
            return Err(cx.err("[study].outputs", "[]", "ask for at least one output"));
        }
        need = 1;
        for (i, o) in outputs.iter().enumerate() {
            let Some((_, k)) = OUTPUTS.iter().find(|(n, _)| n == o) else {
                let names: Vec<&str> = OUTPUTS.iter().map(|(n, _)| *n).collect();
                return Err(cx.err(
                    &format!("[study].outputs[{i}]"),
                    format!("{o:?}"),
                    format!("unknown output; allowed: {}", names.join(", ")),
                ));
            };
            need = need.max(*k);
        }
    }
    let mut request = Request {
        peaks: need,
        t_end: h.t_end,
        trace_dt: None,
    };
    if let Some(p) = h.peaks {
        if p < need as u64 {
            return Err(cx.err(
                "[study].peaks",
                p,
                format!("the outputs asked for need peaks >= {need}"),
            ));
        }
        request.peaks = usize::try_from(p).unwrap_or(usize::MAX);
    }
    request
        .validate()
        .map_err(|e| cx.err(&format!("[study].{}", e.key), range_value(&e), e.allowed))?;
    Ok(request)
}
