//! MUMPS (Debian's sequential `libmumps-seq-dev`, or with the `mpi` feature its MPI build
//! `libmumps-dev`), symmetric indefinite (SYM=2, lower triangle) or unsymmetric (SYM=0).
//!
//! In the MPI build every call is announced to the other ranks first (`cluster.rs`), which make the
//! same call: the matrix and right-hand side stay on rank 0 (centralised input).
//!
//! Settings that were measured to matter (shared/DESIGN.md §2): PAR=1; 1-based indices and a 64-bit
//! `nnz`; JOB −1 once, JOB 1 once per pattern, JOB 2 for each new set of values, JOB 3 for each
//! right-hand side; ICNTL(7) set explicitly (3 = Scotch), ICNTL(8)=7, ICNTL(13)=1, ICNTL(24)=1
//! (null-pivot detection). With ICNTL(24)=1 a singular matrix is reported as *success* with
//! INFOG(28) > 0 null pivots, listed in PIVNUL_LIST: that is turned into a singular-model error. On
//! INFOG(1) = −8 or −9 ICNTL(14) is doubled and only the factorisation is redone, a bounded number of
//! times.

use crate::error::{Phase, SolveError};
use crate::linsol::csc::CscMatrix;
use crate::linsol::{Backend, Failure, LinearSolver, Ordering, SolverOptions};
use crate::memory::{available_memory_mb, resident_memory_mb};
use geoslip_sys::mumps as ffi;
use std::ffi::CStr;
use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};

/// Fortran communicator value that tells MUMPS to use MPI_COMM_WORLD (the sequential stub's only
/// communicator).
const USE_COMM_WORLD: i32 = -987654;
/// How many times a factorisation is retried with a doubled ICNTL(14).
const WORKSPACE_RETRIES: usize = 6;
/// Numbers MUMPS instances, so that the other ranks of an MPI run can tell them apart.
static NEXT_INSTANCE: AtomicU64 = AtomicU64::new(1);

/// What the last factorisation reported.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FactorInfo {
    /// INFOG(12): negative pivots (SYM=2).
    pub negative_pivots: i64,
    /// INFOG(29): entries in the factors.
    pub factor_entries: i64,
    /// INFOG(22): memory used by the factorisation, MB (summed over the ranks of an MPI run).
    pub memory_mb: i64,
    /// INFOG(17) (INFOG(27) out of core): the analysis's estimate of that memory, MB.
    pub estimated_memory_mb: i64,
    /// ICNTL(14) that the factorisation finally ran with.
    pub workspace_percent: i32,
    /// How many times the factorisation was retried with more workspace.
    pub workspace_retries: usize,
}

/// One MUMPS instance: the handle, and the index and value arrays it points into.
pub struct Mumps {
    id: Box<ffi::DMUMPS_STRUC_C>,
    instance: u64,
    symmetric: bool,
    options: SolverOptions,
    n: usize,
    /// CSC entry positions passed to MUMPS (all of them, or the lower triangle for SYM=2).
    positions: Vec<usize>,
    irn: Vec<i32>,
    jcn: Vec<i32>,
    a: Vec<f64>,
    analysed: bool,
    factorized: bool,
    /// ICNTL(14) to use, possibly raised by earlier retries.
    workspace_percent: i32,
    /// CNTL(1), the relative threshold for numerical pivoting (None: MUMPS's default, 0.01).
    pivot_threshold: Option<f64>,
    /// How many times a factorisation may be retried with a doubled ICNTL(14).
    workspace_retries: usize,
    pub info: FactorInfo,
    /// The Schur variables (1-based; empty: no Schur complement), the complement MUMPS writes into
    /// (ICNTL(19) = 1, row by row), the reduced right-hand side (ICNTL(26)) and the right-hand side
    /// between condensation and expansion.
    schur_list: Vec<i32>,
    schur: Vec<f64>,
    reduced_rhs: Vec<f64>,
    condensed_rhs: Vec<f64>,
}

