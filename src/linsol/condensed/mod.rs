//! The interface iteration's linear algebra: a system whose matrix is the soil L, fixed while the
//! soil is elastic, and a part C that changes from one solve to the next but only among a few kept
//! unknowns K,
//!
//! ```text
//! A = L + C,   C zero outside the kept rows and columns K.
//! ```
//!
//! L is condensed onto K once per soil; each new C costs one dense factorisation of S + C_KK (or
//! an update of the last one), and each right-hand side one condensation, one dense solve and one
//! expansion. This is how the interface iteration gets Newton's tangent at the cost of solves: the
//! soil is L, the interface's springs and rows are C. [`CondensedSystem`] is the one way in.
//!
//! The concepts, in the order the code applies them:
//! 1. the kept unknowns K ([`KeptUnknowns`], `kept.rs`);
//! 2. L split into the kept unknowns its interior reaches (K₁) and the others (K₂), which need no
//!    condensing (`coupled.rs`);
//! 3. the soil's Schur complement **S** = L_KK − L_KI L_II⁻¹ L_IK: MUMPS's own (ICNTL(19)), or block
//!    elimination over any backend's factorisation (`elimination.rs`); reused when the reduced L
//!    is the same;
//! 4. S held as a dense block and its few entries outside it (`SoilSchur`), C by columns, and the
//!    kept system M = S + C as an operator (`kept_matrix.rs`);
//! 5. M's factorisation, its sparse unknowns eliminated first and the rest dense (`block_lu.rs`);
//! 6. M kept across changes of C: a low-rank update, BiCGSTAB preconditioned by the last
//!    factorisation, or a new factorisation (`updated_lu.rs`);
//! 7. a whole solve: condense, solve densely, expand, checked against L + C itself and refined
//!    (`linsol::refine`), so that it is never less accurate than a direct solve (`ready.rs`);
//! 8. the kept system solved alone ([`CondensedSystem::solve_kept`]), and the interior following
//!    the kept unknowns' movement ([`CondensedSystem::follow`]);
//! 9. [`Fallback`]: why a system is not solved here, and the full system's solve takes over.

mod block_lu;
pub(in crate::linsol) mod condensing;
mod coupled;
mod elimination;
mod fallback;
mod kept;
mod kept_matrix;
mod parts;
mod ready;
mod updated_lu;

pub use fallback::{CondensedError, Fallback};
pub use kept::KeptUnknowns;
pub use parts::{InterfacePart, KeptSolution, SoilPart};

use super::csc::PatternCache;
use super::linear_system::SolverStats;
use super::{Backend, SolverOptions};
use crate::error::SolveError;
use condensing::Condensing;
use coupled::CoupledKept;
use elimination::make_condensing;
use ready::{CondensedSoil, Ready};
use std::rc::Rc;
use std::time::Instant;

/// The soil condensed onto the interface's unknowns, and the interface system's factorisation:
/// the linear algebra of the interface iteration (module comment).
pub struct CondensedSystem {
    condensing: Box<dyn Condensing>,
    /// The soil as last condensed, with the interface system's factorisation on it.
    soil: Option<CondensedSoil>,
    /// The soil (its key and kept unknowns) whose condensation failed: not tried again.
    failed: Option<(u64, Rc<KeptUnknowns>)>,
}

impl CondensedSystem {
    /// A condensed system on `backend` (MUMPS's Schur complement, or block elimination on the
    /// others).
    ///
    /// # Errors
    /// The backend's error when it cannot be started.
    pub fn new(backend: Backend, options: &SolverOptions) -> Result<Self, SolveError> {
        Ok(CondensedSystem { condensing: make_condensing(backend, options)?, soil: None, failed: None })
    }

    pub fn backend(&self) -> Backend {
        self.condensing.backend()
    }

    /// The kept unknowns and the key of the soil last condensed.
    pub fn condensed_on(&self) -> Option<(&Rc<KeptUnknowns>, u64)> {
        self.soil.as_ref().map(|s| (&s.kept, s.key))
    }

    /// Solve (L + C) x = b. Returns x and ‖Ax − b‖/‖b‖ for the matrix solved with.
    ///
    /// # Errors
    /// A [`Fallback`] (the soil's interior is singular; the solution does not meet a relative
    /// residual of 1e-6 after refinement), or the backend's error.
    pub fn solve(
        &mut self,
        stats: &mut SolverStats,
        soil: &SoilPart,
        interface: &InterfacePart,
        rhs: &[f64],
    ) -> Result<(Vec<f64>, f64), CondensedError> {
        stats.condensed_unknowns = Some(soil.kept.len());
        self.condense(stats, soil)?;
        let mut ready = self.ready(stats, interface, soil.times)?;
        ready.solve(rhs)
    }

