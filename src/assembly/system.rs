//! The global system: element matrices computed once, and the saddle-point matrix of an iteration
//! assembled in triplet form over the free DOFs and the multipliers (with its fingerprint). The
//! internal forces are in `forces.rs`.

use super::block_sum::par_block_sum;
use super::inertia::Inertia;
use crate::dofs::DofMap;
use crate::element::bar::{self, BarLaw, BarMaterial, BarStates};
use crate::element::soil_state::{SoilField, SoilTrial};
use crate::element::solid::{self, Integration, PlaneStrain};
use crate::interface::rows::{multiplier_is_active, InterfaceRows};
use crate::interface::Interface;
use crate::linsol::csc::Triplets;
use crate::mesh::Mesh;
use nalgebra::DMatrix;

/// The soil's state and its current trial, as the assembly and the internal force see them.
#[derive(Clone, Copy)]
pub struct SoilView<'a> {
    pub field: &'a SoilField,
    pub trial: &'a SoilTrial,
}

/// Element stiffness matrices with their global DOF lists (2·node + d).
pub struct ElementMatrices {
    pub blocks: Vec<(Vec<usize>, DMatrix<f64>)>,
    /// For each bar (in mesh order): its block and its law. Solid blocks come first.
    pub bars: Vec<BarLaw>,
    /// Mean absolute diagonal entry of the blocks (see [`ElementMatrices::typical_stiffness`]).
    typical: f64,
    /// While a dynamic stage runs: the soil's masses and the time step's dynamic operator, added
    /// to the soil's blocks and internal force.
    pub inertia: Option<Inertia>,
}

impl ElementMatrices {
    /// The stiffness of every soil element (`elastic`: its plane-strain elasticity, in mesh order;
    /// integrated with `rule`) and every bar (`bar_materials`, in mesh order).
    ///
    /// # Panics
    /// If an element's Jacobian is not positive at a Gauss point of `rule`: the model's validation
    /// checks every element first.
    pub fn compute(mesh: &Mesh, elastic: &[PlaneStrain], bar_materials: &[BarMaterial], rule: Integration) -> Self {
        use rayon::prelude::*;
        // the soil elements in parallel, collected in mesh order
        let mut blocks: Vec<(Vec<usize>, DMatrix<f64>)> = mesh
            .solids
            .par_iter()
            .enumerate()
            .map(|(s, e)| {
                let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.position(n)).collect();
                // Validation has checked every Jacobian; a failure here would be a bug, not bad input.
                let k = solid::stiffness(e.kind, &coords, &elastic[s], rule, mesh.geometry)
                    .expect("element Jacobians were checked when the model was read");
                (dofs_of(&e.nodes), k)
            })
            .collect();
        blocks.reserve(mesh.bars.len());
        let mut bars = Vec::with_capacity(mesh.bars.len());
        for (b, m) in mesh.bars.iter().zip(bar_materials) {
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
        let mut elements = ElementMatrices { blocks, bars, typical: 1.0, inertia: None };
        elements.typical = elements.mean_diagonal();
        elements
    }

