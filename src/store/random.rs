//! The random and record scenes' points table (`random_points`, docs/schema.md): one row per
//! realization ([`RealizationRecord`]), in the part files of [`super::points`] after the
//! identity, system and solver columns every points table starts with.
//!
//! After `tol`: the load's sweepable keys at the design point, `S0` ((m/s^2)^2 or N^2 per
//! rad/s), `omega_g` (rad/s), `zeta_g`, `omega_f` (rad/s), `zeta_f`, `scale` (the factor on the
//! motion: a record's, or under an intensity measure the stripe's `im / own`), `im` (g, the
//! stripe) (null where the scene's load has no such key); `pga`, `sa` (g, the motion's own at
//! scale 1, null without an intensity measure); `capacity` (g), `capacity_censored`,
//! `capacity_resurrected`, `capacity_runs` (the motion's incremental dynamic analysis, null but
//! at the design stripe of a study with an intensity measure and a threshold); `outcome`; `amplitude` (m), `t_peak` (s), `rms_x` (m),
//! `rms_acc` (m/s^2), `first_passage_time` (s, null when `|x|` never passes the threshold or the
//! study sets none); `impacts`, `sticks`; `energy_impact` (J); `samples`, `t_stop` (s), `steps`.
//! The observables over the duration are NaN unless the outcome is `ok`
//! ([`crate::sim::random::RandomRecord`]).

use std::sync::Arc;

use anyhow::Result;
use arrow_array::{Array, ArrayRef, BooleanArray, Float64Array, RecordBatch, UInt64Array};
use arrow_schema::DataType;

use super::points::{
    RunRow, StoredRecord, column, dict_type, f64col, outcome_col, outcomes, u64col,
};
use super::schema::TableKind;
use crate::sim::random::{Capacity, OwnIntensity, RandomRecord, RandomScene, RealizationRecord};
use crate::sim::{Outcome, SolverSettings};

/// The `f64` observables after `outcome`, in schema order (then `first_passage_time`).
const OBSERVABLES: [&str; 4] = ["amplitude", "t_peak", "rms_x", "rms_acc"];

impl StoredRecord for RealizationRecord {
    const TABLE: TableKind = TableKind::RandomPoints;

    fn outcome(&self) -> Outcome {
        self.record.outcome
    }

    fn fields() -> Vec<(&'static str, DataType, bool)> {
        let f = |name| (name, DataType::Float64, false);
        let u = |name| (name, DataType::UInt64, false);
        let mut cols: Vec<(&str, DataType, bool)> = RandomScene::AXES
            .iter()
            .map(|&k| (k, DataType::Float64, true))
            .collect();
        cols.extend(["pga", "sa", "capacity"].map(|k| (k, DataType::Float64, true)));
        cols.push(("capacity_censored", DataType::Boolean, true));
        cols.push(("capacity_resurrected", DataType::Boolean, true));
        cols.push(("capacity_runs", DataType::UInt64, true));
        cols.push(("outcome", dict_type(), false));
        cols.extend(OBSERVABLES.map(f));
        cols.push(("first_passage_time", DataType::Float64, true));
        cols.extend(["impacts", "sticks"].map(u));
        cols.push(f("energy_impact"));
        cols.push(u("samples"));
        cols.push(f("t_stop"));
        cols.push(u("steps"));
        cols
    }

