//! What a run keeps from its start to its end: the model and the options, the element matrices and
//! the soil's laws (computed once), the linear system with its reuse bookkeeping, and what the
//! stages have added up so far (held DOFs, gravity, the weight in the applied force).

use super::options::RunOptions;
use super::soil::SoilSetup;
use super::stats::{RunStats, SolverStats};
use crate::assembly::ElementMatrices;
use crate::dofs::{dof, DofMap};
use crate::element::bar::BarMaterial;
use crate::error::{Error, MemoryShortfall, SolveError};
use crate::interface::active_set::ActiveSet;
use crate::linsol::condensed::CondensedSystem;
use crate::linsol::linear_system::LinearSystem;
use crate::linsol::Backend;
use crate::model::{Model, Scheme};

/// The run's context: passed to every step instead of a long list of parameters.
pub struct Context<'a> {
    pub model: &'a Model,
    pub options: &'a RunOptions,
    pub elements: ElementMatrices,
    /// The soil's laws (reduced by a strength-reduction search while it runs).
    pub setup: SoilSetup,
    pub system: LinearSystem,
    /// The fingerprint of the matrix `system` holds factorised, if it holds one: a later iteration
    /// (of this increment or a later one) with the same fingerprint solves with it again.
    pub system_key: Option<u64>,
    /// The run's counts, times and warnings.
    pub stats: RunStats,
    /// The soil condensed onto the interface's unknowns (`condensation`), where the run condenses.
    pub condensed: Option<CondensedSystem>,
    /// The soil part (its key) whose condensed system's stiffness spread was checked
    /// (`singular::warn_if_ill_conditioned`).
    pub conditioning_checked: Option<u64>,
    /// Nodes that belong to no soil element (reinforcement nodes): their transverse DOF has no
    /// stiffness of its own.
    pub bar_only: Vec<bool>,
    /// DOFs held by the supports and by the prescribed displacements of the stages so far.
    pub held: Vec<bool>,
    /// The sum of the gravity factors of the stages so far.
    pub gravity: f64,
    /// The soil's weight and the boundary water pressure now in the applied force.
    pub applied_weight: Vec<f64>,
    /// The mesh's characteristic length (the scale of gaps and of the force floor).
    pub characteristic: f64,
    /// The elements' force at the end of the last time step of a dynamic stage, for the next
    /// step's first right-hand side ([`Context::take_carried_force`]).
    pub carried_force: Option<CarriedForce>,
}

/// The soil's and the bars' force with the dynamic operator's D·u (`assembly::soil_and_bar_force`)
/// as a time step's closing check found it, at the displacements and with the D it was found for.
/// The soil's and bars' states it was found with are the ones the step committed.
pub struct CarriedForce {
    pub u: Vec<f64>,
    /// The dynamic operator's key ([`Inertia::key`](crate::assembly::inertia::Inertia::key)).
    pub operator: (u64, u64, u64, u64),
    pub force: Vec<f64>,
    /// The out-of-balance force's round-off floor found with it.
    pub floor: f64,
}

impl<'a> Context<'a> {
    /// Check the memory, compute the element matrices and set up the soil and the solver.
    ///
    /// # Errors
    /// [`SolveError::OutOfMemory`] when the model alone would not fit, and the backend's error when
    /// it cannot be started; both at the first stage's first step.
    pub fn new(model: &'a Model, options: &'a RunOptions) -> Result<Context<'a>, Error> {
        let at_start =
            |source| Error::Solve { file: model.source.clone(), stage: model.stages[0].name.clone(), step: 1, source };
        check_memory(model, options).map_err(at_start)?;
        let setup = SoilSetup::new(model);
        let elements = element_matrices(model, &setup);
        let symmetric = symmetric_tangent(model, options);
        let system = LinearSystem::new(options.backend, symmetric, &options.solver).map_err(at_start)?;
        let stats = RunStats { solver: SolverStats { symmetric, ..SolverStats::default() }, ..RunStats::default() };
        let condensed = condenses(options, &setup)
            .then(|| CondensedSystem::new(options.backend, &options.solver))
            .transpose()
            .map_err(at_start)?;
        let dof_count = 2 * model.mesh.nodes.len();
        let mut held = vec![false; dof_count];
        for &(n, d) in &model.supports {
            held[dof(n, d)] = true;
        }
        Ok(Context {
            model,
            options,
            elements,
            setup,
            system,
            system_key: None,
            stats,
            condensed,
            conditioning_checked: None,
            bar_only: bar_only_nodes(model),
            held,
            gravity: 0.0,
            applied_weight: vec![0.0; dof_count],
            characteristic: model.mesh.characteristic_length(),
            carried_force: None,
        })
    }
}

impl Context<'_> {
    /// The elements' force carried from the last time step, if the displacements `u` and the
    /// dynamic operator are still the ones it was found for (a step of the same length from where
    /// the last one ended): the elements' part of an increment's first right-hand side, saving a
    /// pass over the elements. Taken once.
    pub fn take_carried_force(&mut self, u: &[f64]) -> Option<(Vec<f64>, f64)> {
        let carried = self.carried_force.take()?;
        let operator = self.elements.inertia.as_ref()?.key();
        (carried.operator == operator && carried.u == u).then_some((carried.force, carried.floor))
    }

    /// The active-set rules for a stage's DOFs, with the nodes in place now.
    pub fn active_set<'b>(&'b self, dofs: &'b DofMap, placed: &'b [bool]) -> ActiveSet<'b> {
        ActiveSet {
            mesh: &self.model.mesh,
            multipliers: &dofs.multipliers,
            equation: &dofs.equation,
            bar_only: &self.bar_only,
            placed,
        }
    }
}

