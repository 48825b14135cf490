//! The harmonic scene's charts: the frequency-response curves and the impacts per period and
//! period against the frequency ([`frequency_response`]), the recommended design's steady states
//! and basins ([`steady_states`]) and bifurcation diagram ([`bifurcation`]), and the design maps
//! of the located bifurcations over the design axes ([`design_map`]). They read the core's
//! summary and the scene's ([`crate::reduce::harmonic`]).

pub mod bifurcation;
pub mod design_map;
pub mod frequency_response;
pub mod steady_states;
