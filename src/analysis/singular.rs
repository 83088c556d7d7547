//! A singular matrix within an iteration: the three ways an increment recovers from one, and, when
//! none applies, the error that names what is unconstrained.
//!
//! 1. Sliding points have no shear stiffness; where they are all that holds a node along the
//!    interface (a tension-only sheet gone slack, under no normal stress, as a liner laid before its
//!    cover) the tangent is singular though the forces balance: the rest of the increment iterates
//!    with Ks on the sliding points.
//! 2. Yielded soil can leave the consistent tangent singular (a local mechanism of perfectly plastic
//!    Gauss points, as at a footing edge) where the structure itself is not: the rest of the
//!    increment iterates on the elastic soil stiffness.
//! 3. Normal rows that depend on other rows (after a re-association, two reinforcement nodes tied to
//!    the same pair of soil nodes) are set aside, reported, and the iteration retried.
//!
//! Anything else is a mechanism: of the model when the matrix is that of the last equilibrium
//! (named at once), or of where the iteration went when a correction had moved the iterate from
//! it (the increment is then cut back, and the mechanism named if the cutbacks run out).

use super::context::Context;
use super::convergence::{cap, IncrementError};
use super::state::State;
use super::stats::{RunStats, Warning};
use crate::dofs::DofMap;
use crate::element::soil_state::Tangent;
use crate::error::SolveError;
use crate::interface::active_set::describe;
use crate::interface::{Interface, NormalState};
use crate::linsol::csc::{PatternCache, Triplets};
use crate::linsol::{dense_ref, Failure, LinearSolver};
use crate::model::Model;

/// How many times one increment may set dependent rows aside.
const DEPENDENT_RETRIES: usize = 8;

/// The fallbacks an increment has taken so far.
pub struct Fallbacks {
    /// Sliding points' springs on Ks instead of their zero plastic tangent.
    pub elastic_springs: bool,
    /// The tangent the soil gives the matrix after the first iteration.
    pub soil_tangent: Tangent,
    /// How many times dependent rows were set aside.
    pub dependent_retries: usize,
}

/// What the iteration knew when its matrix was singular.
pub struct SingularMatrix<'a> {
    pub triplets: &'a Triplets,
    /// The null pivots the backend named (may be empty).
    pub equations: Vec<usize>,
    /// Some interface point slides at its strength.
    pub sliding: bool,
    /// Some soil element gave the matrix a tangent other than its elastic matrix.
    pub yielded_soil: bool,
    /// The iteration, when the iterate has left the last equilibrium (a correction was applied in
    /// this increment): a matrix still singular there is cut back, not the model's.
    pub away_at: Option<usize>,
}

/// How the iteration goes on.
pub enum Recovered {
    /// With a new matrix (fallback 1 or 2).
    NewMatrix,
    /// With dependent rows set aside; the state changes to report.
    RowsSetAside(Vec<String>),
}

/// Recover from a singular matrix, or name what is unconstrained.
pub fn recover(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    fallbacks: &mut Fallbacks,
    singular: SingularMatrix,
) -> Result<Recovered, IncrementError> {
    if !fallbacks.elastic_springs && singular.sliding {
        fallbacks.elastic_springs = true;
        cx.stats.warnings.add(Warning::SlidingTangentSingular);
        return Ok(Recovered::NewMatrix);
    }
    // (once: a Duncan–Chang or hardening soil gives its own tangent even on the elastic fallback,
    // so a matrix still singular on it is the model's)
    if singular.yielded_soil && !matches!(fallbacks.soil_tangent, Tangent::Elastic | Tangent::Committed) {
        fallbacks.soil_tangent = Tangent::Elastic;
        cx.stats.warnings.add(Warning::YieldedTangentSingular);
        return Ok(Recovered::NewMatrix);
    }
    let null = null_equations(singular.triplets, dofs.size(), singular.equations.clone()).unwrap_or_default();
    let rows: Vec<usize> = null
        .iter()
        .filter_map(|&e| e.checked_sub(dofs.free_count))
        .filter(|&k| !dofs.multipliers[k].tangential)
        .collect();
    if !null.is_empty() && rows.len() == null.len() && fallbacks.dependent_retries < DEPENDENT_RETRIES {
        fallbacks.dependent_retries += 1;
        let mut changes = Vec::new();
        for k in rows {
            let m = dofs.multipliers[k];
            let name = describe(&cx.model.mesh, &state.interfaces, m);
            state.interfaces[m.interface].faces[m.face].points[m.point].normal_state = NormalState::Redundant {
                carried_by: "the other constraint rows on the same soil nodes (it depends on them)".into(),
                multiplier: None,
            };
            state.lambda[k] = 0.0;
            changes.push(format!("{name}: set aside, it depends on other constraint rows"));
        }
        return Ok(Recovered::RowsSetAside(changes));
    }
    let backend = cx.system.backend().name();
    let source = diagnose(backend, cx.model, &state.interfaces, dofs, singular.triplets, singular.equations);
    Err(match singular.away_at {
        Some(iteration) => IncrementError::SingularIterate { iteration, source },
        None => IncrementError::Solve(source),
    })
}

