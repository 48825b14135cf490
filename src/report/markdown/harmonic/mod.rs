//! The harmonic scene's section (model.md §8): each design's frequency response in one table
//! (its peak over the band, the linear system's, the band where the damper helps, how much of
//! the band is periodic), and how to read the curves.

use std::fmt::Write;

mod life;
mod units;

use crate::report::markdown::words::{MAX_ROWS, SceneText, cm, design_text, f, ranked};

use crate::reduce::common::tables::outcome_text;
use crate::reduce::harmonic::{Curve, HarmonicSummary};
use crate::reduce::{PointStats, Summary};
use crate::report::text::{count, fmt_num, thousands};
use crate::sim::harmonic::{DesignPeak, NonPeriodicPeak};
use crate::study::Study;

/// Why a dataset's peaks carried by motions that are not periodic have no design-life estimate.
fn unmeasured_reason(fs: &HarmonicSummary) -> &'static str {
    if units::several(fs) && !units::census_taken(fs) {
        "several damper units without a census: no design lives"
    } else if fs.design_peak == DesignPeak::FromRest {
        "`design_peak = \"from_rest\"`: no census"
    } else if fs.nonperiodic_peak == NonPeriodicPeak::Window {
        "`nonperiodic_peak = \"window\"`"
    } else if units::several(fs) {
        "its measurement made no estimate: too few clusters of large maxima, or maxima that repeat"
    } else {
        "a dataset written before life estimates"
    }
}

/// What the harmonic scene adds to the report ([`SceneText`]): its section after the
/// recommendation ([`section`]), a design point called a design, whose runs are its frequencies
/// times its cases, and whether motions that are not periodic carry window maxima.
pub fn scene_text(study: &Study, s: &Summary, fs: &HarmonicSummary) -> SceneText {
    let cases = study.cases.len() as u64;
    let n = study.curve_points();
    SceneText {
        section: section(s, fs),
        point: ("design", "designs"),
        per_point: (n > 1).then(|| {
            format!(
                "{} × {} per design",
                count(n, "frequency", "frequencies"),
                count(cases, "case", "cases")
            )
        }),
        window_peaks: fs.nonperiodic_peak == NonPeriodicPeak::Window,
        ..SceneText::default()
    }
}

