//! The physical system of `docs/model.md` §1: a main mass `M` on a spring `K` and a
//! viscous damper `C`, with a cavity of total clearance `d` in which a loose inner mass `m`
//! moves freely. All quantities are SI.
//!
//! [`System`] is the validated form: every constructor path goes through [`System::validate`],
//! so later stages (the simulator above all) never see an unvalidated value.

use std::sync::Mutex;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// One impact damper and its initial state. SI units throughout.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct System {
    /// Main mass `M` (kg), `> 0`. Table I: 0.1.
    pub M: f64,
    /// Inner (impact) mass `m` (kg), `>= 0`; `0` is the system without a damper. Table I: 0.02.
    pub m: f64,
    /// Spring stiffness `K` (N/m), `> 0`. Table I: 400.
    pub K: f64,
    /// Viscous damping `C` (N s/m), `>= 0`. Table I: 0.1.
    pub C: f64,
    /// Total clearance of the cavity `d` (m), `> 0`; the walls sit at `y - x = ±d/2`. Table I: 0.01.
    pub d: f64,
    /// Coefficient of restitution `e`, in `[0, 1]`. Table I sweeps it; default 0.9.
    pub e: f64,
    /// Initial displacement of the main mass `x0` (m). Table I: 0.
    pub x0: f64,
    /// Initial velocity of the main mass `v0` (m/s). Table I: 2.
    pub v0: f64,
    /// Initial displacement of the inner mass `y0` (m); `|y0 - x0| <= d/2`. Table I: 0.
    pub y0: f64,
    /// Initial velocity of the inner mass `w0` (m/s). Table I: 0.
    pub w0: f64,
    /// Number of damper units `units` (model.md §14), a whole number in `[1, 64]`; default 1,
    /// the paper's single unit. `N` units share the inner mass `m` equally (`m / N` each), all
    /// with restitution `e`, the initial state `(y0, w0)` and the clearances of
    /// [`System::unit_list`]; each sits in its own cavity and they meet only through the main
    /// mass. A float so that it sweeps like every other key.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub units: f64,
    /// Spread of the units' clearances `d_spread`, in `[0, 1)`; default 0 (all equal to `d`).
    /// With `N > 1` units, unit `i` has `d_i = d (1 + d_spread (2 i / (N - 1) - 1))`: evenly
    /// spaced over `d (1 ± d_spread)`, so that the units engage at different amplitudes.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub d_spread: f64,
    /// Per-unit table (`[[system.unit]]`, model.md §14): each unit's own `m`, `d`, `e` and
    /// initial state, or `None` for the `units` / `d_spread` rule. With a table, `units` is its
    /// length (2 to 64: a table of one unit is the plain system) and `d_spread` 0, and `m`, `d`,
    /// `e` are derived from it ([`UnitTable::derived`]): `m` the total inner mass, `d` the
    /// largest clearance, `e` the mass-weighted mean restitution. Serialized as `unit`, a list
    /// of units, only when present.
    #[serde(default, rename = "unit", skip_serializing_if = "Option::is_none")]
    pub table: Option<UnitTable>,
}

fn one() -> f64 {
    1.0
}

fn is_one(v: &f64) -> bool {
    *v == 1.0
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// One damper unit of a [`System`] (model.md §14): a loose mass in its own cavity.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Unit {
    /// Its mass (kg), `>= 0`.
    pub m: f64,
    /// Its cavity's total clearance (m), `> 0`; walls at `y - x = ±d/2`.
    pub d: f64,
    /// Its coefficient of restitution, in `[0, 1]`.
    pub e: f64,
    /// Its initial displacement (m) and velocity (m/s).
    pub y0: f64,
    pub w0: f64,
}

