//! The linear system of a run: a backend with the bookkeeping that lets it skip work (a new symbolic
//! analysis only for a new pattern, a new factorisation only for new values), the check of every
//! solution's residual with iterative refinement, and the counts and times the run summary reports.

use super::csc::{CscMatrix, PatternCache, Triplets};
use super::refine::{accepted, refine, Refinable};
use super::{Backend, Failure, LinearSolver};
use crate::error::SolveError;
use std::time::Instant;

/// Counts and times of the linear-algebra work, for the run summary.
#[derive(Debug, Default, Clone, serde::Serialize)]
pub struct SolverStats {
    pub analyses: usize,
    pub factorizations: usize,
    pub solves: usize,
    pub analyse_seconds: f64,
    pub factorize_seconds: f64,
    pub solve_seconds: f64,
    pub max_relative_residual: f64,
    /// Time building the triplets and refilling the CSC matrix.
    pub assembly_seconds: f64,
    /// Time checking each linear solution's residual ‖Ax−b‖/‖b‖ (and refining it).
    pub check_seconds: f64,
    /// MUMPS's estimate of its factorisation memory after the last analysis, MB.
    pub estimated_memory_mb: Option<f64>,
    /// Memory MUMPS's last factorisation used (INFOG(22)), MB.
    pub factor_memory_mb: Option<f64>,
    /// Entries in the factors of the last factorisation, where the backend reports them.
    pub factor_entries: Option<u64>,
    /// The run's matrices are symmetric: MUMPS factorises them as LDLᵀ (SYM=2) instead of LU; the
    /// other backends use LU either way.
    pub symmetric: bool,
    /// Condensed solves (the interface iteration): the dense LU factorisations of the interface
    /// system, and the time in them and in the dense solves.
    pub dense_factorizations: usize,
    /// Changes of the interface system taken as low-rank updates of its last factorisation.
    pub dense_updates: usize,
    /// BiCGSTAB iterations on interface systems that drifted from the last factorisation (each
    /// preconditioned by it: `linsol/condensed/updated_lu.rs`).
    pub dense_iterations: usize,
    pub dense_seconds: f64,
    /// The part of `dense_seconds` in the factorisations, and in the BiCGSTAB iterations.
    pub dense_factorization_seconds: f64,
    pub dense_iteration_seconds: f64,
    /// Unknowns the condensed system kept (the interface's), when a run condensed its soil.
    pub condensed_unknowns: Option<usize>,
}

/// A solver backend with the bookkeeping that lets it skip work: a new analysis only for a new
/// pattern, a new factorisation only for new values. Its counts and times go to the run's
/// [`SolverStats`], which each call is handed.
pub struct LinearSystem {
    solver: Box<dyn LinearSolver>,
    patterns: PatternCache,
    factorized: Option<CscMatrix>,
    /// The last factorisation's negative pivots and active multipliers, when they differ.
    inertia_mismatch: Option<(usize, usize)>,
}

impl LinearSystem {
    /// A solver for matrices that are `symmetric` or not (MUMPS: SYM=2 or SYM=0; the run's
    /// [`SolverStats::symmetric`] says which).
    pub fn new(backend: Backend, symmetric: bool, options: &super::SolverOptions) -> Result<Self, SolveError> {
        Ok(LinearSystem {
            solver: super::make(backend, symmetric, options)?,
            patterns: PatternCache::default(),
            factorized: None,
            inertia_mismatch: None,
        })
    }

    pub fn backend(&self) -> Backend {
        self.solver.backend()
    }

