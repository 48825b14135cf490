//! A batch of realizations at hand (the Python binding's `simulate_batch` of the random and
//! record scenes): one run per row over a [`RandomSetup`], row `i` taking `names[j]` =
//! `columns[j][i]`. Each row is the realization its keys name of the one-point study of the
//! setup's keys and the row's values, as the sweep of that study stores it (the same bits as
//! its row in `random_points`), with `point_id = point = i` and `case` its realization.
//!
//! The columns: the system's keys, the load's sweepable keys the setup's load has (`S0` and
//! the filter's `omega_g zeta_g omega_f zeta_f` of a random load, a record's `scale`, a stripe
//! `im` in g under an intensity measure: every row is then its own design stripe, with its
//! capacity where the setup has a threshold), and `realization` (whole numbers; without it,
//! every row runs the setup's `realization`, 0 by default: the same load for every design).
//! `M` and `K` may not vary by row where the setup derives a value from them (a
//! `yield_coefficient` limit, or Sa's period `T` left to default), as a study sweeping them
//! refuses the same.
//!
//! A row may run on its load's standard normals handed in, in place of its realization's
//! stream, and may skip its capacity search ([`RandomBatch::run`]): a reliability library's
//! sample of normals at a stripe, one row a sample.

use super::realization::{MAX_REALIZATION, RandomSetup};
use crate::model::SYSTEM_KEYS;
use crate::plan::Plan;
use crate::sim::Harmonic;
use crate::sim::random::{Measure, RandomRun, RandomScene, RealizationRecord};
use crate::store::RunRow;
use crate::study::{Axis, Study};

/// A checked batch: the setup and its input columns.
pub struct RandomBatch<'a> {
    setup: &'a RandomSetup,
    names: &'a [String],
    cols: &'a [Vec<f64>],
}

/// The input columns a setup takes: the system's keys, its load's sweepable keys, `realization`.
pub fn column_keys(setup: &RandomSetup) -> Vec<&'static str> {
    let scene = setup.scene();
    let mut keys: Vec<&str> = SYSTEM_KEYS.to_vec();
    keys.extend(
        RandomScene::AXES
            .into_iter()
            .filter(|&k| scene.get(k).is_some() || (k == "im" && scene.intensity.is_some())),
    );
    keys.push("realization");
    keys
}

impl<'a> RandomBatch<'a> {
    /// The batch of `names[j]` = `cols[j][i]` for rows `i` in `0..n`; the error names the
    /// column and what is allowed.
    pub fn new(
        setup: &'a RandomSetup,
        names: &'a [String],
        cols: &'a [Vec<f64>],
        n: usize,
    ) -> Result<Self, String> {
        let keys = column_keys(setup);
        for (j, name) in names.iter().enumerate() {
            if !keys.contains(&name.as_str()) {
                let why = if RandomScene::AXES.contains(&name.as_str()) {
                    "not a key of this setup's load"
                } else if Harmonic::KEYS.contains(&name.as_str()) {
                    "a key of the harmonic scene"
                } else {
                    "unknown key"
                };
                return Err(format!(
                    "input column '{name}': {why}; allowed: {}",
                    keys.join(" ")
                ));
            }
            if names[..j].contains(name) {
                return Err(format!("input column '{name}': given twice"));
            }
            if cols[j].len() != n {
                return Err(format!(
                    "input column '{name}': {} values for {n} rows",
                    cols[j].len()
                ));
            }
        }
        let scene = setup.scene();
        let sa_default = scene
            .intensity
            .is_some_and(|s| s.measure == Measure::Sa && !setup.has("T"));
        for key in ["M", "K"] {
            if !names.iter().any(|n| n == key) {
                continue;
            }
            if setup.has("yield_coefficient") {
                return Err(format!(
                    "input column '{key}': first yield at C_y M g / K needs M and K fixed; give \
                     threshold in m instead of yield_coefficient"
                ));
            }
            if sa_default {
                return Err(format!(
                    "input column '{key}': Sa's period defaults to the structure's 2 pi sqrt(M / \
                     K), fixed by the setup's M and K; give T (s)"
                ));
            }
        }
        Ok(RandomBatch { setup, names, cols })
    }

    /// Row `i`: its one-point study and realization, checked; the error names the row, the
    /// key, the value and what is allowed.
    pub fn row(&self, i: usize) -> Result<(Study, u32), String> {
        let mut study = self.setup.study.clone();
        let mut case = self.setup.realization;
        let record = !self.setup.scene().draws_normals();
        for (name, col) in self.names.iter().zip(self.cols) {
            let v = col[i];
            match name.as_str() {
                "realization" => {
                    let max = if record { 0 } else { MAX_REALIZATION };
                    if !(v.fract() == 0.0 && v >= 0.0 && v <= f64::from(max)) {
                        return Err(format!(
                            "row {i}: realization = {}: must be a whole number in [0, {max}]{}",
                            crate::model::fmt_value(v),
                            if record {
                                " (a record is one load)"
                            } else {
                                ""
                            }
                        ));
                    }
                    case = v as u32;
                }
                "im" => {
                    study.axes = vec![Axis {
                        key: "im".into(),
                        values: vec![v],
                    }];
                }
                key => {
                    if !study.system.set(key, v) {
                        study.scene.set(key, v);
                    }
                }
            }
        }
        study.realizations = study.realizations.max(u64::from(case) + 1);
        let (system, scene) = Plan::new(&study).point(0);
        let wrap = |e: crate::model::RangeError| format!("row {i}: {e}");
        system.validate().map_err(wrap)?;
        if let Some(r) = scene.random() {
            r.validate().map_err(wrap)?;
        }
        Ok((study, case))
    }

