//! Statistics of the simulated responses that the reducer and the census share: extreme values
//! over a design life ([`extremes`]), small failure probabilities by subset simulation
//! ([`subset`]) and lognormal fragility curves ([`fragility`]). Pure; no I/O.

pub mod extremes;
pub mod fragility;
pub mod subset;
