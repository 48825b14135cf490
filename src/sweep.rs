//! The sweep engine: a rayon pool over chunks of a [`crate::plan::Plan`], resumable, sharded,
//! with a lock and a manifest. STUB: owned by the sweep-engine work.