fn icntl(id: &mut ffi::DMUMPS_STRUC_C, i: usize, value: i32) {
    id.icntl[i - 1] = value;
}

fn infog(id: &ffi::DMUMPS_STRUC_C, i: usize) -> i32 {
    id.infog[i - 1]
}

fn backend_error(message: String) -> Failure {
    Failure::Other(SolveError::Backend { backend: "mumps", message })
}

impl Mumps {
    /// Start an instance (JOB = −1) and check that the library is the version the build's header
    /// describes.
    ///
    /// # Errors
    /// A backend error with MUMPS's message, or a version mismatch.
    pub fn new(symmetric: bool, options: &SolverOptions) -> Result<Mumps, SolveError> {
        let (id, instance) =
            start_instance(symmetric).map_err(|(code, info2)| SolveError::mumps(Phase::Initialisation, code, info2))?;
        let mut mumps = Mumps {
            id,
            instance,
            symmetric,
            options: options.clone(),
            n: 0,
            positions: Vec::new(),
            irn: Vec::new(),
            jcn: Vec::new(),
            a: Vec::new(),
            analysed: false,
            factorized: false,
            workspace_percent: 20,
            pivot_threshold: None,
            workspace_retries: WORKSPACE_RETRIES,
            info: FactorInfo::default(),
            schur_list: Vec::new(),
            schur: Vec::new(),
            reduced_rhs: Vec::new(),
            condensed_rhs: Vec::new(),
        };
        // Silence MUMPS's own printing from now on (JOB = −1 resets the controls to its defaults).
        mumps.set_controls();
        let built = CStr::from_bytes_until_nul(ffi::MUMPS_VERSION)
            .map(|c| c.to_string_lossy().into_owned())
            .unwrap_or_default();
        let running = mumps.version();
        if running.trim() != built.trim() {
            return Err(SolveError::Backend {
                backend: "mumps",
                message: format!(
                    "the MUMPS library is version {running} but geoslip was built against the {built} header; rebuild geoslip (cargo build --release)"
                ),
            });
        }
        Ok(mumps)
    }

    /// The library's version string (`version_number`).
    pub fn version(&self) -> String {
        let bytes: Vec<u8> = self.id.version_number.iter().take_while(|&&c| c != 0).map(|&c| c as u8).collect();
        String::from_utf8_lossy(&bytes).into_owned()
    }

    /// Force ICNTL(14) (percentage of workspace increase), to exercise the retry path.
    pub fn set_workspace_percent(&mut self, percent: i32) {
        self.workspace_percent = percent;
    }

    /// Limit the retries with a doubled ICNTL(14) (to exercise the error past them).
    pub fn set_workspace_retries(&mut self, retries: usize) {
        self.workspace_retries = retries;
    }

    /// Set CNTL(1), the relative threshold for numerical pivoting: larger is more stable and delays
    /// more pivots (MUMPS's default is 0.01; at most 0.5 for symmetric matrices).
    pub fn set_pivot_threshold(&mut self, threshold: f64) {
        self.pivot_threshold = Some(threshold);
    }

    fn set_controls(&mut self) {
        let id = &mut *self.id;
        if let Some(t) = self.pivot_threshold {
            id.cntl[0] = t;
        }
        icntl(id, 1, -1); // error messages: off (geoslip reports the codes)
        icntl(id, 2, -1); // diagnostics: off
        icntl(id, 3, -1); // global information: off
        icntl(id, 4, 0); // print level
        icntl(id, 7, self.options.ordering.icntl7());
        icntl(id, 8, 7); // scaling recomputed at each factorisation
        icntl(id, 13, 1);
        icntl(id, 14, self.workspace_percent);
        icntl(id, 22, i32::from(self.options.out_of_core)); // factors on disk
        icntl(id, 24, 1); // null-pivot detection
        icntl(id, 19, i32::from(!self.schur_list.is_empty())); // Schur complement by rows
        icntl(id, 26, 0);
        id.size_schur = self.schur_list.len() as i32;
        id.listvar_schur = if self.schur_list.is_empty() { std::ptr::null_mut() } else { self.schur_list.as_mut_ptr() };
        id.schur = if self.schur.is_empty() { std::ptr::null_mut() } else { self.schur.as_mut_ptr() };
    }

