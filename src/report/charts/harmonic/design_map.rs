//! The forced design map (docs/reduce.md, "Bifurcations over the design space"): a design axis
//! `p` against the frequency ratio `r`, in the recommended design's plane (the other axes at its
//! values). Each cell (a design and frequency of the grid) is shaded where the census found two
//! or more steady states (a jump between them is possible there) and where one of them is not
//! periodic (one colour each, a third where both hold); a dot marks a doubled (period 2 or more)
//! stable orbit. Over it: the bifurcation curves followed in `(r, p)` (folds, period doublings,
//! Neimark–Sacker, grazings), the linear system's resonance `r = sqrt(1 - 2 zeta^2)`, and the
//! recommended design at its peak.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::charts::plumbing::{
    Chart, Key, LABEL, Plot, SMALL, TITLE, err, plot_builder, tick,
};

use crate::orbits::attractors::SteadyKind;
use crate::reduce::Summary;
use crate::reduce::harmonic::HarmonicSummary;
use crate::reduce::harmonic::bifurcations::Curve as BifCurve;
use crate::report::text::fmt_num;
use crate::store::table::{Column, Table};

pub const SIZE: (u32, u32) = (1000, 700);

const COEXIST: RGBAColor = RGBAColor(31, 119, 180, 0.30);
const CHAOS: RGBAColor = RGBAColor(255, 127, 14, 0.40);
/// Cells with both: two or more steady states, one of them not periodic.
const BOTH: RGBAColor = RGBAColor(140, 86, 75, 0.45);
const DOUBLED: RGBColor = RGBColor(90, 90, 90);
const SN: RGBColor = RGBColor(0, 0, 0);
const PD: RGBColor = RGBColor(214, 39, 40);
const NS: RGBColor = RGBColor(44, 160, 44);
/// Grazing curves: a flight of the inner mass touches a wall (the impact sequence changes).
const GR: RGBColor = RGBColor(148, 103, 189);
const RESONANCE: RGBColor = RGBColor(120, 120, 120);

/// One cell of the map: a design of the plane at one frequency.
#[derive(Clone, Copy, Debug)]
struct Cell {
    p: f64,
    r: f64,
    /// The cell's extent (half-way to its neighbours).
    r_span: (f64, f64),
    p_span: (f64, f64),
    /// Steady states the census found, whether one is not periodic, whether a stable orbit
    /// has period 2 or more.
    states: usize,
    not_periodic: bool,
    doubled: bool,
}

/// The map of one design axis.
pub struct DesignMap<'a> {
    key: String,
    cells: Vec<Cell>,
    curves: Vec<&'a BifCurve>,
    /// `(r, p)` of the linear resonance at each design of the plane.
    resonance: Vec<(f64, f64)>,
    /// The anchor design's peak `(r, p)`, and what the anchor is (the recommended design, or
    /// the best ranked when none is recommended).
    recommended: Option<(f64, f64)>,
    anchor_label: &'static str,
}

/// Half-way points between sorted values, with the ends mirrored.
fn spans(v: &[f64], i: usize) -> (f64, f64) {
    let lo = if i > 0 {
        0.5 * (v[i - 1] + v[i])
    } else if v.len() > 1 {
        v[0] - 0.5 * (v[1] - v[0])
    } else {
        v[0] - 0.5
    };
    let hi = if i + 1 < v.len() {
        0.5 * (v[i] + v[i + 1])
    } else if v.len() > 1 {
        v[i] + 0.5 * (v[i] - v[i - 1])
    } else {
        v[0] + 0.5
    };
    (lo, hi)
}

fn unit(key: &str) -> &'static str {
    match key {
        "m" => "kg",
        "d" => "m",
        "C" => "N s/m",
        "F0" => "N",
        _ => "–",
    }
}

