//! The data contract's names, units and version: what every table the tool writes calls its
//! columns and in which unit it stores them. `docs/schema.md` lists every column with its type,
//! unit and meaning; a test keeps the two in step.
//!
//! Column names are unique without case in every table (DuckDB, Spark and most SQL engines match
//! names without case). Study keys, `--set` keys, report prose and chart labels keep the paper's
//! symbols (`M`, `m`); [`column_name`] is the only place that maps a key to its column.

/// Schema version written to every Parquet file the tool writes (`impactsweep.schema_version`)
/// and to `manifest.json`. Bump it on any change of a column's name, type, unit or meaning in
/// any table; the reader refuses another version with a message that says what to do.
///
/// History: 1 = the first release (`M`, `m`); 2 = `mass_main`, `mass_inner`, units in the field
/// metadata, every table versioned.
pub const SCHEMA_VERSION: u32 = 2;

/// Key-value metadata: the study text (points only).
pub const META_STUDY: &str = "impactsweep.study";
/// Key-value metadata of an analysis shard's tables: the fingerprint of the math library that
/// computed them ([`crate::sim::math::fingerprint`]).
pub const META_MATH: &str = "impactsweep.math";
/// Key-value metadata: the version of the tool that wrote the file.
pub const META_VERSION: &str = "impactsweep.version";
/// Key-value metadata: [`SCHEMA_VERSION`].
pub const META_SCHEMA_VERSION: &str = "impactsweep.schema_version";
/// Key-value metadata of a points part whose systems have a per-unit table (`[[system.unit]]`,
/// model.md §14): the table as JSON, a list of `{m, d, e, y0, w0}`. Its rows' `units` column
/// counts the units; the table is fixed for a whole study, so it is stored once per part.
pub const META_UNITS: &str = "impactsweep.units";
/// Key-value metadata: which table the file holds ([`TableKind::name`]).
pub const META_TABLE: &str = "impactsweep.table";
/// Field metadata key of a column's unit (`"1"` dimensionless, `""` for ids, labels and flags).
pub const FIELD_UNIT: &str = "unit";

/// The column of a system key: `"M"` → `"mass_main"`, `"m"` → `"mass_inner"`, any other key
/// unchanged (`e`, `d`, `x0`, ...).
pub fn column_name(key: &str) -> &str {
    match key {
        "M" => "mass_main",
        "m" => "mass_inner",
        other => other,
    }
}

/// The system key of a column name (the inverse of [`column_name`]); `None` for a column that
/// is not a system parameter.
pub fn system_key(column: &str) -> Option<&'static str> {
    crate::model::SYSTEM_KEYS
        .into_iter()
        .chain(crate::model::UNIT_KEYS)
        .find(|k| column_name(k) == column)
}

/// The unit of a system key (SI).
pub fn system_unit(key: &str) -> Option<&'static str> {
    Some(match key {
        "M" | "m" => "kg",
        "K" => "N/m",
        "C" => "N s/m",
        "d" | "x0" | "y0" => "m",
        "e" | "units" | "d_spread" => "1",
        "v0" | "w0" => "m/s",
        _ => return None,
    })
}

/// The unit of a key a study may sweep: a system key, or the harmonic scene's `F0` (N),
/// `omega` (rad/s) or `r` (1). Their columns keep the key as the name ([`column_name`]).
pub fn axis_unit(key: &str) -> Option<&'static str> {
    system_unit(key).or(match key {
        "F0" => Some("N"),
        "omega" | "omega_g" | "omega_f" => Some("rad/s"),
        "r" | "zeta_g" | "zeta_f" | "scale" => Some("1"),
        "S0" => Some(S0_UNIT),
        "im" => Some("g"),
        _ => None,
    })
}

/// The key of an axis column (the inverse of [`column_name`] over the sweepable keys).
pub fn axis_key(column: &str) -> Option<&'static str> {
    system_key(column).or_else(|| {
        crate::sim::Harmonic::AXES
            .into_iter()
            .chain(crate::sim::random::RandomScene::AXES)
            .find(|k| *k == column)
    })
}

/// The unit of a random load's two-sided spectral density `S0`: (m/s^2)^2 per rad/s for ground
/// acceleration, N^2 per rad/s for a force.
pub const S0_UNIT: &str = "(m/s^2)^2 s/rad or N^2 s/rad";

/// See [`UNIT_OF_AXIS`]: a fragility curve's median capacity is in the unit of the intensity
/// its study sweeps (`S0` or a record's `scale`), which its `intensity` column names.
pub const UNIT_OF_INTENSITY: &str = "[intensity]";