    /// The DOFs of bar `i`'s block.
    pub fn bar_dofs(&self, i: usize) -> &[usize] {
        &self.blocks[self.bars[i].block].0
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

/// Which element blocks to assemble.
#[derive(Clone, Copy)]
enum Blocks {
    All,
    Soil,
    Bars,
}

/// Everything the saddle-point matrix of one iteration is made of. [`SystemInputs::assemble`] builds
/// the matrix from it and [`SystemInputs::fingerprint`] hashes the same fields, so that the two
/// cannot drift apart: an iteration whose fingerprint equals the last one's has the same matrix and
/// reuses its factorisation.
#[derive(Clone, Copy)]
pub struct SystemInputs<'a> {
    /// Computed once per run; the fingerprint takes only their inertia (a dynamic stage's).
    pub elements: &'a ElementMatrices,
    pub soil: SoilView<'a>,
    pub rows: &'a InterfaceRows,
    /// Ks·ℓ (or the law's tangent times ℓ) of each spring.
    pub spring_stiffness: &'a [f64],
    /// ∂τ/∂σn of each spring (the consistent tangent's coupling to its normal multiplier), when the
    /// scheme asks for it.
    pub spring_coupling: Option<&'a [f64]>,
    /// [∂d/∂s, ∂d/∂σn] of each spring's opening by dilatancy, when a face dilates: its normal row
    /// holds g + d = 0, linearised as (row_n + ∂d/∂s·row_t)·Δu + (∂d/∂σn)·Δλ/ℓ.
    pub spring_dilation: Option<&'a [[f64; 2]]>,
    /// ∂(τ·ℓ)/∂u of each spring through its tributary length ℓ (as (DOF, value); the consistent
    /// tangent under large slip, where ℓ follows the slave line's length and embedment), when the
    /// scheme asks for it: the matrix gets row ⊗ it, unsymmetric.
    pub spring_stretch: Option<&'a [Vec<(usize, f64)>]>,
    pub bars: &'a BarStates,
    pub interfaces: &'a [Interface],
    pub dofs: &'a DofMap,
    /// The scale of the constraint rows, s.
    pub scale: f64,
}

impl SystemInputs<'_> {
    /// Assemble [K sCᵀ; sC sD] over the free DOFs and the multipliers, in a fixed triplet order.
    ///
    /// The constraint rows are scaled by `s` (a typical stiffness,
    /// [`ElementMatrices::typical_stiffness`]) so that they are commensurate with K; the unknowns are
    /// then Δλ/s. This equilibration keeps the saddle-point matrix well conditioned for backends
    /// that do not scale it themselves.
    pub fn assemble(&self) -> Triplets {
        // reserved whole: grown by doubling, the list (the largest array of an assembly, 24 bytes
        // an entry) would keep up to twice its size through the factorisation
        let reserved = self.block_entries(Blocks::All) + self.interface_entries();
        let mut t = Triplets::with_capacity(reserved);
        self.add_blocks(&mut t, Blocks::All);
        self.add_interface(&mut t);
        debug_assert!(t.rows.len() <= reserved, "{} entries pushed, {reserved} reserved", t.rows.len());
        t
    }

    /// The soil elements alone: the part of the matrix that stays while the soil is elastic and
    /// no element is placed or removed ([`SystemInputs::soil_fingerprint`]).
    pub fn assemble_soil(&self) -> Triplets {
        let mut t = Triplets::with_capacity(self.block_entries(Blocks::Soil));
        self.add_blocks(&mut t, Blocks::Soil);
        t
    }

    /// [`SystemInputs::assemble_soil`]'s matrix times `x` (over the equations), from the element
    /// matrices, without assembling it.
    pub fn soil_times(&self, x: &[f64]) -> Vec<f64> {
        let SystemInputs { elements, soil, dofs, .. } = *self;
        let eq = |d: usize| dofs.equation[d];
        let first_bar = elements.bars.first().map_or(elements.blocks.len(), |bar| bar.block);
        let inertia = elements.inertia.as_ref();
        par_block_sum(&elements.blocks[..first_bar], first_bar, x.len(), |b, dl, elastic, y| {
            if !soil.field.elements()[b].active {
                return;
            }
            // a yielding element's tangent, as `add_blocks` takes it, and its dynamic part
            let k = soil.trial.tangents.get(b).and_then(|t| t.as_ref()).unwrap_or(elastic);
            let entry = |a: usize, c: usize| k[(a, c)] + inertia.map_or(0.0, |d| d.entry(b, a, c));
            for (a, &da) in dl.iter().enumerate() {
                let Some(i) = eq(da) else { continue };
                let mut sum = 0.0;
                for (c, &dc) in dl.iter().enumerate() {
                    if let Some(j) = eq(dc) {
                        sum += entry(a, c) * x[j];
                    }
                }
                y[i] += sum;
            }
        })
    }

    /// Everything but the soil elements: the bars, the springs and the constraint rows. With
    /// [`SystemInputs::assemble_soil`] it sums to [`SystemInputs::assemble`].
    pub fn assemble_reinforcement_and_interface(&self) -> Triplets {
        let mut t = Triplets::with_capacity(self.block_entries(Blocks::Bars) + self.interface_entries());
        self.add_blocks(&mut t, Blocks::Bars);
        self.add_interface(&mut t);
        t
    }

