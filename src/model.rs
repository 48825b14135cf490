//! The physical system of `docs/model.md` §1: a main mass `M` on a spring `K` and a
//! viscous damper `C`, with a cavity of total clearance `d` in which a loose inner mass `m`
//! moves freely. All quantities are SI.
//!
//! [`System`] is the validated form: every constructor path goes through [`System::validate`],
//! so later stages (the simulator above all) never see an unvalidated value.

use serde::{Deserialize, Serialize};

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
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
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
    };

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

    /// The number of units, `units` as a count.
    pub fn unit_count(&self) -> usize {
        self.units as usize
    }

    /// The units (model.md §14): `N = units` equal shares `m / N` of the inner mass, each with
    /// `e`, `(y0, w0)` and the clearance `d_i = d (1 + d_spread (2 i / (N - 1) - 1))` (`d` for
    /// one unit). One unit is the paper's system: `m`, `d`, `e`, `y0`, `w0` as given.
    pub fn unit_list(&self) -> Vec<Unit> {
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
