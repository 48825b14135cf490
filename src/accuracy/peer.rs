//! The SciPy peer (`scripts/peer_scipy.py --json`): its runs compared with the reference like
//! any solver setting, so that it joins the trade-off table.

use std::path::Path;

use anyhow::Context;

use super::errors::{Observed, compare};
use super::reference::Reference;
use super::timing::Row;
use crate::sim::Record;

/// The SciPy peer's JSON (`scripts/peer_scipy.py --json`).
#[derive(Clone, Debug, serde::Deserialize)]
pub struct PeerFile {
    pub tool: String,
    #[serde(default)]
    pub version: String,
    pub methods: Vec<PeerMethod>,
}

#[derive(Clone, Debug, serde::Deserialize)]
pub struct PeerMethod {
    pub method: String,
    pub rtol: f64,
    pub atol: f64,
    pub time_per_run_s: f64,
    pub cpu_per_run_s: f64,
    pub reps: u32,
    pub runs: Vec<PeerRun>,
}

#[derive(Clone, Debug, serde::Deserialize)]
pub struct PeerRun {
    pub e: f64,
    /// `ok`, `no_second_peak`, or `chatter` (the guard stopped it).
    pub outcome: String,
    pub xmax: Option<f64>,
    pub t1: Option<f64>,
    pub di: Option<f64>,
    pub impacts: u64,
}

impl PeerFile {
    /// Reads the peer's JSON.
    pub fn load(path: &Path) -> anyhow::Result<PeerFile> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))
    }
}

/// Peer rows, when the peer ran the same reference set (matched by `e`); empty otherwise.
pub fn peer_rows(peer: &PeerFile, reference: &Reference, truth: &[Record]) -> Vec<Row> {
    let mut rows = Vec::new();
    for m in &peer.methods {
        let mut got = Vec::with_capacity(truth.len());
        for sys in &reference.systems {
            let Some(run) = m.runs.iter().find(|r| (r.e - sys.e).abs() < 1e-9) else {
                return Vec::new();
            };
            let nan = |v: Option<f64>| v.unwrap_or(f64::NAN);
            got.push(Observed {
                ok: run.outcome == "ok",
                finished: run.outcome != "chatter",
                xmax: nan(run.xmax),
                t1: nan(run.t1),
                di: nan(run.di),
                impacts: run.impacts,
            });
        }
        let mut row = Row::new(
            format!("{}-{}", peer.tool, m.method),
            format!("rtol = {:e}", m.rtol),
            "rtol",
            m.rtol,
            &compare(truth, &got),
        );
        row.atol = m.atol;
        row.time_per_run = m.time_per_run_s;
        row.cpu_per_run = m.cpu_per_run_s;
        row.reps = m.reps;
        rows.push(row);
    }
    rows
}
