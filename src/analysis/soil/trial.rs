//! Each iteration's trial state of the soil with a law (the stresses, forces and tangents for the
//! displacements since the last converged increment), and its commit.

use super::kinematics::{add_bt_sigma, strain};
use super::setup::SoilSetup;
use crate::element::mohr_coulomb::YieldState;
use crate::element::soil_state::{PointState, SoilField, SoilTrial, Tangent};
use crate::element::solid;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Update every present element with a law for the displacements since the last converged
/// increment. A Duncan–Chang or hardening-soil element always gives its tangent (its stiffness
/// follows its stresses); with [`Tangent::Elastic`], its moduli at the updated stresses without the
/// plastic part; with [`Tangent::Committed`], the law's predictor elasticity
/// ([`SoilLaw::predictor_elasticity`]).
pub fn evaluate(setup: &SoilSetup, field: &SoilField, u: &[f64], u_committed: &[f64], tangent: Tangent) -> SoilTrial {
    let n = setup.laws.len();
    if !setup.any_plastic() {
        return SoilTrial { forces: vec![None; n], tangents: vec![None; n], points: vec![None; n], yielding: 0 };
    }
    type ElementTrial = (Option<Vec<f64>>, Option<DMatrix<f64>>, Option<Vec<PointState>>, usize);
    let consistent = matches!(tangent, Tangent::Consistent | Tangent::Symmetric);
    let results: Vec<ElementTrial> = (0..n)
        .into_par_iter()
        .map(|s| {
            let (Some(law), Some(points), true) = (&setup.laws[s], &setup.points[s], field.elements()[s].active) else {
                return (None, None, None, 0);
            };
            let dofs = &setup.dofs[s];
            let du: Vec<f64> = dofs.iter().map(|&d| u[d] - u_committed[d]).collect();
            let committed = &field.elements()[s].points;
            let mut force = vec![0.0; dofs.len()];
            let mut k = DMatrix::zeros(dofs.len(), dofs.len());
            let mut states = Vec::with_capacity(points.len());
            let mut yielding = 0;
            for (g, p) in points.iter().enumerate() {
                let old = committed.get(g).copied().unwrap_or_default();
                let (update, state, elasticity) = law.update(&setup.elastic[s], &old, strain(p, &du), consistent);
                add_bt_sigma(p, update.stress, &mut force);
                if update.state.is_plastic() {
                    yielding += 1;
                }
                // At the apex the stress cannot change at all (its tangent is zero); a patch of
                // such points, as at a cohesionless surface, would be a mechanism of the iteration
                // matrix alone, so they keep the elastic matrix there.
                let plastic = update.state.is_plastic() && update.state != YieldState::Apex;
                let c = match tangent {
                    Tangent::Committed => {
                        law.predictor_elasticity(&setup.elastic[s], &old).unwrap_or(elasticity).d_matrix_with_hoop()
                    }
                    Tangent::Consistent if plastic => update.tangent,
                    Tangent::Symmetric if plastic => 0.5 * (update.tangent + update.tangent.transpose()),
                    _ => elasticity.d_matrix_with_hoop(),
                };
                k += solid::point_stiffness(p, &c);
                states.push(state);
            }
            let elastic = matches!(tangent, Tangent::Elastic | Tangent::Committed);
            let tangent = ((yielding > 0 && !elastic) || law.is_nonlinear_elastic()).then_some(k);
            (Some(force), tangent, Some(states), yielding)
        })
        .collect();
    let mut trial = SoilTrial::default();
    for (f, k, p, y) in results {
        trial.forces.push(f);
        trial.tangents.push(k);
        trial.points.push(p);
        trial.yielding += y;
    }
    trial
}

/// Keep the converged Gauss-point states.
pub fn commit(field: &mut SoilField, trial: &SoilTrial) {
    // (an elastic soil's trial has no points: its field stays as it is, shared with its copies)
    if trial.points.iter().all(Option::is_none) {
        return;
    }
    for (state, points) in field.elements_mut().iter_mut().zip(&trial.points) {
        if let Some(points) = points {
            state.points = points.clone();
        }
    }
}
