//! One stage: set up (soil placed or removed, water, K0 stresses, contacts placed, DOFs numbered,
//! loads), then its increments, each cut back when it fails, and each converged one completed
//! (`complete.rs`) and handed to the sink. A stage's progress (its set-up's results, the load
//! factors still to reach) is one value, [`StageProgress`], which a saved step keeps as it is.

mod complete;
mod cutback;
mod dynamic;
mod placement;
pub(in crate::analysis) mod progress;

pub use complete::complete_increment;
pub use dynamic::time_steps;
pub use progress::{Increment, Stage, StageProgress};

use placement::{unbalance, Placement};

use super::absorbing;
use super::checkpoint::{Checkpoint, ModelPrint};
use super::context::Context;
use super::loads::external_force;
use super::predictor::{self, LastIncrement};
use super::sink::StepSink;
use super::soil;
use super::springs::normal_stress;
use super::state::State;
use super::stats::Warning;
use crate::dofs::{dof, DofMap};
use crate::error::Error;
use crate::interface::active_set::place_contacts;
use crate::interface::rows::InterfaceRows;
use crate::model::{Extrapolation, Load, StagePlan};
use std::time::Instant;

/// Set a stage up: the soil it places and removes, its water table and K0 stresses, the contacts
/// it puts in place, its DOFs and its loads.
pub fn set_up<'a>(cx: &mut Context, state: &mut State, plan: &'a StagePlan, index: usize) -> Stage<'a> {
    let model = cx.model;
    for &(n, d, _) in &plan.prescribed {
        cx.held[dof(n, d)] = true;
    }
    let freed = plan.dynamic.as_ref().map_or(Vec::new(), |d| absorbing::free_supports(model, d, &mut cx.held));
    // The soil of this stage: lifts placed, soil removed, a new water table, K0 stresses.
    let soil_changed = !plan.activate.is_empty() || !plan.deactivate.is_empty() || plan.k0 || plan.water.is_some();
    soil::deactivate(&mut state.soil, &plan.deactivate);
    let bar_nodes: Vec<usize> = plan.activate_bars.iter().flat_map(|&b| model.mesh.bars[b].nodes).collect();
    soil::activate(model, &cx.setup, &mut state.soil, &plan.activate, &bar_nodes, &mut state.u);
    // placed reinforcement: its force counts from the stretch it lands with
    for &b in &plan.activate_bars {
        state.bars.absent[b] = false;
        let law = &cx.elements.bars[b];
        state.bars.placed_stretch[b] = law.stretch(&state.u, cx.elements.bar_dofs(b));
    }
    if soil_changed {
        let water = plan.water.clone().unwrap_or_else(|| state.soil.water.clone());
        soil::set_water(model, &cx.setup, &mut state.soil, water);
    }
    if plan.k0 {
        soil::set_k0(model, &cx.setup, &mut state.soil, &state.u);
    }
    state.u_committed = state.u.clone();
    let placement = Placement::of(model, &state.soil, &state.bars, &cx.held);
    let placed_before = std::mem::replace(&mut state.placed, placement.placed);
    place_contacts(&mut state.interfaces, &mut state.lambda, &state.placed, &placed_before);
    let dofs = DofMap::new(model.mesh.nodes.len(), &placement.held, &state.interfaces);
    let redundant = cx.active_set(&dofs, &state.placed).mark_redundant(&mut state.interfaces);
    // This stage's additions: its loads, and the change in the soil's weight (gravity switched on
    // or up, soil placed or removed, soil under a new water table).
    cx.gravity += plan.loads.iter().map(|l| if let Load::Gravity { factor } = l { *factor } else { 0.0 }).sum::<f64>();
    let water = soil::water_on_boundary(model, &state.soil, &state.interfaces);
    let mut weight = soil::weight(model, &cx.setup, &state.soil, cx.gravity);
    for (w, p) in weight.iter_mut().zip(water) {
        *w += p;
    }
    let mut force = external_force(model, &plan.loads);
    // the pseudo-static force of the soil present now
    for load in &plan.loads {
        if let Load::PseudoStatic { coefficients } = load {
            for (f, b) in force.iter_mut().zip(soil::body_force(model, &cx.setup, &state.soil, *coefficients)) {
                *f += b;
            }
        }
    }
    for ((f, w), a) in force.iter_mut().zip(&weight).zip(&cx.applied_weight) {
        *f += w - a;
    }
    cx.applied_weight = weight;
    let f_ext_start = state.f_ext.clone();
    // What the soil's change put out of balance (removed soil, new pore pressures, K0 stresses off
    // equilibrium) is released over the stage's load factors: f_ext starts at the internal force of
    // the new configuration and ends at the applied loads.
    let unbalance = if soil_changed { unbalance(cx, &dofs, state) } else { vec![0.0; state.u.len()] };
    let progress = StageProgress {
        redundant,
        force,
        f_ext_start,
        unbalance,
        u_start: state.u.clone(),
        targets: plan.load_factors.clone(),
        reached: 0.0,
        planned: 0,
        cutbacks: 0,
        last: None,
    };
    Stage { plan, index, dofs, step: 0, freed, progress }
}

