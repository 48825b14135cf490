//! Every bad random or record study in `tests/bad_studies/random/` is refused by
//! `RandomStudy::load` with exactly its message (issue 44: the random and record scenes' keys,
//! and a record file that is missing, unsorted in `t`, unevenly sampled, holding NaN or the wrong
//! columns), and nothing panics. Messages name the study file, the key, the value and what is
//! allowed; a record's also name the record file and the row.
//!
//! These go through the library's loader; the binary loads the same way (`Study::load` turns
//! a random study into a `Study`), and `tests/study_errors.rs` pins one of them through it.
//! `{dir}` stands for `tests/bad_studies/random`.

use std::path::Path;

use impactsweep::study::RandomStudy;

/// (file, the exact message with `{dir}` for the folder).
const BAD: &[(&str, &str)] = &[
    (
        "random_S0_negative.toml",
        "{dir}/random_S0_negative.toml: [scene].S0 = -1: the two-sided spectral density must be in (0, 1e12] ((m/s^2)^2 or N^2 per rad/s)",
    ),
    (
        "random_axis_of_the_other_spectrum.toml",
        "{dir}/random_axis_of_the_other_spectrum.toml: [sweep].omega_f = [1, 2]: unknown axis 'omega_f'; allowed: M, m, K, C, d, e, x0, v0, y0, w0, units, d_spread, S0, omega_g, zeta_g (S0, omega_g, zeta_g, omega_f and zeta_f are axes of the random scene as its spectrum has them, scale of the record scene)",
    ),
    (
        "random_units.toml",
        "{dir}/random_units.toml: [system].d_spread = 1: the clearance spread must be in [0, 1)",
    ),
    (
        "random_unit_table.toml",
        "{dir}/random_unit_table.toml: [system].unit[1].d = 0: the clearance must be a finite number > 0 (m)",
    ),
    (
        "random_unit_table_swept.toml",
        "{dir}/random_unit_table_swept.toml: [sweep].d_spread = [0, 0.5]: d_spread is fixed by the [[system.unit]] tables (model.md §14); a study with unit tables sweeps none of m, d, e, y0, w0, units, d_spread",
    ),
    (
        "random_axis_out_of_range.toml",
        "{dir}/random_axis_out_of_range.toml: [sweep].S0 = 0: the two-sided spectral density must be in (0, 1e12] ((m/s^2)^2 or N^2 per rad/s)",
    ),
    (
        "random_design_intensity_not_swept.toml",
        "{dir}/random_design_intensity_not_swept.toml: [scene].design_intensity = 0.01: needs a swept intensity: sweep S0 (a random load) or scale (a record) in [sweep]",
    ),
    (
        "random_design_intensity_off_grid.toml",
        "{dir}/random_design_intensity_off_grid.toml: [scene].design_intensity = 0.03: must be one of the swept S0 values: 0.005, 0.01, 0.02",
    ),
    (
        "random_envelope_key.toml",
        "{dir}/random_envelope_key.toml: [scene].envelope.decay = 0.5: unknown key 'decay'; allowed keys: t1, t2, c",
    ),
    (
        "random_envelope_order.toml",
        "{dir}/random_envelope_order.toml: [scene].envelope.t2 = 2: the envelope's plateau end (s) must be at least its rise t1 = 5 and at most 1e6",
    ),
    (
        "random_filter_key_on_white.toml",
        "{dir}/random_filter_key_on_white.toml: [scene].omega_g = 15.6: spectrum = \"white\" has no omega_g; omega_g and zeta_g belong to kanai-tajimi and clough-penzien, omega_f and zeta_f to clough-penzien",
    ),
    (
        "random_harmonic_key.toml",
        "{dir}/random_harmonic_key.toml: [scene].F0 = 1: F0 belongs to the harmonic scene; this study's kind is \"random\"",
    ),
    (
        "random_input.toml",
        "{dir}/random_input.toml: [scene].input = \"ground\": unknown input; allowed: base (ground acceleration, displacements relative to the ground), force (a force on the main mass)",
    ),
    (
        "random_nothing.toml",
        "{dir}/random_nothing.toml: [scene].spectrum: missing; the random scene needs a spectrum; allowed: white, kanai-tajimi, clough-penzien; and S0, the load's two-sided spectral density per rad/s, in (0, 1e12] ((m/s^2)^2 for a base input, N^2 for a force) (fixed here or swept in [sweep]): for example spectrum = \"kanai-tajimi\" and S0 = 1e-3",
    ),
    (
        "random_no_S0.toml",
        "{dir}/random_no_S0.toml: [scene].S0: missing; the random scene needs S0, the load's two-sided spectral density per rad/s, in (0, 1e12] ((m/s^2)^2 for a base input, N^2 for a force) (fixed here or swept in [sweep])",
    ),
    (
        "random_no_spectrum.toml",
        "{dir}/random_no_spectrum.toml: [scene].spectrum: missing; the random scene needs a spectrum; allowed: white, kanai-tajimi, clough-penzien",
    ),
    (
        "random_peaks.toml",
        "{dir}/random_peaks.toml: [study].peaks = 3: peaks belong to the free-decay scene; a random or record run lasts [scene].duration",
    ),
    (
        "random_perturb.toml",
        "{dir}/random_perturb.toml: [perturb]: a random study's cases are its realizations ([scene].realizations); perturbed cases are not supported in it",
    ),
    (
        "random_realizations_zero.toml",
        "{dir}/random_realizations_zero.toml: [scene].realizations = 0: must be a whole number in [1, 10000000]",
    ),
    (
        "random_scale.toml",
        "{dir}/random_scale.toml: [scene].scale = 2: scale belongs to the record scene; this study's kind is \"random\"",
    ),
    (
        "random_solver.toml",
        "{dir}/random_solver.toml: [solver].kind = \"rk4\": the random and record scenes are solved by exact only",
    ),
    (
        "random_swept_and_fixed.toml",
        "{dir}/random_swept_and_fixed.toml: [scene].S0 = 0.01: S0 is also swept in [sweep]; a key is either fixed or swept, not both",
    ),
    (
        "random_too_many_samples.toml",
        "{dir}/random_too_many_samples.toml: [scene].duration = 1000: duration / dt = 1e9 load samples; at most 1e8 per run",
    ),
    (
        "random_unknown_key.toml",
        "{dir}/random_unknown_key.toml: [scene].sigma = 2: unknown key 'sigma'; allowed keys: kind, F0, omega, r, n_trans, n_trans_max, n_meas, trans_tol, period_tol, starts, design_peak, nonperiodic_peak, design_life, life_quantile, life_tol, life_max_periods, life_curve, input, spectrum, S0, omega_g, zeta_g, omega_f, zeta_f, dt, duration, envelope, realizations, threshold, record, records, scale, design_intensity, intensity, T, ida_tol, ida_max, drift_ratio, storey_height, yield_coefficient",
    ),
    (
        "random_im_in_scene.toml",
        "{dir}/random_im_in_scene.toml: [scene].im = [0.1, 0.2, 0.3]: unknown key 'im' here; the stripes of an intensity measure are an axis: [sweep] im = [...] (g), with [scene] intensity = \"pga\" or \"sa\"",
    ),
    (
        "random_unknown_spectrum.toml",
        "{dir}/random_unknown_spectrum.toml: [scene].spectrum = \"pink\": unknown spectrum; allowed: white, kanai-tajimi, clough-penzien",
    ),
    (
        "random_zeta_g_zero.toml",
        "{dir}/random_zeta_g_zero.toml: [scene].zeta_g = 0: a filter damping ratio must be in [0.001, 10]",
    ),
    (
        "record_columns.toml",
        "{dir}/record_columns.toml: [scene].record = \"columns.csv\": {dir}/columns.csv: the columns are time, acc; allowed: t,a (ground acceleration, m/s^2) or t,F (force on the main mass, N)",
    ),
    (
        "record_input_mismatch.toml",
        "{dir}/record_input_mismatch.toml: [scene].input = \"force\": the record \"good.csv\" holds column a, a ground acceleration; give input = \"base\" or leave input out",
    ),
    (
        "record_missing.toml",
        "{dir}/record_missing.toml: [scene].record = \"nowhere.csv\": cannot read the record file {dir}/nowhere.csv: No such file or directory (os error 2)",
    ),
    (
        "record_nan.toml",
        "{dir}/record_nan.toml: [scene].record = \"nan.csv\": {dir}/nan.csv: row 3 (line 5): a = NaN: every value must be a finite number",
    ),
    (
        "record_parquet.toml",
        "{dir}/record_parquet.toml: [scene].record = \"quake.parquet\": cannot read the record file {dir}/quake.parquet: no such file",
    ),
    (
        "record_parquet_columns.toml",
        "{dir}/record_parquet_columns.toml: [scene].record = \"quake_columns.parquet\": {dir}/quake_columns.parquet: the columns are t, acc; allowed: t,a (ground acceleration, m/s^2) or t,F (force on the main mass, N)",
    ),
    (
        "record_parquet_null.toml",
        "{dir}/record_parquet_null.toml: [scene].record = \"quake_null.parquet\": {dir}/quake_null.parquet: row 2: a is null: every value must be a finite number",
    ),
    (
        "record_parquet_text.toml",
        "{dir}/record_parquet_text.toml: [scene].record = \"quake_text.parquet\": {dir}/quake_text.parquet: column a holds Utf8; a record's columns hold numbers (floats or integers)",
    ),
    (
        "record_parquet_uneven.toml",
        "{dir}/record_parquet_uneven.toml: [scene].record = \"quake_uneven.parquet\": {dir}/quake_uneven.parquet: row 2: t = 0.01: the samples must be evenly spaced; with dt = 0.013333333333333334 s ((t_last - t_first) / (rows - 1)) this row belongs at t = 0.013333333333333334, within 1e-6 dt",
    ),
    (
        "record_realizations.toml",
        "{dir}/record_realizations.toml: [scene].realizations = 10: a record is one load: realizations must be 1 (sweep scale for intensities; a suite of records is records = [...])",
    ),
    (
        "record_spectrum_key.toml",
        "{dir}/record_spectrum_key.toml: [scene].S0 = 0.1: S0 belongs to the random scene; this study's kind is \"record\"",
    ),
    (
        "record_uneven.toml",
        "{dir}/record_uneven.toml: [scene].record = \"uneven.csv\": {dir}/uneven.csv: row 4 (line 5): t = 0.035: the samples must be evenly spaced; with dt = 0.01 s ((t_last - t_first) / (rows - 1)) this row belongs at t = 0.03, within 1e-6 dt",
    ),
    (
        "record_unsorted.toml",
        "{dir}/record_unsorted.toml: [scene].record = \"unsorted.csv\": {dir}/unsorted.csv: row 4 (line 5): t = 0.02 is not after the previous row's t = 0.03: the times must increase",
    ),
    (
        "suite_and_record.toml",
        "{dir}/suite_and_record.toml: [scene].records = [\"good.csv\"]: give one record (record = \"path\") or a suite (records = [...] or a folder), not both",
    ),
    (
        "suite_bad_file.toml",
        "{dir}/suite_bad_file.toml: [scene].records = \"nan.csv\": {dir}/nan.csv: row 3 (line 5): a = NaN: every value must be a finite number",
    ),
    (
        "suite_duplicate.toml",
        "{dir}/suite_duplicate.toml: [scene].records = \"suite_two/../good.csv\": two records named \"good.csv\"; the records of a suite need distinct file names",
    ),
    (
        "suite_empty_folder.toml",
        "{dir}/suite_empty_folder.toml: [scene].records = \"suite_none\": the folder {dir}/suite_none holds no record (.csv or .parquet files); allowed: a folder of records or a list of files",
    ),
    (
        "suite_empty_list.toml",
        "{dir}/suite_empty_list.toml: [scene].records = []: an empty list; give the record files (CSV t,a or Parquet) or a folder of them",
    ),
    (
        "suite_list_of_numbers.toml",
        "{dir}/suite_list_of_numbers.toml: [scene].records = [\"good.csv\", 2]: allowed: a list of record files ([\"a.csv\", \"b.csv\"], relative to the study file) or a folder of them (\"suite\")",
    ),
    (
        "suite_missing_file.toml",
        "{dir}/suite_missing_file.toml: [scene].records = \"gone.csv\": cannot read the record file {dir}/gone.csv: No such file or directory (os error 2)",
    ),
    (
        "suite_missing_folder.toml",
        "{dir}/suite_missing_folder.toml: [scene].records = \"no_such_folder\": cannot read the folder {dir}/no_such_folder: No such file or directory (os error 2)",
    ),
    (
        "suite_mixed_input.toml",
        "{dir}/suite_mixed_input.toml: [scene].records = \"force.csv\": this record is a force, the suite's base; a suite's records share one input (columns t,a or t,F)",
    ),
    (
        "suite_not_a_list.toml",
        "{dir}/suite_not_a_list.toml: [scene].records = 3: allowed: a list of record files ([\"a.csv\", \"b.csv\"], relative to the study file) or a folder of them (\"suite\")",
    ),
    (
        "suite_realizations.toml",
        "{dir}/suite_realizations.toml: [scene].realizations = 3: a suite's realizations are its records: 2 here; leave realizations out or give 2",
    ),
];

const DIR: &str = "tests/bad_studies/random";

#[test]
fn every_bad_random_study_gets_its_exact_message() {
    let mut failures = Vec::new();
    let mut files: Vec<String> = std::fs::read_dir(DIR)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    files.sort();
    for file in &files {
        let path = Path::new(DIR).join(file);
        let got = match RandomStudy::load(&path) {
            Ok(_) => "loaded".to_string(),
            Err(e) => e.to_string().replace(DIR, "{dir}"),
        };
        let want = BAD.iter().find(|(f, _)| f == file).map(|(_, m)| *m);
        if want != Some(got.as_str()) {
            failures.push(format!(
                "    (\n        \"{file}\",\n        {got:?},\n    ),"
            ));
        }
    }
    let listed: Vec<&str> = BAD.iter().map(|(f, _)| *f).collect();
    assert!(
        failures.is_empty(),
        "{}\nlisted: {listed:?}",
        failures.join("\n")
    );
    assert_eq!(files.len(), BAD.len());
}
