//! The choices the reducer takes ([`Options`]): the study's, which the command line can override,
//! with the response and the damping quantity its scene names.

use super::point::{Damping, Response};
use super::zones::ZoneParams;
use crate::study::{DiSource, SafetyForm, Study};

/// Choices the command line can override over the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub safety_form: SafetyForm,
    pub di_source: DiSource,
    /// Zone and jump settings beyond the study's `r_min`, `di_strong` and declared zones.
    pub zones: ZoneParams,
    pub response: Response,
    pub damping: Damping,
    /// Bootstrap resamples for R's interval (`[reliability].bootstrap`).
    pub bootstrap: usize,
}

impl Options {
    /// The study's own choices, with its scene's response and damping quantity
    /// ([`crate::reduce::free::options`], [`crate::reduce::harmonic::options`]).
    pub fn of_study(study: &Study, response: Response, damping: Damping) -> Options {
        Options {
            safety_form: study.reliability.safety_form,
            di_source: study.ranking.di_source,
            zones: ZoneParams {
                min_zone: study.zones.min_zone,
                step_spread: study.zones.step_spread,
                kink_slope: study.zones.kink_slope,
                locate: study.zones.locate,
            },
            response,
            damping,
            bootstrap: study.reliability.bootstrap,
        }
    }
}
