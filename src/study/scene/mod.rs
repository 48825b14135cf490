//! `[scene]`: what every run simulates (model.md §8 and §13, docs/scenes.md), and the one place
//! a study's scene chooses its parser: [`study`] reads `[scene] kind` and hands the raw study to
//! that scene's module.
//!
//! | kind | module | runs per design point |
//! |---|---|---|
//! | `"free"` (the default) | [`free`] | its cases (`[perturb]`) |
//! | `"harmonic"` | [`harmonic`] | its cases, each a frequency-response point |
//! | `"random"`, `"record"` | [`random`] (the load in [`random_load`]) | its realizations |
//!
//! The raw form of the file, `[scene]`'s keys of every scene among it, is [`raw`]'s; the tables
//! the free and harmonic scenes share are [`cased`]'s. A new scene is a module here, one arm
//! below and its name in the list of kinds ([`crate::sim::Scene::NAMES`] or
//! [`raw::RANDOM_KINDS`]).

use std::path::Path;

use crate::error::InputError;
use crate::study::validated::Study;

mod cased;
mod free;
pub(super) mod harmonic;
pub(super) mod random;
pub(super) mod random_load;
mod raw;

/// Parses and validates study text (no size guard): TOML syntax, then the raw form, then the
/// scene's parser, which validates each table in turn; the first error found is returned. A
/// random or record study is validated as a [`random::RandomStudy`] and becomes a [`Study`] of
/// [`Scene::Random`](crate::sim::Scene::Random).
pub(super) fn study(path: &Path, text: &str) -> Result<Study, InputError> {
    raw::with_raw(path, text, |cx, raw| {
        let default = raw::RawScene::default();
        let scene = raw.scene.as_ref().unwrap_or(&default);
        match scene.kind(cx)? {
            kind if raw::RANDOM_KINDS.contains(&kind) => {
                random::study(cx, raw, path, text).map(Study::from)
            }
            "harmonic" => harmonic::study(cx, raw, scene, path, text),
            // `kind` refused any other name.
            _ => free::study(cx, raw, scene, path, text),
        }
    })
}
