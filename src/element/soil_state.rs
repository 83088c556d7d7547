//! The state of the soil elements through a run, as the assembly and the internal force see it:
//! which elements are present, the effective stresses at their Gauss points, their reference
//! state, the pore pressures and the water table in force; and the Mohr–Coulomb elements' trial
//! state at the current iterate (forces, tangents, updated Gauss points). A cutback restores the
//! committed state with the rest of the run's state.
//!
//! Total stress is σ = σ′ − p·m, with m = (1, 1, 0, 1) and p the pore pressure (compression
//! positive); the internal force of an element is ∫Bᵀσ′ dA − ∫Bᵀm·p dA.

use super::mohr_coulomb::YieldState;
use nalgebra::DMatrix;

/// The state of one Gauss point.
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub struct PointState {
    /// Effective stress σ′xx, σ′yy, τxy, σ′zz; tension positive.
    pub stress: [f64; 4],
    /// Accumulated equivalent plastic strain.
    pub plastic_strain: f64,
    pub yield_state: YieldState,
    /// Duncan–Chang soil: the largest stress state SS = SL·(σ3/pa)^¼ the point has had (the
    /// loading criterion's memory); zero for other soils.
    pub largest_stress_state: f64,
    /// Hardening soil: γp, where the shear hardening surface stands; zero for other soils and
    /// before the point's first update (it then starts on the surface through its stress).
    pub shear_hardening: f64,
    /// Hardening soil: pp, where the cap stands; zero as `shear_hardening`.
    pub preconsolidation: f64,
}

/// The state of one soil element.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ElementState {
    pub active: bool,
    /// Element displacements when the element was placed or given its initial stresses: its
    /// strains count from here. `None`: zero.
    pub placed: Option<Vec<f64>>,
    /// Effective stress at each Gauss point: the committed state of a Mohr–Coulomb element, the
    /// reference stress σ′₀ of a linear-elastic one. Empty: zero everywhere.
    pub points: Vec<PointState>,
    /// Linear-elastic elements: ∫Bᵀσ′₀ dA.
    pub reference_force: Option<Vec<f64>>,
    /// Pore pressure at each Gauss point (empty: dry).
    pub pore: Vec<f64>,
    /// ∫Bᵀm·p dA.
    pub pore_force: Option<Vec<f64>>,
}

/// Every soil element's state, and the water table in force. The elements are read through
/// [`elements`](Self::elements) and changed through [`elements_mut`](Self::elements_mut), which
/// forgets the packed presence flags ([`active_words`](Self::active_words)) until they are next
/// asked for: no change to an element can leave them stale. The states are shared between copies
/// of the field until one of them changes (a copy kept to restore a step costs nothing while the
/// step does not change the field).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct SoilField {
    elements: std::sync::Arc<Vec<ElementState>>,
    pub water: Option<WaterTable>,
    /// Each element's `active` flag, 64 to a word; made when first asked for after a change.
    #[serde(skip)]
    active_words: std::sync::OnceLock<Vec<u64>>,
}

impl SoilField {
    /// A field of `elements`, with no water table.
    pub fn new(elements: Vec<ElementState>) -> Self {
        SoilField { elements: std::sync::Arc::new(elements), water: None, active_words: std::sync::OnceLock::new() }
    }

    /// Every soil element's state, in the mesh's order of solids.
    pub fn elements(&self) -> &[ElementState] {
        &self.elements
    }

    /// Every soil element's state, to change.
    pub fn elements_mut(&mut self) -> &mut [ElementState] {
        self.active_words = std::sync::OnceLock::new();
        std::sync::Arc::make_mut(&mut self.elements).as_mut_slice()
    }

    /// Each element's `active` flag, 64 to a word: element `e` is bit `e % 64` of word `e / 64`.
    /// Read by the matrix's fingerprint at every iteration: 1/128 of the elements' states.
    pub fn active_words(&self) -> &[u64] {
        self.active_words.get_or_init(|| {
            let mut words = vec![0u64; self.elements.len().div_ceil(64)];
            for (e, state) in self.elements.iter().enumerate() {
                words[e / 64] |= u64::from(state.active) << (e % 64);
            }
            words
        })
    }
}

/// A phreatic line and the unit weight of water: hydrostatic pore pressure p = γw·(h(x) − y) below
/// it, zero above.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WaterTable {
    /// `[x, y]` points with x increasing (one point: a horizontal table).
    pub line: Vec<[f64; 2]>,
    pub unit_weight: f64,
}

impl WaterTable {
    /// Elevation of the phreatic line at `x` (constant beyond its ends).
    pub fn level_at(&self, x: f64) -> f64 {
        let l = &self.line;
        if x <= l[0][0] {
            return l[0][1];
        }
        for w in l.windows(2) {
            if x <= w[1][0] {
                let t = (x - w[0][0]) / (w[1][0] - w[0][0]);
                return w[0][1] + t * (w[1][1] - w[0][1]);
            }
        }
        l[l.len() - 1][1]
    }

    /// Pore pressure at (x, y), compression positive.
    pub fn pressure(&self, p: [f64; 2]) -> f64 {
        (self.unit_weight * (self.level_at(p[0]) - p[1])).max(0.0)
    }
}

/// Which tangent the Mohr–Coulomb elements give the matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tangent {
    /// The consistent tangent (unsymmetric when ψ ≠ φ).
    Consistent,
    /// Its symmetric part.
    Symmetric,
    /// The elastic matrix (constant stiffness).
    Elastic,
    /// The first iteration's predictor: the elastic matrix at the last converged stresses, where
    /// the law predicts with it (`SoilLaw::predictor_elasticity`).
    Committed,
}

/// The Mohr–Coulomb elements at the current iterate.
#[derive(Debug, Clone, Default)]
pub struct SoilTrial {
    /// Per soil element: the internal force ∫Bᵀσ′ dA of a present Mohr–Coulomb element.
    pub forces: Vec<Option<Vec<f64>>>,
    /// Per soil element: its tangent where it differs from the elastic matrix.
    pub tangents: Vec<Option<DMatrix<f64>>>,
    /// Per soil element: the updated Gauss-point states.
    pub points: Vec<Option<Vec<PointState>>>,
    /// Gauss points on the yield surface.
    pub yielding: usize,
}

/// The soil's part of the internal force of element `s` (with element displacements `u_e`), added
/// into `f` at the element's local positions: the Mohr–Coulomb force, or K_e·(u_e − u₀) + ∫Bᵀσ′₀,
/// less ∫Bᵀm·p. Returns false for an absent element.
pub fn element_force(
    field: &SoilField,
    trial: &SoilTrial,
    s: usize,
    k: &DMatrix<f64>,
    u_e: &[f64],
    f: &mut [f64],
) -> bool {
    let state = &field.elements()[s];
    if !state.active {
        return false;
    }
    match trial.forces.get(s).and_then(|f| f.as_ref()) {
        Some(force) => {
            for (a, v) in force.iter().enumerate() {
                f[a] += v;
            }
        }
        None => {
            let n = u_e.len();
            for a in 0..n {
                let mut sum = 0.0;
                for b in 0..n {
                    let placed = state.placed.as_ref().map_or(0.0, |p| p[b]);
                    sum += k[(a, b)] * (u_e[b] - placed);
                }
                f[a] += sum;
            }
            if let Some(r) = &state.reference_force {
                for (a, v) in r.iter().enumerate() {
                    f[a] += v;
                }
            }
        }
    }
    if let Some(p) = &state.pore_force {
        for (a, v) in p.iter().enumerate() {
            f[a] -= v;
        }
    }
    true
}
