//! The one place that chooses how an iteration's system is solved, and the full system's solve.
//!
//! Three paths, tried in this order until one gives a solution:
//! - [`Path::Interface`]: an interface iteration is under way (the soil condensed, its interior in
//!   balance): the kept unknowns alone (`interface_path.rs`);
//! - [`Path::Condensed`]: the run condenses its elastic soil: the whole system, condensed
//!   (`interface_path.rs`);
//! - [`Path::Full`]: the whole system, assembled and factorised (here), with the recoveries from a
//!   singular matrix (`analysis::singular`).

use super::super::context::Context;
use super::super::convergence::IncrementError;
use super::super::iteration_system::{iteration_system, IterationSystem};
use super::super::non_finite::{self, Iterate};
use super::super::singular::{self, Recovered, SingularMatrix};
use super::super::state::State;
use super::super::stats::Warning;
use super::interface_path::{solve_condensed, solve_interface, start_on_interface};
use super::iterations::{Iterations, Solution};
use super::linearise::Linearisation;
use crate::dofs::DofMap;
use crate::linsol::Failure;
use std::time::Instant;

/// How an iteration's system is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Path {
    /// The kept unknowns alone, the interior following at the end of the interface iteration.
    Interface,
    /// The whole system with the soil condensed onto the interface's unknowns.
    Condensed,
    /// The whole system.
    Full,
}

impl Path {
    /// The path an iteration tries first.
    fn first(cx: &Context, it: &Iterations) -> Path {
        if it.deferred.is_some() {
            Path::Interface
        } else if cx.condensed.is_some() {
            Path::Condensed
        } else {
            Path::Full
        }
    }

    /// The path tried when this one gave no solution (the interface path has let its interior
    /// follow by then; a condensed solve whose backend failed has turned condensing off).
    fn next(self, cx: &Context) -> Path {
        match self {
            Path::Interface if cx.condensed.is_some() => Path::Condensed,
            Path::Interface | Path::Condensed | Path::Full => Path::Full,
        }
    }
}

/// Solve an iteration's system on the first path that gives a solution. `None` when a singular
/// matrix was recovered from and the iteration is to be done again.
pub(super) fn solve_iteration(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    let mut path = Path::first(cx, it);
    if path == Path::Condensed && it.iteration == 1 {
        // an increment whose load moved the kept unknowns alone starts on the interface
        start_on_interface(cx, dofs, state, it, linear);
        if it.deferred.is_some() {
            path = Path::Interface;
        }
    }
    loop {
        let solved = match path {
            Path::Interface => solve_interface(cx, dofs, state, it, linear)?,
            Path::Condensed => solve_condensed(cx, dofs, state, it, linear)?,
            Path::Full => return solve_full(cx, dofs, state, it, linear),
        };
        if solved.is_some() {
            return Ok(solved);
        }
        path = path.next(cx);
    }
}

/// The whole system: assembled (unless the last matrix is still the one) and solved; `None` when a
/// singular matrix was recovered from and the iteration is to be done again.
fn solve_full(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    // The matrix of the last solve, when nothing in it changed (constant stiffness, no state
    // change, in this increment or since an earlier one): no assembly, no factorisation, one solve.
    let t = Instant::now();
    let reuse = cx.system_key == Some(linear.key);
    let system = linear.inputs(&cx.elements, dofs, state);
    let element = it.carried_element_force.take();
    let IterationSystem { triplets, rhs, scale, active } =
        iteration_system(system, &linear.springs, state, !reuse, element);
    cx.stats.solver.assembly_seconds += t.elapsed().as_secs_f64();
    let iterate =
        Iterate { mesh: &cx.model.mesh, dofs, state, soil_trial: Some(&linear.soil_trial), springs: &linear.springs };
    if rhs.iter().chain(&triplets.values).any(|v| !v.is_finite()) {
        let first = non_finite::in_iterate(&iterate).or_else(|| non_finite::in_system(&iterate, &rhs, &triplets));
        if let Some(first) = first {
            return Err(IncrementError::NonFinite { iteration: it.iteration, first });
        }
    }
    let reused = if reuse { cx.system.solve_again(&mut cx.stats.solver, &rhs).ok() } else { None };
    // (taken back below if the matrix turns out singular or the solver fails)
    cx.system_key = Some(linear.key);
    let solved = match reused {
        Some(solution) => Ok(solution),
        None => {
            let triplets = if reuse {
                // the reused factorisation did not give a clean solution: assemble and factorise
                let t = Instant::now();
                let again = system.assemble();
                cx.stats.solver.assembly_seconds += t.elapsed().as_secs_f64();
                again
            } else {
                let diagonal = singular::unconstrained_diagonal_of(&triplets, dofs.free_count);
                singular::warn_if_ill_conditioned(&mut cx.stats, cx.model, dofs, state, &diagonal);
                triplets
            };
            // the list goes once the matrix is built, before the factorisation
            let solved = cx.system.solve(&mut cx.stats.solver, dofs.size(), triplets, &rhs, active);
            if let Some((negative, active)) = cx.system.take_inertia_mismatch() {
                let backend = cx.system.backend().name();
                cx.stats.warnings.add(Warning::InertiaMismatch { backend, negative, active });
            }
            solved
        }
    };
    match solved {
        Ok((x, linear_residual)) => {
            let iterate = Iterate {
                mesh: &cx.model.mesh,
                dofs,
                state,
                soil_trial: Some(&linear.soil_trial),
                springs: &linear.springs,
            };
            if let Some(first) = non_finite::in_solution(&iterate, &x) {
                return Err(IncrementError::NonFinite { iteration: it.iteration, first });
            }
            it.linear_residuals.push(linear_residual);
            Ok(Some(Solution { x, scale, rhs }))
        }
        Err(Failure::Singular { equations }) => {
            cx.system_key = None;
            // the list again, for the diagnosis (a singular matrix is the exception)
            let triplets = system.assemble();
            let singular = SingularMatrix {
                triplets: &triplets,
                equations,
                sliding: linear.springs.iter().any(|r| r.sliding),
                yielded_soil: linear.soil_trial.tangents.iter().any(|t| t.is_some()),
                away_at: it.last_residual.is_some().then_some(it.iteration),
            };
            match singular::recover(cx, dofs, state, &mut it.fallbacks, singular)? {
                Recovered::NewMatrix => cx.system_key = None,
                Recovered::RowsSetAside(changes) => it.state_changes.extend(changes),
            }
            Ok(None)
        }
        Err(Failure::Other(e)) => {
            cx.system_key = None;
            Err(IncrementError::Solve(e))
        }
    }
}