/// The harmonic scene's section: each design's frequency response in one table, the notes on
/// it, the steady states that are not periodic ([`life`]) and where steady states coexist.
pub fn section(s: &Summary, fs: &HarmonicSummary) -> String {
    let mut o = intro(fs);
    let shown: Vec<&PointStats> = {
        let r = ranked(s);
        if r.is_empty() {
            s.points.iter().collect()
        } else {
            r
        }
    };
    let _ = writeln!(
        o,
        "| rank | design | peak amplitude, ideal (cm) [90 % interval] | at r | carried by | from rest (cm) | linear peak (cm) at r | PR, ideal | the damper helps for r in | periodic | not converged |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut wandering_peaks = 0usize;
    let (mut edge_designs, mut edge_r) = (0usize, Vec::new());
    for p in shown.iter().take(MAX_ROWS) {
        let Some(c) = fs.curve(p.point) else {
            continue;
        };
        let (row, wandering) = design_row(s, c, p);
        o.push_str(&row);
        wandering_peaks += usize::from(wandering);
        if let Some(r) = peak_at_band_end(fs, c) {
            edge_designs += 1;
            edge_r.push(r);
        }
    }
    if wandering_peaks > 0 {
        let _ = writeln!(
            o,
            "\n† {} of these peaks {} at a frequency whose motion did not settle on a periodic orbit and whose amplitude over the design life was not measured ({}): such a peak is the largest excursion of a wandering motion over a window, a lower bound of what that motion reaches, and indicative only.",
            wandering_peaks,
            if wandering_peaks == 1 { "lies" } else { "lie" },
            unmeasured_reason(fs)
        );
    }
    o.push_str(&band_end(edge_designs, edge_r));
    let top = &shown[..shown.len().min(MAX_ROWS)];
    o.push_str(&coarse_band(fs, top));
    o.push_str(&life::section(s, fs, top));
    o.push_str(&coexistence(s, fs, top));
    if shown.len() > MAX_ROWS {
        let _ = writeln!(
            o,
            "\n… and {} more designs (columns `peak_r`, `linear_peak`, `help_r_from`, `help_r_to`, `help_share`, `periodic_share`, `peak_periodic` of the summary).",
            shown.len() - MAX_ROWS
        );
    }
    o.push_str(&reading(fs));
    o.push_str(&units::section(fs));
    o
}

/// The note on designs whose peak lies at an end of the band (`designs` of them, at `r`).
fn band_end(designs: usize, mut r: Vec<f64>) -> String {
    if designs == 0 {
        return String::new();
    }
    r.sort_by(f64::total_cmp);
    r.dedup();
    let at: Vec<String> = r.iter().map(|r| f(*r, 3)).collect();
    format!(
        "\n**Peaks at the band's end.** The peak of {} at an end of the swept band (r = {}): the response beyond it was not simulated and may be higher, so such a peak and its PR are the band's, not the design's. Widen the frequency axis of `[sweep]` past it to see.\n",
        count(
            designs as u64,
            "of these designs lies",
            "of these designs lie"
        ),
        at.join(" and ")
    )
}

/// How far below its peak the swept frequencies may sample the linear system before the report
/// says the band is too coarse for the resonance (5 %).
pub const COARSE_LINEAR: f64 = 0.95;

/// The note on a band whose frequencies miss the linear resonance: the linear system's peak
/// between them ([`Curve::linear_peak_between`]) more than 5 % above the largest they sample,
/// for any of the designs shown (the first such design's figures are given).
fn coarse_band(fs: &HarmonicSummary, shown: &[&PointStats]) -> String {
    let coarse: Vec<&Curve> = shown
        .iter()
        .filter_map(|p| fs.curve(p.point))
        .filter(|c| {
            let (sampled, between) = (c.linear_peak().0, c.linear_peak_between().0);
            sampled < COARSE_LINEAR * between
        })
        .collect();
    let Some(c) = coarse.first() else {
        return String::new();
    };
    let ((sampled, r_s), (between, r_b)) = (c.linear_peak(), c.linear_peak_between());
    let step = c
        .points
        .windows(2)
        .map(|w| (w[1].r - w[0].r).abs())
        .fold(0.0, f64::max);
    format!(
        "\n**A band too coarse for the resonance** ({} of these designs). The linear system peaks at r = {} with {} cm, between the swept frequencies, which sample it at {} cm at most (r = {}): the band's step, up to {} in r, is wider than the resonance (its half-power width, 2ζ = {}). PR compares the design's sampled peak with that sampled linear peak, and a design's own peak can fall between the frequencies too. A finer step around that r resolves both.\n",
        coarse.len(),
        f(r_b, 4),
        cm(between),
        cm(sampled),
        f(r_s, 3),
        f(step, 4),
        f(2.0 * c.system.zeta(), 4)
    )
}

/// Where curve `c`'s ideal peak is (its `r`) when that is the first or last frequency of a
/// swept frequency band (`r` or `omega`; a curve along the force has no frequency axis, and its
/// peak is at its largest force by nature), else `None`.
fn peak_at_band_end(fs: &HarmonicSummary, c: &Curve) -> Option<f64> {
    if fs.frequency.as_ref().is_none_or(|(_, v)| v.len() < 2) {
        return None;
    }
    let (peak, r) = c.peak();
    let ends = [c.points.first()?.r, c.points.last()?.r];
    (peak.is_finite() && ends.contains(&r)).then_some(r)
}

/// The section's heading and what a design's response and damping quantity are.
fn intro(fs: &HarmonicSummary) -> String {
    let mut o = String::from("## Frequency response\n\n");
    let band = match &fs.frequency {
        Some((k, v)) if v.len() > 1 => format!(
            "{} frequencies, {k} from {} to {}",
            v.len(),
            fmt_num(v[0]),
            fmt_num(v[v.len() - 1])
        ),
        Some((k, v)) => format!("one frequency, {k} = {}", fmt_num(v[0])),
        None => "a single frequency".to_string(),
    };
    // At one frequency (no axis along the frequency or the force) there is no band.
    let response = if fs.frequency.is_none() && fs.curves.iter().all(|c| c.points.len() == 1) {
        "A design's response is its **steady amplitude at that frequency**: for each case the largest steady amplitude of its run, a sample of which gives the stress, R and the ranking. Its damping quantity is the **peak reduction** PR = 1 − amplitude / the linear system's amplitude there (the primary system without the inner mass): 0.9 means the damper removes 90 % of the linear amplitude, below 0 it makes it worse."
    } else {
        "A design's response is its **peak amplitude over the band**: for each case the largest steady amplitude of its runs, a sample of which gives the stress, R and the ranking. Its damping quantity is the **peak reduction** PR = 1 − peak amplitude / the linear system's peak over the band (the primary system without the inner mass): 0.9 means the damper removes 90 % of the resonance peak, below 0 it makes the peak worse."
    };
    let _ = writeln!(
        o,
        "Every design's curve has {band}; {} simulated ({}). {response}\n",
        count(fs.runs, "run was", "runs were"),
        outcome_text(&fs.outcomes, false)
    );
    o
}

/// Design `p`'s row of the table, and whether its peak is a wandering motion's window maximum
/// with no design-life estimate (marked †).
fn design_row(s: &Summary, c: &Curve, p: &PointStats) -> (String, bool) {
    let (peak, peak_r) = c.peak();
    let life = c
        .peak_attractor()
        .filter(|a| !a.kind.periodic() && a.life_lo.is_finite());
    let wandering = life.is_none() && peak.is_finite() && !c.peak_periodic();
    let mark = match life {
        Some(a) => format!(" [{} – {}]", cm(a.life_lo), cm(a.life_hi)),
        None if wandering => " †".to_string(),
        None => String::new(),
    };
    let (lin, lin_r) = c.linear_peak();
    let helps = match c.help_band() {
        // One frequency: whether it helps there, not a band.
        _ if c.points.len() == 1 => if c.points[0].helps() { "yes" } else { "no" }.to_string(),
        Some(b) => format!(
            "{}{} – {}{}",
            if b.from_edge { "≤ " } else { "" },
            f(b.from, 3),
            f(b.to, 3),
            if b.to_edge { " (band edge)" } else { "" }
        ),
        None => "not at the linear peak".to_string(),
    };
    let row = format!(
        "| {} | {} | {}{mark} | {} | {} | {} | {} at {} | {} | {} | {} % | {} |\n",
        p.rank.map(|r| r.to_string()).unwrap_or_default(),
        design_text(s, p.point),
        cm(peak),
        f(peak_r, 3),
        carried_by(c),
        cm(c.peak_from_rest().0),
        cm(lin),
        f(lin_r, 3),
        f(1.0 - peak / lin, 3),
        helps,
        f(100.0 * c.periodic_share(), 0),
        c.points.iter().filter(|q| !q.converged).count()
    );
    (row, wandering)
}

/// The steady state that carries a curve's peak: its kind or period and impacts, and its basin
/// share when the census measured one; where no start reached it, how the census found it.
fn carried_by(c: &Curve) -> String {
    c.peak_point().map_or(String::new(), |q| {
        let what = if q.design_period == 0 {
            c.peak_attractor()
                .map_or("not periodic", |a| a.kind.name())
                .to_string()
        } else if q.design_impacts == 0.0 {
            "no impacts".to_string()
        } else {
            format!(
                "period {}, {} impacts per period",
                q.design_period,
                f(q.design_impacts, 2)
            )
        };
        let found = match c.peak_attractor().map(|a| a.origin) {
            Some("up") => "continued up in r from the next lower frequency",
            Some("down") => "continued down in r from the next higher frequency",
            Some("recurrence") => "found from the close returns of a wandering motion",
            _ => "",
        };
        if q.design_share == 0.0 && !found.is_empty() {
            format!("{what}, no start reached it ({found})")
        } else if q.design_share.is_finite() {
            format!("{what}, basin {} %", f(100.0 * q.design_share, 0))
        } else {
            what
        }
    })
}

/// How the design peak is found and how to read the curves, with the counts over the ideal
/// curves of frequencies that are not periodic and runs that did not converge.
fn reading(fs: &HarmonicSummary) -> String {
    let mut o = String::new();
    let mut not_converged = 0usize;
    let mut not_periodic = 0usize;
    let mut frequencies = 0usize;
    for c in &fs.curves {
        frequencies += c.points.len();
        not_converged += c.points.iter().filter(|p| !p.converged).count();
        not_periodic += c.points.iter().filter(|p| p.period == 0).count();
    }
    if units::several(fs) && units::census_taken(fs) {
        o.push_str(&units::reading(fs));
        return o;
    }
    if units::several(fs) {
        let _ = writeln!(
            o,
            "\n**The design peak.** The study has several damper units (docs/model.md §14). No census was taken (`starts = 0`, or a dataset written before the census of several units), so no design lives either: each frequency's steady state is the one the run from the study's initial state settles on (*from rest* above), for every design alike, one unit included. A point is *periodic* when the motion repeats after 1 to 8 forcing periods; the others ({} of {} frequencies over the ideal curves) are quasi-periodic or chaotic, or still in their transient ({} runs reached `n_trans_max`), and carry their largest amplitude over the measuring window, a lower bound. The band where the damper helps is the stretch around the linear system's resonance where the steady amplitude is below the linear system's, its ends interpolated where the attenuation crosses 1; \"band edge\" means it still helps at the end of the swept band.",
            thousands(not_periodic as u64),
            thousands(frequencies as u64),
            thousands(not_converged as u64)
        );
        return o;
    }
    let _ = writeln!(
        o,
        "\n**The design peak.** {} Each run goes from the study's initial state to its steady state (*from rest* above), then an attractor census at the same frequency runs several starts, each to its attractor (periodic orbits solved exactly by shooting), and records the worst steady amplitude with its basin share (the share of the starts that reach it). *Carried by* names the steady state behind each design's peak. The census cannot promise a steady state whose basin none of its starts fell into; `branches.csv` and `attractors.csv` hold the periodic branches followed along r (stable and unstable, with folds SN, period doublings PD and grazings GR) and every attractor of every frequency of the ideal curves.\n\n**Reading the curves.** A point is *periodic* when the motion repeats after 1 to 8 forcing periods; the others ({} of {} frequencies over the ideal curves, from rest) are quasi-periodic or chaotic, or still in their transient; {} from-rest runs reached `n_trans_max` without their section converging (one may still repeat over its measuring window, so the two counts overlap without one holding the other); with the census their design amplitude is their largest amplitude over the design life (above; the frequency-response charts draw its 90 % interval as whiskers), without it the largest of a wandering motion over the window, a lower bound. The band where the damper helps is the stretch around the linear system's resonance where the design quantity is below the linear system's amplitude (its attenuation < 1: with `design_peak = \"worst\"` the worst steady state's, not the from-rest run's), its ends interpolated where that attenuation crosses 1; `≤` and \"band edge\" mean it still helps at the end of the swept band.\n",
        match fs.design_peak {
            crate::sim::harmonic::DesignPeak::Worst =>
                "The peak is the **worst steady state** found at each frequency (`[scene] design_peak = \"worst\"`): near resonance several steady states coexist, and the one reached from rest can be far below the worst.",
            crate::sim::harmonic::DesignPeak::FromRest =>
                "The peak is the steady state reached **from the initial state** (`[scene] design_peak = \"from_rest\"`); the worst steady state found may be higher (column `amplitude_worst` of the points).",
        },
        thousands(not_periodic as u64),
        thousands(frequencies as u64),
        thousands(not_converged as u64)
    );
    o
}

/// Where each design of `shown` has coexisting steady states (docs/reduce.md, "Bifurcations
/// over the design space"): the bands of r, and how they enter the ranking.
/// The bands of r where the census found coexisting steady states, per design shown. The
/// paragraph names `design_map` and `bifurcations.csv` only where the reduction can write them:
/// one damper unit (the continuation covers one) and a swept design axis they are drawn over.
fn coexistence(s: &Summary, fs: &HarmonicSummary, shown: &[&PointStats]) -> String {
    let mut lines = Vec::new();
    for p in shown {
        let Some(c) = fs.curve(p.point) else {
            continue;
        };
        let bands = c.coexistence_bands();
        if c.attractors.is_none() {
            continue;
        }
        let text = if bands.is_empty() {
            "one steady state at every frequency".to_string()
        } else {
            bands
                .iter()
                .map(|(a, b)| {
                    if a == b {
                        format!("r = {}", f(*a, 3))
                    } else {
                        format!("r = {} – {}", f(*a, 3), f(*b, 3))
                    }
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        lines.push(format!("- {}: {text}", design_text(s, p.point)));
    }
    if lines.is_empty() {
        return String::new();
    }
    let g = &s.grid;
    let mapped = !units::several(fs)
        && (0..g.n_axes())
            .any(|a| g.n(a) >= 2 && crate::orbits::twopar::Axis::of_key(g.key(a)).is_some());
    let where_drawn = if mapped {
        "; the shaded cells of `design_map`, with the folds, doublings and Neimark–Sacker curves of `bifurcations.csv` over the design axes"
    } else {
        ""
    };
    format!(
        "\n**Coexisting steady states.** Where the census found two or more steady states at a frequency (a periodic orbit and its mirror image, the same amplitude and multipliers, count once), the response can jump between them (the forced counterpart of the paper's zone II{where_drawn}). The bands of r, per design:\n\n{}\n\nThey enter the ranking through the design peak: with `design_peak = \"worst\"` a design's peak is the worst of its coexisting states, so the upper state of a jump is already counted; a design whose band reaches its peak's frequency can jump to that peak from a lower state.\n",
        lines.join("\n")
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::orbits::attractors::SteadyKind::Chaotic;
    use crate::reduce::harmonic::curve::CurvePoint;
    use crate::reduce::testing::attractor_row;
    use crate::sim::Outcome;

    /// A peak carried by a motion no start reached says how the census found it, not
    /// "basin 0 %".
    #[test]
    fn a_peak_no_start_reached_says_how_it_was_found() {
        let point = CurvePoint {
            r: 0.9,
            omega: 57.0,
            outcome: Outcome::Ok,
            amplitude: 1.0,
            linear: 2.0,
            attenuation: 1.5,
            impacts_per_period: 2.0,
            period: 0,
            converged: false,
            design: 3.0,
            design_period: 0,
            design_impacts: 2.0,
            design_share: 0.0,
            attractors: 2,
        };
        let mut down = attractor_row(0, Chaotic, 3.0, f64::NAN, 0.0);
        down.origin = "down";
        let mut c = Curve {
            design: 0,
            points: vec![point],
            system: crate::model::System::TABLE_I,
            f0: 1.0,
            attractors: Some(vec![attractor_row(0, Chaotic, 2.9, f64::NAN, 1.0), down]),
        };
        assert_eq!(
            carried_by(&c),
            "chaotic, no start reached it (continued down in r from the next higher frequency)"
        );
        c.points[0].design_share = 0.25;
        assert_eq!(carried_by(&c), "chaotic, basin 25 %");
    }
}
