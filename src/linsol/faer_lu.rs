//! faer's sparse LU: the pure-Rust backend, and the default where no native library is built in.
//!
//! A signed LDLᵀ is not used: it assumes K is positive definite, which fails here (a bar node's
//! transverse DOF has K_ii = 0 and is held only by the multipliers). LU with partial pivoting
//! handles the zero block and the zero-stiffness DOFs.

use super::{Backend, Failure, LinearSolver};
use crate::assembly::{CscMatrix, CscPattern};
use crate::error::SolveError;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use std::sync::Arc;

#[derive(Default)]
pub struct FaerLu {
    pattern: Option<Arc<CscPattern>>,
    symbolic: Option<SymbolicLu<usize>>,
    numeric: Option<Lu<usize, f64>>,
}

fn backend_error(message: String) -> Failure {
    Failure::Other(SolveError::Backend { backend: "faer", message })
}

impl LinearSolver for FaerLu {
    fn backend(&self) -> Backend {
        Backend::Faer
    }

    fn analyse(&mut self, pattern: &Arc<CscPattern>) -> Result<(), Failure> {
        let n = pattern.n();
        let symbolic = SymbolicSparseColMatRef::new_checked(n, n, pattern.col_ptr(), None, pattern.row_idx());
        let lu = SymbolicLu::try_new(symbolic).map_err(|e| backend_error(format!("symbolic analysis: {e:?}")))?;
        self.symbolic = Some(lu);
        self.pattern = Some(pattern.clone());
        self.numeric = None;
        Ok(())
    }

    fn factorize(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        let (Some(symbolic), Some(pattern)) = (&self.symbolic, &self.pattern) else {
            return Err(backend_error("factorize called before analyse".into()));
        };
        let n = pattern.n();
        let structure = SymbolicSparseColMatRef::new_checked(n, n, pattern.col_ptr(), None, pattern.row_idx());
        let a = SparseColMatRef::new(structure, &matrix.values);
        match Lu::try_new_with_symbolic(symbolic.clone(), a) {
            Ok(lu) => {
                self.numeric = Some(lu);
                Ok(())
            }
            Err(faer::sparse::linalg::LuError::SymbolicSingular { index }) => {
                Err(Failure::Singular { equations: vec![index] })
            }
            Err(e) => Err(backend_error(format!("numeric factorisation: {e:?}"))),
        }
    }

    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        let Some(lu) = &self.numeric else {
            return Err(backend_error("solve called before factorize".into()));
        };
        let mut x = rhs.to_vec();
        let n = x.len();
        lu.solve_in_place(faer::MatMut::from_column_major_slice_mut(&mut x, n, 1));
        Ok(x)
    }
}
