//! The design chart (the paper's Figure 6) along one axis: two panels sharing the axis, the
//! zones shaded and named in both, the located jumps marked; on top R with its bootstrap
//! interval on its own tight range and the `r_min` threshold dashed, below the safety factor
//! (left axis) and DI (right axis). With several axes it is drawn along each axis through the
//! recommended design.

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::di::{di_source, drawn_jumps, jump_keys, jump_lines};
use crate::report::charts::plumbing::{
    BLUE, Chart, GREEN, GREY, Key, LABEL, LEGEND_PITCH, MANY, Profile, RED_LINE, SMALL, TITLE, err,
    legend_lines, legend_row, minmax, pad, tick, with_headroom, x_ticks_at, zone_color,
};
use crate::report::text::{axis_desc, fmt_num};

/// The design chart (the paper's Figure 6) in two panels sharing the swept axis, the zones
/// shaded and named in both: on top R with its bootstrap interval on its own tight range and
/// the `r_min` threshold dashed; below the safety factor (left axis) and DI (right axis).
/// Legends sit in rows above the panels, never over data.
pub struct DesignChart<'a>(pub &'a Profile<'a>);

/// Size of the design chart (pixels).
pub const SIZE: (u32, u32) = (1000, 820);
/// Margin and label-area widths of both panels: equal, so the two plots align on the x axis.
const DESIGN_MARGIN: u32 = 12;
const DESIGN_LEFT: u32 = 80;
const DESIGN_RIGHT: u32 = 80;
/// Height of a legend row (pixels).
const LEGEND_ROW: u32 = 30;

/// Where the legends start (pixels from the left): above the plot area.
const LEGEND_X: i32 = (DESIGN_MARGIN + DESIGN_LEFT) as i32;

/// The height of a legend area that shows all of `items` (one row, or more when they do not
/// fit across `area`).
fn legend_height<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[(Key, String)],
) -> anyhow::Result<u32>
where
    DB::ErrorType: 'static,
{
    let rows = legend_lines(area, LEGEND_X, items)?;
    Ok(LEGEND_ROW + rows.saturating_sub(1) * LEGEND_PITCH)
}

/// The safety factor's share of its axis at the least: the axis spans at least this fraction of
/// the values' middle, so that a change of a percent reads as one and not as a cliff (the
/// multi-unit showcase's factors, 1.428 to 1.444 over its units, once filled the whole axis).
const SAFETY_FACTOR_MIN_SPAN: f64 = 0.05;

/// The damping panel's left range over the safety factors `mu` ([`SAFETY_FACTOR_MIN_SPAN`]),
/// with room for the zone names above.
fn safety_factor_range(mu: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = minmax(mu);
    // Without a finite factor `with_headroom` gives its usable axis before reading the span.
    with_headroom(lo, hi, SAFETY_FACTOR_MIN_SPAN * ((lo + hi) / 2.0).abs())
}

/// The R panel's range over `r` (R and its interval bounds): with `r_min` when that at most
/// doubles the span (so the threshold never flattens R), and room for the zone names above;
/// true when `r_min` is inside.
fn reliability_range(r: impl IntoIterator<Item = f64>, r_min: f64) -> ((f64, f64), bool) {
    let (lo, hi) = minmax(r);
    if !(lo.is_finite() && hi.is_finite()) {
        return ((0.0, 1.0), r_min.is_finite());
    }
    let span = (hi - lo).max(2e-3);
    let shown = r_min.is_finite() && r_min >= lo - span && r_min <= hi + span;
    let (lo, hi) = if shown {
        (lo.min(r_min), hi.max(r_min))
    } else {
        (lo, hi)
    };
    (with_headroom(lo, hi, 2e-3), shown)
}

