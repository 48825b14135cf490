//! Errors users hit. An [`InputError`] is bad input (a key, a value, a study file): the binary
//! exits with status 2 for it. Anything else (I/O, a broken dataset) exits with status 1.

/// Bad user input: the message names the file (when there is one), the key, the value and what
/// is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

impl InputError {
    pub fn new(msg: impl Into<String>) -> Self {
        InputError(msg.into())
    }
}

/// A sweep stopped by an interrupt (Ctrl-C, SIGTERM) after writing the chunks in hand; the run
/// directory is consistent and `--resume` continues it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "interrupted: {written} chunks written and {left} left in {dir}; run again with --resume to finish"
)]
pub struct Interrupted {
    pub dir: String,
    pub written: u64,
    pub left: u64,
}

/// Exit status for an interrupted sweep (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Exit status for bad input (documented in `--help`).
pub const EXIT_INPUT: i32 = 2;
/// Exit status for any other failure.
pub const EXIT_FAILURE: i32 = 1;

/// The exit status an error maps to.
pub fn exit_code(err: &anyhow::Error) -> i32 {
    let is = |f: fn(&(dyn std::error::Error + 'static)) -> bool| err.chain().any(f);
    if is(|e| e.downcast_ref::<Interrupted>().is_some()) {
        EXIT_INTERRUPTED
    } else if is(|e| e.downcast_ref::<InputError>().is_some()) {
        EXIT_INPUT
    } else {
        EXIT_FAILURE
    }
}
