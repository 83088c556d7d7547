//! The nodal forces of the loads a stage applies.

use crate::model::{Load, Model};

/// Consistent nodal forces of a list of loads (full load, factor 1), but for gravity and the
/// pseudo-static force, which come from `soil::body_force`.
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
            Load::Gravity { .. } | Load::PseudoStatic { .. } => {}
            Load::EdgeTraction { sides, pressure, shear } => {
                for side in sides {
                    let e = &mesh.solids[side.solid];
                    let local = &e.kind.sides()[side.side];
                    let nodes: Vec<usize> = local.iter().map(|&l| e.nodes[l]).collect();
                    let coords: Vec<[f64; 2]> = nodes.iter().map(|&n| mesh.position(n)).collect();
                    // Element sides run counter-clockwise: the element lies to their left.
                    let fe = solid::side_traction(&coords, *pressure, *shear, 1.0, mesh.geometry);
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