/// The tables the tool writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableKind {
    /// `points/part-NNNNNN.parquet`: one row per run of a free-decay study.
    Points,
    /// `points/part-NNNNNN.parquet`: one row per run of a harmonic (forced) study.
    HarmonicPoints,
    /// `points/part-NNNNNN.parquet`: one row per realization of a random or record study.
    RandomPoints,
    /// `summary.parquet`, `summary.csv`: one row per design point.
    Summary,
    /// `zones.parquet`, `zones.csv`: one row per zone.
    Zones,
    /// `jumps.parquet`, `jumps.csv`: one row per jump.
    Jumps,
    /// `sensitivity.parquet`, `sensitivity.csv`: one row per quantity and axis.
    Sensitivity,
    /// `tradeoff.parquet`: one row per solver setting.
    Tradeoff,
    /// `attractors/part-NNNNNN.parquet` (the sweep) and `attractors.csv` (`reduce`: the ideal
    /// case's rows): one row per run of a harmonic study and attractor.
    Attractors,
    /// `branches.parquet`, `branches.csv`: one row per continuation point of a harmonic study's
    /// ideal case (and `analysis/branches-I-of-N.parquet`, a shard's, with each row's section).
    Branches,
    /// `analysis/probes-I-of-N.parquet`: the jump probes a shard of the analysis computed.
    Probes,
    /// `bifurcations.parquet`, `bifurcations.csv`: one row per point of a bifurcation curve
    /// followed in `(r, p)` over a design axis `p` (`reduce` of a harmonic study).
    Bifurcations,
    /// `verification.parquet`, `verification.csv`: one row per motion a harmonic study's
    /// `reduce` measured again directly to verify the ranking (docs/scenes.md, "The decision
    /// verified").
    Verification,
    /// `capacities.parquet`, `capacities.csv`: one row per motion of a random or record study
    /// with an intensity measure and a threshold: its capacity by incremental dynamic analysis
    /// (`reduce`; docs/scenes.md).
    Capacities,
}

impl TableKind {
    pub const ALL: [TableKind; 14] = [
        TableKind::Points,
        TableKind::HarmonicPoints,
        TableKind::RandomPoints,
        TableKind::Summary,
        TableKind::Zones,
        TableKind::Jumps,
        TableKind::Sensitivity,
        TableKind::Tradeoff,
        TableKind::Attractors,
        TableKind::Branches,
        TableKind::Probes,
        TableKind::Bifurcations,
        TableKind::Verification,
        TableKind::Capacities,
    ];

    /// The table's name (`impactsweep.table`, the file stem).
    pub fn name(self) -> &'static str {
        match self {
            TableKind::Points => "points",
            TableKind::HarmonicPoints => "forced_points",
            TableKind::RandomPoints => "random_points",
            TableKind::Summary => "summary",
            TableKind::Zones => "zones",
            TableKind::Jumps => "jumps",
            TableKind::Sensitivity => "sensitivity",
            TableKind::Tradeoff => "tradeoff",
            TableKind::Attractors => "attractors",
            TableKind::Branches => "branches",
            TableKind::Probes => "probes",
            TableKind::Bifurcations => "bifurcations",
            TableKind::Verification => "verification",
            TableKind::Capacities => "capacities",
        }
    }
}

/// A unit written as `[col]` means "the unit of the quantity named in column `col` of the same
/// row" (a jump's `at` is in the unit of its `axis`).
pub const UNIT_OF_AXIS: &str = "[axis]";
/// The unit of a bifurcation curve's `p`: that of the axis its `p_name` names.
pub const UNIT_OF_P: &str = "[p_name]";
/// See [`UNIT_OF_AXIS`].
pub const UNIT_OF_KNOB: &str = "[knob]";
/// See [`UNIT_OF_AXIS`]: a jump's size is in the unit named in its `size_unit` column (the
/// quantity's for a step, the quantity's per unit of the axis for a kink).
pub const UNIT_OF_SIZE: &str = "[size_unit]";

