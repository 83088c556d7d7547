//! The `[design]` table: what the design checks need, gathered from the checked model.

use crate::design::{DesignParameters, Wall, WallInputs};
use crate::error::Problem;
use crate::model::{Load, Model};

/// The wall that `parameters` describe in `model`.
pub(super) fn wall(model: &Model, parameters: &DesignParameters) -> Result<Wall, Problem> {
    let name = &parameters.reinforced_soil;
    let Some(fill) = model.soils.iter().position(|(n, _)| n == name) else {
        return Err(Problem {
            field: "design.reinforced_soil".into(),
            entity: Some(format!("material \"{name}\"")),
            message: "is not a soil material of the model".into(),
        });
    };
    let mesh = &model.mesh;
    if mesh.geometry.is_axisymmetric() {
        return Err(Problem {
            field: "design".into(),
            entity: None,
            message: "the design methods are for plane-strain walls; this model is axisymmetric".into(),
        });
    }
    let soil = &model.soils[fill].1;
    let fill_points = mesh
        .solids
        .iter()
        .filter(|s| s.material == fill)
        .flat_map(|s| s.nodes.iter().map(|&n| mesh.position(n)))
        .collect();
    let reinforcements = model
        .interfaces
        .iter()
        .filter_map(|i| {
            let nodes = model.node_sets.get(&format!("{}.reinforcement", i.name))?;
            Some((i.name.clone(), nodes.iter().map(|&n| mesh.position(n)).collect()))
        })
        .collect();
    let edge_tractions = model
        .stages
        .iter()
        .flat_map(|stage| &stage.loads)
        .filter_map(|load| match load {
            Load::EdgeTraction { sides, pressure, .. } => {
                let ys = sides
                    .iter()
                    .flat_map(|side| {
                        let solid = &mesh.solids[side.solid];
                        solid.kind.sides()[side.side].iter().map(move |&k| mesh.position(solid.nodes[k])[1])
                    })
                    .collect();
                Some((*pressure, ys))
            }
            _ => None,
        })
        .collect();
    let inputs = WallInputs {
        unit_weight: soil.unit_weight,
        friction_angle_degrees: soil.friction_angle,
        fill_points,
        reinforcements,
        edge_tractions,
        metre: Model::metre(&model.units),
    };
    Wall::new(parameters, &inputs)
}
