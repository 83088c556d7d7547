//! The first iterate of an increment: the last converged displacements and multipliers, or (with
//! `extrapolation = "linear"`) those carried on along the last increment of the stage, scaled to the
//! new load-factor step (Abaqus/Standard's linear extrapolation).
//!
//! Under a steady pull the slip front moves on by about as much in each increment as in the one
//! before, so the extrapolated field starts the iteration where most points already stick or slip
//! as they will at equilibrium. The equations solved are the same (every law is integrated from the
//! last converged state, whatever the iterate), so the answer is the same to the convergence
//! tolerance; only the path of the iteration changes.

use super::state::State;
use crate::dofs::DofMap;
use serde::{Deserialize, Serialize};

/// Largest ratio of the new load-factor step to the last one that is extrapolated over: beyond it
/// the last increment says little about the next (a first step after a long pause, say).
const MAX_RATIO: f64 = 2.0;

/// The last converged increment of a stage: the displacements and multipliers before it and the
/// load factor it started from.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LastIncrement {
    pub u_before: Vec<f64>,
    pub lambda_before: Vec<f64>,
    pub from: f64,
    /// The load factor it reached.
    pub to: f64,
}

/// Move the free displacements and the multipliers of `state` (the last converged increment's,
/// which ended at `last.to`) on along `last` for the step to `target`. Held and prescribed DOFs
/// keep what the stage set them to. Nothing moves when the last increment went the other way (a
/// reversal), took no step, or the new step is more than twice as long.
pub fn extrapolate(state: &mut State, dofs: &DofMap, last: &LastIncrement, target: f64) {
    let previous_step = last.to - last.from;
    let ratio = (target - last.to) / previous_step;
    if !(ratio > 0.0 && ratio <= MAX_RATIO) || !previous_step.is_finite() {
        return;
    }
    if last.u_before.len() != state.u.len() || last.lambda_before.len() != state.lambda.len() {
        return;
    }
    for (d, eq) in dofs.equation.iter().enumerate() {
        if eq.is_some() {
            state.u[d] += ratio * (state.u_committed[d] - last.u_before[d]);
        }
    }
    for (lambda, before) in state.lambda.iter_mut().zip(&last.lambda_before) {
        // a row released now, or one whose force would change sign, keeps its multiplier: which
        // rows hold is the active set's to decide
        let extrapolated = *lambda + ratio * (*lambda - before);
        if extrapolated * *lambda > 0.0 {
            *lambda = extrapolated;
        }
    }
}