    /// Solve (S + C_KK) x_K = r_K on the kept unknowns alone: an iteration whose interior is
    /// already in balance, on the soil condensed for `soil_key`. Returns x_K, its relative residual
    /// on the kept system, and S·x_K (the change of the soil's force on the kept unknowns; the
    /// residual's check computes it). Lets go of L's matrix: a later whole solve checks its
    /// residual with the caller's product of L.
    ///
    /// # Errors
    /// A [`Fallback`]: the soil condensed is not `soil_key`'s, or the kept system's residual
    /// exceeds 1e-6.
    pub fn solve_kept(
        &mut self,
        stats: &mut SolverStats,
        soil_key: u64,
        interface: &InterfacePart,
        rhs_kept: &[f64],
    ) -> Result<KeptSolution, CondensedError> {
        let soil = self.soil.as_mut().ok_or(Fallback::NotCondensed)?;
        if soil.key != soil_key {
            return Err(Fallback::OtherSoil.into());
        }
        soil.matrix = None;
        // (no whole solve follows here: L's product is never asked for)
        let unused = |_: &[f64]| Vec::new();
        let mut ready = self.ready(stats, interface, &unused)?;
        ready.solve_kept(rhs_kept)
    }

    /// The diagonal of the soil L last condensed (every equation); `None` when L's matrix has been
    /// let go (an interface iteration solved the kept system alone since).
    pub fn linear_diagonal(&self) -> Option<Vec<f64>> {
        let matrix = self.soil.as_ref()?.matrix.as_ref()?;
        let pattern = &matrix.pattern;
        let mut diagonal = vec![0.0; pattern.n()];
        for (j, d) in diagonal.iter_mut().enumerate() {
            let entries = pattern.col_ptr()[j]..pattern.col_ptr()[j + 1];
            for k in entries {
                if pattern.row_idx()[k] == j {
                    *d += matrix.values[k];
                }
            }
        }
        Some(diagonal)
    }

    /// The whole correction when the kept unknowns moved by `moved` with the interior following in
    /// balance: x_I = −L_II⁻¹ L_IK·moved, x_K = moved. One condensation of nothing and one
    /// expansion.
    ///
    /// # Errors
    /// [`Fallback::NotCondensed`], or the backend's failure.
    pub fn follow(&mut self, stats: &mut SolverStats, moved: &[f64]) -> Result<Vec<f64>, CondensedError> {
        let soil = self.soil.as_ref().ok_or(Fallback::NotCondensed)?;
        let zero = vec![0.0; soil.kept.n()];
        let t = Instant::now();
        soil.coupled.condense(self.condensing.as_mut(), &zero)?;
        let x = soil.coupled.expand(self.condensing.as_mut(), &zero, moved)?;
        stats.solve_seconds += t.elapsed().as_secs_f64();
        stats.solves += 1;
        Ok(x)
    }

    /// Condense L when its key (or the kept unknowns) is new. A new soil drops the interface
    /// system's factorisation made on the last one.
    fn condense(&mut self, stats: &mut SolverStats, part: &SoilPart) -> Result<(), CondensedError> {
        let kept = part.kept;
        let current = self.soil.as_ref().is_some_and(|s| s.key == part.key && *s.kept == **kept);
        if current {
            return Ok(());
        }
        if self.failed.as_ref().is_some_and(|(key, list)| *key == part.key && **list == **kept) {
            return Err(Fallback::SoilFailedBefore.into());
        }
        // the last condensation, whose factorisation a new L with the same reduced L reuses
        let last = self.soil.take().map(|s| (s.schur, s.coupled));
        let t = Instant::now();
        let triplets = (part.assemble)();
        // a pattern cache would keep its refill map for the next soil, which comes seldom
        let (matrix, _) = PatternCache::default().assemble(kept.n(), &triplets);
        drop(triplets);
        stats.assembly_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let (schur, coupled, reused) = match CoupledKept::condense_onto(self.condensing.as_mut(), &matrix, kept, last) {
            Ok(s) => s,
            Err(e) => {
                self.failed = Some((part.key, kept.clone()));
                return Err(e.into());
            }
        };
        if !reused {
            stats.analyses += 1;
            stats.factorizations += 1;
        }
        stats.factorize_seconds += t.elapsed().as_secs_f64();
        self.soil = Some(CondensedSoil {
            key: part.key,
            kept: kept.clone(),
            matrix: Some(matrix),
            schur,
            coupled,
            interface: None,
        });
        Ok(())
    }

    /// The condensed soil with the interface system factorised for `interface.key` (assembling C
    /// only when the key is new): ready to solve.
    fn ready<'a>(
        &'a mut self,
        stats: &'a mut SolverStats,
        interface: &InterfacePart,
        linear_times: &'a dyn Fn(&[f64]) -> Vec<f64>,
    ) -> Result<Ready<'a>, CondensedError> {
        let backend = self.condensing.backend();
        let soil = self.soil.as_mut().ok_or(Fallback::NotCondensed)?;
        Ready::prepare(self.condensing.as_mut(), soil, stats, interface, linear_times).map_err(|(i, j)| {
            CondensedError::Backend(SolveError::Backend {
                backend: backend.name(),
                message: format!("an entry ({i}, {j}) of the changing part lies outside the kept unknowns"),
            })
        })
    }
}

#[cfg(test)]
mod tests;