    /// After the analysis: stop when the factorisation would need more memory than the run may use.
    fn check_memory(&mut self) -> Result<(), Failure> {
        let id = &*self.id;
        // INFOG(17) / INFOG(27): estimated total of MUMPS's data for the factorisation, MB, in core /
        // out of core, summed over the ranks; a margin for ICNTL(14).
        let estimate = if self.options.out_of_core { infog(id, 27) } else { infog(id, 17) } as f64;
        self.info.estimated_memory_mb = estimate as i64;
        // what is left for the factorisation: the run's limit less what it already holds, or what the
        // machine has available now
        let left = match self.options.memory_limit_mb {
            Some(limit) => Some((limit - resident_memory_mb()).max(0.0)),
            None => available_memory_mb(),
        };
        let Some(limit) = left else { return Ok(()) };
        if estimate > limit {
            let hint = if self.options.out_of_core {
                "run it with geoslip-mpi on more machines (docs/cluster.md), or coarsen the mesh".to_string()
            } else {
                format!(
                    "try --out-of-core (MUMPS then estimates {} MB in memory), or geoslip-mpi on more machines (docs/cluster.md)",
                    infog(id, 27)
                )
            };
            return Err(Failure::Other(SolveError::OutOfMemory(Box::new(crate::error::MemoryShortfall {
                backend: "mumps",
                what: "the factorisation (MUMPS's estimate after its analysis)",
                needed_mb: estimate,
                available_mb: limit,
                hint,
            }))));
        }
        Ok(())
    }
}

/// A new MUMPS instance (JOB = −1) and its number, or INFOG(1) and INFOG(2) when that fails.
fn start_instance(symmetric: bool) -> Result<(Box<ffi::DMUMPS_STRUC_C>, u64), (i32, i64)> {
    let instance = NEXT_INSTANCE.fetch_add(1, AtomicOrdering::Relaxed);
    // SAFETY: DMUMPS_STRUC_C is a plain C struct of integers, floats, arrays and pointers, for which
    // all-zero is a valid value; MUMPS initialises it in JOB = −1.
    let mut id: Box<ffi::DMUMPS_STRUC_C> = Box::new(unsafe { std::mem::zeroed() });
    id.comm_fortran = USE_COMM_WORLD;
    id.par = 1;
    id.sym = if symmetric { 2 } else { 0 };
    id.job = -1;
    call(&mut id, instance);
    let code = infog(&id, 1);
    if code < 0 {
        let info2 = infog(&id, 2) as i64;
        // JOB = −1 failed: there is no instance to terminate.
        std::mem::forget(id);
        return Err((code, info2));
    }
    Ok((id, instance))
}

/// The one place that enters MUMPS: under the global lock, and in an MPI run after telling the other
/// ranks to make the same call.
fn call(id: &mut ffi::DMUMPS_STRUC_C, instance: u64) {
    let _guard = geoslip_sys::MUMPS_LOCK.lock().unwrap_or_else(|p| p.into_inner());
    #[cfg(feature = "mpi")]
    super::cluster::announce(instance, id);
    #[cfg(not(feature = "mpi"))]
    let _ = instance;
    // SAFETY: `id` is a live instance (JOB = −1 was called first, or this is that call); every
    // pointer in it was set by `Mumps` to a buffer it owns and keeps alive and unmoved until the next
    // call replaces it.
    unsafe { ffi::dmumps_c(id) };
}

impl LinearSolver for Mumps {
    fn backend(&self) -> Backend {
        Backend::Mumps
    }

