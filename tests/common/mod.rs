//! Studies built in Rust for the engine's tests (independent of the study-file parser).
#![allow(dead_code)]

use std::path::PathBuf;

use impactsweep::model::System;
use impactsweep::sim::{NoiseSettings, Request, SolverSettings};
use impactsweep::study::{
    Axis, Case, DiSource, Ranking, Reliability, RunSettings, SafetyForm, Study, Zones,
};

/// The Table I system, `e` over `n_e` values in [0.45, 0.95], `m` over 3 values, four cases per
/// point (ideal, a clearance change, two noisy ones), noise on.
pub fn study(name: &str, n_e: usize) -> Study {
    let e: Vec<f64> = (0..n_e)
        .map(|i| 0.45 + 0.5 * i as f64 / (n_e - 1) as f64)
        .collect();
    Study {
        path: PathBuf::from(format!("{name}.toml")),
        source: format!("# built in tests/determinism.rs\n[study]\nname = \"{name}\"\n"),
        name: name.to_string(),
        seed: 2013,
        request: Request::default(),
        system: System::TABLE_I,
        axes: vec![
            Axis {
                key: "e".into(),
                values: e,
            },
            Axis {
                key: "m".into(),
                values: vec![0.015, 0.02, 0.025],
            },
        ],
        cases: vec![
            Case {
                dm: 0.0,
                dd: 0.0,
                noise_seed: None,
                ideal: true,
            },
            Case {
                dm: 0.0,
                dd: 0.001,
                noise_seed: None,
                ideal: false,
            },
            Case {
                dm: 0.0,
                dd: 0.0,
                noise_seed: Some(23341),
                ideal: false,
            },
            Case {
                dm: 0.001,
                dd: -0.001,
                noise_seed: Some(22413),
                ideal: false,
            },
        ],
        noise: Some(NoiseSettings {
            power: 5e-9,
            sample_time: 1e-3,
        }),
        solver: SolverSettings::default(),
        reliability: Reliability {
            E: 200e9,
            r: 3.4e-3,
            L: 0.5,
            strength_mean: 300e6,
            strength_sd: 30e6,
            safety_form: SafetyForm::Exact,
            bootstrap: 200,
            confidence: 0.95,
        },
        zones: Zones {
            jump_k: 6.0,
            r_min: 0.98,
            di_strong: None,
            declared: vec![],
        },
        ranking: Ranking {
            wf1: 0.5,
            wf2: 0.5,
            di_source: DiSource::Ideal,
        },
        run: RunSettings {
            chunk_points: 16,
            audit: 0,
        },
    }
}
