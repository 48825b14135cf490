//! `[scene] kind = "harmonic"`: a force `F0 cos(omega t)` on the main mass, run to its steady
//! state (model.md §8, docs/scenes.md). `F0` and the frequency (`omega`, or
//! `r = omega / sqrt(K/M)`) are fixed here or swept in `[sweep]`, so a harmonic study is a family
//! of frequency-response curves; the transient and measurement settings are phase 1's
//! [`Harmonic`] settings. The scene shares every other table with free decay
//! ([`super::cased`]) and adds its checks at their places: no free-decay `[study]` keys, the
//! frequency axis last (consecutive design points form one curve), `exact` only, chunks of
//! whole curves, no accuracy audit.
//!
//! Resonance without damping is refused for every run of the plan (each design point, each
//! case's perturbed `m`) at load, not discovered in the night: [`check_runs`] bounds the dynamic
//! stiffness from below over the whole grid and, only when the bound does not settle it,
//! enumerates the combinations of the keys it depends on (`M`, `m + dm`, `K`, `C`, the frequency).

use std::collections::BTreeMap;
use std::path::Path;

use super::cased::{self, CasedScene};
use super::raw::{RawScene, RawStudy};
use crate::error::InputError;
use crate::model::{RangeError, System};
use crate::sim::harmonic::motion::RESONANCE_FLOOR;
use crate::sim::harmonic::{DesignPeak, LifeCurve, NonPeriodicPeak};
use crate::sim::{Drive, Harmonic, Scene, SolverKind, SolverSettings};
use crate::study::axis::{Axis, RawAxis};
use crate::study::context::{Cx, num, range_value};
use crate::study::header::RawHeader;
use crate::study::perturb::Case;
use crate::study::run::{DEFAULT_CHUNK_RUNS, DEFAULT_CHUNK_RUNS_CENSUS, RunRules};
use crate::study::sweep::SceneAxes;
use crate::study::validated::Study;

/// A harmonic study: `[scene]` validated into the scene's fixed settings, then the tables it
/// shares with free decay.
pub(super) fn study(
    cx: &Cx,
    raw: &RawStudy,
    scene: &RawScene,
    path: &Path,
    text: &str,
) -> Result<Study, InputError> {
    scene.refuse_random_keys(cx)?;
    let h = settings(cx, scene, &raw.sweep)?;
    let study = cased::study(cx, raw, path, text, &HarmonicScene(h))?;
    Ok(study)
}

/// The validated `[scene]` of a harmonic study (before its axes are known): its fixed settings.
/// The keys swept in `[sweep]` are cross-checked here (a key is fixed or swept, not both;
/// `omega` or `r`, not both).
fn settings(
    cx: &Cx,
    raw: &RawScene,
    sweep: &BTreeMap<String, RawAxis>,
) -> Result<Harmonic, InputError> {
    check_swept_keys(cx, raw, sweep)?;
    let mut h = fixed_settings(raw, sweep);
    parse_peaks(cx, raw, &mut h)?;
    h.check_ranges()
        .map_err(|e| cx.err(&format!("[scene].{}", e.key), range_value(&e), e.allowed))?;
    Ok(h)
}

/// The harmonic scene's rules over the shared tables.
struct HarmonicScene(Harmonic);

impl CasedScene for HarmonicScene {
    fn scene(&self) -> Scene {
        Scene::Harmonic(self.0)
    }

    /// The free-decay scene's `[study]` keys are refused ([`FREE_ONLY`]).
    fn check_header(&self, cx: &Cx, h: &RawHeader) -> Result<(), InputError> {
        h.refuse_free_keys(cx, FREE_ONLY)
    }

