//! Stages, increments and the equilibrium iteration.
//!
//! Each increment solves, until the out-of-balance force and the displacement correction are both
//! small,
//!
//! ```text
//! [ K  Cᵀ ] { Δu }   { f_ext − f_int(u) − Cᵀλ }
//! [ C  D  ] { Δλ } = { −g(u)  (or −λ on a unit-diagonal row) }
//! ```
//!
//! (the paper's Eq. 5 in residual form). Held DOFs (supports and prescribed displacements) are
//! eliminated; their reactions come from the same residual.

pub mod results;
pub mod system;

use crate::dofs::DofMap;
use crate::error::{Error, SolveError};
use crate::interface::{Interface, NormalState, ShearLaw};
use crate::linsol::{dense_ref, Backend, Failure, LinearSolver};
use crate::model::file::Direction;
use crate::model::{Load, Model};
use results::StepResults;
use std::collections::HashMap;
use system::{ElementMatrices, InterfaceRows, LinearSystem, SolverStats};

/// What a run may be asked to do.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub backend: Backend,
    /// Out-of-balance force relative to the applied and reaction forces.
    pub force_tolerance: f64,
    /// Displacement correction relative to the increment's displacement.
    pub displacement_tolerance: f64,
    pub max_iterations: usize,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions { backend: Backend::Auto, force_tolerance: 1e-9, displacement_tolerance: 1e-9, max_iterations: 25 }
    }
}

/// Receives each converged step as soon as it exists, so that a later failure never loses it.
pub trait StepSink {
    fn step_done(&mut self, step: &StepResults, record: &StepRecord, stats: &SolverStats) -> Result<(), Error>;
}

/// Keeps every converged step in memory (for tests and for programs that use geoslip as a library).
#[derive(Debug, Default)]
pub struct Collect {
    pub steps: Vec<(StepRecord, StepResults)>,
}

impl StepSink for Collect {
    fn step_done(&mut self, step: &StepResults, record: &StepRecord, _: &SolverStats) -> Result<(), Error> {
        self.steps.push((record.clone(), step.clone()));
        Ok(())
    }
}

impl Collect {
    /// The last converged step.
    pub fn last(&self) -> Option<&StepResults> {
        self.steps.last().map(|(_, r)| r)
    }
}

/// One converged step, as the run summary lists it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepRecord {
    pub stage: String,
    pub stage_index: usize,
    pub step: usize,
    pub load_factor: f64,
    pub iterations: usize,
    /// Out-of-balance force after the last iteration, relative to the reference force.
    pub force_residual: f64,
    /// ‖Ax − b‖/‖b‖ of each linear solve in this step.
    pub linear_residuals: Vec<f64>,
    pub seconds: f64,
    /// Interface points whose normal row repeats another row on the free DOFs (see NormalState).
    pub redundant_rows: Vec<String>,
}

/// The state carried from step to step.
#[derive(Debug, Clone)]
pub struct State {
    /// Displacements of every node, `2·node + d`.
    pub u: Vec<f64>,
    /// Multipliers in `dofs::multipliers` order.
    pub lambda: Vec<f64>,
    pub interfaces: Vec<Interface>,
    /// Total external force applied so far.
    pub f_ext: Vec<f64>,
}

