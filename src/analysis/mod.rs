//! Stages, increments and the equilibrium iteration (the paper's Fig. 3).
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

pub mod reassociate;
pub mod results;
pub mod soil;
pub mod system;

use crate::dofs::DofMap;
use crate::error::{Error, SolveError};
use crate::interface::{Interface, NormalState, ShearResponse};
use crate::linsol::{dense_ref, Backend, Failure, LinearSolver};
use crate::model::file::{AnalysisSettings, Direction, ReassociationRule, Scheme};
use crate::model::{Load, Model};
use results::StepResults;
use std::collections::HashMap;
use std::time::Instant;
use system::{ElementMatrices, InterfaceRows, LinearSystem, SoilView, SolverStats};

/// What a run may be asked to do: a backend and the model's `[analysis]` settings
/// ([`RunOptions::for_model`]).
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub backend: Backend,
    pub analysis: AnalysisSettings,
    /// Ordering, out-of-core and memory limit of the backend.
    pub solver: crate::linsol::SolverOptions,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            backend: Backend::Auto,
            analysis: AnalysisSettings::default(),
            solver: crate::linsol::SolverOptions::default(),
        }
    }
}

impl RunOptions {
    /// The model's `[analysis]` settings with a backend and its default settings.
    pub fn for_model(model: &Model, backend: Backend) -> RunOptions {
        RunOptions { backend, analysis: model.analysis.clone(), solver: crate::linsol::SolverOptions::default() }
    }
}

/// Memory the model, its element matrices and its assembled system take, MB, before the solver's
/// own: about 70 bytes per entry of the soil element matrices (the matrices, an iteration's
/// triplets, the triplet-to-CSC refill map and the CSC matrix with the copy kept to detect
/// unchanged values), calibrated against `geoslip bench`'s "model and assembly only" rows
/// (docs/performance.md).
pub fn model_memory_estimate_mb(model: &Model) -> f64 {
    let entries: f64 = model.mesh.solids.iter().map(|s| (2 * s.nodes.len()).pow(2) as f64).sum();
    (70.0 * entries + 200.0 * model.mesh.nodes.len() as f64) / (1024.0 * 1024.0)
}

/// Receives each converged step as soon as it exists, so that a later failure never loses it.
pub trait StepSink {
    fn step_done(&mut self, step: &StepResults, record: &StepRecord, stats: &SolverStats) -> Result<(), Error>;

    /// The result of a strength-reduction stage, after its last step.
    fn factor_of_safety(&mut self, _fs: &FactorOfSafety) -> Result<(), Error> {
        Ok(())
    }
}

/// The factor of safety found by a strength-reduction stage.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FactorOfSafety {
    pub stage: String,
    /// FS: the largest strength reduction factor with equilibrium.
    pub value: f64,
    /// The smallest factor tried without equilibrium; `None` when every factor up to `max_factor`
    /// found one (FS is then at least `value`).
    pub failed_at: Option<f64>,
    /// `interfaces` or `soil and interfaces`.
    pub reduced: &'static str,
    /// Every factor tried, and whether it found equilibrium.
    pub trials: Vec<(f64, bool)>,
    /// Why the search found no equilibrium at `failed_at`: how the iterations ended, the soil
    /// yielding, and the reinforcement that ruptured on the way (rolled back with the trial).
    pub failure: Option<String>,
}

/// Keeps every converged step in memory (for tests and for programs that use geoslip as a library).
#[derive(Debug, Default)]
pub struct Collect {
    pub steps: Vec<(StepRecord, StepResults)>,
    pub factors_of_safety: Vec<FactorOfSafety>,
}

impl StepSink for Collect {
    fn step_done(&mut self, step: &StepResults, record: &StepRecord, _: &SolverStats) -> Result<(), Error> {
        self.steps.push((record.clone(), step.clone()));
        Ok(())
    }

