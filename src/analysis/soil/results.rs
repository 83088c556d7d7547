//! The soil's results at its Gauss points: stress, strain since placement, pore pressure and yield
//! state, and the normal stress across a line between elements.

use super::kinematics::strain;
use crate::element::mohr_coulomb::{self, YieldState};
use crate::element::soil_state::SoilField;
use crate::element::solid::{self, MappedPoint};
use crate::model::Model;
use rayon::prelude::*;

/// One Gauss point's results.
#[derive(Debug, Clone)]
pub struct ElementStress {
    pub element: u64,
    pub point: usize,
    pub x: [f64; 2],
    /// σxx, σyy, τxy, σzz; tension positive.
    pub stress: [f64; 4],
    /// εxx, εyy, γxy since the element was placed; extension positive.
    pub strain: [f64; 3],
    /// Pore pressure, compression positive (the stresses above are effective: σ = σ′ − p).
    pub pore_pressure: f64,
    pub yield_state: YieldState,
    /// Accumulated equivalent plastic strain.
    pub plastic_strain: f64,
}

/// The Gauss-point results of every present element: effective stress, strain since placement,
/// pore pressure and yield state.
pub fn gauss_results(model: &Model, field: &SoilField, u: &[f64]) -> Vec<ElementStress> {
    // (each worker's elements gathered in one list, and the lists joined once; each worker reuses
    // its buffers from element to element)
    (0..model.mesh.solids.len())
        .into_par_iter()
        .map_init(ResultBuffers::default, |buffers, s| element_results(model, field, u, s, buffers))
        .flat_map_iter(|points| points)
        .collect()
}

/// What one worker reuses from element to element for the Gauss-point results: the element's node
/// coordinates, its displacements and its mapped points.
#[derive(Default)]
struct ResultBuffers {
    coords: Vec<[f64; 2]>,
    u_e: Vec<f64>,
    points: Vec<MappedPoint>,
}

/// The Gauss-point results of soil element `s` (none when it is absent): a linear-elastic
/// element's stress from the displacements `u`, the stress of an element with a law as last
/// committed.
fn element_results(
    model: &Model,
    field: &SoilField,
    u: &[f64],
    s: usize,
    buffers: &mut ResultBuffers,
) -> Vec<ElementStress> {
    let state = &field.elements()[s];
    if !state.active {
        return Vec::new();
    }
    let e = &model.mesh.solids[s];
    let ResultBuffers { coords, u_e, points } = buffers;
    u_e.clear();
    u_e.extend(e.nodes.iter().flat_map(|&n| [u[2 * n], u[2 * n + 1]]));
    if let Some(p) = &state.placed {
        for (a, b) in u_e.iter_mut().zip(p) {
            *a -= b;
        }
    }
    coords.clear();
    coords.extend(e.nodes.iter().map(|&n| model.mesh.position(n)));
    solid::mapped_points_of_checked_into(e.kind, coords, model.integration(), model.mesh.geometry, points)
        .expect("element Jacobians were checked when the model was read");
    // (a law's stress is read as committed: the elasticity is wanted for linear-elastic soil only,
    // and neither the law nor the elasticity is built per element of every step's results)
    let elastic = (!model.keeps_stresses(s)).then(|| model.elasticity(s));
    points
        .iter()
        .enumerate()
        .map(|(g, p)| {
            let eps = strain(p, u_e);
            let point = state.points.get(g).copied().unwrap_or_default();
            let stress = match &elastic {
                None => point.stress,
                Some(elastic) => mohr_coulomb::trial_stress(elastic, point.stress, eps),
            };
            ElementStress {
                element: e.id,
                point: g + 1,
                x: p.x,
                stress,
                strain: [eps[0], eps[1], eps[2]],
                pore_pressure: state.pore.get(g).copied().unwrap_or(0.0),
                yield_state: point.yield_state,
                plastic_strain: point.plastic_strain,
            }
        })
        .collect()
}

/// The soil's total normal stress (compression positive) across a line of unit normal `n` that
/// runs between the soil elements `solids`: for each present one, the mean over its Gauss points of
/// −n·σ′·n + p, and the mean of those. On a side shared by two linear elements this is exact for a
/// stress that varies linearly across it (the two element means straddle the line). `None` when no
/// element there is present.
pub fn normal_stress_across(model: &Model, field: &SoilField, u: &[f64], solids: &[usize], n: [f64; 2]) -> Option<f64> {
    let per_element: Vec<f64> = solids
        .iter()
        .filter_map(|&s| {
            let points = element_results(model, field, u, s, &mut ResultBuffers::default());
            (!points.is_empty()).then(|| {
                let sum: f64 = points
                    .iter()
                    .map(|p| {
                        let [sxx, syy, sxy, _] = p.stress;
                        -(n[0] * n[0] * sxx + 2.0 * n[0] * n[1] * sxy + n[1] * n[1] * syy) + p.pore_pressure
                    })
                    .sum();
                sum / points.len() as f64
            })
        })
        .collect();
    (!per_element.is_empty()).then(|| per_element.iter().sum::<f64>() / per_element.len() as f64)
}
