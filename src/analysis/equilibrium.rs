//! One increment iterated to equilibrium: each iteration assembles, solves, updates and asks
//! whether it has converged.
//!
//! ```text
//! [ K  sCᵀ ] { Δu    }   { f_ext − f_int(u) − Cᵀλ }
//! [ sC sD  ] { Δλ/s } = { −s·g(u)  (or −λ on a unit-diagonal row) }
//! ```
//!
//! K holds the elements and each spring's Ks·ℓ (constant stiffness: kept while the contact states
//! stay, so the factorisation is reused and an iteration costs one solve) or its tangent (Newton);
//! under the consistent Newton tangent the springs' shear is coupled to their normal multipliers.

use super::condensation::{self, Condensed, Deferred};
use super::context::Context;
use super::convergence::{balance, displacement_ok, gaps_closed, IncrementError, Measures};
use super::correction::{apply_correction, line_search};
use super::iteration_system::{inputs, iteration_system, IterationSystem};
use super::non_finite::{self, Iterate};
use super::singular::{self, Fallbacks, Recovered, SingularMatrix};
use super::soil;
use super::springs::{self, SpringResult};
use super::state::State;
use crate::assembly::{soil_and_bar_force_and_floor, ElementMatrices, SoilView, SystemInputs};
use crate::dofs::DofMap;
use crate::element::soil_state::{SoilTrial, Tangent};
use crate::interface::active_set::{describe, Bands, Flips};
use crate::interface::reassociate::{clip_tributaries, tributary_rates};
use crate::interface::rows::InterfaceRows;
use crate::interface::NormalState;
use crate::linsol::condensed::CondensedError;
use crate::linsol::Failure;
use crate::model::{ReassociationRule, Scheme};
use std::time::Instant;

/// A converged increment.
pub struct IncrementReport {
    pub iterations: usize,
    pub force_residual: f64,
    pub linear_residuals: Vec<f64>,
    pub springs: Vec<SpringResult>,
    pub state_changes: Vec<String>,
    /// The soil's Gauss-point states at equilibrium.
    pub soil: SoilTrial,
    /// The soil's and the bars' part of the internal force at equilibrium (the closing check's,
    /// `assembly::soil_and_bar_force_and_floor`), which the step's reactions are taken from.
    pub element_force: Vec<f64>,
}

/// What one increment's iterations carry from one to the next.
struct Iterations {
    u_increment_start: Vec<f64>,
    linear_residuals: Vec<f64>,
    flips: Flips,
    state_changes: Vec<String>,
    /// Constant stiffness: the contact states and the springs' Ks·ℓ the matrix was built with.
    kept_stiffness: Option<(Vec<bool>, Vec<f64>)>,
    /// The fingerprint of the last matrix solved with.
    matrix_key: Option<u64>,
    fallbacks: Fallbacks,
    /// The soil evaluated at the current iterate by the last convergence check.
    carried_soil: Option<SoilTrial>,
    /// The elements' part of the internal force at the current iterate, from the same check.
    carried_element_force: Option<Vec<f64>>,
    /// The iteration under way.
    iteration: usize,
    /// The last out-of-balance force and its reference.
    last_residual: Option<(f64, f64)>,
    /// This iteration solved the whole system condensed: the interior is in balance after it.
    condensed_solve: bool,
    /// The interface iteration under way (`condensation::Deferred`).
    deferred: Option<Deferred>,
}

/// The linearisation at one iterate: what the matrix and the right-hand side are built from.
struct Linearisation {
    rows: InterfaceRows,
    springs: Vec<SpringResult>,
    /// The soil's tangent in this iteration.
    tangent: Tangent,
    soil_trial: SoilTrial,
    coupling: Option<Vec<f64>>,
    /// [∂d/∂s, ∂d/∂σn] of each spring's opening, when a face dilates.
    dilation: Option<Vec<[f64; 2]>>,
    /// ∂(τ·ℓ)/∂u of each spring through its tributary length, under Newton with large slip.
    stretch: Option<Vec<Vec<(usize, f64)>>>,
    key: u64,
}

impl Linearisation {
    /// The inputs of this iteration's matrix, with the springs' stiffness kept for it.
    fn inputs<'a>(
        &'a self,
        elements: &'a ElementMatrices,
        stiffness: &'a [f64],
        dofs: &'a DofMap,
        state: &'a State,
    ) -> SystemInputs<'a> {
        inputs(
            elements,
            &self.soil_trial,
            &self.rows,
            stiffness,
            self.coupling.as_deref(),
            self.dilation.as_deref(),
            self.stretch.as_deref(),
            dofs,
            state,
        )
    }
}

