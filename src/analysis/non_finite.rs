//! A number that is not finite (NaN or ±∞) in an iteration stops it, with where it first appeared.
//!
//! The places are looked at in the order the iteration computes them: the displacements and
//! multipliers it starts from, the applied loads, the soil's Gauss-point forces, the interface
//! springs' shear stresses, then the out-of-balance forces, the matrix and the solution. The first
//! non-finite number in that order is where it came from; everything after it only carries it on.

use super::springs::SpringResult;
use super::state::State;
use crate::dofs::DofMap;
use crate::element::soil_state::SoilTrial;
use crate::interface::active_set::describe;
use crate::interface::MultiplierRef;
use crate::linsol::csc::Triplets;
use crate::mesh::Mesh;

/// The first non-finite number of an iteration, and where it was.
#[derive(Debug, Clone)]
pub struct NonFinite {
    pub value: f64,
    pub location: String,
}

/// What an iteration has computed so far, in the order it computed it.
pub struct Iterate<'a> {
    pub mesh: &'a Mesh,
    pub dofs: &'a DofMap,
    pub state: &'a State,
    pub soil_trial: Option<&'a SoilTrial>,
    pub springs: &'a [SpringResult],
}

fn dof_name(mesh: &Mesh, d: usize) -> String {
    format!("node {} {}", mesh.node_id(d / 2), if d % 2 == 0 { "ux" } else { "uy" })
}

/// The first non-finite number in what the iteration started from and computed before its system.
pub fn in_iterate(it: &Iterate) -> Option<NonFinite> {
    let Iterate { mesh, dofs, state, soil_trial, springs } = *it;
    let found = |value: f64, location: String| Some(NonFinite { value, location });
    if let Some((d, &v)) = state.u.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return found(v, format!("the displacement {}", dof_name(mesh, d)));
    }
    if let Some((k, &v)) = state.lambda.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return found(v, format!("the multiplier of {}", multiplier(mesh, state, dofs.multipliers[k])));
    }
    if let Some((d, &v)) = state.f_ext.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return found(v, format!("the applied load at {}", dof_name(mesh, d)));
    }
    if let Some(trial) = soil_trial {
        for (s, force) in trial.forces.iter().enumerate() {
            if let Some(v) = force.as_ref().and_then(|f| f.iter().copied().find(|v| !v.is_finite())) {
                return found(
                    v,
                    format!(
                        "the internal force of soil element {} (its Mohr–Coulomb stress update at this iterate)",
                        mesh.solids[s].id
                    ),
                );
            }
        }
    }
    for r in springs {
        for (what, v) in [("shear stress τ", r.tau), ("normal stress σn", r.sigma_n)] {
            if !v.is_finite() {
                let p = &state.interfaces[r.interface].faces[r.face].points[r.point];
                let i = &state.interfaces[r.interface];
                return found(
                    v,
                    format!(
                        "the {what} of interface \"{}\" {} at node {}",
                        i.name,
                        i.faces[r.face].named(),
                        mesh.node_id(p.slave)
                    ),
                );
            }
        }
    }
    None
}

fn multiplier(mesh: &Mesh, state: &State, m: MultiplierRef) -> String {
    describe(mesh, &state.interfaces, m)
}

/// The first non-finite entry of an iteration's right-hand side, or of its matrix.
pub fn in_system(it: &Iterate, rhs: &[f64], triplets: &Triplets) -> Option<NonFinite> {
    let Iterate { mesh, dofs, state, .. } = *it;
    if let Some((e, &v)) = rhs.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        let what = if e < dofs.free_count { "the out-of-balance force at" } else { "the gap of" };
        return Some(NonFinite { value: v, location: format!("{what} {}", dofs.describe(e, mesh, &state.interfaces)) });
    }
    let k = triplets.values.iter().position(|v| !v.is_finite())?;
    Some(NonFinite {
        value: triplets.values[k],
        location: format!(
            "the matrix entry of {} against {}",
            dofs.describe(triplets.rows[k] as usize, mesh, &state.interfaces),
            dofs.describe(triplets.cols[k] as usize, mesh, &state.interfaces)
        ),
    })
}