    fn factor_of_safety(&mut self, fs: &FactorOfSafety) -> Result<(), Error> {
        self.factors_of_safety.push(fs.clone());
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
    /// The strength reduction factor F of a strength-reduction stage (strengths divided by F).
    pub strength_factor: Option<f64>,
    pub iterations: usize,
    /// How many times this increment was cut back before it converged.
    pub cutbacks: usize,
    /// Out-of-balance force after the last iteration, relative to the reference force.
    pub force_residual: f64,
    /// ‖Ax − b‖/‖b‖ of each linear solve in this step.
    pub linear_residuals: Vec<f64>,
    pub seconds: f64,
    /// Interface points whose normal row repeats another row on the free DOFs (see NormalState).
    pub redundant_rows: Vec<String>,
    /// Interface points that changed state (released, re-activated, held) in this step.
    pub state_changes: Vec<String>,
    /// Points re-associated with another master segment after this step.
    pub reassociations: Vec<reassociate::Reassociation>,
    /// Points now sliding at their strength.
    pub sliding_points: usize,
    /// Soil Gauss points on the yield surface.
    pub yielding_points: usize,
    /// Points with a tangential law that are in contact.
    pub contact_points: usize,
    /// Force balance of every reinforcement: what is applied to its nodes against what its interfaces
    /// carry.
    pub balance: Vec<results::ReinforcementBalance>,
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
    /// Displacements at the end of the last converged increment (slip increments start there).
    pub u_committed: Vec<f64>,
    /// σn per spring frozen at the start of the stage (when asked for).
    pub frozen_sigma_n: Option<Vec<f64>>,
    /// Bars (in mesh order): ruptured, not yet placed, stretch at placement.
    pub bars: system::BarStates,
    /// The soil: present elements, Gauss-point stresses, pore pressures.
    pub soil: soil::SoilField,
    /// Nodes of soil or reinforcement in place now: a face whose master segment is not (cover soil
    /// still to come over a liner) has no contact there. Empty: every node.
    pub placed: Vec<bool>,
}

/// Run every stage of a model.
///
/// # Errors
/// A solve or convergence failure names the stage and step, and the interface points that kept
/// changing state; steps completed before it have already been passed to `sink`.
pub fn run(model: &Model, options: &RunOptions, sink: &mut dyn StepSink) -> Result<SolverStats, Error> {
    // Stop before allocating anything large when the model alone would not fit.
    if let Some(limit) = options.solver.memory_limit_mb.or_else(crate::linsol::available_memory_mb) {
        let needed = model_memory_estimate_mb(model);
        if needed > limit {
            return Err(Error::Solve {
                file: model.source.clone(),
                stage: model.stages[0].name.clone(),
                step: 1,
                source: SolveError::OutOfMemory(Box::new(crate::error::MemoryShortfall {
                    backend: "geoslip",
                    what: "the model, its element matrices and the assembled system (estimate)",
                    needed_mb: needed,
                    available_mb: limit,
                    hint: "rank 0 of an MPI run holds these too: use a machine with more memory, or coarsen the mesh"
                        .into(),
                })),
            });
        }
    }
    let elements = ElementMatrices::compute(model);
    let mut setup = soil::SoilSetup::new(model);
    let mut system =
        LinearSystem::new(options.backend, options.analysis.scheme != Scheme::Newton, &options.solver).map_err(
            |source| Error::Solve { file: model.source.clone(), stage: model.stages[0].name.clone(), step: 1, source },
        )?;
    let dof_count = 2 * model.mesh.nodes.len();
    let mut state = State {
        u: vec![0.0; dof_count],
        lambda: vec![0.0; crate::dofs::multipliers(&model.interfaces).len()],
        interfaces: model.interfaces.clone(),
        f_ext: vec![0.0; dof_count],
        u_committed: vec![0.0; dof_count],
        frozen_sigma_n: None,
        bars: system::BarStates {
            absent: model.initially_absent_bars(),
            ..system::BarStates::new(model.mesh.bars.len())
        },
        soil: soil::initial_field(model),
        placed: Vec::new(),
    };
    reserve_segments(options, &mut state.interfaces);
    let bar_only = bar_only_nodes(model);
    let mut held = vec![false; dof_count];
    for &(n, d) in &model.supports {
        held[dof(n, d)] = true;
    }
    // Gravity so far (the sum of the stages' gravity factors), and the weight and boundary water
    // pressure in f_ext.
    let mut gravity = 0.0;
    let mut applied_weight = vec![0.0; dof_count];
    for (stage_index, stage) in model.stages.iter().enumerate() {
        for &(n, d, _) in &stage.prescribed {
            held[dof(n, d)] = true;
        }
        // The soil of this stage: lifts placed, soil removed, a new water table, K0 stresses.
        let soil_changed =
            !stage.activate.is_empty() || !stage.deactivate.is_empty() || stage.k0 || stage.water.is_some();
        soil::deactivate(&mut state.soil, &stage.deactivate);
        let bar_nodes: Vec<usize> = stage.activate_bars.iter().flat_map(|&b| model.mesh.bars[b].nodes).collect();
        soil::activate(model, &setup, &mut state.soil, &stage.activate, &bar_nodes, &mut state.u);
        // placed reinforcement: its force counts from the stretch it lands with
        for &b in &stage.activate_bars {
            state.bars.absent[b] = false;
            let law = &elements.bars[b];
            state.bars.placed_stretch[b] = law.stretch(&state.u, &elements.blocks[law.block].0);
        }
        if soil_changed {
            let water = stage.water.clone().unwrap_or_else(|| state.soil.water.clone());
            soil::set_water(model, &setup, &mut state.soil, water);
        }
        if stage.k0 {
            soil::set_k0(model, &setup, &mut state.soil, &state.u);
        }
        state.u_committed = state.u.clone();
        let placed_before = std::mem::replace(&mut state.placed, placed_nodes(model, &state.soil, &state.bars));
        place_contacts(&mut state, &placed_before);
        let stage_held = with_absent_nodes(model, &state.soil, &state.bars, &held);
        let dofs = DofMap::new(model.mesh.nodes.len(), &stage_held, &state.interfaces);
        let mut redundant = mark_redundant_rows(model, &mut state.interfaces, &dofs);
        // This stage's additions: its loads, and the change in the soil's weight (gravity switched
        // on or up, soil placed or removed, soil under a new water table).
        gravity +=
            stage.loads.iter().map(|l| if let Load::Gravity { factor } = l { *factor } else { 0.0 }).sum::<f64>();
        let mut weight = soil::weight(model, &setup, &state.soil, gravity);
        for (w, p) in weight.iter_mut().zip(soil::water_on_boundary(model, &state.soil, &state.interfaces)) {
            *w += p;
        }
        let mut stage_force = external_force(model, &stage.loads);
        for ((f, w), a) in stage_force.iter_mut().zip(&weight).zip(&applied_weight) {
            *f += w - a;
        }
        applied_weight = weight;
        let f_ext_start = state.f_ext.clone();
        // What the soil's change put out of balance (removed soil, new pore pressures, K0 stresses
        // off equilibrium) is released over the stage's load factors: f_ext starts at the
        // internal force of the new configuration and ends at the applied loads.
        let unbalance =
            if soil_changed { stage_unbalance(model, &setup, &elements, &dofs, &state) } else { vec![0.0; dof_count] };
        if let Some(reduction) = stage.strength_reduction {
            let fs = strength_reduction(
                model,
                options,
                &elements,
                &mut setup,
                &mut system,
                &dofs,
                &bar_only,
                &held,
                &mut state,
                &mut redundant,
                (stage, stage_index),
                reduction,
                sink,
            )?;
            sink.factor_of_safety(&fs)?;
            continue;
        }
        let u_start = state.u.clone();
        state.frozen_sigma_n = options.analysis.freeze_normal_stress.then(|| {
            let rows = InterfaceRows::new(model, &state.interfaces, &dofs);
            rows.springs.iter().map(|s| normal_stress(&state, &rows, s)).collect()
        });
        // Target load factors; a failed increment puts its midpoint in front.
        let mut targets: Vec<f64> = stage.load_factors.clone();
        let mut reached = 0.0;
        let mut step = 0;
        let mut cutbacks = 0;
        while let Some(&target) = targets.first() {
            let started = std::time::Instant::now();
            let snapshot = state.clone();
            for (k, f) in state.f_ext.iter_mut().enumerate() {
                *f = f_ext_start[k] + target * stage_force[k] - (1.0 - target) * unbalance[k];
            }
            for &(n, d, value) in &stage.prescribed {
                state.u[dof(n, d)] = u_start[dof(n, d)] + target * value;
            }
            let attempt = equilibrium(model, options, &elements, &setup, &mut system, &dofs, &bar_only, &mut state);
            let report = match attempt {
                Ok(report) => report,
                Err(e) => {
                    if e.retryable() && cutbacks < options.analysis.max_cutbacks {
                        state = snapshot;
                        targets.insert(0, 0.5 * (reached + target));
                        cutbacks += 1;
                        continue;
                    }
                    return Err(e.at(&model.source, &stage.name, step + 1, cutbacks));
                }
            };
            step += 1;
            let increment =
                Increment { stage, stage_index, step, load_factor: target, strength_factor: None, cutbacks, started };
            complete_increment(
                model,
                options,
                &elements,
                &mut system,
                &dofs,
                &held,
                &mut state,
                report,
                &mut redundant,
                &increment,
                sink,
            )?;
            targets.remove(0);
            reached = target;
            if stage.load_factors.iter().any(|&f| (f - target).abs() < 1e-15) {
                cutbacks = 0;
            }
        }
    }
    Ok(system.stats)
}

/// Where a converged increment sits in the run.
struct Increment<'a> {
    stage: &'a crate::model::StagePlan,
    stage_index: usize,
    step: usize,
    load_factor: f64,
    /// The strength reduction factor of a strength-reduction stage.
    strength_factor: Option<f64>,
    cutbacks: usize,
    started: Instant,
}

