//! Which soil elements are present: the field at the start, elements placed on the deformed ground
//! (with the reinforcements placed with them), and elements removed.

use super::setup::{element_u, SoilSetup};
use crate::element::soil_state::{ElementState, SoilField};
use crate::model::Model;

/// The field at the start of a run: every element present but those a stage places later
/// (`absent`: [`Model::initially_absent`]).
pub fn initial_field(absent: &[bool]) -> SoilField {
    SoilField::new(absent.iter().map(|&a| ElementState { active: !a, ..ElementState::default() }).collect())
}

/// Nodes of present soil elements.
pub fn present_nodes(model: &Model, field: &SoilField) -> Vec<bool> {
    let mut present = vec![false; model.mesh.nodes.len()];
    for (e, s) in model.mesh.solids.iter().zip(field.elements()) {
        if s.active {
            for &n in &e.nodes {
                present[n] = true;
            }
        }
    }
    present
}

/// Place soil elements: each starts stress-free on the deformed ground. A node that no present
/// element used before takes the displacement of the nearest node that one did (the ground it is
/// placed on), so that the new element's strains count from the deformed geometry.
///
/// `bar_nodes` are the nodes of reinforcements placed with these elements: they land on the ground
/// the same way.
pub fn activate(
    model: &Model,
    setup: &SoilSetup,
    field: &mut SoilField,
    solids: &[usize],
    bar_nodes: &[usize],
    u: &mut [f64],
) {
    let before = present_nodes(model, field);
    let old: Vec<usize> = (0..before.len()).filter(|&n| before[n]).collect();
    let mesh = &model.mesh;
    let mut moved = vec![false; before.len()];
    let new_nodes = solids.iter().flat_map(|&s| mesh.solids[s].nodes.iter().copied()).chain(bar_nodes.iter().copied());
    {
        for n in new_nodes {
            if before[n] || moved[n] {
                continue;
            }
            moved[n] = true;
            let x = mesh.position(n);
            let nearest = old.iter().copied().min_by(|&a, &b| {
                let (pa, pb) = (mesh.position(a), mesh.position(b));
                let da = (pa[0] - x[0]).powi(2) + (pa[1] - x[1]).powi(2);
                let db = (pb[0] - x[0]).powi(2) + (pb[1] - x[1]).powi(2);
                da.total_cmp(&db)
            });
            if let Some(m) = nearest {
                u[2 * n] = u[2 * m];
                u[2 * n + 1] = u[2 * m + 1];
            }
        }
    }
    for &s in solids {
        let state = &mut field.elements_mut()[s];
        if state.active {
            continue;
        }
        *state = ElementState {
            active: true,
            placed: Some(element_u(&setup.dofs[s], u)),
            points: Vec::new(),
            reference_force: None,
            pore: Vec::new(),
            pore_force: None,
        };
    }
}

/// Remove soil elements (excavation).
pub fn deactivate(field: &mut SoilField, solids: &[usize]) {
    for &s in solids {
        field.elements_mut()[s] = ElementState::default();
    }
}
