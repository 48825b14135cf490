//! Study files: TOML → validated [`Study`].
//!
//! CONTRACT (shared by the sweep engine and the reducer): the types below are the validated
//! form; later stages never see an unvalidated value. The TOML format is documented in
//! `docs/study.md`. Parsing follows ripgrep's low/high args: `#[serde(deny_unknown_fields)]` raw
//! structs mirror the TOML, one conversion validates units, ranges and cross-field rules.
//!
//! [`Study::parse`] reads the text (`toml_error.rs` turns a syntax or type error into
//! `file:line:col` or `file: [table].key = value: ...`) and hands it to the scene's parser,
//! chosen in one place, `scene/mod.rs`: one module per scene (`scene/free.rs`,
//! `scene/harmonic.rs`, `scene/random.rs` with its load in `scene/random_load.rs`). Each
//! parser validates the tables in turn, each table in its own file, which holds the table's
//! raw struct, its validated type and its messages: `header.rs` (`[study]`), `system.rs`,
//! `sweep.rs`, `noise.rs`, `perturb.rs` (with the cross-checks over every design point's
//! extremes), `solver.rs`, `reliability.rs`, `zones.rs`, `ranking.rs`, `run.rs`, `hazard.rs`,
//! and a record file's checks in `record.rs`. The messages' context (the file, its text, the
//! number format) is `context.rs`'s, the validated [`Study`] `validated.rs`'s and the size guard
//! `size.rs`'s; none of these imports this file.
//!
//! A study of the random or record scene (`[scene] kind = "random"` or `"record"`) is validated
//! into a [`RandomStudy`], which [`Study::load`] turns into a [`Study`] of [`Scene::Random`](crate::sim::Scene::Random)
//! whose cases are its realizations ([`Study::realizations`]).

use std::path::Path;

use crate::error::InputError;

mod axis;
mod context;
mod hazard;
mod header;
mod noise;
mod perturb;
mod ranking;
mod record;
mod reliability;
mod run;
mod scene;
mod size;
mod solver;
mod sweep;
mod system;
mod toml_error;
mod validated;
mod zones;

pub use axis::Axis;
pub use context::num;
pub use hazard::HAZARD_COPY;
pub use header::OUTPUTS;
pub use perturb::Case;
pub use ranking::{DiSource, Ranking, VERIFY_PERIODS};
pub use record::{EVEN_TOL, RECORD_COPY, RECORD_COPY_PARQUET, SUITE_COPY, record_copy};
pub use reliability::{Reliability, SafetyForm};
pub use run::{DEFAULT_CHUNK_RUNS, RunSettings, whole_curves};
pub use scene::harmonic::frequency_axis;
pub use scene::random::RandomStudy;
pub use scene::random_load::{DEFAULT_DT, DEFAULT_REALIZATIONS, INTENSITY_KEYS};
pub use size::{LoadOptions, MAX_RUNS};
pub use sweep::MAX_AXIS_VALUES;
pub use validated::{CensusKind, Study};
pub use zones::{DeclaredZone, Zones};

/// Loading and parsing, and what a study's scene decides (its frequency axis, its design
/// intensity).
impl Study {
    /// Reads and validates a study file with the default size guard ([`MAX_RUNS`]). Errors
    /// name the file, the key, the value and the allowed range; TOML syntax errors give line
    /// and column.
    pub fn load(path: &Path) -> Result<Study, InputError> {
        Study::load_with(path, LoadOptions::default())
    }