/// The element matrices of the model's soil (with `setup`'s elasticity and integration rule) and
/// bars.
pub fn element_matrices(model: &Model, setup: &SoilSetup) -> ElementMatrices {
    let bar_materials: Vec<BarMaterial> = model
        .mesh
        .bars
        .iter()
        .map(|b| {
            let m = &model.reinforcements[b.material].1;
            BarMaterial {
                axial_stiffness: m.axial_stiffness,
                tension_only: m.tension_only,
                rupture_strength: m.rupture_strength,
            }
        })
        .collect();
    ElementMatrices::compute(&model.mesh, &setup.elastic, &bar_materials, setup.rule)
}

/// Whether the run condenses its soil onto the interface (`condensation`): asked for (the default),
/// a soil that stays elastic, and a backend with a condensed path (every one but the dense
/// reference; not in the MPI build, whose ranks share one factorisation).
fn condenses(options: &RunOptions, setup: &SoilSetup) -> bool {
    options.solver.condense
        && !setup.any_plastic()
        && options.backend.resolve() != Backend::Dense
        && !cfg!(feature = "mpi")
}

/// Whether every matrix of the run is symmetric, so that the solver may factorise it as LDLᵀ (MUMPS
/// SYM=2, on the lower triangle) rather than LU. The constant-stiffness and newton-symmetric schemes
/// always are, unless a face dilates. Newton's consistent tangent is unsymmetric where τ is coupled to σn (a law with
/// friction, with σn not frozen: frozen in every stage that loads, from the first on, unless that
/// stage is a strength-reduction search, which starts unfrozen), under large slip (re-association
/// on: a spring's force follows its tributary length) or where Mohr–Coulomb soil flows
/// non-associatively (ψ ≠ φ, the return map's tangent).
fn symmetric_tangent(model: &Model, options: &RunOptions) -> bool {
    // a dilating face's normal row takes the slip's direction, its column does not
    if model.interfaces.iter().flat_map(|i| &i.faces).any(|f| f.dilation.is_some()) {
        return false;
    }
    if options.analysis.scheme != Scheme::Newton {
        return true;
    }
    // (a strength-reduction stage keeps the σn frozen by the stage before it)
    let frozen = model.stages.first().is_some_and(|s| s.strength_reduction.is_none())
        && model
            .stages
            .iter()
            .filter(|s| s.strength_reduction.is_none())
            .all(|s| s.freeze_normal_stress.unwrap_or(options.analysis.freeze_normal_stress));
    // (an embedded reinforcement's σn is the soil's, not coupled to a multiplier in the tangent)
    let coupled = !frozen
        && model.interfaces.iter().flat_map(|i| &i.faces).any(|f| f.law.is_frictional() && f.embedded.is_none());
    // under large slip a spring's force τ·ℓ follows its tributary length, which the slave line's
    // stretch and embedment move: row ⊗ ∂(τ·ℓ)/∂u
    let stretched = options.analysis.reassociation != crate::model::ReassociationRule::None
        && model.interfaces.iter().any(|i| !i.is_tie());
    !coupled && !stretched && !model.has_non_associated_soil()
}

/// Stop before allocating anything large when the model alone would not fit, in memory or in the
/// assembly's 32-bit indices.
fn check_memory(model: &Model, options: &RunOptions) -> Result<(), SolveError> {
    // every node's two displacements and a multiplier per interface point and face bound the
    // equations; the soil's element matrices are nearly all of a list's entries (half the limit
    // leaves the rest to the bars and interfaces)
    let points: usize = model.interfaces.iter().flat_map(|i| &i.faces).map(|f| f.points.len()).sum();
    let equations = 2 * model.mesh.nodes.len() + points;
    let entries: usize = model.mesh.solids.iter().map(|s| (2 * s.nodes.len()).pow(2)).sum();
    let limit = crate::linsol::csc::MAX_ENTRIES;
    if equations >= limit || entries >= limit / 2 {
        return Err(SolveError::BeyondIndices { equations, entries, limit });
    }
    if let Some(limit) = options.solver.memory_limit_mb.or_else(crate::memory::available_memory_mb) {
        let needed = model_memory_estimate_mb(model);
        if needed > limit {
            return Err(SolveError::OutOfMemory(Box::new(MemoryShortfall {
                backend: "geoslip",
                what: "the model, its element matrices and the assembled system (estimate)",
                needed_mb: needed,
                available_mb: limit,
                hint: "rank 0 of an MPI run holds these too: use a machine with more memory, or coarsen the mesh"
                    .into(),
            })));
        }
    }
    Ok(())
}

/// Memory the model, its element matrices and its assembled system take, MB, before the solver's
/// own: about 70 bytes per entry of the soil element matrices (the matrices, an iteration's
/// triplets, the triplet-to-CSC refill map and the CSC matrix with the copy kept to detect
/// unchanged values), calibrated against `geoslip bench`'s "model and assembly only" rows
/// (docs/performance.md).
pub fn model_memory_estimate_mb(model: &Model) -> f64 {
    let entries: f64 = model.mesh.solids.iter().map(|s| (2 * s.nodes.len()).pow(2) as f64).sum();
    crate::mesh::memory_estimate_mb(model.mesh.nodes.len(), entries)
}

/// Nodes that belong to no soil element (reinforcement nodes): their transverse DOF has no
/// stiffness of its own.
fn bar_only_nodes(model: &Model) -> Vec<bool> {
    let mut in_soil = vec![false; model.mesh.nodes.len()];
    for s in &model.mesh.solids {
        for &n in &s.nodes {
            in_soil[n] = true;
        }
    }
    in_soil.iter().map(|s| !s).collect()
}
