//! `report.md` as HTML, parsed by pulldown-cmark (CommonMark with tables): every construct the
//! report writes (headings, paragraphs, lists, tables, `**bold**`, `*emphasis*`, `` `code` ``,
//! image lines) is rendered as CommonMark defines it, rather than by a hand-written subset that
//! must be taught each new construct. Three things are the page's own: each `##` heading opens a
//! `<section>` (its id the heading's [`slug`]), an image alone in its paragraph
//! (`![a.svg](a.svg)`) becomes what `figure` returns for its file name, and a row of the zones
//! table (first column `zone`) carries `data-zone`, so the page's script can highlight that
//! zone's cells on the maps. Raw HTML in the text is shown as text, never passed through.

use std::fmt::Write;

use pulldown_cmark::{Event, HeadingLevel, Options, Parser, Tag, TagEnd};

/// Escapes text for HTML content and attribute values.
pub fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c => o.push(c),
        }
    }
    o
}

/// A heading's anchor: `Zones (Table III)` → `zones-table-iii`.
pub fn slug(s: &str) -> String {
    let mut o = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            o.push(c.to_ascii_lowercase());
        } else if !o.ends_with('-') && !o.is_empty() {
            o.push('-');
        }
    }
    o.trim_end_matches('-').to_string()
}

/// The report's Markdown as events, raw HTML turned into text.
fn events(md: &str) -> Vec<Event<'_>> {
    Parser::new_ext(md, Options::ENABLE_TABLES)
        .map(|e| match e {
            Event::Html(t) | Event::InlineHtml(t) => Event::Text(t),
            e => e,
        })
        .collect()
}

/// Events as HTML.
fn render(events: &[Event<'_>]) -> String {
    let mut o = String::new();
    pulldown_cmark::html::push_html(&mut o, events.iter().cloned());
    o
}

/// The text of events (for anchors and the zone names).
fn text_of(events: &[Event<'_>]) -> String {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Text(t) | Event::Code(t) => Some(t.as_ref()),
            _ => None,
        })
        .collect()
}

/// Inline Markdown (one line: emphasis, strong, code) as HTML without a paragraph around it.
pub fn inline(s: &str) -> String {
    let evs: Vec<Event<'_>> = events(s)
        .into_iter()
        .filter(|e| {
            !matches!(
                e,
                Event::Start(Tag::Paragraph) | Event::End(TagEnd::Paragraph)
            )
        })
        .collect();
    render(&evs).trim_end().to_string()
}