    fn analyse(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        let p = &matrix.pattern;
        let n = p.n();
        if n > i32::MAX as usize {
            return Err(backend_error(format!("{n} unknowns exceed MUMPS's 32-bit indices")));
        }
        self.positions.clear();
        self.irn.clear();
        self.jcn.clear();
        for j in 0..n {
            for k in p.col_ptr()[j]..p.col_ptr()[j + 1] {
                let i = p.row_idx()[k];
                if !self.symmetric || i >= j {
                    self.positions.push(k);
                    self.irn.push(i as i32 + 1);
                    self.jcn.push(j as i32 + 1);
                }
            }
        }
        self.a = self.positions.iter().map(|&k| matrix.values[k]).collect();
        self.n = n;
        self.set_controls();
        let id = &mut *self.id;
        id.n = n as i32;
        id.nnz = self.irn.len() as i64;
        id.irn = self.irn.as_mut_ptr();
        id.jcn = self.jcn.as_mut_ptr();
        id.a = self.a.as_mut_ptr();
        id.job = 1;
        call(id, self.instance);
        let code = infog(id, 1);
        if code < 0 {
            self.analysed = false;
            return Err(Failure::Other(SolveError::mumps(Phase::Analysis, code, infog(id, 2) as i64)));
        }
        self.analysed = true;
        self.factorized = false;
        self.check_memory()
    }

    fn factorize(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        if !self.analysed {
            return Err(backend_error("factorize called before analyse".into()));
        }
        for (slot, &k) in self.a.iter_mut().zip(&self.positions) {
            *slot = matrix.values[k];
        }
        let mut retries = 0;
        loop {
            self.set_controls();
            let id = &mut *self.id;
            id.irn = self.irn.as_mut_ptr();
            id.jcn = self.jcn.as_mut_ptr();
            id.a = self.a.as_mut_ptr();
            id.job = 2;
            call(id, self.instance);
            let code = infog(id, 1);
            if (code == -8 || code == -9) && retries < self.workspace_retries {
                // Not enough workspace: double ICNTL(14) and redo the factorisation only.
                self.workspace_percent = self.workspace_percent.max(1).saturating_mul(2);
                retries += 1;
                continue;
            }
            self.factorized = false;
            if code < 0 {
                return Err(Failure::Other(SolveError::Mumps {
                    phase: Phase::Factorisation,
                    code: crate::error::MumpsCode::from_code(code),
                    infog1: code,
                    infog2: infog(id, 2) as i64,
                    workspace_retries: retries,
                }));
            }
            let null_pivots = infog(id, 28);
            if null_pivots > 0 {
                // SAFETY: with ICNTL(24) = 1, MUMPS allocates PIVNUL_LIST with INFOG(28) entries.
                let list = unsafe { std::slice::from_raw_parts(id.pivnul_list, null_pivots as usize) };
                let equations = list.iter().map(|&i| (i - 1) as usize).collect();
                return Err(Failure::Singular { equations });
            }
            self.info = FactorInfo {
                negative_pivots: infog(id, 12) as i64,
                // INFOG(29) < 0 counts millions of entries
                factor_entries: match infog(id, 29) as i64 {
                    v if v < 0 => -v * 1_000_000,
                    v => v,
                },
                memory_mb: infog(id, 22) as i64,
                estimated_memory_mb: self.info.estimated_memory_mb,
                workspace_percent: self.workspace_percent,
                workspace_retries: retries,
            };
            self.factorized = true;
            return Ok(());
        }
    }

    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        if !self.factorized || rhs.len() != self.n {
            return Err(backend_error("solve called without a factorisation of this size".into()));
        }
        let mut x = rhs.to_vec();
        let id = &mut *self.id;
        id.rhs = x.as_mut_ptr();
        id.nrhs = 1;
        id.lrhs = self.n as i32;
        id.job = 3;
        call(id, self.instance);
        id.rhs = std::ptr::null_mut();
        let code = infog(id, 1);
        if code < 0 {
            return Err(Failure::Other(SolveError::mumps(Phase::Solution, code, infog(id, 2) as i64)));
        }
        Ok(x)
    }

    fn negative_pivots(&self) -> Option<usize> {
        (self.symmetric && self.factorized).then_some(self.info.negative_pivots.max(0) as usize)
    }

    fn factor_entries(&self) -> Option<u64> {
        self.factorized.then_some(self.info.factor_entries.max(0) as u64)
    }

    fn estimated_memory_mb(&self) -> Option<f64> {
        self.analysed.then_some(self.info.estimated_memory_mb as f64)
    }

    fn factor_memory_mb(&self) -> Option<f64> {
        self.factorized.then_some(self.info.memory_mb as f64)
    }
}

