//! Element formulations: plane-strain soil solids and reinforcement bars.

pub mod bar;
pub mod mohr_coulomb;
pub mod soil_state;
pub mod solid;
