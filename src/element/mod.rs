//! Element formulations: plane-strain and axisymmetric soil solids and reinforcement bars.

pub mod bar;
pub mod duncan_chang;
pub mod geometry;
pub mod mohr_coulomb;
pub mod soil_law;
pub mod soil_state;
pub mod solid;
