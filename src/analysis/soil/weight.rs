//! What the soil's unit weight gives: its weight and other body forces as nodal forces, and its
//! masses for a dynamic stage (saturated below the water table).

use super::setup::{element_points, SoilSetup};
use crate::element::soil_state::{SoilField, WaterTable};
use crate::model::Model;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// The unit weight at a point: saturated below the water table.
pub(crate) fn unit_weight(model: &Model, solid: usize, water: Option<&WaterTable>, x: [f64; 2]) -> f64 {
    let m = model.soil(solid);
    match water {
        Some(w) if x[1] < w.level_at(x[0]) => m.saturated_weight(),
        _ => m.unit_weight,
    }
}

/// Each soil element's mass matrix (`lumping`), its density its unit weight over `gravity` (g in
/// the model's length per s²; saturated below the water table).
pub fn masses(
    model: &Model,
    field: &SoilField,
    gravity: f64,
    lumping: crate::element::mass::Lumping,
) -> Vec<DMatrix<f64>> {
    let mesh = &model.mesh;
    mesh.solids
        .par_iter()
        .enumerate()
        .map(|(s, e)| {
            let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.position(n)).collect();
            let density = |x: [f64; 2]| unit_weight(model, s, field.water.as_ref(), x) / gravity;
            crate::element::mass::mass(e.kind, &coords, density, mesh.geometry, lumping)
        })
        .collect()
}

/// Consistent nodal forces of the weight (−y) of the present soil, times `factor`.
pub fn weight(model: &Model, setup: &SoilSetup, field: &SoilField, factor: f64) -> Vec<f64> {
    body_force(model, setup, field, [0.0, -factor])
}

/// Consistent nodal forces of the present soil's weight times `coefficients` (x, y): a body force
/// γ·(kx, ky) (the weight is `[0, −1]`, a pseudo-static seismic force `[kh, kv]`).
pub fn body_force(model: &Model, setup: &SoilSetup, field: &SoilField, coefficients: [f64; 2]) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut f = vec![0.0; 2 * mesh.nodes.len()];
    if coefficients == [0.0, 0.0] {
        return f;
    }
    for (s, e) in mesh.solids.iter().enumerate() {
        if !field.elements()[s].active {
            continue;
        }
        for p in element_points(model, e, setup.rule) {
            let gamma = unit_weight(model, s, field.water.as_ref(), p.x);
            // (in this order, the weight's forces are those of −(factor·γ)·N·w to the last bit)
            let (gx, gy) = (coefficients[0] * gamma, coefficients[1] * gamma);
            for (i, &n) in e.nodes.iter().enumerate() {
                f[2 * n] += p.n[i] * gx * p.weight;
                f[2 * n + 1] += p.n[i] * gy * p.weight;
            }
        }
    }
    f
}
