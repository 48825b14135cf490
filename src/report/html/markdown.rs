//! `report.md` as HTML: the small Markdown the report writes (headings, paragraphs, lists,
//! tables, `**bold**`, `` `code` ``, and image lines), so the page has exactly the report's
//! sections and words. An image line (`![a.svg](a.svg)`) becomes what `figure` returns for
//! its file name; a row of the zones table (first column `zone`) carries `data-zone`, so the
//! page's script can highlight that zone's cells on the maps.

use std::fmt::Write;

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

/// Inline Markdown: `` `code` `` and `**bold**`, the rest escaped.
pub fn inline(s: &str) -> String {
    let mut o = String::new();
    for (i, part) in s.split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(o, "<code>{}</code>", esc(part));
            continue;
        }
        for (j, t) in esc(part).split("**").enumerate() {
            if j % 2 == 1 {
                let _ = write!(o, "<strong>{t}</strong>");
            } else {
                o.push_str(t);
            }
        }
    }
    o
}

/// The cells of a table row `| a | b |`.
fn cells(line: &str) -> Vec<&str> {
    let t = line.trim();
    let t = t.strip_prefix('|').unwrap_or(t);
    let t = t.strip_suffix('|').unwrap_or(t);
    t.split('|').map(str::trim).collect()
}

/// The file of an image line `![alt](file)`.
fn image(line: &str) -> Option<&str> {
    let t = line.trim();
    let rest = t.strip_prefix("![")?;
    let (_, tail) = rest.split_once("](")?;
    tail.strip_suffix(')')
}

/// A table block (header, rule, rows); the zones table's rows carry `data-zone`.
fn table(lines: &[&str], zones: &[String]) -> String {
    let head = cells(lines[0]);
    let zone_table = head.first() == Some(&"zone");
    let mut o = String::from("<div class=\"table\"><table>\n<thead><tr>");
    for h in &head {
        let _ = write!(o, "<th>{}</th>", inline(h));
    }
    o.push_str("</tr></thead>\n<tbody>\n");
    for line in lines.iter().skip(2) {
        let row = cells(line);
        match row.first() {
            Some(z) if zone_table && zones.iter().any(|n| n == z) => {
                let _ = write!(
                    o,
                    "<tr class=\"zone-row\" data-zone=\"{}\" tabindex=\"0\" title=\"click: show zone {} on the maps\">",
                    esc(z),
                    esc(z)
                );
            }
            _ => o.push_str("<tr>"),
        }
        for c in &row {
            let _ = write!(o, "<td>{}</td>", inline(c));
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
    let lines: Vec<&str> = md.lines().collect();
    let mut o = String::new();
    let mut i = 0;
    let mut open_section = false;
    while i < lines.len() {
        let line = lines[i];
        let t = line.trim_start();
        if t.is_empty() {
            i += 1;
        } else if let Some(h) = t.strip_prefix("# ") {
            let _ = writeln!(o, "<h1>{}</h1>", inline(h));
            i += 1;
        } else if let Some(h) = t.strip_prefix("## ") {
            if open_section {
                o.push_str("</section>\n");
            }
            open_section = true;
            let _ = writeln!(o, "<section id=\"{}\">\n<h2>{}</h2>", slug(h), inline(h));
            i += 1;
        } else if let Some(h) = t.strip_prefix("### ") {
            let _ = writeln!(o, "<h3 id=\"{}\">{}</h3>", slug(h), inline(h));
            i += 1;
        } else if let Some(file) = image(t) {
            o.push_str(&figure(file)?);
            i += 1;
        } else if t.starts_with('|') {
            let start = i;
            while i < lines.len() && lines[i].trim_start().starts_with('|') {
                i += 1;
            }
            if i - start >= 2 {
                o.push_str(&table(&lines[start..i], zones));
            } else {
                let _ = writeln!(o, "<p>{}</p>", inline(t));
            }
        } else if t.starts_with("- ") {
            o.push_str("<ul>\n");
            while i < lines.len() && lines[i].trim_start().starts_with("- ") {
                let item = &lines[i].trim_start()[2..];
                let _ = writeln!(o, "<li>{}</li>", inline(item));
                i += 1;
            }
            o.push_str("</ul>\n");
        } else {
            // A paragraph: the lines up to a blank line or another block.
            let mut text = Vec::new();
            while i < lines.len() {
                let l = lines[i].trim_start();
                if l.is_empty()
                    || l.starts_with('#')
                    || l.starts_with('|')
                    || l.starts_with("- ")
                    || image(l).is_some()
                {
                    break;
                }
                text.push(l);
                i += 1;
            }
            let _ = writeln!(o, "<p>{}</p>", inline(&text.join(" ")));
        }
    }
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
        let md = "# T\n\nA **b** `c<d>` e\nf.\n\n## Zones (Table III)\n\n| zone | n |\n|---|---|\n| I | 3 |\n| x | 4 |\n\n- one\n- two\n\n![a.svg](a.svg)\n";
        let mut figs = Vec::new();
        let html = to_html(md, &["I".to_string()], &mut |f| {
            figs.push(f.to_string());
            Ok(format!("<figure>{f}</figure>"))
        })
        .unwrap();
        assert!(html.contains("<h1>T</h1>"));
        assert!(html.contains("<p>A <strong>b</strong> <code>c&lt;d&gt;</code> e f.</p>"));
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
