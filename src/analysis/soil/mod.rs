//! The soil through a run: which elements are present, the effective stresses at their Gauss points,
//! the pore pressures, the soil's weight, and the forces and tangents all of these give.
//!
//! Total stress is σ = σ′ − p·m, with m = (1, 1, 0, 1) and p the pore pressure (compression
//! positive); the internal force of an element is ∫Bᵀσ′ dA − ∫Bᵀm·p dA.
//! - A linear-elastic element keeps a reference state (its stresses when placed or given K0
//!   stresses, and its displacements then): σ′ = σ′₀ + D·B·(u − u₀), so its force is
//!   ∫Bᵀσ′₀ dA + K_e·(u − u₀) and K_e is computed once.
//! - A Mohr–Coulomb, Duncan–Chang or hardening-soil element keeps the committed σ′ at each Gauss
//!   point (and its state variables); each iteration updates it for the strain since the last
//!   converged increment
//!   ([`SoilLaw::update`](crate::element::soil_law::SoilLaw::update)). A cutback restores the
//!   committed state with the rest of the run's state.
//!
//! Its parts: what does not change (`setup.rs`), a point's strain and Bᵀσ (`kinematics.rs`), which
//! elements are present (`placement.rs`), the water's pressures (`water.rs`), what the unit weight
//! gives (`weight.rs`), the K0 initial stresses (`initial_stress.rs`), each iteration's trial state
//! and its commit (`trial.rs`), and the Gauss-point results (`results.rs`).

mod initial_stress;
mod kinematics;
mod placement;
mod results;
mod setup;
mod trial;
mod water;
mod weight;

pub use crate::element::soil_state::{element_force, ElementState, PointState, SoilField, SoilTrial, Tangent};
pub use initial_stress::set_k0;
pub use placement::{activate, deactivate, initial_field, present_nodes};
pub use results::{gauss_results, normal_stress_across, ElementStress};
pub use setup::SoilSetup;
pub use trial::{commit, evaluate};
pub use water::{set_water, water_on_boundary};
pub(crate) use weight::unit_weight;
pub use weight::{body_force, masses, weight};