    fn arrays(rows: &[RunRow<Self>], _settings: &SolverSettings) -> Result<Vec<ArrayRef>> {
        let opt = |g: &dyn Fn(&RunRow<Self>) -> Option<f64>| -> ArrayRef {
            Arc::new(Float64Array::from_iter(rows.iter().map(g)))
        };
        let mut cols: Vec<ArrayRef> = (0..RandomScene::AXES.len())
            .map(|i| opt(&|r| r.record.load[i]))
            .collect();
        cols.push(opt(&|r| r.record.own.map(|o| o.pga)));
        cols.push(opt(&|r| r.record.own.map(|o| o.sa)));
        cols.push(opt(&|r| r.record.capacity.map(|c| c.capacity)));
        let flag = |g: &dyn Fn(&Capacity) -> bool| -> ArrayRef {
            Arc::new(BooleanArray::from_iter(
                rows.iter().map(|r| r.record.capacity.as_ref().map(g)),
            ))
        };
        cols.push(flag(&|c| c.censored));
        cols.push(flag(&|c| c.resurrected));
        cols.push(Arc::new(UInt64Array::from_iter(
            rows.iter()
                .map(|r| r.record.capacity.map(|c| u64::from(c.runs))),
        )));
        cols.push(outcome_col(rows)?);
        cols.push(f64col(rows, |r| r.record.record.amplitude));
        cols.push(f64col(rows, |r| r.record.record.t_peak));
        cols.push(f64col(rows, |r| r.record.record.rms_x));
        cols.push(f64col(rows, |r| r.record.record.rms_acc));
        cols.push(opt(&|r| r.record.record.first_passage_time));
        cols.push(u64col(rows, |r| r.record.record.impacts));
        cols.push(u64col(rows, |r| r.record.record.sticks));
        cols.push(f64col(rows, |r| r.record.record.energy_impact));
        cols.push(u64col(rows, |r| r.record.record.samples));
        cols.push(f64col(rows, |r| r.record.record.t_stop));
        cols.push(u64col(rows, |r| r.record.record.steps));
        Ok(cols)
    }

    fn read(batch: &RecordBatch) -> Result<Vec<Self>> {
        let u64s = |n| column::<UInt64Array>(batch, n);
        let f64s = |n| column::<Float64Array>(batch, n);
        let outcome = outcomes(batch)?;
        let load: Vec<&Float64Array> = RandomScene::AXES
            .iter()
            .map(|k| f64s(k))
            .collect::<Result<_>>()?;
        let obs: Vec<&Float64Array> = OBSERVABLES.iter().map(|k| f64s(k)).collect::<Result<_>>()?;
        let passage = f64s("first_passage_time")?;
        let (pga, sa, capacity) = (f64s("pga")?, f64s("sa")?, f64s("capacity")?);
        let censored = column::<BooleanArray>(batch, "capacity_censored")?;
        let resurrected = column::<BooleanArray>(batch, "capacity_resurrected")?;
        let runs = u64s("capacity_runs")?;
        let (impacts, sticks, samples, steps) = (
            u64s("impacts")?,
            u64s("sticks")?,
            u64s("samples")?,
            u64s("steps")?,
        );
        let (energy, t_stop) = (f64s("energy_impact")?, f64s("t_stop")?);
        let nullable = |c: &Float64Array, i: usize| c.is_valid(i).then(|| c.value(i));
        Ok(outcome
            .into_iter()
            .enumerate()
            .map(|(i, outcome)| RealizationRecord {
                load: std::array::from_fn(|j| nullable(load[j], i)),
                own: pga.is_valid(i).then(|| OwnIntensity {
                    pga: pga.value(i),
                    sa: sa.value(i),
                }),
                capacity: capacity.is_valid(i).then(|| Capacity {
                    capacity: capacity.value(i),
                    censored: censored.value(i),
                    resurrected: resurrected.value(i),
                    runs: runs.value(i) as u32,
                }),
                record: RandomRecord {
                    outcome,
                    amplitude: obs[0].value(i),
                    t_peak: obs[1].value(i),
                    rms_x: obs[2].value(i),
                    rms_acc: obs[3].value(i),
                    first_passage_time: nullable(passage, i),
                    impacts: impacts.value(i),
                    sticks: sticks.value(i),
                    energy_impact: energy.value(i),
                    samples: samples.value(i),
                    t_stop: t_stop.value(i),
                    steps: steps.value(i),
                },
            })
            .collect())
    }
}