/// An iteration's linear solution.
struct Solution {
    /// [Δu on the free DOFs | Δλ/s].
    x: Vec<f64>,
    /// The constraint rows' scale s.
    scale: f64,
    /// The right-hand side it solved for.
    rhs: Vec<f64>,
}

/// Iterate one increment to equilibrium.
pub fn equilibrium(cx: &mut Context, dofs: &DofMap, state: &mut State) -> Result<IncrementReport, IncrementError> {
    let mut it = Iterations {
        u_increment_start: state.u.clone(),
        linear_residuals: Vec::new(),
        flips: Flips::new(),
        state_changes: Vec::new(),
        kept_stiffness: None,
        matrix_key: None,
        fallbacks: Fallbacks {
            elastic_springs: false,
            soil_tangent: match cx.options.analysis.scheme {
                Scheme::Newton => Tangent::Consistent,
                Scheme::NewtonSymmetric => Tangent::Symmetric,
                Scheme::ConstantStiffness => Tangent::Elastic,
            },
            dependent_retries: 0,
        },
        carried_soil: None,
        carried_element_force: None,
        iteration: 0,
        last_residual: None,
        condensed_solve: false,
        deferred: None,
    };
    let max_iterations = cx.options.analysis.max_iterations;
    for iteration in 1..=max_iterations {
        cx.system.stats.iterations += 1;
        it.iteration = iteration;
        let linear = linearise(cx, dofs, state, &mut it, iteration);
        it.condensed_solve = false;
        let solution = match solve_interface(cx, dofs, state, &mut it, &linear)? {
            Some(solution) => Some(solution),
            None => solve(cx, dofs, state, &mut it, &linear)?,
        };
        let Some(Solution { x, scale, rhs }) = solution else { continue };
        let step = if linear.soil_trial.yielding > 0 && linear.tangent != Tangent::Elastic {
            line_search(cx, dofs, state, &linear.rows, &x, scale, &rhs[..dofs.free_count])
        } else {
            1.0
        };
        let correction2 = apply_correction(dofs, state, &x, step, scale);
        // an interface iteration carries its soil (elastic, the interior unmoved) to the next
        let soil = it.deferred.is_some().then_some(linear.soil_trial);
        match check(cx, dofs, state, &mut it, iteration, correction2, soil)? {
            Some(report) => return Ok(report),
            None => continue,
        }
    }
    // every iteration ended in a recovery from a singular matrix
    let (residual, reference) = it.last_residual.unwrap_or((0.0, 0.0));
    Err(IncrementError::NotConverged {
        iterations: max_iterations,
        residual,
        reference: reference.max(f64::MIN_POSITIVE),
        unsettled: it.state_changes.iter().rev().take(12).cloned().collect(),
        yielding: 0,
    })
}

/// Clip the tributary lengths to the embedded part (large slip).
fn clip(cx: &Context, state: &mut State) {
    if cx.options.analysis.reassociation != ReassociationRule::None {
        clip_tributaries(&cx.model.mesh, &mut state.interfaces, &state.u);
    }
}

