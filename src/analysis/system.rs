//! The global system: element matrices computed once, the saddle-point matrix assembled in triplet
//! form for a DOF map, internal forces, and the linear solver with its reuse bookkeeping.

use crate::assembly::{CscMatrix, PatternCache, Triplets};
use crate::dofs::DofMap;
use crate::element::{bar, solid};
use crate::error::SolveError;
use crate::interface::{Interface, NormalState, Row};
use crate::linsol::{self, Backend, Failure, LinearSolver};
use crate::model::Model;
use nalgebra::DMatrix;
use std::time::Instant;

/// The soil's state and its current trial, as the assembly and the internal force see them.
#[derive(Clone, Copy)]
pub struct SoilView<'a> {
    pub field: &'a super::soil::SoilField,
    pub trial: &'a super::soil::SoilTrial,
}

/// Element stiffness matrices with their global DOF lists (2·node + d).
pub struct ElementMatrices {
    pub blocks: Vec<(Vec<usize>, DMatrix<f64>)>,
    /// For each bar (in mesh order): its block and its law. Solid blocks come first.
    pub bars: Vec<BarLaw>,
    /// Mean absolute diagonal entry of the blocks (see [`ElementMatrices::typical_stiffness`]).
    typical: f64,
}

/// Sum per-DOF contributions of element blocks over `n` DOFs, in parallel: the blocks are cut into a
/// fixed number of runs (not one per thread), each summed into a vector of its own, and the vectors
/// are added in order, so that the result does not depend on the number of threads.
fn par_block_sum(
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    n: usize,
    each: impl Fn(usize, &[usize], &DMatrix<f64>, &mut [f64]) + Sync,
) -> Vec<f64> {
    use rayon::prelude::*;
    const RUNS: usize = 4;
    const SEQUENTIAL_BELOW: usize = 4096;
    let run = if blocks.len() < SEQUENTIAL_BELOW { blocks.len().max(1) } else { blocks.len().div_ceil(RUNS) };
    let parts: Vec<Vec<f64>> = blocks
        .par_chunks(run)
        .enumerate()
        .map(|(c, chunk)| {
            let mut f = vec![0.0; n];
            for (i, (dl, k)) in chunk.iter().enumerate() {
                each(c * run + i, dl, k, &mut f);
            }
            f
        })
        .collect();
    let mut parts = parts.into_iter();
    let mut total = parts.next().unwrap_or_else(|| vec![0.0; n]);
    for part in parts {
        for (t, p) in total.iter_mut().zip(&part) {
            *t += p;
        }
    }
    total
}

/// A bar's axial law: linear elastic, optionally tension-only, optionally rupturing at T_ult.
#[derive(Debug, Clone)]
pub struct BarLaw {
    pub id: u64,
    pub block: usize,
    pub axis: [f64; 2],
    pub length: f64,
    pub axial_stiffness: f64,
    pub tension_only: bool,
    pub rupture_strength: Option<f64>,
}

/// The state of every bar (in mesh order): ruptured, not yet placed, and the stretch it had when it
/// was placed (its force counts from there).
#[derive(Debug, Clone, Default)]
pub struct BarStates {
    pub ruptured: Vec<bool>,
    pub absent: Vec<bool>,
    pub placed_stretch: Vec<f64>,
}

impl BarStates {
    pub fn new(count: usize) -> BarStates {
        BarStates { ruptured: vec![false; count], absent: vec![false; count], placed_stretch: vec![0.0; count] }
    }

    /// A bar that carries nothing: ruptured or not placed.
    pub fn idle(&self, i: usize) -> bool {
        self.ruptured.get(i).copied().unwrap_or(false) || self.absent.get(i).copied().unwrap_or(false)
    }

    pub fn stretch0(&self, i: usize) -> f64 {
        self.placed_stretch.get(i).copied().unwrap_or(0.0)
    }
}