/// Run every stage of a model.
///
/// # Errors
/// A solve or convergence failure names the stage and step; steps completed before it have
/// already been passed to `sink`.
pub fn run(model: &Model, options: &RunOptions, sink: &mut dyn StepSink) -> Result<SolverStats, Error> {
    refuse_laws_not_yet_implemented(model)?;
    let elements = ElementMatrices::compute(model);
    let mut system = LinearSystem::new(options.backend).map_err(|source| Error::Solve {
        file: model.source.clone(),
        stage: model.stages[0].name.clone(),
        step: 1,
        source,
    })?;
    let dof_count = 2 * model.mesh.nodes.len();
    let mut state = State {
        u: vec![0.0; dof_count],
        lambda: vec![0.0; crate::dofs::multipliers(&model.interfaces).len()],
        interfaces: model.interfaces.clone(),
        f_ext: vec![0.0; dof_count],
    };
    let mut held = vec![false; dof_count];
    for &(n, d) in &model.supports {
        held[dof(n, d)] = true;
    }
    for (stage_index, stage) in model.stages.iter().enumerate() {
        for &(n, d, _) in &stage.prescribed {
            held[dof(n, d)] = true;
        }
        let dofs = DofMap::new(model.mesh.nodes.len(), &held, &state.interfaces);
        let redundant = mark_redundant_rows(model, &mut state.interfaces, &dofs);
        let stage_force = external_force(model, &stage.loads);
        let f_ext_start = state.f_ext.clone();
        let u_start = state.u.clone();
        for (step_index, &factor) in stage.load_factors.iter().enumerate() {
            let started = std::time::Instant::now();
            let step = step_index + 1;
            for (k, f) in state.f_ext.iter_mut().enumerate() {
                *f = f_ext_start[k] + factor * stage_force[k];
            }
            for &(n, d, value) in &stage.prescribed {
                state.u[dof(n, d)] = u_start[dof(n, d)] + factor * value;
            }
            let (iterations, force_residual, linear_residuals) =
                equilibrium(model, options, &elements, &mut system, &dofs, &mut state)
                    .map_err(|e| e.at(&model.source, &stage.name, step))?;
            let rows = InterfaceRows::new(model, &state.interfaces, &dofs);
            let results = StepResults::compute(model, &elements, &rows, &state, &held);
            let record = StepRecord {
                stage: stage.name.clone(),
                stage_index,
                step,
                load_factor: factor,
                iterations,
                force_residual,
                linear_residuals,
                seconds: started.elapsed().as_secs_f64(),
                redundant_rows: redundant.clone(),
            };
            sink.step_done(&results, &record, &system.stats)?;
        }
    }
    Ok(system.stats)
}

fn dof(n: usize, d: Direction) -> usize {
    2 * n + if d == Direction::X { 0 } else { 1 }
}

fn refuse_laws_not_yet_implemented(model: &Model) -> Result<(), Error> {
    let problems: Vec<crate::error::Problem> = model
        .interfaces
        .iter()
        .enumerate()
        .filter_map(|(k, i)| match &i.law {
            ShearLaw::Strength { kind, .. } => Some(crate::error::Problem {
                field: format!("interfaces[{k}].law"),
                entity: Some(format!("interface \"{}\"", i.name)),
                message: format!(
                    "the '{kind}' shear law is accepted by the model format, but this version of geoslip runs only 'linear' and 'tie' interfaces; its strength limit is not applied yet"
                ),
            }),
            _ => None,
        })
        .collect();
    if problems.is_empty() {
        Ok(())
    } else {
        Err(Error::Model(crate::error::ModelError { file: model.source.clone(), problems }))
    }
}

/// Consistent nodal forces of a list of loads (full load, factor 1).
pub fn external_force(model: &Model, loads: &[Load]) -> Vec<f64> {
    use crate::element::solid;
    let mesh = &model.mesh;
    let mut f = vec![0.0; 2 * mesh.nodes.len()];
    for load in loads {
        match load {
            Load::Point { node, force } => {
                f[2 * node] += force[0];
                f[2 * node + 1] += force[1];
            }
            Load::Gravity { factor } => {
                for (s, e) in mesh.solids.iter().enumerate() {
                    let gamma = model.soil(s).unit_weight * factor;
                    let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.position(n)).collect();
                    let fe = solid::body_force(e.kind, &coords, [0.0, -gamma])
                        .expect("element Jacobians were checked when the model was read");
                    for (a, &n) in e.nodes.iter().enumerate() {
                        f[2 * n] += fe[2 * a];
                        f[2 * n + 1] += fe[2 * a + 1];
                    }
                }
            }
            Load::EdgeTraction { sides, pressure, shear } => {
                for side in sides {
                    let e = &mesh.solids[side.solid];
                    let local = &e.kind.sides()[side.side];
                    let nodes: Vec<usize> = local.iter().map(|&l| e.nodes[l]).collect();
                    let coords: Vec<[f64; 2]> = nodes.iter().map(|&n| mesh.position(n)).collect();
                    // Element sides run counter-clockwise: the element lies to their left.
                    let fe = solid::side_traction(&coords, *pressure, *shear, 1.0);
                    for (a, &n) in nodes.iter().enumerate() {
                        f[2 * n] += fe[2 * a];
                        f[2 * n + 1] += fe[2 * a + 1];
                    }
                }
            }
        }
    }
    f
}