/// The reliability panel's legend (before the jumps' keys): the bootstrap band, R, and `r_min`
/// with where it lies against the plotted range (which starts at `y0`).
fn reliability_keys(pr: &Profile, y0: f64, r_min_shown: bool) -> Vec<(Key, String)> {
    let (blue, grey) = (BLUE, GREY);
    let s = pr.s;
    let mut items = vec![
        (
            Key::Swatch(blue.mix(0.3)),
            format!("{:.0} % bootstrap interval of R", 100.0 * s.confidence),
        ),
        (
            if pr.points.len() <= MANY {
                Key::LineDot(blue)
            } else {
                Key::Line(blue)
            },
            "reliability R".to_string(),
        ),
    ];
    if s.r_min.is_finite() {
        let where_ = if r_min_shown {
            "reliable: interval at or above"
        } else if s.r_min < y0 {
            "below the plotted range"
        } else {
            "above the plotted range"
        };
        items.push((
            Key::Dashed(grey),
            format!("r_min = {} ({where_})", fmt_num(s.r_min)),
        ));
    }
    items
}

/// R along the profile: its bootstrap band, `r_min` when shown, the jumps, and R itself (with
/// its points when there are few).
fn draw_reliability<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    pr: &Profile,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    r_min_shown: bool,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let (blue, grey) = (BLUE, GREY);
    let s = pr.s;
    let hi = pr.series(|p| p.reliability_hi);
    let lo = pr.series(|p| p.reliability_lo);
    let band: Vec<(f64, f64)> = hi.into_iter().chain(lo.into_iter().rev()).collect();
    if !band.is_empty() {
        chart
            .draw_series(std::iter::once(Polygon::new(band, blue.mix(0.3).filled())))
            .map_err(err)?;
    }
    if r_min_shown {
        chart
            .draw_series(DashedLineSeries::new(
                [(x0, s.r_min), (x1, s.r_min)],
                8,
                5,
                grey.stroke_width(2),
            ))
            .map_err(err)?;
    }
    jump_lines(chart, pr, (y0, y1))?;
    let r = pr.series(|p| p.reliability);
    chart
        .draw_series(LineSeries::new(r.clone(), blue.stroke_width(2)))
        .map_err(err)?;
    if r.len() <= MANY {
        chart
            .draw_series(r.iter().map(|&p| Circle::new(p, 3, blue.filled())))
            .map_err(err)?;
    }
    Ok(())
}

/// Where a zone's name goes along x, in pixels: centred on its span `(lo, hi)` unless a jump's
/// line (`lines`) passes through the name (`w` wide, with a gap of [`NAME_GAP`] each side); then
/// beside the line nearest to the centre on the side with room in the span, clear of every
/// line. `None` when a line passes through the centred name and no place beside a line fits in
/// the span clear of every line (the name is then centred on a pale ground, over the line). The
/// caller skips a span too narrow for the name before asking.
fn name_place(lines: &[i32], (lo, hi): (i32, i32), w: i32) -> Option<i32> {
    let half = w / 2 + NAME_GAP;
    let clear = |c: i32| lines.iter().all(|&l| (l - c).abs() > half);
    let fits = |c: i32| c - half >= lo && c + half <= hi;
    let centre = (lo + hi) / 2;
    if clear(centre) {
        return Some(centre);
    }
    lines
        .iter()
        .flat_map(|&l| [l - half - 1, l + half + 1])
        .filter(|&c| fits(c) && clear(c))
        .min_by_key(|&c| (c - centre).abs())
}

/// The gap between a zone's name and a jump's line beside it (pixels).
const NAME_GAP: i32 = 4;

