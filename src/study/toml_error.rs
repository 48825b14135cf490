//! TOML errors → messages that name the file, the key, the value and what is allowed: a syntax
//! error gives `file:line:col`; a wrong type, an unknown or a missing key gives the key path
//! (`[sweep].e.step`) and the value as written.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::error::InputError;

/// One step of a key path: a table key or an array index.
enum Seg {
    Key(String),
    Index(usize),
}

/// Renders a key path as `[table].key[2].sub`.
fn render_path(path: &[Seg]) -> String {
    let mut out = String::new();
    for (i, seg) in path.iter().enumerate() {
        match (i, seg) {
            (0, Seg::Key(k)) => out.push_str(&format!("[{k}]")),
            (_, Seg::Key(k)) => out.push_str(&format!(".{k}")),
            (_, Seg::Index(j)) => out.push_str(&format!("[{j}]")),
        }
    }
    out
}

/// 1-based line and column (in characters) of a byte offset.
pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// The source text of a value, on one line and at most 60 characters.
pub(super) fn snippet(text: &str, span: &Range<usize>) -> String {
    let raw = text.get(span.clone()).unwrap_or("");
    let one_line: Vec<&str> = raw.split_whitespace().collect();
    let s = one_line.join(" ");
    if s.chars().count() > 60 {
        let cut: String = s.chars().take(57).collect();
        format!("{cut}...")
    } else {
        s
    }
}

pub(super) fn syntax_error(file: &str, text: &str, err: &toml::de::Error) -> InputError {
    let span = err.span().unwrap_or(0..0);
    let (line, col) = line_col(text, span.start);
    let mut msg = err.message().trim().to_string();
    if msg == "duplicate key" {
        msg = format!("duplicate key '{}'", snippet(text, &span));
    }
    InputError::new(format!("{file}:{line}:{col}: TOML syntax error: {msg}"))
}

struct Hit {
    path: Vec<Seg>,
    value: Range<usize>,
}

/// Finds the deepest key whose key span is `span` or whose value span contains it.
fn locate(table: &DeTable<'_>, span: &Range<usize>, path: &mut Vec<Seg>, best: &mut Option<Hit>) {
    for (k, v) in table.iter() {
        path.push(Seg::Key(k.get_ref().to_string()));
        consider(k.span() == *span, v, span, path, best);
        path.pop();
    }
}

fn consider(
    on_key: bool,
    v: &Spanned<DeValue<'_>>,
    span: &Range<usize>,
    path: &mut Vec<Seg>,
    best: &mut Option<Hit>,
) {
    let vs = v.span();
    let inside = vs.start <= span.start && span.end <= vs.end;
    if on_key || inside {
        let better = match best {
            None => true,
            Some(b) => {
                path.len() > b.path.len()
                    || (path.len() == b.path.len() && vs.len() < b.value.len())
            }
        };
        if better {
            let copy = path
                .iter()
                .map(|s| match s {
                    Seg::Key(k) => Seg::Key(k.clone()),
                    Seg::Index(i) => Seg::Index(*i),
                })
                .collect();
            *best = Some(Hit {
                path: copy,
                value: vs,
            });
        }
    }
    match v.get_ref() {
        DeValue::Table(t) => locate(t, span, path, best),
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                consider(false, item, span, path, best);
                path.pop();
            }
        }
        _ => {}
    }
}

/// Between the first pair of backticks after `prefix`.
fn quoted_after<'m>(msg: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = msg.strip_prefix(prefix)?;
    let rest = rest.strip_prefix('`')?;
    rest.split('`').next()
}

/// serde's "expected ..." in words a user reads.
fn human_expected(exp: &str) -> String {
    let exp = exp.trim();
    match exp {
        "f64" => "must be a number".into(),
        "u64" | "usize" => "must be a whole number >= 0".into(),
        "a string" => "must be a string".into(),
        "a sequence" => "must be a list".into(),
        "a boolean" => "must be true or false".into(),
        _ if exp.starts_with("struct ") || exp == "a map" => "must be a table".into(),
        _ => format!("expected {exp}"),
    }
}