/// Rows with no free DOF, or that repeat an earlier row on the free DOFs, would make the system
/// singular; they are set on a unit diagonal and reported. Returns the report lines.
fn mark_redundant_rows(model: &Model, interfaces: &mut [Interface], dofs: &DofMap) -> Vec<String> {
    let rows = InterfaceRows::new(model, interfaces, dofs);
    let mut seen: HashMap<Vec<(usize, i64)>, usize> = HashMap::new();
    let mut report = Vec::new();
    for (k, row) in rows.constraint_rows.iter().enumerate() {
        let m = dofs.multipliers[k];
        let mut free: Vec<(usize, f64)> = row
            .iter()
            .filter_map(|&(d, c)| dofs.equation[d].map(|e| (e, c)))
            .filter(|&(_, c)| c.abs() > 1e-12)
            .collect();
        free.sort_by_key(|&(e, _)| e);
        let name = |interfaces: &[Interface], k: usize| {
            let m = dofs.multipliers[k];
            let i = &interfaces[m.interface];
            let f = &i.faces[m.face];
            format!("interface \"{}\" {} face at node {}", i.name, f.label, model.mesh.node_id(f.points[m.point].slave))
        };
        let carried_by = if free.is_empty() {
            Some("the supports (every DOF of the row is held)".to_string())
        } else {
            let scale = free[0].1;
            let key: Vec<(usize, i64)> = free.iter().map(|&(e, c)| (e, (c / scale * 1e9).round() as i64)).collect();
            match seen.get(&key) {
                Some(&first) => Some(name(interfaces, first)),
                None => {
                    seen.insert(key, k);
                    None
                }
            }
        };
        let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
        let state = if m.tangential { &mut point.tangential_state } else { &mut point.normal_state };
        match carried_by {
            Some(by) => {
                report.push(format!(
                    "{} ({}): carried by {by}",
                    name(interfaces, k),
                    if m.tangential { "tangential" } else { "normal" }
                ));
                let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
                let state = if m.tangential { &mut point.tangential_state } else { &mut point.normal_state };
                *state = NormalState::Redundant { carried_by: by };
            }
            None => {
                if matches!(state, NormalState::Redundant { .. }) {
                    *state = NormalState::Active;
                }
            }
        }
    }
    report
}

/// Why an increment failed, before the stage and step are known.
enum IncrementError {
    Solve(SolveError),
    NotConverged { iterations: usize, residual: f64, reference: f64 },
}

impl IncrementError {
    fn at(self, file: &std::path::Path, stage: &str, step: usize) -> Error {
        match self {
            IncrementError::Solve(source) => {
                Error::Solve { file: file.to_path_buf(), stage: stage.to_string(), step, source }
            }
            IncrementError::NotConverged { iterations, residual, reference } => Error::NotConverged {
                file: file.to_path_buf(),
                stage: stage.to_string(),
                step,
                iterations,
                residual,
                reference,
                hint: "try more load factors in this stage (smaller increments)".into(),
            },
        }
    }
}

