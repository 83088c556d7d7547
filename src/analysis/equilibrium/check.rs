//! After a correction: the active set and the bars' rupture, then the convergence test, on the
//! interface alone during an interface iteration and on the whole system otherwise.

use super::super::context::Context;
use super::super::convergence::{displacement_ok, IncrementError, IterateCheck, Measures};
use super::super::non_finite::{self, Iterate};
use super::super::soil;
use super::super::springs::InterfaceIterate;
use super::super::state::State;
use super::condensation::{BalancedInterior, Deferred};
use super::interface_path::finish_interface;
use super::iterations::{IncrementReport, Iterations};
use crate::assembly::{soil_and_bar_force_and_floor, ElementForce, SoilView};
use crate::dofs::DofMap;
use crate::element::soil_state::SoilTrial;
use crate::interface::active_set::{describe, Bands};
use std::time::Instant;

/// After a correction: the active set and the bars' rupture, then the convergence test. Returns
/// the report when the increment has converged.
pub(super) fn check(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    iteration: usize,
    correction2: f64,
    interface_soil: Option<SoilTrial>,
) -> Result<Option<IncrementReport>, IncrementError> {
    let t = Instant::now();
    let rule = cx.options.analysis.reassociation;
    let interface = InterfaceIterate::clipped(cx.model, rule, state, &dofs.multipliers);
    let characteristic = cx.characteristic;
    let force_floor = state
        .f_ext
        .iter()
        .fold(0.0f64, |m, f| m.max(f.abs()))
        .max(1e-6 * cx.elements.typical_stiffness() * characteristic);
    let gaps = interface.rows.gaps(&state.u);
    let bands = Bands::new(&state.lambda, force_floor, characteristic);
    let mut changes = cx.active_set(dofs, &state.placed).update(
        &mut state.interfaces,
        &mut state.lambda,
        &gaps,
        bands,
        &mut it.flips,
    );
    let elements = &cx.elements;
    changes.extend(state.bars.rupture(&elements.bars, |i| &elements.blocks[i].0, &state.u));
    cx.stats.interface_seconds += t.elapsed().as_secs_f64();
    it.state_changes.extend(changes.iter().cloned());
    let settings = &cx.options.analysis;
    let checked = IterateCheck {
        interface: &interface,
        gaps: &gaps,
        settled: changes.is_empty(),
        // (the correction against the displacements so far, for an increment that moves almost
        // nothing, as a strength-reduction trial at F = 1, while slack sheets under no normal
        // stress drift along themselves without changing any force)
        displacement_ok: displacement_ok(settings, iteration, correction2, &state.u, &it.u_increment_start),
        characteristic,
    };
    if let (Some(deferred), Some(_)) = (it.deferred.as_ref(), cx.condensed.as_ref()) {
        // an interface iteration: the residual on the kept unknowns, the interior unmoved
        let t = Instant::now();
        let element = deferred.element_force(&cx.elements, state);
        let measures = Measures::of(&checked, &element, deferred.floor, state, dofs);
        cx.stats.residual_seconds += t.elapsed().as_secs_f64();
        it.last_residual = Some((measures.residual, measures.reference));
        if let Some(n) = it.progress.stalled(measures.residual, measures.threshold(settings)) {
            return Err(not_converged(cx, dofs, state, it, iteration, 0, Some(n)));
        }
        let last = iteration == settings.max_iterations;
        if !measures.converged(settings) && !last && measures.residual.is_finite() {
            it.carried_element_force = Some(element);
            it.carried_soil = interface_soil;
            return Ok(None);
        }
        // converged on the interface (or out of iterations): the interior follows, and the whole
        // system is checked below
        finish_interface(cx, dofs, state, it)?;
    }
    let settings = &cx.options.analysis;
    let t = Instant::now();
    // with the tangent the next iteration assembles (the forces do not depend on it)
    let soil_trial = soil::evaluate(&cx.setup, &state.soil, &state.u, &state.u_committed, it.fallbacks.soil_tangent);
    // the elements' force and the residual's round-off floor in one pass
    let view = SoilView { field: &state.soil, trial: &soil_trial };
    let ElementForce { force: element_force, floor, operator: operator_force } =
        soil_and_bar_force_and_floor(&cx.elements, view, &state.bars, &state.u);
    let measures = Measures::of(&checked, &element_force, floor, state, dofs);
    let (residual, reference) = (measures.residual, measures.reference);
    cx.stats.residual_seconds += t.elapsed().as_secs_f64();
    if !residual.is_finite() || !reference.is_finite() {
        let springs = &interface.springs;
        let iterate = Iterate { mesh: &cx.model.mesh, dofs, state, soil_trial: Some(&soil_trial), springs };
        let first = non_finite::in_iterate(&iterate).unwrap_or(non_finite::NonFinite {
            value: if residual.is_finite() { reference } else { residual },
            location:
                "the out-of-balance force (every displacement, load, soil force and interface stress was finite: \
                       their products overflowed)"
                    .into(),
        });
        return Err(IncrementError::NonFinite { iteration, first });
    }
    it.last_residual = Some((residual, reference));
    if measures.converged(settings) {
        return Ok(Some(IncrementReport {
            iterations: iteration,
            force_residual: residual / reference,
            linear_residuals: std::mem::take(&mut it.linear_residuals),
            springs: interface.springs,
            state_changes: std::mem::take(&mut it.state_changes),
            soil: soil_trial,
            element_force,
            element_floor: floor,
            operator_force,
        }));
    }
    let stalled = it.progress.stalled(residual, measures.threshold(settings));
    if stalled.is_some() || iteration == settings.max_iterations {
        return Err(not_converged(cx, dofs, state, it, iteration, soil_trial.yielding, stalled));
    }
    if it.condensed_solve {
        // the whole system was solved condensed: the interior is in balance, and the iterations
        // go on on the interface alone
        if let Some(condensed) = cx.condensed.as_ref() {
            let balanced = BalancedInterior { element_force: &element_force, floor: measures.floor };
            it.deferred = Deferred::start(condensed, &cx.elements, dofs, state, balanced);
        }
    }
    it.carried_soil = Some(soil_trial);
    it.carried_element_force = Some(element_force);
    Ok(None)
}

/// The failure of an increment that ran out of iterations or stalled: its last residual, and the
/// interface points that changed state more than once.
fn not_converged(
    cx: &Context,
    dofs: &DofMap,
    state: &State,
    it: &Iterations,
    iteration: usize,
    yielding: usize,
    stalled: Option<usize>,
) -> IncrementError {
    let (residual, reference) = it.last_residual.unwrap_or((0.0, f64::MIN_POSITIVE));
    let mut unsettled: Vec<(usize, usize)> = it.flips.iter().map(|(&k, &n)| (k, n)).filter(|&(_, n)| n > 1).collect();
    unsettled.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
    let unsettled = unsettled
        .into_iter()
        .map(|(k, n)| format!("{} ({n} changes)", describe(&cx.model.mesh, &state.interfaces, dofs.multipliers[k])))
        .collect();
    IncrementError::NotConverged { iterations: iteration, residual, reference, unsettled, yielding, stalled }
}
