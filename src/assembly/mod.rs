//! Assembly: the element matrices, the saddle-point matrix of one iteration from one input struct
//! (and its fingerprint), and the internal forces.

pub mod system;

pub use system::{internal_force, round_off_floor, ElementMatrices, SoilView, SystemInputs};