/// The index of the first event from `from` that ends the block opened at `from`.
fn end_of(evs: &[Event<'_>], from: usize, end: fn(&TagEnd) -> bool) -> usize {
    (from + 1..evs.len())
        .find(|&j| matches!(&evs[j], Event::End(t) if end(t)))
        .unwrap_or(evs.len() - 1)
}

/// The file of a paragraph that holds one image and nothing else (`evs` its inner events).
fn lone_image<'a>(evs: &'a [Event<'_>]) -> Option<&'a str> {
    match evs.first()? {
        Event::Start(Tag::Image { dest_url, .. })
            if matches!(evs.last()?, Event::End(TagEnd::Image))
                && !evs[1..evs.len() - 1]
                    .iter()
                    .any(|e| matches!(e, Event::Start(_))) =>
        {
            Some(dest_url.as_ref())
        }
        _ => None,
    }
}

/// A table's events (from its start to its end) as HTML; the zones table's rows carry
/// `data-zone`.
fn table(evs: &[Event<'_>], zones: &[String]) -> String {
    // Rows of cells, each cell's inner events; the first row is the header.
    let mut rows: Vec<Vec<&[Event<'_>]>> = Vec::new();
    let mut i = 0;
    while i < evs.len() {
        match &evs[i] {
            Event::Start(Tag::TableHead) | Event::Start(Tag::TableRow) => {
                rows.push(Vec::new());
                i += 1;
            }
            Event::Start(Tag::TableCell) => {
                let end = end_of(evs, i, |t| matches!(t, TagEnd::TableCell));
                if let Some(row) = rows.last_mut() {
                    row.push(&evs[i + 1..end]);
                }
                i = end + 1;
            }
            _ => i += 1,
        }
    }
    let Some((head, body)) = rows.split_first() else {
        return String::new();
    };
    let zone_table = head.first().map(|c| text_of(c)).as_deref() == Some("zone");
    let mut o = String::from("<div class=\"table\"><table>\n<thead><tr>");
    for h in head {
        let _ = write!(o, "<th>{}</th>", render(h));
    }
    o.push_str("</tr></thead>\n<tbody>\n");
    for row in body {
        let first = row.first().map(|c| text_of(c)).unwrap_or_default();
        if zone_table && zones.contains(&first) {
            let _ = write!(
                o,
                "<tr class=\"zone-row\" data-zone=\"{}\" tabindex=\"0\" title=\"click: show zone {} on the maps\">",
                esc(&first),
                esc(&first)
            );
        } else {
            o.push_str("<tr>");
        }
        for c in row {
            let _ = write!(o, "<td>{}</td>", render(c));
        }
        o.push_str("</tr>\n");
    }
    o.push_str("</tbody></table></div>\n");
    o
}

/// The sections of the report: `(id, title)` of every `##` heading, in order.
pub fn sections(md: &str) -> Vec<(String, String)> {
    md.lines()
        .filter_map(|l| l.strip_prefix("## "))
        .map(|t| (slug(t), t.to_string()))
        .collect()
}

/// The report's Markdown as HTML. `zones` are the zone names (rows of the zones table that
/// get `data-zone`); `figure` turns an image's file name into its HTML.
pub fn to_html(
    md: &str,
    zones: &[String],
    figure: &mut dyn FnMut(&str) -> anyhow::Result<String>,
) -> anyhow::Result<String> {
    let evs = events(md);
    let mut o = String::new();
    let mut plain: Vec<Event<'_>> = Vec::new();
    let mut open_section = false;
    let mut i = 0;
    while i < evs.len() {
        match &evs[i] {
            Event::Start(Tag::Heading { level, .. }) => {
                o.push_str(&render(&std::mem::take(&mut plain)));
                let end = end_of(&evs, i, |t| matches!(t, TagEnd::Heading(_)));
                let inner = &evs[i + 1..end];
                let (html, id) = (render(inner), slug(&text_of(inner)));
                match level {
                    HeadingLevel::H1 => {
                        let _ = writeln!(o, "<h1>{html}</h1>");
                    }
                    HeadingLevel::H2 => {
                        if open_section {
                            o.push_str("</section>\n");
                        }
                        open_section = true;
                        let _ = writeln!(o, "<section id=\"{id}\">\n<h2>{html}</h2>");
                    }
                    other => {
                        let _ = writeln!(o, "<{other} id=\"{id}\">{html}</{other}>");
                    }
                }
                i = end + 1;
            }
            Event::Start(Tag::Paragraph) => {
                let end = end_of(&evs, i, |t| matches!(t, TagEnd::Paragraph));
                match lone_image(&evs[i + 1..end]) {
                    Some(file) => {
                        o.push_str(&render(&std::mem::take(&mut plain)));
                        o.push_str(&figure(file)?);
                    }
                    None => plain.extend(evs[i..=end].iter().cloned()),
                }
                i = end + 1;
            }
            Event::Start(Tag::Table(_)) => {
                o.push_str(&render(&std::mem::take(&mut plain)));
                let end = end_of(&evs, i, |t| matches!(t, TagEnd::Table));
                o.push_str(&table(&evs[i..=end], zones));
                i = end + 1;
            }
            e => {
                plain.push(e.clone());
                i += 1;
            }
        }
    }
    o.push_str(&render(&plain));
    if open_section {
        o.push_str("</section>\n");
    }
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_and_inline() {
        let md = "# T\n\nA **b** `c<d>` *e*\nf <g>.\n\n## Zones (Table III)\n\n| zone | n |\n|---|---|\n| I | 3 |\n| x | 4 |\n\n- one\n- two\n\n![a.svg](a.svg)\n";
        let mut figs = Vec::new();
        let html = to_html(md, &["I".to_string()], &mut |f| {
            figs.push(f.to_string());
            Ok(format!("<figure>{f}</figure>"))
        })
        .unwrap();
        assert!(html.contains("<h1>T</h1>"));
        assert!(
            html.contains(
                "<p>A <strong>b</strong> <code>c&lt;d&gt;</code> <em>e</em>\nf &lt;g&gt;.</p>"
            ),
            "{html}"
        );
        assert!(!html.contains('*'));
        assert!(html.contains("<section id=\"zones-table-iii\">"));
        assert!(html.contains("<tr class=\"zone-row\" data-zone=\"I\""));
        assert!(html.contains("<tr><td>x</td><td>4</td></tr>"));
        assert!(html.contains("<li>two</li>"));
        assert!(html.contains("<figure>a.svg</figure>"));
        assert_eq!(figs, ["a.svg"]);
        assert!(html.trim_end().ends_with("</section>"));
        assert_eq!(
            sections(md),
            [(
                "zones-table-iii".to_string(),
                "Zones (Table III)".to_string()
            )]
        );
    }
}