/// A per-unit table of a [`System`] (`[[system.unit]]`, model.md §14), interned: a shared
/// `&'static [Unit]`.
///
/// Why not `Option<Arc<[Unit]>>`: [`System`] is `Copy` and copied by value all over the crate
/// (every design point's system is the study's with its axes set, every run and stored row
/// holds one, the simulator's scenes keep their own copy). An `Arc` would drop `Copy` for
/// `Clone`, touch each of those places and put a reference count on every copy of every
/// system, also the systems of one unit that never have a table. A table is fixed for a whole
/// study (no key of it is swept), so the few distinct tables a process ever sees are interned
/// once, deduplicated bit for bit, and live for the process: `System` stays `Copy`, 16 bytes
/// larger (a fat pointer; `None` is a null pointer), and the simulator reads the table only
/// through [`System::unit_list`], once per run. The memory held is the distinct tables'
/// (at most 64 units of 40 bytes each), however many systems, rows or parses refer to them.
#[derive(Clone, Copy, PartialEq)]
pub struct UnitTable(&'static [Unit]);

/// The distinct tables of the process ([`UnitTable`]).
static TABLES: Mutex<Vec<&'static [Unit]>> = Mutex::new(Vec::new());

impl UnitTable {
    /// The interned table of `units`: the same one for every call with the same bits.
    pub fn new(units: &[Unit]) -> UnitTable {
        let bits = |u: &Unit| [u.m, u.d, u.e, u.y0, u.w0].map(f64::to_bits);
        let same = |t: &&'static [Unit]| {
            t.len() == units.len() && t.iter().zip(units).all(|(a, b)| bits(a) == bits(b))
        };
        let mut tables = TABLES.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(t) = tables.iter().find(|t| same(t)) {
            return UnitTable(t);
        }
        let t: &'static [Unit] = Box::leak(units.to_vec().into_boxed_slice());
        tables.push(t);
        UnitTable(t)
    }

    /// The units, in table order.
    pub fn units(&self) -> &'static [Unit] {
        self.0
    }

    /// The system keys a table decides: `m` the total inner mass, `d` the largest clearance,
    /// `e` the mass-weighted mean restitution (the plain mean when every unit is massless).
    pub fn derived(&self) -> (f64, f64, f64) {
        let m: f64 = self.0.iter().map(|u| u.m).sum();
        let d = self.0.iter().map(|u| u.d).fold(0.0, f64::max);
        let e = if m > 0.0 {
            self.0.iter().map(|u| u.m * u.e).sum::<f64>() / m
        } else {
            self.0.iter().map(|u| u.e).sum::<f64>() / self.0.len().max(1) as f64
        };
        (m, d, e)
    }
}

impl std::fmt::Debug for UnitTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.0).finish()
    }
}

impl Serialize for UnitTable {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> Deserialize<'de> for UnitTable {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let units = Vec::<Unit>::deserialize(d)?;
        Ok(UnitTable::new(&units))
    }
}

/// The names of the system keys, in the order used by tables and Parquet columns.
pub const SYSTEM_KEYS: [&str; 10] = ["M", "m", "K", "C", "d", "e", "x0", "v0", "y0", "w0"];

/// The keys that split the inner mass over several units (model.md §14), beside
/// [`SYSTEM_KEYS`]: a study that leaves them at their defaults (one unit) has exactly the
/// columns and records of a study written before they existed.
pub const UNIT_KEYS: [&str; 2] = ["units", "d_spread"];

/// The most units a system may carry.
pub const MAX_UNITS: f64 = 64.0;

/// A value outside its allowed range: names the key, the value and what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {allowed}")]
pub struct RangeError {
    pub key: String,
    pub value: String,
    pub allowed: String,
}

impl RangeError {
    pub fn new(key: &str, value: f64, allowed: impl Into<String>) -> Self {
        RangeError {
            key: key.to_string(),
            value: fmt_value(value),
            allowed: allowed.into(),
        }
    }
}

