//! What every record's JSON carries besides its scene's fields (`simulate --json`, the Python
//! binding): the system and the solver settings.

use crate::model::{SYSTEM_KEYS, System, UNIT_KEYS};
use crate::sim::SolverSettings;

/// `system` (its keys, SI units, NaN as null) and `solver` into a record's JSON `map`.
pub fn insert_system(
    map: &mut serde_json::Map<String, serde_json::Value>,
    sys: &System,
    solver: &SolverSettings,
) {
    let num = |v: f64| serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, Into::into);
    let mut system = serde_json::Map::new();
    for k in SYSTEM_KEYS {
        system.insert(k.into(), num(sys.get(k).unwrap_or(f64::NAN)));
    }
    // Several units only when there are (one unit's JSON is as it always was).
    if sys.unit_count() > 1 {
        for k in UNIT_KEYS {
            system.insert(k.into(), num(sys.get(k).unwrap_or(f64::NAN)));
        }
    }
    // A per-unit table (model.md §14) as the list of its units.
    if let Some(table) = sys.table {
        system.insert(
            "unit".into(),
            serde_json::to_value(table).unwrap_or_default(),
        );
    }
    map.insert("system".into(), system.into());
    map.insert(
        "solver".into(),
        serde_json::to_value(solver).unwrap_or_default(),
    );
}
