//! geoslip: finite-element analysis of soil–geosynthetic interfaces that slip a lot.
//!
//! Normal compatibility between soil and reinforcement is imposed by Lagrange multipliers (Yi 1996,
//! Eq. 5), with no arbitrary normal stiffness; tangential resistance comes from a shear stiffness Ks
//! per face. The saddle-point system [K sCᵀ; sC sD] (s: the constraint rows' scale; D: the unit
//! diagonal of released rows and the dilating faces' terms) is assembled in triplet form and solved
//! by a sparse direct solver: MUMPS, UMFPACK or faer, with a dense reference ([`linsol`]). While the
//! soil is elastic, each iteration solves only the interface's unknowns: the soil is condensed onto
//! them once ([`linsol::condensed`]), an iteration costs a dense factorisation of that small
//! system or an update of it, and the soil's interior follows once an increment
//! (the interface path of `analysis/equilibrium/`). Results are the same as the whole system's, to its
//! residual check.
//!
//! The driver reads top to bottom: [`model::Model::load`] → [`analysis::run`] → [`output`].

#![deny(unsafe_code)]
// `!(x > tol)` is used on purpose throughout: it is true for NaN, which must count as a failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Dense loops over CSC columns read better with the column index.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod assembly;
pub mod calibration;
pub mod cli;
pub mod design;
pub mod dofs;
pub mod element;
pub mod error;
pub mod geo_script;
pub mod gmsh;
pub mod input_file;
pub mod interface;
pub mod linsol;
pub mod memory;
pub mod mesh;
pub mod meshgen;
pub mod model;
// The FFI that is not a linear solver: the C heap, the resource limits of a child program, and
// HDF5's direct chunk write. The solver backends' FFI is in `linsol::native`.
#[allow(unsafe_code)]
pub mod native;
pub mod output;
pub mod timing;

pub use error::{Error, ModelError, Problem, SolveError};
