//! A record file (`[scene] record = "path"` of a record study): a recorded accelerogram or force
//! history, read once at load and shared by every run.
//!
//! The format is CSV: a header naming two columns, `t` (s) and `a` (ground acceleration, m/s^2)
//! or `t` and `F` (a force on the main mass, N), then one row per sample. Blank lines and lines
//! starting with `#` are skipped. The samples must be evenly spaced and in increasing `t`:
//! `dt = (t_last - t_first) / (rows - 1)`, and every `t_i` within `1e-6 dt` of
//! `t_first + i dt` (a record written with enough digits passes; one resampled by hand
//! without does not). The run's `t = 0` is the first row. Every value must be a finite number.
//! Each error names the study, the key, the record file, the row (counted from the first data
//! row, with its line in the file) and what is allowed.
//!
//! A Parquet record (a path ending in `.parquet`) holds the same two columns, `t` and `a` or `t`
//! and `F`, of floats or integers ([`crate::store::columns`] reads them), with the same checks;
//! its rows are counted from 1.

use std::path::Path;
use std::sync::Arc;

use super::context::{Cx, num};
use crate::error::InputError;
use crate::sim::random::Input;

/// The copy of a record study's record in its run directory, beside `study.toml`: read when
/// the study's own path does not resolve from there (the run directory's study is the user's
/// text, with the record's path relative to where the user kept it).
pub const RECORD_COPY: &str = "record.csv";

/// The run directory's copy of a Parquet record ([`RECORD_COPY`]'s sibling).
pub const RECORD_COPY_PARQUET: &str = "record.parquet";

/// The name of the run directory's copy of the record the study names `shown`.
pub fn record_copy(shown: &str) -> &'static str {
    if is_parquet(Path::new(shown)) {
        RECORD_COPY_PARQUET
    } else {
        RECORD_COPY
    }
}

/// The folder of a run directory that holds the copies of a suite's records (`[scene] records`),
/// each under its own file name.
pub const SUITE_COPY: &str = "records";

/// A suite as the study gives it: a list of record files, or a folder of them.
pub(super) enum SuiteSource<'a> {
    List(&'a [String]),
    Folder(&'a str),
}

/// A suite's record files, in the suite's order: `(name, path)` with `name` the file name. A
/// list keeps its order; a folder's `.csv` and `.parquet` files come by name. Paths are relative
/// to the study's folder `dir`; one that does not resolve there is looked for in `dir`'s
/// [`SUITE_COPY`] (a run directory's copies). Two records of one file name are refused (their
/// copies would collide), as are an empty list or folder.
/// The error is the value as shown and what is allowed.
pub(super) fn suite_files(
    source: &SuiteSource<'_>,
    dir: &Path,
) -> Result<Vec<(String, std::path::PathBuf)>, (String, String)> {
    let name_of = |p: &Path| {
        p.file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_string()
    };
    let files: Vec<(String, std::path::PathBuf)> = match source {
        SuiteSource::List(list) => {
            if list.is_empty() {
                return Err((
                    "[]".into(),
                    "an empty list; give the record files (CSV t,a or Parquet) or a folder of them"
                        .into(),
                ));
            }
            let mut files = Vec::new();
            for shown in list.iter() {
                let path = dir.join(shown);
                let name = name_of(&path);
                let copy = dir.join(SUITE_COPY).join(&name);
                let path = if !path.exists() && copy.exists() {
                    copy
                } else {
                    path
                };
                if files.iter().any(|(n, _): &(String, _)| *n == name) {
                    return Err((
                        format!("{shown:?}"),
                        format!(
                            "two records named {name:?}; the records of a suite need distinct \
                             file names"
                        ),
                    ));
                }
                files.push((name, path));
            }
            files
        }
        SuiteSource::Folder(shown) => {
            let mut folder = dir.join(shown);
            if !folder.is_dir() && dir.join(SUITE_COPY).is_dir() {
                folder = dir.join(SUITE_COPY);
            }
            let entries = std::fs::read_dir(&folder).map_err(|e| {
                (
                    format!("{shown:?}"),
                    format!("cannot read the folder {}: {e}", folder.display()),
                )
            })?;
            let mut files: Vec<(String, std::path::PathBuf)> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.is_file()
                        && p.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                            e.eq_ignore_ascii_case("csv") || e.eq_ignore_ascii_case("parquet")
                        })
                })
                .map(|p| (name_of(&p), p))
                .collect();
            files.sort();
            if files.is_empty() {
                return Err((
                    format!("{shown:?}"),
                    format!(
                        "the folder {} holds no record (.csv or .parquet files); allowed: a \
                         folder of records or a list of files",
                        folder.display()
                    ),
                ));
            }
            files
        }
    };
    Ok(files)
}