impl Mumps {
    /// Let the copy of the matrix handed to MUMPS go (its pointers cleared first). The factors
    /// stay; a factorisation needs a new analysis.
    fn release_matrix(&mut self) {
        let id = &mut *self.id;
        id.irn = std::ptr::null_mut();
        id.jcn = std::ptr::null_mut();
        id.a = std::ptr::null_mut();
        self.positions = Vec::new();
        self.irn = Vec::new();
        self.jcn = Vec::new();
        self.a = Vec::new();
        self.analysed = false;
    }

    /// JOB = 3 with ICNTL(26) = `phase` (1: condensation, 2: expansion) on the right-hand side
    /// kept between the two and the reduced right-hand side.
    fn reduced_solve(&mut self, phase: i32) -> Result<(), Failure> {
        let id = &mut *self.id;
        id.rhs = self.condensed_rhs.as_mut_ptr();
        id.nrhs = 1;
        id.lrhs = self.n as i32;
        id.redrhs = self.reduced_rhs.as_mut_ptr();
        id.lredrhs = self.schur_list.len() as i32;
        icntl(id, 26, phase);
        id.job = 3;
        call(id, self.instance);
        icntl(id, 26, 0);
        id.rhs = std::ptr::null_mut();
        let code = infog(id, 1);
        if code < 0 {
            return Err(Failure::Other(SolveError::mumps(Phase::Solution, code, infog(id, 2) as i64)));
        }
        Ok(())
    }
}

impl crate::linsol::condensed::condensing::Condensing for Mumps {
    fn backend(&self) -> Backend {
        Backend::Mumps
    }

    /// Analysis and factorisation with the kept unknowns as MUMPS's Schur variables (ICNTL(19) = 1):
    /// MUMPS eliminates the interior and leaves S in the buffer given to it. A symmetric instance
    /// fills the lower triangle (row i, columns ≤ i); the upper is mirrored from it here.
    fn factorize_condensed(&mut self, matrix: &CscMatrix, kept: &[usize]) -> Result<Vec<f64>, Failure> {
        let m = kept.len();
        self.schur_list = kept.iter().map(|&e| e as i32 + 1).collect();
        self.schur = vec![0.0; m * m];
        self.reduced_rhs = vec![0.0; m];
        self.analyse(matrix)?;
        self.factorize(matrix)?;
        // The matrix handed over is not read again: the condensation and the expansion (JOB = 3
        // without ICNTL(10) or (11)) use the factors alone, and the next condensed factorisation
        // analyses afresh. Its copy goes (at 10⁵ unknowns 23 MB beside the factors for the whole
        // run), and with it the analysis it belonged to.
        self.release_matrix();
        // MUMPS has written the complement: the buffer is handed over (a new one is made for the
        // next factorisation)
        let mut s = std::mem::take(&mut self.schur);
        if self.symmetric {
            for i in 0..m {
                for j in i + 1..m {
                    s[i * m + j] = s[j * m + i];
                }
            }
        }
        Ok(s)
    }

    /// JOB = 3 with ICNTL(26) = 1: the forward elimination, leaving the reduced right-hand side.
    fn condense(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        if !self.factorized || rhs.len() != self.n || self.schur_list.is_empty() {
            return Err(backend_error("condense called without a Schur factorisation of this size".into()));
        }
        self.condensed_rhs = rhs.to_vec();
        self.reduced_solve(1)?;
        Ok(self.reduced_rhs.clone())
    }

