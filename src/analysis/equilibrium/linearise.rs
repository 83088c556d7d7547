//! The linearisation at one iterate: the rows, the springs' laws and stiffness, and the soil,
//! from which the iteration's matrix and right-hand side are built.

use super::super::context::Context;
use super::super::iteration_system::{inputs, SpringTangents};
use super::super::soil;
use super::super::springs::{InterfaceIterate, SpringResult};
use super::super::state::State;
use super::iterations::{Iterations, SpringStiffness};
use crate::assembly::{ElementMatrices, SystemInputs};
use crate::dofs::DofMap;
use crate::element::soil_state::{SoilTrial, Tangent};
use crate::interface::reassociate::tributary_rates;
use crate::interface::rows::InterfaceRows;
use crate::interface::NormalState;
use crate::model::{ReassociationRule, Scheme};
use std::time::Instant;

/// The linearisation at one iterate: what the matrix and the right-hand side are built from.
pub(super) struct Linearisation {
    pub rows: InterfaceRows,
    pub springs: Vec<SpringResult>,
    /// The soil's tangent in this iteration.
    pub tangent: Tangent,
    pub soil_trial: SoilTrial,
    coupling: Option<Vec<f64>>,
    /// [∂d/∂s, ∂d/∂σn] of each spring's opening, when a face dilates.
    dilation: Option<Vec<[f64; 2]>>,
    /// ∂(τ·ℓ)/∂u of each spring through its tributary length, under Newton with large slip.
    stretch: Option<Vec<Vec<(usize, f64)>>>,
    /// The springs' stiffness this iteration's matrix is built with.
    pub stiffness: SpringStiffness,
    /// The fingerprint of this iteration's matrix.
    pub key: u64,
}

impl Linearisation {
    /// The inputs of this iteration's matrix.
    pub fn inputs<'a>(&'a self, elements: &'a ElementMatrices, dofs: &'a DofMap, state: &'a State) -> SystemInputs<'a> {
        inputs(elements, &self.soil_trial, &self.rows, self.tangents(), dofs, state)
    }

    fn tangents(&self) -> SpringTangents<'_> {
        SpringTangents {
            stiffness: &self.stiffness.values,
            coupling: self.coupling.as_deref(),
            dilation: self.dilation.as_deref(),
            stretch: self.stretch.as_deref(),
        }
    }
}