/// Commit a converged increment (shear states and soil stresses), hand its results to the sink, and
/// re-associate the interface points for the next one.
#[allow(clippy::too_many_arguments)]
fn complete_increment(
    model: &Model,
    options: &RunOptions,
    elements: &ElementMatrices,
    system: &mut LinearSystem,
    dofs: &DofMap,
    held: &[bool],
    state: &mut State,
    report: IncrementReport,
    redundant: &mut Vec<String>,
    at: &Increment<'_>,
    sink: &mut dyn StepSink,
) -> Result<(), Error> {
    // Commit the increment: shear states and soil stresses, then the re-association for the
    // next one.
    commit(state, &report.springs);
    soil::commit(&mut state.soil, &report.soil);
    let output_started = Instant::now();
    let rows = InterfaceRows::new(model, &state.interfaces, dofs);
    let taus: Vec<f64> = report.springs.iter().map(|r| r.tau).collect();
    let sliding: Vec<bool> = report.springs.iter().map(|r| r.sliding).collect();
    let results = StepResults::compute(model, elements, &rows, &taus, &sliding, state, &report.soil, held);
    let balance = results::reinforcement_balance(model, &results, state);
    system.stats.output_seconds += output_started.elapsed().as_secs_f64();
    let search_started = Instant::now();
    let mut reassociations = match options.analysis.reassociation {
        ReassociationRule::None => Vec::new(),
        rule => reassociate::reassociate(
            &model.mesh,
            &mut state.interfaces,
            &state.u,
            rule == ReassociationRule::NearestNode,
        ),
    };
    if options.analysis.reassociation != ReassociationRule::None {
        reassociations.extend(reassociate::uncover_slits(&model.mesh, &mut state.interfaces, &state.u));
    }
    reserve_segments(options, &mut state.interfaces);
    let redundant_now = redundant.clone();
    if options.analysis.reassociation != ReassociationRule::None {
        // new associations and clipped lengths can make two rows repeat each other (both
        // faces tied to segments ending at one soil node, at a slit tip): find them again
        *redundant = mark_redundant_rows(model, &mut state.interfaces, dofs);
    }
    system.stats.interface_seconds += search_started.elapsed().as_secs_f64();
    state.u_committed = state.u.clone();
    let record = StepRecord {
        stage: at.stage.name.clone(),
        stage_index: at.stage_index,
        step: at.step,
        load_factor: at.load_factor,
        strength_factor: at.strength_factor,
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
    sink.step_done(&results, &record, &system.stats)?;
    system.stats.output_seconds += written.elapsed().as_secs_f64();
    Ok(())
}

/// The factor of safety by strength reduction (Griffiths & Lane, Géotechnique 49 (1999) 387–403;
/// Dawson, Roth & Drescher, Géotechnique 49 (1999) 835–840): the strengths are divided by F, which
/// rises from 1 (steps of 0.1, doubling) until an increment finds no equilibrium, and the bracket
/// [F_safe, F_fail] is then halved until its width is `tolerance`·F_safe. Every F with equilibrium is
/// a step of the stage (its `strength_factor`); a trial without equilibrium is undone. The laws are
/// restored to full strength afterwards.
#[allow(clippy::too_many_arguments)]
fn strength_reduction(
    model: &Model,
    options: &RunOptions,
    elements: &ElementMatrices,
    setup: &mut soil::SoilSetup,
    system: &mut LinearSystem,
    dofs: &DofMap,
    bar_only: &[bool],
    held: &[bool],
    state: &mut State,
    redundant: &mut Vec<String>,
    (stage, stage_index): (&crate::model::StagePlan, usize),
    reduction: crate::model::StrengthReduction,
    sink: &mut dyn StepSink,
) -> Result<FactorOfSafety, Error> {
    let face_laws: Vec<crate::interface::ShearLaw> =
        state.interfaces.iter().flat_map(|i| i.faces.iter().map(|f| f.law.clone())).collect();
    let soil_laws = setup.laws.clone();
    let apply = |state: &mut State, setup: &mut soil::SoilSetup, factor: f64| {
        for (face, law) in state.interfaces.iter_mut().flat_map(|i| i.faces.iter_mut()).zip(&face_laws) {
            face.law = law.reduced(factor);
        }
        if reduction.soil {
            setup.laws = soil_laws.iter().map(|l| l.map(|l| l.reduced(factor))).collect();
        }
    };
    let (mut safe, mut failed) = (1.0f64, None::<f64>);
    let mut failure = None;
    let mut factor = 1.0;
    let mut growth = 0.1;
    let mut trials = Vec::new();
    let mut step = 0;
    loop {
        let started = Instant::now();
        let snapshot = state.clone();
        apply(state, setup, factor);
        match equilibrium(model, options, elements, setup, system, dofs, bar_only, state) {
            Ok(report) => {
                trials.push((factor, true));
                safe = factor;
                step += 1;
                let at = Increment {
                    stage,
                    stage_index,
                    step,
                    load_factor: 1.0,
                    strength_factor: Some(factor),
                    cutbacks: 0,
                    started,
                };
                complete_increment(model, options, elements, system, dofs, held, state, report, redundant, &at, sink)?;
            }
            Err(e) => {
                let ruptured = ruptured_since(model, &snapshot.bars, &state.bars);
                if failed.is_none_or(|f| factor < f) {
                    failure = Some(match ruptured.is_empty() {
                        true => e.describe(),
                        false => {
                            format!("{}; reinforcement ruptured on the way: {}", e.describe(), ruptured.join(", "))
                        }
                    });
                }
                *state = snapshot;
                if factor == 1.0 {
                    // not even the full strengths hold the model: that is a failure of the stages
                    // before, not a factor of safety
                    apply(state, setup, 1.0);
                    return Err(e.at(&model.source, &stage.name, 1, 0));
                }
                trials.push((factor, false));
                failed = Some(factor);
            }
        }
        factor = match failed {
            Some(f) if f - safe <= reduction.tolerance * safe => break,
            Some(f) => 0.5 * (safe + f),
            None if safe >= reduction.max_factor => break,
            None => {
                let next = (safe + growth).min(reduction.max_factor);
                growth *= 2.0;
                next
            }
        };
    }
    apply(state, setup, 1.0);
    Ok(FactorOfSafety {
        stage: stage.name.clone(),
        value: safe,
        failed_at: failed,
        reduced: if reduction.soil { "soil and interfaces" } else { "interfaces" },
        trials,
        failure,
    })
}

/// Bars ruptured in `after` and not in `before`, counted per reinforcement material.
fn ruptured_since(model: &Model, before: &system::BarStates, after: &system::BarStates) -> Vec<String> {
    let mut counts: Vec<(String, usize)> = Vec::new();
    for (i, bar) in model.mesh.bars.iter().enumerate() {
        if after.ruptured[i] && !before.ruptured[i] {
            let name = &model.reinforcements[bar.material].0;
            match counts.iter_mut().find(|(n, _)| n == name) {
                Some(c) => c.1 += 1,
                None => counts.push((name.clone(), 1)),
            }
        }
    }
    counts.into_iter().map(|(n, c)| format!("{c} bars of {n}")).collect()
}

/// Reserve master segments around every interface point (see `AnalysisSettings::reserved_segments`).
fn reserve_segments(options: &RunOptions, interfaces: &mut [Interface]) {
    if options.analysis.reassociation != ReassociationRule::None && options.analysis.reserved_segments > 0 {
        crate::interface::reserve_windows(interfaces, options.analysis.reserved_segments);
    }
}

/// Nodes of present soil elements and of placed bars, and nodes of neither (a rigid base).
fn placed_nodes(model: &Model, field: &soil::SoilField, bars: &system::BarStates) -> Vec<bool> {
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

/// Whether a point (its node and its master segment) is in place (see `State::placed`).
fn in_place(placed: &[bool], face: &crate::interface::ContactFace, point: &crate::interface::ContactPoint) -> bool {
    placed.is_empty()
        || (placed[point.slave]
            && face.master[point.segment..=(point.segment + 1).min(face.master.len() - 1)].iter().all(|&n| placed[n]))
}

/// Contacts as a stage places and removes soil and reinforcement. A point not in place, or whose
/// master segment is not (a reinforcement still to be laid; a liner under cover soil still to come,
/// or soil excavated off it), is released: it would bear on nodes held where they were. A point that
/// this stage puts in place (a sheet laid on the ground, soil placed on it) starts in contact.
fn place_contacts(state: &mut State, placed_before: &[bool]) {
    let multipliers = crate::dofs::multipliers(&state.interfaces);
    for (k, m) in multipliers.iter().enumerate() {
        let face = &state.interfaces[m.interface].faces[m.face];
        if m.tangential || state.interfaces[m.interface].slit_of.is_some() || state.interfaces[m.interface].is_tie() {
            continue;
        }
        let point = &face.points[m.point];
        let now = in_place(&state.placed, face, point);
        let before = !placed_before.is_empty() && in_place(placed_before, face, point);
        let point = &mut state.interfaces[m.interface].faces[m.face].points[m.point];
        match (before, now, &point.normal_state) {
            (_, false, NormalState::Active) => {
                point.normal_state = NormalState::Released;
                state.lambda[k] = 0.0;
            }
            (false, true, NormalState::Released | NormalState::Held { outside: false }) => {
                // laid now: its slip and shear count from here
                point.normal_state = NormalState::Active;
                point.shear = Default::default();
            }
            _ => {}
        }
    }
}

/// `held` plus both DOFs of every node whose soil elements are all absent (and that no bar uses).
fn with_absent_nodes(model: &Model, field: &soil::SoilField, bars: &system::BarStates, held: &[bool]) -> Vec<bool> {
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
fn stage_unbalance(
    model: &Model,
    setup: &soil::SoilSetup,
    elements: &ElementMatrices,
    dofs: &DofMap,
    state: &State,
) -> Vec<f64> {
    let rows = InterfaceRows::new(model, &state.interfaces, dofs);
    let springs = evaluate_springs(state, &rows);
    let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
    let trial = soil::evaluate(setup, &state.soil, &state.u, &state.u_committed, soil::Tangent::Elastic);
    let view = SoilView { field: &state.soil, trial: &trial };
    let f_int = system::internal_force(elements, view, &rows, &taus, &state.bars, &state.u);
    let f_c = system::constraint_force(&rows, &state.lambda, state.u.len());
    (0..state.u.len())
        .map(|d| if dofs.equation[d].is_some() { state.f_ext[d] - f_int[d] - f_c[d] } else { 0.0 })
        .collect()
}

fn dof(n: usize, d: Direction) -> usize {
    2 * n + if d == Direction::X { 0 } else { 1 }
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

/// Store each spring's converged law state in its point.
fn commit(state: &mut State, springs: &[SpringResult]) {
    for r in springs {
        state.interfaces[r.interface].faces[r.face].points[r.point].shear = r.response.state.clone();
    }
}

/// Consistent nodal forces of a list of loads (full load, factor 1), but for gravity, whose force
/// comes from [`soil::weight`].
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
            // the soil's weight depends on which soil is present and where the water is: see
            // `soil::weight`
            Load::Gravity { .. } => {}
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
    // the rows already kept, per slave node: (multiplier, free part of its row)
    type KeptRows = Vec<(usize, Vec<(usize, f64)>)>;
    let mut by_slave: HashMap<usize, KeptRows> = HashMap::new();
    let mut report = Vec::new();
    for (k, row) in rows.constraint_rows.iter().enumerate() {
        let m = dofs.multipliers[k];
        let current = {
            let p = &interfaces[m.interface].faces[m.face].points[m.point];
            if m.tangential {
                &p.tangential_state
            } else {
                &p.normal_state
            }
        };
        if !matches!(current, NormalState::Active | NormalState::Redundant { .. }) {
            continue; // released, held, covered or outside rows carry nothing to repeat
        }
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
            Some(("the supports (every DOF of the row is held)".to_string(), None))
        } else {
            let scale = free[0].1;
            let key: Vec<(usize, i64)> = free.iter().map(|&(e, c)| (e, (c / scale * 1e9).round() as i64)).collect();
            // Rows of the same slave node that are nearly parallel (both faces of a reinforcement
            // tied to segments that end at the same soil node, as at a slit tip) make the system
            // singular or ill-conditioned: the later one is carried by the earlier one.
            let slave = interfaces[m.interface].faces[m.face].points[m.point].slave;
            let near = by_slave.get(&slave).and_then(|earlier: &KeptRows| {
                earlier.iter().find(|(_, other)| nearly_parallel(&free, other)).map(|(j, _)| *j)
            });
            let tip = interfaces[m.interface].faces[m.face].points[m.point].slit_tip && !m.tangential;
            let tip_partner = if tip { by_slave.get(&slave).and_then(|e| e.first()).map(|(j, _)| *j) } else { None };
            match seen.get(&key).copied().or(near).or(tip_partner) {
                Some(first) => Some((name(interfaces, first), Some(first))),
                // a stack's tail inside the soil: the lower face's row there is the sum of the
                // upper face's and the rows between the layers, which carry it together
                None if tip && interfaces[m.interface].faces.len() > 2 => {
                    Some(("the other faces of the stack at the slit tip".to_string(), None))
                }
                None => {
                    seen.insert(key, k);
                    by_slave.entry(slave).or_default().push((k, free.clone()));
                    None
                }
            }
        };
        let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
        let state = if m.tangential { &mut point.tangential_state } else { &mut point.normal_state };
        match carried_by {
            Some((by, multiplier)) => {
                report.push(format!(
                    "{} ({}): carried by {by}",
                    name(interfaces, k),
                    if m.tangential { "tangential" } else { "normal" }
                ));
                let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
                let state = if m.tangential { &mut point.tangential_state } else { &mut point.normal_state };
                *state = NormalState::Redundant { carried_by: by, multiplier };
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

/// Whether two sparse rows (sorted by equation) are parallel or antiparallel to within an angle of
/// about 10⁻³ rad (|cos| > 1 − 5·10⁻⁷).
fn nearly_parallel(a: &[(usize, f64)], b: &[(usize, f64)]) -> bool {
    let norm = |r: &[(usize, f64)]| r.iter().map(|(_, c)| c * c).sum::<f64>().sqrt();
    let (na, nb) = (norm(a), norm(b));
    if na == 0.0 || nb == 0.0 {
        return false;
    }
    let mut dot = 0.0;
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].0.cmp(&b[j].0) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                dot += a[i].1 * b[j].1;
                i += 1;
                j += 1;
            }
        }
    }
    (dot / (na * nb)).abs() > 1.0 - 5e-7
}

/// Why an increment failed, before the stage and step are known.
enum IncrementError {
    Solve(SolveError),
    NotConverged { iterations: usize, residual: f64, reference: f64, unsettled: Vec<String>, yielding: usize },
}

impl IncrementError {
    /// One line on how the increment failed.
    fn describe(&self) -> String {
        match self {
            IncrementError::Solve(e) => format!("the solve failed: {e}"),
            IncrementError::NotConverged { iterations, residual, reference, unsettled, yielding } => {
                let mut s = format!(
                    "no equilibrium after {iterations} iterations (force residual {:.1e} of the reference)",
                    residual / reference
                );
                if !unsettled.is_empty() {
                    s += &format!("; {} interface points kept changing state", unsettled.len());
                }
                if *yielding > 0 {
                    s += &format!("; {yielding} soil Gauss points on the yield surface");
                }
                s
            }
        }
    }

    /// A failure that a smaller increment may cure.
    fn retryable(&self) -> bool {
        matches!(self, IncrementError::NotConverged { .. })
    }

    fn at(self, file: &std::path::Path, stage: &str, step: usize, cutbacks: usize) -> Error {
        match self {
            IncrementError::Solve(source) => {
                Error::Solve { file: file.to_path_buf(), stage: stage.to_string(), step, source }
            }
            IncrementError::NotConverged { iterations, residual, reference, unsettled, yielding } => Error::NotConverged {
                file: file.to_path_buf(),
                stage: stage.to_string(),
                step,
                iterations,
                residual,
                reference,
                hint: format!(
                    "after {cutbacks} cutbacks. {}{}Try more load factors in this stage, a larger max_iterations, or the newton scheme",
                    if unsettled.is_empty() {
                        String::new()
                    } else {
                        format!("Interface points that kept changing state: {}. ", cap(unsettled).join("; "))
                    },
                    if yielding > 0 {
                        format!(
                            "{yielding} soil Gauss points were on the yield surface at the last iteration: the soil may be \
                             collapsing (a limit load reached). "
                        )
                    } else {
                        String::new()
                    }
                ),
            },
        }
    }
}

/// One spring's law evaluated at the current iterate.
#[derive(Debug, Clone)]
pub struct SpringResult {
    pub interface: usize,
    pub face: usize,
    pub point: usize,
    pub response: ShearResponse,
    pub tau: f64,
    pub sigma_n: f64,
    pub sliding: bool,
}

/// A converged increment.
struct IncrementReport {
    iterations: usize,
    force_residual: f64,
    linear_residuals: Vec<f64>,
    springs: Vec<SpringResult>,
    state_changes: Vec<String>,
    /// The soil's Gauss-point states at equilibrium.
    soil: soil::SoilTrial,
}

/// σn = λ/ℓ of a spring's point (compression positive); a redundant row's force is carried by
/// another row, whose σn it shares.
fn normal_stress(state: &State, rows: &InterfaceRows, spring: &system::Spring) -> f64 {
    let p = &state.interfaces[spring.interface].faces[spring.face].points[spring.point];
    match &p.normal_state {
        NormalState::Active => state.lambda[spring.normal_multiplier] / spring.tributary.max(f64::MIN_POSITIVE),
        NormalState::Redundant { multiplier: Some(carrier), .. } => {
            let owner = rows.springs.iter().find(|s| s.normal_multiplier == *carrier);
            let l = owner.map(|s| s.tributary).unwrap_or(spring.tributary).max(f64::MIN_POSITIVE);
            state.lambda[*carrier].abs() / l
        }
        _ => 0.0,
    }
}

/// Evaluate every spring's law at the current displacements.
fn evaluate_springs(state: &State, rows: &InterfaceRows) -> Vec<SpringResult> {
    rows.springs
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let interface = &state.interfaces[s.interface];
            let p = &interface.faces[s.face].points[s.point];
            let slip_increment: f64 = s.row.iter().map(|&(d, c)| c * (state.u[d] - state.u_committed[d])).sum();
            let slip = p.shear.slip + slip_increment;
            let sigma_n = match &state.frozen_sigma_n {
                Some(frozen) => frozen.get(k).copied().unwrap_or(0.0),
                None => normal_stress(state, rows, s),
            };
            // the strength acts on the effective normal stress σn′ = σn − p
            let sigma_n = match &state.soil.water {
                Some(w) => {
                    let at = [s.position[0] + state.u[2 * s.slave], s.position[1] + state.u[2 * s.slave + 1]];
                    sigma_n - w.pressure(at)
                }
                None => sigma_n,
            };
            let response = if p.in_contact() {
                interface.faces[s.face].law.response(&p.shear, slip, sigma_n)
            } else {
                // Out of contact: no shear; the slip goes on accumulating and restarts elastic.
                let mut st = p.shear.clone();
                st.slip = slip;
                st.plastic_slip = slip;
                st.tau = 0.0;
                ShearResponse { tau: 0.0, tangent: 0.0, d_tau_d_sigma: 0.0, state: st, sliding: false }
            };
            SpringResult {
                interface: s.interface,
                face: s.face,
                point: s.point,
                tau: response.tau,
                sliding: response.sliding,
                sigma_n,
                response,
            }
        })
        .collect()
}