    /// `F0`, `omega` and `r`, each checked on its own by [`check_key`].
    fn sweep_keys(&self) -> SceneAxes<'static> {
        SceneAxes {
            keys: &Harmonic::AXES,
            check: check_key,
            listed: false,
            units: true,
        }
    }

    /// The frequency axis last, wherever the file has it.
    fn order_axes(&self, axes: &mut Vec<Axis>) {
        if let Some(i) = frequency_axis(axes) {
            let f = axes.remove(i);
            axes.push(f);
        }
    }

    /// The harmonic scene is solved by `exact` only (closed form with the forcing term).
    fn check_solver(&self, cx: &Cx, solver: &SolverSettings) -> Result<(), InputError> {
        if solver.kind != SolverKind::Exact {
            return Err(cx.err(
                "[solver].kind",
                format!("{:?}", solver.kind.name()),
                "the harmonic scene is solved by exact only",
            ));
        }
        Ok(())
    }

    /// Chunks of whole frequency-response curves, smaller with an attractor census (and smaller
    /// again by the square of the most damper units a run has: each unit's walls are searched on
    /// their own, so a forcing period of `n` units costs well over `n` times one unit's, 26 times
    /// at 8 units in one timing), and no accuracy audit.
    fn run_rules<'a>(&self, system: &System, axes: &'a [Axis]) -> RunRules<'a> {
        let units = axes
            .iter()
            .filter(|a| a.key == "units")
            .flat_map(|a| a.values.iter().map(|&n| n as u64))
            .fold(system.unit_count() as u64, u64::max)
            .max(1);
        RunRules {
            aim: if self.0.starts > 0 {
                (DEFAULT_CHUNK_RUNS_CENSUS / (units * units)).max(1)
            } else {
                DEFAULT_CHUNK_RUNS
            },
            realizations: false,
            no_audit: Some(
                "the accuracy audit re-runs free-decay runs; a harmonic study has none (its \
                 accuracy is shown in tests/forced.rs, docs/scenes.md)",
            ),
            curve: frequency_axis(axes).map(|i| &axes[i]),
        }
    }

    fn check_runs(
        &self,
        cx: &Cx,
        system: &System,
        axes: &[Axis],
        cases: &[Case],
    ) -> Result<(), InputError> {
        check_runs(cx, &self.0, system, axes, cases)
    }
}

/// Checks the range of one sweepable scene key on its own (`F0 > 0`, `omega > 0`, `r > 0`).
fn check_key(key: &str, v: f64) -> Result<(), RangeError> {
    let mut h = Harmonic::default();
    h.set(key, v);
    h.check_ranges()
}

/// The keys of the harmonic scene that `[sweep]` also sets: none fixed and swept, and the
/// frequency given as `omega` or `r`, not both.
fn check_swept_keys(
    cx: &Cx,
    raw: &RawScene,
    sweep: &BTreeMap<String, RawAxis>,
) -> Result<(), InputError> {
    for key in Harmonic::AXES {
        if let (Some(v), true) = (raw.harmonic(key), sweep.contains_key(key)) {
            return Err(cx.err(
                &format!("[scene].{key}"),
                num(v),
                format!("{key} is also swept in [sweep]; a key is either fixed or swept, not both"),
            ));
        }
    }
    let omega_at = scene_key_at(raw, sweep, "omega");
    let r_at = scene_key_at(raw, sweep, "r");
    if let (Some(w), Some(r)) = (&omega_at, &r_at) {
        let value = if r.starts_with("[scene]") {
            raw.r.map(num).unwrap_or_default()
        } else {
            cx.source("sweep", "r")
        };
        return Err(cx.err(
            r,
            value,
            format!("give the forcing frequency as omega or as r, not both (omega is in {w})"),
        ));
    }
    Ok(())
}

