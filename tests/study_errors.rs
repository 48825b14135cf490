//! Every bad study in `tests/bad_studies/` is refused by the real binary with exit status 2
//! and exactly its message, and nothing panics (issue 3: "Every bad study in the table gets its
//! exact message and exit status 2; none panics").
//!
//! Messages name the file, the key, the value and what is allowed
//! (`FILE: [table].key = VALUE: what is allowed`); TOML syntax errors give `FILE:LINE:COL`.
//! The binary runs inside `tests/bad_studies/` so FILE is the bare file name.

use std::path::Path;

use assert_cmd::Command;

/// (file, the exact message after `error: `).
const BAD: &[(&str, &str)] = &[
    (
        "axis_not_a_range.toml",
        "axis_not_a_range.toml: [sweep].e = { from = 0.5, to = 0.9 }: an axis is a list of numbers, {start, stop, step} or {start, stop, num}",
    ),
    (
        "bad_name.toml",
        "bad_name.toml: [study].name = \"my study\": the name must match [A-Za-z0-9_.-]+ and not be . or .. (it names the output directory)",
    ),
    (
        "cases_and_factorial.toml",
        "cases_and_factorial.toml: [perturb].dm = [0.001]: give either explicit cases or the factorial lists dm, dd, noise_seeds, not both",
    ),
    (
        "chunk_points_zero.toml",
        "chunk_points_zero.toml: [run].chunk_points = 0: must be a whole number >= 1",
    ),
    (
        "duplicate_axis_key.toml",
        "duplicate_axis_key.toml:5:1: TOML syntax error: duplicate key 'e'",
    ),
    (
        "e_out_of_range.toml",
        "e_out_of_range.toml: [system].e = 1.3: the coefficient of restitution must be in [0, 1]",
    ),
    (
        "empty_axis.toml",
        "empty_axis.toml: [sweep].e = []: an axis needs at least one value",
    ),
    (
        "harmonic_chunk_cuts_a_curve.toml",
        "harmonic_chunk_cuts_a_curve.toml: [run].chunk_points = 12: must be a multiple of the 11 values of the frequency axis [sweep].r, so that every chunk holds whole frequency-response curves",
    ),
    (
        "harmonic_omega_and_r.toml",
        "harmonic_omega_and_r.toml: [sweep].r = [0.9, 1.0, 1.1]: give the forcing frequency as omega or as r, not both (omega is in [scene].omega)",
    ),
    (
        "harmonic_nonperiodic_peak.toml",
        "harmonic_nonperiodic_peak.toml: [scene].nonperiodic_peak = \"maximum\": unknown peak of a steady state that is not periodic; allowed: life, window (its largest amplitude over the design life, estimated, or the largest over the census's 200-period window, a lower bound)",
    ),
    (
        "harmonic_life_curve.toml",
        "harmonic_life_curve.toml: [scene].life_curve = \"all\": unknown extent of the design-life measurement; allowed: decisions, whole (only where a value can change a decision, or every frequency of the ideal curve until its value is known)",
    ),
    (
        "harmonic_resonance.toml",
        "harmonic_resonance.toml: [sweep].r = 1: resonance without damping: |K - M omega^2 + i C omega| = 1.456201205281444e-14 N/m is below 1e-6 K = 4e-4 N/m, the steady amplitude is unbounded; move r or give C > 0 (at M = 0.1, m = 0.02, K = 400, C = 0)",
    ),
    (
        "list_not_increasing.toml",
        "list_not_increasing.toml: [sweep].d[2] = 0.015: the values of an axis must be strictly increasing (previous value 0.02)",
    ),
    (
        "missing_name.toml",
        "missing_name.toml: [study].name: missing; this key is required",
    ),
    (
        "missing_study.toml",
        "missing_study.toml: [study]: missing table; every study needs [study] with at least a name",
    ),
    (
        "negative_seed.toml",
        "negative_seed.toml: [study].seed = -1: must be a whole number >= 0",
    ),
    (
        "negative_step.toml",
        "negative_step.toml: [sweep].m.step = -0.01: the step must be a finite number > 0",
    ),
    (
        "noise_power_negative.toml",
        "noise_power_negative.toml: [noise].power = -1e-10: the noise power must be a finite number >= 0 (m^2 s)",
    ),
    (
        "noise_seed_without_noise.toml",
        "noise_seed_without_noise.toml: [perturb].cases[1].noise_seed = 4: a noise seed needs a [noise] table (power, sample_time)",
    ),
    (
        "perturbed_clearance.toml",
        "perturbed_clearance.toml: [perturb].cases[0].dd = -0.01: d + dd must be > 0 at every design point; the smallest d is 0.01 m ([system].d)",
    ),
    (
        "perturbed_mass_negative.toml",
        "perturbed_mass_negative.toml: [perturb].dm = -0.01: m + dm must be >= 0 at every design point; the smallest m is 0.005 kg ([sweep].m)",
    ),
    (
        "reversed_axis.toml",
        "reversed_axis.toml: [sweep].e.stop = 0.5: the axis is reversed: stop must be >= start = 0.9",
    ),
    (
        "scene_axis_in_free_study.toml",
        "scene_axis_in_free_study.toml: [sweep].r = [0.9, 1.0, 1.1]: unknown axis 'r'; allowed: M, m, K, C, d, e, x0, v0, y0, w0, units, d_spread (F0, omega and r are axes of the harmonic scene: [scene] kind = \"harmonic\")",
    ),
    (
        "solver_tol.toml",
        "solver_tol.toml: [solver].tol = 0.1: must be in [1e-15, 0.001]",
    ),
    (
        "start_outside_cavity.toml",
        "start_outside_cavity.toml: [sweep].y0 = 0.006: the inner mass must start inside the cavity: |y0 - x0| reaches 0.006, more than d/2 = 0.005 ([system].d)",
    ),
    (
        "start_outside_perturbed_cavity.toml",
        "start_outside_perturbed_cavity.toml: [perturb].dd = -0.003: the inner mass must start inside the perturbed cavity: |y0 - x0| reaches 0.004, more than (d + dd)/2 = 0.0035",
    ),
    (
        "step_and_num.toml",
        "step_and_num.toml: [sweep].e = { start = 0.5, stop = 0.9, step = 0.1, num = 5 }: give either step or num, not both",
    ),
    (
        "seeds_not_a_list.toml",
        "seeds_not_a_list.toml: [perturb].noise_seeds = 3: must be a list, one seed a case: for example noise_seeds = [1, 2, 3]",
    ),
    (
        "strength_without_sd.toml",
        "strength_without_sd.toml: [reliability].strength_mean = 2.85e8: strength_sd must be given too (both or neither)",
    ),
    (
        "sweep_out_of_range.toml",
        "sweep_out_of_range.toml: [sweep].e = 1.05: the coefficient of restitution must be in [0, 1]",
    ),
    (
        "swept_and_fixed.toml",
        "swept_and_fixed.toml: [system].e = 0.9: e is also swept in [sweep]; a key is either fixed or swept, not both",
    ),
    (
        "syntax_error.toml",
        "syntax_error.toml:5:5: TOML syntax error: string values must be quoted, expected literal string",
    ),
    (
        "too_few_peaks.toml",
        "too_few_peaks.toml: [study].peaks = 1: the outputs asked for need peaks >= 2",
    ),
    (
        "too_large.toml",
        "too_large.toml: [sweep] = 10211201 runs (10211201 design points x 1 case): more than the size guard of 10000000 runs; pass --allow-large to run it anyway",
    ),
    (
        "uneven_step.toml",
        "uneven_step.toml: [sweep].e.step = 0.15: (stop - start) / step = 2.666666666666667 is not a whole number; stop must be start + n * step",
    ),
    (
        "unknown_axis.toml",
        "unknown_axis.toml: [sweep].mu = [0.1, 0.2]: unknown axis 'mu'; allowed: M, m, K, C, d, e, x0, v0, y0, w0, units, d_spread",
    ),
    (
        "unknown_key.toml",
        "unknown_key.toml: [system].mass = 0.1: unknown key 'mass'; allowed keys: M, m, K, C, d, e, x0, v0, y0, w0, units, d_spread, unit",
    ),
    (
        "units_in_study.toml",
        "units_in_study.toml: [system].units = 2.5: the number of units must be a whole number in [1, 64]",
    ),
    // Issue 68: per-unit tables.
    (
        "unit_unknown_key.toml",
        "unit_unknown_key.toml: [system].unit[0].mass = 0.1: unknown key 'mass'; allowed keys: m, d, e, y0, w0",
    ),
    (
        "unit_missing_e.toml",
        "unit_missing_e.toml: [system].unit[1].e: missing; every unit needs its own m, d and e (y0 and w0 default to the system's)",
    ),
    (
        "unit_e_out_of_range.toml",
        "unit_e_out_of_range.toml: [system].unit[1].e = 1.2: the coefficient of restitution must be in [0, 1]",
    ),
    (
        "unit_start_outside.toml",
        "unit_start_outside.toml: [system].unit[0].y0 = 0.004: the unit must start inside its cavity: |y0 - x0| = 0.004 exceeds its d/2 = 0.003 (x0 = 0)",
    ),
    (
        "unit_too_many.toml",
        "unit_too_many.toml: [system].unit = 65 tables: give 1 to 64 [[system.unit]] tables, one per damper unit",
    ),
    (
        "unit_with_units.toml",
        "unit_with_units.toml: [system].units = 3: units is decided by the [[system.unit]] tables (model.md §14): give each unit's m, d and e there; m, d, e, units and d_spread cannot be set beside them",
    ),
    (
        "unit_swept_m.toml",
        "unit_swept_m.toml: [sweep].m = [0.01, 0.02]: m is fixed by the [[system.unit]] tables (model.md §14); a study with unit tables sweeps none of m, d, e, y0, w0, units, d_spread",
    ),
    (
        "unit_perturbed.toml",
        "unit_perturbed.toml: [perturb].dm = 0.001: perturbed m and d belong to the plain system; with [[system.unit]] tables each unit's m and d are its own (perturb them by listing the tables again)",
    ),
    (
        "unit_x0_axis_outside.toml",
        "unit_x0_axis_outside.toml: [sweep].x0 = -0.002: unit[0].y0: the unit must start inside its cavity: |y0 - x0| = 0.004 exceeds its d/2 = 0.003 (x0 = -0.002)",
    ),
    (
        "unknown_key_in_case.toml",
        "unknown_key_in_case.toml: [perturb].cases[1].seed = 3: unknown key 'seed'; allowed keys: dm, dd, noise_seed",
    ),
    (
        "unknown_output.toml",
        "unknown_output.toml: [study].outputs[1] = \"energy\": unknown output; allowed: x1, t1, x2, t2, xmax, di, impacts, sticks, energy_impact, energy_viscous",
    ),
    (
        "unknown_solver.toml",
        "unknown_solver.toml: [solver].kind = \"euler\": unknown solver; allowed: exact, rk4, dopri5",
    ),
    (
        "unknown_table.toml",
        "unknown_table.toml: [sweeps]: unknown table; allowed tables: study, scene, system, sweep, perturb, noise, solver, reliability, zones, ranking, run",
    ),
    (
        "weights_do_not_sum.toml",
        "weights_do_not_sum.toml: [ranking].wf2 = 0.5: wf1 + wf2 must be 1 (here 1.2), so that perfectibility is a percentage",
    ),
    (
        "wrong_type.toml",
        "wrong_type.toml: [system].e = \"high\": must be a number",
    ),
    (
        "zero_step.toml",
        "zero_step.toml: [sweep].e.step = 0: the step must be a finite number > 0",
    ),
    (
        "zone_axis_not_swept.toml",
        "zone_axis_not_swept.toml: [zones].zone[0].axis = \"m\": a zone is a range of a swept axis; swept: e",
    ),
    // Issue 44: the random and record scenes are checked (tests/random_study_errors.rs, through
    // the library) and reach the binary's messages the same way; their keys do not belong to
    // the other scenes.
    (
        "random_S0_negative_via_run.toml",
        "random_S0_negative_via_run.toml: [scene].S0 = -0.01: the two-sided spectral density must be in (0, 1e12] ((m/s^2)^2 or N^2 per rad/s)",
    ),
    (
        "random_key_in_free_study.toml",
        "random_key_in_free_study.toml: [scene].S0 = 0.01: S0 belongs to the random and record scenes; set [scene] kind = \"random\" or \"record\"",
    ),
    (
        "random_axis_in_free_study.toml",
        "random_axis_in_free_study.toml: [sweep].S0 = [0.01, 0.1]: unknown axis 'S0'; allowed: M, m, K, C, d, e, x0, v0, y0, w0, units, d_spread (S0, omega_g, zeta_g, omega_f and zeta_f are axes of the random scene as its spectrum has them, scale of the record scene)",
    ),
    // Issue 10: the jump and zone keys.
    (
        "zones_jump_k.toml",
        "zones_jump_k.toml: [zones].jump_k = 6: no longer a key: a jump is now decided in the quantity's own units; use step_spread (steps, in spreads across a point's cases) and kink_slope (kinks, in typical slopes), see docs/study.md",
    ),
    (
        "zones_kink_slope.toml",
        "zones_kink_slope.toml: [zones].kink_slope = -1: must be a finite number > 0 (typical slopes)",
    ),
    (
        "zones_locate_zero.toml",
        "zones_locate_zero.toml: [zones].locate = 0: a fraction of the grid step in (0, 0.5]",
    ),
    (
        "zones_min_zone.toml",
        "zones_min_zone.toml: [zones].min_zone = 0.7: a fraction of the design points in [0, 0.5]",
    ),
];

