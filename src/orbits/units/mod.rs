//! Periodic orbits of several damper units (model.md §14, issue 68): the stroboscopic map on
//! the `2 + 2N`-dimensional section `(x, x', z_1, y_1', ..., z_N, y_N')` ([`map`]), its exact
//! Jacobian where the impacts come one unit at a time ([`exact`]; central differences of the map
//! elsewhere, [`map::jacobian`]), Newton shooting with Floquet multipliers ([`shoot`]) and the
//! census of periodic steady states at one frequency point ([`census`]), its motions that are
//! not periodic told apart ([`motion`]), the largest Lyapunov exponent of such a motion from two
//! trajectories ([`lyapunov`]), and a
//! periodic orbit followed along `r` with its bifurcations labelled ([`continuation`]). One unit's orbits are
//! [`crate::orbits::map`], [`crate::orbits::shoot`] and [`crate::orbits::census`]; with `N = 1`
//! this module's map is theirs bit for bit.

pub mod census;
pub mod continuation;
pub mod exact;
pub mod lyapunov;
pub mod map;
pub mod motion;
pub mod shoot;

pub use census::{
    UnitsAttractor, UnitsCensus, UnitsCensusSettings, census_from_rest, census_units,
};
pub use map::{UnitsEval, eval};
pub use motion::{UnitsCloud, UnitsMotion};
pub use shoot::{UnitsNewton, UnitsOrbit, orbit_at, solve};
