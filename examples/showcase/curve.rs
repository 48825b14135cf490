//! The frequency-response showcase's curves for the race examples (`race_cost`, `race_drop`):
//! `configs/frequency-response.toml`'s system with inner mass `m` and clearance `d`, 81
//! frequencies r = 0.8 .. 1.2, 8 census starts, the study's seed, design points from `design`.

use impactsweep::model::System;
use impactsweep::orbits::census::Census;
use impactsweep::orbits::curve::{
    CurveFrequency, census_passes, curve_points, from_rest, race_points,
};
use impactsweep::orbits::map::Forcing;
use impactsweep::sim::{Drive, Harmonic, Request, SolverSettings};

/// One curve's censuses (both passes, before any life is measured) and its race points.
pub struct ShowcaseCurve {
    pub censuses: Vec<Option<Census>>,
    pub race_points: Vec<Option<(Forcing, Harmonic)>>,
}

/// The curve of design `design` (its points are `design * 81 + i`) at inner mass `m` (kg) and
/// clearance `d` (m).
pub fn showcase_curve(m: f64, d: f64, design: u64) -> ShowcaseCurve {
    let settings = SolverSettings::default();
    let sys = System {
        M: 0.1,
        K: 400.0,
        C: 0.1,
        e: 0.9,
        m,
        d,
        x0: 0.0,
        v0: 0.0,
        y0: 0.0,
        w0: 0.0,
    };
    let freqs: Vec<CurveFrequency> = (0..81u32)
        .map(|i| CurveFrequency {
            scene: Harmonic {
                F0: 0.1,
                drive: Drive::Ratio(0.8 + 0.005 * f64::from(i)),
                starts: 8,
                ..Harmonic::default()
            },
            point: design * 81 + u64::from(i),
            noise: None,
        })
        .collect();
    let targets: Vec<(Harmonic, u64)> = freqs.iter().map(|f| (f.scene, f.point)).collect();
    let records = from_rest(&sys, &settings, &Request::default(), None, freqs);
    let points = curve_points(&sys, &settings, 1966, &targets, &records);
    ShowcaseCurve {
        censuses: census_passes(&points),
        race_points: race_points(&points, &targets),
    }
}