/// The unit of `column` in `table`; `None` for a column the contract does not know (the writer
/// refuses it, so that no column goes undocumented).
pub fn unit(table: TableKind, column: &str) -> Option<&'static str> {
    if matches!(
        table,
        TableKind::Points | TableKind::HarmonicPoints | TableKind::RandomPoints
    ) && let Some(key) = system_key(column)
    {
        return system_unit(key);
    }
    // A design axis (a harmonic study's `F0` too).
    if matches!(
        table,
        TableKind::Summary | TableKind::Jumps | TableKind::Probes | TableKind::Capacities
    ) && let Some(key) = axis_key(column)
    {
        return axis_unit(key);
    }
    match table {
        TableKind::Points => points_unit(column),
        TableKind::HarmonicPoints => forced_points_unit(column),
        TableKind::RandomPoints => random_points_unit(column),
        TableKind::Summary => summary_unit(column),
        TableKind::Zones => {
            for suffix in ["_from", "_to"] {
                if let Some(key) = column.strip_suffix(suffix).and_then(axis_key) {
                    return axis_unit(key);
                }
            }
            for prefix in ["best_", "rep_"] {
                if let Some(key) = column.strip_prefix(prefix).and_then(axis_key) {
                    return axis_unit(key);
                }
            }
            zones_unit(column)
        }
        TableKind::Jumps => jumps_unit(column),
        TableKind::Sensitivity => sensitivity_unit(column),
        TableKind::Tradeoff => tradeoff_unit(column),
        TableKind::Attractors | TableKind::Branches => orbits_unit(column),
        TableKind::Bifurcations => match column {
            "curve" | "point" | "kind" | "p_name" | "at_grid" => Some(""),
            "p" => Some(UNIT_OF_P),
            "r" | "period" | "impacts_per_period" => Some("1"),
            "amplitude" => Some("m"),
            _ => None,
        },
        TableKind::Capacities => match column {
            "point" | "case" | "record" | "censored" | "resurrected" => Some(""),
            "runs" => Some("1"),
            "capacity" | "pga" | "sa" => Some("g"),
            _ => None,
        },
        TableKind::Verification => match column {
            "point" | "case" | "supported" | "measured_again" | "round" | "rank_before"
            | "rank_after" | "direct_capped" | "direct_fitted" => Some(""),
            "r" | "estimate_periods" | "direct_periods" | "direct_xi" | "direct_xi_se"
            | "direct_exceedances" | "direct_fit_periods" => Some("1"),
            "estimate"
            | "estimate_lo"
            | "estimate_hi"
            | "direct"
            | "direct_lo"
            | "direct_hi"
            | "largest_seen"
            | "peak_before"
            | "peak_after"
            | "direct_threshold"
            | "direct_sigma"
            | "direct_end_point"
            | "direct_lowest_threshold" => Some("m"),
            _ => None,
        },
        TableKind::Probes => match column {
            "ok" => Some(""),
            "peak_amplitude" => Some("m"),
            "peak_reduction" => Some("1"),
            _ => None,
        },
    }
}

fn points_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "point_id" | "point" | "case" | "ideal" | "noise_seed" | "solver" | "outcome" => "",
        "dm" => "kg",
        "dd" | "atol" | "x1" | "x2" | "xmax" => "m",
        "tol" | "rtol" | "impacts" | "sticks" | "steps" => "1",
        "h" | "t1" | "t2" | "t_stop" => "s",
        "di" => "m/s",
        "energy_impact" | "energy_viscous" => "J",
        _ => return None,
    })
}

fn forced_points_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "point_id" | "point" | "case" | "ideal" | "noise_seed" | "solver" | "outcome"
        | "converged" => "",
        "dm" => "kg",
        "dd" | "amplitude" | "amplitude_linear" => "m",
        "tol" | "r" | "impacts_per_period" | "period" | "attenuation" | "n_trans" | "n_meas"
        | "impacts" | "sticks" | "steps" => "1",
        "F0" => "N",
        "omega" => "rad/s",
        "energy_force" | "energy_viscous" | "energy_impact" => "J",
        "t_stop" => "s",
        "amplitude_worst" | "rest_amplitude" => "m",
        "starts"
        | "attractors"
        | "worst_period"
        | "worst_impacts_per_period"
        | "worst_basin_share"
        | "rest_period"
        | "census_periods" => "1",
        "worst_kind" => "",
        "worst_lyapunov" => "1/period",
        "worst_window_amplitude" | "worst_life_lo" | "worst_life_hi" => "m",
        _ => return None,
    })
}