impl BarLaw {
    /// Stretch e·(u_b − u_a) along the bar's axis.
    pub fn stretch(&self, u: &[f64], dofs: &[usize]) -> f64 {
        self.axis[0] * (u[dofs[2]] - u[dofs[0]]) + self.axis[1] * (u[dofs[3]] - u[dofs[1]])
    }

    /// Elastic axial force T = EA/L·(e·(u_b − u_a) − stretch at placement) (tension positive).
    pub fn elastic_force(&self, u: &[f64], dofs: &[usize], stretch0: f64) -> f64 {
        self.axial_stiffness / self.length * (self.stretch(u, dofs) - stretch0)
    }

    /// The force the bar carries: zero once ruptured or before it is placed, and never compressive
    /// when tension-only.
    pub fn force(&self, u: &[f64], dofs: &[usize], bars: &BarStates, i: usize) -> f64 {
        let t = self.elastic_force(u, dofs, bars.stretch0(i));
        if bars.idle(i) || (self.tension_only && t < 0.0) {
            0.0
        } else {
            t
        }
    }

    /// Whether the bar carries no stiffness in the current state.
    pub fn slack(&self, u: &[f64], dofs: &[usize], bars: &BarStates, i: usize) -> bool {
        bars.idle(i) || (self.tension_only && self.elastic_force(u, dofs, bars.stretch0(i)) < 0.0)
    }
}

impl ElementMatrices {
    pub fn compute(model: &Model) -> Self {
        use rayon::prelude::*;
        let mesh = &model.mesh;
        // the soil elements in parallel, collected in mesh order
        let mut blocks: Vec<(Vec<usize>, DMatrix<f64>)> = mesh
            .solids
            .par_iter()
            .enumerate()
            .map(|(s, e)| {
                let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.position(n)).collect();
                let m = model.soil(s);
                let material =
                    solid::PlaneStrain { youngs_modulus: m.youngs_modulus, poissons_ratio: m.poissons_ratio };
                // Validation has checked every Jacobian; a failure here would be a bug, not bad input.
                let k = solid::stiffness(e.kind, &coords, &material, model.integration())
                    .expect("element Jacobians were checked when the model was read");
                (dofs_of(&e.nodes), k)
            })
            .collect();
        blocks.reserve(mesh.bars.len());
        let mut bars = Vec::with_capacity(mesh.bars.len());
        for b in &mesh.bars {
            let m = &model.reinforcements[b.material].1;
            let (a, c) = (mesh.position(b.nodes[0]), mesh.position(b.nodes[1]));
            let k = bar::stiffness(a, c, m.axial_stiffness);
            let (axis, length) = bar::axis(a, c);
            bars.push(BarLaw {
                id: b.id,
                block: blocks.len(),
                axis,
                length,
                axial_stiffness: m.axial_stiffness,
                tension_only: m.tension_only,
                rupture_strength: m.rupture_strength,
            });
            blocks.push((dofs_of(&b.nodes), DMatrix::from_fn(4, 4, |i, j| k[(i, j)])));
        }
        let mut elements = ElementMatrices { blocks, bars, typical: 1.0 };
        elements.typical = elements.mean_diagonal();
        elements
    }

    /// Mean absolute diagonal entry of the element matrices: the scale of the constraint rows.
    pub fn typical_stiffness(&self) -> f64 {
        self.typical
    }

    fn mean_diagonal(&self) -> f64 {
        let (sum, count) = self
            .blocks
            .iter()
            .flat_map(|(_, k)| (0..k.nrows()).map(move |i| k[(i, i)].abs()))
            .fold((0.0, 0usize), |(s, c), v| (s + v, c + 1));
        if count == 0 || !(sum > 0.0) {
            1.0
        } else {
            sum / count as f64
        }
    }
}

fn dofs_of(nodes: &[usize]) -> Vec<usize> {
    nodes.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect()
}

