//! Typed errors that carry what a user needs to act: the file, the field, the entity.

use std::fmt;
use std::path::PathBuf;

pub mod native;
pub use native::{MumpsCode, Phase, UmfpackStatus};

/// One problem found in a model file.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Where in the file, as a path: `elements[3].nodes`, `interfaces[0].reinforcement.path`.
    pub field: String,
    /// The entity concerned: `element 42`, `node 17`, `interface "grid-1"`.
    pub entity: Option<String>,
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.entity {
            Some(e) => write!(f, "{} ({}): {}", self.field, e, self.message),
            None => write!(f, "{}: {}", self.field, self.message),
        }
    }
}

/// Every problem found in one model file.
#[derive(Debug, Clone)]
pub struct ModelError {
    pub file: PathBuf,
    pub problems: Vec<Problem>,
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.problems.len();
        write!(f, "{}: {} problem{} in the model", self.file.display(), n, if n == 1 { "" } else { "s" })?;
        for p in &self.problems {
            write!(f, "\n  {}: {}", self.file.display(), p)?;
        }
        Ok(())
    }
}

impl std::error::Error for ModelError {}

/// What a linear solver reports.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum SolveError {
    /// The matrix is singular; `unknowns` names what is unconstrained.
    #[error("the system is singular ({backend}): {}", .unknowns.join("; "))]
    Singular { backend: &'static str, unknowns: Vec<String> },
    /// The matrix is too ill-conditioned to factorise reliably: its pivots looked singular, but the
    /// stiffnesses on its diagonal are many orders of magnitude apart.
    #[error(
        "the system is ill-conditioned, not shown to be singular ({backend}): the stiffness on the diagonal \
         ranges from {softest_value:.3e} at {softest} to {stiffest_value:.3e} at {stiffest}, a ratio of {ratio:.1e}, \
         beyond the 1e12 that double precision factorises reliably, and {null_pivots} pivots vanished in round-off. \
         Bring the stiffnesses closer (the soil's Young's modulus against the reinforcement's EA and the \
         interfaces' Ks, in consistent units)"
    )]
    IllConditioned {
        backend: &'static str,
        ratio: f64,
        softest: String,
        softest_value: f64,
        stiffest: String,
        stiffest_value: f64,
        null_pivots: usize,
    },
    /// The dense reference solver refuses systems above its size limit.
    #[error(
        "the dense reference solver handles at most {limit} unknowns and this system has {size}; \
         use --solver faer (or auto) for a model this size"
    )]
    TooLarge { size: usize, limit: usize },
    /// The assembled system would need indices beyond the assembly's 32 bits.
    #[error(
        "the model's system would have up to {equations} equations and {entries} soil matrix entries; the assembly \
         indexes equations in 32 bits (below {limit}) and the soil's entries in half that: coarsen the mesh or \
         split the model"
    )]
    BeyondIndices { equations: usize, entries: usize, limit: usize },
    /// The requested backend is not compiled into this build.
    #[error("solver backend '{backend}' is not available in this build: {hint}")]
    Unavailable { backend: String, hint: String },
    /// The model or its factorisation would need more memory than the run may use: stopped before
    /// the work started.
    #[error(transparent)]
    OutOfMemory(Box<MemoryShortfall>),
    /// MUMPS returned an error code (INFOG(1) < 0).
    #[error(
        "MUMPS {phase}: {} (INFOG(1) = {infog1}, INFOG(2) = {infog2}){}{}",
        code.meaning(),
        retries_text(*workspace_retries),
        hint_text(code.hint())
    )]
    Mumps { phase: Phase, code: MumpsCode, infog1: i32, infog2: i64, workspace_retries: usize },
    /// UMFPACK returned an error status (or a warning that makes the result unusable).
    #[error("UMFPACK {phase}: {} (status {status}){}", code.meaning(), hint_text(code.hint()))]
    Umfpack { phase: Phase, code: UmfpackStatus, status: i64 },
    /// A backend failed for a reason of its own (not a library status code).
    #[error("{backend} failed: {message}")]
    Backend { backend: &'static str, message: String },
}

impl SolveError {
    /// The typed error of a MUMPS INFOG(1) and INFOG(2).
    pub fn mumps(phase: Phase, infog1: i32, infog2: i64) -> SolveError {
        SolveError::Mumps { phase, code: MumpsCode::from_code(infog1), infog1, infog2, workspace_retries: 0 }
    }

    /// The typed error of a UMFPACK status.
    pub fn umfpack(phase: Phase, status: i64) -> SolveError {
        SolveError::Umfpack { phase, code: UmfpackStatus::from_code(status), status }
    }
}

fn retries_text(retries: usize) -> String {
    match retries {
        0 => String::new(),
        n => format!(" after {n} workspace increases"),
    }
}

fn hint_text(hint: Option<&str>) -> String {
    hint.map(|h| format!("; {h}")).unwrap_or_default()
}

/// What would not fit in memory, and what to do.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{backend}: {what} needs about {needed_mb:.1} MB and this run has {available_mb:.1} MB for it; {hint}")]
pub struct MemoryShortfall {
    pub backend: &'static str,
    pub what: &'static str,
    pub needed_mb: f64,
    pub available_mb: f64,
    pub hint: String,
}

/// A run that could not finish.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    #[error("{path}: cannot read the model file: {source}")]
    Read { path: PathBuf, source: crate::input_file::Unreadable },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Backend(#[from] SolveError),
    #[error("{}: stage \"{stage}\", step {step}: {source}", .file.display())]
    Solve { file: PathBuf, stage: String, step: usize, source: SolveError },
    #[error(
        "{}: stage \"{stage}\", step {step}: no equilibrium: at iteration {iteration}, away from the \
         last equilibrium, {source}; after {cutbacks} cutbacks. Try more load factors in this stage",
        .file.display()
    )]
    SingularIterate { file: PathBuf, stage: String, step: usize, iteration: usize, cutbacks: usize, source: SolveError },
    #[error(
        "{}: stage \"{stage}\", step {step}: no equilibrium after {iterations} iterations \
         (force residual {residual:.3e} of {reference:.3e}); {hint}", .file.display()
    )]
    NotConverged {
        file: PathBuf,
        stage: String,
        step: usize,
        iterations: usize,
        residual: f64,
        reference: f64,
        hint: String,
    },
    #[error(
        "{}: stage \"{stage}\", step {step}: a number that is not finite ({value}) appeared in iteration \
         {iteration}, first in {location} (after {cutbacks} cutbacks). Check the values that feed it (loads, \
         stiffnesses, strengths and their units): one that overflows, or a law evaluated where it is undefined, \
         gives such a number", .file.display()
    )]
    NonFinite {
        file: PathBuf,
        stage: String,
        step: usize,
        iteration: usize,
        value: f64,
        location: String,
        cutbacks: usize,
    },
    #[error("{path}: cannot write output: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    /// A saved step that a run cannot continue from: missing, unreadable, or saved with a model
    /// that differs where the saved state depends on it.
    #[error("{path}: cannot continue from it: {message}")]
    Restart { path: PathBuf, message: String },
    /// The program driving the run asked it to stop (Ctrl-C from Python): the steps before are
    /// complete and kept.
    #[error("{}: stopped after {steps} completed steps: {reason}", .file.display())]
    Stopped { file: PathBuf, steps: usize, reason: String },
}