/// Shades the zones over `y0..y1` and names those wide enough for their name near the top,
/// clear of the jumps' lines where the zone has room ([`name_place`]).
fn shade_zones<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    pr: &Profile,
    (y0, y1): (f64, f64),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = ("sans-serif", 18)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    // The jumps' lines along x, in pixels.
    let lines: Vec<i32> = drawn_jumps(pr)
        .iter()
        .map(|j| chart.backend_coord(&(pr.at_x(j.location), y0)).0)
        .collect();
    for (lo, hi, z) in pr.zone_spans() {
        let color = zone_color(pr.s, z);
        let name = pr.s.zones[z as usize].name.clone();
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(lo, y0), (hi, y1)],
                color.mix(0.45).filled(),
            )))
            .map_err(err)?;
        let px = |x: f64| chart.backend_coord(&(x, y0)).0;
        let (w, h) = chart
            .plotting_area()
            .estimate_text_size(&name, &font)
            .map_err(err)?;
        let (w, h) = (w as i32, h as i32);
        if px(hi) - px(lo) < w + 4 {
            continue; // too narrow for its name
        }
        let centre = (px(lo) + px(hi)) / 2;
        let at = ((lo + hi) / 2.0, y1 - 0.03 * (y1 - y0));
        let place = name_place(&lines, (px(lo), px(hi)), w);
        if place.is_none() {
            let ground = [(-w / 2 - 2, -1), (w / 2 + 2, h + 1)];
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(at) + Rectangle::new(ground, WHITE.mix(0.8).filled()),
                ))
                .map_err(err)?;
        }
        let dx = place.map_or(0, |c| c - centre);
        chart
            .draw_series(std::iter::once(
                EmptyElement::at(at) + Text::new(name, (dx, 0), font.clone()),
            ))
            .map_err(err)?;
    }
    Ok(())
}

