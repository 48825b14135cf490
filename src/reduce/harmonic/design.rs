//! A design of a harmonic study: a design point without its frequency (the study's grid with
//! the frequency axis taken out, [`design_study`]), what its response and damping quantity are
//! ([`PEAK_AMPLITUDE`], [`PEAK_REDUCTION`]) and which steady state is its design quantity
//! ([`design_peak`]).

use crate::reduce::common::{Damping, Options, Response};
use crate::sim::harmonic::DesignPeak;
use crate::study::{Study, frequency_axis};

/// The response of a harmonic study: the largest steady amplitude over the swept band.
pub const PEAK_AMPLITUDE: Response = Response {
    name: "peak_amplitude",
    unit: "m",
    description: "largest steady amplitude over the frequency band",
};

/// The damping quantity of a harmonic study: `1 - peak amplitude / the linear system's peak
/// over the band`.
pub const PEAK_REDUCTION: Damping = Damping {
    name: "peak_reduction",
    symbol: "PR",
    title: "Peak reduction",
    unit: "1",
    description: "peak reduction, 1 - peak amplitude / the linear system's peak over the band",
};

/// The study's `[scene].design_peak` (the worst steady state unless it says otherwise).
pub fn design_peak(study: &Study) -> DesignPeak {
    study
        .scene
        .harmonic()
        .map_or(DesignPeak::Worst, |h| h.design_peak)
}

/// The study of the designs: the harmonic study without its frequency axis.
pub fn design_study(study: &Study) -> Study {
    let mut s = study.clone();
    if let Some(i) = frequency_axis(&s.axes) {
        s.axes.remove(i);
    }
    s
}

/// The reducer's options for a harmonic study: the design study's own, with the peak
/// amplitude as the response and the peak reduction as the damping quantity.
pub fn options(design: &Study) -> Options {
    Options::of_study(design, PEAK_AMPLITUDE, PEAK_REDUCTION)
}
