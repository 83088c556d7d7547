//! The interface iteration's side of an iteration: the whole system solved with the elastic soil
//! condensed onto the interface's unknowns, the kept unknowns solved alone while the interior
//! waits in balance, and the interior following at the end ([`super::condensation`]).

use super::super::context::Context;
use super::super::convergence::IncrementError;
use super::super::iteration_system::{iteration_system, IterationSystem};
use super::super::non_finite::{self, Iterate};
use super::super::singular;
use super::super::state::State;
use super::condensation::{self, BalancedInterior, Condensed};
use super::iterations::{Iterations, Solution};
use super::linearise::Linearisation;
use crate::assembly::{soil_and_bar_force_and_floor, ElementMatrices, SystemInputs};
use crate::dofs::DofMap;
use crate::linsol::condensed::CondensedError;
use crate::linsol::linear_system::SolverStats;
use std::time::Instant;

/// The first iteration of an increment whose load moved the kept unknowns alone: the iterations
/// start on the interface at once (`condensation::start_in_balance`), and the increment's one
/// sparse solve is the interior following at its end. Otherwise the elements' force computed here
/// serves the condensed solve.
pub(super) fn start_on_interface(
    cx: &mut Context,
    dofs: &DofMap,
    state: &State,
    it: &mut Iterations,
    linear: &Linearisation,
) {
    // (only where a condensed soil is in place to start on)
    let Some(condensed) = cx.condensed.as_ref().filter(|c| c.condensed_on().is_some()) else { return };
    let t = Instant::now();
    let system = linear.inputs(&cx.elements, dofs, state);
    // (the residual's round-off floor with the force, in the same pass over the elements)
    // (carried from the time step before, where it still holds)
    let (element, floor) = match (it.carried_element_force.take(), it.start_floor.take()) {
        (Some(element), Some(floor)) => (element, floor),
        _ => {
            let found = soil_and_bar_force_and_floor(&cx.elements, system.soil, &state.bars, &state.u);
            (found.force, found.floor)
        }
    };
    let rhs = iteration_system(system, &linear.springs, state, false, Some(element.clone())).rhs;
    if rhs.iter().all(|v| v.is_finite()) {
        let balanced = BalancedInterior { element_force: &element, floor };
        it.deferred = condensation::start_in_balance(condensed, system, state, &rhs, balanced);
    }
    cx.stats.solver.assembly_seconds += t.elapsed().as_secs_f64();
    it.carried_element_force = Some(element);
}

/// The inputs of an iteration's matrix and its right-hand side alone (no matrix assembled), for
/// the solves that take the matrix in parts; the constraint rows' scale.
fn right_hand_side<'a>(
    elements: &'a ElementMatrices,
    stats: &mut SolverStats,
    linear: &'a Linearisation,
    dofs: &'a DofMap,
    state: &'a State,
    element: Option<Vec<f64>>,
) -> (SystemInputs<'a>, Vec<f64>, f64) {
    let t = Instant::now();
    let system = linear.inputs(elements, dofs, state);
    let IterationSystem { rhs, scale, .. } = iteration_system(system, &linear.springs, state, false, element);
    stats.assembly_seconds += t.elapsed().as_secs_f64();
    (system, rhs, scale)
}

/// The iteration's system solved with the soil condensed onto the interface (`condensation`);
/// `None` where this iteration needs the full system.
pub(super) fn solve_condensed(
    cx: &mut Context,
    dofs: &DofMap,
    state: &State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    let model = cx.model;
    let Context { condensed, stats, elements, .. } = &mut *cx;
    let Some(kept) = condensation::condensable(condensed, &linear.inputs(elements, dofs, state)) else {
        return Ok(None);
    };
    let element = it.carried_element_force.clone();
    let (system, rhs, scale) = right_hand_side(elements, &mut stats.solver, linear, dofs, state, element);
    if rhs.iter().any(|v| !v.is_finite()) {
        // the full path names the first place
        return Ok(None);
    }
    let Condensed::Solved(x, linear_residual) = condensation::solve(condensed, stats, system, kept, linear.key, &rhs)
    else {
        return Ok(None);
    };
    let iterate =
        Iterate { mesh: &model.mesh, dofs, state, soil_trial: Some(&linear.soil_trial), springs: &linear.springs };
    if let Some(first) = non_finite::in_solution(&iterate, &x) {
        return Err(IncrementError::NonFinite { iteration: it.iteration, first });
    }
    // the stiffness spread of the whole matrix, once for each condensed soil
    let soil_key = cx.condensed.as_ref().and_then(|c| c.condensed_on()).map(|(_, key)| key);
    if soil_key.is_some() && soil_key != cx.conditioning_checked {
        cx.conditioning_checked = soil_key;
        // the soil's diagonal from the condensed soil's matrix, the rest assembled (not the whole
        // list again: it would sit beside the soil's factors and the interface system)
        let system = linear.inputs(&cx.elements, dofs, state);
        let diagonal = match cx.condensed.as_ref().and_then(|c| c.linear_diagonal()) {
            Some(soil) => {
                let rest = system.assemble_reinforcement_and_interface();
                let mut diagonal = singular::diagonal_of(&rest, dofs.free_count);
                for (d, s) in diagonal.iter_mut().zip(soil) {
                    *d += s;
                }
                singular::pass_over_constrained(&mut diagonal, &rest);
                diagonal
            }
            None => singular::unconstrained_diagonal_of(&system.assemble(), dofs.free_count),
        };
        singular::warn_if_ill_conditioned(&mut cx.stats, cx.model, dofs, state, &diagonal);
    }
    it.carried_element_force = None;
    it.condensed_solve = true;
    it.linear_residuals.push(linear_residual);
    Ok(Some(Solution { x, scale, rhs }))
}

/// An interface iteration (`condensation::Deferred`), when one is under way: the kept rows of the
/// right-hand side solved on the condensed system. `None` when none is under way, or when the
/// kept system cannot be solved (the interior then follows, and the whole system is solved).
pub(super) fn solve_interface(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    let Some(deferred) = it.deferred.as_mut() else { return Ok(None) };
    let Context { condensed, stats, elements, .. } = &mut *cx;
    let element = it.carried_element_force.take();
    let (system, rhs, scale) = right_hand_side(elements, &mut stats.solver, linear, dofs, state, element);
    let solved = match condensed.as_mut() {
        Some(c) if rhs.iter().all(|v| v.is_finite()) => {
            condensation::solve_deferred(c, &mut stats.solver, deferred, system, linear.key, &rhs)
        }
        _ => None,
    };
    match solved {
        Some((x, linear_residual)) => {
            it.linear_residuals.push(linear_residual);
            Ok(Some(Solution { x, scale, rhs }))
        }
        None => {
            finish_interface(cx, dofs, state, it)?;
            Ok(None)
        }
    }
}

/// The interior follows an interface iteration's movement of the kept unknowns.
pub(super) fn finish_interface(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
) -> Result<(), IncrementError> {
    let Some(deferred) = it.deferred.take() else { return Ok(()) };
    it.carried_element_force = None;
    it.carried_soil = None;
    let Context { condensed, stats, .. } = &mut *cx;
    let Some(c) = condensed.as_mut() else { return Ok(()) };
    deferred.finish(c, &mut stats.solver, dofs, state).map_err(|e| match e {
        CondensedError::Backend(e) => IncrementError::Solve(e),
        CondensedError::Fallback(_) => IncrementError::Solve(crate::error::SolveError::Backend {
            backend: c.backend().name(),
            message: "the interior could not follow the interface's movement".into(),
        }),
    })
}
