//! The design life of one chaotic point as a one-frequency study, run as the sweep runs a curve
//! (its run from the initial state, the census, the race), and the brute force it is checked
//! against (`results/life_validation/brute/NAME.json`).

use std::path::Path;

use impactsweep::orbits::census::{Census, Kind};
use impactsweep::orbits::curve::run_curve;
use impactsweep::plan::Plan;
use impactsweep::study::Study;

/// A life estimate of a study and the horizon it was asked for.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    /// The horizon in forcing periods.
    pub periods: f64,
    pub amplitude: f64,
    pub lo: f64,
    pub hi: f64,
    /// Periods the estimate was measured over.
    pub measured: u64,
}

/// The one-frequency study of Table I's M and K, C = 0.1 N s/m, e = 0.9, F0 = 0.1 N, inner mass
/// `m` (kg), clearance `d` (m) at ratio `r`, 16 starts, study seed `seed`, its design life
/// `periods` forcing periods (1,000 h when `None`).
pub fn study_text(m: f64, d: f64, r: f64, seed: u64, periods: Option<f64>) -> String {
    let period = std::f64::consts::TAU / (r * (400.0f64 / 0.1).sqrt());
    let life = periods.map_or(3.6e6, |n| n * period);
    format!(
        "[study]\nname = \"life\"\nseed = {seed}\n[system]\nM = 0.1\nK = 400.0\nC = 0.1\ne = 0.9\nm = {m}\nd = {d}\nx0 = 0.0\nv0 = 0.0\ny0 = 0.0\nw0 = 0.0\n[scene]\nkind = \"harmonic\"\nF0 = 0.1\nr = {r}\nstarts = 16\ndesign_life = {life:?}\n"
    )
}

/// The design life of the motion that is not periodic with the largest design amplitude in the
/// study of [`study_text`] (`None` when its census found none).
pub fn one_frequency_life(
    m: f64,
    d: f64,
    r: f64,
    seed: u64,
    periods: Option<f64>,
) -> Option<Estimate> {
    let text = study_text(m, d, r, seed, periods);
    let study = Study::parse(Path::new("life.toml"), &text).expect("a valid study");
    let plan = Plan::new(&study);
    let run = plan.run(0, 0);
    let freq = plan.curve_frequency(&run);
    let curve = run_curve(
        &run.system,
        &study.solver,
        &study.request,
        study.noise.as_ref(),
        study.seed,
        vec![freq],
    );
    let census = curve.censuses.into_iter().flatten().next()?;
    let f = run.system;
    let period = std::f64::consts::TAU / (r * (f.K / f.M).sqrt());
    largest_life(&census, periods.unwrap_or(3.6e6 / period))
}

/// The design life of the census's motion that is not periodic with the largest design
/// amplitude, asked for over `periods` forcing periods (`None` when it has none, or no estimate).
fn largest_life(census: &Census, periods: f64) -> Option<Estimate> {
    let a = census
        .attractors
        .iter()
        .filter(|a| matches!(a.kind, Kind::NonPeriodic(_)))
        .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))?;
    let Kind::NonPeriodic(w) = &a.kind else {
        return None;
    };
    let life = w.life?;
    let e = life.estimate?;
    Some(Estimate {
        periods,
        amplitude: e.amplitude,
        lo: e.lo,
        hi: e.hi,
        measured: life.measured,
    })
}

/// A point's brute force: its block maxima of 10^6 periods.
pub struct Brute {
    pub blocks: Vec<f64>,
}

impl Brute {
    /// `results/life_validation/brute/NAME.json`.
    pub fn read(name: &str) -> Brute {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(format!("results/life_validation/brute/{name}.json"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let v: serde_json::Value = serde_json::from_str(&text).expect("brute-force JSON");
        let blocks = v["blocks"]
            .as_array()
            .expect("blocks")
            .iter()
            .map(|b| {
                b.as_array()
                    .expect("sub-block maxima")
                    .iter()
                    .filter_map(|x| x.as_f64())
                    .fold(f64::MIN, f64::max)
            })
            .collect();
        Brute { blocks }
    }

    /// The median of the largest of `l` periods: the `0.5^(10^6 / l)` quantile of the block
    /// maxima (max-stability).
    pub fn median(&self, l: f64) -> f64 {
        impactsweep::numeric::quantile(&self.blocks, 0.5f64.powf(1e6 / l))
    }
}

/// The design lives (1,000 h) of one design's curve over the ratios `rs`, run as the sweep runs
/// it (one run from rest per frequency, one census over the curve, one race): per frequency,
/// the estimate of its motion that is not periodic with the largest design amplitude (`None`
/// where the census found only periodic motions).
pub fn curve_life(m: f64, d: f64, rs: &[f64], seed: u64) -> Vec<Option<Estimate>> {
    let list = rs
        .iter()
        .map(|r| format!("{r:?}"))
        .collect::<Vec<_>>()
        .join(", ");
    let text = study_text(m, d, rs[0], seed, None).replace(&format!("r = {}\n", rs[0]), "")
        + &format!("[sweep]\nr = [{list}]\n");
    let study = Study::parse(Path::new("curve.toml"), &text).expect("a valid study");
    let plan = Plan::new(&study);
    let runs: Vec<_> = (0..plan.n_points()).map(|p| plan.run(p, 0)).collect();
    let freqs = runs.iter().map(|run| plan.curve_frequency(run)).collect();
    let f = runs[0].system;
    let curve = run_curve(
        &f,
        &study.solver,
        &study.request,
        study.noise.as_ref(),
        study.seed,
        freqs,
    );
    curve
        .censuses
        .into_iter()
        .zip(rs)
        .map(|(census, &r)| {
            let period = std::f64::consts::TAU / (r * (f.K / f.M).sqrt());
            largest_life(&census?, 3.6e6 / period)
        })
        .collect()
}
