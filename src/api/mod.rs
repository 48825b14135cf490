//! The calls the command line (`app`) and the Python binding share: a keyed single run
//! ([`setup`]; one realization of a random or record design in [`realization`], a batch of them in
//! [`random_batch`]), the sizing of a study ([`plan`]) and the reduction of a run directory
//! ([`reduce`]). The binding imports these, never the command line (`app`: arguments in,
//! printing out).
//!
//! A run directory's reduction chooses its scene in one place, [`reduce::reduce_dir`]: one
//! module per scene ([`free`], [`harmonic`], [`random`]), each returning a [`outputs::Reduced`];
//! what every scene writes is [`outputs`]'s, what a scene adds to it goes through
//! [`outputs::SceneOutputs`], and the arguments and options are [`reduce_options`]'s.

mod free;
mod harmonic;
pub mod json;
mod outputs;
pub mod plan;
pub mod random;
pub mod random_batch;
pub mod realization;
pub mod reduce;
mod reduce_options;
pub mod setup;
mod tables;