/// Whether a record path names a Parquet file (by its extension, any case).
fn is_parquet(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// How far a sample's time may sit from its place on the grid, relative to `dt`.
pub const EVEN_TOL: f64 = 1e-6;

/// A record as read: its sample interval, its samples and what they are.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct RecordFile {
    pub dt: f64,
    pub values: Arc<[f64]>,
    pub input: Input,
}

/// Reads and checks the record at `path` (as the study wrote it in `shown`, resolved against the
/// study's folder).
pub(super) fn read(cx: &Cx, shown: &str, path: &Path) -> Result<RecordFile, InputError> {
    read_at(cx, "[scene].record", shown, path)
}

/// [`read`] for the key `at` (`[scene].record`, or `[scene].records` for a suite's file).
pub(super) fn read_at(
    cx: &Cx,
    at: &str,
    shown: &str,
    path: &Path,
) -> Result<RecordFile, InputError> {
    let value = format!("{shown:?}");
    if is_parquet(path) {
        if !path.exists() {
            return Err(cx.err(
                at,
                &value,
                format!(
                    "cannot read the record file {}: no such file",
                    path.display()
                ),
            ));
        }
        let read = crate::store::columns::read_f64_columns(path).and_then(|cols| {
            let names: Vec<&str> = cols.iter().map(|(n, _)| n.as_str()).collect();
            let input = input_of(&names)?;
            match cols.as_slice() {
                [(_, t), (_, v)] => check(t, v, input, &|i| format!("row {}", i + 1)),
                _ => unreachable!("input_of takes two columns"),
            }
        });
        return read.map_err(|why| cx.err(at, &value, format!("{}: {why}", path.display())));
    }
    let text = std::fs::read_to_string(path).map_err(|e| {
        cx.err(
            at,
            &value,
            format!("cannot read the record file {}: {e}", path.display()),
        )
    })?;
    parse(&text).map_err(|why| cx.err(at, &value, format!("{}: {why}", path.display())))
}

/// Parses and checks a record's CSV text (module doc); the error says where and what is
/// allowed.
pub(super) fn parse(text: &str) -> Result<RecordFile, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err("the file is empty; it needs a header t,a or t,F and at least two rows".into());
    };
    let names: Vec<&str> = header
        .split(',')
        .map(|c| c.trim().trim_matches('"'))
        .collect();
    let input = input_of(&names)?;
    let column = names[1];
    let mut ts: Vec<f64> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut rows: Vec<usize> = Vec::new();
    for (line, body) in lines {
        let row = ts.len() + 1;
        let at = format!("row {row} (line {line})");
        let cells: Vec<&str> = body.split(',').map(str::trim).collect();
        if cells.len() != 2 {
            return Err(format!(
                "{at}: {} values; each row holds t and {column}",
                cells.len()
            ));
        }
        let mut pair = [0.0; 2];
        for (slot, (cell, name)) in pair.iter_mut().zip(cells.iter().zip(["t", column])) {
            let v: f64 = cell
                .parse()
                .map_err(|_| format!("{at}: {name} = {cell:?} is not a number"))?;
            if !v.is_finite() {
                return Err(format!(
                    "{at}: {name} = {cell}: every value must be a finite number"
                ));
            }
            *slot = v;
        }
        if let Some(&prev) = ts.last()
            && pair[0] <= prev
        {
            return Err(not_after(&at, pair[0], prev));
        }
        ts.push(pair[0]);
        values.push(pair[1]);
        rows.push(line);
    }
    check(&ts, &values, input, &|i| {
        format!("row {} (line {})", i + 1, rows[i])
    })
}

/// The message for a sample at `at` whose time `t` does not follow the previous one's `prev`.
fn not_after(at: &str, t: f64, prev: f64) -> String {
    format!(
        "{at}: t = {} is not after the previous row's t = {}: the times must increase",
        num(t),
        num(prev)
    )
}

