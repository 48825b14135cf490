//! `[scene] kind = "free"` (or no `[scene]`): the paper's free decay from the initial state
//! (model.md §1–3). The scene has no keys of its own: every table is the shared one
//! ([`super::cased`]), and `[scene]` may only name the kind.

use std::path::Path;

use super::cased::{self, CasedScene};
use super::raw::{RawScene, RawStudy};
use crate::error::InputError;
use crate::sim::Scene;
use crate::study::context::Cx;
use crate::study::validated::Study;

/// The free-decay scene: every default of [`CasedScene`].
struct Free;

impl CasedScene for Free {
    fn scene(&self) -> Scene {
        Scene::Free
    }
}

/// A free-decay study: `[scene]` holds no other scene's key, then the shared tables.
pub(super) fn study(
    cx: &Cx,
    raw: &RawStudy,
    scene: &RawScene,
    path: &Path,
    text: &str,
) -> Result<Study, InputError> {
    scene.refuse_random_keys(cx)?;
    if let Some(key) = scene.harmonic_given().first() {
        return Err(cx.err(
            &format!("[scene].{key}"),
            cx.source("scene", key),
            format!(
                "{key} belongs to the harmonic scene; set [scene] kind = \"harmonic\" \
                 (the free-decay scene has no forcing)"
            ),
        ));
    }
    cased::study(cx, raw, path, text, &Free)
}
