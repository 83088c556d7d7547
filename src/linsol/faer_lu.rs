//! faer's sparse LU: the pure-Rust backend, and the default where no native library is built in.
//!
//! A signed LDLᵀ is not used: it assumes K is positive definite, which fails here (a bar node's
//! transverse DOF has K_ii = 0 and is held only by the multipliers). LU with partial pivoting
//! handles the zero block and the zero-stiffness DOFs.

use super::{Backend, Failure, LinearSolver};
use crate::error::SolveError;
use crate::linsol::csc::{CscMatrix, CscPattern};
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

    fn analyse(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        let pattern = &matrix.pattern;
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

#[cfg(test)]
mod tests {
    //! faer on the saddle-point structure of the paper's Eq. (5): the multiplier block is exactly zero
    //! and K has a zero-stiffness DOF (a bar node's transverse DOF, held only by a multiplier).
    use super::*;
    use crate::linsol::csc::{PatternCache, Triplets};
    use crate::linsol::dense_ref::DenseReference;

    /// Unknowns: u0 (bar node, axial), u1 (bar node, transverse: K = 0), u2 (soil node, vertical),
    /// λ (ties u1 to u2).
    ///
    /// ```text
    /// [ 3  0  0   0 ] {u0}   {1}
    /// [ 0  0  0   1 ] {u1} = {0}
    /// [ 0  0  2  -1 ] {u2}   {4}
    /// [ 0  1 -1   0 ] {λ }   {0}
    /// ```
    /// By hand: row 1 gives u0 = 1/3, row 2 gives λ = 0, row 3 then u2 = 2, row 4 u1 = u2 = 2.
    fn system() -> (CscMatrix, Vec<f64>, Vec<f64>) {
        let mut t = Triplets::default();
        t.push(0, 0, 3.0);
        t.push(1, 1, 0.0); // the zero-stiffness DOF, kept in the pattern
        t.push(1, 3, 1.0);
        t.push(2, 2, 2.0);
        t.push(2, 3, -1.0);
        t.push(3, 1, 1.0);
        t.push(3, 2, -1.0);
        t.push(3, 3, 0.0); // the zero block, exactly zero
        let a = PatternCache::default().assemble(4, &t).0;
        (a, vec![1.0, 0.0, 4.0, 0.0], vec![1.0 / 3.0, 2.0, 2.0, 0.0])
    }

    #[test]
    fn faer_solves_a_saddle_point_with_zero_block_and_zero_stiffness_dof() {
        let (a, b, exact) = system();
        let mut s = FaerLu::default();
        s.analyse(&a).unwrap();
        s.factorize(&a).unwrap();
        let x = s.solve(&b).unwrap();
        for (v, e) in x.iter().zip(&exact) {
            assert!((v - e).abs() < 1e-14, "{x:?}");
        }
        let mut d = DenseReference::default();
        d.analyse(&a).unwrap();
        d.factorize(&a).unwrap();
        assert_eq!(d.solve(&b).unwrap().len(), 4);
    }

    #[test]
    fn faer_reuses_its_symbolic_analysis_for_new_values() {
        let (mut a, b, _) = system();
        let mut s = FaerLu::default();
        s.analyse(&a).unwrap();
        s.factorize(&a).unwrap();
        // double K's entries: same pattern, u0 = 1/6, u2 = 1 (λ = 0), u1 = 1
        let p = a.pattern.clone();
        for j in 0..4 {
            for k in p.col_ptr()[j]..p.col_ptr()[j + 1] {
                let i = p.row_idx()[k];
                if i < 3 && j < 3 {
                    a.values[k] *= 2.0;
                }
            }
        }
        s.factorize(&a).unwrap();
        let x = s.solve(&b).unwrap();
        for (v, e) in x.iter().zip([1.0 / 6.0, 1.0, 1.0, 0.0]) {
            assert!((v - e).abs() < 1e-14, "{x:?}");
        }
    }
}
