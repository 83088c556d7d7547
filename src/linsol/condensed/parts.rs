//! The values a condensed solve takes and gives: the soil part, the interface part, and a solve of
//! the kept system alone.

use super::kept::KeptUnknowns;
use crate::linsol::csc::Triplets;
use std::rc::Rc;

/// The soil part L of a solve: its kept unknowns, the key that names its values, how to assemble
/// it (called only when the key is new) and its product with a vector (from the caller's
/// elements, once L's matrix has been let go).
pub struct SoilPart<'a> {
    pub kept: &'a Rc<KeptUnknowns>,
    pub key: u64,
    pub assemble: &'a dyn Fn() -> Triplets,
    pub times: &'a dyn Fn(&[f64]) -> Vec<f64>,
}

/// The changing part C of a solve: the key of the iteration's matrix (while it stays, the dense
/// factorisation made with the C of its first solve is reused), and how to assemble C (called
/// only when the key is new).
pub struct InterfacePart<'a> {
    pub key: u64,
    pub assemble: &'a dyn Fn() -> Triplets,
}

/// A solve of the kept system alone ([`CondensedSystem::solve_kept`]).
pub struct KeptSolution {
    /// x_K.
    pub x: Vec<f64>,
    /// ‖(S + C_KK)·x_K − r_K‖ / ‖r_K‖.
    pub residual: f64,
    /// S·x_K: the change of the soil's force on the kept unknowns when they move by x_K and the
    /// interior follows in balance.
    pub soil_force: Vec<f64>,
}