/// Iterate one increment to equilibrium. Returns (iterations, final relative residual, linear
/// solve residuals).
fn equilibrium(
    model: &Model,
    options: &RunOptions,
    elements: &ElementMatrices,
    system: &mut LinearSystem,
    dofs: &DofMap,
    state: &mut State,
) -> Result<(usize, f64, Vec<f64>), IncrementError> {
    let u_increment_start = state.u.clone();
    let mut linear_residuals = Vec::new();
    for iteration in 1..=options.max_iterations {
        let IterationSystem { triplets, rhs, scale, active } = iteration_system(model, elements, dofs, state);
        let (x, lin_res) = match system.solve(dofs.size(), &triplets, &rhs, active) {
            Ok(v) => v,
            Err(Failure::Singular { equations }) => {
                return Err(IncrementError::Solve(SolveError::Singular {
                    backend: system.backend().name(),
                    unknowns: diagnose_singular(model, &state.interfaces, dofs, &triplets, equations),
                }))
            }
            Err(Failure::Other(e)) => return Err(IncrementError::Solve(e)),
        };
        linear_residuals.push(lin_res);
        let mut correction2 = 0.0f64;
        for (d, eq) in dofs.equation.iter().enumerate() {
            if let Some(e) = eq {
                state.u[d] += x[*e];
                correction2 += x[*e] * x[*e];
            }
        }
        for k in 0..dofs.multipliers.len() {
            state.lambda[k] += scale * x[dofs.multiplier_equation(k)];
        }
        // Converged when the out-of-balance force is small and the gaps are closed, and either the
        // correction is small against the increment or this was the first solve (a first solve that
        // already balances the forces had a linear increment: its correction is the increment).
        let increment2: f64 = state.u.iter().zip(&u_increment_start).map(|(a, b)| (a - b).powi(2)).sum();
        let displacement_ok = iteration == 1
            || correction2.sqrt() <= options.displacement_tolerance * increment2.sqrt().max(f64::MIN_POSITIVE);
        let rows = InterfaceRows::new(model, &state.interfaces, dofs);
        let (residual, reference) = out_of_balance(elements, &rows, state, dofs);
        if !residual.is_finite() {
            return Err(IncrementError::NotConverged { iterations: iteration, residual, reference });
        }
        let gaps = row_gaps(&rows, &state.u);
        if residual <= options.force_tolerance * reference && gaps_closed(&gaps, state, dofs) && displacement_ok {
            return Ok((iteration, residual / reference, linear_residuals));
        }
        if iteration == options.max_iterations {
            return Err(IncrementError::NotConverged { iterations: iteration, residual, reference });
        }
    }
    Err(IncrementError::NotConverged { iterations: 0, residual: f64::NAN, reference: f64::NAN })
}

/// The linear system of one equilibrium iteration.
pub struct IterationSystem {
    pub triplets: crate::assembly::Triplets,
    pub rhs: Vec<f64>,
    /// Scale of the constraint rows (the multiplier unknowns are Δλ/scale).
    pub scale: f64,
    /// Rows that hold a constraint (zero diagonal).
    pub active: usize,
}

/// Assemble the system of one iteration from the current state: out-of-balance forces on the free
/// DOFs, −g on active rows, −λ on the rest.
pub fn iteration_system(model: &Model, elements: &ElementMatrices, dofs: &DofMap, state: &State) -> IterationSystem {
    let n_dof = state.u.len();
    let rows = InterfaceRows::new(model, &state.interfaces, dofs);
    let gaps = row_gaps(&rows, &state.u);
    let f_int = system::internal_force(elements, &rows, &state.u);
    let f_c = system::constraint_force(&rows, &state.lambda, n_dof);
    let mut rhs = vec![0.0; dofs.size()];
    for (d, eq) in dofs.equation.iter().enumerate() {
        if let Some(e) = eq {
            rhs[*e] = state.f_ext[d] - f_int[d] - f_c[d];
        }
    }
    let scale = elements.typical_stiffness();
    let mut active = 0;
    for k in 0..dofs.multipliers.len() {
        rhs[dofs.multiplier_equation(k)] = if system::multiplier_is_active(&state.interfaces, dofs, k) {
            active += 1;
            -scale * gaps[k]
        } else {
            -state.lambda[k]
        };
    }
    let triplets = system::assemble(elements, &rows, &state.interfaces, dofs, scale);
    IterationSystem { triplets, rhs, scale, active }
}