/// A row as (global DOF, coefficient) pairs.
pub fn row_dofs(row: &Row) -> Vec<(usize, f64)> {
    row.iter().flat_map(|&(n, c)| [(2 * n, c[0]), (2 * n + 1, c[1])]).collect()
}

/// A tangential spring: one slave point of one face of an interface with a shear stiffness.
#[derive(Debug, Clone)]
pub struct Spring {
    /// Slip s = row · u.
    pub row: Vec<(usize, f64)>,
    pub tributary: f64,
    pub interface: usize,
    pub face: usize,
    pub point: usize,
    /// The multiplier of the point's normal row.
    pub normal_multiplier: usize,
    /// The slave node and its reference position (for the pore pressure there).
    pub slave: usize,
    pub position: [f64; 2],
}

/// The rows of the multipliers and the springs, for the current association.
pub struct InterfaceRows {
    /// One per multiplier, in `DofMap::multipliers` order.
    pub constraint_rows: Vec<Vec<(usize, f64)>>,
    /// Reference gap of each multiplier's row (zero for tangential rows).
    pub gap0: Vec<f64>,
    /// The full normal row of a held point (its constraint row acts on the slave alone, but its gap
    /// is still measured to the master face).
    held_rows: Vec<Option<Vec<(usize, f64)>>>,
    pub springs: Vec<Spring>,
}

impl InterfaceRows {
    pub fn new(model: &Model, interfaces: &[Interface], dofs: &DofMap) -> Self {
        let mut constraint_rows = Vec::with_capacity(dofs.multipliers.len());
        let mut gap0 = Vec::with_capacity(dofs.multipliers.len());
        let mut held_rows = Vec::with_capacity(dofs.multipliers.len());
        let mut normal_multiplier = std::collections::HashMap::new();
        for (k, m) in dofs.multipliers.iter().enumerate() {
            let face = &interfaces[m.interface].faces[m.face];
            let point = &face.points[m.point];
            let mut row = if m.tangential {
                gap0.push(0.0);
                face.tangential_row(point)
            } else {
                normal_multiplier.insert((m.interface, m.face, m.point), k);
                gap0.push(point.gap0);
                face.normal_row(&model.mesh, point)
            };
            if !m.tangential && matches!(point.normal_state, NormalState::Held { .. }) {
                held_rows.push(Some(row_dofs(&row)));
                // holds the slave node alone: the master entries stay in the pattern as zeros
                for entry in row.iter_mut().skip(1) {
                    entry.1 = [0.0, 0.0];
                }
            } else {
                held_rows.push(None);
            }
            constraint_rows.push(row_dofs(&row));
        }
        let mut springs = Vec::new();
        for (i, interface) in interfaces.iter().enumerate() {
            if !interface.is_tie() {
                for (f, face) in interface.faces.iter().enumerate() {
                    for (p, point) in face.points.iter().enumerate() {
                        springs.push(Spring {
                            row: row_dofs(&face.tangential_row(point)),
                            tributary: point.tributary,
                            interface: i,
                            face: f,
                            point: p,
                            normal_multiplier: normal_multiplier[&(i, f, p)],
                            slave: point.slave,
                            position: model.mesh.position(point.slave),
                        });
                    }
                }
            }
        }
        InterfaceRows { constraint_rows, gap0, held_rows, springs }
    }

    /// Current gap of every row: g = gap0 + row · u.
    pub fn gaps(&self, u: &[f64]) -> Vec<f64> {
        self.constraint_rows
            .iter()
            .zip(&self.held_rows)
            .zip(&self.gap0)
            .map(|((row, held), g0)| g0 + held.as_ref().unwrap_or(row).iter().map(|&(d, c)| c * u[d]).sum::<f64>())
            .collect()
    }
}

/// Whether multiplier `k` currently holds its row (true) or sits on a unit diagonal (false).
pub fn multiplier_is_active(interfaces: &[Interface], dofs: &DofMap, k: usize) -> bool {
    let m = dofs.multipliers[k];
    let p = &interfaces[m.interface].faces[m.face].points[m.point];
    if m.tangential {
        // a tie's tangential row holds while its normal row does
        matches!(p.tangential_state, NormalState::Active) && matches!(p.normal_state, NormalState::Active)
    } else {
        matches!(p.normal_state, NormalState::Active | NormalState::Held { .. })
    }
}