/// A stage set up again from a saved step: its DOFs from the saved state, its progress and step
/// count as saved.
pub fn resumed<'a>(
    cx: &Context,
    state: &State,
    plan: &'a StagePlan,
    index: usize,
    progress: StageProgress,
    step: usize,
) -> Stage<'a> {
    let placement = Placement::of(cx.model, &state.soil, &state.bars, &cx.held);
    let dofs = DofMap::new(cx.model.mesh.nodes.len(), &placement.held, &state.interfaces);
    Stage { plan, index, dofs, step, freed: Vec::new(), progress }
}

/// Freeze the interfaces' σn for the stage's increments when it asks for it (at the start of a
/// loading stage; a saved step carries the frozen values in its state).
pub fn freeze_normal_stress(cx: &mut Context, state: &mut State, stage: &Stage) {
    let (model, plan) = (cx.model, stage.plan);
    let freeze = plan.freeze_normal_stress.unwrap_or(cx.options.analysis.freeze_normal_stress);
    state.frozen_sigma_n = None;
    if freeze {
        let rows = InterfaceRows::new(&model.mesh, &state.interfaces, &stage.dofs.multipliers);
        let frozen: Vec<f64> = rows.springs.iter().map(|s| normal_stress(model, state, &rows, s)).collect();
        warn_of_unloaded_freeze(cx, state, plan, &rows, &frozen);
        state.frozen_sigma_n = Some(frozen);
    }
}

/// The stage's increments from where its progress stands: each target load factor in turn; a
/// failed increment is cut back (its midpoint put in front, the state restored) up to
/// `max_cutbacks` times.
pub fn increments(
    cx: &mut Context,
    state: &mut State,
    stage: &mut Stage,
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    let (model, plan) = (cx.model, stage.plan);
    let extrapolate = cx.options.analysis.extrapolation == Extrapolation::Linear;
    let print = sink.keeps_checkpoints().then(|| ModelPrint::of(model));
    while let Some(&target) = stage.progress.targets.first() {
        let started = Instant::now();
        let snapshot = state.clone();
        // the out-of-balance force left by the stage before goes in with the factor, or, for a
        // history (whose factor may go back or change sign), in the first step
        let ramp = if plan.cyclic { 1.0 } else { target };
        let progress = &stage.progress;
        for (k, f) in state.f_ext.iter_mut().enumerate() {
            *f = progress.f_ext_start[k] + target * progress.force[k] - (1.0 - ramp) * progress.unbalance[k];
        }
        for &(n, d, value) in &plan.prescribed {
            state.u[dof(n, d)] = progress.u_start[dof(n, d)] + target * value;
        }
        if let Some(last) = progress.last.as_ref().filter(|_| extrapolate) {
            predictor::extrapolate(state, &stage.dofs, last, target);
        }
        let Some(report) = cutback::solved_or_cut_back(cx, stage, state, &snapshot, target)? else { continue };
        stage.step += 1;
        // a step of the plan (not a cutback's midpoint): count it, and whether the history reverses
        let progress = &mut stage.progress;
        let planned_step = progress.count_planned(&plan.load_factors, target);
        let reversal = planned_step && plan.reversals.contains(&progress.planned);
        let at = Increment {
            step: stage.step,
            load_factor: target,
            strength_factor: None,
            cutbacks: progress.cutbacks,
            started,
            reversal,
        };
        complete_increment(cx, stage, state, report, &at, sink)?;
        let progress = &mut stage.progress;
        if extrapolate {
            progress.last = Some(LastIncrement {
                u_before: snapshot.u,
                lambda_before: snapshot.lambda,
                from: progress.reached,
                to: target,
            });
        }
        progress.reach(target, planned_step);
        if let Some(print) = &print {
            let saving = Instant::now();
            let saved = sink.checkpoint(Checkpoint {
                geoslip_version: env!("CARGO_PKG_VERSION").into(),
                model: print.clone(),
                stage_index: stage.index,
                stage: plan.name.clone(),
                step: stage.step,
                state: state.clone(),
                held: cx.held.clone(),
                gravity: cx.gravity,
                applied_weight: cx.applied_weight.clone(),
                progress: stage.progress.clone(),
            });
            cx.stats.checkpoint_seconds += saving.elapsed().as_secs_f64();
            saved?;
        }
    }
    Ok(())
}

/// A stage that freezes σn where no interface point in contact is compressed yet (a surcharge
/// stage, before the surcharge) leaves its faces the cohesion alone: say so in the run's warnings.
fn warn_of_unloaded_freeze(cx: &mut Context, state: &State, plan: &StagePlan, rows: &InterfaceRows, frozen: &[f64]) {
    let in_contact: Vec<f64> = rows
        .springs
        .iter()
        .zip(frozen)
        .filter(|(s, _)| state.interfaces[s.interface].faces[s.face].points[s.point].in_contact())
        .map(|(_, &f)| f)
        .collect();
    let unloaded = in_contact.iter().filter(|&&f| !(f > 0.0)).count();
    if unloaded > 0 && unloaded == in_contact.len() {
        cx.stats.warnings.add(Warning::UnloadedFreeze { stage: plan.name.clone(), unloaded });
    }
}