/// The random and record scenes' points (store/random.rs).
fn random_points_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "point_id"
        | "point"
        | "case"
        | "ideal"
        | "noise_seed"
        | "solver"
        | "outcome"
        | "capacity_censored"
        | "capacity_resurrected" => "",
        "dm" => "kg",
        "dd" | "amplitude" | "rms_x" => "m",
        "tol" | "scale" | "zeta_g" | "zeta_f" | "impacts" | "sticks" | "samples" | "steps"
        | "capacity_runs" => "1",
        "im" | "pga" | "sa" | "capacity" => "g",
        "S0" => S0_UNIT,
        "omega_g" | "omega_f" => "rad/s",
        "t_peak" | "first_passage_time" | "t_stop" => "s",
        "rms_acc" => "m/s^2",
        "energy_impact" => "J",
        _ => return None,
    })
}

/// The attractors table (the sweep's parts, store/attractors.rs) and the branches table of a
/// harmonic study (reduce/harmonic/steady.rs).
fn orbits_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "point_id" | "point" | "case" | "ideal" | "branch" | "attractor" | "kind" | "stable"
        | "stability" | "label" | "located" | "end" | "grazing_outcome" | "origin"
        | "life_capped" => "",
        "r" | "period" | "impacts_per_period" | "basin_share" | "starts" | "multiplier_max"
        | "tail_shape" | "exceedances" | "measured_periods" => "1",
        "mu1_re" | "mu1_im" | "mu2_re" | "mu2_im" | "mu3_re" | "mu3_im" | "mu4_re" | "mu4_im" => {
            "1"
        }
        "min_impact_speed" => "m/s",
        "lyapunov" | "lyapunov_se" => "1/period",
        "lyapunov_per_s" => "1/s",
        "omega" => "rad/s",
        "F0" => "N",
        "amplitude" | "window_amplitude" | "life_amplitude" | "life_lo" | "life_hi"
        | "tail_end" | "section_x" | "section_z" => "m",
        "section_v" | "section_w" => "m/s",
        "section_units" => "m, m/s",
        _ => return None,
    })
}

fn summary_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "point" | "all_ok" | "failed" | "rank" | "pareto" | "robust" | "class" | "zone" => "",
        "n" | "n_cases" | "n_ok" => "1",
        "xmax_mean" | "xmax_sd" | "xmax_min" | "xmax_q1" | "xmax_median" | "xmax_q3"
        | "xmax_max" | "xmax_ideal" => "m",
        "stress_mean" | "stress_sd" => "Pa",
        "stress_mu_ln" | "strength_mu_ln" => "ln(Pa)",
        "stress_sigma_ln" | "strength_sigma_ln" => "1",
        "reliability_index" | "reliability" | "reliability_lo" | "reliability_hi" | "cn"
        | "safety_factor" | "ad_stat" | "ad_p" => "1",
        "di" | "di_ideal" | "di_sd" => "m/s",
        "perfectibility" => "%",
        // A harmonic study (reduce/harmonic/design.rs): the peak amplitude over the band is the
        // response, the peak reduction the damping quantity; the band of the ideal case.
        "peak_amplitude_mean"
        | "peak_amplitude_sd"
        | "peak_amplitude_min"
        | "peak_amplitude_q1"
        | "peak_amplitude_median"
        | "peak_amplitude_q3"
        | "peak_amplitude_max"
        | "peak_amplitude_ideal"
        | "peak_from_rest"
        | "linear_peak"
        | "peak_window_amplitude"
        | "peak_life_lo"
        | "peak_life_hi" => "m",
        "peak_lyapunov" => "1/period",
        "design_life" => "s",
        "peak_kind" => "",
        "peak_reduction"
        | "peak_reduction_ideal"
        | "peak_reduction_sd"
        | "peak_r"
        | "linear_peak_r"
        | "help_r_from"
        | "help_r_to"
        | "help_share"
        | "periodic_share"
        | "peak_attractor_period"
        | "peak_impacts_per_period"
        | "peak_basin_share" => "1",
        "peak_periodic" => "",
        // A random or record study (reduce/random/): the amplitude per realization is the
        // response, the share of realizations within the threshold the damping quantity.
        "amplitude_mean" | "amplitude_sd" | "amplitude_min" | "amplitude_q1"
        | "amplitude_median" | "amplitude_q3" | "amplitude_max" | "amplitude_ideal"
        | "rms_x_mean" | "threshold" => "m",
        "p_s" | "p_s_ideal" | "p_s_sd" | "p_f" | "p_f_lo" | "p_f_hi" | "beta" | "n_exceed"
        | "p_f_cov" | "p_f_cov_upper" | "subset_runs" | "subset_repeats" | "fragility_beta"
        | "fragility_beta_lo" | "fragility_beta_hi" | "capacity_rank" => "1",
        "intensity" | "fragility_outcome" | "p_f_method" => "",
        "theta" | "theta_lo" | "theta_hi" | "deagg_im_10" | "deagg_im_50" | "deagg_im_90" => "g",
        "beta_im"
        | "beta_im_lo"
        | "beta_im_hi"
        | "ks"
        | "ks_critical"
        | "capacities"
        | "capacities_censored"
        | "capacities_resurrected"
        | "ida_runs_mean"
        | "p_f_years"
        | "p_f_years_lo"
        | "p_f_years_hi"
        | "risk_rank" => "1",
        "fit_ok" | "lambda_f_curve" => "",
        "lambda_f"
        | "lambda_f_lo"
        | "lambda_f_hi"
        | "lambda_f_capacities"
        | "lambda_f_capacities_lo"
        | "lambda_f_capacities_hi"
        | "lambda_f_empirical"
        | "lambda_f_lognormal"
        | "lambda_f_cornell"
        | "lambda_f_stripes"
        | "lambda_f_stripes_lo"
        | "lambda_f_stripes_hi" => "1/year",
        "intensity_design" | "fragility_theta" | "fragility_theta_lo" | "fragility_theta_hi" => {
            UNIT_OF_INTENSITY
        }
        _ => return None,
    })
}

