//! The parse context every table's validation shares: the file, its text and its parsed TOML
//! document, to build messages that name the file, the key, the value and what is allowed
//! (`study.toml: [system].e = 1.3: ...`), and the number format of those messages.
//!
//! A leaf: every module of `study/` may import it, and it imports none of them but the TOML
//! snippets of `toml_error.rs`.

use toml::de::DeTable;

use super::toml_error::snippet;
use crate::error::InputError;
use crate::model::{RangeError, fmt_value};

/// Error builder for one file.
pub(super) struct Cx<'a> {
    /// The file as messages name it.
    pub(super) file: String,
    text: &'a str,
    doc: &'a DeTable<'a>,
}

impl<'a> Cx<'a> {
    /// The context of `file`, whose text is `text` and parsed document `doc`.
    pub(super) fn new(file: String, text: &'a str, doc: &'a DeTable<'a>) -> Cx<'a> {
        Cx { file, text, doc }
    }

    pub(super) fn err(
        &self,
        loc: &str,
        value: impl std::fmt::Display,
        allowed: impl std::fmt::Display,
    ) -> InputError {
        InputError::new(format!("{}: {loc} = {value}: {allowed}", self.file))
    }

    /// The source text of `[table].key`, on one line.
    pub(super) fn source(&self, table: &str, key: &str) -> String {
        self.doc
            .get(table)
            .and_then(|t| t.get_ref().as_table())
            .and_then(|t| t.get(key))
            .map(|v| snippet(self.text, &v.span()))
            .unwrap_or_default()
    }

    /// The position of a key in the file (for file order of `[sweep]`).
    pub(super) fn key_pos(&self, table: &str, key: &str) -> usize {
        self.doc
            .get(table)
            .and_then(|t| t.get_ref().as_table())
            .and_then(|t| t.get_key_value(key))
            .map(|(k, _)| k.span().start)
            .unwrap_or(usize::MAX)
    }
}

/// A number as a user would write it: shortest round-trip digits, in exponent form when very
/// small or very large (`5e-10`, not `0.0000000005`).
pub fn num(v: f64) -> String {
    fmt_value(v)
}

/// A [`RangeError`]'s value in the same form.
pub(super) fn range_value(e: &RangeError) -> String {
    e.value.parse::<f64>().map_or_else(|_| e.value.clone(), num)
}
