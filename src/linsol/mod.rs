//! Linear solvers for the saddle-point system [K sCᵀ; sC sD].
//!
//! Two ways a system is solved:
//! - whole, by a backend behind the [`LinearSolver`] trait (MUMPS, UMFPACK, faer, the dense
//!   reference), with [`linear_system::LinearSystem`]'s bookkeeping: the symbolic analysis
//!   (`analyse`) once per sparsity pattern, the numeric factorisation (`factorize`) once per set of
//!   values, `solve` once per right-hand side, every solution checked and refined (`refine.rs`);
//! - condensed, the elastic soil onto the interface's unknowns ([`condensed::CondensedSystem`]),
//!   for the interface iteration.

pub mod condensed;
pub mod csc;
pub mod dense_ref;
pub mod faer_lu;
pub mod linear_system;
#[allow(unsafe_code)]
pub mod native;
mod refine;

#[cfg(all(geoslip_mumps, feature = "mpi"))]
pub use native::cluster;

use crate::error::SolveError;
use csc::CscMatrix;

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

/// MUMPS's fill-reducing ordering, ICNTL(7). Debian's sequential MUMPS has Scotch and PORD, its
/// MPI build PORD only; neither has METIS. docs/performance.md shows the measurements behind the
/// default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Ordering {
    /// Scotch in the sequential build, PORD in the MPI build.
    #[default]
    Auto,
    /// Scotch (ICNTL(7) = 3).
    Scotch,
    /// PORD (ICNTL(7) = 4).
    Pord,
    /// Approximate minimum degree (ICNTL(7) = 0).
    Amd,
}

impl Ordering {
    /// The concrete ordering `auto` stands for in this build.
    pub fn resolve(self) -> Ordering {
        match self {
            Ordering::Auto if cfg!(feature = "mpi") => Ordering::Pord,
            Ordering::Auto => Ordering::Scotch,
            o => o,
        }
    }

    /// MUMPS's ICNTL(7) value.
    pub fn icntl7(self) -> i32 {
        match self.resolve() {
            Ordering::Scotch => 3,
            Ordering::Pord => 4,
            _ => 0,
        }
    }

    pub fn name(self) -> &'static str {
        match self.resolve() {
            Ordering::Scotch => "scotch",
            Ordering::Pord => "pord",
            _ => "amd",
        }
    }
}

/// Settings that only some backends use.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverOptions {
    /// MUMPS's ordering.
    pub ordering: Ordering,
    /// MUMPS keeps its factors on disk (ICNTL(22) = 1), in `MUMPS_OOC_TMPDIR` or `/tmp`.
    pub out_of_core: bool,
    /// Memory the run may use in all, MB; `None`: what the machine has available (MemAvailable). A
    /// model estimated above it stops before it is assembled; a factorisation that MUMPS's analysis
    /// estimates above what is left of it (the limit less what the run already holds) stops before
    /// it starts.
    pub memory_limit_mb: Option<f64>,
    /// Condense an elastic soil onto the interface's unknowns and iterate on the small system
    /// (`analysis::condensation`; the default); `false`: the full system every iteration
    /// (`--full-system`).
    pub condense: bool,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions { ordering: Ordering::Auto, out_of_core: false, memory_limit_mb: None, condense: true }
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
    /// The backend's own estimate of its factorisation memory after the last analysis, MB.
    fn estimated_memory_mb(&self) -> Option<f64> {
        None
    }
    /// Memory the last factorisation used, MB (MUMPS: INFOG(22)).
    fn factor_memory_mb(&self) -> Option<f64> {
        None
    }
}

/// Make a solver for a backend. `symmetric` says whether the matrices it will see are symmetric
/// (MUMPS then uses SYM=2 on the lower triangle; otherwise SYM=0).
///
/// # Errors
/// [`SolveError::Unavailable`] for a backend that is not compiled into this build, saying how to get
/// it.
pub fn make(backend: Backend, symmetric: bool, options: &SolverOptions) -> Result<Box<dyn LinearSolver>, SolveError> {
    let _ = (symmetric, options);
    match backend.resolve() {
        Backend::Dense => Ok(Box::new(dense_ref::DenseReference::default())),
        Backend::Faer => Ok(Box::new(faer_lu::FaerLu::default())),
        #[cfg(geoslip_mumps)]
        Backend::Mumps => Ok(Box::new(native::mumps::Mumps::new(symmetric, options)?)),
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
    let r: Vec<f64> = ax.iter().zip(b).map(|(p, q)| p - q).collect();
    let (r, nb) = (norm2(&r), norm2(b));
    if nb > 0.0 {
        r / nb
    } else {
        r
    }
}

/// ‖v‖₂ without overflow or underflow in the squares (entries scaled by the largest first).
pub fn norm2(v: &[f64]) -> f64 {
    let largest = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest * v.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
}