impl<'a> DesignMap<'a> {
    /// The map of axis `a` through design `anchor`; `None` when the plane has no stored
    /// attractors.
    fn new(
        s: &Summary,
        f: &HarmonicSummary,
        curves: &'a [BifCurve],
        anchor: u64,
        a: usize,
    ) -> Option<Self> {
        let g = &s.grid;
        let values = g.axis_values(a).to_vec();
        let i0 = g.index(anchor, a) as i64;
        let mut cells = Vec::new();
        let mut resonance = Vec::new();
        for (j, &p) in values.iter().enumerate() {
            let design = g.step(anchor, a, j as i64 - i0)?;
            let c = f.curve(design)?;
            c.attractors.as_ref()?;
            let rs: Vec<f64> = c.points.iter().map(|q| q.r).collect();
            for (i, &r) in rs.iter().enumerate() {
                let here: Vec<_> = c.attractors_at(i).collect();
                cells.push(Cell {
                    p,
                    r,
                    r_span: spans(&rs, i),
                    p_span: spans(&values, j),
                    states: c.distinct_states_at(i),
                    not_periodic: here.iter().any(|x| !x.kind.periodic()),
                    doubled: here
                        .iter()
                        .any(|x| x.kind == SteadyKind::Periodic && x.period >= 2),
                });
            }
            let sys = &c.system;
            let zeta = sys.C / (2.0 * (sys.K * sys.M).sqrt());
            if 1.0 - 2.0 * zeta * zeta > 0.0 {
                resonance.push(((1.0 - 2.0 * zeta * zeta).sqrt(), p));
            }
        }
        let plane = |k: &BifCurve| {
            k.axis_index == a
                && (0..g.n_axes())
                    .all(|x| x == a || g.index(k.seed_design, x) == g.index(anchor, x))
        };
        let recommended = f
            .curve(anchor)
            .map(|c| c.peak().1)
            .filter(|r| r.is_finite())
            .map(|r| (r, g.value(anchor, a)));
        Some(DesignMap {
            key: g.key(a).to_string(),
            cells,
            curves: curves.iter().filter(|k| plane(k)).collect(),
            resonance,
            recommended,
            anchor_label: if s.recommended == Some(anchor) {
                "recommended (peak)"
            } else {
                "best ranked (peak)"
            },
        })
    }

    /// The chart's data: the cells.
    fn data(&self) -> Table {
        let c = &self.cells;
        let mut t = Table::default();
        t.push(
            crate::store::table::axis_column(&self.key),
            Column::F64(c.iter().map(|x| x.p).collect()),
        );
        t.push("r", Column::F64(c.iter().map(|x| x.r).collect()));
        t.push(
            "steady_states",
            Column::U64(c.iter().map(|x| Some(x.states as u64)).collect()),
        );
        t.push(
            "not_periodic",
            Column::Bool(c.iter().map(|x| x.not_periodic).collect()),
        );
        t.push(
            "doubled",
            Column::Bool(c.iter().map(|x| x.doubled).collect()),
        );
        t
    }
}

/// The legend's entries: the cells' colours and the curves'.
fn legend_items() -> Vec<(Key, String)> {
    vec![
        (
            Key::Swatch(COEXIST),
            "two or more steady states (a jump is possible)".to_string(),
        ),
        (
            Key::Swatch(CHAOS),
            "a steady state not periodic".to_string(),
        ),
        (Key::Swatch(BOTH), "both".to_string()),
        (Key::Line(SN), "fold (SN)".to_string()),
        (Key::Line(PD), "period doubling (PD)".to_string()),
        (Key::Line(NS), "Neimark–Sacker (NS)".to_string()),
        (Key::Line(GR), "grazing (GR)".to_string()),
        (Key::Dashed(RESONANCE), "linear resonance".to_string()),
    ]
}