/// The harmonic scene's defaults with the keys `raw` gives (ranges checked by the caller).
fn fixed_settings(raw: &RawScene, sweep: &BTreeMap<String, RawAxis>) -> Harmonic {
    let mut h = Harmonic::default();
    if let Some(v) = raw.F0 {
        h.F0 = v;
    }
    if let Some(w) = raw.omega {
        h.drive = Drive::Omega(w);
    }
    if let Some(r) = raw.r {
        h.drive = Drive::Ratio(r);
    }
    // A swept frequency: the drive's kind (its values come from the plan, per design point).
    if sweep.contains_key("omega") {
        h.drive = Drive::Omega(1.0);
    }
    if raw.n_trans.is_some() {
        h.n_trans = raw.n_trans;
    }
    if let Some(n) = raw.n_trans_max {
        h.n_trans_max = n;
    }
    if let Some(n) = raw.n_meas {
        h.n_meas = n;
    }
    if let Some(v) = raw.trans_tol {
        h.trans_tol = v;
    }
    if let Some(v) = raw.period_tol {
        h.period_tol = v;
    }
    if let Some(n) = raw.starts {
        h.starts = n;
    }
    if let Some(v) = raw.design_life {
        h.design_life = v;
    }
    if let Some(v) = raw.life_quantile {
        h.life_quantile = v;
    }
    if let Some(v) = raw.life_tol {
        h.life_tol = v;
    }
    if let Some(n) = raw.life_max_periods {
        h.life_max_periods = n;
    }
    h
}

/// `design_peak`, `nonperiodic_peak` and `life_curve` of `raw` into `h`, each one of its names.
fn parse_peaks(cx: &Cx, raw: &RawScene, h: &mut Harmonic) -> Result<(), InputError> {
    if let Some(p) = named(
        cx,
        "design_peak",
        &raw.design_peak,
        (DesignPeak::parse, &DesignPeak::NAMES),
        "unknown design peak",
        "the worst steady state the census finds, or the one reached from the initial state",
    )? {
        h.design_peak = p;
    }
    if let Some(p) = named(
        cx,
        "nonperiodic_peak",
        &raw.nonperiodic_peak,
        (NonPeriodicPeak::parse, &NonPeriodicPeak::NAMES),
        "unknown peak of a steady state that is not periodic",
        "its largest amplitude over the design life, estimated, or the largest over the \
         census's 200-period window, a lower bound",
    )? {
        h.nonperiodic_peak = p;
    }
    if let Some(c) = named(
        cx,
        "life_curve",
        &raw.life_curve,
        (LifeCurve::parse, &LifeCurve::NAMES),
        "unknown extent of the design-life measurement",
        "only where a value can change a decision, or every frequency of the ideal curve until \
         its value is known",
    )? {
        h.life_curve = c;
    }
    Ok(())
}

/// A setting's parser and the names it takes.
type Names<T> = (fn(&str) -> Option<T>, &'static [&'static str]);

/// The `[scene].key` given as one of `names` (`parse`), if given; otherwise the error says
/// `what` was wrong, the names allowed and what they mean.
fn named<T>(
    cx: &Cx,
    key: &str,
    given: &Option<String>,
    (parse, names): Names<T>,
    what: &str,
    meaning: &str,
) -> Result<Option<T>, InputError> {
    given
        .as_ref()
        .map(|p| {
            parse(p).ok_or_else(|| {
                cx.err(
                    &format!("[scene].{key}"),
                    format!("{p:?}"),
                    format!("{what}; allowed: {} ({meaning})", names.join(", ")),
                )
            })
        })
        .transpose()
}

/// Where a frequency key is set (`[scene].r` or `[sweep].r`), if anywhere.
fn scene_key_at(raw: &RawScene, sweep: &BTreeMap<String, RawAxis>, key: &str) -> Option<String> {
    if raw.harmonic(key).is_some() {
        Some(format!("[scene].{key}"))
    } else if sweep.contains_key(key) {
        Some(format!("[sweep].{key}"))
    } else {
        None
    }
}

/// The frequency axis of a harmonic study (`omega` or `r`), if it is swept.
pub fn frequency_axis(axes: &[Axis]) -> Option<usize> {
    axes.iter().position(|a| a.key == "omega" || a.key == "r")
}

