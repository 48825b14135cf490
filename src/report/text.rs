//! Text shared by the charts, the markdown report and the HTML page: numbers at label precision,
//! axis keys with their units, counts with their nouns. Below all three, so none imports another
//! for a word.

/// Unit of a system key (or of a harmonic study's `F0` and `omega`), for axis labels.
pub fn axis_unit(key: &str) -> &'static str {
    match key {
        "F0" => "N",
        "omega" => "rad/s",
        k => crate::model::System::unit(k),
    }
}

/// An axis label: `coefficient of restitution e (–)`, `m (kg)`.
pub fn axis_desc(key: &str) -> String {
    match key {
        "e" => "coefficient of restitution e (–)".into(),
        k => format!("{k} ({})", axis_unit(k)),
    }
}

/// `m = 0.02 kg`.
pub fn axis_value(key: &str, v: f64) -> String {
    match axis_unit(key) {
        "–" => format!("{key} = {}", fmt_num(v)),
        u => format!("{key} = {} {u}", fmt_num(v)),
    }
}

/// Short number formatting for labels.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.4e}")
    }
}

/// `1 jump`, `3 jumps`, `1,247 jumps`: a count and its noun (`plural` when not 1).
pub fn count(n: u64, noun: &str, plural: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{} {plural}", thousands(n))
    }
}

/// `1,247,148`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}
