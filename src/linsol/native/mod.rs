//! The native solver backends (MUMPS, UMFPACK, MPI): with `crate::native` (the C heap, a child's
//! resource limits, HDF5's chunk write), the only unsafe code in geoslip.
//!
//! Each backend has one struct that owns its native handle: created (and null-checked) in `new`,
//! freed in `Drop`. No raw pointer leaves this module. MUMPS calls hold `geoslip_sys::MUMPS_LOCK`.
//! Their status codes come back typed (`error::native`: `SolveError::Mumps`, `SolveError::Umfpack`).

#[cfg(all(geoslip_mumps, feature = "mpi"))]
pub mod cluster;
#[cfg(geoslip_mumps)]
pub mod mumps;
#[cfg(geoslip_umfpack)]
pub mod umfpack;
