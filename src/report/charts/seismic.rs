//! The fragility chart of a study with capacities (an intensity measure and a threshold):
//! `fragility` (SVG, PNG, its data as CSV) in place of the fit to the stripes' counts. Two
//! panels over the intensity measure in g: `P(f | IM)` and `log10 P(f | IM)` (down to 1e-4,
//! where the hazard weighs the curve most). Each shown design's curve that its annual risk is
//! taken over (`Risk::curve`: the lognormal fitted to the stripes' counts where motions fall
//! back; else the capacities' curve, their lognormal where it holds, else their empirical step
//! curve; without a hazard the capacities' curve), its stripes' Monte Carlo `p_f` (markers)
//! with their Clopper–Pearson 95 % intervals (whiskers), and the structure without damper dashed
//! grey beside them. The legend sits in the log panel's lower right, where a curve rising with
//! the intensity never runs.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plumbing::{
    Chart, DESIGN_COLORS, Data, GREY, LABEL, Scale, err, render, series_legend, shorten, xy_chart,
};
use crate::reduce::Summary;
use crate::reduce::random::RandomSummary;
use crate::reduce::random::risk;
use crate::report::text::{axis_value, fmt_num};
use crate::stats::capacity::Capacities;
use crate::store::table::{Column, Table};

/// Designs drawn at most besides the structure without damper.
pub const MAX_DESIGNS: usize = 5;

/// The lowest probability the log panel shows.
const LOG_FLOOR: f64 = -4.0;

struct Curve {
    name: String,
    /// `(im, p)` along the curve.
    line: Vec<(f64, f64)>,
    /// `(im, p_f, lo, hi)` at each stripe.
    stripes: Vec<(f64, f64, f64, f64)>,
    bare: bool,
}

struct CapacityChart {
    title: String,
    x_desc: String,
    curves: Vec<Curve>,
    x: (f64, f64),
}

impl CapacityChart {
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        log: bool,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let y = |p: f64| {
            if log {
                p.log10().max(LOG_FLOOR - 0.2)
            } else {
                p
            }
        };
        let (title, y_range, y_desc) = if log {
            (
                "log10 P: the lower tail",
                (LOG_FLOOR - 0.1)..0.1,
                "log10 P(max |x| > limit)",
            )
        } else {
            ("P", -0.02..1.02, "P(max |x| > limit)")
        };
        let mut chart = xy_chart(
            area,
            (title, LABEL),
            (self.x.0..self.x.1, y_range),
            (&self.x_desc, y_desc),
            (&[], Scale::Linear),
        )?;
        let mut k = 0;
        for c in &self.curves {
            let color = if c.bare {
                GREY
            } else {
                k += 1;
                DESIGN_COLORS[(k - 1) % DESIGN_COLORS.len()]
            };
            let style = color.stroke_width(2);
            let pieces = if log {
                above_floor(&c.line, LOG_FLOOR - 0.1)
            } else {
                vec![c.line.clone()]
            };
            for line in pieces {
                if c.bare {
                    chart
                        .draw_series(DashedLineSeries::new(line, 8, 5, style))
                        .map_err(err)?;
                } else {
                    chart
                        .draw_series(LineSeries::new(line, style))
                        .map_err(err)?;
                }
            }
            let shown: Vec<&(f64, f64, f64, f64)> =
                c.stripes.iter().filter(|s| !log || s.1 > 0.0).collect();
            chart
                .draw_series(shown.iter().map(|&&(x, _, lo, hi)| {
                    let lo = if log && lo <= 0.0 {
                        LOG_FLOOR - 0.2
                    } else {
                        y(lo)
                    };
                    PathElement::new(vec![(x, lo), (x, y(hi))], color.stroke_width(1))
                }))
                .map_err(err)?;
            let series = chart
                .draw_series(
                    shown
                        .iter()
                        .map(|&&(x, p, _, _)| Circle::new((x, y(p)), 4, color.filled())),
                )
                .map_err(err)?;
            // The legend in the log panel's lower right: high intensity and low probability,
            // where a fragility curve (rising with the intensity) never is. (In the P panel's
            // corners the curves or the stripes' whiskers run.)
            if log {
                series.label(c.name.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
            }
        }
        if log {
            series_legend(&mut chart, SeriesLabelPosition::LowerRight)
        } else {
            Ok(())
        }
    }
}

