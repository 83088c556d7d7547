//! A dynamic stage's absorbing sides and compliant base (docs/dynamics.md): their nodes freed from
//! the supports, whose reactions at the stage's start stay on as forces; each side's
//! Lysmer–Kuhlemeyer dashpots (`element/dashpot.rs`) in its soil element's matrix; and a compliant
//! base's input, the force C_b·ι·v_g(t) of the outcrop motion's velocity through the base's
//! dashpots C_b (Joyner & Chen, BSSA 65(5), 1975: twice the incident wave's ρ·V·v, the incident
//! wave being half the outcrop motion).

use super::soil::unit_weight;
use crate::dofs::Direction;
use crate::element::dashpot::side_dashpots;
use crate::element::soil_state::SoilField;
use crate::model::{DynamicPlan, HalfSpace, Model};
use nalgebra::DMatrix;

/// The supported DOFs of the stage's absorbing sides' nodes in their directions, freed in `held`.
pub fn free_supports(model: &Model, plan: &DynamicPlan, held: &mut [bool]) -> Vec<usize> {
    let mut freed = Vec::new();
    for a in &plan.absorbing {
        let e = &model.mesh.solids[a.side.solid];
        for &l in e.kind.sides()[a.side.side] {
            for (d, dof) in [2 * e.nodes[l], 2 * e.nodes[l] + 1].into_iter().enumerate() {
                if a.directions[d] && held[dof] {
                    held[dof] = false;
                    freed.push(dof);
                }
            }
        }
    }
    freed
}

/// The absorbing sides' dashpots, per soil element, and a compliant base's input force per unit
/// of the ground's velocity in each direction shaken.
pub struct Dashpots {
    pub elements: Vec<Option<DMatrix<f64>>>,
    /// C_b·ι_d for each direction d of the base motion (empty on a rigid base).
    pub input: Vec<(Direction, Vec<f64>)>,
}

impl Dashpots {
    /// The dashpots of `plan`'s sides, with the soil's density from its unit weight in `field`'s
    /// water over the plan's g and its elastic moduli, or the half-space's given impedances.
    pub fn new(model: &Model, field: &SoilField, plan: &DynamicPlan) -> Dashpots {
        let mesh = &model.mesh;
        let mut elements: Vec<Option<DMatrix<f64>>> = vec![None; mesh.solids.len()];
        let mut input_x = vec![0.0; 2 * mesh.nodes.len()];
        let mut input_y = input_x.clone();
        for a in &plan.absorbing {
            let (s, e) = (a.side.solid, &mesh.solids[a.side.solid]);
            let local = e.kind.sides()[a.side.side];
            let coords: Vec<[f64; 2]> = local.iter().map(|&l| mesh.position(e.nodes[l])).collect();
            let impedance = a.half_space.unwrap_or_else(|| {
                let mid = [0.5 * (coords[0][0] + coords[1][0]), 0.5 * (coords[0][1] + coords[1][1])];
                let density = unit_weight(model, s, field.water.as_ref(), mid) / plan.gravity;
                let elastic = model.elasticity(s);
                HalfSpace::elastic(density, elastic.youngs_modulus, elastic.poissons_ratio)
            });
            let blocks = side_dashpots(&coords, impedance.normal, impedance.tangential, mesh.geometry);
            let n = 2 * e.nodes.len();
            let matrix = elements[s].get_or_insert_with(|| DMatrix::zeros(n, n));
            for (&l, block) in local.iter().zip(&blocks) {
                // (the components in the side's directions)
                let block: Vec<[f64; 2]> = (0..2)
                    .map(|i| [0, 1].map(|j| if a.directions[i] && a.directions[j] { block[i][j] } else { 0.0 }))
                    .collect();
                for (i, row) in block.iter().enumerate() {
                    for (j, c) in row.iter().enumerate() {
                        matrix[(2 * l + i, 2 * l + j)] += c;
                    }
                    if a.input {
                        // C_b·ι: the block's column of the shaken direction
                        input_x[2 * e.nodes[l] + i] += row[0];
                        input_y[2 * e.nodes[l] + i] += row[1];
                    }
                }
            }
        }
        let input = if plan.compliant_base {
            plan.base_motion
                .iter()
                .map(|(d, _)| (*d, if *d == Direction::X { input_x.clone() } else { input_y.clone() }))
                .collect()
        } else {
            Vec::new()
        };
        Dashpots { elements, input }
    }
}
