//! Why an iteration's system is not solved condensed: the full system's solve takes over, with its
//! own recoveries and diagnosis. A backend that fails outright is another matter
//! ([`CondensedError::Backend`]): the run stops condensing.

use crate::error::SolveError;
use crate::linsol::Failure;

/// Why this system is not solved condensed (the full system is).
#[derive(Debug, Clone, PartialEq)]
pub enum Fallback {
    /// This soil on these kept unknowns failed to condense before, and is not tried again.
    SoilFailedBefore,
    /// The soil's interior is singular: the soil alone cannot hold it (the interior's equation
    /// numbers, in the reduced soil, would mean nothing to the caller).
    InteriorSingular,
    /// A whole solve's relative residual, after refinement, is not below 1e-6 (or not finite):
    /// the interface system S + C is numerically singular or too ill-conditioned.
    Inaccurate { residual: f64 },
    /// The same for the kept system solved alone.
    KeptInaccurate { residual: f64 },
    /// Nothing is condensed yet.
    NotCondensed,
    /// The soil condensed is not the one asked for.
    OtherSoil,
}

/// A condensed solve that did not give a solution.
#[derive(Debug, Clone)]
pub enum CondensedError {
    /// The full system takes over for this solve.
    Fallback(Fallback),
    /// The backend failed: the run goes on without condensing.
    Backend(SolveError),
}

impl From<Fallback> for CondensedError {
    fn from(f: Fallback) -> Self {
        CondensedError::Fallback(f)
    }
}

impl From<Failure> for CondensedError {
    /// A backend's failure in the condensation: a singular matrix there is the soil's interior.
    fn from(f: Failure) -> Self {
        match f {
            Failure::Singular { .. } => CondensedError::Fallback(Fallback::InteriorSingular),
            Failure::Other(e) => CondensedError::Backend(e),
        }
    }
}
