//! The native backends, the C heap they share, HDF5's direct chunk write, and the resource limits
//! of a program geoslip starts: the only unsafe code in geoslip.
//!
//! Each backend has one struct that owns its native handle: created (and null-checked) in `new`,
//! freed in `Drop`. No raw pointer leaves this module. MUMPS calls hold `geoslip_sys::MUMPS_LOCK`.
//! Their status codes come back typed (`error::native`: `SolveError::Mumps`, `SolveError::Umfpack`).

pub mod child_limits;
#[cfg(all(geoslip_mumps, feature = "mpi"))]
pub mod cluster;
#[cfg(feature = "hdf5")]
pub mod hdf5_chunk;
pub mod heap;
#[cfg(geoslip_mumps)]
pub mod mumps;
#[cfg(geoslip_umfpack)]
pub mod umfpack;