/// Iterate one increment to equilibrium.
#[allow(clippy::too_many_arguments)]
fn equilibrium(
    model: &Model,
    options: &RunOptions,
    elements: &ElementMatrices,
    setup: &soil::SoilSetup,
    system: &mut LinearSystem,
    dofs: &DofMap,
    bar_only: &[bool],
    state: &mut State,
) -> Result<IncrementReport, IncrementError> {
    let u_increment_start = state.u.clone();
    let mut linear_residuals = Vec::new();
    let mut flips: HashMap<usize, usize> = HashMap::new();
    let mut state_changes = Vec::new();
    let characteristic = model.mesh.characteristic_length();
    let mut kept_stiffness: Option<(Vec<bool>, Vec<f64>)> = None;
    let mut matrix_key: Option<u64> = None;
    let mut dependent_retries = 0;
    let mut soil_tangent = match options.analysis.scheme {
        Scheme::Newton => soil::Tangent::Consistent,
        Scheme::NewtonSymmetric => soil::Tangent::Symmetric,
        Scheme::ConstantStiffness => soil::Tangent::Elastic,
    };
    let mut carried_soil: Option<soil::SoilTrial> = None;
    // Sliding points' springs on Ks instead of their zero plastic tangent (see the singular case)
    let mut elastic_springs = false;
    for iteration in 1..=options.analysis.max_iterations {
        system.stats.iterations += 1;
        let t = Instant::now();
        if options.analysis.reassociation != ReassociationRule::None {
            reassociate::clip_tributaries(&model.mesh, &mut state.interfaces, &state.u);
        }
        state_changes.extend(hold_free_reinforcement_nodes(model, state, dofs, bar_only));
        let rows = InterfaceRows::new(model, &state.interfaces, dofs);
        let springs = evaluate_springs(state, &rows);
        // The first iteration of an increment predicts with the elastic soil stiffness: prescribed
        // displacements strain only the elements next to them at first, and their tangent would
        // say nothing about the rest.
        let tangent = if iteration == 1 { soil::Tangent::Elastic } else { soil_tangent };
        // The soil at this iterate was evaluated (with this tangent) to check the last iteration's
        // residual: nothing since has moved the displacements.
        let soil_trial = match carried_soil.take() {
            Some(trial) => trial,
            None => soil::evaluate(setup, &state.soil, &state.u, &state.u_committed, tangent),
        };
        // Constant stiffness (the paper's Fig. 3): Ks·ℓ as the increment found it, kept while the
        // contact states stay, so the factorisation is reused and each iteration costs one solve.
        // Newton: the law's tangent at the current iterate.
        let contact: Vec<bool> = rows
            .springs
            .iter()
            .map(|s| state.interfaces[s.interface].faces[s.face].points[s.point].in_contact())
            .collect();
        let keep = options.analysis.scheme == Scheme::ConstantStiffness
            && kept_stiffness.as_ref().is_some_and(|(c, _)| *c == contact);
        if !keep {
            let stiffness: Vec<f64> = rows
                .springs
                .iter()
                .zip(&springs)
                .zip(&contact)
                .map(|((s, r), &in_contact)| {
                    if !in_contact {
                        return 0.0;
                    }
                    let ks = state.interfaces[s.interface].faces[s.face].law.shear_stiffness().unwrap_or(0.0);
                    let k = match options.analysis.scheme {
                        Scheme::ConstantStiffness => ks,
                        Scheme::Newton | Scheme::NewtonSymmetric if elastic_springs => ks,
                        Scheme::Newton | Scheme::NewtonSymmetric => r.response.tangent.max(0.0),
                    };
                    k * s.tributary
                })
                .collect();
            kept_stiffness = Some((contact, stiffness));
        }
        let stiffness = &kept_stiffness.as_ref().expect("set above").1;
        // the consistent tangent couples each sliding point's shear to its normal multiplier
        let coupling: Option<Vec<f64>> = (options.analysis.scheme == Scheme::Newton && state.frozen_sigma_n.is_none())
            .then(|| {
                rows.springs
                    .iter()
                    .zip(&springs)
                    .map(|(s, r)| {
                        let p = &state.interfaces[s.interface].faces[s.face].points[s.point];
                        if matches!(p.normal_state, NormalState::Active) {
                            r.response.d_tau_d_sigma
                        } else {
                            0.0
                        }
                    })
                    .collect()
            });
        let key = system::matrix_key(
            SoilView { field: &state.soil, trial: &soil_trial },
            &rows,
            stiffness,
            coupling.as_deref(),
            &state.bars,
            &state.interfaces,
            dofs,
            elements.typical_stiffness(),
        );
        system.stats.interface_seconds += t.elapsed().as_secs_f64();
        // The matrix of the last solve, when nothing in it changed (constant stiffness, no state
        // change): no assembly, no factorisation, one solve.
        let t = Instant::now();
        let reuse = matrix_key == Some(key);
        let build = |with_matrix: bool| {
            iteration_system(
                elements,
                &soil_trial,
                &rows,
                &springs,
                stiffness,
                coupling.as_deref(),
                dofs,
                state,
                with_matrix,
            )
        };
        let IterationSystem { triplets, rhs, scale, active } = build(!reuse);
        system.stats.assembly_seconds += t.elapsed().as_secs_f64();
        let reused = if reuse { system.solve_again(&rhs).ok() } else { None };
        let triplets = match reused {
            Some(_) => triplets,
            None if reuse => {
                // the reused factorisation did not give a clean solution: assemble and factorise
                let t = Instant::now();
                let again = build(true);
                system.stats.assembly_seconds += t.elapsed().as_secs_f64();
                again.triplets
            }
            None => triplets,
        };
        matrix_key = Some(key);
        let (x, lin_res) = match reused.map_or_else(|| system.solve(dofs.size(), &triplets, &rhs, active), Ok) {
            Ok(v) => v,
            Err(Failure::Singular { .. }) if !elastic_springs && springs.iter().any(|r| r.sliding) => {
                // Sliding points have no shear stiffness; where they are all that holds a node along
                // the interface (a tension-only sheet gone slack, under no normal stress, as a liner
                // laid before its cover) the tangent is singular though the forces balance: the
                // rest of the increment iterates with Ks on the sliding points.
                elastic_springs = true;
                matrix_key = None;
                let w = "the tangent with sliding interface points was singular in some increments (a slack \
                         reinforcement held only by sliding points); they continued with Ks on those points"
                    .to_string();
                if !system.stats.warnings.contains(&w) {
                    system.stats.warnings.push(w);
                }
                continue;
            }
            Err(Failure::Singular { .. }) if soil_trial.tangents.iter().any(|t| t.is_some()) => {
                // Yielded soil can leave the consistent tangent singular (a local mechanism of
                // perfectly plastic Gauss points, as at a footing edge) where the structure itself
                // is not: the rest of the increment iterates on the elastic soil stiffness.
                soil_tangent = soil::Tangent::Elastic;
                matrix_key = None;
                let w = "the consistent tangent of the yielded soil was singular in some increments; they \
                         continued on the elastic soil stiffness"
                    .to_string();
                if !system.stats.warnings.contains(&w) {
                    system.stats.warnings.push(w);
                }
                continue;
            }
            Err(Failure::Singular { equations }) => {
                // Normal rows that depend on other rows (after a re-association, two reinforcement
                // nodes tied to the same pair of soil nodes) are set aside, reported, and the
                // iteration retried; anything else is a mechanism of the model.
                let null = null_equations(&triplets, dofs.size(), equations.clone()).unwrap_or_default();
                let rows: Vec<usize> = null
                    .iter()
                    .filter_map(|&e| e.checked_sub(dofs.free_count))
                    .filter(|&k| !dofs.multipliers[k].tangential)
                    .collect();
                if !null.is_empty() && rows.len() == null.len() && dependent_retries < 8 {
                    dependent_retries += 1;
                    for k in rows {
                        let m = dofs.multipliers[k];
                        let name = multiplier_name(model, &state.interfaces, dofs, k);
                        state.interfaces[m.interface].faces[m.face].points[m.point].normal_state =
                            NormalState::Redundant {
                                carried_by: "the other constraint rows on the same soil nodes (it depends on them)"
                                    .into(),
                                multiplier: None,
                            };
                        state.lambda[k] = 0.0;
                        state_changes.push(format!("{name}: set aside, it depends on other constraint rows"));
                    }
                    continue;
                }
                return Err(IncrementError::Solve(SolveError::Singular {
                    backend: system.backend().name(),
                    unknowns: diagnose_singular(model, &state.interfaces, dofs, &triplets, equations),
                }));
            }
            Err(Failure::Other(e)) => return Err(IncrementError::Solve(e)),
        };
        linear_residuals.push(lin_res);
        let step = if soil_trial.yielding > 0 && tangent != soil::Tangent::Elastic {
            line_search(elements, setup, dofs, state, &rows, &x, scale, &rhs[..dofs.free_count])
        } else {
            1.0
        };
        let mut correction2 = 0.0f64;
        for (d, eq) in dofs.equation.iter().enumerate() {
            if let Some(e) = eq {
                state.u[d] += step * x[*e];
                correction2 += (step * x[*e]).powi(2);
            }
        }
        for k in 0..dofs.multipliers.len() {
            state.lambda[k] += step * scale * x[dofs.multiplier_equation(k)];
        }
        let t = Instant::now();
        if options.analysis.reassociation != ReassociationRule::None {
            reassociate::clip_tributaries(&model.mesh, &mut state.interfaces, &state.u);
        }
        let rows = InterfaceRows::new(model, &state.interfaces, dofs);
        let springs = evaluate_springs(state, &rows);
        let force_floor = state
            .f_ext
            .iter()
            .fold(0.0f64, |m, f| m.max(f.abs()))
            .max(1e-6 * elements.typical_stiffness() * characteristic);
        let mut changes =
            update_active_set(model, state, &rows, dofs, bar_only, characteristic, force_floor, &mut flips);
        changes.extend(rupture_bars(elements, state));
        system.stats.interface_seconds += t.elapsed().as_secs_f64();
        state_changes.extend(changes.iter().cloned());
        // Converged when the out-of-balance force is small, the gaps are closed, no point changed
        // state, and either the correction is small against the increment or this was the first
        // solve (a first solve that already balances the forces had a linear increment).
        // (or against the displacements so far, for an increment that moves almost nothing, as a
        // strength-reduction trial at F = 1, while slack sheets under no normal stress drift along
        // themselves without changing any force)
        let increment2: f64 = state.u.iter().zip(&u_increment_start).map(|(a, b)| (a - b).powi(2)).sum();
        let total2: f64 = state.u.iter().map(|a| a * a).sum();
        let displacement_ok = iteration == 1
            || correction2.sqrt()
                <= options.analysis.displacement_tolerance
                    * increment2.sqrt().max(total2.sqrt()).max(f64::MIN_POSITIVE);
        let t = Instant::now();
        let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
        // with the tangent the next iteration assembles (the forces do not depend on it)
        let soil_trial = soil::evaluate(setup, &state.soil, &state.u, &state.u_committed, soil_tangent);
        let (residual, reference) = out_of_balance(elements, &soil_trial, &rows, &taus, state, dofs);
        system.stats.residual_seconds += t.elapsed().as_secs_f64();
        if !residual.is_finite() {
            return Err(IncrementError::NotConverged {
                iterations: iteration,
                residual,
                reference,
                unsettled: Vec::new(),
                yielding: soil_trial.yielding,
            });
        }
        let gaps = rows.gaps(&state.u);
        let floor = system::round_off_floor(elements, SoilView { field: &state.soil, trial: &soil_trial }, &state.u);
        if changes.is_empty()
            && residual <= (options.analysis.force_tolerance * reference).max(floor)
            && gaps_closed(&gaps, state, dofs, characteristic)
            && displacement_ok
        {
            return Ok(IncrementReport {
                iterations: iteration,
                force_residual: residual / reference,
                linear_residuals,
                springs,
                state_changes,
                soil: soil_trial,
            });
        }
        if iteration == options.analysis.max_iterations {
            let mut unsettled: Vec<(usize, usize)> = flips.into_iter().filter(|&(_, n)| n > 1).collect();
            unsettled.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
            let unsettled = unsettled
                .into_iter()
                .map(|(k, n)| format!("{} ({n} changes)", multiplier_name(model, &state.interfaces, dofs, k)))
                .collect();
            let yielding = soil_trial.yielding;
            return Err(IncrementError::NotConverged {
                iterations: iteration,
                residual,
                reference,
                unsettled,
                yielding,
            });
        }
        carried_soil = Some(soil_trial);
    }
    Err(IncrementError::NotConverged {
        iterations: 0,
        residual: f64::NAN,
        reference: f64::NAN,
        unsettled: Vec::new(),
        yielding: 0,
    })
}