impl DesignChart<'_> {
    /// The zone key: one swatch per zone name (declared zones) or label (automatic zones).
    fn zone_keys(&self) -> Vec<(Key, String)> {
        let pr = self.0;
        let s = pr.s;
        let mut keys: Vec<(Key, String)> = Vec::new();
        let mut seen: Vec<String> = Vec::new();
        for (_, _, z) in pr.zone_spans() {
            let zone = &s.zones[z as usize];
            let text = if zone.declared() {
                zone.name.clone()
            } else {
                zone.label().to_string()
            };
            if seen.contains(&text) {
                continue;
            }
            seen.push(text.clone());
            keys.push((
                Key::Swatch(zone_color(s, z).mix(0.6)),
                format!("zone: {text}"),
            ));
        }
        keys
    }

    fn reliability_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x0, x1): (f64, f64),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let pr = self.0;
        let s = pr.s;
        let ((y0, y1), r_min_shown) = reliability_range(
            pr.points
                .iter()
                .flat_map(|p| [p.reliability, p.reliability_lo, p.reliability_hi]),
            s.r_min,
        );
        let has_r = pr.points.iter().any(|p| p.reliability.is_finite());
        let mut items = reliability_keys(pr, y0, r_min_shown);
        items.extend(jump_keys(pr));
        let (keys, plot) = area.split_vertically(legend_height(area, &items)?);
        if has_r {
            legend_row(&keys, LEGEND_X, &items)?;
        } else {
            // Without R the jumps' lines still cross both panels: their keys stay.
            let jumps = jump_keys(pr);
            if !jumps.is_empty() {
                legend_row(&keys, LEGEND_X, &jumps)?;
            }
        }
        let mut chart = ChartBuilder::on(&plot)
            .margin(DESIGN_MARGIN)
            .margin_top(4)
            .margin_right(DESIGN_MARGIN + DESIGN_RIGHT)
            .x_label_area_size(30)
            .y_label_area_size(DESIGN_LEFT)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        shade_zones(&mut chart, pr, (y0, y1))?;
        let x_ticks = pr.scale.ticks(&pr.xs);
        let mut mesh = chart.configure_mesh();
        if !x_ticks.is_empty() {
            mesh.x_labels(0);
        }
        mesh.y_desc("reliability R (–)")
            .x_label_formatter(&tick)
            .y_labels(8)
            // The headroom for the zone names may pass 1; R never does, so no label there.
            .y_label_formatter(&|v| {
                if *v > 1.0 + 1e-9 {
                    String::new()
                } else {
                    fmt_num(*v)
                }
            })
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(err)?;
        x_ticks_at(&plot, &chart, (&x_ticks, pr.scale), y0)?;
        if !has_r {
            use plotters::style::text_anchor::{HPos, Pos, VPos};
            chart
                .draw_series(std::iter::once(Text::new(
                    "R not available: the study gives no strength ([reliability].strength_mean)",
                    ((x0 + x1) / 2.0, (y0 + y1) / 2.0),
                    LABEL
                        .into_font()
                        .color(&BLACK)
                        .pos(Pos::new(HPos::Center, VPos::Center)),
                )))
                .map_err(err)?;
            jump_lines(&mut chart, pr, (y0, y1))?;
            return Ok(());
        }
        draw_reliability(&mut chart, pr, (x0, x1), (y0, y1), r_min_shown)
    }

    fn damping_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x0, x1): (f64, f64),
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let pr = self.0;
        let s = pr.s;
        let key = pr.key();
        let (green, red) = (GREEN, RED_LINE);
        let di_key = if pr.points.len() <= MANY {
            Key::LineDot(red)
        } else {
            Key::Line(red)
        };
        let mut items = Vec::new();
        if pr.points.iter().any(|p| p.safety_factor.is_finite()) {
            items.push((Key::Line(green), "safety factor μn (left axis)".to_string()));
        }
        items.push((
            di_key,
            format!(
                "{}, {} (right axis)",
                s.options.damping.symbol,
                di_source(s)
            ),
        ));
        let (keys, plot) = area.split_vertically(legend_height(area, &items)?);
        legend_row(&keys, LEGEND_X, &items)?;
        let (m0, m1) = safety_factor_range(pr.points.iter().map(|p| p.safety_factor));
        let (d0, d1) = minmax(pr.points.iter().map(|p| p.di));
        let (d0, d1) = with_headroom(d0.min(0.0), d1, 0.0);
        let mut chart = ChartBuilder::on(&plot)
            .margin(DESIGN_MARGIN)
            .margin_top(4)
            .x_label_area_size(48)
            .y_label_area_size(DESIGN_LEFT)
            .right_y_label_area_size(DESIGN_RIGHT)
            .build_cartesian_2d(x0..x1, m0..m1)
            .map_err(err)?
            .set_secondary_coord(x0..x1, d0..d1);
        shade_zones(&mut chart, pr, (m0, m1))?;
        jump_lines(&mut chart, pr, (m0, m1))?;
        let x_ticks = pr.scale.ticks(&pr.xs);
        let mut mesh = chart.configure_mesh();
        if !x_ticks.is_empty() {
            mesh.x_labels(0);
        }
        mesh.x_desc(pr.scale.desc(&axis_desc(key)))
            .y_desc("safety factor μn (–)")
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(err)?;
        x_ticks_at(&plot, &chart, (&x_ticks, pr.scale), m0)?;
        chart
            .configure_secondary_axes()
            .y_desc(s.options.damping.label())
            .y_label_formatter(&tick)
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .draw()
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                pr.series(|p| p.safety_factor),
                green.stroke_width(2),
            ))
            .map_err(err)?;
        let di = pr.series(|p| p.di);
        chart
            .draw_secondary_series(LineSeries::new(di.clone(), red.stroke_width(2)))
            .map_err(err)?;
        if di.len() <= MANY {
            chart
                .draw_secondary_series(di.iter().map(|&p| Circle::new(p, 3, red.filled())))
                .map_err(err)?;
        }
        Ok(())
    }
}

