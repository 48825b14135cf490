//! The censuses' shared settings (one unit's, [`super::census`], and several units',
//! [`super::units::census`]): a leaf, so that both and the attractor rows read them without
//! importing the module that runs them.

/// Periods a motion that is not periodic is measured over in the census
/// ([`super::census::CensusSettings::window`]; the last periods of a start of several units
/// that does not settle).
pub const CENSUS_WINDOW: u64 = 200;

/// Relative `p`-step difference at which the census hands a start over to Newton
/// ([`super::census::CensusSettings::handover`]).
pub const HANDOVER: f64 = 1e-3;