/// A backtracking line search on the Newton correction of yielding soil: the step is halved (at
/// most five times) while the out-of-balance force on the free DOFs would grow. Perfectly plastic
/// Gauss points make the consistent tangent nearly singular where a mechanism is forming, and a
/// full step can then overshoot far (Crisfield, Non-linear Finite Element Analysis of Solids and
/// Structures, vol. 1 (1991) §9.3).
#[allow(clippy::too_many_arguments)]
fn line_search(
    elements: &ElementMatrices,
    setup: &soil::SoilSetup,
    dofs: &DofMap,
    state: &State,
    rows: &InterfaceRows,
    x: &[f64],
    scale: f64,
    before: &[f64],
) -> f64 {
    let r0: f64 = before.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut trial = state.clone();
    let mut step = 1.0;
    for _ in 0..6 {
        for (d, eq) in dofs.equation.iter().enumerate() {
            if let Some(e) = eq {
                trial.u[d] = state.u[d] + step * x[*e];
            }
        }
        for k in 0..dofs.multipliers.len() {
            trial.lambda[k] = state.lambda[k] + step * scale * x[dofs.multiplier_equation(k)];
        }
        let springs = evaluate_springs(&trial, rows);
        let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
        let soil_trial = soil::evaluate(setup, &trial.soil, &trial.u, &trial.u_committed, soil::Tangent::Elastic);
        let (r, _) = out_of_balance(elements, &soil_trial, rows, &taus, &trial, dofs);
        if r <= r0 || step < 0.05 {
            break;
        }
        step *= 0.5;
    }
    step
}