impl Chart for DesignChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let pr = self.0;
        let x = minmax(pr.positions());
        let x = if x.1 > x.0 { x } else { pad(x.0, x.1, 0.5) };
        let title = if pr.slice.is_empty() {
            "Design chart: reliability, safety factor and damping by zone".to_string()
        } else {
            format!("Design chart along {}{}", pr.key(), pr.at())
        };
        let root = root.titled(&title, TITLE).map_err(err)?;
        let zone_keys = self.zone_keys();
        let (zone_key, rest) = root.split_vertically(legend_height(&root, &zone_keys)?);
        legend_row(&zone_key, LEGEND_X, &zone_keys)?;
        let h = rest.dim_in_pixel().1 as i32;
        let (top, bottom) = rest.split_vertically(h * 44 / 100);
        self.reliability_panel(&top, x)?;
        self.damping_panel(&bottom, x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zone_name_stands_clear_of_the_jump_lines() {
        // A zone 200 px wide (100..300) and a name 20 px wide: half of it with its gaps is 14.
        let span = (100, 300);
        assert_eq!(name_place(&[], span, 20), Some(200));
        // A line away from the centre leaves the name there.
        assert_eq!(name_place(&[150], span, 20), Some(200));
        // A line through the centre (a zone around a jump): the name moves beside it, the
        // nearer side first, and no line passes within its half-width.
        for lines in [vec![200], vec![196], vec![205, 230]] {
            let c = name_place(&lines, span, 20).unwrap();
            assert!(lines.iter().all(|&l| (l - c).abs() > 14), "{lines:?}: {c}");
            assert!((100 + 14..=300 - 14).contains(&c), "{lines:?}: {c}");
            assert!((c - 200).abs() <= 45, "{lines:?}: {c}");
        }
        assert!(name_place(&[196], span, 20).unwrap() > 196);
        // No room beside the line in a narrow zone: no place (centred on a pale ground).
        assert_eq!(name_place(&[130], (110, 150), 20), None);
    }

    #[test]
    fn reliability_gets_a_tight_range_with_the_threshold() {
        // The paper's sweep: R and its interval within 0.972..0.999, r_min = 0.98.
        let r = [0.9972, 0.9963, 0.9981, 0.9797, 0.9725, 0.9868, 0.9990];
        let ((y0, y1), shown) = reliability_range(r, 0.98);
        assert!(shown);
        assert!(y0 < 0.9725 && y1 > 0.999, "{y0}..{y1}");
        // The whole axis is a few hundredths, not the 0.95..1.25 R shared with mu_n before.
        assert!(y1 - y0 < 0.04, "{y0}..{y1}");
        // Room above the data for the zone names: a fifth of the axis or more.
        assert!((y1 - 0.9990) / (y1 - y0) > 0.15, "{y0}..{y1}");
    }

    #[test]
    fn a_far_threshold_does_not_flatten_reliability() {
        let ((y0, y1), shown) = reliability_range([0.99, 0.995, 0.999], 0.5);
        assert!(!shown);
        assert!(y0 > 0.98 && y1 < 1.01, "{y0}..{y1}");
        // Inside the doubled span it is drawn.
        let ((y0, _), shown) = reliability_range([0.99, 0.995, 0.999], 0.985);
        assert!(shown && y0 < 0.985);
    }

    #[test]
    fn a_percent_of_safety_factor_is_not_drawn_as_a_cliff() {
        // The multi-unit showcase's factors over its units: 1.1 % apart.
        let (y0, y1) = safety_factor_range([1.4352, 1.4436, 1.4284, 1.4280]);
        assert!(y1 - y0 >= 0.05 * 1.4358, "{y0}..{y1}");
        assert!(y0 < 1.4280 && y1 > 1.4436, "{y0}..{y1}");
        // The values sit in the middle of the span, below the zone names' headroom.
        assert!((1.4436 - 1.4280) / (y1 - y0) < 0.25, "{y0}..{y1}");
        // A wider spread keeps its own tight axis (the paper's, 5.9 %).
        let (y0, y1) = safety_factor_range([1.1657, 1.236]);
        assert!(
            (y1 - y0 - 1.32 * (1.236 - 1.1657)).abs() < 1e-12,
            "{y0}..{y1}"
        );
        // No finite factor: a usable axis.
        assert_eq!(safety_factor_range([f64::NAN]), (0.0, 1.0));
    }

    #[test]
    fn flat_or_missing_reliability_keeps_a_usable_axis() {
        // R = 1 everywhere: an axis a few thousandths wide around 1, not a degenerate one.
        let ((y0, y1), shown) = reliability_range([1.0, 1.0], 0.2);
        assert!(!shown);
        assert!(y1 - y0 >= 2e-3 && y0 < 1.0 && y1 > 1.0, "{y0}..{y1}");
        assert_eq!(reliability_range([f64::NAN], 0.98).0, (0.0, 1.0));
    }
}