/// The first system a run of `model` solves (stage 1, step 1, iteration 1): for benchmarks and
/// solver studies.
pub fn first_system(model: &Model) -> (usize, IterationSystem) {
    let elements = ElementMatrices::compute(model);
    let dof_count = 2 * model.mesh.nodes.len();
    let mut held = vec![false; dof_count];
    for &(n, d) in &model.supports {
        held[dof(n, d)] = true;
    }
    let stage = &model.stages[0];
    for &(n, d, _) in &stage.prescribed {
        held[dof(n, d)] = true;
    }
    let mut interfaces = model.interfaces.clone();
    let dofs = DofMap::new(model.mesh.nodes.len(), &held, &interfaces);
    mark_redundant_rows(model, &mut interfaces, &dofs);
    let factor = stage.load_factors[0];
    let mut u = vec![0.0; dof_count];
    for &(n, d, value) in &stage.prescribed {
        u[dof(n, d)] = factor * value;
    }
    let f_ext = external_force(model, &stage.loads).into_iter().map(|f| factor * f).collect();
    let state = State { u, lambda: vec![0.0; dofs.multipliers.len()], interfaces, f_ext };
    (dofs.size(), iteration_system(model, &elements, &dofs, &state))
}

fn row_gaps(rows: &InterfaceRows, u: &[f64]) -> Vec<f64> {
    rows.constraint_rows.iter().map(|row| row.iter().map(|&(d, c)| c * u[d]).sum()).collect()
}

/// ‖out-of-balance force on the free DOFs‖ and the reference force (applied loads and reactions).
fn out_of_balance(elements: &ElementMatrices, rows: &InterfaceRows, state: &State, dofs: &DofMap) -> (f64, f64) {
    let n_dof = state.u.len();
    let f_int = system::internal_force(elements, rows, &state.u);
    let f_c = system::constraint_force(rows, &state.lambda, n_dof);
    let mut r2 = 0.0;
    let mut reference2 = 0.0;
    for d in 0..n_dof {
        let r = state.f_ext[d] - f_int[d] - f_c[d];
        if dofs.equation[d].is_some() {
            r2 += r * r;
            reference2 += state.f_ext[d].powi(2);
        } else {
            reference2 += r * r; // reactions
        }
    }
    (r2.sqrt(), reference2.sqrt().max(f64::MIN_POSITIVE))
}

fn gaps_closed(gaps: &[f64], state: &State, dofs: &DofMap) -> bool {
    let scale = state.u.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
    gaps.iter()
        .enumerate()
        .all(|(k, g)| !system::multiplier_is_active(&state.interfaces, dofs, k) || g.abs() <= 1e-9 * scale)
}

/// Name what is unconstrained in a singular system.
fn diagnose_singular(
    model: &Model,
    interfaces: &[Interface],
    dofs: &DofMap,
    triplets: &crate::assembly::Triplets,
    equations: Vec<usize>,
) -> Vec<String> {
    let n = dofs.size();
    let mut column_norm = vec![0.0f64; n];
    for (&j, &v) in triplets.cols.iter().zip(&triplets.values) {
        column_norm[j] += v.abs();
    }
    let describe = |e: usize| {
        let name = dofs.describe(e, &model.mesh, interfaces);
        if column_norm.get(e).is_some_and(|&c| c == 0.0) {
            format!("{name} has no stiffness and no constraint")
        } else {
            format!("{name} is not held (a null pivot: a mechanism runs through it)")
        }
    };
    if !equations.is_empty() {
        return cap(equations.into_iter().map(describe).collect());
    }
    // Unknowns with no stiffness and no constraint at all.
    let empty: Vec<String> = (0..n).filter(|&j| column_norm[j] == 0.0).map(describe).collect();
    if !empty.is_empty() {
        return cap(empty);
    }
    // Ask the reference solver, whose complete pivoting isolates the undetermined unknowns.
    if n <= dense_ref::SIZE_LIMIT {
        let matrix = crate::assembly::PatternCache::default().assemble(n, triplets).0;
        let mut dense = dense_ref::DenseReference::default();
        if dense.analyse(&matrix).is_ok() {
            if let Err(Failure::Singular { equations }) = dense.factorize(&matrix) {
                return cap(equations.into_iter().map(describe).collect());
            }
        }
    }
    vec!["a mechanism that the structural checks did not isolate: check that every bar node is held by an interface and every body is supported".into()]
}

fn cap(mut list: Vec<String>) -> Vec<String> {
    if list.len() > 12 {
        let more = list.len() - 12;
        list.truncate(12);
        list.push(format!("and {more} more"));
    }
    list
}
