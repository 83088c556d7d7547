//! Which nodes a stage's soil and reinforcement place, which DOFs they leave held, and what the
//! soil's change puts out of balance.

use super::super::context::Context;
use super::super::soil;
use super::super::springs::InterfaceIterate;
use super::super::state::State;
use crate::assembly::{internal_force, SoilView};
use crate::dofs::DofMap;
use crate::element::bar::BarStates;
use crate::element::soil_state::{SoilField, Tangent};
use crate::interface::rows::constraint_force;
use crate::model::Model;

/// Which nodes a stage's soil and reinforcement place, and which DOFs that leaves held.
pub(super) struct Placement {
    /// Nodes of present soil elements and of placed bars, and nodes of neither (a rigid base).
    pub placed: Vec<bool>,
    /// The DOFs held: those held anyway, and both DOFs of every node of absent soil or of a bar not
    /// yet placed.
    pub held: Vec<bool>,
}

impl Placement {
    /// The placement of the soil `field` and the `bars`, with the DOFs `held` anyway.
    pub fn of(model: &Model, field: &SoilField, bars: &BarStates, held: &[bool]) -> Placement {
        let present = soil::present_nodes(model, field);
        Placement { placed: placed_nodes(model, &present, bars), held: with_absent_nodes(model, &present, bars, held) }
    }
}

/// Nodes of present soil elements (`present`) and of placed bars, and nodes of neither (a rigid
/// base).
fn placed_nodes(model: &Model, present: &[bool], bars: &BarStates) -> Vec<bool> {
    let mut placed = present.to_vec();
    let mut in_something = vec![false; placed.len()];
    for e in &model.mesh.solids {
        for &n in &e.nodes {
            in_something[n] = true;
        }
    }
    for (i, b) in model.mesh.bars.iter().enumerate() {
        for &n in &b.nodes {
            in_something[n] = true;
            if !bars.absent[i] {
                placed[n] = true;
            }
        }
    }
    for (p, used) in placed.iter_mut().zip(in_something) {
        *p |= !used;
    }
    placed
}

/// `held` plus both DOFs of every node whose soil elements are all absent (and that no bar uses),
/// and of every bar not yet placed.
fn with_absent_nodes(model: &Model, present: &[bool], bars: &BarStates, held: &[bool]) -> Vec<bool> {
    let mut held = held.to_vec();
    let mut in_soil = vec![false; present.len()];
    for e in &model.mesh.solids {
        for &n in &e.nodes {
            in_soil[n] = true;
        }
    }
    for b in &model.mesh.bars {
        for &n in &b.nodes {
            in_soil[n] = false;
        }
    }
    for n in 0..present.len() {
        if in_soil[n] && !present[n] {
            held[2 * n] = true;
            held[2 * n + 1] = true;
        }
    }
    // the nodes of reinforcement not yet placed
    for (i, b) in model.mesh.bars.iter().enumerate() {
        if bars.absent[i] {
            for &n in &b.nodes {
                held[2 * n] = true;
                held[2 * n + 1] = true;
            }
        }
    }
    held
}

/// The out-of-balance force of the converged state under the stage's new soil configuration, on the
/// free DOFs: f_ext − f_int − Cᵀλ.
pub(super) fn unbalance(cx: &Context, dofs: &DofMap, state: &State) -> Vec<f64> {
    let out_of_balance = out_of_balance(cx, dofs, state);
    (0..state.u.len()).map(|d| if dofs.equation[d].is_some() { out_of_balance[d] } else { 0.0 }).collect()
}

/// The reactions of the supports at `freed` in the converged state: f_int + Cᵀλ − f_ext there.
pub(super) fn reactions(cx: &Context, dofs: &DofMap, state: &State, freed: &[usize]) -> Vec<f64> {
    let out_of_balance = out_of_balance(cx, dofs, state);
    freed.iter().map(|&d| -out_of_balance[d]).collect()
}

/// f_ext − f_int − Cᵀλ over all displacement DOFs.
fn out_of_balance(cx: &Context, dofs: &DofMap, state: &State) -> Vec<f64> {
    let interface = InterfaceIterate::at(cx.model, state, &dofs.multipliers);
    let trial = soil::evaluate(&cx.setup, &state.soil, &state.u, &state.u_committed, Tangent::Elastic);
    let view = SoilView { field: &state.soil, trial: &trial };
    let f_int = internal_force(&cx.elements, view, &interface.rows, &interface.taus(), &state.bars, &state.u);
    let f_c = constraint_force(&interface.rows, &state.lambda, state.u.len());
    (0..state.u.len()).map(|d| state.f_ext[d] - f_int[d] - f_c[d]).collect()
}
