//! DI against one axis (the paper's Figure 4), with the jumps located on that line marked:
//! steps as solid lines, kinks dashed.

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, Key, MANY, MAX_JUMP_LINES, Profile, RED_LINE, TITLE, err, minmax, pad, series_legend,
    xy_chart,
};

use crate::reduce::common::tables::quantity_of;
use crate::reduce::{Jump, JumpKind};
use crate::report::text::axis_desc;

pub struct DiChart<'a>(pub &'a Profile<'a>);

pub const SIZE: (u32, u32) = (900, 560);

/// The DI source as the legend says it.
pub fn di_source(s: &crate::reduce::Summary) -> &'static str {
    match s.options.di_source {
        crate::study::DiSource::Ideal => "ideal case",
        crate::study::DiSource::Mean => "mean over cases",
    }
}

impl Chart for DiChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let pr = self.0;
        let s = pr.s;
        let (x0, x1) = minmax(pr.positions());
        let (x0, x1) = if x1 > x0 { (x0, x1) } else { pad(x0, x1, 0.5) };
        let di = pr.series(|p| p.di);
        let (y0, y1) = minmax(di.iter().map(|p| p.1));
        let (y0, y1) = pad(y0.min(0.0), y1, 0.08);
        let d = &s.options.damping;
        let title = format!("{} {} against {}{}", d.title, d.symbol, pr.key(), pr.at());
        let mut chart = xy_chart(
            root,
            (&title, TITLE),
            (x0..x1, y0..y1),
            (&axis_desc(pr.key()), &d.label()),
            (&pr.xs, pr.scale),
        )?;
        let blue = crate::report::charts::plumbing::BLUE;
        chart
            .draw_series(LineSeries::new(di.clone(), blue.stroke_width(2)))
            .map_err(err)?
            .label(format!("{} ({})", s.options.damping.symbol, di_source(s)))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], blue.stroke_width(2))
            });
        if di.len() <= MANY {
            chart
                .draw_series(di.iter().map(|&p| Circle::new(p, 3, blue.filled())))
                .map_err(err)?;
        }
        jump_lines(&mut chart, pr, (y0, y1))?;
        series_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}

/// The colour of a step's line and of a kink's (dashed).
const STEP: RGBColor = RED_LINE;
const KINK: RGBColor = RGBColor(230, 120, 0);

/// Legend keys for the kinds of jumps on the profile, for charts with legend rows.
pub fn jump_keys(pr: &Profile) -> Vec<(Key, String)> {
    [JumpKind::Step, JumpKind::Kink]
        .into_iter()
        .filter_map(|kind| {
            let names = quantities(pr, pr.jumps.iter().copied(), kind)?;
            let key = match kind {
                JumpKind::Step => Key::Line(STEP),
                JumpKind::Kink => Key::Dashed(KINK),
            };
            Some((key, format!("{} of {names}", kind.name())))
        })
        .collect()
}

/// The quantities with a jump of `kind` among `jumps` ([`distinct`]); `None` when there is none.
/// One line colour stands for a kind, so its legend entry names every quantity it marks.
fn quantities<'a>(
    pr: &Profile,
    jumps: impl Iterator<Item = &'a Jump>,
    kind: JumpKind,
) -> Option<String> {
    distinct(
        jumps
            .filter(|j| j.kind == kind)
            .map(|j| quantity_of(pr.s, j.quantity).0),
    )
}

/// `names` each once, in the order they first appear, joined ("DI, xmax"); `None` for none.
fn distinct<'a>(names: impl Iterator<Item = &'a str>) -> Option<String> {
    let mut out: Vec<&str> = Vec::new();
    for name in names {
        if !out.contains(&name) {
            out.push(name);
        }
    }
    (!out.is_empty()).then(|| out.join(", "))
}

/// The jumps [`jump_lines`] draws: the largest [`MAX_JUMP_LINES`] by size, in the order of
/// their locations.
pub fn drawn_jumps<'a>(pr: &Profile<'a>) -> Vec<&'a Jump> {
    let mut jumps = pr.jumps.clone();
    jumps.sort_by(|a, b| b.size.abs().total_cmp(&a.size.abs()));
    jumps.truncate(MAX_JUMP_LINES);
    jumps.sort_by(|a, b| a.location.total_cmp(&b.location));
    jumps
}

/// Vertical lines at the jumps of the profile (the largest [`MAX_JUMP_LINES`] by size relative
/// to their kind's largest), steps solid, kinks dashed, one legend entry per kind naming every
/// quantity it marks.
pub fn jump_lines<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    pr: &Profile,
    (y0, y1): (f64, f64),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let n = pr.jumps.len();
    let jumps = drawn_jumps(pr);
    let mut labelled: Vec<JumpKind> = Vec::new();
    for j in &jumps {
        let x = pr.at_x(j.location);
        let color = match j.kind {
            JumpKind::Step => STEP.mix(0.8),
            JumpKind::Kink => KINK.mix(0.9),
        };
        let style = color.stroke_width(2);
        let series = match j.kind {
            JumpKind::Step => chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x, y0), (x, y1)],
                    style,
                )))
                .map_err(err)?,
            JumpKind::Kink => chart
                .draw_series(DashedLineSeries::new([(x, y0), (x, y1)], 6, 4, style))
                .map_err(err)?,
        };
        if labelled.contains(&j.kind) {
            continue;
        }
        labelled.push(j.kind);
        let names = quantities(pr, jumps.iter().copied(), j.kind).unwrap_or_default();
        let text = format!("{} of {names} (located)", j.kind.name());
        let text = if n > MAX_JUMP_LINES {
            format!("{text}; {MAX_JUMP_LINES} largest of {n} jumps")
        } else {
            text
        };
        // The key drawn as the line is: solid for a step, dashed for a kink.
        let (dash, gap) = match j.kind {
            JumpKind::Step => (18, 1),
            JumpKind::Kink => (6, 4),
        };
        series.label(text).legend(move |(x, y)| {
            DashedPathElement::new(vec![(x, y), (x + 18, y)], dash, gap, style)
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::distinct;

    #[test]
    fn a_kinds_legend_names_each_quantity_once_in_order() {
        // Jumps along the line alternate between the quantities: each is named once (a
        // `dedup` of neighbours named DI twice).
        let names = ["DI", "xmax", "DI", "DI", "xmax"];
        assert_eq!(distinct(names.into_iter()).as_deref(), Some("DI, xmax"));
        assert_eq!(distinct(["xmax"].into_iter()).as_deref(), Some("xmax"));
        assert_eq!(distinct(std::iter::empty()), None);
    }
}