/// What a record's two columns are: `t,a` ground acceleration, `t,F` a force.
fn input_of(names: &[&str]) -> Result<Input, String> {
    match names {
        ["t", "a"] => Ok(Input::Base),
        ["t", "F"] => Ok(Input::Force),
        _ => Err(format!(
            "the columns are {}; allowed: t,a (ground acceleration, m/s^2) or t,F (force on the \
             main mass, N)",
            names.join(", ")
        )),
    }
}

/// Checks a record's samples (at least two, evenly spaced; the values finite and `t`
/// increasing as read), `row(i)` naming sample `i` in messages.
fn check(
    ts: &[f64],
    values: &[f64],
    input: Input,
    row: &dyn Fn(usize) -> String,
) -> Result<RecordFile, String> {
    let column = if input == Input::Base { "a" } else { "F" };
    for (i, (&t, &v)) in ts.iter().zip(values).enumerate() {
        for (name, x) in [("t", t), (column, v)] {
            if !x.is_finite() {
                return Err(format!(
                    "{}: {name} = {}: every value must be a finite number",
                    row(i),
                    num(x)
                ));
            }
        }
        if i > 0 && t <= ts[i - 1] {
            return Err(not_after(&row(i), t, ts[i - 1]));
        }
    }
    if ts.len() < 2 {
        return Err(format!(
            "{} row{}; a record needs at least two samples",
            ts.len(),
            if ts.len() == 1 { "" } else { "s" }
        ));
    }
    let n = ts.len();
    let dt = (ts[n - 1] - ts[0]) / (n - 1) as f64;
    for (i, &t) in ts.iter().enumerate() {
        let grid = ts[0] + i as f64 * dt;
        if (t - grid).abs() > EVEN_TOL * dt {
            return Err(format!(
                "{}: t = {}: the samples must be evenly spaced; with dt = {} s ((t_last - \
                 t_first) / (rows - 1)) this row belongs at t = {}, within {} dt",
                row(i),
                num(t),
                num(dt),
                num(grid),
                num(EVEN_TOL)
            ));
        }
    }
    Ok(RecordFile {
        dt,
        values: values.to_vec().into(),
        input,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_good_record_is_read_with_its_step() {
        let r = parse("# an accelerogram\nt,a\n0.0,0.0\n0.01,0.5\n\n0.02,-0.25\n0.03,0\n").unwrap();
        assert_eq!(r.input, Input::Base);
        assert!((r.dt - 0.01).abs() < 1e-15);
        assert_eq!(&*r.values, &[0.0, 0.5, -0.25, 0.0]);
        let f = parse("t, F\n1.5, 2\n1.75, 3\n").unwrap();
        assert_eq!((f.input, f.dt), (Input::Force, 0.25));
    }

    #[test]
    fn bad_records_name_the_row_and_what_is_allowed() {
        let cases = [
            (
                "",
                "the file is empty; it needs a header t,a or t,F and at least two rows",
            ),
            (
                "time,acc\n0,1\n",
                "the columns are time, acc; allowed: t,a (ground acceleration, \
                 m/s^2) or t,F (force on the main mass, N)",
            ),
            ("t,a\n0,1\n", "1 row; a record needs at least two samples"),
            (
                "t,a\n0,1\n0.1,NaN\n",
                "row 2 (line 3): a = NaN: every value must be a finite number",
            ),
            (
                "t,a\n0,1\n0.1,x\n",
                "row 2 (line 3): a = \"x\" is not a number",
            ),
            (
                "t,a\n0,1\n0.1\n",
                "row 2 (line 3): 1 values; each row holds t and a",
            ),
            (
                "t,a\n0,1\n0.2,1\n0.1,1\n",
                "row 3 (line 4): t = 0.1 is not after the previous row's t = 0.2: the times must \
                 increase",
            ),
            (
                "t,a\n0,1\n0.5,1\n1.25,1\n1.5,1\n",
                "row 3 (line 4): t = 1.25: the samples must be evenly spaced; with dt = 0.5 s \
                 ((t_last - t_first) / (rows - 1)) this row belongs at t = 1, within 1e-6 dt",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(parse(text).unwrap_err(), want, "{text:?}");
        }
    }
}
