//! The mesh as the file lists it: nodes, soil elements (with their Jacobians) and hand-made bars.

use super::Draft;
use crate::element::geometry::Geometry;
use crate::element::solid::{mapped_points, BadJacobian, Integration};
use crate::mesh::{Bar, Solid};
use crate::model::file::*;
use crate::model::problems::Problems;
use std::collections::HashSet;

/// The largest node or element id: the largest integer a TOML file can hold, so that a JSON file
/// cannot give ids a TOML file cannot, and the ids added after the largest one (the nodes and bars
/// of a split reinforcement) cannot overflow.
pub(super) const MAX_ID: u64 = i64::MAX as u64;

/// In an axisymmetric model, a node whose x is within this fraction of the model's largest
/// coordinate of the axis is on the axis.
pub(crate) const AXIS_TOLERANCE: f64 = 1e-9;

/// Nodes, soil elements and bars (soil elements and bars share one id space).
pub(super) fn mesh(d: &mut Draft, file: &ModelFile, p: &mut Problems) {
    let Draft { mesh, element_ids, mesh_ok, soil_index, reinf_index, .. } = d;
    if file.nodes.is_empty() {
        p.push("nodes", None, "the model has no nodes");
    }
    for (k, NodeRow(id, x, y)) in file.nodes.iter().enumerate() {
        let entity = format!("node {id}");
        if mesh.node_index(*id).is_some() {
            p.push(format!("nodes[{k}]"), &entity, format!("duplicate node id {id}"));
            continue;
        }
        if !(x.is_finite() && y.is_finite()) {
            p.push(format!("nodes[{k}]"), &entity, format!("coordinates must be finite numbers, found ({x}, {y})"));
        }
        if *id > MAX_ID || *id == 0 {
            p.push(format!("nodes[{k}]"), &entity, format!("node ids are from 1 to {MAX_ID}, found {id}"));
            *mesh_ok = false;
        }
        mesh.add_node(*id, [*x, *y]);
    }
    mesh.geometry = file.analysis.geometry;
    if mesh.geometry.is_axisymmetric() {
        // x is the radius: nothing may lie on the other side of the axis (a node within round-off
        // of it is on the axis, and its radial displacement is held there)
        let tol = AXIS_TOLERANCE * file.nodes.iter().fold(0.0f64, |m, NodeRow(_, x, y)| m.max(x.abs()).max(y.abs()));
        for (k, NodeRow(id, x, _)) in file.nodes.iter().enumerate() {
            if *x < -tol {
                p.push(
                    format!("nodes[{k}]"),
                    format!("node {id}"),
                    format!(
                        "x is the radius in an axisymmetric model (analysis.geometry) and must be ≥ 0, found {x}: \
                         draw the body on the positive side of the axis x = 0"
                    ),
                );
                *mesh_ok = false;
            }
        }
    }

    // Soil elements and bars share one id space.
    for (k, e) in file.elements.iter().enumerate() {
        let entity = format!("element {}", e.id);
        let field = format!("elements[{k}]");
        let before = p.len();
        if !element_ids.insert(e.id) {
            p.push(format!("{field}.id"), &entity, format!("duplicate element id {}", e.id));
        }
        if e.id > MAX_ID || e.id == 0 {
            p.push(format!("{field}.id"), &entity, format!("element ids are from 1 to {MAX_ID}, found {}", e.id));
        }
        if e.nodes.len() != e.kind.node_count() {
            p.push(
                format!("{field}.nodes"),
                &entity,
                format!("a {} element has {} nodes, found {}", e.kind.name(), e.kind.node_count(), e.nodes.len()),
            );
        }
        let mut nodes = Vec::new();
        for (j, id) in e.nodes.iter().enumerate() {
            match mesh.node_index(*id) {
                Some(i) => nodes.push(i),
                None => p.push(format!("{field}.nodes[{j}]"), &entity, format!("node {id} does not exist")),
            }
        }
        let distinct: HashSet<_> = e.nodes.iter().collect();
        if distinct.len() != e.nodes.len() {
            p.push(format!("{field}.nodes"), &entity, "the same node appears twice");
        }
        let material = soil_index.get(e.material.as_str()).copied();
        if material.is_none() {
            p.push(format!("{field}.material"), &entity, format!("no soil material named \"{}\"", e.material));
        }
        let coords: Vec<[f64; 2]> = nodes.iter().map(|&i| mesh.position(i)).collect();
        // A node with non-finite coordinates is reported under `nodes`; its elements have no area
        // to check.
        let finite = coords.iter().all(|c| c[0].is_finite() && c[1].is_finite());
        if !finite {
            *mesh_ok = false;
        }
        if p.len() == before && finite {
            // every rule the run integrates with: the full one, and the 2×2 one of quad8 elements
            // under reduced integration
            let full = mapped_points(e.kind, &coords, Integration::Full, Geometry::PlaneStrain).err();
            let reduced = file.analysis.reduced_integration && full.is_none();
            let bad = match full {
                None if reduced => mapped_points(e.kind, &coords, Integration::Reduced, Geometry::PlaneStrain).err(),
                full => full,
            };
            // then in the run's own formulation: an axisymmetric element must have every Gauss
            // point right of the axis (the run divides by the radius there)
            let axis = match bad {
                None if mesh.geometry.is_axisymmetric() => [Integration::Full]
                    .into_iter()
                    .chain(reduced.then_some(Integration::Reduced))
                    .find_map(|rule| mapped_points(e.kind, &coords, rule, mesh.geometry).err()),
                _ => None,
            };
            if let Some(BadJacobian { det }) = axis {
                p.push(
                    format!("{field}.nodes"),
                    &entity,
                    format!(
                        "has a Gauss point at radius {det:.3e}, on or left of the axis: an axisymmetric model divides by the \
                         radius there (an element touching the axis must be at least as wide as its other sides are long; \
                         refine the mesh along the axis, or move the element right of it)"
                    ),
                );
            }
            if let Some(BadJacobian { det }) = bad {
                let msg = if reduced {
                    "is too distorted for reduced integration: its Jacobian is not positive at a 2×2 Gauss point \
                     (move its mid-side nodes towards the middle of its sides, or set reduced_integration = false)"
                        .to_string()
                } else if det < 0.0 {
                    "has negative area or is inverted: list its corners counter-clockwise".to_string()
                } else {
                    "has zero area (its nodes are collinear or coincide)".to_string()
                };
                p.push(format!("{field}.nodes"), &entity, msg);
            }
        }
        if p.len() == before {
            mesh.solids.push(Solid { id: e.id, kind: e.kind, nodes, material: material.unwrap_or(0) });
        } else {
            *mesh_ok = false;
        }
    }
    for (k, b) in file.bars.iter().enumerate() {
        let entity = format!("bar {}", b.id);
        let field = format!("bars[{k}]");
        let before = p.len();
        if !element_ids.insert(b.id) {
            p.push(format!("{field}.id"), &entity, format!("duplicate element id {}", b.id));
        }
        if b.id > MAX_ID || b.id == 0 {
            p.push(format!("{field}.id"), &entity, format!("element ids are from 1 to {MAX_ID}, found {}", b.id));
        }
        let mut nodes = [0usize; 2];
        for (j, id) in b.nodes.iter().enumerate() {
            match mesh.node_index(*id) {
                Some(i) => nodes[j] = i,
                None => p.push(format!("{field}.nodes[{j}]"), &entity, format!("node {id} does not exist")),
            }
        }
        let material = reinf_index.get(b.material.as_str()).copied();
        if material.is_none() {
            p.push(format!("{field}.material"), &entity, format!("no reinforcement material named \"{}\"", b.material));
        }
        if p.len() == before {
            let (a, c) = (mesh.position(nodes[0]), mesh.position(nodes[1]));
            if ((a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2)).sqrt()
                <= 1e-12 * mesh.characteristic_length().max(1e-300)
            {
                p.push(format!("{field}.nodes"), &entity, "the bar has zero length");
            }
        }
        if p.len() == before {
            mesh.bars.push(Bar { id: b.id, nodes, material: material.unwrap_or(0) });
        } else {
            *mesh_ok = false;
        }
    }
    if file.elements.is_empty() && file.bars.is_empty() {
        p.push("elements", None, "the model has no elements");
    }
}