    /// A fingerprint of the soil part: which elements are present, their tangents and the
    /// equation numbers.
    pub fn soil_fingerprint(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        hash_soil(self.soil, &mut h);
        self.elements.inertia.as_ref().map(Inertia::key).hash(&mut h);
        self.soil.trial.tangents.len().hash(&mut h);
        self.dofs.equation_key().hash(&mut h);
        h.finish()
    }

    /// Whether `add_blocks` takes block `b` for `which`: the wanted kind, and absent soil left out
    /// (`first_bar`: the first bar's block).
    fn takes_block(&self, b: usize, first_bar: usize, which: Blocks) -> bool {
        let wanted = match which {
            Blocks::All => true,
            Blocks::Soil => b < first_bar,
            Blocks::Bars => b >= first_bar,
        };
        wanted && (b >= first_bar || self.soil.field.elements()[b].active)
    }

    /// The entries `add_blocks` pushes for `which`.
    fn block_entries(&self, which: Blocks) -> usize {
        let SystemInputs { elements, dofs, .. } = *self;
        let first_bar = elements.bars.first().map_or(usize::MAX, |bar| bar.block);
        let free = |dl: &[usize]| dl.iter().filter(|&&d| dofs.equation[d].is_some()).count();
        (0..elements.blocks.len())
            .filter(|&b| self.takes_block(b, first_bar, which))
            .map(|b| free(&elements.blocks[b].0).pow(2))
            .sum()
    }

    /// At least as many entries as `add_interface` pushes.
    fn interface_entries(&self) -> usize {
        let SystemInputs { rows, spring_coupling, spring_dilation, spring_stretch, .. } = *self;
        let springs: usize = rows.springs.iter().map(|s| s.row.len() * s.row.len()).sum();
        let row_entries: usize = rows.springs.iter().map(|s| s.row.len()).sum();
        let coupling = if spring_coupling.is_some() { row_entries } else { 0 };
        let dilation = if spring_dilation.is_some() { row_entries + rows.springs.len() } else { 0 };
        let stretch: usize = spring_stretch
            .map_or(0, |stretch| rows.springs.iter().zip(stretch).map(|(s, g)| s.row.len() * g.len()).sum());
        let constraints: usize = rows.constraint_rows.iter().map(|r| 2 * r.len() + 1).sum();
        springs + coupling + dilation + stretch + constraints
    }

    fn add_blocks(&self, t: &mut Triplets, which: Blocks) {
        let SystemInputs { elements, soil, bars, dofs, .. } = *self;
        let eq = |d: usize| dofs.equation[d];
        let first_bar = elements.bars.first().map_or(usize::MAX, |bar| bar.block);
        for (e, (dl, elastic)) in elements.blocks.iter().enumerate() {
            if !self.takes_block(e, first_bar, which) {
                continue;
            }
            // a yielding element gives its tangent
            let k = if e < first_bar {
                soil.trial.tangents.get(e).and_then(|t| t.as_ref()).unwrap_or(elastic)
            } else {
                elastic
            };
            // an element's inertia and damping in a dynamic stage
            let inertia = elements.inertia.as_ref();
            // a ruptured or not yet placed bar keeps its place in the pattern with no stiffness
            let factor = if e >= first_bar && bars.idle(e - first_bar) { 0.0 } else { 1.0 };
            for (a, &da) in dl.iter().enumerate() {
                let Some(ia) = eq(da) else { continue };
                for (b, &db) in dl.iter().enumerate() {
                    if let Some(ib) = eq(db) {
                        let dynamic = inertia.map_or(0.0, |d| d.entry(e, a, b));
                        t.push(ia, ib, factor * k[(a, b)] + dynamic);
                    }
                }
            }
        }
    }