/// Beyond this ratio of the largest to the smallest stiffness on the diagonal, a factorisation in
/// double precision (16 digits) keeps too few to tell a mechanism from round-off.
const ILL_CONDITIONED: f64 = 1e12;

/// The smallest and the largest positive stiffness on the diagonal of the displacement unknowns
/// (equation and value), and their ratio.
pub struct StiffnessSpread {
    pub softest: (usize, f64),
    pub stiffest: (usize, f64),
    pub ratio: f64,
}

impl StiffnessSpread {
    pub fn of(triplets: &Triplets, dofs: &DofMap) -> Option<StiffnessSpread> {
        StiffnessSpread::of_diagonal(&diagonal_of(triplets, dofs.free_count))
    }

    /// The spread of the displacement unknowns' diagonal.
    pub fn of_diagonal(diagonal: &[f64]) -> Option<StiffnessSpread> {
        let positive = diagonal.iter().copied().enumerate().filter(|&(_, v)| v > 0.0 && v.is_finite());
        let softest = positive.clone().min_by(|a, b| a.1.total_cmp(&b.1))?;
        let stiffest = positive.max_by(|a, b| a.1.total_cmp(&b.1))?;
        Some(StiffnessSpread { softest, stiffest, ratio: stiffest.1 / softest.1 })
    }
}

/// The diagonal of `triplets` over the first `n` equations (the displacement unknowns, when `n` is
/// `free_count`).
pub fn diagonal_of(triplets: &Triplets, n: usize) -> Vec<f64> {
    let mut diagonal = vec![0.0; n];
    for ((&i, &j), &v) in triplets.rows.iter().zip(&triplets.cols).zip(&triplets.values) {
        let i = i as usize;
        if i == j as usize && i < n {
            diagonal[i] += v;
        }
    }
    diagonal
}

/// The diagonal of the displacement unknowns that no constraint row holds (the others zero, which
/// [`StiffnessSpread::of_diagonal`] passes over): a reinforcement node's transverse stiffness is
/// round-off where its bars are straight, and its normal row holds it there, so its diagonal says
/// nothing of how well the saddle-point system is conditioned.
pub fn unconstrained_diagonal_of(triplets: &Triplets, n: usize) -> Vec<f64> {
    let mut diagonal = diagonal_of(triplets, n);
    pass_over_constrained(&mut diagonal, triplets);
    diagonal
}

/// Zero the entries of `diagonal` (the first `diagonal.len()` equations) that a constraint row of
/// `triplets` holds.
pub fn pass_over_constrained(diagonal: &mut [f64], triplets: &Triplets) {
    let n = diagonal.len();
    for ((&i, &j), &v) in triplets.rows.iter().zip(&triplets.cols).zip(&triplets.values) {
        let (i, j) = (i as usize, j as usize);
        if v != 0.0 && (i < n) != (j < n) {
            diagonal[i.min(j)] = 0.0;
        }
    }
}