/// Formats a number the way a user would write it: shortest round-trip digits, in exponent
/// form when very small or very large (`5e-10`, not `0.0000000005`).
pub fn fmt_value(v: f64) -> String {
    if v != 0.0 && v.is_finite() && (v.abs() < 1e-3 || v.abs() >= 1e7) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

impl Default for System {
    /// The paper's Table I system with `e = 0.9` (the case of its Table II).
    fn default() -> Self {
        System::TABLE_I
    }
}

impl System {
    /// Table I of the paper, with `e = 0.9`.
    pub const TABLE_I: System = System {
        M: 0.1,
        m: 0.02,
        K: 400.0,
        C: 0.1,
        d: 0.01,
        e: 0.9,
        x0: 0.0,
        v0: 2.0,
        y0: 0.0,
        w0: 0.0,
        units: 1.0,
        d_spread: 0.0,
        table: None,
    };

    /// This system with the per-unit table `units` (model.md §14): `units` its length,
    /// `d_spread` 0 and `m`, `d`, `e` derived from it ([`UnitTable::derived`]). A table of one
    /// unit is the plain system: its `m`, `d`, `e`, `y0`, `w0` are the system's, and no table is
    /// kept. Not validated: call [`System::validate`] afterwards.
    pub fn with_units(mut self, units: &[Unit]) -> System {
        if let [u] = units {
            (self.m, self.d, self.e, self.y0, self.w0) = (u.m, u.d, u.e, u.y0, u.w0);
            (self.units, self.d_spread, self.table) = (1.0, 0.0, None);
            return self;
        }
        let table = UnitTable::new(units);
        (self.m, self.d, self.e) = table.derived();
        self.units = units.len() as f64;
        self.d_spread = 0.0;
        self.table = Some(table);
        self
    }

    /// Reads a key by its model.md name.
    pub fn get(&self, key: &str) -> Option<f64> {
        Some(match key {
            "M" => self.M,
            "m" => self.m,
            "K" => self.K,
            "C" => self.C,
            "d" => self.d,
            "e" => self.e,
            "x0" => self.x0,
            "v0" => self.v0,
            "y0" => self.y0,
            "w0" => self.w0,
            "units" => self.units,
            "d_spread" => self.d_spread,
            _ => return None,
        })
    }

    /// Sets a key by its model.md name; `false` when the key is not a system key.
    /// The result is not validated: call [`System::validate`] afterwards.
    pub fn set(&mut self, key: &str, value: f64) -> bool {
        let slot = match key {
            "M" => &mut self.M,
            "m" => &mut self.m,
            "K" => &mut self.K,
            "C" => &mut self.C,
            "d" => &mut self.d,
            "e" => &mut self.e,
            "x0" => &mut self.x0,
            "v0" => &mut self.v0,
            "y0" => &mut self.y0,
            "w0" => &mut self.w0,
            "units" => &mut self.units,
            "d_spread" => &mut self.d_spread,
            _ => return false,
        };
        *slot = value;
        true
    }

    /// The unit of a key (SI), `–` for the dimensionless `e` and for unknown keys.
    pub fn unit(key: &str) -> &'static str {
        match key {
            "M" | "m" => "kg",
            "K" => "N/m",
            "C" => "N s/m",
            "d" | "x0" | "y0" => "m",
            "v0" | "w0" => "m/s",
            _ => "–",
        }
    }

    /// The allowed range of one key, as a sentence (used in error messages and `--help`).
    pub fn allowed(key: &str) -> &'static str {
        match key {
            "M" => "the main mass must be a finite number > 0 (kg)",
            "m" => "the inner mass must be a finite number >= 0 (kg; 0 means no damper)",
            "K" => "the stiffness must be a finite number > 0 (N/m)",
            "C" => "the damping must be a finite number >= 0 (N s/m)",
            "d" => "the clearance must be a finite number > 0 (m)",
            "e" => "the coefficient of restitution must be in [0, 1]",
            "x0" | "v0" | "y0" | "w0" => "the initial state must be finite (SI units)",
            "units" => "the number of units must be a whole number in [1, 64]",
            "d_spread" => "the clearance spread must be in [0, 1)",
            _ => "unknown key",
        }
    }

    /// The magnitudes that make sense in SI, for the keys that have one: `(low, high, what)`
    /// with `low <= |value| <= high` (a zero inner mass, no damper, and zero damping, initial
    /// state or velocity are allowed too). Beyond them a value is no physical damper
    /// (a main mass of 1e-300 kg, a velocity of 1e200 m/s), and the closed form's frequencies,
    /// energies and derivatives leave the floating-point range (the run would end at the step
    /// cap after seconds of work instead of at once with an error).
    pub fn si_range(key: &str) -> Option<(f64, f64, &'static str)> {
        Some(match key {
            "M" => (1e-12, 1e12, "the main mass must be in [1e-12, 1e12] kg"),
            "m" => (
                1e-12,
                1e12,
                "the inner mass must be 0 (no damper) or in [1e-12, 1e12] kg",
            ),
            "K" => (1e-12, 1e15, "the stiffness must be in [1e-12, 1e15] N/m"),
            "C" => (0.0, 1e15, "the damping must be in [0, 1e15] N s/m"),
            "d" => (1e-12, 1e6, "the clearance must be in [1e-12, 1e6] m"),
            "x0" | "y0" => (0.0, 1e6, "an initial position must be in [-1e6, 1e6] m"),
            "v0" | "w0" => (0.0, 1e6, "an initial velocity must be in [-1e6, 1e6] m/s"),
            _ => return None,
        })
    }

    /// Checks every range of model.md §1: `M > 0`, `m >= 0`, `K > 0`, `C >= 0`, `d > 0`,
    /// `0 <= e <= 1`, `|y0 - x0| <= d/2`, every number finite, and the SI magnitudes of
    /// [`System::si_range`].
    pub fn validate(&self) -> Result<(), RangeError> {
        for key in SYSTEM_KEYS {
            let v = self.get(key).unwrap_or(f64::NAN);
            let ok = v.is_finite()
                && match key {
                    "M" | "K" | "d" => v > 0.0,
                    "m" | "C" => v >= 0.0,
                    "e" => (0.0..=1.0).contains(&v),
                    _ => true,
                };
            if !ok {
                return Err(RangeError::new(key, v, Self::allowed(key)));
            }
            if let Some((low, high, what)) = Self::si_range(key)
                && v != 0.0
                && !(low..=high).contains(&v.abs())
            {
                return Err(RangeError::new(key, v, what));
            }
        }
        if let Some(table) = self.table {
            return self.validate_table(table);
        }
        let n = self.units;
        if !(n.is_finite() && n.fract() == 0.0 && (1.0..=MAX_UNITS).contains(&n)) {
            return Err(RangeError::new("units", n, Self::allowed("units")));
        }
        if !(0.0..1.0).contains(&self.d_spread) {
            return Err(RangeError::new(
                "d_spread",
                self.d_spread,
                Self::allowed("d_spread"),
            ));
        }
        let gap = (self.y0 - self.x0).abs();
        let d_min = self.unit_list().iter().map(|u| u.d).fold(self.d, f64::min);
        if gap > 0.5 * d_min && d_min < self.d {
            return Err(RangeError::new(
                "y0",
                self.y0,
                format!(
                    "every unit must start inside its cavity: |y0 - x0| = {} exceeds the \
                     smallest unit's d/2 = {} (d_spread = {})",
                    fmt_value(gap),
                    fmt_value(0.5 * d_min),
                    fmt_value(self.d_spread)
                ),
            ));
        }
        if gap > 0.5 * self.d {
            return Err(RangeError::new(
                "y0",
                self.y0,
                format!(
                    "the inner mass must start inside the cavity: |y0 - x0| = {} exceeds d/2 = {}",
                    fmt_value(gap),
                    fmt_value(0.5 * self.d)
                ),
            ));
        }
        Ok(())
    }

    /// [`System::validate`]'s checks of a per-unit table: each unit's `m`, `d`, `e`, `y0`, `w0`
    /// in range (named `unit[i].key`), its start inside its own cavity, 2 to 64 units, and the
    /// keys the table decides (`units`, `d_spread`, `m`, `d`, `e`) as it decides them.
    fn validate_table(&self, table: UnitTable) -> Result<(), RangeError> {
        let units = table.units();
        let n = units.len() as f64;
        if !(2.0..=MAX_UNITS).contains(&n) {
            return Err(RangeError::new(
                "unit",
                n,
                "a table of units holds 1 to 64 units (one is the plain system)",
            ));
        }
        for (i, u) in units.iter().enumerate() {
            Self::check_unit(i, u, self.x0)?;
        }
        let (m, d, e) = table.derived();
        for (key, v, want) in [
            ("units", self.units, n),
            ("d_spread", self.d_spread, 0.0),
            ("m", self.m, m),
            ("d", self.d, d),
            ("e", self.e, e),
        ] {
            if v.to_bits() != want.to_bits() {
                return Err(RangeError::new(
                    key,
                    v,
                    format!(
                        "the table of units decides {key} = {} (model.md §14)",
                        fmt_value(want)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// One unit `i` of a table: its keys in range and its start inside its cavity (`x0` the
    /// main mass's start).
    pub fn check_unit(i: usize, u: &Unit, x0: f64) -> Result<(), RangeError> {
        let named = |e: RangeError, key: &str| RangeError {
            key: format!("unit[{i}].{key}"),
            ..e
        };
        let s = System {
            m: u.m,
            d: u.d,
            e: u.e,
            w0: u.w0,
            ..System::TABLE_I
        };
        s.validate().map_err(|e| {
            let key = e.key.clone();
            named(e, &key)
        })?;
        let s = System {
            x0: u.y0,
            y0: u.y0,
            ..System::TABLE_I
        };
        s.validate().map_err(|e| named(e, "y0"))?;
        let gap = (u.y0 - x0).abs();
        if gap.is_nan() || gap > 0.5 * u.d {
            return Err(RangeError::new(
                &format!("unit[{i}].y0"),
                u.y0,
                format!(
                    "the unit must start inside its cavity: |y0 - x0| = {} exceeds its d/2 = {} \
                     (x0 = {})",
                    fmt_value(gap),
                    fmt_value(0.5 * u.d),
                    fmt_value(x0)
                ),
            ));
        }
        Ok(())
    }

    /// The number of units, `units` as a count.
    pub fn unit_count(&self) -> usize {
        self.units as usize
    }

    /// The units (model.md §14): `N = units` equal shares `m / N` of the inner mass, each with
    /// `e`, `(y0, w0)` and the clearance `d_i = d (1 + d_spread (2 i / (N - 1) - 1))` (`d` for
    /// one unit). One unit is the paper's system: `m`, `d`, `e`, `y0`, `w0` as given.
    ///
    /// With a per-unit table ([`UnitTable`]) the units are the table's, in its order.
    pub fn unit_list(&self) -> Vec<Unit> {
        if let Some(table) = self.table {
            return table.units().to_vec();
        }
        let n = self.unit_count().max(1);
        (0..n)
            .map(|i| {
                let d = if n == 1 || self.d_spread == 0.0 {
                    self.d
                } else {
                    self.d * (1.0 + self.d_spread * (2.0 * i as f64 / (n - 1) as f64 - 1.0))
                };
                Unit {
                    m: if n == 1 { self.m } else { self.m / n as f64 },
                    d,
                    e: self.e,
                    y0: self.y0,
                    w0: self.w0,
                }
            })
            .collect()
    }

    /// Undamped natural angular frequency of the main mass alone, `sqrt(K/M)` (rad/s).
    pub fn omega(&self) -> f64 {
        (self.K / self.M).sqrt()
    }

    /// Undamped natural period of the main mass alone, `2 pi sqrt(M/K)` (s).
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.omega()
    }

    /// Damping ratio of the main mass alone, `zeta = C / (2 sqrt(K M))`.
    pub fn zeta(&self) -> f64 {
        self.C / (2.0 * (self.K * self.M).sqrt())
    }

    /// Steady amplitude (m) of the main mass alone (no inner mass) under `F0 cos(omega t)` at
    /// the frequency ratio `r = omega / sqrt(K/M)`: `X_st / sqrt((1 - r^2)^2 + (2 zeta r)^2)`,
    /// `X_st = F0 / K`.
    #[allow(non_snake_case)]
    pub fn linear_amplitude(&self, F0: f64, r: f64) -> f64 {
        F0 / self.K / ((1.0 - r * r).powi(2) + (2.0 * self.zeta() * r).powi(2)).sqrt()
    }

    /// Total mechanical energy (J) of a state of this system: both kinetic energies and the
    /// spring's potential energy.
    pub fn energy(&self, x: f64, v: f64, w: f64) -> f64 {
        0.5 * (self.M * v * v + self.m * w * w + self.K * x * x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_i_is_valid() {
        System::TABLE_I.validate().unwrap();
    }

    #[test]
    fn errors_name_key_value_and_range() {
        let mut s = System::TABLE_I;
        s.e = 1.3;
        assert_eq!(
            s.validate().unwrap_err().to_string(),
            "e = 1.3: the coefficient of restitution must be in [0, 1]"
        );
        let mut s = System::TABLE_I;
        s.M = f64::NAN;
        assert_eq!(
            s.validate().unwrap_err().to_string(),
            "M = NaN: the main mass must be a finite number > 0 (kg)"
        );
        let mut s = System::TABLE_I;
        s.M = 1e-300;
        assert_eq!(
            s.validate().unwrap_err().to_string(),
            "M = 1e-300: the main mass must be in [1e-12, 1e12] kg"
        );
        let mut s = System::TABLE_I;
        s.v0 = -1e200;
        assert_eq!(
            s.validate().unwrap_err().to_string(),
            "v0 = -1e200: an initial velocity must be in [-1e6, 1e6] m/s"
        );
        let mut s = System::TABLE_I;
        s.m = 0.0;
        s.C = 0.0;
        s.x0 = 0.0;
        s.validate().unwrap();
        let mut s = System::TABLE_I;
        s.y0 = 0.006;
        assert_eq!(
            s.validate().unwrap_err().to_string(),
            "y0 = 0.006: the inner mass must start inside the cavity: |y0 - x0| = 0.006 exceeds d/2 = 0.005"
        );
    }

    fn unit(m: f64, d: f64, e: f64) -> Unit {
        Unit {
            m,
            d,
            e,
            y0: 0.0,
            w0: 0.0,
        }
    }

    #[test]
    fn a_unit_table_decides_the_derived_keys_and_is_interned() {
        let units = [unit(0.004, 0.008, 0.8), unit(0.006, 0.012, 0.6)];
        let s = System::TABLE_I.with_units(&units);
        s.validate().unwrap();
        assert_eq!((s.units, s.d_spread, s.m, s.d), (2.0, 0.0, 0.01, 0.012));
        assert!((s.e - 0.68).abs() < 1e-15, "{}", s.e);
        assert_eq!(s.unit_list(), units.to_vec());
        assert_eq!(s.unit_count(), 2);
        // The same bits share one table; other bits another.
        let again = System::TABLE_I.with_units(&units);
        let (a, b) = (s.table.unwrap().units(), again.table.unwrap().units());
        assert!(std::ptr::eq(a, b));
        let other = System::TABLE_I.with_units(&[units[1], units[0]]);
        assert!(!std::ptr::eq(a, other.table.unwrap().units()));
        // A table of one unit is the plain system.
        let one = System::TABLE_I.with_units(&[Unit {
            y0: 0.001,
            ..units[0]
        }]);
        assert_eq!(one.table, None);
        assert_eq!(
            (one.m, one.d, one.e, one.y0, one.units),
            (0.004, 0.008, 0.8, 0.001, 1.0)
        );
        // Serde round trip: `unit` only when there is a table.
        let json = serde_json::to_string(&s).unwrap();
        assert!(json.contains("\"unit\":[{\"m\":0.004"), "{json}");
        assert_eq!(serde_json::from_str::<System>(&json).unwrap(), s);
        assert!(
            !serde_json::to_string(&System::TABLE_I)
                .unwrap()
                .contains("unit")
        );
        // The system keys the table decides are checked against it.
        let mut bad = s;
        bad.m = 0.02;
        assert_eq!(
            bad.validate().unwrap_err().to_string(),
            "m = 0.02: the table of units decides m = 0.01 (model.md §14)"
        );
        let bad = System::TABLE_I.with_units(&[units[0], unit(0.001, 0.004, 1.5)]);
        assert_eq!(
            bad.validate().unwrap_err().to_string(),
            "unit[1].e = 1.5: the coefficient of restitution must be in [0, 1]"
        );
        let bad = System::TABLE_I.with_units(&[
            units[0],
            Unit {
                y0: 0.007,
                ..units[1]
            },
        ]);
        assert_eq!(
            bad.validate().unwrap_err().to_string(),
            "unit[1].y0 = 0.007: the unit must start inside its cavity: |y0 - x0| = 0.007 \
             exceeds its d/2 = 0.006 (x0 = 0)"
        );
        let bad = System::TABLE_I.with_units(&vec![units[0]; 65]);
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .starts_with("unit = 65")
        );
    }

    #[test]
    fn set_and_get_round_trip_every_key() {
        let mut s = System::TABLE_I;
        for (i, k) in SYSTEM_KEYS.iter().enumerate() {
            assert!(s.set(k, i as f64 * 0.001));
            assert_eq!(s.get(k), Some(i as f64 * 0.001));
        }
        assert!(!s.set("bogus", 1.0));
    }
}
