//! An iteration's correction applied to the displacements and the multipliers, and the step length
//! a line search gives it where yielding soil would make a full step overshoot.

use super::context::Context;
use super::convergence::out_of_balance;
use super::soil;
use super::springs;
use super::state::State;
use crate::dofs::DofMap;
use crate::element::soil_state::Tangent;
use crate::interface::rows::{multiplier_is_active, InterfaceRows};

/// Add `step` times the correction to the displacements and the multipliers; returns the squared
/// norm of the displacement correction.
pub fn apply_correction(dofs: &DofMap, state: &mut State, x: &[f64], step: f64, scale: f64) -> f64 {
    let mut correction2 = 0.0f64;
    for (d, eq) in dofs.equation.iter().enumerate() {
        if let Some(e) = eq {
            state.u[d] += step * x[*e];
            correction2 += (step * x[*e]).powi(2);
        }
    }
    for k in 0..dofs.multipliers.len() {
        state.lambda[k] = corrected_multiplier(dofs, state, x, k, step, scale);
    }
    correction2
}

/// Multiplier k after `step` times the correction: a released row's is zero, as its equation says
/// (exactly, whatever round-off an iterative solve left in its Δλ = −λ = 0).
fn corrected_multiplier(dofs: &DofMap, state: &State, x: &[f64], k: usize, step: f64, scale: f64) -> f64 {
    if multiplier_is_active(&state.interfaces, dofs.multipliers[k]) {
        state.lambda[k] + step * scale * x[dofs.multiplier_equation(k)]
    } else {
        0.0
    }
}

/// A backtracking line search on the Newton correction of yielding soil: the step is halved (at
/// most five times) while the out-of-balance force on the free DOFs would grow. Perfectly plastic
/// Gauss points make the consistent tangent nearly singular where a mechanism is forming, and a
/// full step can then overshoot far (Crisfield, Non-linear Finite Element Analysis of Solids and
/// Structures, vol. 1 (1991) §9.3).
pub fn line_search(
    cx: &Context,
    dofs: &DofMap,
    state: &State,
    rows: &InterfaceRows,
    x: &[f64],
    scale: f64,
    before: &[f64],
) -> f64 {
    let r0: f64 = before.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut trial = state.clone();
    let mut step = 1.0;
    for _ in 0..6 {
        for (d, eq) in dofs.equation.iter().enumerate() {
            if let Some(e) = eq {
                trial.u[d] = state.u[d] + step * x[*e];
            }
        }
        for k in 0..dofs.multipliers.len() {
            trial.lambda[k] = corrected_multiplier(dofs, state, x, k, step, scale);
        }
        let springs = springs::evaluate(cx.model, &trial, rows);
        let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
        let soil_trial = soil::evaluate(&cx.setup, &trial.soil, &trial.u, &trial.u_committed, Tangent::Elastic);
        let (r, _, _) = out_of_balance(&cx.elements, &soil_trial, rows, &taus, &trial, dofs);
        if r <= r0 || step < 0.05 {
            break;
        }
        step *= 0.5;
    }
    step
}
