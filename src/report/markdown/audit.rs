//! The accuracy audit of the run (`manifest.json`, key `audit`).

use std::fmt::Write;

/// The audit: relative errors as a table when they come as `{max, median, n}` objects, the rest
/// as a list, and the JSON itself.
pub fn section(a: &serde_json::Value) -> String {
    let mut o = String::from("## Accuracy audit\n\n");
    if let Some(map) = a.as_object() {
        let stats: Vec<_> = map
            .iter()
            .filter(|(_, v)| v.get("max").is_some() && v.get("median").is_some())
            .collect();
        if !stats.is_empty() {
            let _ = writeln!(
                o,
                "Points re-run against a tighter reference; relative errors:\n\n| quantity | max | median | n |\n|---|---|---|---|"
            );
            for (k, v) in stats {
                let num = |key: &str| {
                    v.get(key)
                        .and_then(|x| x.as_f64())
                        .map(|x| format!("{x:.2e}"))
                        .unwrap_or_else(|| "–".into())
                };
                let n = v.get("n").map(|x| x.to_string()).unwrap_or_default();
                let _ = writeln!(o, "| {k} | {} | {} | {n} |", num("max"), num("median"));
            }
            let _ = writeln!(o);
        }
        for (k, v) in map {
            if !(v.is_object() || v.is_array()) {
                let _ = writeln!(o, "- {k}: {v}");
            }
        }
        let _ = writeln!(o);
    }
    let _ = writeln!(
        o,
        "From `manifest.json`:\n\n```json\n{}\n```\n",
        serde_json::to_string_pretty(a).unwrap_or_default()
    );
    o
}