fn multiplier_name(model: &Model, interfaces: &[Interface], dofs: &DofMap, k: usize) -> String {
    let m = dofs.multipliers[k];
    let i = &interfaces[m.interface];
    let f = &i.faces[m.face];
    format!("interface \"{}\" {} face at node {}", i.name, f.label, model.mesh.node_id(f.points[m.point].slave))
}

/// Bars whose tension passed their rupture strength break: they carry nothing from then on.
fn rupture_bars(elements: &ElementMatrices, state: &mut State) -> Vec<String> {
    let mut changes = Vec::new();
    for (i, bar) in elements.bars.iter().enumerate() {
        let Some(t_ult) = bar.rupture_strength else { continue };
        if state.bars.idle(i) {
            continue;
        }
        let t = bar.elastic_force(&state.u, &elements.blocks[bar.block].0, state.bars.stretch0(i));
        if t > t_ult {
            state.bars.ruptured[i] = true;
            changes.push(format!("bar {} ruptured: T = {t:.4} > T_ult = {t_ult}", bar.id));
        }
    }
    changes
}

/// How many state changes of one point an increment allows before the point is kept in contact.
const CHATTER_LIMIT: usize = 4;

/// Release rows whose λ turned tensile, re-activate released rows whose gap closed, and hold the
/// transverse DOF of a reinforcement node whose faces are all open (a 2-node bar has no transverse
/// stiffness). Returns what changed.
#[allow(clippy::too_many_arguments)]
fn update_active_set(
    model: &Model,
    state: &mut State,
    rows: &InterfaceRows,
    dofs: &DofMap,
    bar_only: &[bool],
    characteristic: f64,
    force_floor: f64,
    flips: &mut HashMap<usize, usize>,
) -> Vec<String> {
    let gaps = rows.gaps(&state.u);
    // The scale of a contact force: the largest multiplier, but never below the applied forces or
    // a force that moves the soil by 10⁻⁶ of its size, so that multipliers that are zero up to
    // round-off (a reinforcement turned off the axes, pulled along itself) are not taken for tension.
    let lambda_scale = state.lambda.iter().fold(0.0f64, |m, l| m.max(l.abs())).max(force_floor).max(f64::MIN_POSITIVE);
    // Hysteresis bands: a row is released only when clearly tensile, re-activated only when the
    // faces clearly overlap, so states do not ping-pong on round-off.
    let release_below = -1e-4 * lambda_scale;
    let close_above = 1e-6 * characteristic;
    let mut changes = Vec::new();
    for (k, m) in dofs.multipliers.iter().enumerate() {
        if m.tangential || state.interfaces[m.interface].is_tie() {
            continue;
        }
        let placed = {
            let face = &state.interfaces[m.interface].faces[m.face];
            in_place(&state.placed, face, &face.points[m.point])
        };
        let p = &mut state.interfaces[m.interface].faces[m.face].points[m.point];
        // A point that has already switched CHATTER_LIMIT times in this increment stays in contact:
        // its λ is then slightly tensile at most, and it is reported.
        let locked = flips.get(&k).is_some_and(|&n| n >= CHATTER_LIMIT);
        let new = match p.normal_state {
            NormalState::Active if state.lambda[k] < release_below && !locked => Some(NormalState::Released),
            NormalState::Released | NormalState::Held { outside: false } if gaps[k] > close_above && placed => {
                Some(NormalState::Active)
            }
            // a row holding a sheet's node that pushes it as contact would (a layer above presses
            // it onto this face): the contact is back
            NormalState::Held { outside: false } if state.lambda[k] > -release_below && placed => {
                Some(NormalState::Active)
            }
            _ => None,
        };
        if let Some(new) = new {
            let what =
                if matches!(new, NormalState::Active) { "re-activated (gap closed)" } else { "released (tension)" };
            p.normal_state = new;
            *flips.entry(k).or_default() += 1;
            changes.push(format!("{} {what}", multiplier_name(model, &state.interfaces, dofs, k)));
            if !matches!(state.interfaces[m.interface].faces[m.face].points[m.point].normal_state, NormalState::Active)
            {
                state.lambda[k] = 0.0;
            }
        }
    }
    changes.extend(hold_free_reinforcement_nodes(model, state, dofs, bar_only));
    changes
}

