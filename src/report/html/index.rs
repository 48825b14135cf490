//! `OUT/index.html`: one page for an output root, one row per study: its state, runs, wall
//! time, the recommended design, a thumbnail of the chart it is chosen by (its design chart, a
//! load study's risk map) and a link to its `report.html`. The command layer says what each run
//! directory holds ([`Row`]); the recommended design and the thumbnail are read back from the
//! study's `report.html` (its `<meta>` lines, [`super::META_RECOMMENDED`]). Links and images
//! are relative to the root, so the page works from a copy of the whole output root.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::markdown::esc;
use super::{CSS, META_BEST, META_RECOMMENDED, META_THUMBNAIL};
use crate::report::text::thousands;

/// Where a study's sweep stands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum State {
    Complete,
    /// Some chunks done, no writer at work.
    Partial,
    /// A live lock: a writer is at work.
    Running,
    /// Part files failed their checksum.
    Damaged,
    /// The run directory could not be read (why).
    Unreadable(String),
}

impl State {
    fn css(&self) -> &'static str {
        match self {
            State::Complete => "complete",
            State::Partial => "partial",
            State::Running => "running",
            State::Damaged => "damaged",
            State::Unreadable(_) => "unreadable",
        }
    }
}

/// Whether a study has its report, and whether it is newer than its data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Report {
    NotReduced,
    /// Older than the newest part file.
    Stale,
    Current,
}

/// One study of the output root, as the command layer found it.
#[derive(Clone, Debug)]
pub struct Row {
    /// The run directory's name (the study's name).
    pub name: String,
    pub state: State,
    /// The state in words, as `status` says it: `complete`, `chunks 3/8 done`, ….
    pub state_text: String,
    pub runs_done: u64,
    pub n_runs: u64,
    /// From the study's start to its last part file (s), by the files' times.
    pub wall_s: Option<f64>,
    pub report: Report,
}

/// The content of `<meta name="NAME" content="…">` in a page we wrote.
pub fn read_meta(html: &str, name: &str) -> Option<String> {
    let key = format!("<meta name=\"{name}\" content=\"");
    let start = html.find(&key)? + key.len();
    let len = html[start..].find('"')?;
    let v = &html[start..start + len];
    Some(
        v.replace("&quot;", "\"")
            .replace("&#39;", "'")
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&"),
    )
}

/// `42 s`, `3 min 5 s`, `2 h 07 min`.
pub fn duration(s: f64) -> String {
    if !s.is_finite() || s < 0.0 {
        return "–".into();
    }
    let t = s.round() as u64;
    if s < 0.1 {
        "< 0.1 s".into()
    } else if s < 10.0 {
        format!("{s:.1} s")
    } else if t < 60 {
        format!("{t} s")
    } else if t < 3600 {
        format!("{} min {} s", t / 60, t % 60)
    } else {
        format!("{} h {:02} min", t / 3600, (t % 3600) / 60)
    }
}

/// The page for the output root `root` (its run directories' pages are read from it).
pub fn page(root: &Path, rows: &[Row]) -> String {
    let title = format!(
        "impactsweep: {}",
        root.file_name().map_or_else(
            || root.display().to_string(),
            |n| n.to_string_lossy().to_string()
        )
    );
    let mut o = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<meta name=\"generator\" content=\"impactsweep\">\n<title>{}</title>\n<style>\n{CSS}</style>\n</head>\n<body>\n<main>\n<h1>{}</h1>\n<p>{} in this output root, in name order. Each study's report is <code>NAME/report.html</code> (and <code>report.md</code>); <code>impactsweep status DIR</code> says more about a study.</p>\n",
        esc(&title),
        esc(&title),
        if rows.len() == 1 {
            "1 study".to_string()
        } else {
            format!("{} studies", rows.len())
        }
    );
    o.push_str("<div class=\"table\"><table class=\"index\">\n<thead><tr><th>study</th><th>state</th><th>runs</th><th>wall time</th><th>recommended design</th><th>chart</th><th>report</th></tr></thead>\n<tbody>\n");
    for r in rows {
        o += &row(root, r);
    }
    o.push_str("</tbody></table></div>\n<p>Wall time: from the study's start (its <code>study.toml</code> written) to its last part file, by the files' times; a run stopped and resumed counts the pause.</p>\n</main>\n</body>\n</html>\n");
    o
}

fn row(root: &Path, r: &Row) -> String {
    let name = esc(&r.name);
    let page = root.join(&r.name).join("report.html");
    let html = match r.report {
        Report::NotReduced => None,
        _ => std::fs::read_to_string(&page).ok(),
    };
    let recommended = html
        .as_deref()
        .and_then(|h| read_meta(h, META_RECOMMENDED))
        .filter(|v| !v.is_empty());
    let thumbnail = html
        .as_deref()
        .and_then(|h| read_meta(h, META_THUMBNAIL))
        .filter(|t| !t.is_empty() && root.join(&r.name).join(t).is_file());
    let link = |inner: &str| {
        if html.is_some() {
            format!("<a href=\"{name}/report.html\">{inner}</a>")
        } else {
            inner.to_string()
        }
    };
    let mut state = esc(&r.state_text);
    if r.report == Report::NotReduced {
        state.push_str(", not reduced");
    }
    let mut o = format!(
        "<tr data-study=\"{name}\"><td>{}</td><td class=\"state-{}\">{state}</td><td>{} of {}</td><td>{}</td>",
        link(&format!("<strong>{name}</strong>")),
        r.state.css(),
        thousands(r.runs_done),
        thousands(r.n_runs),
        r.wall_s.map_or("–".to_string(), duration)
    );
    let _ = write!(
        o,
        "<td>{}</td>",
        match (&recommended, &html) {
            (Some(v), _) => esc(v),
            (None, Some(h)) => match read_meta(h, META_BEST).filter(|b| !b.is_empty()) {
                Some(b) => format!("none is robust; best ranked: {}", esc(&b)),
                None => "none (see the report)".to_string(),
            },
            (None, None) => "–".to_string(),
        }
    );
    let _ = write!(
        o,
        "<td>{}</td>",
        thumbnail.map_or("–".to_string(), |t| link(&format!(
            "<img src=\"{name}/{}\" alt=\"{name}: the chart it is chosen by\" loading=\"lazy\">",
            esc(&t)
        )))
    );
    let report = match (r.report, &html) {
        (Report::NotReduced, _) => "not reduced".to_string(),
        (_, None) => {
            format!("<code>{name}/report.md</code> (no <code>report.html</code>: reduce again)")
        }
        (Report::Stale, Some(_)) => format!(
            "<a href=\"{name}/report.html\">report.html</a> (older than the data: reduce again)"
        ),
        (Report::Current, Some(_)) => format!("<a href=\"{name}/report.html\">report.html</a>"),
    };
    let _ = writeln!(o, "<td>{report}</td></tr>");
    o
}

/// Writes `root/index.html`; returns its path.
pub fn write(root: &Path, rows: &[Row]) -> anyhow::Result<PathBuf> {
    let path = root.join("index.html");
    std::fs::write(&path, page(root, rows))
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meta_and_duration() {
        let h = "<head><meta name=\"a\" content=\"e = 0.5, &quot;x&quot; &amp; y\"></head>";
        assert_eq!(read_meta(h, "a").as_deref(), Some("e = 0.5, \"x\" & y"));
        assert_eq!(read_meta(h, "b"), None);
        assert_eq!(duration(3.25), "3.2 s");
        assert_eq!(duration(42.0), "42 s");
        assert_eq!(duration(185.0), "3 min 5 s");
        assert_eq!(duration(7620.0), "2 h 07 min");
    }
}
