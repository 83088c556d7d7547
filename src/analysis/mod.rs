//! Stages, increments and the equilibrium iteration (the paper's Fig. 3).
//!
//! [`run`] reads top to bottom: the run's context (element matrices, soil laws, the solver), the
//! initial state, then for each stage its set-up and either its increments (each iterated to
//! equilibrium, cut back when it fails, committed and handed to the sink) or a strength-reduction
//! search for the factor of safety.
//!
//! - `options`: what a run may be asked to do; `sink`: where its steps and factors of safety go;
//! - `context`: what the run keeps from start to end; `state`: what a step carries to the next;
//!   `stats`: the run's counts, times and typed warnings;
//! - `stage`: a stage's set-up, its increments with cutback, and the completion of each step;
//!   `checkpoint` and `resume_check`: a saved step and whether it fits the model;
//! - `predictor`: an increment's first iterate (the last increment's, carried on when asked);
//! - `equilibrium`: one increment's iterations (linearise → solve → update → check), with
//!   `iteration_system` (an iteration's matrix inputs and right-hand side), `loads` and
//!   `correction` (the line search and the update);
//! - `convergence`: when an increment has converged, and how it failed; `singular`: the recoveries
//!   from a singular matrix, or the diagnosis of what is unconstrained; `non_finite`: where a NaN
//!   or an infinity first appeared;
//! - `springs`: the interface springs' shear laws at an iterate; `soil`: the soil through a run;
//! - `strength_reduction`: the factor-of-safety search; `results`: what a converged step produced.
//!
//! Each increment iterates, until the out-of-balance force, the gaps and the displacement correction
//! are all small and no interface point changes state,
//!
//! ```text
//! [ K  sCᵀ ] { Δu    }   { f_ext − f_int(u) − Cᵀλ }
//! [ sC sD  ] { Δλ/s } = { −s·g(u)  (or −λ on a unit-diagonal row) }
//! ```
//!
//! (the paper's Eq. 5 in residual form). f_int holds the elements' forces and each spring's τ·ℓ from
//! its shear law; K holds the elements and each spring's Ks·ℓ (the paper's constant-stiffness
//! iteration: the factorisation is reused and each iteration costs one solve) or its tangent (the
//! `newton` scheme, symmetric, with σn lagged one iteration). Normal rows are released when λ turns
//! tensile and re-activated when the gap closes. A failed increment is cut back with the state
//! restored. After each converged increment every slave point is re-associated with the master
//! segment it now faces. Held DOFs (supports and prescribed displacements) are eliminated; their
//! reactions come from the same residual.

mod absorbing;
pub mod checkpoint;
mod context;
mod convergence;
mod correction;
mod equilibrium;
mod iteration_system;
mod loads;
mod non_finite;
mod options;
mod predictor;
pub mod results;
pub mod resume_check;
mod singular;
mod sink;
pub mod soil;
mod springs;
mod stage;
mod state;
mod stats;
mod strength_reduction;
pub mod time_scheme;

pub use checkpoint::{Checkpoint, ResumeRefusal};
pub use context::model_memory_estimate_mb;
pub use iteration_system::{first_system, IterationSystem};
pub use loads::external_force;
pub use options::RunOptions;
pub use sink::{Collect, FactorOfSafety, StepRecord, StepSink};
pub use springs::SpringResult;
pub use state::State;
pub use stats::{RunStats, SolverStats, Warning, Warnings};

use crate::error::Error;
use crate::model::Model;
use context::Context;
use std::time::Instant;

/// Run every stage of a model.
///
/// # Errors
/// A solve or convergence failure names the stage and step, and the interface points that kept
/// changing state; steps completed before it have already been passed to `sink`.
pub fn run(model: &Model, options: &RunOptions, sink: &mut dyn StepSink) -> Result<RunStats, Error> {
    let started = Instant::now();
    let mut cx = Context::new(model, options)?;
    let mut state = State::initial(model, options);
    cx.stats.setup_seconds += started.elapsed().as_secs_f64();
    stages_from(&mut cx, &mut state, 0, sink)?;
    Ok(cx.stats)
}

/// Continue a run from a saved step (a [`Checkpoint`] that [`Checkpoint::fits`] the model): the rest
/// of its stage, then the model's later stages, which may differ from those of the run that saved
/// it. The steps are those the uninterrupted run would have made.
///
/// # Errors
/// As [`run`]; the checkpoint is not checked here.
pub fn resume(
    model: &Model,
    options: &RunOptions,
    checkpoint: Checkpoint,
    sink: &mut dyn StepSink,
) -> Result<RunStats, Error> {
    let started = Instant::now();
    let mut cx = Context::new(model, options)?;
    let Checkpoint { stage_index, step, mut state, held, gravity, applied_weight, progress, .. } = checkpoint;
    (cx.held, cx.gravity, cx.applied_weight) = (held, gravity, applied_weight);
    let mut stage = stage::resumed(&cx, &state, &model.stages[stage_index], stage_index, progress, step);
    cx.stats.setup_seconds += started.elapsed().as_secs_f64();
    let started = Instant::now();
    let increments = stage::increments(&mut cx, &mut state, &mut stage, sink);
    cx.stats.increments_seconds += started.elapsed().as_secs_f64();
    increments?;
    stages_from(&mut cx, &mut state, stage_index + 1, sink)?;
    Ok(cx.stats)
}

/// Every stage from `first` on: its set-up, then its increments or its strength-reduction search.
fn stages_from(cx: &mut Context, state: &mut State, first: usize, sink: &mut dyn StepSink) -> Result<(), Error> {
    let model = cx.model;
    for (index, plan) in model.stages.iter().enumerate().skip(first) {
        let started = Instant::now();
        let mut stage = stage::set_up(cx, state, plan, index);
        if plan.strength_reduction.is_none() {
            stage::freeze_normal_stress(cx, state, &stage);
        }
        cx.stats.stage_setup_seconds += started.elapsed().as_secs_f64();
        let started = Instant::now();
        let done = match (plan.strength_reduction, &plan.dynamic) {
            (Some(reduction), _) => strength_reduction::search(cx, state, &mut stage, reduction, sink)
                .and_then(|fs| sink.factor_of_safety(&fs)),
            (None, Some(dynamic)) => stage::time_steps(cx, state, &mut stage, dynamic, sink),
            (None, None) => stage::increments(cx, state, &mut stage, sink),
        };
        cx.stats.increments_seconds += started.elapsed().as_secs_f64();
        done?;
    }
    Ok(())
}