/// The runs of the curve `(im, p)` whose `log10 p` lies at or above `floor` (the log panel's
/// bottom), each as `(im, log10 p)`, cut where the curve crosses the floor (linearly in
/// `log10 p` between the two points), so that a curve below the panel leaves no line along
/// its bottom edge.
fn above_floor(line: &[(f64, f64)], floor: f64) -> Vec<Vec<(f64, f64)>> {
    let mut pieces = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    let mut prev: Option<(f64, f64)> = None;
    for &(x, p) in line {
        let l = p.log10();
        let crossing = |(x0, l0): (f64, f64)| {
            let t = if l0.is_finite() && l.is_finite() {
                (floor - l0) / (l - l0)
            } else if l0.is_finite() {
                0.0
            } else {
                1.0
            };
            (x0 + t * (x - x0), floor)
        };
        let inside = l >= floor;
        match prev {
            Some(q) if inside && q.1 < floor => run.push(crossing(q)),
            Some(q) if !inside && q.1 >= floor => {
                run.push(crossing(q));
                pieces.push(std::mem::take(&mut run));
            }
            _ => {}
        }
        if inside {
            run.push((x, l));
        }
        prev = Some((x, l));
    }
    if !run.is_empty() {
        pieces.push(run);
    }
    pieces
}

impl Chart for CapacityChart {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let root = root.titled(&self.title, LABEL).map_err(err)?;
        let (left, right) = root.split_horizontally(root.dim_in_pixel().0 / 2);
        self.panel(&left, false)?;
        self.panel(&right, true)
    }
}

/// The fragility chart's data columns: each shown design's curve on the intensity grid, then
/// its stripes (`p_f` and its interval NaN off a stripe).
#[derive(Default)]
struct FragilityData {
    point: Vec<Option<u64>>,
    im: Vec<f64>,
    p_curve: Vec<f64>,
    curve: Vec<String>,
    p_f: Vec<f64>,
    p_f_lo: Vec<f64>,
    p_f_hi: Vec<f64>,
}

impl FragilityData {
    fn push(&mut self, d: u64, im: f64, p: f64, curve: risk::Curve, stripe: (f64, f64, f64)) {
        self.point.push(Some(d));
        self.im.push(im);
        self.p_curve.push(p);
        self.curve.push(curve.name().to_string());
        self.p_f.push(stripe.0);
        self.p_f_lo.push(stripe.1);
        self.p_f_hi.push(stripe.2);
    }

    fn table(self) -> Table {
        let mut data = Table::default();
        data.push("point", Column::U64(self.point));
        data.push("im", Column::F64(self.im));
        data.push("p_curve", Column::F64(self.p_curve));
        data.push("curve", Column::Str(self.curve));
        data.push("p_f", Column::F64(self.p_f));
        data.push("p_f_lo", Column::F64(self.p_f_lo));
        data.push("p_f_hi", Column::F64(self.p_f_hi));
        data
    }
}

/// The designs the fragility chart shows: the best ranked ones with a damper (at most
/// [`MAX_DESIGNS`]), and the structure without a damper when the study has it.
fn shown_designs(s: &Summary) -> (Vec<u64>, Option<u64>) {
    let bare = s
        .points
        .iter()
        .find(|p| s.grid.without_damper(p.point))
        .map(|p| p.point);
    let mut ranked: Vec<_> = s.points.iter().filter(|p| p.rank.is_some()).collect();
    ranked.sort_by_key(|p| p.rank);
    let shown: Vec<u64> = ranked
        .iter()
        .map(|p| p.point)
        .filter(|&d| !s.grid.without_damper(d))
        .take(MAX_DESIGNS)
        .collect();
    (shown, bare)
}

/// The intensity range where the shown curves rise, from their capacities: 0.8 times the
/// smallest to 1.1 times the largest (capacities that were only bounded left out); `None`
/// without one.
fn intensity_range(rs: &RandomSummary, shown: &[u64], bare: Option<u64>) -> Option<(f64, f64)> {
    let mut all: Vec<f64> = rs
        .capacities
        .iter()
        .filter(|c| shown.contains(&c.0) || Some(c.0) == bare)
        .filter(|c| !c.2.1)
        .map(|c| c.2.0)
        .collect();
    all.sort_by(f64::total_cmp);
    if all.is_empty() {
        return None;
    }
    let q = |f: f64| all[((all.len() - 1) as f64 * f) as usize];
    Some((q(0.0) * 0.8, q(1.0) * 1.1))
}

