//! Statistics of the simulated responses that the reducer and the census share: extreme values
//! over a design life ([`extremes`]), the percentile bootstrap over a design's motions
//! ([`bootstrap`]), small failure probabilities by subset simulation
//! ([`subset`]), a Monte Carlo proportion's exact interval ([`binomial`]) and lognormal
//! fragility curves ([`fragility`]), a design's fragility from its capacities ([`capacity`]) and
//! annual risk over a hazard curve ([`hazard`]). Pure; no I/O.

pub mod binomial;
pub mod bootstrap;
pub mod capacity;
pub mod extremes;
pub mod fragility;
pub mod hazard;
pub mod subset;
