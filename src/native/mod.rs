//! The unsafe code that is not a linear solver: the C heap geoslip shares with the native solvers,
//! the resource limits of a program geoslip starts (Gmsh), and HDF5's direct chunk write. Each
//! call is wrapped in a safe function here; no raw pointer leaves this module. The solver
//! backends' FFI (MUMPS, UMFPACK, MPI) is in `linsol::native`, beside the traits it implements.

pub mod child_limits;
#[cfg(feature = "hdf5")]
pub mod hdf5_chunk;
pub mod heap;
