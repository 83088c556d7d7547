//! What the soil keeps through a run that does not change: each element's law, elasticity and DOFs,
//! and the mapped Gauss points of the elements with a law.

use crate::element::soil_law::SoilLaw;
use crate::element::solid::{self, Integration, MappedPoint, PlaneStrain};
use crate::model::Model;
use rayon::prelude::*;

/// What does not change through a run: each element's law, its DOFs, and the Gauss points of the
/// elements with a law (mapped once).
pub struct SoilSetup {
    pub laws: Vec<Option<SoilLaw>>,
    pub elastic: Vec<PlaneStrain>,
    pub dofs: Vec<Vec<usize>>,
    pub rule: Integration,
    pub(super) points: Vec<Option<Vec<MappedPoint>>>,
}

impl SoilSetup {
    pub fn new(model: &Model) -> SoilSetup {
        let rule = model.integration();
        let mesh = &model.mesh;
        let laws: Vec<Option<SoilLaw>> = (0..mesh.solids.len()).map(|s| model.soil_law(s)).collect();
        let elastic = (0..mesh.solids.len()).map(|s| model.elasticity(s)).collect();
        let dofs = mesh.solids.iter().map(|e| e.nodes.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect()).collect();
        let points =
            mesh.solids.par_iter().zip(&laws).map(|(e, law)| law.map(|_| element_points(model, e, rule))).collect();
        SoilSetup { laws, elastic, dofs, rule, points }
    }

    /// Whether the element keeps its stresses (it has a law: it may yield, or its stiffness
    /// follows its stresses).
    pub fn is_plastic(&self, solid: usize) -> bool {
        self.laws[solid].is_some()
    }

    /// Whether any element keeps its stresses.
    pub fn any_plastic(&self) -> bool {
        self.laws.iter().any(|l| l.is_some())
    }
}

pub(super) fn element_points(model: &Model, e: &crate::mesh::Solid, rule: Integration) -> Vec<MappedPoint> {
    let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| model.mesh.position(n)).collect();
    solid::mapped_points_of_checked(e.kind, &coords, rule, model.mesh.geometry)
        .expect("element Jacobians were checked when the model was read")
}

/// An element's entries of the global vector `u`.
pub(super) fn element_u(dofs: &[usize], u: &[f64]) -> Vec<f64> {
    dofs.iter().map(|&d| u[d]).collect()
}
