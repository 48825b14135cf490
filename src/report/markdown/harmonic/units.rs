//! The harmonic section of a study of several damper units (model.md §14): for each number of
//! units, its best design over the other axes against one unit of the same added mass: the
//! peak, the band where the damper helps, and how much of the band is periodic.

use std::fmt::Write;

use crate::reduce::harmonic::{Curve, HarmonicSummary};
use crate::report::markdown::words::{cm, f};
use crate::report::text::thousands;

/// Whether the study's designs carry several units.
pub(super) fn several(fs: &HarmonicSummary) -> bool {
    fs.curves.iter().any(|c| c.system.units > 1.0)
}

/// Whether the runs took the census of several units (issue 68; a dataset written before it,
/// or `starts = 0`, has none).
pub(super) fn census_taken(fs: &HarmonicSummary) -> bool {
    fs.curves
        .iter()
        .any(|c| c.points.iter().any(|p| p.attractors > 0))
}

/// How the design peak of a study of several units with its census is found, with the counts
/// over the ideal curves of frequencies whose design quantity is not periodic.
pub(super) fn reading(fs: &HarmonicSummary) -> String {
    let (mut frequencies, mut wandering, mut from_rest) = (0usize, 0usize, 0usize);
    for c in &fs.curves {
        frequencies += c.points.len();
        wandering += c
            .points
            .iter()
            .filter(|p| p.design.is_finite() && p.design_period == 0)
            .count();
        from_rest += c.points.iter().filter(|p| p.period == 0).count();
    }
    format!(
        "\n**The design peak.** The study has several damper units (docs/model.md §14). Each run goes from the study's initial state to its steady state (*from rest* above), then the census of several units at the same frequency runs its starts, each to its attractor: start 0 from the state the run ended in, the others seeded in the cavities (periodic orbits solved exactly by shooting on the 2 + 2N section, with their Floquet multipliers), for every design alike, one unit included. The design peak is the worst steady state found, and never below the run's own measured amplitude (start 0 continues the run's motion). A motion that does not settle on a periodic orbit within `n_trans_max` periods (quasi-periodic, chaotic, or a slow transient) is measured over the design life as one unit's is: the starts that did not settle are grouped into motions by where they wander (two motions at one frequency stay two rows of `attractors`, each with its own starts and state), each named by its largest Lyapunov exponent from two trajectories and measured by the race along each curve (docs/scenes.md, \"The amplitude over a design life\"); its design amplitude is that estimate, never below its largest amplitude over its last 200 periods and, for the run's own motion, the run's window. `reduce` measures the deciding designs' peaks again as for one unit (*The decision verified*), each motion restarted from its stored whole state (`section_units`). The periodic orbits stored are followed along the frequency as one unit's are (the `branches` table and chart; a unit at rest over an orbit is held where it rests; folds, period doublings, Neimark–Sacker points and branch points located between two points, a grazing where a branch ends). Over the ideal curves {} of {} frequencies have such a motion as their design quantity ({} from-rest runs did not repeat over their window). The band where the damper helps is the stretch around the linear system's resonance where the design quantity is below the linear system's amplitude, its ends interpolated where its attenuation crosses 1; \"band edge\" means it still helps at the end of the swept band.\n",
        thousands(wandering as u64),
        thousands(frequencies as u64),
        thousands(from_rest as u64)
    )
}

/// One design's figures: units, spread, ideal peak (m), PR, the help band and its width, the
/// periodic share.
struct Figures {
    units: f64,
    spread: f64,
    /// Units of their own (`[[system.unit]]`): different units, `d_spread` 0.
    table: bool,
    peak: f64,
    pr: f64,
    band: Option<(f64, f64, bool)>,
    periodic: f64,
}

impl Figures {
    fn of(c: &Curve) -> Figures {
        let peak = c.peak().0;
        Figures {
            units: c.system.units,
            spread: c.system.d_spread,
            table: c.system.table.is_some(),
            peak,
            pr: 1.0 - peak / c.linear_peak().0,
            band: c.help_band().map(|b| (b.from, b.to, b.to_edge)),
            periodic: c.periodic_share(),
        }
    }

    fn width(&self) -> f64 {
        self.band.map_or(0.0, |(a, b, _)| b - a)
    }

    fn band_text(&self) -> String {
        match self.band {
            Some((a, b, edge)) => format!(
                "{} – {}{} (width {})",
                f(a, 3),
                f(b, 3),
                if edge { ", band edge" } else { "" },
                f(b - a, 3)
            ),
            None => "none".to_string(),
        }
    }
}