    /// [`Study::load`] with options (`allow_large`).
    pub fn load_with(path: &Path, opts: LoadOptions) -> Result<Study, InputError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            InputError::new(format!(
                "{}: cannot read the study file: {e}",
                path.display()
            ))
        })?;
        Study::parse_with(path, &text, opts)
    }

    /// Parses and validates study text with the default size guard; `path` is used in
    /// messages.
    pub fn parse(path: &Path, text: &str) -> Result<Study, InputError> {
        Study::parse_with(path, text, LoadOptions::default())
    }

    /// [`Study::parse`] with options (`allow_large`).
    pub fn parse_with(path: &Path, text: &str, opts: LoadOptions) -> Result<Study, InputError> {
        let study = scene::study(path, text)?;
        study.check_size(opts.allow_large)?;
        Ok(study)
    }

    /// The swept frequency axis of a harmonic study (`omega` or `r`; always the last axis).
    pub fn frequency_axis(&self) -> Option<&Axis> {
        self.scene.harmonic()?;
        frequency_axis(&self.axes).map(|i| &self.axes[i])
    }

    /// The swept intensity the designs are ranked at (`S0`, `scale` or a stripe's `im`):
    /// `[scene].design_intensity`, or else the middle swept value (the lower middle one for an
    /// even count); `None` without an intensity axis.
    pub fn design_intensity_value(&self) -> Option<f64> {
        let axis = self
            .axes
            .iter()
            .find(|a| INTENSITY_KEYS.contains(&a.key.as_str()))?;
        Some(
            self.design_intensity
                .unwrap_or(axis.values[(axis.values.len() - 1) / 2]),
        )
    }

    /// Design points per frequency-response curve: the length of the frequency axis of a
    /// harmonic study, 1 otherwise. Chunks hold whole curves.
    pub fn curve_points(&self) -> u64 {
        self.frequency_axis().map_or(1, |a| a.values.len() as u64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::System;
    use crate::sim::Request;

    fn parse(text: &str) -> Result<Study, InputError> {
        Study::parse(Path::new("t.toml"), text)
    }

    fn study(body: &str) -> Study {
        parse(&format!("[study]\nname = \"t\"\n{body}")).unwrap()
    }

    fn err(body: &str) -> String {
        parse(&format!("[study]\nname = \"t\"\n{body}"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn minimal_study_is_table_i_with_one_ideal_case() {
        let s = study("");
        assert_eq!(s.system, System::TABLE_I);
        assert_eq!(s.n_points(), 1);
        assert_eq!(s.cases, vec![Case::IDEAL]);
        assert_eq!(s.request, Request::default());
        assert!(s.noise.is_none());
        assert!(!s.reliability.has_strength());
        assert_eq!(s.run.chunk_points, DEFAULT_CHUNK_RUNS);
        assert_eq!(s.seed, 0);
    }

    #[test]
    fn step_grid_counts_are_pinned() {
        // hyperfine pins 11 values for 0..=1 step 0.1.
        let s = study("[sweep]\ne = { start = 0.0, stop = 1.0, step = 0.1 }\n");
        let v = &s.axes[0].values;
        assert_eq!(v.len(), 11);
        assert_eq!(v[0], 0.0);
        assert_eq!(v[3], 0.3); // 3 * 0.1 = 0.30000000000000004 before rounding
        assert_eq!(v[10], 1.0);
        // The paper's sweep: 51 values, every one the double the user would type.
        let s = study("[sweep]\ne = { start = 0.45, stop = 0.95, step = 0.01 }\n");
        let v = &s.axes[0].values;
        assert_eq!(v.len(), 51);
        for (i, x) in v.iter().enumerate() {
            let typed: f64 = format!("0.{}", 45 + i).parse().unwrap();
            assert_eq!(x.to_bits(), typed.to_bits(), "value {i}");
        }
        // A single value, and a step that does not divide the range.
        let s = study("[sweep]\ne = { start = 0.5, stop = 0.5, step = 0.1 }\n");
        assert_eq!(s.axes[0].values, vec![0.5]);
        assert!(err("[sweep]\ne = { start = 0.0, stop = 1.0, step = 0.3 }\n").contains(
            "[sweep].e.step = 0.3: (stop - start) / step = 3.3333333333333335 is not a whole number"
        ));
    }

    #[test]
    fn linspace_endpoints_are_exact() {
        let s = study("[sweep]\nd = { start = 0.001, stop = 0.0123, num = 7 }\n");
        let v = &s.axes[0].values;
        assert_eq!(v.len(), 7);
        assert_eq!(v[0].to_bits(), 0.001f64.to_bits());
        assert_eq!(v[6].to_bits(), 0.0123f64.to_bits());
        assert!(v.windows(2).all(|w| w[0] < w[1]));
        let s = study("[sweep]\ne = { start = 0.0, stop = 1.0, num = 5 }\n");
        assert_eq!(s.axes[0].values, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        let s = study("[sweep]\ne = { start = 0.3, stop = 0.3, num = 1 }\n");
        assert_eq!(s.axes[0].values, vec![0.3]);
    }

    #[test]
    fn axes_keep_file_order_and_the_grid_is_their_product() {
        let s = study(
            "[sweep]\nm = [0.01, 0.02]\ne = { start = 0.5, stop = 0.9, num = 5 }\nd = [0.01]\n",
        );
        let keys: Vec<&str> = s.axes.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(keys, ["m", "e", "d"]);
        assert_eq!(s.n_points(), 10);
    }

    #[test]
    fn ideal_case_is_first_and_not_duplicated() {
        let s = study(
            "[noise]\npower = 1e-10\nsample_time = 1e-3\n[perturb]\ncases = [\n  { dm = 0.0, dd = 0.0 },\n  { dd = 0.001 },\n  { noise_seed = 7 },\n  {},\n]\n",
        );
        assert_eq!(s.cases.len(), 3);
        assert_eq!(s.cases[0], Case::IDEAL);
        assert!(s.cases[1..].iter().all(|c| !c.ideal));
        assert_eq!(s.cases[1].dd, 0.001);
        assert_eq!(s.cases[2].noise_seed, Some(7));
        // Factorial: 3 x 3 minus the ideal combination, plus the ideal case first.
        let s = study("[perturb]\ndm = [-0.001, 0, 0.001]\ndd = [-0.001, 0.0, 0.001]\n");
        assert_eq!(s.cases.len(), 9);
        assert_eq!(s.cases.iter().filter(|c| c.ideal).count(), 1);
        assert!(s.cases[0].ideal);
        assert_eq!((s.cases[1].dm, s.cases[1].dd), (-0.001, -0.001));
        // With noise seeds no factorial row is ideal.
        let s = study(
            "[noise]\npower = 1e-10\nsample_time = 1e-3\n[perturb]\ndm = [0, 0.001]\nnoise_seeds = [1, 2]\n",
        );
        assert_eq!(s.cases.len(), 5);
        assert_eq!(s.n_runs(), 5);
    }

    #[test]
    fn outputs_set_the_horizon() {
        assert_eq!(study("").request.peaks, 2);
        assert_eq!(study("outputs = [\"x1\", \"impacts\"]\n").request.peaks, 1);
        assert_eq!(study("outputs = [\"x1\"]\npeaks = 5\n").request.peaks, 5);
        assert_eq!(study("t_end = 0.5\n").request.t_end, Some(0.5));
        assert!(
            err("outputs = [\"di\"]\npeaks = 1\n")
                .contains("[study].peaks = 1: the outputs asked for need peaks >= 2")
        );
    }

    #[test]
    fn size_guard_and_allow_large() {
        let text = "[study]\nname = \"big\"\n[sweep]\ne = { start = 0, stop = 1, num = 5000 }\nm = { start = 0, stop = 0.02, num = 2001 }\n";
        let e = parse(text).unwrap_err().to_string();
        assert_eq!(
            e,
            "t.toml: [sweep] = 10005000 runs (10005000 design points x 1 case): more than the size guard of 10000000 runs; pass --allow-large to run it anyway"
        );
        let s = Study::parse_with(Path::new("t.toml"), text, LoadOptions { allow_large: true })
            .unwrap();
        assert_eq!(s.n_runs(), 10_005_000);
        assert!(s.check_size(false).is_err());
    }

    #[test]
    fn unit_tables_make_a_study_of_several_units() {
        let s = study(
            "[system]\nw0 = 0.1\n[[system.unit]]\nm = 0.004\nd = 0.008\ne = 0.8\n\
             [[system.unit]]\nm = 0.006\nd = 0.012\ne = 0.6\ny0 = 0.001\n[sweep]\nC = [0.1, 0.2]\n",
        );
        assert!(s.several_units());
        assert!(!s.census());
        let units = s.system.unit_list();
        assert_eq!(units.len(), 2);
        assert_eq!((units[0].y0, units[0].w0), (0.0, 0.1));
        assert_eq!((units[1].y0, units[1].w0), (0.001, 0.1));
        assert_eq!((s.system.m, s.system.d, s.system.units), (0.01, 0.012, 2.0));
        // One table is the plain system: the same study as its [system] keys.
        let one = study("[[system.unit]]\nm = 0.01\nd = 0.02\ne = 0.5\n");
        let plain = study("[system]\nm = 0.01\nd = 0.02\ne = 0.5\n");
        assert_eq!(one.system, plain.system);
        assert!(!one.several_units());
        // Its unit is still fixed by the table.
        assert!(
            err("[[system.unit]]\nm = 0.01\nd = 0.02\ne = 0.5\n[sweep]\ne = [0.5, 0.6]\n")
                .contains("[sweep].e = [0.5, 0.6]: e is fixed by the [[system.unit]] tables")
        );
    }

    proptest::proptest! {
        /// Whatever value lands on whatever key, parsing answers Ok or an error naming the
        /// file; it never panics.
        #[test]
        fn any_value_on_any_key_never_panics(
            key in proptest::sample::select(vec![
                "[system]\ne", "[system]\nm", "[system]\nd", "[system]\ny0", "seed",
                "peaks", "t_end", "outputs", "[sweep]\ne", "[sweep]\nd", "[sweep]\ny0",
                "[perturb]\ndm", "[perturb]\ndd", "[perturb]\ncases", "[perturb]\nnoise_seeds",
                "[noise]\npower", "[solver]\ntol", "[solver]\nmax_steps", "[reliability]\nE",
                "[reliability]\nstrength_mean", "[zones]\nzone", "[ranking]\nwf1",
                "[run]\nchunk_points", "[bogus]\nx", "[scene]\nkind", "[scene]\nF0",
                "[scene]\nkind = \"harmonic\"\nr", "[scene]\nkind = \"harmonic\"\nn_meas",
                "[scene]\nkind = \"harmonic\"\ntrans_tol",
                "[system]\nC = 0\n[scene]\nkind = \"harmonic\"\n[sweep]\nr",
                "[scene]\nkind = \"harmonic\"\n[sweep]\nomega",
                "[scene]\nkind = \"harmonic\"\n[run]\nchunk_points",
                "[[system.unit]]\nm = 0.01\nd = 0.01\ne",
                "[[system.unit]]\nd = 0.01\ne = 0.5\nm",
                "[[system.unit]]\nm = 0.01\nd = 0.01\ne = 0.5\ny0",
                "[[system.unit]]\nm = 0.01\nd = 0.01\ne = 0.5\n[[system.unit]]\nm = 0.01\ne = 0.5\nd",
                "[[system.unit]]\nm = 0.01\nd = 0.01\ne = 0.5\n[sweep]\nx0",
                "[system]\nunit",
            ]),
            value in proptest::sample::select(vec![
                "nan", "inf", "-inf", "-0.0", "0", "1e308", "-1", "9223372036854775807", "\"x\"",
                "[]", "{}", "[nan]", "[1, 0]", "[0.0, 1e-300]", "{ start = 0, stop = 1e300, step = 1e-300 }",
                "{ start = 0, stop = 1, num = 0 }", "{ start = 1e-3, stop = 1e-3, num = 1 }",
                "{ start = 0, stop = 1, step = nan }", "[{ dm = nan }]", "[{ dd = -1 }]",
                "[{ name = \"a\", axis = \"e\", from = 1, to = 0 }]", "true", "1979-05-27",
            ]),
        ) {
            let text = format!("[study]\nname = \"p\"\n{key} = {value}\n");
            if let Err(e) = Study::parse(Path::new("p.toml"), &text) {
                proptest::prop_assert!(e.to_string().starts_with("p.toml"), "{}", e);
            }
        }
    }
}