/// Assemble [K sCᵀ; sC sD] over the free DOFs and the multipliers, in a fixed triplet order.
///
/// The constraint rows are scaled by `s` (a typical stiffness, [`ElementMatrices::typical_stiffness`])
/// so that they are commensurate with K; the unknowns are then Δλ/s. This equilibration keeps the
/// saddle-point matrix well conditioned for backends that do not scale it themselves.
#[allow(clippy::too_many_arguments)]
pub fn assemble(
    elements: &ElementMatrices,
    soil: SoilView<'_>,
    rows: &InterfaceRows,
    spring_stiffness: &[f64],
    spring_coupling: Option<&[f64]>,
    bars: &BarStates,
    interfaces: &[Interface],
    dofs: &DofMap,
    scale: f64,
) -> Triplets {
    let mut t = Triplets::default();
    let eq = |d: usize| dofs.equation[d];
    let first_bar = elements.bars.first().map_or(usize::MAX, |bar| bar.block);
    for (b, (dl, k)) in elements.blocks.iter().enumerate() {
        // absent soil is left out; a yielding element gives its tangent
        let k = if b < first_bar {
            if !soil.field.elements[b].active {
                continue;
            }
            soil.trial.tangents.get(b).and_then(|t| t.as_ref()).unwrap_or(k)
        } else {
            k
        };
        // a ruptured or not yet placed bar keeps its place in the pattern with no stiffness
        let factor = if b >= first_bar && bars.idle(b - first_bar) { 0.0 } else { 1.0 };
        for (a, &da) in dl.iter().enumerate() {
            let Some(ia) = eq(da) else { continue };
            for (b, &db) in dl.iter().enumerate() {
                if let Some(ib) = eq(db) {
                    t.push(ia, ib, factor * k[(a, b)]);
                }
            }
        }
    }
    for (spring, k) in rows.springs.iter().zip(spring_stiffness) {
        for &(da, ca) in &spring.row {
            let Some(ia) = eq(da) else { continue };
            for &(db, cb) in &spring.row {
                if let Some(ib) = eq(db) {
                    t.push(ia, ib, k * ca * cb);
                }
            }
        }
    }
    // The consistent tangent's ∂(τ·ℓ·row)/∂λ = (∂τ/∂σn)·row in the columns of each spring's normal
    // multiplier (unknown λ/s, hence the factor s). Always pushed under this scheme, zero where it
    // does not apply, so the pattern does not change between iterations.
    if let Some(coupling) = spring_coupling {
        for (spring, &c) in rows.springs.iter().zip(coupling) {
            let m = dofs.multiplier_equation(spring.normal_multiplier);
            for &(d, cd) in &spring.row {
                if let Some(i) = eq(d) {
                    t.push(i, m, scale * c * cd);
                }
            }
        }
    }
    for (k, row) in rows.constraint_rows.iter().enumerate() {
        let m = dofs.multiplier_equation(k);
        let active = multiplier_is_active(interfaces, dofs, k);
        for &(d, c) in row {
            if let Some(i) = eq(d) {
                let c = if active { scale * c } else { 0.0 };
                t.push(m, i, c);
                t.push(i, m, c);
            }
        }
        t.push(m, m, if active { 0.0 } else { scale });
    }
    t
}

