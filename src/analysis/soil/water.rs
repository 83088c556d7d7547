//! The soil's water: the pore pressures at the Gauss points under a stage's water table, the force
//! ∫Bᵀm·p they give, and the water's push on the soil's free boundary below the table.

use super::kinematics::add_bt_sigma;
use super::setup::{element_points, SoilSetup};
use crate::element::soil_state::{SoilField, WaterTable};
use crate::element::solid;
use crate::model::Model;
use rayon::prelude::*;

/// The pore pressures of every present element under `water` (or none).
pub fn set_water(model: &Model, setup: &SoilSetup, field: &mut SoilField, water: Option<WaterTable>) {
    let mesh = &model.mesh;
    field.water = water;
    let water = field.water.clone();
    field.elements_mut().par_iter_mut().enumerate().for_each(|(s, state)| {
        state.pore.clear();
        state.pore_force = None;
        let (Some(w), true) = (&water, state.active) else { return };
        let points = element_points(model, &mesh.solids[s], setup.rule);
        let pore: Vec<f64> = points.iter().map(|p| w.pressure(p.x)).collect();
        if pore.iter().all(|&p| p == 0.0) {
            return;
        }
        let mut f = vec![0.0; setup.dofs[s].len()];
        for (p, &pw) in points.iter().zip(&pore) {
            add_bt_sigma(p, [pw, pw, 0.0, pw], &mut f);
        }
        state.pore = pore;
        state.pore_force = Some(f);
    });
}

/// Nodal forces of the water pressing on the soil's free boundary below the water table: p
/// against the outward normal of every side that one present element alone has and that is not an
/// interface face. (Inside the soil the pore pressure is carried by the elements' ∫Bᵀm·p; at a free
/// boundary the water outside balances it. At an interface the contact multiplier carries total
/// stress and the interface strength subtracts p itself.)
pub fn water_on_boundary(model: &Model, field: &SoilField, interfaces: &[crate::interface::Interface]) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut f = vec![0.0; 2 * mesh.nodes.len()];
    let Some(water) = &field.water else { return f };
    let mut on_interface = vec![false; mesh.nodes.len()];
    for face in interfaces.iter().flat_map(|i| &i.faces) {
        for &n in &face.master {
            on_interface[n] = true;
        }
        for p in &face.points {
            on_interface[p.slave] = true;
        }
    }
    let mut count: std::collections::HashMap<(usize, usize), usize> = std::collections::HashMap::new();
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    for (e, st) in mesh.solids.iter().zip(field.elements()) {
        if st.active {
            for side in e.kind.sides() {
                *count.entry(key(e.nodes[side[0]], e.nodes[side[1]])).or_default() += 1;
            }
        }
    }
    let g = (0.6f64).sqrt();
    let rule = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
    for (e, st) in mesh.solids.iter().zip(field.elements()) {
        if !st.active {
            continue;
        }
        for side in e.kind.sides() {
            let nodes: Vec<usize> = side.iter().map(|&l| e.nodes[l]).collect();
            if count[&key(nodes[0], nodes[1])] != 1 || (on_interface[nodes[0]] && on_interface[nodes[1]]) {
                continue;
            }
            let coords: Vec<[f64; 2]> = nodes.iter().map(|&n| mesh.position(n)).collect();
            for (t, w) in rule {
                let (n, dn) = solid::side_shape(coords.len(), t);
                let (mut x, mut dx) = ([0.0; 2], [0.0; 2]);
                for ((ni, di), c) in n.iter().zip(&dn).zip(&coords) {
                    x[0] += ni * c[0];
                    x[1] += ni * c[1];
                    dx[0] += di * c[0];
                    dx[1] += di * c[1];
                }
                let p = water.pressure(x) * mesh.geometry.circumference(x);
                if p == 0.0 {
                    continue;
                }
                // sides run counter-clockwise: the outward normal is the right-hand normal of dx
                let outward = [dx[1], -dx[0]];
                for (i, &node) in nodes.iter().enumerate() {
                    f[2 * node] -= n[i] * p * outward[0] * w;
                    f[2 * node + 1] -= n[i] * p * outward[1] * w;
                }
            }
        }
    }
    f
}
