//! UMFPACK (SuiteSparse, Debian's `libsuitesparse-dev`), unsymmetric LU through the 64-bit `dl`
//! interface.
//!
//! The symbolic analysis is done once per pattern and kept; each new set of values gets a numeric
//! factorisation. The matrix arrives already compressed (the assembler refills its values through a
//! precomputed triplet → CSC map), so nothing is re-sorted here. A singular-matrix warning is an
//! error.

use crate::error::{Phase, SolveError};
use crate::linsol::csc::CscMatrix;
use crate::linsol::{Backend, Failure, LinearSolver};
use geoslip_sys::umfpack as ffi;
use std::os::raw::c_void;

const CONTROL: usize = ffi::UMFPACK_CONTROL as usize;
const INFO: usize = ffi::UMFPACK_INFO as usize;

/// One UMFPACK solver: the symbolic and numeric objects it owns, and the arrays they refer to.
pub struct Umfpack {
    n: usize,
    ap: Vec<i64>,
    ai: Vec<i64>,
    /// Values of the factorised matrix (UMFPACK's solve uses them for iterative refinement).
    ax: Vec<f64>,
    symbolic: *mut c_void,
    numeric: *mut c_void,
    control: [f64; CONTROL],
    info: [f64; INFO],
}

fn backend_error(message: String) -> Failure {
    Failure::Other(SolveError::Backend { backend: "umfpack", message })
}

impl Default for Umfpack {
    fn default() -> Self {
        let mut control = [0.0; CONTROL];
        // SAFETY: umfpack_dl_defaults writes UMFPACK_CONTROL entries into the array it is given.
        unsafe { ffi::umfpack_dl_defaults(control.as_mut_ptr()) };
        Umfpack {
            n: 0,
            ap: Vec::new(),
            ai: Vec::new(),
            ax: Vec::new(),
            symbolic: std::ptr::null_mut(),
            numeric: std::ptr::null_mut(),
            control,
            info: [0.0; INFO],
        }
    }
}

impl Umfpack {
    fn free_numeric(&mut self) {
        if !self.numeric.is_null() {
            // SAFETY: `numeric` came from umfpack_dl_numeric and is freed once, then nulled.
            unsafe { ffi::umfpack_dl_free_numeric(&mut self.numeric) };
            self.numeric = std::ptr::null_mut();
        }
    }

    fn free_symbolic(&mut self) {
        if !self.symbolic.is_null() {
            // SAFETY: `symbolic` came from umfpack_dl_symbolic and is freed once, then nulled.
            unsafe { ffi::umfpack_dl_free_symbolic(&mut self.symbolic) };
            self.symbolic = std::ptr::null_mut();
        }
    }

    /// Entries in L and U after the last factorisation.
    pub fn factor_entries(&self) -> u64 {
        (self.info[ffi::UMFPACK_LNZ as usize] + self.info[ffi::UMFPACK_UNZ as usize]).max(0.0) as u64
    }
}

impl LinearSolver for Umfpack {
    fn backend(&self) -> Backend {
        Backend::Umfpack
    }

    fn analyse(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        self.free_numeric();
        self.free_symbolic();
        let p = &matrix.pattern;
        self.n = p.n();
        self.ap = p.col_ptr().iter().map(|&v| v as i64).collect();
        self.ai = p.row_idx().iter().map(|&v| v as i64).collect();
        self.ax = matrix.values.clone();
        let n = self.n as i64;
        // SAFETY: ap/ai/ax describe a valid n × n CSC matrix (checked when the pattern was built)
        // and outlive the call; control and info have the sizes UMFPACK expects.
        let status = unsafe {
            ffi::umfpack_dl_symbolic(
                n,
                n,
                self.ap.as_ptr(),
                self.ai.as_ptr(),
                self.ax.as_ptr(),
                &mut self.symbolic,
                self.control.as_ptr(),
                self.info.as_mut_ptr(),
            )
        };
        if status != 0 || self.symbolic.is_null() {
            self.symbolic = std::ptr::null_mut();
            return Err(Failure::Other(SolveError::umfpack(Phase::Analysis, status)));
        }
        Ok(())
    }

    fn factorize(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        if self.symbolic.is_null() || matrix.values.len() != self.ai.len() {
            return Err(backend_error("factorize called before analyse, or with another pattern".into()));
        }
        self.free_numeric();
        self.ax.copy_from_slice(&matrix.values);
        // SAFETY: as in `analyse`; `symbolic` is live and belongs to this pattern.
        let status = unsafe {
            ffi::umfpack_dl_numeric(
                self.ap.as_ptr(),
                self.ai.as_ptr(),
                self.ax.as_ptr(),
                self.symbolic,
                &mut self.numeric,
                self.control.as_ptr(),
                self.info.as_mut_ptr(),
            )
        };
        if status == ffi::UMFPACK_WARNING_singular_matrix as i64 {
            self.free_numeric();
            return Err(Failure::Singular { equations: Vec::new() });
        }
        if status < 0 || self.numeric.is_null() {
            self.numeric = std::ptr::null_mut();
            return Err(Failure::Other(SolveError::umfpack(Phase::Factorisation, status)));
        }
        Ok(())
    }

    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        if self.numeric.is_null() || rhs.len() != self.n {
            return Err(backend_error("solve called without a factorisation of this size".into()));
        }
        let mut x = vec![0.0; self.n];
        // SAFETY: x and rhs have n entries; `numeric` is live; ap/ai/ax are the factorised matrix.
        let status = unsafe {
            ffi::umfpack_dl_solve(
                ffi::UMFPACK_A as i64,
                self.ap.as_ptr(),
                self.ai.as_ptr(),
                self.ax.as_ptr(),
                x.as_mut_ptr(),
                rhs.as_ptr(),
                self.numeric,
                self.control.as_ptr(),
                self.info.as_mut_ptr(),
            )
        };
        if status != 0 {
            return Err(Failure::Other(SolveError::umfpack(Phase::Solution, status)));
        }
        Ok(x)
    }

    fn factor_entries(&self) -> Option<u64> {
        (!self.numeric.is_null()).then(|| Umfpack::factor_entries(self))
    }
}

impl Drop for Umfpack {
    fn drop(&mut self) {
        self.free_numeric();
        self.free_symbolic();
    }
}

// SAFETY: the objects are only reached through `&mut self`; UMFPACK keeps no global state.
unsafe impl Send for Umfpack {}

#[cfg(test)]
mod tests {
    //! UMFPACK's own statuses, as UMFPACK returns them, come back typed.
    use super::*;
    use crate::error::UmfpackStatus;
    use crate::linsol::csc::{PatternCache, Triplets};

    #[test]
    fn an_empty_matrix_is_umfpacks_n_nonpositive_status() {
        let a = PatternCache::default().assemble(0, &Triplets::default()).0;
        match Umfpack::default().analyse(&a) {
            Err(Failure::Other(e @ SolveError::Umfpack { phase: Phase::Analysis, status: -6, .. })) => {
                assert!(matches!(e, SolveError::Umfpack { code: UmfpackStatus::OrderNotPositive, .. }));
                assert!(e.to_string().contains("UMFPACK_ERROR_n_nonpositive"), "{e}");
            }
            other => panic!("expected UMFPACK's status -6, got {:?}", other.err()),
        }
    }
}