/// Design `d`'s curve over `(lo, hi)` (the one its annual risk is taken over; without a hazard
/// the capacities' lognormal fit where it holds, their empirical fractions otherwise) and its
/// stripes, added to `cols`; `None` without a risk record.
fn design_curve(
    s: &Summary,
    rs: &RandomSummary,
    d: u64,
    is_bare: bool,
    (lo, hi): (f64, f64),
    cols: &mut FragilityData,
) -> Option<Curve> {
    let r = rs.risk_of(d)?;
    let caps = Capacities::new(
        rs.capacities
            .iter()
            .filter(|c| c.0 == d)
            .map(|c| (c.2.0, c.2.1))
            .collect(),
    );
    let curve = r.risk.as_ref().map_or(
        if r.fit_ok && r.fit.is_some() {
            risk::Curve::Lognormal
        } else {
            risk::Curve::Empirical
        },
        |k| k.curve,
    );
    let own = rs.fragility_of(d);
    let p = |x: f64| match (curve, own, r.fit) {
        (risk::Curve::Stripes, Some(f), _) => f.probability(x),
        (risk::Curve::Lognormal, _, Some(f)) => f.p(x),
        _ => caps.p(x),
    };
    let line: Vec<(f64, f64)> = (0..200)
        .map(|k| lo + (hi - lo) * k as f64 / 199.0)
        .map(|x| (x, p(x)))
        .collect();
    let off_stripe = (f64::NAN, f64::NAN, f64::NAN);
    for &(x, p) in &line {
        cols.push(d, x, p, curve, off_stripe);
    }
    for st in &r.stripes {
        let on = match curve {
            risk::Curve::Stripes => p(st.im),
            risk::Curve::Lognormal => st.lognormal,
            risk::Curve::Empirical => st.empirical,
        };
        cols.push(d, st.im, on, curve, (st.p_f, st.p_f_lo, st.p_f_hi));
    }
    let label = (0..s.grid.n_axes())
        .map(|a| axis_value(s.grid.key(a), s.grid.value(d, a)))
        .collect::<Vec<_>>()
        .join(", ");
    let kind = match (is_bare, curve) {
        (true, _) => "no damper",
        (false, risk::Curve::Stripes) => "stripes' fit",
        (false, risk::Curve::Lognormal) => "capacities' lognormal",
        (false, risk::Curve::Empirical) => "capacities, empirical",
    };
    Some(Curve {
        name: shorten(&format!("{label} ({kind})"), 60),
        line,
        stripes: r
            .stripes
            .iter()
            .map(|s| (s.im, s.p_f, s.p_f_lo, s.p_f_hi))
            .collect(),
        bare: is_bare,
    })
}

/// Draws `<dir>/fragility.{svg,png,csv}`; the data holds each shown design's curve on a grid of
/// 200 intensities (`point`, `im`, `p_curve`, `curve`: `stripes`, `lognormal` or `empirical`)
/// and its stripes (`p_f`, `p_f_lo`, `p_f_hi`, NaN off a stripe).
pub fn charts(s: &Summary, rs: &RandomSummary, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let Some(b) = rs.threshold else {
        return Ok(Vec::new());
    };
    let (shown, bare) = shown_designs(s);
    let Some(x) = intensity_range(rs, &shown, bare) else {
        return Ok(Vec::new());
    };
    let mut cols = FragilityData::default();
    let curves: Vec<Curve> = shown
        .iter()
        .map(|&d| (d, false))
        .chain(bare.map(|d| (d, true)))
        .filter_map(|(d, is_bare)| design_curve(s, rs, d, is_bare, x, &mut cols))
        .collect();
    let im = rs.measure.map_or("IM".to_string(), |m| match m.measure {
        crate::sim::random::Measure::Pga => "PGA".into(),
        crate::sim::random::Measure::Sa => {
            format!("Sa({} s)", fmt_num((m.period * 1e3).round() / 1e3))
        }
    });
    let chart = CapacityChart {
        title: format!(
            "Fragility: P(max |x| > {} cm) against {im}, the curve each design's risk is taken over; stripes with 95 % intervals",
            fmt_num((b * 1e5).round() / 1e3)
        ),
        x_desc: format!("{im} (g)"),
        curves,
        x,
    };
    render(
        dir,
        "fragility",
        (1400, 620),
        &chart,
        &Data::Table(cols.table()),
    )
}

#[cfg(test)]
mod tests {
    use super::above_floor;

    #[test]
    fn the_log_panel_draws_a_curve_only_above_its_floor_and_enters_where_it_crosses() {
        // 1e-6, 1e-3 (crossing -4 a third of the way), 1e-1; a zero, then 1e-2 and 1.
        let line = [
            (0.1, 1e-6),
            (0.2, 1e-3),
            (0.3, 1e-1),
            (0.4, 0.0),
            (0.5, 1e-2),
            (0.6, 1.0),
        ];
        let pieces = above_floor(&line, -4.0);
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        let (x, l) = pieces[0][0];
        assert!((x - (0.1 + 0.1 * 2.0 / 3.0)).abs() < 1e-12 && l == -4.0);
        assert_eq!(pieces[0][1], (0.2, -3.0));
        // Down to zero: the line leaves at the last point above and comes back at the next.
        assert_eq!(*pieces[0].last().unwrap(), (0.3, -4.0));
        assert_eq!(pieces[1][0], (0.5, -4.0));
        assert_eq!(*pieces[1].last().unwrap(), (0.6, 0.0));
        // No point on or below the floor but those cuts.
        assert!(pieces.iter().flatten().all(|&(_, l)| l >= -4.0));
        // A curve wholly below draws nothing.
        assert!(above_floor(&[(0.1, 1e-9), (0.2, 1e-8)], -4.0).is_empty());
    }
}
