//! One stage: set up (soil placed or removed, water, K0 stresses, contacts placed, DOFs numbered,
//! loads), then its increments, each cut back when it fails, and each converged one committed and
//! handed to the sink.

use super::checkpoint::{Checkpoint, ModelPrint, StageProgress};
use super::context::Context;
use super::equilibrium::{self, EmbeddedSigmaN, IncrementReport};
use super::loads::external_force;
use super::predictor::{self, LastIncrement};
use super::results::{reinforcement_balance, StepResults};
use super::sink::{StepRecord, StepSink};
use super::soil;
use super::springs::{self, normal_stress};
use super::state::State;
use crate::assembly::{internal_force, SoilView};
use crate::dofs::{dof, DofMap};
use crate::element::bar::BarStates;
use crate::element::soil_state::{SoilField, Tangent};
use crate::error::Error;
use crate::interface::active_set::place_contacts;
use crate::interface::reassociate;
use crate::interface::rows::{constraint_force, InterfaceRows};
use crate::model::{Extrapolation, Load, Model, ReassociationRule, StagePlan};
use std::time::Instant;

/// A stage once it is set up.
pub struct Stage<'a> {
    pub plan: &'a StagePlan,
    pub index: usize,
    /// The DOFs of this stage: held where supported, prescribed or not yet placed.
    pub dofs: DofMap,
    /// Rows carried by others (see `ActiveSet::mark_redundant`), as last found.
    pub redundant: Vec<String>,
    /// The stage's full load (factor 1): its loads and the change in the soil's weight.
    force: Vec<f64>,
    /// The applied force when the stage started.
    f_ext_start: Vec<f64>,
    /// What the soil's change put out of balance, released over the stage's load factors.
    unbalance: Vec<f64>,
}

/// Where a converged increment sits in its stage.
pub struct Increment {
    pub step: usize,
    pub load_factor: f64,
    /// The strength reduction factor of a strength-reduction stage.
    pub strength_factor: Option<f64>,
    pub cutbacks: usize,
    pub started: Instant,
    /// A loading history's factor reverses at this step.
    pub reversal: bool,
}

/// Set a stage up: the soil it places and removes, its water table and K0 stresses, the contacts
/// it puts in place, its DOFs and its loads.
pub fn set_up<'a>(cx: &mut Context, state: &mut State, plan: &'a StagePlan, index: usize) -> Stage<'a> {
    let model = cx.model;
    for &(n, d, _) in &plan.prescribed {
        cx.held[dof(n, d)] = true;
    }
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
    let placed_before = std::mem::replace(&mut state.placed, placed_nodes(model, &state.soil, &state.bars));
    place_contacts(&mut state.interfaces, &mut state.lambda, &state.placed, &placed_before);
    let stage_held = with_absent_nodes(model, &state.soil, &state.bars, &cx.held);
    let dofs = DofMap::new(model.mesh.nodes.len(), &stage_held, &state.interfaces);
    let redundant = cx.active_set(&dofs, &state.placed).mark_redundant(&mut state.interfaces);
    // This stage's additions: its loads, and the change in the soil's weight (gravity switched on
    // or up, soil placed or removed, soil under a new water table).
    cx.gravity += plan.loads.iter().map(|l| if let Load::Gravity { factor } = l { *factor } else { 0.0 }).sum::<f64>();
    let mut weight = soil::weight(model, &cx.setup, &state.soil, cx.gravity);
    for (w, p) in weight.iter_mut().zip(soil::water_on_boundary(model, &state.soil, &state.interfaces)) {
        *w += p;
    }
    let mut force = external_force(model, &plan.loads);
    for ((f, w), a) in force.iter_mut().zip(&weight).zip(&cx.applied_weight) {
        *f += w - a;
    }
    cx.applied_weight = weight;
    let f_ext_start = state.f_ext.clone();
    // What the soil's change put out of balance (removed soil, new pore pressures, K0 stresses off
    // equilibrium) is released over the stage's load factors: f_ext starts at the internal force of
    // the new configuration and ends at the applied loads.
    let unbalance = if soil_changed { unbalance(cx, &dofs, state) } else { vec![0.0; state.u.len()] };
    Stage { plan, index, dofs, redundant, force, f_ext_start, unbalance }
}

/// A stage set up again from a saved step's progress: its DOFs from the saved state, the rest as
/// its set-up left it then.
pub fn resumed<'a>(
    cx: &Context,
    state: &State,
    plan: &'a StagePlan,
    index: usize,
    progress: &StageProgress,
) -> Stage<'a> {
    let stage_held = with_absent_nodes(cx.model, &state.soil, &state.bars, &cx.held);
    let dofs = DofMap::new(cx.model.mesh.nodes.len(), &stage_held, &state.interfaces);
    Stage {
        plan,
        index,
        dofs,
        redundant: progress.redundant.clone(),
        force: progress.force.clone(),
        f_ext_start: progress.f_ext_start.clone(),
        unbalance: progress.unbalance.clone(),
    }
}