/// A reinforcement node with no active normal row (every face open, or the node out of the soil)
/// keeps its transverse position through one of its rows (held), and gives it back when another row
/// becomes active. Returns what changed.
fn hold_free_reinforcement_nodes(model: &Model, state: &mut State, dofs: &DofMap, bar_only: &[bool]) -> Vec<String> {
    let mut changes = Vec::new();
    let mut by_slave: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, m) in dofs.multipliers.iter().enumerate() {
        if !m.tangential {
            let slave = state.interfaces[m.interface].faces[m.face].points[m.point].slave;
            by_slave.entry(slave).or_default().push(k);
        }
    }
    let mut slaves: Vec<_> = by_slave.into_iter().collect();
    slaves.sort_by_key(|(s, _)| *s);
    for (slave, ks) in slaves {
        // a node not yet placed is held where it is anyway
        if !bar_only[slave] || (dofs.equation[2 * slave].is_none() && dofs.equation[2 * slave + 1].is_none()) {
            continue;
        }
        let st = |k: usize| {
            let m = dofs.multipliers[k];
            state.interfaces[m.interface].faces[m.face].points[m.point].normal_state.clone()
        };
        // a row carried by another counts only while its carrier holds (a carrier released in
        // tension leaves the node free)
        let holds = |k: usize| match st(k) {
            NormalState::Active => true,
            NormalState::Redundant { multiplier: Some(carrier), .. } => matches!(st(carrier), NormalState::Active),
            NormalState::Redundant { multiplier: None, .. } => true,
            _ => false,
        };
        let any_active = ks.iter().any(|&k| holds(k));
        let held: Vec<usize> = ks.iter().copied().filter(|&k| matches!(st(k), NormalState::Held { .. })).collect();
        if !any_active && held.is_empty() {
            if let Some(&k) = ks.iter().find(|&&k| matches!(st(k), NormalState::Released | NormalState::Outside)) {
                let m = dofs.multipliers[k];
                let outside = matches!(st(k), NormalState::Outside);
                state.interfaces[m.interface].faces[m.face].points[m.point].normal_state =
                    NormalState::Held { outside };
                changes.push(format!(
                    "node {} transverse DOF held ({})",
                    model.mesh.node_id(slave),
                    if outside { "it has left the soil" } else { "every face of the reinforcement is open there" }
                ));
            }
        } else if any_active {
            for k in held {
                let m = dofs.multipliers[k];
                let point = &mut state.interfaces[m.interface].faces[m.face].points[m.point];
                point.normal_state = match point.normal_state {
                    NormalState::Held { outside: true } => NormalState::Outside,
                    _ => NormalState::Released,
                };
                state.lambda[k] = 0.0;
            }
        }
    }
    changes
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
/// DOFs, −g on active rows (no transverse motion on held rows), −λ on the rest.
#[allow(clippy::too_many_arguments)]
fn iteration_system(
    elements: &ElementMatrices,
    soil_trial: &soil::SoilTrial,
    rows: &InterfaceRows,
    springs: &[SpringResult],
    spring_stiffness: &[f64],
    spring_coupling: Option<&[f64]>,
    dofs: &DofMap,
    state: &State,
    with_matrix: bool,
) -> IterationSystem {
    let n_dof = state.u.len();
    let gaps = rows.gaps(&state.u);
    let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
    let view = SoilView { field: &state.soil, trial: soil_trial };
    let f_int = system::internal_force(elements, view, rows, &taus, &state.bars, &state.u);
    let f_c = system::constraint_force(rows, &state.lambda, n_dof);
    let mut rhs = vec![0.0; dofs.size()];
    for (d, eq) in dofs.equation.iter().enumerate() {
        if let Some(e) = eq {
            rhs[*e] = state.f_ext[d] - f_int[d] - f_c[d];
        }
    }
    let scale = elements.typical_stiffness();
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
        } else if system::multiplier_is_active(&state.interfaces, dofs, k) {
            active += 1;
            -scale * gaps[k]
        } else {
            -state.lambda[k]
        };
    }
    let triplets = if with_matrix {
        system::assemble(
            elements,
            view,
            rows,
            spring_stiffness,
            spring_coupling,
            &state.bars,
            &state.interfaces,
            dofs,
            scale,
        )
    } else {
        crate::assembly::Triplets::default()
    };
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
    let state = State {
        u,
        lambda: vec![0.0; dofs.multipliers.len()],
        interfaces,
        f_ext,
        u_committed: vec![0.0; dof_count],
        frozen_sigma_n: None,
        bars: system::BarStates::new(model.mesh.bars.len()),
        soil: soil::initial_field(model),
        placed: Vec::new(),
    };
    let rows = InterfaceRows::new(model, &state.interfaces, &dofs);
    let springs = evaluate_springs(&state, &rows);
    let soil_trial = soil::SoilTrial::default();
    let stiffness: Vec<f64> = rows
        .springs
        .iter()
        .map(|s| state.interfaces[s.interface].faces[s.face].law.shear_stiffness().unwrap_or(0.0) * s.tributary)
        .collect();
    (dofs.size(), iteration_system(&elements, &soil_trial, &rows, &springs, &stiffness, None, &dofs, &state, true))
}

