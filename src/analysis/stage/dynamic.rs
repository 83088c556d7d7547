//! A dynamic stage's time steps: the soil's masses computed for the stage, then each step as an
//! increment of the static problem with the step's dynamic operator D and constant force
//! (`time_scheme.rs`), the base motion as the inertia force −M·ι·a_g(t) in the frame of the base
//! (Chopra, Dynamics of Structures, §9.4). A step that fails is cut back (the state and motion
//! restored, its midpoint in time put in front). A dynamic stage keeps no saved steps: a run
//! continues from the last one before it.

use super::super::context::Context;
use super::super::sink::StepSink;
use super::super::soil;
use super::super::state::State;
use super::super::time_scheme::{Hht, Motion, Soil, StepStart};
use super::complete::complete_increment;
use super::cutback::solved_or_cut_back;
use super::progress::{Increment, Stage};
use crate::assembly::inertia::{mass_times, Inertia};
use crate::dofs::Direction;
use crate::error::Error;
use crate::model::DynamicPlan;
use std::time::Instant;

/// The stage's time steps, from the state the stages before it left.
pub fn time_steps(
    cx: &mut Context,
    state: &mut State,
    stage: &mut Stage,
    plan: &DynamicPlan,
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    let masses = soil::masses(cx.model, &state.soil, plan.gravity, plan.lumping);
    // the ground's acceleration in each direction puts −M·ι_d·a_g,d(t) on the soil
    let influence: Vec<(Direction, Vec<f64>)> = plan
        .base_motion
        .iter()
        .map(|(d, _)| {
            let mut iota = vec![0.0; state.u.len()];
            let first = if *d == Direction::X { 0 } else { 1 };
            for v in iota.iter_mut().skip(first).step_by(2) {
                *v = 1.0;
            }
            (*d, mass_times(&masses, &cx.elements.blocks, &state.soil, &iota))
        })
        .collect();
    cx.elements.inertia = Some(Inertia { masses, mass: 0.0, stiffness: 0.0, generation: stage.index as u64 + 1 });
    state.motion = Some(Motion::at_rest(state.u.len()));
    let stepped = steps(cx, state, stage, plan, &influence, sink);
    cx.elements.inertia = None;
    state.motion = None;
    state.f_ext = stage.progress.f_ext_start.clone();
    stepped
}

fn steps(
    cx: &mut Context,
    state: &mut State,
    stage: &mut Stage,
    plan: &DynamicPlan,
    influence: &[(Direction, Vec<f64>)],
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    let scheme = Hht::new(plan.alpha);
    while let Some(&target) = stage.progress.targets.first() {
        let started = Instant::now();
        let snapshot = state.clone();
        let start = state.motion.clone().expect("a dynamic stage carries its motion");
        let time = target * plan.duration;
        let k = scheme.step(nominal_step(time - start.time, plan.time_step));
        let (mass, stiffness) = k.operator(plan.rayleigh);
        let inertia = cx.elements.inertia.as_mut().expect("the stage's masses are in place");
        (inertia.mass, inertia.stiffness) = (mass, stiffness);
        let masses = &cx.elements.inertia.as_ref().expect("in place").masses;
        let soil = Soil { elements: &cx.elements, field: &state.soil, masses, rayleigh: plan.rayleigh };
        let step_start = StepStart::new(&soil, &state.u, &start, &k);
        let mut ground = [0.0; 2];
        for (d, motion) in &plan.base_motion {
            ground[if *d == Direction::X { 0 } else { 1 }] = motion.at(time);
        }
        let progress = &stage.progress;
        for (i, f) in state.f_ext.iter_mut().enumerate() {
            *f = progress.f_ext_start[i] - step_start.constant[i];
        }
        for (d, m_iota) in influence {
            let a_g = ground[if *d == Direction::X { 0 } else { 1 }];
            for (f, m) in state.f_ext.iter_mut().zip(m_iota) {
                *f -= m * a_g;
            }
        }
        let Some(report) = solved_or_cut_back(cx, stage, state, &snapshot, target)? else { continue };
        let masses = &cx.elements.inertia.as_ref().expect("in place").masses;
        let soil = Soil { elements: &cx.elements, field: &state.soil, masses, rayleigh: plan.rayleigh };
        let end = step_start.end(&soil, &state.u, &start, &k, time, ground);
        state.motion = Some(end);
        stage.step += 1;
        let progress = &mut stage.progress;
        let planned_step = progress.count_planned(&stage.plan.load_factors, target);
        let at = Increment {
            step: stage.step,
            load_factor: target,
            strength_factor: None,
            cutbacks: progress.cutbacks,
            started,
            reversal: false,
        };
        complete_increment(cx, stage, state, report, &at, sink)?;
        stage.progress.reach(target, planned_step);
    }
    Ok(())
}

/// The step `h` as the plan's Δt halved k times when it is that up to round-off: the times come
/// from load factors (t/duration), whose last bits differ from step to step, and a step whose
/// coefficients differed in their last bits would change the matrix and be factorised again.
fn nominal_step(h: f64, dt: f64) -> f64 {
    let halvings = (dt / h).log2().round();
    let nominal = dt / halvings.exp2();
    if halvings >= 0.0 && (h - nominal).abs() <= 1e-9 * nominal {
        nominal
    } else {
        h
    }
}