    /// JOB = 3 with ICNTL(26) = 2: the backward substitution from the solution on the Schur
    /// variables. Follows the condensation of the same right-hand side (MUMPS keeps its forward
    /// elimination in between), so `rhs` is not read again.
    fn expand(&mut self, rhs: &[f64], kept_solution: &[f64]) -> Result<Vec<f64>, Failure> {
        let m = self.schur_list.len();
        if self.condensed_rhs.len() != rhs.len() || kept_solution.len() != m {
            return Err(backend_error("expand called without a condensation of this size".into()));
        }
        self.reduced_rhs.copy_from_slice(kept_solution);
        self.reduced_solve(2)?;
        let mut x = std::mem::take(&mut self.condensed_rhs);
        for (&e, &v) in self.schur_list.iter().zip(kept_solution) {
            x[e as usize - 1] = v;
        }
        Ok(x)
    }
}

impl Drop for Mumps {
    fn drop(&mut self) {
        let id = &mut *self.id;
        // Pointers must be valid (or null) for JOB = −2.
        id.irn = self.irn.as_mut_ptr();
        id.jcn = self.jcn.as_mut_ptr();
        id.a = self.a.as_mut_ptr();
        id.rhs = std::ptr::null_mut();
        id.job = -2;
        call(id, self.instance);
    }
}

// SAFETY: the handle is only used through `&mut self` and every MUMPS call holds the global lock.
unsafe impl Send for Mumps {}

/// A bare MUMPS run on a matrix already in MUMPS's format (1-based coordinates; the lower triangle
/// when `symmetric`), with the same controls as [`Mumps`]: JOB −1, 1, 2, 3, −2 and nothing else.
/// `geoslip bench` measures the wrapper against it. Returns INFOG(1) of the first failing phase (0
/// on success); `rhs` holds the solution.
pub fn bare_run(symmetric: bool, n: usize, irn: &mut [i32], jcn: &mut [i32], a: &mut [f64], rhs: &mut [f64]) -> i32 {
    let (mut id, instance) = match start_instance(symmetric) {
        Ok(x) => x,
        Err((code, _)) => return code,
    };
    for (i, v) in [(1, -1), (2, -1), (3, -1), (4, 0), (7, Ordering::Auto.icntl7()), (8, 7), (13, 1), (14, 20), (24, 1)]
    {
        icntl(&mut id, i, v);
    }
    id.n = n as i32;
    id.nnz = irn.len() as i64;
    id.irn = irn.as_mut_ptr();
    id.jcn = jcn.as_mut_ptr();
    id.a = a.as_mut_ptr();
    id.rhs = rhs.as_mut_ptr();
    id.nrhs = 1;
    id.lrhs = n as i32;
    let mut status = 0;
    for job in [1, 2, 3] {
        id.job = job;
        call(&mut id, instance);
        if infog(&id, 1) < 0 {
            status = infog(&id, 1);
            break;
        }
    }
    id.rhs = std::ptr::null_mut();
    id.job = -2;
    call(&mut id, instance);
    status
}

#[cfg(test)]
mod tests {
    //! MUMPS's own error paths: the memory-retry path (forced with a tiny ICNTL(14)) and the
    //! null-pivot list of a singular matrix.
    use super::*;
    use crate::linsol::csc::{PatternCache, Triplets};

    /// A chain of springs whose every node is tied to the next by a multiplier: many zero diagonal
    /// entries, so pivots are delayed and the workspace estimate is tight.
    fn saddle_chain(n_u: usize, multiplier_diagonal: f64) -> (CscMatrix, Vec<f64>) {
        let mut t = Triplets::default();
        for i in 0..n_u {
            t.push(i, i, 2.0 + (i % 3) as f64);
            if i + 1 < n_u {
                t.push(i, i + 1, -1.0);
                t.push(i + 1, i, -1.0);
            }
        }
        let m = n_u / 2;
        for r in 0..m {
            let (a, b) = (2 * r, (2 * r + 7) % n_u);
            t.push(n_u + r, a, 1.0);
            t.push(a, n_u + r, 1.0);
            t.push(n_u + r, b, -0.5);
            t.push(b, n_u + r, -0.5);
            t.push(n_u + r, n_u + r, multiplier_diagonal);
        }
        let n = n_u + m;
        let a = PatternCache::default().assemble(n, &t).0;
        (a, (0..n).map(|i| (i % 5) as f64 - 2.0).collect())
    }

