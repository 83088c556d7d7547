//! The linear system of one equilibrium iteration: the matrix's inputs gathered from the state,
//! and the right-hand side (out-of-balance forces, −s·g on active rows, −λ on the rest).

use super::context::element_matrices;
use super::soil;
use super::springs::{self, SpringResult};
use super::state::State;
use crate::assembly::{add_spring_forces, soil_and_bar_force, ElementMatrices, SoilView, SystemInputs};
use crate::dofs::{dof, DofMap};
use crate::element::soil_state::SoilTrial;
use crate::interface::active_set::ActiveSet;
use crate::interface::rows::{constraint_force, multiplier_is_active, InterfaceRows};
use crate::interface::NormalState;
use crate::linsol::csc::Triplets;
use crate::model::Model;

/// The springs' parts of an iteration's matrix (as in [`SystemInputs`]'s `spring_*` fields).
#[derive(Clone, Copy)]
pub struct SpringTangents<'a> {
    pub stiffness: &'a [f64],
    pub coupling: Option<&'a [f64]>,
    pub dilation: Option<&'a [[f64; 2]]>,
    pub stretch: Option<&'a [Vec<(usize, f64)>]>,
}

/// The inputs of an iteration's matrix.
pub fn inputs<'a>(
    elements: &'a ElementMatrices,
    soil_trial: &'a SoilTrial,
    rows: &'a InterfaceRows,
    springs: SpringTangents<'a>,
    dofs: &'a DofMap,
    state: &'a State,
) -> SystemInputs<'a> {
    SystemInputs {
        elements,
        soil: SoilView { field: &state.soil, trial: soil_trial },
        rows,
        spring_stiffness: springs.stiffness,
        spring_coupling: springs.coupling,
        spring_dilation: springs.dilation,
        spring_stretch: springs.stretch,
        bars: &state.bars,
        interfaces: &state.interfaces,
        dofs,
        scale: elements.typical_stiffness(),
    }
}

/// The linear system of one equilibrium iteration.
pub struct IterationSystem {
    pub triplets: Triplets,
    pub rhs: Vec<f64>,
    /// Scale of the constraint rows (the multiplier unknowns are Δλ/scale).
    pub scale: f64,
    /// Rows that hold a constraint (zero diagonal).
    pub active: usize,
}

/// The system of one iteration from the current state: out-of-balance forces on the free DOFs, −g
/// on active rows (no transverse motion on held rows), −λ on the rest; the matrix when asked for.
/// `element`: the elements' part of the internal force at this state, when the convergence check
/// already computed it.
pub fn iteration_system(
    inputs: SystemInputs,
    springs: &[SpringResult],
    state: &State,
    with_matrix: bool,
    element: Option<Vec<f64>>,
) -> IterationSystem {
    let SystemInputs { elements, soil, rows, dofs, scale, .. } = inputs;
    let n_dof = state.u.len();
    let gaps = rows.gaps(&state.u);
    let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
    let mut f_int = element.unwrap_or_else(|| soil_and_bar_force(elements, soil, &state.bars, &state.u));
    add_spring_forces(&mut f_int, rows, &taus);
    let f_c = constraint_force(rows, &state.lambda, n_dof);
    let mut rhs = vec![0.0; dofs.size()];
    for (d, eq) in dofs.equation.iter().enumerate() {
        if let Some(e) = eq {
            rhs[*e] = state.f_ext[d] - f_int[d] - f_c[d];
        }
    }
    let mut active = 0;
    for k in 0..dofs.multipliers.len() {
        let m = dofs.multipliers[k];
        let held = !m.tangential
            && matches!(
                state.interfaces[m.interface].faces[m.face].points[m.point].normal_state,
                NormalState::Held { .. }
            );
        rhs[dofs.multiplier_equation(k)] = if held {
            active += 1;
            0.0
        } else if multiplier_is_active(&state.interfaces, m) {
            active += 1;
            -scale * gaps[k]
        } else {
            -state.lambda[k]
        };
    }
    let triplets = if with_matrix { inputs.assemble() } else { Triplets::default() };
    IterationSystem { triplets, rhs, scale, active }
}

/// The first system a run of `model` solves (stage 1, step 1, iteration 1): for benchmarks and
/// solver studies.
pub fn first_system(model: &Model) -> (usize, IterationSystem) {
    let setup = soil::SoilSetup::new(model);
    let elements = element_matrices(model, &setup);
    let dof_count = 2 * model.mesh.nodes.len();
    let mut held = vec![false; dof_count];
    let stage = &model.stages[0];
    let prescribed = stage.prescribed.iter().map(|&(n, d, _)| (n, d));
    for (n, d) in model.supports.iter().copied().chain(prescribed) {
        held[dof(n, d)] = true;
    }
    let mut interfaces = model.interfaces.clone();
    let dofs = DofMap::new(model.mesh.nodes.len(), &held, &interfaces);
    let rules = ActiveSet {
        mesh: &model.mesh,
        multipliers: &dofs.multipliers,
        equation: &dofs.equation,
        bar_only: &[],
        placed: &[],
    };
    rules.mark_redundant(&mut interfaces);
    let factor = stage.load_factors[0];
    let mut u = vec![0.0; dof_count];
    for &(n, d, value) in &stage.prescribed {
        u[dof(n, d)] = factor * value;
    }
    let f_ext = super::loads::external_force(model, &stage.loads).into_iter().map(|f| factor * f).collect();
    let state = State {
        u,
        lambda: vec![0.0; dofs.multipliers.len()],
        interfaces,
        f_ext,
        u_committed: vec![0.0; dof_count],
        frozen_sigma_n: None,
        soil_sigma_from: None,
        bars: crate::element::bar::BarStates::new(model.mesh.bars.len()),
        soil: soil::initial_field(&model.initially_absent()),
        placed: Vec::new(),
        motion: None,
    };
    let rows = InterfaceRows::new(&model.mesh, &state.interfaces, &dofs.multipliers);
    let springs = springs::evaluate(model, &state, &rows);
    let soil_trial = SoilTrial::default();
    let stiffness: Vec<f64> = rows
        .springs
        .iter()
        .map(|s| state.interfaces[s.interface].faces[s.face].law.shear_stiffness().unwrap_or(0.0) * s.tributary)
        .collect();
    let tangents = SpringTangents { stiffness: &stiffness, coupling: None, dilation: None, stretch: None };
    let system = inputs(&elements, &soil_trial, &rows, tangents, &dofs, &state);
    (dofs.size(), iteration_system(system, &springs, &state, true, None))
}
