//! Statistics of the simulated responses that the reducer and the census share: extreme values
//! over a design life ([`extremes`]). Pure; no I/O.

pub mod extremes;
