//! `[noise]`: the measurement noise added to the noisy cases (off when the table is absent).

use serde::Deserialize;

use super::context::{Cx, range_value};
use crate::error::InputError;
use crate::sim::NoiseSettings;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawNoise {
    power: f64,
    sample_time: f64,
}

/// The validated `[noise]`.
pub(super) fn noise(cx: &Cx, raw: Option<&RawNoise>) -> Result<Option<NoiseSettings>, InputError> {
    Ok(match raw {
        None => None,
        Some(n) => {
            let ns = NoiseSettings {
                power: n.power,
                sample_time: n.sample_time,
            };
            ns.validate()
                .map_err(|e| cx.err(&format!("[noise].{}", e.key), range_value(&e), e.allowed))?;
            Some(ns)
        }
    })
}