    /// Runs row `i` of the checked `study` and realization `case` ([`RandomBatch::row`]), its
    /// capacity searched where `capacity` (and the setup has a threshold and an intensity
    /// measure; with `false` the capacity columns are null and nothing else changes).
    ///
    /// With `normals` (the load's standard normals, [`RandomRun::n_normals`] of them, finite)
    /// the row runs on them in place of the realization's stream: its `case` is 0 and its
    /// `noise_seed` null (no stream seeds its load). On the normals realization `c`'s stream
    /// draws, the row of `c` bit for bit but for those two.
    pub fn run(
        i: usize,
        study: &Study,
        case: u32,
        normals: Option<&[f64]>,
        capacity: bool,
    ) -> RunRow<RealizationRecord> {
        let plan = Plan::new(study);
        let mut run = plan.run(0, if normals.is_some() { 0 } else { case });
        run.point = i as u64;
        run.point_id = i as u64;
        if normals.is_some() {
            run.spec.noise_seed = None;
        }
        crate::sweep::random::realization_row(&plan, &run, normals, capacity)
    }

    /// The standard normals a run of this batch's load draws ([`RandomRun::n_normals`]; 0 for
    /// a record): every row's, as its columns change no key they depend on.
    pub fn n_normals(&self) -> usize {
        let study = &self.setup.study;
        RandomRun::new(&study.system, &study.solver, &self.setup.scene()).n_normals()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(items: &[&str]) -> RandomSetup {
        let sets: Vec<String> = items.iter().map(|s| s.to_string()).collect();
        RandomSetup::from_sets("random", &sets).unwrap()
    }

    #[test]
    fn a_row_is_the_one_point_studys_realization() {
        let base = [
            "scene=random",
            "spectrum=kanai-tajimi",
            "S0=0.01",
            "duration=1",
        ];
        let s = setup(&base);
        let names = vec!["m".to_string(), "realization".to_string()];
        let cols = vec![vec![0.02], vec![3.0]];
        let batch = RandomBatch::new(&s, &names, &cols, 1).unwrap();
        let (study, case) = batch.row(0).unwrap();
        let row = RandomBatch::run(0, &study, case, None, true);
        let mut sets = base.to_vec();
        sets.extend(["m=0.02", "realization=3"]);
        let one = setup(&sets);
        let (want, _) = one.run(None).unwrap();
        assert_eq!(row.record, want);
        assert_eq!((row.point_id, row.point, row.case), (0, 0, 3));
        // The normals realization 3's stream draws, handed in: the same record, with no stream
        // to name (case 0, noise_seed null).
        use crate::sim::random::{Normals, RealizationStream};
        let mut stream = RealizationStream::new(study.seed, 0, 3);
        let u: Vec<f64> = (0..batch.n_normals())
            .map(|_| stream.next_normal())
            .collect();
        let given = RandomBatch::run(0, &study, case, Some(&u), true);
        assert_eq!(given.record, want);
        assert_eq!((given.case, given.noise_seed), (0, None));
        assert_eq!(row.noise_seed, Some(3));
    }

    #[test]
    fn the_capacity_is_searched_only_where_asked() {
        let s = setup(&[
            "scene=random",
            "spectrum=white",
            "duration=1",
            "threshold=0.005",
            "intensity=pga",
            "im=0.5",
        ]);
        let batch = RandomBatch::new(&s, &[], &[], 1).unwrap();
        let (study, case) = batch.row(0).unwrap();
        let with = RandomBatch::run(0, &study, case, None, true);
        let without = RandomBatch::run(0, &study, case, None, false);
        assert!(with.record.capacity.is_some() && without.record.capacity.is_none());
        assert_eq!(with.record.record, without.record.record);
        assert_eq!(with.record.own, without.record.own);
    }

    #[test]
    fn bad_columns_and_rows_name_what_is_allowed() {
        let s = setup(&["scene=random", "spectrum=white", "S0=0.01", "duration=1"]);
        let err = |names: &[&str], cols: Vec<Vec<f64>>| {
            let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
            match RandomBatch::new(&s, &names, &cols, 1) {
                Err(e) => e,
                Ok(b) => b.row(0).unwrap_err(),
            }
        };
        assert!(
            err(&["omega_g"], vec![vec![3.0]])
                .starts_with("input column 'omega_g': not a key of this setup's load; allowed:")
        );
        assert!(err(&["F0"], vec![vec![3.0]]).contains("a key of the harmonic scene"));
        assert_eq!(
            err(&["realization"], vec![vec![1.5]]),
            "row 0: realization = 1.5: must be a whole number in [0, 9999999]"
        );
        assert!(err(&["S0"], vec![vec![-1.0]]).starts_with("row 0: S0 = -1: "));
        assert!(err(&["e"], vec![vec![2.0]]).starts_with("row 0: e = 2: "));
    }
}