/// The section: one row per number of units (its design with the lowest peak, and its design
/// with the widest band where the damper helps), then what splitting did, with numbers.
pub(super) fn section(fs: &HarmonicSummary) -> String {
    if !several(fs) {
        return String::new();
    }
    // Every design's ideal curve.
    let all: Vec<Figures> = fs
        .curves
        .iter()
        .map(Figures::of)
        .filter(|g| g.peak.is_finite())
        .collect();
    let mut o = String::new();
    let _ = writeln!(
        o,
        "\n## Several units\n\nThe same added mass split over several units, each in its own cavity (docs/model.md §14). For each number of units: its design with the lowest peak, and its design with the widest band where the damper helps, over the other axes. Equal clearances (`d_spread = 0`) with the units started together keep them in step: they are one unit of the same mass, and their curves differ from one unit's only where the motion is not periodic (there rounding grows to the size of the motion).{}\n",
        if all.iter().any(|g| g.table) {
            " The units of `[[system.unit]]` tables are the study's own (each its mass, clearance and restitution): `d_spread` reads 0 for them, and they are not one unit."
        } else {
            ""
        }
    );
    let best = table(&mut o, &all);
    scatter(&mut o, &all);
    if let Some((_, one_low, one_wide)) = best.iter().find(|b| b.0 == 1.0) {
        o.push('\n');
        for (n, low, wide) in best.iter().filter(|b| b.0 > 1.0) {
            against_one(&mut o, *n, (low, wide), (one_low, one_wide));
        }
    }
    o.push('\n');
    o
}

/// The table's rows, one per number of units; returns each number with its design of the
/// lowest peak and its design of the widest band.
fn table<'a>(o: &mut String, all: &'a [Figures]) -> Vec<(f64, &'a Figures, &'a Figures)> {
    let mut counts: Vec<f64> = all.iter().map(|g| g.units).collect();
    counts.sort_by(f64::total_cmp);
    counts.dedup();
    let _ = writeln!(
        o,
        "| units | lowest peak (cm) | at d_spread | PR | its band where the damper helps | widest band | at d_spread | its peak (cm) | periodic share of the band |\n|---|---|---|---|---|---|---|---|---|"
    );
    let mut best = Vec::new();
    for n in &counts {
        let of_n: Vec<&Figures> = all.iter().filter(|g| g.units == *n).collect();
        let low = of_n
            .iter()
            .min_by(|a, b| a.peak.total_cmp(&b.peak))
            .copied();
        let wide = of_n
            .iter()
            .max_by(|a, b| {
                a.width()
                    .total_cmp(&b.width())
                    .then(b.peak.total_cmp(&a.peak))
            })
            .copied();
        let (Some(low), Some(wide)) = (low, wide) else {
            continue;
        };
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} % |",
            f(*n, 0),
            cm(low.peak),
            f(low.spread, 2),
            f(low.pr, 3),
            low.band_text(),
            f(wide.width(), 3),
            f(wide.spread, 2),
            cm(wide.peak),
            f(100.0 * wide.periodic, 0)
        );
        best.push((*n, low, wide));
    }
    best
}

/// How far the peaks of the designs that are one unit in effect scatter. Equal clearances are
/// one unit whatever their number: that scatter is the estimator's noise (window maxima of
/// motions that are not periodic), not physics.
fn scatter(o: &mut String, all: &[Figures]) {
    let same: Vec<f64> = all
        .iter()
        .filter(|g| (g.spread == 0.0 && !g.table) || g.units == 1.0)
        .map(|g| g.peak)
        .collect();
    if same.len() > 1 {
        let lo = same.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = same.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let _ = writeln!(
            o,
            "\nThe {} designs that are one unit in effect (one unit, or equal clearances) peak between {} and {} cm: a scatter of {} % among designs that splitting does not change while their units move in step (the census's seeded starts part units of equal clearance, and a motion that is not periodic carries an estimate). A difference within it is not a gain from splitting.",
            same.len(),
            cm(lo),
            cm(hi),
            f((hi / lo - 1.0) * 100.0, 1)
        );
    }
}

/// `n` units' lowest peak and widest band against one unit's.
fn against_one(
    o: &mut String,
    n: f64,
    (low, wide): (&Figures, &Figures),
    (one_low, one_wide): (&Figures, &Figures),
) {
    let peak = (low.peak / one_low.peak - 1.0) * 100.0;
    let width = if one_wide.width() > 0.0 {
        (wide.width() / one_wide.width() - 1.0) * 100.0
    } else {
        f64::NAN
    };
    let _ = writeln!(
        o,
        "- **{} units** against one: the lowest peak {} cm (d_spread = {}) against {} cm, {}{} %; the widest band where the damper helps {} (d_spread = {}, its peak {} cm) against {}, {}{} % wider.",
        f(n, 0),
        cm(low.peak),
        f(low.spread, 2),
        cm(one_low.peak),
        if peak >= 0.0 { "+" } else { "" },
        f(peak, 1),
        f(wide.width(), 3),
        f(wide.spread, 2),
        cm(wide.peak),
        f(one_wide.width(), 3),
        if width >= 0.0 { "+" } else { "" },
        f(width, 0)
    );
}
