//! Linear solvers for the saddle-point system [K Cᵀ; C D] behind one trait.
//!
//! The symbolic analysis (`analyse`) is done once per sparsity pattern and reused; the numeric
//! factorisation (`factorize`) once per set of values; `solve` once per right-hand side.

pub mod dense_ref;
pub mod faer_lu;
#[allow(unsafe_code)]
pub mod native;

use crate::assembly::CscMatrix;
use crate::error::SolveError;

/// Backends that can be asked for on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    /// The best backend compiled into this build.
    Auto,
    /// Dense Gauss elimination with complete pivoting: the reference, small models only.
    Dense,
    /// faer's sparse LU (pure Rust).
    Faer,
    /// MUMPS, sequential: symmetric indefinite LDLᵀ (SYM=2) for symmetric systems.
    Mumps,
    /// UMFPACK (SuiteSparse): unsymmetric LU.
    Umfpack,
}

impl Backend {
    /// Backends compiled into this build, best first.
    pub fn available() -> Vec<Backend> {
        let mut list = Vec::new();
        if cfg!(geoslip_mumps) {
            list.push(Backend::Mumps);
        }
        if cfg!(geoslip_umfpack) {
            list.push(Backend::Umfpack);
        }
        list.extend([Backend::Faer, Backend::Dense]);
        list
    }

    pub fn name(self) -> &'static str {
        match self {
            Backend::Auto => "auto",
            Backend::Dense => "dense",
            Backend::Faer => "faer",
            Backend::Mumps => "mumps",
            Backend::Umfpack => "umfpack",
        }
    }

    /// The concrete backend `auto` stands for.
    pub fn resolve(self) -> Backend {
        match self {
            Backend::Auto => Backend::available()[0],
            b => b,
        }
    }
}

/// A failure that names unknowns by their equation numbers; the analysis turns the numbers into
/// node, DOF and interface names.
#[derive(Debug, Clone)]
pub enum Failure {
    Singular { equations: Vec<usize> },
    Other(SolveError),
}

impl From<SolveError> for Failure {
    fn from(e: SolveError) -> Self {
        Failure::Other(e)
    }
}

/// One linear solver backend.
pub trait LinearSolver {
    fn backend(&self) -> Backend;
    /// Symbolic analysis of a pattern (ordering, fill), given the first values on it. Called again only
    /// when the pattern changes.
    fn analyse(&mut self, matrix: &CscMatrix) -> Result<(), Failure>;
    /// Numeric factorisation of values on the analysed pattern.
    fn factorize(&mut self, matrix: &CscMatrix) -> Result<(), Failure>;
    /// Solve with the current factorisation.
    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure>;
    /// Negative pivots of the last symmetric factorisation, where the backend reports its inertia.
    fn negative_pivots(&self) -> Option<usize> {
        None
    }
    /// Entries in the factors of the last factorisation, where the backend reports them.
    fn factor_entries(&self) -> Option<u64> {
        None
    }
}

/// Make a solver for a backend. `symmetric` says whether the matrices it will see are symmetric
/// (MUMPS then uses SYM=2 on the lower triangle; otherwise SYM=0).
///
/// # Errors
/// [`SolveError::Unavailable`] for a backend that is not compiled into this build, saying how to get
/// it.
pub fn make(backend: Backend, symmetric: bool) -> Result<Box<dyn LinearSolver>, SolveError> {
    let _ = symmetric;
    match backend.resolve() {
        Backend::Dense => Ok(Box::new(dense_ref::DenseReference::default())),
        Backend::Faer => Ok(Box::new(faer_lu::FaerLu::default())),
        #[cfg(geoslip_mumps)]
        Backend::Mumps => Ok(Box::new(native::mumps::Mumps::new(symmetric, native::mumps::Ordering::Scotch)?)),
        #[cfg(geoslip_umfpack)]
        Backend::Umfpack => Ok(Box::new(native::umfpack::Umfpack::default())),
        other => Err(unavailable(other)),
    }
}

/// Whether a backend is compiled into this build.
///
/// # Errors
/// [`SolveError::Unavailable`], saying how to get it.
pub fn check_available(backend: Backend) -> Result<(), SolveError> {
    if Backend::available().contains(&backend.resolve()) {
        Ok(())
    } else {
        Err(unavailable(backend))
    }
}

fn unavailable(backend: Backend) -> SolveError {
    SolveError::Unavailable {
        backend: backend.name().into(),
        hint: format!(
            "this build has {}. To get {}, install {} (as root: apt-get install -y {} libclang-dev) and rebuild \
             geoslip (cargo build --release); `geoslip backends` lists the backends a build has",
            Backend::available().iter().map(|b| b.name()).collect::<Vec<_>>().join(", "),
            backend.name(),
            package(backend),
            package(backend),
        ),
    }
}

/// The Debian package that provides a native backend.
fn package(backend: Backend) -> &'static str {
    match backend {
        Backend::Mumps => "libmumps-seq-dev",
        Backend::Umfpack => "libsuitesparse-dev",
        _ => "nothing",
    }
}

/// ‖A x − b‖ / ‖b‖ (or ‖A x − b‖ when b = 0).
pub fn relative_residual(a: &CscMatrix, x: &[f64], b: &[f64]) -> f64 {
    let ax = a.mul_vec(x);
    let r: f64 = ax.iter().zip(b).map(|(p, q)| (p - q).powi(2)).sum::<f64>().sqrt();
    let nb: f64 = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    if nb > 0.0 {
        r / nb
    } else {
        r
    }
}