/// The rows, the springs' laws, the soil and the springs' stiffness at the current iterate.
fn linearise(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    iteration: usize,
) -> Linearisation {
    let t = Instant::now();
    clip(cx, state);
    let held =
        cx.active_set(dofs, &state.placed).hold_free_reinforcement_nodes(&mut state.interfaces, &mut state.lambda);
    it.state_changes.extend(held);
    let mut rows = InterfaceRows::new(&cx.model.mesh, &state.interfaces, &dofs.multipliers);
    let springs = springs::evaluate(cx.model, state, &rows);
    rows.dilate(springs.iter().map(|r| r.dilation));
    // The first iteration of an increment predicts with the elastic soil stiffness: prescribed
    // displacements strain only the elements next to them at first, and their tangent would say
    // nothing about the rest.
    let tangent = if iteration == 1 { Tangent::Elastic } else { it.fallbacks.soil_tangent };
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
    let keep = scheme == Scheme::ConstantStiffness && it.kept_stiffness.as_ref().is_some_and(|(c, _)| *c == contact);
    if !keep {
        let stiffness = rows
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
        it.kept_stiffness = Some((contact, stiffness));
    }
    // the consistent tangent couples each sliding point's shear to its normal multiplier
    // (never on a solver that takes the matrix as symmetric: see `context::symmetric_tangent`)
    let coupling: Option<Vec<f64>> =
        (scheme == Scheme::Newton && state.frozen_sigma_n.is_none() && !cx.system.stats.symmetric).then(|| {
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
    let stiffness = &it.kept_stiffness.as_ref().expect("set above").1;
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
        && !cx.system.stats.symmetric)
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
    let key = inputs(
        &cx.elements,
        &soil_trial,
        &rows,
        stiffness,
        coupling.as_deref(),
        dilation.as_deref(),
        stretch.as_deref(),
        dofs,
        state,
    )
    .fingerprint();
    cx.system.stats.interface_seconds += t.elapsed().as_secs_f64();
    Linearisation { rows, springs, tangent, soil_trial, coupling, dilation, stretch, key }
}

/// Assemble (unless the last matrix is still the one) and solve; `None` when a singular matrix was recovered from and the
/// iteration is to be done again.
fn solve(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    if cx.condensed.is_some() {
        if it.iteration == 1 {
            start_on_interface(cx, dofs, state, it, linear);
            if it.deferred.is_some() {
                if let Some(solution) = solve_interface(cx, dofs, state, it, linear)? {
                    return Ok(Some(solution));
                }
            }
        }
        if let Some(solution) = solve_condensed(cx, dofs, state, it, linear)? {
            return Ok(Some(solution));
        }
    }
    // The matrix of the last solve, when nothing in it changed (constant stiffness, no state
    // change): no assembly, no factorisation, one solve.
    let t = Instant::now();
    let reuse = it.matrix_key == Some(linear.key);
    let stiffness = &it.kept_stiffness.as_ref().expect("set by linearise").1;
    let system = linear.inputs(&cx.elements, stiffness, dofs, state);
    let element = it.carried_element_force.take();
    let IterationSystem { triplets, rhs, scale, active } =
        iteration_system(system, &linear.springs, state, !reuse, element);
    cx.system.stats.assembly_seconds += t.elapsed().as_secs_f64();
    let iterate =
        Iterate { mesh: &cx.model.mesh, dofs, state, soil_trial: Some(&linear.soil_trial), springs: &linear.springs };
    if rhs.iter().chain(&triplets.values).any(|v| !v.is_finite()) {
        let first = non_finite::in_iterate(&iterate).or_else(|| non_finite::in_system(&iterate, &rhs, &triplets));
        if let Some(first) = first {
            return Err(IncrementError::NonFinite { iteration: it.iteration, first });
        }
    }
    let reused = if reuse { cx.system.solve_again(&rhs).ok() } else { None };
    it.matrix_key = Some(linear.key);
    let solved = match reused {
        Some(solution) => Ok(solution),
        None => {
            let triplets = if reuse {
                // the reused factorisation did not give a clean solution: assemble and factorise
                let t = Instant::now();
                let again = system.assemble();
                cx.system.stats.assembly_seconds += t.elapsed().as_secs_f64();
                again
            } else {
                let diagonal = singular::unconstrained_diagonal_of(&triplets, dofs.free_count);
                singular::warn_if_ill_conditioned(&mut cx.system.stats, cx.model, dofs, state, &diagonal);
                triplets
            };
            // the list goes once the matrix is built, before the factorisation
            cx.system.solve(dofs.size(), triplets, &rhs, active)
        }
    };
    match solved {
        Ok((x, linear_residual)) => {
            let iterate = Iterate {
                mesh: &cx.model.mesh,
                dofs,
                state,
                soil_trial: Some(&linear.soil_trial),
                springs: &linear.springs,
            };
            if let Some(first) = non_finite::in_solution(&iterate, &x) {
                return Err(IncrementError::NonFinite { iteration: it.iteration, first });
            }
            it.linear_residuals.push(linear_residual);
            Ok(Some(Solution { x, scale, rhs }))
        }
        Err(Failure::Singular { equations }) => {
            // the list again, for the diagnosis (a singular matrix is the exception)
            let triplets = system.assemble();
            let singular = SingularMatrix {
                triplets: &triplets,
                equations,
                sliding: linear.springs.iter().any(|r| r.sliding),
                yielded_soil: linear.soil_trial.tangents.iter().any(|t| t.is_some()),
            };
            match singular::recover(cx, dofs, state, &mut it.fallbacks, singular)? {
                Recovered::NewMatrix => it.matrix_key = None,
                Recovered::RowsSetAside(changes) => it.state_changes.extend(changes),
            }
            Ok(None)
        }
        Err(Failure::Other(e)) => Err(IncrementError::Solve(e)),
    }
}

/// The first iteration of an increment whose load moved the kept unknowns alone: the iterations
/// start on the interface at once (`condensation::start_in_balance`), and the increment's one
/// sparse solve is the interior following at its end. Otherwise the elements' force computed here
/// serves the condensed solve.
fn start_on_interface(cx: &mut Context, dofs: &DofMap, state: &State, it: &mut Iterations, linear: &Linearisation) {
    let Some(condensed) = cx.condensed.as_ref() else { return };
    let t = Instant::now();
    let stiffness = &it.kept_stiffness.as_ref().expect("set by linearise").1;
    let system = linear.inputs(&cx.elements, stiffness, dofs, state);
    // (the residual's round-off floor with the force, in the same pass over the elements)
    let (element, floor) = soil_and_bar_force_and_floor(&cx.elements, system.soil, &state.bars, &state.u);
    let rhs = iteration_system(system, &linear.springs, state, false, Some(element.clone())).rhs;
    if rhs.iter().all(|v| v.is_finite()) {
        it.deferred =
            condensation::start_in_balance(condensed, &cx.elements, dofs, state, system, &rhs, &element, floor);
    }
    cx.system.stats.assembly_seconds += t.elapsed().as_secs_f64();
    it.carried_element_force = Some(element);
}

/// The inputs of an iteration's matrix and its right-hand side alone (no matrix assembled), for
/// the solves that take the matrix in parts; the constraint rows' scale.
fn right_hand_side<'a>(
    elements: &'a ElementMatrices,
    stats: &mut crate::linsol::linear_system::SolverStats,
    stiffness: &'a [f64],
    linear: &'a Linearisation,
    dofs: &'a DofMap,
    state: &'a State,
    element: Option<Vec<f64>>,
) -> (SystemInputs<'a>, Vec<f64>, f64) {
    let t = Instant::now();
    let system = linear.inputs(elements, stiffness, dofs, state);
    let IterationSystem { rhs, scale, .. } = iteration_system(system, &linear.springs, state, false, element);
    stats.assembly_seconds += t.elapsed().as_secs_f64();
    (system, rhs, scale)
}