/// The first non-finite entry of a solution (the matrix was finite: it is too ill-conditioned for
/// the solver).
pub fn in_solution(it: &Iterate, x: &[f64]) -> Option<NonFinite> {
    let (e, &v) = x.iter().enumerate().find(|(_, v)| !v.is_finite())?;
    Some(NonFinite {
        value: v,
        location: format!(
            "the solution for {} (the matrix was finite: it is too ill-conditioned for the solver, as from \
             stiffnesses many orders of magnitude apart)",
            it.dofs.describe(e, it.mesh, &it.state.interfaces)
        ),
    })
}

#[cfg(test)]
mod tests {
    //! Where a NaN is named: the first place in the order the iteration computes, on a one-element
    //! block (nodes 1 and 2 held, 3 and 4 free).
    use super::*;
    use crate::analysis::options::RunOptions;
    use crate::model::{parse, Model};
    use std::path::Path;

    const BLOCK: &str = r#"
units = { length = "m", force = "kN" }
nodes = [[1, 0.0, 0.0], [2, 1.0, 0.0], [3, 1.0, 1.0], [4, 0.0, 1.0]]
elements = [{ id = 1, type = "quad4", nodes = [1, 2, 3, 4], material = "clay" }]
[materials.soil.clay]
youngs_modulus = 10000.0
poissons_ratio = 0.3
unit_weight = 18.0
[node_sets]
bottom = [1, 2]
[[supports]]
set = "bottom"
fix = ["x", "y"]
[[stages]]
name = "load"
"#;

    fn block() -> (Model, DofMap, State) {
        let path = Path::new("block.toml");
        let model = Model::from_file(path, &parse(path, BLOCK).unwrap()).unwrap();
        let held: Vec<bool> = (0..8).map(|d| d < 4).collect();
        let dofs = DofMap::new(4, &held, &model.interfaces);
        let state = State::initial(&model, &RunOptions::default());
        (model, dofs, state)
    }

    #[test]
    fn the_first_place_in_the_order_of_computation_is_named() {
        let (model, dofs, mut state) = block();
        let iterate = |state: &State| {
            in_iterate(&Iterate { mesh: &model.mesh, dofs: &dofs, state, soil_trial: None, springs: &[] })
                .map(|n| n.location)
        };
        assert!(iterate(&state).is_none());
        state.f_ext[7] = f64::INFINITY;
        assert_eq!(iterate(&state).unwrap(), "the applied load at node 4 uy");
        // a displacement comes before the load in the order of computation
        state.u[4] = f64::NAN;
        assert_eq!(iterate(&state).unwrap(), "the displacement node 3 ux");
    }

    #[test]
    fn the_system_and_the_solution_name_their_unknown() {
        let (model, dofs, state) = block();
        let iterate = Iterate { mesh: &model.mesh, dofs: &dofs, state: &state, soil_trial: None, springs: &[] };
        let mut rhs = vec![0.0; dofs.size()];
        let mut triplets = Triplets::default();
        triplets.push(0, 0, 1.0);
        triplets.push(1, 0, f64::NAN);
        let first = in_system(&iterate, &rhs, &triplets).unwrap();
        assert!(first.value.is_nan());
        assert_eq!(
            first.location,
            "the matrix entry of node 3 uy (at x = 1.000, y = 1.000) against node 3 ux (at x = 1.000, y = 1.000)"
        );
        rhs[2] = f64::NEG_INFINITY;
        assert_eq!(
            in_system(&iterate, &rhs, &triplets).unwrap().location,
            "the out-of-balance force at node 4 ux (at x = 0.000, y = 1.000)"
        );
        let x = [0.0, 0.0, 0.0, f64::NAN];
        assert!(in_solution(&iterate, &x).unwrap().location.starts_with("the solution for node 4 uy"));
    }
}