/// The stage's increments: each target load factor in turn; a failed increment is cut back (its
/// midpoint put in front, the state restored) up to `max_cutbacks` times. `resume` continues the
/// stage from a saved step (its progress and converged step count) instead of its start.
pub fn increments(
    cx: &mut Context,
    state: &mut State,
    stage: &mut Stage,
    sink: &mut dyn StepSink,
    resume: Option<(&StageProgress, usize)>,
) -> Result<(), Error> {
    let (model, plan) = (cx.model, stage.plan);
    let (u_start, mut targets, mut reached, mut step, mut planned, mut cutbacks, mut last) = match resume {
        Some((p, step)) => {
            (p.u_start.clone(), p.targets.clone(), p.reached, step, p.planned, p.cutbacks, p.last.clone())
        }
        None => {
            let freeze = plan.freeze_normal_stress.unwrap_or(cx.options.analysis.freeze_normal_stress);
            state.frozen_sigma_n = None;
            if freeze {
                let rows = InterfaceRows::new(&model.mesh, &state.interfaces, &stage.dofs.multipliers);
                let frozen: Vec<f64> = rows.springs.iter().map(|s| normal_stress(model, state, &rows, s)).collect();
                warn_of_unloaded_freeze(cx, state, plan, &rows, &frozen);
                state.frozen_sigma_n = Some(frozen);
            }
            (state.u.clone(), plan.load_factors.clone(), 0.0, 0, 0, 0, None)
        }
    };
    let extrapolate = cx.options.analysis.extrapolation == Extrapolation::Linear;
    let print = sink.keeps_checkpoints().then(|| ModelPrint::of(model));
    while let Some(&target) = targets.first() {
        let started = Instant::now();
        let snapshot = state.clone();
        // the out-of-balance force left by the stage before goes in with the factor, or, for a
        // history (whose factor may go back or change sign), in the first step
        let ramp = if plan.cyclic { 1.0 } else { target };
        for (k, f) in state.f_ext.iter_mut().enumerate() {
            *f = stage.f_ext_start[k] + target * stage.force[k] - (1.0 - ramp) * stage.unbalance[k];
        }
        for &(n, d, value) in &plan.prescribed {
            state.u[dof(n, d)] = u_start[dof(n, d)] + target * value;
        }
        if let Some(last) = last.as_ref().filter(|_| extrapolate) {
            predictor::extrapolate(state, &stage.dofs, last, target);
        }
        let report = match equilibrium::increment(cx, &stage.dofs, state, EmbeddedSigmaN::Settled) {
            Ok(report) => report,
            Err(e) => {
                if e.retryable() && cutbacks < cx.options.analysis.max_cutbacks {
                    *state = snapshot;
                    targets.insert(0, 0.5 * (reached + target));
                    cutbacks += 1;
                    continue;
                }
                return Err(e.at(&model.source, &plan.name, step + 1, cutbacks));
            }
        };
        step += 1;
        // a step of the plan (not a cutback's midpoint): count it, and whether the history reverses
        let planned_step = plan.load_factors.get(planned) == Some(&target);
        if planned_step {
            planned += 1;
        }
        let reversal = planned_step && plan.reversals.contains(&planned);
        let at = Increment { step, load_factor: target, strength_factor: None, cutbacks, started, reversal };
        complete_increment(cx, stage, state, report, &at, sink)?;
        if extrapolate {
            last =
                Some(LastIncrement { u_before: snapshot.u, lambda_before: snapshot.lambda, from: reached, to: target });
        }
        targets.remove(0);
        reached = target;
        if planned_step {
            cutbacks = 0;
        }
        if let Some(print) = &print {
            let progress = StageProgress {
                redundant: stage.redundant.clone(),
                force: stage.force.clone(),
                f_ext_start: stage.f_ext_start.clone(),
                unbalance: stage.unbalance.clone(),
                u_start: u_start.clone(),
                targets: targets.clone(),
                reached,
                planned,
                cutbacks,
                last: last.clone(),
            };
            sink.checkpoint(&Checkpoint {
                geoslip_version: env!("CARGO_PKG_VERSION").into(),
                model: print.clone(),
                stage_index: stage.index,
                stage: plan.name.clone(),
                step,
                state: state.clone(),
                held: cx.held.clone(),
                gravity: cx.gravity,
                applied_weight: cx.applied_weight.clone(),
                progress,
            })?;
        }
    }
    Ok(())
}

/// A reinforcement's force balance (applied against carried, relative) beyond which the run warns
/// (or ten times the force tolerance, when that is more).
const BALANCE_WARNING: f64 = 1e-6;

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
        let warning = format!(
            "stage \"{}\" freezes σn at its start, where no interface point in contact is compressed yet ({unloaded} points at σn ≤ 0): their shear strength through the stage is the cohesion alone; set freeze_normal_stress = false on that stage",
            plan.name
        );
        cx.system.stats.warn(warning);
    }
}