/// An example of the list a key of `[perturb]` takes, for a study that gave one value.
fn list_example(key: &str) -> &'static str {
    match key {
        "noise_seeds" => ", one seed a case: for example noise_seeds = [1, 2, 3]",
        "dm" => ", one change of m (kg) a case: for example dm = [-0.001, 0.001]",
        "dd" => ", one change of d (m) a case: for example dd = [-0.0005, 0.0005]",
        _ => "",
    }
}

pub(super) fn serde_error(
    file: &str,
    text: &str,
    doc: &DeTable<'_>,
    err: &toml::de::Error,
) -> InputError {
    let msg = err.message().trim();
    let mut best = None;
    if let Some(span) = err.span() {
        locate(doc, &span, &mut Vec::new(), &mut best);
    }
    let (path, value) = match best {
        Some(h) => (h.path, snippet(text, &h.value)),
        None => (Vec::new(), String::new()),
    };
    let loc = render_path(&path);
    let tables =
        "study, scene, system, sweep, perturb, noise, solver, reliability, zones, ranking, run";
    let out = if let Some(field) = quoted_after(msg, "unknown field ") {
        let allowed = msg
            .split_once(", expected ")
            .map(|(_, e)| {
                e.replace('`', "")
                    .replace(" or ", ", ")
                    .replace("one of ", "")
            })
            .unwrap_or_default();
        if path.len() <= 1 {
            format!("[{field}]: unknown table; allowed tables: {tables}")
        } else if field == "im" {
            // The stripes are an axis, not a scene key: say where they go.
            format!(
                "{loc} = {value}: unknown key 'im' here; the stripes of an intensity measure \
                 are an axis: [sweep] im = [...] (g), with [scene] intensity = \"pga\" or \"sa\""
            )
        } else {
            format!("{loc} = {value}: unknown key '{field}'; allowed keys: {allowed}")
        }
    } else if let Some(field) = quoted_after(msg, "missing field ") {
        let mut p = path;
        let top = tables.split(", ").any(|t| t == field);
        let (Some(Seg::Key(_)), false) = (p.first(), top) else {
            return InputError::new(format!(
                "{file}: [{field}]: missing table; every study needs [{field}] with at least a name"
            ));
        };
        p.push(Seg::Key(field.to_string()));
        format!("{}: missing; this key is required", render_path(&p))
    } else if msg.starts_with("data did not match any variant of untagged enum RawAxis") {
        format!(
            "{loc} = {value}: an axis is a list of numbers, {{start, stop, step}} or \
             {{start, stop, num}}"
        )
    } else if msg.starts_with("invalid length ") && msg.contains(", expected struct ") {
        // serde reads a struct from a list too, and then complains about the list's length.
        format!("{loc} = {value}: must be a table")
    } else if let Some((_, exp)) = msg
        .strip_prefix("invalid type: ")
        .or_else(|| msg.strip_prefix("invalid value: "))
        .and_then(|m| m.rsplit_once(", expected "))
    {
        let example = match path.last() {
            Some(Seg::Key(k)) if human_expected(exp) == "must be a list" => list_example(k),
            _ => "",
        };
        format!("{loc} = {value}: {}{example}", human_expected(exp))
    } else if loc.is_empty() {
        msg.to_string()
    } else {
        format!("{loc} = {value}: {msg}")
    };
    InputError::new(format!("{file}: {out}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_count_characters() {
        assert_eq!(line_col("ab\ncdé\nf", 0), (1, 1));
        assert_eq!(line_col("ab\ncdé\nf", 3), (2, 1));
        assert_eq!(line_col("ab\ncdé\nf", 8), (3, 1));
        assert_eq!(line_col("ab\ncdé\nf", 7), (2, 4));
    }
}