    /// The springs, their coupling to the multipliers and the constraint rows.
    fn add_interface(&self, t: &mut Triplets) {
        let SystemInputs {
            rows,
            spring_stiffness,
            spring_coupling,
            spring_dilation,
            spring_stretch,
            interfaces,
            dofs,
            scale,
            ..
        } = *self;
        let eq = |d: usize| dofs.equation[d];
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
        // ∂(τ·ℓ·row)/∂u through ℓ: row ⊗ ∂(τ·ℓ)/∂u (always pushed under this scheme, zero where ℓ
        // does not change, for a fixed pattern)
        if let Some(stretch) = spring_stretch {
            for (spring, rate) in rows.springs.iter().zip(stretch) {
                for &(d, cd) in &spring.row {
                    let Some(i) = eq(d) else { continue };
                    for &(g, value) in rate {
                        if let Some(j) = eq(g) {
                            t.push(i, j, cd * value);
                        }
                    }
                }
            }
        }
        for (k, row) in rows.constraint_rows.iter().enumerate() {
            let m = dofs.multiplier_equation(k);
            let active = multiplier_is_active(interfaces, dofs.multipliers[k]);
            for &(d, c) in row {
                if let Some(i) = eq(d) {
                    let c = if active { scale * c } else { 0.0 };
                    t.push(m, i, c);
                    t.push(i, m, c);
                }
            }
            t.push(m, m, if active { 0.0 } else { scale });
        }
        // A dilating face's normal row, g + d(κ) = 0, in the rows of the multipliers (always pushed
        // where a face dilates, zero where it does not apply, for a fixed pattern); the row is
        // scaled by s and the unknown is Δλ/s, so ∂d/∂σn·Δλ/ℓ enters as s²·(∂d/∂σn)/ℓ.
        if let Some(dilation) = spring_dilation {
            for (spring, &[slope, pressure]) in rows.springs.iter().zip(dilation) {
                let k = spring.normal_multiplier;
                let m = dofs.multiplier_equation(k);
                let active = multiplier_is_active(interfaces, dofs.multipliers[k]);
                for &(d, c) in &spring.row {
                    if let Some(i) = eq(d) {
                        t.push(m, i, if active { scale * slope * c } else { 0.0 });
                    }
                }
                let l = spring.tributary.max(f64::MIN_POSITIVE);
                t.push(m, m, if active { scale * scale * pressure / l } else { 0.0 });
            }
        }
    }

    /// A fingerprint of everything in the assembled matrix but the element matrices (which do not
    /// change within a run): the rows of the springs and multipliers, the springs' stiffness and
    /// coupling, the ruptured and absent bars, the soil present and its tangents, which multipliers
    /// are active, and the row scale.
    pub fn fingerprint(&self) -> u64 {
        let SystemInputs {
            elements,
            soil,
            rows,
            spring_stiffness,
            spring_coupling,
            spring_dilation,
            spring_stretch,
            bars,
            interfaces,
            dofs,
            scale,
        } = *self;
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
        for k in spring_dilation.unwrap_or(&[]).iter().flatten() {
            k.to_bits().hash(&mut h);
        }
        for rate in spring_stretch.unwrap_or(&[]) {
            entries(rate, &mut h);
        }
        bars.ruptured.hash(&mut h);
        bars.absent.hash(&mut h);
        hash_soil(soil, &mut h);
        elements.inertia.as_ref().map(Inertia::key).hash(&mut h);
        for k in 0..dofs.multipliers.len() {
            multiplier_is_active(interfaces, dofs.multipliers[k]).hash(&mut h);
        }
        scale.to_bits().hash(&mut h);
        // (the equation numbers change from stage to stage)
        dofs.equation_key().hash(&mut h);
        h.finish()
    }
}

/// Which soil elements are present (64 to a word) and the tangents of those that have one, into
/// `h`.
fn hash_soil(soil: SoilView<'_>, h: &mut impl std::hash::Hasher) {
    use std::hash::Hash;
    soil.field.active_words().hash(h);
    for (e, tangent) in soil.trial.tangents.iter().enumerate() {
        if let Some(k) = tangent {
            e.hash(h);
            for v in k.iter() {
                v.to_bits().hash(h);
            }
        }
    }
}
