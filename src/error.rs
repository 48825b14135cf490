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

/// Exit status for bad input (documented in `--help`).
pub const EXIT_INPUT: i32 = 2;
/// Exit status for any other failure.
pub const EXIT_FAILURE: i32 = 1;

/// The exit status an error maps to.
pub fn exit_code(err: &anyhow::Error) -> i32 {
    if err
        .chain()
        .any(|e| e.downcast_ref::<InputError>().is_some())
    {
        EXIT_INPUT
    } else {
        EXIT_FAILURE
    }
}