fn dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/bad_studies"))
}

#[test]
fn every_bad_study_gets_its_exact_message_and_status_2() {
    let mut failures = Vec::new();
    for (file, message) in BAD {
        let out = Command::cargo_bin("impactsweep")
            .unwrap()
            .current_dir(dir())
            .args(["plan", file])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let expected = format!("error: {message}\n");
        if out.status.code() != Some(2) || stderr != expected || !out.stdout.is_empty() {
            failures.push(format!(
                "{file}: status {:?}\n  expected: {expected}  got:      {stderr}",
                out.status.code()
            ));
        }
        assert!(!stderr.contains("panicked"), "{file} panicked: {stderr}");
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_table_covers_every_file_in_the_directory() {
    let mut on_disk: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = BAD.iter().map(|(f, _)| f.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed);
    assert!(listed.len() >= 15);
}

#[test]
fn the_size_guard_yields_to_allow_large() {
    Command::cargo_bin("impactsweep")
        .unwrap()
        .current_dir(dir())
        .args(["plan", "too_large.toml", "--allow-large"])
        .assert()
        .success()
        .stdout(predicates::str::contains("total runs:     10211201\n"));
}

#[test]
fn a_missing_file_is_bad_input() {
    let out = Command::cargo_bin("impactsweep")
        .unwrap()
        .current_dir(dir())
        .args(["plan", "no_such_study.toml"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("error: no_such_study.toml: cannot read the study file: "),
        "{stderr}"
    );
}