/// A fingerprint of everything in the assembled matrix but the element matrices (which do not change
/// within a run): the rows of the springs and multipliers, the springs' stiffness and coupling, the
/// ruptured bars, which multipliers are active, and the row scale. Two iterations of one increment
/// with the same key have the same matrix, so the second needs neither an assembly nor a
/// factorisation.
#[allow(clippy::too_many_arguments)]
pub fn matrix_key(
    soil: SoilView<'_>,
    rows: &InterfaceRows,
    spring_stiffness: &[f64],
    spring_coupling: Option<&[f64]>,
    bars: &BarStates,
    interfaces: &[Interface],
    dofs: &DofMap,
    scale: f64,
) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    let entries = |row: &[(usize, f64)], h: &mut std::collections::hash_map::DefaultHasher| {
        row.len().hash(h);
        for &(d, c) in row {
            d.hash(h);
            c.to_bits().hash(h);
        }
    };
    for spring in &rows.springs {
        entries(&spring.row, &mut h);
    }
    for row in &rows.constraint_rows {
        entries(row, &mut h);
    }
    for k in spring_stiffness.iter().chain(spring_coupling.unwrap_or(&[])) {
        k.to_bits().hash(&mut h);
    }
    bars.ruptured.hash(&mut h);
    bars.absent.hash(&mut h);
    for (state, tangent) in soil.field.elements.iter().zip(&soil.trial.tangents) {
        state.active.hash(&mut h);
        if let Some(k) = tangent {
            for v in k.iter() {
                v.to_bits().hash(&mut h);
            }
        }
    }
    for k in 0..dofs.multipliers.len() {
        multiplier_is_active(interfaces, dofs, k).hash(&mut h);
    }
    scale.to_bits().hash(&mut h);
    h.finish()
}

/// Internal forces over all displacement DOFs: the elements' K_e·u_e plus the springs' τ·ℓ·row (the
/// multipliers' Cᵀλ apart). `taus` holds each spring's shear stress.
pub fn internal_force(
    elements: &ElementMatrices,
    soil: SoilView<'_>,
    rows: &InterfaceRows,
    taus: &[f64],
    bars: &BarStates,
    u: &[f64],
) -> Vec<f64> {
    let first_bar = elements.bars.first().map(|b| b.block).unwrap_or(elements.blocks.len());
    let mut f = par_block_sum(&elements.blocks[..first_bar], u.len(), |s, dl, k, f| {
        let state = &soil.field.elements[s];
        if !state.active {
            return;
        }
        if state.placed.is_none() && state.reference_force.is_none() && state.pore_force.is_none() {
            // the common case (elastic soil present from the start): K_e·u_e with no copies
            if !matches!(soil.trial.forces.get(s), Some(Some(_))) {
                for (a, &da) in dl.iter().enumerate() {
                    let mut sum = 0.0;
                    for (b, &db) in dl.iter().enumerate() {
                        sum += k[(a, b)] * u[db];
                    }
                    f[da] += sum;
                }
                return;
            }
        }
        let u_e: Vec<f64> = dl.iter().map(|&d| u[d]).collect();
        let mut fe = vec![0.0; dl.len()];
        super::soil::element_force(soil.field, soil.trial, s, k, &u_e, &mut fe);
        for (a, &da) in dl.iter().enumerate() {
            f[da] += fe[a];
        }
    });
    for (i, bar) in elements.bars.iter().enumerate() {
        let dl = &elements.blocks[bar.block].0;
        let t = bar.force(u, dl, bars, i);
        let e = bar.axis;
        f[dl[0]] -= t * e[0];
        f[dl[1]] -= t * e[1];
        f[dl[2]] += t * e[0];
        f[dl[3]] += t * e[1];
    }
    for (spring, tau) in rows.springs.iter().zip(taus) {
        for &(d, c) in &spring.row {
            f[d] += tau * spring.tributary * c;
        }
    }
    f
}

