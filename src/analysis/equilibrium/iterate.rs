//! The iterations of one increment: linearise → solve → update → check, until it has converged.

use super::super::context::Context;
use super::super::convergence::IncrementError;
use super::super::correction::{apply_correction, line_search};
use super::super::state::State;
use super::check::check;
use super::iterations::{IncrementReport, Iterations, Solution};
use super::linearise::linearise;
use super::solve::solve_iteration;
use crate::dofs::DofMap;
use crate::element::soil_state::Tangent;
use std::time::Instant;

/// Iterate one increment to equilibrium: linearise, solve, update, check; given up after
/// `stall_iterations` iterations without progress (0: only after `max_iterations`).
pub(super) fn iterate(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    stall_iterations: usize,
) -> Result<IncrementReport, IncrementError> {
    let mut it = Iterations::new(cx, state, stall_iterations);
    let max_iterations = cx.options.analysis.max_iterations;
    for iteration in 1..=max_iterations {
        cx.stats.iterations += 1;
        it.iteration = iteration;
        let mut linear = linearise(cx, dofs, state, &mut it, iteration);
        it.condensed_solve = false;
        let solution = solve_iteration(cx, dofs, state, &mut it, &linear)?;
        // the springs' stiffness goes on to the next iteration (constant stiffness keeps it)
        it.spring_stiffness = Some(std::mem::take(&mut linear.stiffness));
        let Some(Solution { x, scale, rhs }) = solution else { continue };
        let step = if linear.soil_trial.yielding > 0 && !matches!(linear.tangent, Tangent::Elastic | Tangent::Committed)
        {
            // its trial steps are out-of-balance forces, timed with the check's
            let t = Instant::now();
            let step = line_search(cx, dofs, state, &linear.rows, &x, scale, &rhs[..dofs.free_count]);
            cx.stats.residual_seconds += t.elapsed().as_secs_f64();
            step
        } else {
            1.0
        };
        let correction2 = apply_correction(dofs, state, &x, step, scale);
        // an interface iteration carries its soil (elastic, the interior unmoved) to the next
        let soil = it.deferred.is_some().then_some(linear.soil_trial);
        match check(cx, dofs, state, &mut it, iteration, correction2, soil)? {
            Some(report) => return Ok(report),
            None => continue,
        }
    }
    // every iteration ended in a recovery from a singular matrix
    let (residual, reference) = it.last_residual.unwrap_or((0.0, 0.0));
    Err(IncrementError::NotConverged {
        iterations: max_iterations,
        residual,
        reference: reference.max(f64::MIN_POSITIVE),
        unsettled: it.state_changes.iter().rev().take(12).cloned().collect(),
        yielding: 0,
        stalled: None,
    })
}