/// Warn (once a run) when a matrix that was solved is ill-conditioned: its results carry round-off
/// that the residual check may not show. `diagonal`: the matrix's diagonal over the displacement
/// unknowns (`dofs.free_count`) that no constraint row holds ([`unconstrained_diagonal_of`]).
pub fn warn_if_ill_conditioned(stats: &mut RunStats, model: &Model, dofs: &DofMap, state: &State, diagonal: &[f64]) {
    if stats.warnings.iter().any(|w| matches!(w, Warning::IllConditioned { .. })) {
        return;
    }
    if let Some(spread) = StiffnessSpread::of_diagonal(diagonal).filter(|s| s.ratio > ILL_CONDITIONED) {
        stats.warnings.add(Warning::IllConditioned {
            softest: (spread.softest.1, dofs.describe(spread.softest.0, &model.mesh, &state.interfaces)),
            stiffest: (spread.stiffest.1, dofs.describe(spread.stiffest.0, &model.mesh, &state.interfaces)),
            ratio: spread.ratio,
        });
    }
}

/// Name what is unconstrained in a singular system, or say that it is ill-conditioned (stiffnesses
/// many orders of magnitude apart) rather than singular.
fn diagnose(
    backend: &'static str,
    model: &Model,
    interfaces: &[Interface],
    dofs: &DofMap,
    triplets: &Triplets,
    equations: Vec<usize>,
) -> SolveError {
    let n = dofs.size();
    if let Some(spread) = StiffnessSpread::of(triplets, dofs).filter(|s| s.ratio > ILL_CONDITIONED) {
        let null_pivots = null_equations(triplets, n, equations).map_or(0, |l| l.len());
        return SolveError::IllConditioned {
            backend,
            ratio: spread.ratio,
            softest: dofs.describe(spread.softest.0, &model.mesh, interfaces),
            softest_value: spread.softest.1,
            stiffest: dofs.describe(spread.stiffest.0, &model.mesh, interfaces),
            stiffest_value: spread.stiffest.1,
            null_pivots,
        };
    }
    SolveError::Singular { backend, unknowns: unconstrained(model, interfaces, dofs, triplets, equations) }
}

/// The unknowns of a singular system that are not held, by name.
fn unconstrained(
    model: &Model,
    interfaces: &[Interface],
    dofs: &DofMap,
    triplets: &Triplets,
    equations: Vec<usize>,
) -> Vec<String> {
    let n = dofs.size();
    let column_norm = column_norms(triplets, n);
    let describe = |e: usize| {
        let name = dofs.describe(e, &model.mesh, interfaces);
        if column_norm.get(e).is_some_and(|&c| c == 0.0) {
            format!("{name} has no stiffness and no constraint")
        } else {
            format!("{name} is not held (a null pivot: a mechanism runs through it)")
        }
    };
    match null_equations(triplets, n, equations) {
        Some(list) => cap(list.into_iter().map(describe).collect()),
        None => vec!["a mechanism that the structural checks did not isolate: check that every bar node is held by an interface and every body is supported".into()],
    }
}

fn column_norms(triplets: &Triplets, n: usize) -> Vec<f64> {
    let mut column_norm = vec![0.0f64; n];
    for (&j, &v) in triplets.cols.iter().zip(&triplets.values) {
        column_norm[j as usize] += v.abs();
    }
    column_norm
}

/// The undetermined unknowns of a singular system: those the backend named, else the empty
/// columns, else those the reference solver's complete pivoting isolates (small systems).
fn null_equations(triplets: &Triplets, n: usize, equations: Vec<usize>) -> Option<Vec<usize>> {
    if !equations.is_empty() {
        return Some(equations);
    }
    let column_norm = column_norms(triplets, n);
    let empty: Vec<usize> = (0..n).filter(|&j| column_norm[j] == 0.0).collect();
    if !empty.is_empty() {
        return Some(empty);
    }
    if n <= dense_ref::SIZE_LIMIT {
        let matrix = PatternCache::default().assemble(n, triplets).0;
        let mut dense = dense_ref::DenseReference::default();
        if dense.analyse(&matrix).is_ok() {
            if let Err(Failure::Singular { equations }) = dense.factorize(&matrix) {
                return Some(equations);
            }
        }
    }
    None
}