/// The round-off floor of the out-of-balance force: ‖Σ_e |K_e·u_e|‖ (per DOF, the sum of the
/// magnitudes of the element forces that cancel there) times a few ε. A residual below it cannot be
/// reduced by iterating.
pub fn round_off_floor(elements: &ElementMatrices, soil: SoilView<'_>, u: &[f64]) -> f64 {
    let first_bar = elements.bars.first().map(|b| b.block).unwrap_or(elements.blocks.len());
    let f = par_block_sum(&elements.blocks, u.len(), |s, dl, k, f| {
        if s < first_bar {
            let state = &soil.field.elements[s];
            if !state.active {
                return;
            }
            // the stress-carried forces: reference, Mohr–Coulomb and pore forces
            let forces = [
                state.reference_force.as_ref(),
                state.pore_force.as_ref(),
                soil.trial.forces.get(s).and_then(|f| f.as_ref()),
            ];
            for extra in forces.into_iter().flatten() {
                for (a, &da) in dl.iter().enumerate() {
                    f[da] += extra[a].abs();
                }
            }
        }
        for (a, &da) in dl.iter().enumerate() {
            for (b, &db) in dl.iter().enumerate() {
                f[da] += (k[(a, b)] * u[db]).abs();
            }
        }
    });
    64.0 * f64::EPSILON * f.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Cᵀλ over all displacement DOFs.
pub fn constraint_force(rows: &InterfaceRows, lambda: &[f64], dof_count: usize) -> Vec<f64> {
    let mut f = vec![0.0; dof_count];
    for (row, l) in rows.constraint_rows.iter().zip(lambda) {
        for &(d, c) in row {
            f[d] += c * l;
        }
    }
    f
}

/// Counts and times of the linear-algebra work, for the run summary.
#[derive(Debug, Default, Clone, serde::Serialize)]
pub struct SolverStats {
    pub analyses: usize,
    pub factorizations: usize,
    pub solves: usize,
    pub analyse_seconds: f64,
    pub factorize_seconds: f64,
    pub solve_seconds: f64,
    pub max_relative_residual: f64,
    /// Outer (equilibrium) iterations over the run.
    pub iterations: usize,
    /// Time building the triplets and refilling the CSC matrix.
    pub assembly_seconds: f64,
    /// Time on interface points: rows, laws, active set, tributary clipping, re-association.
    pub interface_seconds: f64,
    /// Time computing the out-of-balance force.
    pub residual_seconds: f64,
    /// Time checking each linear solution's residual ‖Ax−b‖/‖b‖ (and refining it).
    pub check_seconds: f64,
    /// Time computing and writing each step's results.
    pub output_seconds: f64,
    /// MUMPS's estimate of its factorisation memory after the last analysis, MB.
    pub estimated_memory_mb: Option<f64>,
    /// Memory MUMPS's last factorisation used (INFOG(22)), MB.
    pub factor_memory_mb: Option<f64>,
    /// Entries in the factors of the last factorisation, where the backend reports them.
    pub factor_entries: Option<u64>,
    /// Diagnostics that do not stop a run (for example an inertia that differs from the number of
    /// active multipliers).
    pub warnings: Vec<String>,
}

/// A solver backend with the bookkeeping that lets it skip work: a new analysis only for a new
/// pattern, a new factorisation only for new values.
pub struct LinearSystem {
    solver: Box<dyn LinearSolver>,
    patterns: PatternCache,
    factorized: Option<CscMatrix>,
    pub stats: SolverStats,
}

impl LinearSystem {
    /// A solver for matrices that are `symmetric` or not (MUMPS: SYM=2 or SYM=0).
    pub fn new(backend: Backend, symmetric: bool, options: &linsol::SolverOptions) -> Result<Self, SolveError> {
        Ok(LinearSystem {
            solver: linsol::make(backend, symmetric, options)?,
            patterns: PatternCache::default(),
            factorized: None,
            stats: SolverStats::default(),
        })
    }

    pub fn backend(&self) -> Backend {
        self.solver.backend()
    }

    /// Solve A x = b for the assembled triplets, of which `active_multipliers` rows hold a
    /// constraint (zero diagonal). Returns x and the relative residual.
    pub fn solve(
        &mut self,
        n: usize,
        triplets: &Triplets,
        rhs: &[f64],
        active_multipliers: usize,
    ) -> Result<(Vec<f64>, f64), Failure> {
        let t = Instant::now();
        let (matrix, new_pattern) = self.patterns.assemble(n, triplets);
        self.stats.assembly_seconds += t.elapsed().as_secs_f64();
        if new_pattern {
            let t = Instant::now();
            let analysed = self.solver.analyse(&matrix);
            self.stats.estimated_memory_mb = self.solver.estimated_memory_mb();
            analysed?;
            self.stats.analyses += 1;
            self.stats.analyse_seconds += t.elapsed().as_secs_f64();
            self.factorized = None;
        }
        let same_values = self.factorized.as_ref().is_some_and(|f| f.values == matrix.values);
        if !same_values {
            // a failed factorisation leaves nothing to reuse
            self.factorized = None;
            let t = Instant::now();
            self.solver.factorize(&matrix)?;
            self.stats.factorizations += 1;
            self.stats.factor_entries = self.solver.factor_entries();
            self.stats.factor_memory_mb = self.solver.factor_memory_mb();
            // Inertia check (DESIGN §2): the negative pivots equal the active multipliers when Kc has
            // full row rank, K is positive definite on its null space, supports are eliminated and no
            // tangent is negative. A mismatch is worth knowing, not an error.
            if let Some(negative) = self.solver.negative_pivots() {
                if negative != active_multipliers {
                    let w = format!(
                        "{} reports {negative} negative pivots for {active_multipliers} active multipliers: \
                         some constraint rows may be dependent, or K is not positive definite on their null space",
                        self.solver.backend().name()
                    );
                    if !self.stats.warnings.contains(&w) {
                        self.stats.warnings.push(w);
                    }
                }
            }
            self.stats.factorize_seconds += t.elapsed().as_secs_f64();
        }
        self.factorized = Some(matrix);
        self.solve_again(rhs)
    }

    /// Solve with the matrix of the last [`LinearSystem::solve`] and its factorisation, for a new
    /// right-hand side: the constant-stiffness iterations, whose matrix does not change.
    pub fn solve_again(&mut self, rhs: &[f64]) -> Result<(Vec<f64>, f64), Failure> {
        let Some(matrix) = self.factorized.as_ref() else {
            return Err(Failure::Other(SolveError::Backend {
                backend: self.solver.backend().name(),
                message: "solve_again called before a factorisation".into(),
            }));
        };
        let t = Instant::now();
        let mut x = self.solver.solve(rhs)?;
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        self.stats.solves += 1;
        let t = Instant::now();
        let mut residual = linsol::relative_residual(matrix, &x, rhs);
        // Iterative refinement (at most two corrections) when pivoting on the saddle point left more
        // than 1e-10 in the residual (the outer iteration corrects anything smaller).
        for _ in 0..2 {
            if !(residual > 1e-10) || !x.iter().all(|v| v.is_finite()) {
                break;
            }
            let ax = matrix.mul_vec(&x);
            let r: Vec<f64> = rhs.iter().zip(&ax).map(|(b, a)| b - a).collect();
            let s = Instant::now();
            let dx = self.solver.solve(&r)?;
            self.stats.solve_seconds += s.elapsed().as_secs_f64();
            self.stats.solves += 1;
            let refined: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
            let refined_residual = linsol::relative_residual(matrix, &refined, rhs);
            if refined_residual < residual {
                x = refined;
                residual = refined_residual;
            } else {
                break;
            }
        }
        // the residual checks are geoslip's own work, counted apart from the backend's solves
        self.stats.check_seconds += t.elapsed().as_secs_f64();
        if !x.iter().all(|v| v.is_finite()) || !(residual < 1e-6) {
            // A numerically singular matrix: LU divides by a (near) zero pivot.
            return Err(Failure::Singular { equations: Vec::new() });
        }
        self.stats.max_relative_residual = self.stats.max_relative_residual.max(residual);
        Ok((x, residual))
    }
}