/// Commit a converged increment (shear states and soil stresses), hand its results to the sink, and
/// re-associate the interface points for the next one.
pub fn complete_increment(
    cx: &mut Context,
    stage: &mut Stage,
    state: &mut State,
    report: IncrementReport,
    at: &Increment,
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    let (model, options) = (cx.model, cx.options);
    springs::commit(state, &report.springs);
    soil::commit(&mut state.soil, &report.soil);
    let output_started = Instant::now();
    let rows = InterfaceRows::new(&model.mesh, &state.interfaces, &stage.dofs.multipliers);
    let results =
        StepResults::compute(model, &cx.elements, &rows, &report.springs, state, &report.element_force, &cx.held);
    let balance = reinforcement_balance(model, &results, state);
    // an increment converges with a residual up to the force tolerance of the force scale, and a
    // reinforcement's balance is part of that residual: only a mismatch well beyond it is news
    let allowed = BALANCE_WARNING.max(10.0 * options.analysis.force_tolerance);
    for b in balance.iter().filter(|b| !(b.mismatch <= allowed)) {
        let of = if b.applied[0].hypot(b.applied[1]) >= b.scale {
            "the applied force"
        } else {
            "the model's largest nodal force"
        };
        let warning = format!(
            "reinforcement \"{}\": the forces applied to its nodes ({:.6e}, {:.6e}) and those its interfaces carry ({:.6e}, {:.6e}) differ by {:.1e} of {of}, beyond ten times the force tolerance (first in stage \"{}\", step {})",
            b.interface, b.applied[0], b.applied[1], b.interface_force[0], b.interface_force[1], b.mismatch, stage.plan.name, at.step
        );
        let known = format!("reinforcement \"{}\": the forces applied", b.interface);
        if !cx.system.stats.warnings.iter().any(|w| w.starts_with(&known)) {
            cx.system.stats.warnings.push(warning);
        }
    }
    cx.system.stats.output_seconds += output_started.elapsed().as_secs_f64();
    let search_started = Instant::now();
    let rule = options.analysis.reassociation;
    let mut reassociations = match rule {
        ReassociationRule::None => Vec::new(),
        rule => {
            let tie = match rule {
                ReassociationRule::NearestNode => reassociate::Tie::NearestNode,
                ReassociationRule::Mortar => reassociate::Tie::Mortar,
                _ => reassociate::Tie::Segment,
            };
            reassociate::reassociate(&model.mesh, &mut state.interfaces, &state.u, tie)
        }
    };
    if rule != ReassociationRule::None {
        reassociations.extend(reassociate::uncover_slits(&model.mesh, &mut state.interfaces, &state.u));
    }
    state.reserve_segments(options);
    let redundant_now = stage.redundant.clone();
    if rule != ReassociationRule::None {
        // new associations and clipped lengths can make two rows repeat each other (both faces
        // tied to segments ending at one soil node, at a slit tip): find them again
        stage.redundant = cx.active_set(&stage.dofs, &state.placed).mark_redundant(&mut state.interfaces);
    }
    cx.system.stats.interface_seconds += search_started.elapsed().as_secs_f64();
    state.u_committed = state.u.clone();
    state.soil_sigma_from = None;
    let record = StepRecord {
        stage: stage.plan.name.clone(),
        stage_index: stage.index,
        step: at.step,
        load_factor: at.load_factor,
        strength_factor: at.strength_factor,
        reversal: at.reversal,
        iterations: report.iterations,
        cutbacks: at.cutbacks,
        force_residual: report.force_residual,
        linear_residuals: report.linear_residuals,
        seconds: at.started.elapsed().as_secs_f64(),
        redundant_rows: redundant_now,
        state_changes: report.state_changes,
        reassociations,
        sliding_points: report.springs.iter().filter(|r| r.sliding).count(),
        yielding_points: report.soil.yielding,
        contact_points: report
            .springs
            .iter()
            .filter(|r| state.interfaces[r.interface].faces[r.face].points[r.point].in_contact())
            .count(),
        balance,
    };
    let written = Instant::now();
    sink.step_done(&results, &record, &cx.system.stats)?;
    cx.system.stats.output_seconds += written.elapsed().as_secs_f64();
    Ok(())
}

/// Nodes of present soil elements and of placed bars, and nodes of neither (a rigid base).
fn placed_nodes(model: &Model, field: &SoilField, bars: &BarStates) -> Vec<bool> {
    let mut placed = soil::present_nodes(model, field);
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
fn with_absent_nodes(model: &Model, field: &SoilField, bars: &BarStates, held: &[bool]) -> Vec<bool> {
    let mut held = held.to_vec();
    let present = soil::present_nodes(model, field);
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
fn unbalance(cx: &Context, dofs: &DofMap, state: &State) -> Vec<f64> {
    let rows = InterfaceRows::new(&cx.model.mesh, &state.interfaces, &dofs.multipliers);
    let springs = springs::evaluate(cx.model, state, &rows);
    let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
    let trial = soil::evaluate(&cx.setup, &state.soil, &state.u, &state.u_committed, Tangent::Elastic);
    let view = SoilView { field: &state.soil, trial: &trial };
    let f_int = internal_force(&cx.elements, view, &rows, &taus, &state.bars, &state.u);
    let f_c = constraint_force(&rows, &state.lambda, state.u.len());
    (0..state.u.len())
        .map(|d| if dofs.equation[d].is_some() { state.f_ext[d] - f_int[d] - f_c[d] } else { 0.0 })
        .collect()
}
