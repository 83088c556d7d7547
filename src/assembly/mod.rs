//! Assembly: the element matrices, the saddle-point matrix of one iteration from one input struct
//! (and its fingerprint), and the internal forces.

mod block_sum;
pub mod forces;
pub mod inertia;
pub mod system;

pub use forces::{
    add_spring_forces, bar_force, internal_force, soil_and_bar_force, soil_and_bar_force_and_floor, ElementForce,
};
pub use inertia::Inertia;
pub use system::{ElementMatrices, SoilView, SystemInputs};
