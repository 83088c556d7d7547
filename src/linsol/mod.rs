//! Linear solvers for the saddle-point system [K Cᵀ; C D] behind one trait.
//!
//! The symbolic analysis (`analyse`) is done once per sparsity pattern and reused; the numeric
//! factorisation (`factorize`) once per set of values; `solve` once per right-hand side.

pub mod dense_ref;
pub mod faer_lu;

use crate::assembly::{CscMatrix, CscPattern};
use crate::error::SolveError;
use std::sync::Arc;

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
}

impl Backend {
    /// Backends compiled into this build, best first.
    pub fn available() -> Vec<Backend> {
        vec![Backend::Faer, Backend::Dense]
    }

    pub fn name(self) -> &'static str {
        match self {
            Backend::Auto => "auto",
            Backend::Dense => "dense",
            Backend::Faer => "faer",
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
    /// Symbolic analysis of a pattern (ordering, fill). Called again only when the pattern changes.
    fn analyse(&mut self, pattern: &Arc<CscPattern>) -> Result<(), Failure>;
    /// Numeric factorisation of values on the analysed pattern.
    fn factorize(&mut self, matrix: &CscMatrix) -> Result<(), Failure>;
    /// Solve with the current factorisation.
    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure>;
}

/// Make a solver for a backend.
///
/// # Errors
/// [`SolveError::Unavailable`] for a backend that is not compiled in.
pub fn make(backend: Backend) -> Result<Box<dyn LinearSolver>, SolveError> {
    match backend.resolve() {
        Backend::Dense => Ok(Box::new(dense_ref::DenseReference::default())),
        Backend::Faer => Ok(Box::new(faer_lu::FaerLu::default())),
        Backend::Auto => {
            Err(SolveError::Unavailable { backend: "auto".into(), hint: "no backend is compiled in".into() })
        }
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