impl DesignMap<'_> {
    /// The cells in one colour each (coexistence, a motion not periodic, or both) and a dot on
    /// each cell where a period doubled.
    fn draw_cells<'a, DB: DrawingBackend + 'a>(
        &self,
        chart: &mut Plot<'a, DB>,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let rect = |c: &Cell, colour: RGBAColor| {
            Rectangle::new(
                [(c.r_span.0, c.p_span.0), (c.r_span.1, c.p_span.1)],
                colour.filled(),
            )
        };
        chart
            .draw_series(
                self.cells
                    .iter()
                    .filter_map(|c| match (c.states >= 2, c.not_periodic) {
                        (true, false) => Some(rect(c, COEXIST)),
                        (false, true) => Some(rect(c, CHAOS)),
                        (true, true) => Some(rect(c, BOTH)),
                        (false, false) => None,
                    }),
            )
            .map_err(err)?;
        chart
            .draw_series(
                self.cells
                    .iter()
                    .filter(|c| c.doubled)
                    .map(|c| Circle::new((c.r, c.p), 2, DOUBLED.filled())),
            )
            .map_err(err)?;
        Ok(())
    }

    /// The linear resonance, the bifurcation curves (each type its colour) and the anchor
    /// design's cross.
    fn draw_curves<'a, DB: DrawingBackend + 'a>(
        &self,
        chart: &mut Plot<'a, DB>,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        chart
            .draw_series(DashedLineSeries::new(
                self.resonance.clone(),
                6,
                4,
                RESONANCE.stroke_width(2),
            ))
            .map_err(err)?;
        for k in &self.curves {
            let colour = match k.curve.label.name() {
                "SN" => SN,
                "PD" => PD,
                "GR" => GR,
                _ => NS,
            };
            let pts: Vec<(f64, f64)> = k.curve.points.iter().map(|q| (q.r, q.p)).collect();
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                .map_err(err)?;
        }
        if let Some((r, p)) = self.recommended {
            // The label on a pale ground, so that the curves it crosses do not hide it.
            let area = chart.plotting_area();
            let (w, h) = area
                .estimate_text_size(self.anchor_label, &SMALL.into_text_style(area))
                .map_err(err)?;
            let ground = [(7, -20), (13 + w as i32, -16 + h as i32)];
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((r, p))
                        + Rectangle::new(ground, WHITE.mix(0.8).filled())
                        + Cross::new((0, 0), 8, BLACK.stroke_width(3))
                        + Text::new(self.anchor_label, (10, -18), SMALL.into_font()),
                ))
                .map_err(err)?;
        }
        Ok(())
    }
}

impl Chart for DesignMap<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let (title, rest) = root.split_vertically(40);
        title
            .titled(&format!("Steady states over {} and r", self.key), TITLE)
            .map_err(err)?;
        let plot = crate::report::charts::plumbing::legend_block(&rest, 80, &legend_items())?;
        let (r0, r1) = self
            .cells
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                (a.min(c.r_span.0), b.max(c.r_span.1))
            });
        let (p0, p1) = self
            .cells
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                (a.min(c.p_span.0), b.max(c.p_span.1))
            });
        let mut chart = plot_builder(&plot, 48)
            .build_cartesian_2d(r0..r1, p0..p1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("frequency ratio r = omega / sqrt(K/M) (–)")
            .x_label_formatter(&tick)
            .y_desc(format!("{} ({})", self.key, unit(&self.key)))
            .y_label_formatter(&|v: &f64| fmt_num(*v))
            .label_style(SMALL)
            .axis_desc_style(LABEL)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        self.draw_cells(&mut chart)?;
        self.draw_curves(&mut chart)?;
        Ok(())
    }
}

/// Draws `design_map` (or `design_map_KEY` for each of several swept design axes among `m`,
/// `d`, `e`, `C`, `F0`) in the plane of design `anchor` into `dir`; returns the files. Nothing
/// without a frequency axis or stored attractors.
pub fn charts(
    s: &Summary,
    f: &HarmonicSummary,
    curves: &[BifCurve],
    anchor: u64,
    dir: &std::path::Path,
) -> anyhow::Result<Vec<std::path::PathBuf>> {
    if f.frequency.is_none() {
        return Ok(Vec::new());
    }
    let g = &s.grid;
    let axes: Vec<usize> = (0..g.n_axes())
        .filter(|&a| g.n(a) >= 2 && crate::orbits::twopar::Axis::of_key(g.key(a)).is_some())
        .collect();
    let mut files = Vec::new();
    for &a in &axes {
        let Some(map) = DesignMap::new(s, f, curves, anchor, a) else {
            continue;
        };
        let stem = if axes.len() > 1 {
            format!("design_map_{}", crate::store::table::axis_column(g.key(a)))
        } else {
            "design_map".to_string()
        };
        files.extend(crate::report::charts::plumbing::render(
            dir,
            &stem,
            SIZE,
            &map,
            &crate::report::charts::plumbing::Data::Table(map.data()),
        )?);
    }
    Ok(files)
}