/// ‖out-of-balance force on the free DOFs‖ and the reference force (applied loads and reactions).
fn out_of_balance(
    elements: &ElementMatrices,
    soil_trial: &soil::SoilTrial,
    rows: &InterfaceRows,
    taus: &[f64],
    state: &State,
    dofs: &DofMap,
) -> (f64, f64) {
    let n_dof = state.u.len();
    let view = SoilView { field: &state.soil, trial: soil_trial };
    let f_int = system::internal_force(elements, view, rows, taus, &state.bars, &state.u);
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

fn gaps_closed(gaps: &[f64], state: &State, dofs: &DofMap, characteristic: f64) -> bool {
    let scale = state.u.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-6 * characteristic);
    gaps.iter().enumerate().all(|(k, g)| {
        let m = dofs.multipliers[k];
        let held = !m.tangential
            && matches!(
                state.interfaces[m.interface].faces[m.face].points[m.point].normal_state,
                NormalState::Held { .. }
            );
        held || !system::multiplier_is_active(&state.interfaces, dofs, k) || g.abs() <= 1e-9 * scale
    })
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
    let column_norm = column_norms(triplets, n);
    let describe = |e: usize| {
        let name = dofs.describe(e, &model.mesh, interfaces);
        if column_norm.get(e).is_some_and(|&c| c == 0.0) {
            format!("{name} has no stiffness and no constraint")
        } else {
            format!("{name} is not held (a null pivot: a mechanism runs through it)")
        }
    };
    match null_equations(triplets, n, equations) {
        Some(list) => cap(list.into_iter().map(describe).collect()),
        None => vec!["a mechanism that the structural checks did not isolate: check that every bar node is held by an interface and every body is supported".into()],
    }
}

fn column_norms(triplets: &crate::assembly::Triplets, n: usize) -> Vec<f64> {
    let mut column_norm = vec![0.0f64; n];
    for (&j, &v) in triplets.cols.iter().zip(&triplets.values) {
        column_norm[j] += v.abs();
    }
    column_norm
}

/// The undetermined unknowns of a singular system: those the backend named, else the empty
/// columns, else those the reference solver's complete pivoting isolates (small systems).
fn null_equations(triplets: &crate::assembly::Triplets, n: usize, equations: Vec<usize>) -> Option<Vec<usize>> {
    if !equations.is_empty() {
        return Some(equations);
    }
    let column_norm = column_norms(triplets, n);
    let empty: Vec<usize> = (0..n).filter(|&j| column_norm[j] == 0.0).collect();
    if !empty.is_empty() {
        return Some(empty);
    }
    if n <= dense_ref::SIZE_LIMIT {
        let matrix = crate::assembly::PatternCache::default().assemble(n, triplets).0;
        let mut dense = dense_ref::DenseReference::default();
        if dense.analyse(&matrix).is_ok() {
            if let Err(Failure::Singular { equations }) = dense.factorize(&matrix) {
                return Some(equations);
            }
        }
    }
    None
}

fn cap(mut list: Vec<String>) -> Vec<String> {
    if list.len() > 12 {
        let more = list.len() - 12;
        list.truncate(12);
        list.push(format!("and {more} more"));
    }
    list
}
