//! The calls the command line ([`crate::app`]) and the Python binding share: a keyed single run
//! ([`setup`]; one realization of a random or record design in [`realization`], a batch of them in
//! [`random_batch`]), the sizing of a study ([`plan`]) and the reduction of a run directory
//! ([`reduce`]; a random or record study's in [`random`]). The binding imports these, never [`crate::app`], which is only the command
//! line (arguments in, printing out).

pub mod json;
pub mod plan;
pub mod random;
pub mod random_batch;
pub mod realization;
pub mod reduce;
pub mod setup;
mod tables;