/// The iteration's system solved with the soil condensed onto the interface (`condensation`);
/// `None` where this iteration needs the full system.
fn solve_condensed(
    cx: &mut Context,
    dofs: &DofMap,
    state: &State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    let model = cx.model;
    let Context { condensed, system: linear_system, elements, .. } = &mut *cx;
    let stats = &mut linear_system.stats;
    let stiffness = &it.kept_stiffness.as_ref().expect("set by linearise").1;
    let element = it.carried_element_force.clone();
    let (system, rhs, scale) = right_hand_side(elements, stats, stiffness, linear, dofs, state, element);
    if rhs.iter().any(|v| !v.is_finite()) {
        // the full path names the first place
        return Ok(None);
    }
    let Condensed::Solved(x, linear_residual) =
        condensation::solve(condensed, stats, elements, dofs, state, system, linear.key, &rhs)
    else {
        return Ok(None);
    };
    let iterate =
        Iterate { mesh: &model.mesh, dofs, state, soil_trial: Some(&linear.soil_trial), springs: &linear.springs };
    if let Some(first) = non_finite::in_solution(&iterate, &x) {
        return Err(IncrementError::NonFinite { iteration: it.iteration, first });
    }
    // the stiffness spread of the whole matrix, once for each condensed soil
    let soil_key = cx.condensed.as_ref().and_then(|c| c.condensed_on()).map(|(_, key)| key);
    if soil_key.is_some() && soil_key != cx.conditioning_checked {
        cx.conditioning_checked = soil_key;
        // the soil's diagonal from the condensed soil's matrix, the rest assembled (not the whole
        // list again: it would sit beside the soil's factors and the interface system)
        let stiffness = &it.kept_stiffness.as_ref().expect("set by linearise").1;
        let system = linear.inputs(&cx.elements, stiffness, dofs, state);
        let diagonal = match cx.condensed.as_ref().and_then(|c| c.linear_diagonal()) {
            Some(soil) => {
                let rest = system.assemble_reinforcement_and_interface();
                let mut diagonal = singular::diagonal_of(&rest, dofs.free_count);
                for (d, s) in diagonal.iter_mut().zip(soil) {
                    *d += s;
                }
                singular::pass_over_constrained(&mut diagonal, &rest);
                diagonal
            }
            None => singular::unconstrained_diagonal_of(&system.assemble(), dofs.free_count),
        };
        singular::warn_if_ill_conditioned(&mut cx.system.stats, cx.model, dofs, state, &diagonal);
    }
    it.carried_element_force = None;
    // the full system's factorisation (if any) is not this iteration's matrix
    it.matrix_key = None;
    it.condensed_solve = true;
    it.linear_residuals.push(linear_residual);
    Ok(Some(Solution { x, scale, rhs }))
}