fn zones_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "zone" | "label" | "declared" | "best_point" | "rep_point" => "",
        "n_points" | "n_merged" | "mean_reliability" => "1",
        "mean_di" => "m/s",
        "mean_peak_reduction" | "mean_p_s" => "1",
        "perfectibility" => "%",
        _ => return None,
    })
}

fn jumps_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "axis" | "kind" | "quantity" | "size_unit" => "",
        "location" | "location_tol" | "from" | "to" => UNIT_OF_AXIS,
        "size" => UNIT_OF_SIZE,
        _ => return None,
    })
}

fn sensitivity_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "quantity" | "axis" => "",
        "first_order" | "total" | "n_points" => "1",
        _ => return None,
    })
}

fn tradeoff_unit(column: &str) -> Option<&'static str> {
    Some(match column {
        "solver" | "setting" | "knob" | "cheapest" => "",
        "value" => UNIT_OF_KNOB,
        "atol" => "m",
        "time_per_run" | "cpu_per_run" => "s",
        "reps" | "steps_per_run" | "changed_outcome" | "changed_impacts" | "unfinished"
        | "runs" => "1",
        c if c.contains("_err_") => "1",
        _ => return None,
    })
}

/// Names equal without case, if any: `[("M", "m")]`. Empty for a valid table.
pub fn case_clashes<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<(&'a str, &'a str)> {
    let names: Vec<&str> = names.into_iter().collect();
    let mut out = Vec::new();
    for (i, a) in names.iter().enumerate() {
        for b in &names[i + 1..] {
            if a.eq_ignore_ascii_case(b) {
                out.push((*a, *b));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masses_get_long_names_and_other_keys_keep_theirs() {
        assert_eq!(column_name("M"), "mass_main");
        assert_eq!(column_name("m"), "mass_inner");
        for key in ["K", "C", "d", "e", "x0", "v0", "y0", "w0", "dm", "xmax"] {
            assert_eq!(column_name(key), key);
        }
        for key in crate::model::SYSTEM_KEYS {
            assert_eq!(system_key(column_name(key)), Some(key));
            assert!(system_unit(key).is_some(), "{key}");
        }
        assert_eq!(system_key("M"), None);
        assert_eq!(system_key("xmax"), None);
    }

    #[test]
    fn system_columns_are_unique_without_case() {
        let names: Vec<&str> = crate::model::SYSTEM_KEYS
            .iter()
            .map(|k| column_name(k))
            .collect();
        assert!(case_clashes(names).is_empty());
        assert_eq!(case_clashes(["M", "m", "e"]), vec![("M", "m")]);
    }

    #[test]
    fn axis_columns_take_the_unit_of_their_key() {
        assert_eq!(unit(TableKind::Summary, "mass_inner"), Some("kg"));
        assert_eq!(unit(TableKind::Zones, "mass_inner_from"), Some("kg"));
        assert_eq!(unit(TableKind::Zones, "e_to"), Some("1"));
        assert_eq!(unit(TableKind::Zones, "m_to"), None);
        assert_eq!(unit(TableKind::Points, "m"), None);
        assert_eq!(unit(TableKind::Tradeoff, "di_err_median"), Some("1"));
    }
}
