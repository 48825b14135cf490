//! Steady states of the forced scene as periodic orbits (`docs/model.md` §8): orbits known in
//! closed form, against which the simulator and the shooting solver are checked.
//!
//! [`analytic`] holds Masri and Caughey's (1966) symmetric period-1 orbit with two impacts per
//! forcing period. Pure functions of the system and the forcing: no I/O.

pub mod analytic;