/// The rows, the springs' laws, the soil and the springs' stiffness at the current iterate.
pub(super) fn linearise(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    iteration: usize,
) -> Linearisation {
    let t = Instant::now();
    // (a free reinforcement node is held by its normal states alone, whatever the tributaries)
    let held =
        cx.active_set(dofs, &state.placed).hold_free_reinforcement_nodes(&mut state.interfaces, &mut state.lambda);
    it.state_changes.extend(held);
    let rule = cx.options.analysis.reassociation;
    let InterfaceIterate { rows, springs } = InterfaceIterate::clipped(cx.model, rule, state, &dofs.multipliers);
    // The first iteration of an increment predicts with the elastic soil stiffness at the last
    // converged stresses: prescribed displacements strain only the elements next to them at
    // first, and their tangent, or a stress-dependent elasticity at their strained state, would
    // say nothing about the rest (and would make the prediction of a uniform test non-uniform).
    let tangent = if iteration == 1 { Tangent::Committed } else { it.fallbacks.soil_tangent };
    // The soil at this iterate was evaluated (with this tangent) to check the last iteration's
    // residual: nothing since has moved the displacements.
    let soil_trial = match it.carried_soil.take() {
        Some(trial) => trial,
        None => soil::evaluate(&cx.setup, &state.soil, &state.u, &state.u_committed, tangent),
    };
    let scheme = cx.options.analysis.scheme;
    // Constant stiffness (the paper's Fig. 3): Ks·ℓ as the increment found it, kept while the
    // contact states stay, so the factorisation is reused and each iteration costs one solve.
    // Newton: the law's tangent at the current iterate.
    let contact: Vec<bool> =
        rows.springs.iter().map(|s| state.interfaces[s.interface].faces[s.face].points[s.point].in_contact()).collect();
    let last = it.spring_stiffness.take().filter(|s| scheme == Scheme::ConstantStiffness && s.contact == contact);
    let stiffness = match last {
        Some(kept) => kept,
        None => {
            let values = rows
                .springs
                .iter()
                .zip(&springs)
                .zip(&contact)
                .map(|((s, r), &in_contact)| {
                    if !in_contact {
                        return 0.0;
                    }
                    let ks = r.elastic_stiffness;
                    let k = match scheme {
                        Scheme::ConstantStiffness => ks,
                        Scheme::Newton | Scheme::NewtonSymmetric if it.fallbacks.elastic_springs => ks,
                        Scheme::Newton | Scheme::NewtonSymmetric => r.response.tangent.max(0.0),
                    };
                    k * s.tributary
                })
                .collect();
            SpringStiffness { contact, values }
        }
    };
    // the consistent tangent couples each sliding point's shear to its normal multiplier
    // (never on a solver that takes the matrix as symmetric: see `context::symmetric_tangent`)
    let coupling: Option<Vec<f64>> =
        (scheme == Scheme::Newton && state.frozen_sigma_n.is_none() && !cx.stats.solver.symmetric).then(|| {
            rows.springs
                .iter()
                .zip(&springs)
                .map(|(s, r)| {
                    let face = &state.interfaces[s.interface].faces[s.face];
                    let p = &face.points[s.point];
                    // (a point whose σn is its neighbour's, or the soil's on an embedded line,
                    // gets no coupling to its own multiplier)
                    if matches!(p.normal_state, NormalState::Active)
                        && p.pressure_from.is_none()
                        && face.embedded.is_none()
                    {
                        r.response.d_tau_d_sigma
                    } else {
                        0.0
                    }
                })
                .collect()
        });
    // a dilating face's normal row follows its opening (∂d/∂σn only where σn is this row's own
    // multiplier and not frozen)
    let dilation: Option<Vec<[f64; 2]>> =
        state.interfaces.iter().flat_map(|i| &i.faces).any(|f| f.dilation.is_some()).then(|| {
            rows.springs
                .iter()
                .zip(&springs)
                .map(|(s, r)| {
                    let p = &state.interfaces[s.interface].faces[s.face].points[s.point];
                    let own = matches!(p.normal_state, NormalState::Active)
                        && p.pressure_from.is_none()
                        && state.frozen_sigma_n.is_none();
                    [r.dilation_rates[0], if own { r.dilation_rates[1] } else { 0.0 }]
                })
                .collect()
        });
    // Under large slip each spring's force τ·ℓ follows its tributary length ℓ (the slave line's
    // current length, the part of it still facing the master face): the consistent tangent has
    // row ⊗ ∂(τ·ℓ)/∂u, with ∂(τ·ℓ)/∂ℓ = τ, or τ − (∂τ/∂σn)·σn where σn = λ/ℓ is the point's own.
    // Unsymmetric: never on a solver that takes the matrix as symmetric (`context::symmetric_tangent`
    // keeps Newton off it under large slip).
    let stretch: Option<Vec<Vec<(usize, f64)>>> = (scheme == Scheme::Newton
        && !it.fallbacks.elastic_springs
        && cx.options.analysis.reassociation != ReassociationRule::None
        && !cx.stats.solver.symmetric)
        .then(|| {
            let rates = tributary_rates(&cx.model.mesh, &state.interfaces, &state.u);
            rows.springs
                .iter()
                .zip(&springs)
                .enumerate()
                .map(|(k, (s, r))| {
                    let face = &state.interfaces[s.interface].faces[s.face];
                    let in_contact = face.points[s.point].in_contact();
                    let own = coupling.as_ref().map_or(0.0, |c| c[k]);
                    let per_length = if in_contact { r.tau - own * r.sigma_n } else { 0.0 };
                    let sides = face.sides();
                    rates[s.interface][s.face][s.point].iter().map(|&(d, g)| (d, per_length * sides * g)).collect()
                })
                .collect()
        });
    let mut linear =
        Linearisation { rows, springs, tangent, soil_trial, coupling, dilation, stretch, stiffness, key: 0 };
    linear.key = linear.inputs(&cx.elements, dofs, state).fingerprint();
    cx.stats.interface_seconds += t.elapsed().as_secs_f64();
    linear
}
