//! The sections every scene's report has, in the report's order: [`cases`] (what was reduced,
//! the nominal design's cases, the outcomes, normality), [`settings`], [`recommendation`],
//! [`zones`], [`jumps`], [`sensitivity`], [`ranking`] and [`audit`]. They read the core's
//! summary and the study, and word what differs between scenes from the scene's
//! [`super::SceneText`].

pub mod audit;
pub mod cases;
pub mod jumps;
pub mod ranking;
pub mod recommendation;
pub mod sensitivity;
pub mod settings;
pub mod zones;
