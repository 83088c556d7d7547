//! A converged increment completed, in order: its laws and soil committed, its results computed,
//! the reinforcements' balance checked, the interface points re-associated and the repeated rows
//! found again, the displacements accepted, and its record handed to the sink. The order matters:
//! the results read the last committed displacements, which are replaced only after them.

use super::super::context::Context;
use super::super::equilibrium::IncrementReport;
use super::super::results::{reinforcement_balance, ReinforcementBalance, StepResults};
use super::super::sink::{StepRecord, StepSink};
use super::super::soil;
use super::super::springs;
use super::super::state::State;
use super::super::stats::Warning;
use super::progress::{Increment, Stage};
use crate::error::Error;
use crate::interface::reassociate::{self, Reassociation};
use crate::interface::rows::InterfaceRows;
use crate::model::ReassociationRule;
use std::time::Instant;

/// A reinforcement's force balance (applied against carried, relative) beyond which the run warns
/// (or ten times the force tolerance, when that is more).
const BALANCE_WARNING: f64 = 1e-6;

/// Complete a converged increment: commit it, compute and check its results, re-associate the
/// interface points for the next one, and hand its record to the sink.
pub fn complete_increment(
    cx: &mut Context,
    stage: &mut Stage,
    state: &mut State,
    report: IncrementReport,
    at: &Increment,
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    commit(state, &report);
    let output_started = Instant::now();
    let results = step_results(cx, stage, state, &report);
    let balance = check_balance(cx, stage, at, &results, state);
    cx.stats.output_seconds += output_started.elapsed().as_secs_f64();
    let search_started = Instant::now();
    let reassociations = reassociate_points(cx, state);
    let redundant_rows = remark_redundant(cx, stage, state);
    cx.stats.interface_seconds += search_started.elapsed().as_secs_f64();
    accept_displacements(state);
    let record = step_record(stage, state, report, at, redundant_rows, reassociations, balance);
    hand_over(cx, sink, &results, &record)
}

/// The interface laws' and the soil's states at equilibrium become the committed ones.
fn commit(state: &mut State, report: &IncrementReport) {
    springs::commit(state, &report.springs);
    soil::commit(&mut state.soil, &report.soil);
}

/// The step's results (displacements, reactions, interface stresses, bar forces), from the
/// displacements still committed from the step before where they depend on them.
fn step_results(cx: &Context, stage: &Stage, state: &State, report: &IncrementReport) -> StepResults {
    let rows = InterfaceRows::new(&cx.model.mesh, &state.interfaces, &stage.dofs.multipliers);
    StepResults::compute(cx.model, &cx.elements, &rows, &report.springs, state, &report.element_force, &cx.held)
}

/// Each reinforcement's force balance, with a warning (once per reinforcement) where the forces
/// applied to it and those its interfaces carry differ well beyond the force tolerance.
fn check_balance(
    cx: &mut Context,
    stage: &Stage,
    at: &Increment,
    results: &StepResults,
    state: &State,
) -> Vec<ReinforcementBalance> {
    let balance = reinforcement_balance(cx.model, results, state);
    // an increment converges with a residual up to the force tolerance of the force scale, and a
    // reinforcement's balance is part of that residual: only a mismatch well beyond it is news
    let allowed = BALANCE_WARNING.max(10.0 * cx.options.analysis.force_tolerance);
    for b in balance.iter().filter(|b| !(b.mismatch <= allowed)) {
        let of = if b.applied[0].hypot(b.applied[1]) >= b.scale {
            "the applied force"
        } else {
            "the model's largest nodal force"
        };
        cx.stats.warnings.add(Warning::ReinforcementBalance {
            interface: b.interface.clone(),
            applied: b.applied,
            carried: b.interface_force,
            mismatch: b.mismatch,
            of,
            stage: stage.plan.name.clone(),
            step: at.step,
        });
    }
    balance
}

/// Re-associate the interface points with the segments they face now (large slip), and uncover
/// the slits behind them; room for the segments a next step may reach.
fn reassociate_points(cx: &Context, state: &mut State) -> Vec<Reassociation> {
    let (model, options) = (cx.model, cx.options);
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
    reassociations
}

/// The rows carried by others in this step, and found again for the next one where the points
/// were re-associated (new associations and clipped lengths can make two rows repeat each other:
/// both faces tied to segments ending at one soil node, at a slit tip).
fn remark_redundant(cx: &mut Context, stage: &mut Stage, state: &mut State) -> Vec<String> {
    let redundant_now = stage.progress.redundant.clone();
    if cx.options.analysis.reassociation != ReassociationRule::None {
        stage.progress.redundant = cx.active_set(&stage.dofs, &state.placed).mark_redundant(&mut state.interfaces);
    }
    redundant_now
}

/// The converged displacements become the committed ones, from which the next increment's strains
/// and an embedded reinforcement's σn count.
fn accept_displacements(state: &mut State) {
    state.u_committed = state.u.clone();
    state.soil_sigma_from = None;
}

/// What the step's record says of it.
fn step_record(
    stage: &Stage,
    state: &State,
    report: IncrementReport,
    at: &Increment,
    redundant_rows: Vec<String>,
    reassociations: Vec<Reassociation>,
    balance: Vec<ReinforcementBalance>,
) -> StepRecord {
    StepRecord {
        stage: stage.plan.name.clone(),
        stage_index: stage.index,
        step: at.step,
        load_factor: at.load_factor,
        time: state.motion.as_ref().map(|m| m.time),
        strength_factor: at.strength_factor,
        reversal: at.reversal,
        iterations: report.iterations,
        cutbacks: at.cutbacks,
        force_residual: report.force_residual,
        linear_residuals: report.linear_residuals,
        seconds: at.started.elapsed().as_secs_f64(),
        redundant_rows,
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
    }
}

/// The step's results and record to the sink (which writes them), timed as output.
fn hand_over(
    cx: &mut Context,
    sink: &mut dyn StepSink,
    results: &StepResults,
    record: &StepRecord,
) -> Result<(), Error> {
    let written = Instant::now();
    sink.step_done(cx.model, results, record, &cx.stats)?;
    cx.stats.output_seconds += written.elapsed().as_secs_f64();
    Ok(())
}