/// An interface iteration (`condensation::Deferred`), when one is under way: the kept rows of the
/// right-hand side solved on the condensed system. `None` when none is under way, or when the
/// kept system cannot be solved (the interior then follows, and the whole system is solved).
fn solve_interface(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    linear: &Linearisation,
) -> Result<Option<Solution>, IncrementError> {
    let Some(deferred) = it.deferred.as_mut() else { return Ok(None) };
    let Context { condensed, system: linear_system, elements, .. } = &mut *cx;
    let stats = &mut linear_system.stats;
    let stiffness = &it.kept_stiffness.as_ref().expect("set by linearise").1;
    let element = it.carried_element_force.take();
    let (system, rhs, scale) = right_hand_side(elements, stats, stiffness, linear, dofs, state, element);
    let solved = match condensed.as_mut() {
        Some(c) if rhs.iter().all(|v| v.is_finite()) => {
            condensation::solve_deferred(c, stats, deferred, system, linear.key, &rhs)
        }
        _ => None,
    };
    match solved {
        Some((x, linear_residual)) => {
            it.linear_residuals.push(linear_residual);
            Ok(Some(Solution { x, scale, rhs }))
        }
        None => {
            finish_interface(cx, dofs, state, it)?;
            Ok(None)
        }
    }
}

/// The interior follows an interface iteration's movement of the kept unknowns.
fn finish_interface(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
) -> Result<(), IncrementError> {
    let Some(deferred) = it.deferred.take() else { return Ok(()) };
    it.carried_element_force = None;
    it.carried_soil = None;
    let Context { condensed, system: linear_system, .. } = &mut *cx;
    let Some(c) = condensed.as_mut() else { return Ok(()) };
    deferred.finish(c, &mut linear_system.stats, dofs, state).map_err(|e| match e {
        CondensedError::Backend(e) => IncrementError::Solve(e),
        CondensedError::Fallback(_) => IncrementError::Solve(crate::error::SolveError::Backend {
            backend: c.backend().name(),
            message: "the interior could not follow the interface's movement".into(),
        }),
    })
}

