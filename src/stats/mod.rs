//! Statistics of the simulated responses that the reducer and the census share: extreme values
//! over a design life ([`extremes`]), small failure probabilities by subset simulation
//! ([`subset`]), a Monte Carlo proportion's exact interval ([`binomial`]) and lognormal
//! fragility curves ([`fragility`]). Pure; no I/O.

pub mod binomial;
pub mod extremes;
pub mod fragility;
pub mod subset;
