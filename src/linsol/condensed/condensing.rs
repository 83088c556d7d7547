//! What a backend does to condense a matrix onto kept unknowns (MUMPS's own Schur complement, or
//! [`super::elimination::BlockElimination`] over any backend's factorisation): the one contract
//! between the condensed system and the backends.

use crate::linsol::csc::CscMatrix;
use crate::linsol::{Backend, Failure};

/// A backend that condenses a matrix onto kept unknowns.
pub trait Condensing {
    fn backend(&self) -> Backend;
    /// Factorise the interior of `matrix` and return the Schur complement on `kept` (sorted,
    /// distinct equation numbers), dense and row by row.
    fn factorize_condensed(&mut self, matrix: &CscMatrix, kept: &[usize]) -> Result<Vec<f64>, Failure>;
    /// r_K − A_KI A_II⁻¹ r_I, in the order of `kept`.
    fn condense(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure>;
    /// The solution on every unknown, from the one on the kept unknowns.
    fn expand(&mut self, rhs: &[f64], kept_solution: &[f64]) -> Result<Vec<f64>, Failure>;
}
