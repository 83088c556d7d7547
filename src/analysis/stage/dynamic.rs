//! A dynamic stage's time steps: the soil's masses and the absorbing sides' dashpots computed for
//! the stage (the supports they replace freed by the set-up, their reactions kept on as forces),
//! then each step as an increment of the static problem with the step's dynamic operator D and
//! constant force (`time_scheme.rs`). The base motion is the inertia force −M·ι·a_g(t) in the frame
//! of a rigid base (Chopra, Dynamics of Structures, §9.4), or over a compliant base the force
//! C_b·ι·v_g(t) through its dashpots (`absorbing.rs`). A step that fails is cut back (the state and
//! motion restored, its midpoint in time put in front). A dynamic stage keeps no saved steps: a run
//! continues from the last one before it.

use super::super::absorbing::Dashpots;
use super::super::context::{CarriedForce, Context};
use super::super::sink::StepSink;
use super::super::soil;
use super::super::state::State;
use super::super::time_scheme::{Hht, Motion, Products, Soil, StepStart};
use super::complete::complete_increment;
use super::cutback::solved_or_cut_back;
use super::placement::reactions;
use super::progress::{Increment, Stage};
use crate::assembly::inertia::Inertia;
use crate::dofs::Direction;
use crate::element::mass::bar_mass;
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
    // every block's mass (the soil's, then the bars'), and whether its element is present
    let mut masses = soil::masses(cx.model, &state.soil, plan.gravity, plan.lumping);
    let mut present: Vec<bool> = state.soil.elements().iter().map(|e| e.active).collect();
    for (i, bar) in cx.elements.bars.iter().enumerate() {
        let weight = cx.model.reinforcements[cx.model.mesh.bars[i].material].1.weight.unwrap_or(0.0);
        masses.push(bar_mass(weight * bar.length / plan.gravity, plan.lumping));
        present.push(!state.bars.absent[i]);
    }
    let dashpots = Dashpots::new(cx.model, &state.soil, plan);
    // the freed supports' reactions stay on as forces
    let f_ext_before = stage.progress.f_ext_start.clone();
    for (&d, r) in stage.freed.iter().zip(reactions(cx, &stage.dofs, state, &stage.freed)) {
        stage.progress.f_ext_start[d] += r;
        state.f_ext[d] += r;
    }
    let generation = stage.index as u64 + 1;
    let Dashpots { elements: dashpots, input } = dashpots;
    let inertia = Inertia::new(masses, dashpots, present, generation, &cx.elements.blocks, state.u.len());
    // on a rigid base, the ground's acceleration in each direction puts −M·ι_d·a_g,d(t) on the
    // soil and the bars
    let influence: Vec<(Direction, Vec<f64>)> = plan
        .base_motion
        .iter()
        .filter(|_| !plan.compliant_base)
        .map(|(d, _)| {
            let mut iota = vec![0.0; state.u.len()];
            for v in iota.iter_mut().skip(index(*d)).step_by(2) {
                *v = 1.0;
            }
            (*d, inertia.mass_times(&cx.elements.blocks, &iota))
        })
        .collect();
    cx.elements.inertia = Some(inertia);
    state.motion = Some(Motion::at_rest(state.u.len(), !plan.compliant_base));
    let stepped = steps(cx, state, stage, plan, &Forces { influence, input }, sink);
    cx.elements.inertia = None;
    state.motion = None;
    // the freed supports hold again where the shaking left them
    for &d in &stage.freed {
        cx.held[d] = true;
    }
    stage.progress.f_ext_start = f_ext_before;
    state.f_ext = stage.progress.f_ext_start.clone();
    stepped
}

/// The base motion's forces per unit of its acceleration (a rigid base's −M·ι) or of its velocity
/// (a compliant base's C_b·ι), in each direction shaken.
struct Forces {
    influence: Vec<(Direction, Vec<f64>)>,
    input: Vec<(Direction, Vec<f64>)>,
}

fn steps(
    cx: &mut Context,
    state: &mut State,
    stage: &mut Stage,
    plan: &DynamicPlan,
    forces: &Forces,
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    let scheme = Hht::new(plan.alpha);
    // M·x and C·x of the motion at the step's start (at rest in the stage's first)
    let mut products = Products::at_rest(&soil_of(cx, plan), &state.u);
    while let Some(&target) = stage.progress.targets.first() {
        let started = Instant::now();
        let snapshot = state.clone();
        let start = state.motion.clone().expect("a dynamic stage carries its motion");
        let time = target * plan.duration;
        let k = scheme.step(nominal_step(time - start.time, plan.time_step));
        let inertia = cx.elements.inertia.as_mut().expect("the stage's masses are in place");
        inertia.set_coefficients(k.operator(plan.rayleigh), &cx.elements.blocks);
        let step_start = StepStart::new(&state.u, &start, &products, &k);
        let (mut ground, mut velocity) = ([0.0; 2], [0.0; 2]);
        for (d, motion) in &plan.base_motion {
            ground[index(*d)] = motion.at(time);
            velocity[index(*d)] = motion.velocity(time);
        }
        let progress = &stage.progress;
        for (i, f) in state.f_ext.iter_mut().enumerate() {
            *f = progress.f_ext_start[i] - step_start.constant[i];
        }
        for (d, m_iota) in &forces.influence {
            for (f, m) in state.f_ext.iter_mut().zip(m_iota) {
                *f -= m * ground[index(*d)];
            }
        }
        for (d, c_iota) in &forces.input {
            for (f, c) in state.f_ext.iter_mut().zip(c_iota) {
                *f += c * velocity[index(*d)];
            }
        }
        let Some(report) = solved_or_cut_back(cx, stage, state, &snapshot, target)? else { continue };
        // the elements' force at the step's end: the next step's first right-hand side, if it
        // has the same length
        let carried = CarriedForce {
            u: state.u.clone(),
            operator: cx.elements.inertia.as_ref().expect("the stage's masses are in place").key(),
            force: report.element_force.clone(),
            floor: report.element_floor,
        };
        // (before the step commits: the soil's states are no longer shared with the copy)
        drop(snapshot);
        let soil = soil_of(cx, plan);
        let operator = report.operator_force.as_deref();
        let (end, end_products) = step_start.end(&soil, &state.u, operator, &start, &products, &k, time, ground);
        state.motion = Some(end);
        products = end_products;
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
        cx.carried_force = Some(carried);
        stage.progress.reach(target, planned_step);
    }
    cx.carried_force = None;
    Ok(())
}

/// The mass and damping in the stage.
fn soil_of<'a>(cx: &'a Context, plan: &DynamicPlan) -> Soil<'a> {
    let inertia = cx.elements.inertia.as_ref().expect("the stage's masses are in place");
    Soil { elements: &cx.elements, inertia, rayleigh: plan.rayleigh }
}

/// The index of a direction in (x, y).
fn index(d: Direction) -> usize {
    if d == Direction::X {
        0
    } else {
        1
    }
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
