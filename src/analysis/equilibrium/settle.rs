//! The σn of an embedded reinforcement, settled within each increment.
//!
//! An embedded point's σn is the soil's normal stress across the reinforcement
//! ([`normal_stress`]). Taken at every iterate it would depend on the shear the
//! point itself puts into the soil beside it, and an increment could then have more than one
//! equilibrium (the constant-stiffness and Newton schemes found two, 1 % apart, on
//! `examples/embedded-pullout`). So each pass of an increment holds σn at the soil's stress of a
//! given displacement field (at first the last converged increment's) and iterates to equilibrium;
//! then σn is taken again at the equilibrium found, and the increment is iterated again from there,
//! until σn changes by less than [`SETTLED`] of the largest. Each pass is one problem with one
//! answer, so every scheme goes through the same passes to the same end.

use super::super::context::Context;
use super::super::convergence::IncrementError;
use super::super::springs::normal_stress;
use super::super::state::State;
use super::iterate::iterate;
use super::iterations::IncrementReport;
use crate::dofs::DofMap;
use crate::interface::rows::InterfaceRows;

/// σn has settled when no embedded point's changed by more than this share of the largest.
pub const SETTLED: f64 = 1e-9;

/// The most passes of one increment before it is cut back.
pub const MAX_PASSES: usize = 50;

/// Iterate an increment to equilibrium, and again while its embedded reinforcements' σn moves.
/// `stall_iterations` as in [`iterate`].
pub(super) fn settled(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    stall_iterations: usize,
) -> Result<IncrementReport, IncrementError> {
    let mut report = iterate(cx, dofs, state, stall_iterations)?;
    let embedded = state.interfaces.iter().flat_map(|i| &i.faces).any(|f| f.embedded.is_some());
    if !embedded || state.frozen_sigma_n.is_some() {
        return Ok(report);
    }
    let mut iterations = report.iterations;
    for _ in 0..MAX_PASSES {
        let used = embedded_sigma_n(cx, dofs, state);
        let from = std::mem::replace(&mut state.soil_sigma_from, Some(state.u.clone()));
        let now = embedded_sigma_n(cx, dofs, state);
        let largest = now.iter().map(|(_, s)| s.abs()).fold(0.0f64, f64::max);
        let moved: Vec<&(String, f64)> = used
            .iter()
            .zip(&now)
            .filter(|((_, a), (_, b))| (a - b).abs() > SETTLED * largest.max(f64::MIN_POSITIVE))
            .map(|(_, b)| b)
            .collect();
        if moved.is_empty() {
            state.soil_sigma_from = from;
            report.iterations = iterations;
            return Ok(report);
        }
        report = iterate(cx, dofs, state, stall_iterations)?;
        iterations += report.iterations;
    }
    let unsettled = embedded_sigma_n(cx, dofs, state)
        .into_iter()
        .take(12)
        .map(|(point, s)| format!("{point}: σn from the soil still moving ({s:.4})"))
        .collect();
    Err(IncrementError::NotConverged {
        iterations,
        residual: 0.0,
        reference: 1.0,
        unsettled,
        yielding: 0,
        stalled: None,
    })
}

/// Each embedded point's σn (named), from the soil at `state.soil_sigma_from` (or the last
/// converged increment).
fn embedded_sigma_n(cx: &Context, dofs: &DofMap, state: &State) -> Vec<(String, f64)> {
    let rows = InterfaceRows::new(&cx.model.mesh, &state.interfaces, &dofs.multipliers);
    rows.springs
        .iter()
        .filter(|s| state.interfaces[s.interface].faces[s.face].embedded.is_some())
        .map(|s| {
            let name =
                format!("interface \"{}\" node {}", state.interfaces[s.interface].name, cx.model.mesh.node_id(s.slave));
            (name, normal_stress(cx.model, state, &rows, s))
        })
        .collect()
}
