//! The design-life question ([`Life`]: how many periods, which quantile, which tail shapes)
//! and its answer ([`LifeEstimate`]), with the constants both the fits ([`super::gpd`],
//! [`super::gev`]) and the estimate ([`super`]) use.

/// Chi-square quantile, one degree of freedom, at 0.90: the profile-likelihood interval's drop.
pub const CHI2_90: f64 = 2.705_543_454_095_404;

/// The lowest shape of a bounded quantity's fit (the module doc of [`super`]): the likelihood is
/// regular above it.
pub const XI_BOUNDED: f64 = -0.5;

/// The largest value over a design life, estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LifeEstimate {
    /// The quantile `q` of the largest value over `N` periods (the posterior median of the
    /// estimate's fits, the module doc of [`super`]), and its 90 % interval (the upper end `inf`
    /// when the likelihood does not drop enough above the estimate).
    pub amplitude: f64,
    pub lo: f64,
    pub hi: f64,
    /// The tail's law of the middle fit: threshold, scale, shape (and the shape's standard
    /// error).
    pub threshold: f64,
    pub sigma: f64,
    pub xi: f64,
    pub xi_se: f64,
    /// The bounded tail's end point `u - sigma / xi` (NaN unless `xi < 0`).
    pub end_point: f64,
    /// Cluster maxima above the middle fit's threshold, and periods measured.
    pub exceedances: u64,
    pub measured: u64,
    /// The lowest threshold of the fits: per-period maxima below it enter only as periods
    /// below the thresholds (the measurement need not locate them exactly).
    pub lowest_threshold: f64,
}

impl LifeEstimate {
    /// The interval's half-width relative to the estimate.
    pub fn rel_halfwidth(&self) -> f64 {
        0.5 * (self.hi - self.lo) / self.amplitude
    }
}

/// The design-life question: `n_life` periods (`N`, may exceed the sample by far), the quantile
/// `q` of the largest value over them, and the tail shapes allowed, `[xi_min, xi_max]`
/// ([`Life::bounded`] for the main mass's excursion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Life {
    pub n_life: f64,
    pub q: f64,
    pub xi_min: f64,
    pub xi_max: f64,
}

impl Life {
    /// The question for a bounded quantity: shapes in `[XI_BOUNDED, 0]` (the module doc of
    /// [`super`]).
    pub fn bounded(n_life: f64, q: f64) -> Life {
        Life {
            n_life,
            q,
            xi_min: XI_BOUNDED,
            xi_max: 0.0,
        }
    }

    /// `m = N nu / (-ln q)` for a cluster rate `nu` per period.
    pub fn m(&self, nu: f64) -> f64 {
        self.n_life * nu / (-self.q.ln())
    }
}
