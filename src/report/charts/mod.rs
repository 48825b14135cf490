//! Charts, each written as SVG and PNG (plotters) with its data beside it as CSV (same stem):
//! the summary rows it draws with the columns it draws (after `point` and the axes), or the
//! samples of a waveform. The PNG text is drawn with DejaVu
//! Sans, embedded in the binary and registered once as `sans-serif`.
//!
//! One axis (the paper's figures):
//! * `di` — DI against the axis (Figure 4), the located jumps marked ([`self::common::di`]);
//! * `design_chart` — R with its interval, μn and DI by zone (Figure 6, [`self::common::design`]);
//! * `xmax_spread` — the response over the cases of each design point ([`self::common::spread`]).
//!
//! Two or more axes, through the recommended design (the best design when none is robust):
//! * `design_chart_<axis>` and `xmax_spread_<axis>` along every axis, the others fixed;
//! * `perfectibility_map_<a>_<b>` and `zone_map_<a>_<b>` over every pair of axes, the others
//!   fixed ([`self::common::map`]);
//! * with three axes, `zone_maps_<c>`: zone maps of the last two axes at several values of the
//!   first, as small multiples ([`self::common::multiples`]).
//!
//! Those are the [`self::common`]'s summary charts ([`summary_charts`]), drawn for every scene. In a
//! harmonic study the design points are designs (a design point without its frequency), the
//! response is the peak amplitude over the band (`peak_amplitude_spread`) and DI's place is
//! taken by the peak reduction (`peak_reduction`); the scene's own charts are in [`harmonic`]
//! (the frequency-response curves, the impacts per period and period against the frequency,
//! the steady states, the bifurcation diagram and the design maps).
//!
//! A random or record study sweeping an intensity gets [`random`]'s `fragility` chart: each
//! design's `p_f` at every intensity and its fitted fragility curve, the structure without
//! damper beside them (with capacities, [`seismic`]'s). A random or record study with a threshold
//! draws its designs by the number they rank by ([`risk`]: `risk_profile_<axis>` and
//! `risk_map_<a>_<b>`, `lambda_f` or `p_f` on a log scale with intervals) instead of the design
//! charts and perfectibility maps, and its spread charts carry the limit ([`load_charts`]).
//!
//! And [`free`], the free-decay scene's waveforms (the paper's Figures 2 and 5), [`tradeoff`]
//! (the solver chart of `tradeoff`). [`plumbing`] holds what they share.

pub mod common;
pub mod free;
pub mod harmonic;
pub mod plumbing;
pub mod random;
pub mod risk;
pub mod seismic;
pub mod tradeoff;

pub use self::common::{load_charts, summary_charts};
pub use crate::report::text::{axis_unit, fmt_num};
pub use free::{Trace, waveforms};
pub use plumbing::{Data, Profile, register_fonts};