/// After a correction: the active set and the bars' rupture, then the convergence test. Returns
/// the report when the increment has converged.
fn check(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    it: &mut Iterations,
    iteration: usize,
    correction2: f64,
    interface_soil: Option<SoilTrial>,
) -> Result<Option<IncrementReport>, IncrementError> {
    let t = Instant::now();
    clip(cx, state);
    let mut rows = InterfaceRows::new(&cx.model.mesh, &state.interfaces, &dofs.multipliers);
    let springs = springs::evaluate(cx.model, state, &rows);
    rows.dilate(springs.iter().map(|r| r.dilation));
    let characteristic = cx.characteristic;
    let force_floor = state
        .f_ext
        .iter()
        .fold(0.0f64, |m, f| m.max(f.abs()))
        .max(1e-6 * cx.elements.typical_stiffness() * characteristic);
    let gaps = rows.gaps(&state.u);
    let bands = Bands::new(&state.lambda, force_floor, characteristic);
    let mut changes = cx.active_set(dofs, &state.placed).update(
        &mut state.interfaces,
        &mut state.lambda,
        &gaps,
        bands,
        &mut it.flips,
    );
    let elements = &cx.elements;
    changes.extend(state.bars.rupture(&elements.bars, |i| &elements.blocks[i].0, &state.u));
    cx.system.stats.interface_seconds += t.elapsed().as_secs_f64();
    it.state_changes.extend(changes.iter().cloned());
    let settings = &cx.options.analysis;
    // (the correction against the displacements so far, for an increment that moves almost
    // nothing, as a strength-reduction trial at F = 1, while slack sheets under no normal stress
    // drift along themselves without changing any force)
    let displacement_ok = displacement_ok(settings, iteration, correction2, &state.u, &it.u_increment_start);
    let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
    if let (Some(deferred), Some(_)) = (it.deferred.as_ref(), cx.condensed.as_ref()) {
        // an interface iteration: the residual on the kept unknowns, the interior unmoved
        let t = Instant::now();
        let element = deferred.element_force(&cx.elements, state);
        let (residual, reference) = balance(&element, &rows, &taus, state, dofs);
        cx.system.stats.residual_seconds += t.elapsed().as_secs_f64();
        it.last_residual = Some((residual, reference));
        let measures = Measures {
            residual,
            reference,
            floor: deferred.floor,
            settled: changes.is_empty(),
            gaps_closed: gaps_closed(&gaps, state, dofs, characteristic),
            displacement_ok,
        };
        let last = iteration == settings.max_iterations;
        if !measures.converged(settings) && !last && residual.is_finite() {
            it.carried_element_force = Some(element);
            it.carried_soil = interface_soil;
            return Ok(None);
        }
        // converged on the interface (or out of iterations): the interior follows, and the whole
        // system is checked below
        finish_interface(cx, dofs, state, it)?;
    }
    let settings = &cx.options.analysis;
    let t = Instant::now();
    // with the tangent the next iteration assembles (the forces do not depend on it)
    let soil_trial = soil::evaluate(&cx.setup, &state.soil, &state.u, &state.u_committed, it.fallbacks.soil_tangent);
    // the elements' force and the residual's round-off floor in one pass
    let view = SoilView { field: &state.soil, trial: &soil_trial };
    let (element_force, floor) = soil_and_bar_force_and_floor(&cx.elements, view, &state.bars, &state.u);
    let (residual, reference) = balance(&element_force, &rows, &taus, state, dofs);
    cx.system.stats.residual_seconds += t.elapsed().as_secs_f64();
    if !residual.is_finite() || !reference.is_finite() {
        let iterate = Iterate { mesh: &cx.model.mesh, dofs, state, soil_trial: Some(&soil_trial), springs: &springs };
        let first = non_finite::in_iterate(&iterate).unwrap_or(non_finite::NonFinite {
            value: if residual.is_finite() { reference } else { residual },
            location:
                "the out-of-balance force (every displacement, load, soil force and interface stress was finite: \
                       their products overflowed)"
                    .into(),
        });
        return Err(IncrementError::NonFinite { iteration, first });
    }
    it.last_residual = Some((residual, reference));
    let measures = Measures {
        residual,
        reference,
        floor,
        settled: changes.is_empty(),
        gaps_closed: gaps_closed(&gaps, state, dofs, characteristic),
        displacement_ok,
    };
    if measures.converged(settings) {
        return Ok(Some(IncrementReport {
            iterations: iteration,
            force_residual: residual / reference,
            linear_residuals: std::mem::take(&mut it.linear_residuals),
            springs,
            state_changes: std::mem::take(&mut it.state_changes),
            soil: soil_trial,
            element_force,
        }));
    }
    if iteration == settings.max_iterations {
        let mut unsettled: Vec<(usize, usize)> =
            it.flips.iter().map(|(&k, &n)| (k, n)).filter(|&(_, n)| n > 1).collect();
        unsettled.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
        let unsettled = unsettled
            .into_iter()
            .map(|(k, n)| format!("{} ({n} changes)", describe(&cx.model.mesh, &state.interfaces, dofs.multipliers[k])))
            .collect();
        return Err(IncrementError::NotConverged {
            iterations: iteration,
            residual,
            reference,
            unsettled,
            yielding: soil_trial.yielding,
        });
    }
    if it.condensed_solve {
        // the whole system was solved condensed: the interior is in balance, and the iterations
        // go on on the interface alone
        if let Some(condensed) = cx.condensed.as_ref() {
            it.deferred = Deferred::start(condensed, &cx.elements, dofs, state, &element_force, measures.floor);
        }
    }
    it.carried_soil = Some(soil_trial);
    it.carried_element_force = Some(element_force);
    Ok(None)
}