/// Refuses resonance without damping at any run of the plan (every design point, every case's
/// perturbed `m`). First a lower bound of the dynamic stiffness over the whole grid,
/// `|K - mass omega^2 + i C omega| >= C omega >= C_min omega_min`; only when it does not clear
/// `1e-6 K_max` are the combinations of `M`, `m + dm`, `K`, `C` and the frequency enumerated
/// (at most the number of runs; usually only `C = 0` studies get there).
fn check_runs(
    cx: &Cx,
    h: &Harmonic,
    system: &System,
    axes: &[Axis],
    cases: &[Case],
) -> Result<(), InputError> {
    let values = |key: &str| -> Vec<f64> {
        match axes.iter().find(|a| a.key == key) {
            Some(a) => a.values.clone(),
            None => vec![system.get(key).unwrap_or(f64::NAN)],
        }
    };
    let (freq_key, freqs) = match h.drive {
        Drive::Omega(w) => ("omega", axes_or(axes, "omega", w)),
        Drive::Ratio(r) => ("r", axes_or(axes, "r", r)),
    };
    let (ms, ks, cs, bigm) = (values("m"), values("K"), values("C"), values("M"));
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let omega_min = match h.drive {
        Drive::Omega(_) => min(&freqs),
        Drive::Ratio(_) => min(&freqs) * (min(&ks) / max(&bigm)).sqrt(),
    };
    if min(&cs) * omega_min >= RESONANCE_FLOOR * max(&ks) {
        return Ok(());
    }
    let mut dms: Vec<(f64, usize)> = Vec::new();
    for (i, c) in cases.iter().enumerate() {
        if !dms.iter().any(|(d, _)| *d == c.dm) {
            dms.push((c.dm, i));
        }
    }
    let freq_at = if axes.iter().any(|a| a.key == freq_key) {
        format!("[sweep].{freq_key}")
    } else {
        format!("[scene].{freq_key}")
    };
    for &big_m in &bigm {
        for &m in &ms {
            for &k in &ks {
                for &c in &cs {
                    for &f in &freqs {
                        for &(dm, case) in &dms {
                            let sys = System {
                                M: big_m,
                                m: m + dm,
                                K: k,
                                C: c,
                                ..*system
                            };
                            let mut run = *h;
                            run.set(freq_key, f);
                            if let Err(e) = run.check_resonance(&sys) {
                                let mut at = format!(
                                    "at M = {}, m = {}, K = {}, C = {}",
                                    num(big_m),
                                    num(m + dm),
                                    num(k),
                                    num(c)
                                );
                                if dm != 0.0 {
                                    at.push_str(&format!(" (case {case}: dm = {})", num(dm)));
                                }
                                return Err(cx.err(
                                    &freq_at,
                                    range_value(&e),
                                    format!("{} ({at})", e.allowed),
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

/// The values of `key`'s axis, or the fixed value.
fn axes_or(axes: &[Axis], key: &str, fixed: f64) -> Vec<f64> {
    match axes.iter().find(|a| a.key == key) {
        Some(a) => a.values.clone(),
        None => vec![fixed],
    }
}

/// Study keys that belong to the free-decay scene and are refused in a harmonic study, with
/// what to do instead.
const FREE_ONLY: [(&str, &str); 3] = [
    (
        "outputs",
        "the harmonic scene records all its outputs (docs/scenes.md); leave [study].outputs out",
    ),
    (
        "peaks",
        "peaks belong to the free-decay scene; a harmonic run measures over [scene].n_meas \
         forcing periods",
    ),
    (
        "t_end",
        "t_end belongs to the free-decay scene; a harmonic run ends after its transient and \
         [scene].n_meas forcing periods",
    ),
];

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::sim::{Drive, Harmonic, Scene};
    use crate::study::Study;

    fn parse(body: &str) -> Result<Study, String> {
        Study::parse(
            Path::new("h.toml"),
            &format!("[study]\nname = \"h\"\n{body}"),
        )
        .map_err(|e| e.to_string())
    }

    fn harmonic(s: &Study) -> Harmonic {
        match s.scene {
            Scene::Harmonic(h) => h,
            _ => panic!("not the harmonic scene"),
        }
    }

    #[test]
    fn no_scene_is_free_decay_and_harmonic_defaults_are_phase_1s() {
        assert_eq!(parse("").unwrap().scene, Scene::Free);
        assert_eq!(
            parse("[scene]\nkind = \"free\"\n").unwrap().scene,
            Scene::Free
        );
        let s = parse("[scene]\nkind = \"harmonic\"\n").unwrap();
        assert_eq!(harmonic(&s), Harmonic::default());
        let s = parse(
            "[scene]\nkind = \"harmonic\"\nF0 = 0.3\nomega = 60\nn_trans = 100\nn_meas = 8\n\
             n_trans_max = 50\ntrans_tol = 1e-8\nperiod_tol = 1e-5\n",
        )
        .unwrap();
        let h = harmonic(&s);
        assert_eq!(h.F0, 0.3);
        assert_eq!(h.drive, Drive::Omega(60.0));
        assert_eq!((h.n_trans, h.n_meas, h.n_trans_max), (Some(100), 8, 50));
        assert_eq!((h.trans_tol, h.period_tol), (1e-8, 1e-5));
    }

    #[test]
    fn the_frequency_axis_varies_fastest_wherever_it_stands() {
        let s = parse(
            "[scene]\nkind = \"harmonic\"\n[sweep]\nr = [0.5, 1.0, 1.5]\nm = [0.01, 0.02]\n\
             d = [0.005, 0.01]\n",
        )
        .unwrap();
        let keys: Vec<&str> = s.axes.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(keys, ["m", "d", "r"]);
        // The default chunk holds whole curves; a chunk size that cuts one is refused.
        assert_eq!(s.run.chunk_points % 3, 0);
        let e = parse(
            "[scene]\nkind = \"harmonic\"\n[sweep]\nr = [0.5, 1.0, 1.5]\n[run]\nchunk_points = 4\n",
        )
        .unwrap_err();
        assert_eq!(
            e,
            "h.toml: [run].chunk_points = 4: must be a multiple of the 3 values of the frequency \
             axis [sweep].r, so that every chunk holds whole frequency-response curves"
        );
    }

    /// A census study's default chunk aims at 4,096 runs, divided by the square of the most
    /// units a run has (each unit's walls are searched on their own): the bundled several-units
    /// showcase, up to 8 units and 5 cases over curves of 31 frequencies, gets one curve a chunk
    /// (16 chunks: an interrupt loses minutes, not the whole study), 2 units 6 curves, one unit
    /// 26.
    #[test]
    fn a_census_chunk_aims_at_fewer_runs_the_more_units_a_run_has() {
        let census = |sweep: &str| {
            parse(&format!(
                "[scene]\nkind = \"harmonic\"\nstarts = 4\n[sweep]\n{sweep}\n\
                 r = {{ start = 0.85, stop = 1.15, step = 0.01 }}\n\
                 [perturb]\ndm = [-0.001, 0.001]\ndd = [-0.001, 0.001]\n"
            ))
            .unwrap()
            .run
            .chunk_points
        };
        assert_eq!(census("units = [1, 2, 4, 8]"), 31); // 4096 / 64 / 5 = 12 points
        assert_eq!(census("units = [1, 2]"), 6 * 31); // 4096 / 4 / 5 = 204
        assert_eq!(census("m = [0.01, 0.02]"), 26 * 31); // 4096 / 5 = 819
    }

    #[test]
    fn errors_name_the_key_the_value_and_the_range() {
        let cases = [
            (
                "[scene]\nkind = \"forced\"\n",
                "h.toml: [scene].kind = \"forced\": unknown scene; allowed: free, harmonic, random, record",
            ),
            (
                "[scene]\nF0 = 2\n",
                "h.toml: [scene].F0 = 2: F0 belongs to the harmonic scene; set [scene] kind = \
                 \"harmonic\" (the free-decay scene has no forcing)",
            ),
            (
                "[scene]\nkind = \"harmonic\"\nF0 = -1\n",
                "h.toml: [scene].F0 = -1: the force amplitude must be a finite number > 0 (N)",
            ),
            (
                "[scene]\nkind = \"harmonic\"\nn_meas = 0\n",
                "h.toml: [scene].n_meas = 0: must be in [1, 1000000]",
            ),
            (
                "[scene]\nkind = \"harmonic\"\nomega = 60\nr = 1\n",
                "h.toml: [scene].r = 1: give the forcing frequency as omega or as r, not both \
                 (omega is in [scene].omega)",
            ),
            (
                "[scene]\nkind = \"harmonic\"\nomega = 60\n[sweep]\nr = [0.5, 1]\n",
                "h.toml: [sweep].r = [0.5, 1]: give the forcing frequency as omega or as r, not \
                 both (omega is in [scene].omega)",
            ),
            (
                "[scene]\nkind = \"harmonic\"\nr = 1.2\n[sweep]\nr = [0.5, 1]\n",
                "h.toml: [scene].r = 1.2: r is also swept in [sweep]; a key is either fixed or \
                 swept, not both",
            ),
            (
                "[scene]\nkind = \"harmonic\"\n[sweep]\nr = [0, 1]\n",
                "h.toml: [sweep].r = 0: the frequency ratio omega / sqrt(K/M) must be a finite \
                 number > 0",
            ),
            (
                "[sweep]\nr = [0.5, 1]\n",
                "h.toml: [sweep].r = [0.5, 1]: unknown axis 'r'; allowed: M, m, K, C, d, e, x0, \
                 v0, y0, w0, units, d_spread (F0, omega and r are axes of the harmonic scene: [scene] kind = \
                 \"harmonic\")",
            ),
            (
                "t_end = 1\n[scene]\nkind = \"harmonic\"\n",
                "h.toml: [study].t_end = 1: t_end belongs to the free-decay scene; a harmonic \
                 run ends after its transient and [scene].n_meas forcing periods",
            ),
            (
                "[scene]\nkind = \"harmonic\"\n[solver]\nkind = \"rk4\"\n",
                "h.toml: [solver].kind = \"rk4\": the harmonic scene is solved by exact only",
            ),
            (
                "[scene]\nkind = \"harmonic\"\n[run]\naudit = 3\n",
                "h.toml: [run].audit = 3: the accuracy audit re-runs free-decay runs; a harmonic \
                 study has none (its accuracy is shown in tests/forced.rs, docs/scenes.md)",
            ),
        ];
        for (body, want) in cases {
            assert_eq!(parse(body).unwrap_err(), want, "{body}");
        }
    }

    #[test]
    fn resonance_without_damping_is_refused_at_load_for_every_run() {
        // C = 0 and r = 1 on the main mass.
        let e = parse("[system]\nC = 0\n[scene]\nkind = \"harmonic\"\n[sweep]\nr = [0.5, 1]\n")
            .unwrap_err();
        assert!(
            e.starts_with("h.toml: [sweep].r = 1: resonance without damping"),
            "{e}"
        );
        assert!(e.ends_with("(at M = 0.1, m = 0.02, K = 400, C = 0)"), "{e}");
        // The stuck pair resonates at omega = sqrt(K / (M + m)) only for a perturbed m:
        // M = 0.1, m + dm = 0.025 → omega = sqrt(400 / 0.125).
        let w = (400.0f64 / 0.125).sqrt();
        let body = format!(
            "[system]\nC = 0\n[scene]\nkind = \"harmonic\"\nomega = {w}\n[perturb]\ndm = [0.005]\n"
        );
        let e = parse(&body).unwrap_err();
        assert!(e.contains("|K - (M + m) omega^2 + i C omega|"), "{e}");
        assert!(
            e.ends_with("(at M = 0.1, m = 0.025, K = 400, C = 0 (case 1: dm = 0.005))"),
            "{e}"
        );
        // With a little damping the same grid loads.
        parse("[system]\nC = 0.001\n[scene]\nkind = \"harmonic\"\n[sweep]\nr = [0.5, 1]\n")
            .unwrap();
        // Undamped but away from resonance: enumerated and accepted.
        parse("[system]\nC = 0\n[scene]\nkind = \"harmonic\"\n[sweep]\nr = [0.5, 2]\n").unwrap();
    }
}