    /// Solve A x = b for the assembled triplets, of which `active_multipliers` rows hold a
    /// constraint (zero diagonal). Returns x and the relative residual. The list is let go once
    /// the matrix is built, before the analysis and factorisation.
    pub fn solve(
        &mut self,
        stats: &mut SolverStats,
        n: usize,
        triplets: Triplets,
        rhs: &[f64],
        active_multipliers: usize,
    ) -> Result<(Vec<f64>, f64), Failure> {
        let t = Instant::now();
        let (matrix, new_pattern) = self.patterns.assemble(n, &triplets);
        drop(triplets);
        stats.assembly_seconds += t.elapsed().as_secs_f64();
        if new_pattern {
            let t = Instant::now();
            let analysed = self.solver.analyse(&matrix);
            stats.estimated_memory_mb = self.solver.estimated_memory_mb();
            analysed?;
            stats.analyses += 1;
            stats.analyse_seconds += t.elapsed().as_secs_f64();
            self.factorized = None;
        }
        let same_values = self.factorized.as_ref().is_some_and(|f| f.values == matrix.values);
        if !same_values {
            // a failed factorisation leaves nothing to reuse
            self.factorized = None;
            let t = Instant::now();
            self.solver.factorize(&matrix)?;
            stats.factorizations += 1;
            stats.factor_entries = self.solver.factor_entries();
            stats.factor_memory_mb = self.solver.factor_memory_mb();
            // Inertia check (DESIGN §2): the negative pivots equal the active multipliers when Kc has
            // full row rank, K is positive definite on its null space, supports are eliminated and no
            // tangent is negative. A mismatch is worth knowing, not an error: the run warns of it.
            if let Some(negative) = self.solver.negative_pivots() {
                if negative != active_multipliers {
                    self.inertia_mismatch = Some((negative, active_multipliers));
                }
            }
            stats.factorize_seconds += t.elapsed().as_secs_f64();
        }
        self.factorized = Some(matrix);
        self.solve_again(stats, rhs)
    }

    /// The negative pivots and active multipliers of a factorisation since the last call, when
    /// they differed.
    pub fn take_inertia_mismatch(&mut self) -> Option<(usize, usize)> {
        self.inertia_mismatch.take()
    }

    /// Solve with the matrix of the last [`LinearSystem::solve`] and its factorisation, for a new
    /// right-hand side: the constant-stiffness iterations, whose matrix does not change.
    pub fn solve_again(&mut self, stats: &mut SolverStats, rhs: &[f64]) -> Result<(Vec<f64>, f64), Failure> {
        let Some(matrix) = self.factorized.as_ref() else {
            return Err(Failure::Other(SolveError::Backend {
                backend: self.solver.backend().name(),
                message: "solve_again called before a factorisation".into(),
            }));
        };
        let t = Instant::now();
        let x = self.solver.solve(rhs)?;
        stats.solve_seconds += t.elapsed().as_secs_f64();
        stats.solves += 1;
        // the residual checks are geoslip's own work, counted apart from the backend's solves
        // (the refinement's correcting solves are counted as solves too)
        let t = Instant::now();
        let mut full = FullSystem { solver: self.solver.as_mut(), matrix, stats: &mut *stats };
        let (x, residual) = refine(&mut full, x, rhs)?;
        stats.check_seconds += t.elapsed().as_secs_f64();
        if !accepted(&x, residual) {
            // A numerically singular matrix: LU divides by a (near) zero pivot. The backend named
            // no pivots: the analysis finds them (`analysis::singular`).
            return Err(Failure::Singular { equations: Vec::new() });
        }
        stats.max_relative_residual = stats.max_relative_residual.max(residual);
        Ok((x, residual))
    }
}

/// The full system as [`refine`] sees it: its matrix and the backend's factorisation of it.
struct FullSystem<'a> {
    solver: &'a mut dyn LinearSolver,
    matrix: &'a CscMatrix,
    stats: &'a mut SolverStats,
}

impl Refinable for FullSystem<'_> {
    type Error = Failure;

    fn residual(&self, x: &[f64], rhs: &[f64]) -> Vec<f64> {
        let ax = self.matrix.mul_vec(x);
        rhs.iter().zip(&ax).map(|(b, a)| b - a).collect()
    }

    fn correct(&mut self, r: &[f64]) -> Result<Vec<f64>, Failure> {
        let t = Instant::now();
        let dx = self.solver.solve(r)?;
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        self.stats.solves += 1;
        Ok(dx)
    }
}