    #[test]
    fn a_tiny_workspace_is_retried_with_a_doubled_icntl14() {
        // A strict pivoting threshold (CNTL(1) = 0.5) delays many pivots of this symmetric indefinite
        // system beyond what the analysis planned; with ICNTL(14) = 0 (no margin) the workspace
        // overflows (INFOG(1) = −8 or −9) and the factorisation must be retried with more.
        let (a, b) = saddle_chain(3000, 0.0);
        let mut reference = Mumps::new(true, &SolverOptions::default()).unwrap();
        reference.analyse(&a).unwrap();
        reference.factorize(&a).unwrap();
        let x_ref = reference.solve(&b).unwrap();
        for _ in 0..3 {
            let mut mumps = Mumps::new(true, &SolverOptions::default()).unwrap();
            mumps.set_workspace_percent(0);
            mumps.set_pivot_threshold(0.5);
            mumps.analyse(&a).unwrap();
            mumps.factorize(&a).unwrap();
            assert!(mumps.info.workspace_retries > 0, "ICNTL(14) = 0 did not run out of workspace");
            assert!(mumps.info.workspace_percent > 0);
            let x = mumps.solve(&b).unwrap();
            for (p, q) in x.iter().zip(&x_ref) {
                assert!((p - q).abs() < 1e-10 * (1.0 + q.abs()));
            }
        }
    }

    #[test]
    fn a_workspace_overflow_past_the_retries_is_a_typed_error() {
        // as above, with no retry allowed: MUMPS's own INFOG(1) = −8 or −9 comes back typed
        let (a, _) = saddle_chain(3000, 0.0);
        let mut mumps = Mumps::new(true, &SolverOptions::default()).unwrap();
        mumps.set_workspace_percent(0);
        mumps.set_pivot_threshold(0.5);
        mumps.set_workspace_retries(0);
        mumps.analyse(&a).unwrap();
        match mumps.factorize(&a) {
            Err(Failure::Other(e @ SolveError::Mumps { phase: Phase::Factorisation, infog1, code, .. })) => {
                assert!(infog1 == -8 || infog1 == -9, "{e}");
                assert!(matches!(
                    code,
                    crate::error::MumpsCode::IntegerWorkspaceTooSmall | crate::error::MumpsCode::RealWorkspaceTooSmall
                ));
                assert!(e.to_string().contains("ICNTL(14)"), "{e}");
            }
            other => panic!("expected MUMPS's workspace error, got {other:?}"),
        }
    }

    #[test]
    fn a_singular_matrix_lists_its_null_pivots() {
        // unknown 2 has no stiffness and no constraint
        let mut t = Triplets::default();
        t.push(0, 0, 2.0);
        t.push(1, 1, 3.0);
        t.push(2, 2, 0.0);
        t.push(0, 1, -1.0);
        t.push(1, 0, -1.0);
        let a = PatternCache::default().assemble(3, &t).0;
        for symmetric in [true, false] {
            let mut mumps =
                Mumps::new(symmetric, &SolverOptions { ordering: Ordering::Pord, ..SolverOptions::default() }).unwrap();
            mumps.analyse(&a).unwrap();
            match mumps.factorize(&a) {
                Err(Failure::Singular { equations }) => assert_eq!(equations, vec![2]),
                other => panic!("expected a null pivot at unknown 2, got {other:?}"),
            }
        }
    }

    #[test]
    fn the_library_is_the_version_of_the_header() {
        let mumps = Mumps::new(true, &SolverOptions::default()).unwrap();
        assert!(mumps.version().starts_with("5."), "{}", mumps.version());
    }
}
