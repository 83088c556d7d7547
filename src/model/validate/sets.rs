//! Named sets: node sets, edge sets (each edge resolved to an element side, which survives a
//! split) and element sets.

use super::Draft;
use crate::mesh::{NodeIndex, SideMap};
use crate::model::file::*;
use crate::model::problems::Problems;
use crate::model::LoadedSide;
use std::collections::HashMap;

/// Node sets and edge sets.
pub(super) fn node_and_edge_sets(d: &mut Draft, file: &ModelFile, p: &mut Problems) {
    let Draft { mesh, node_sets, edge_sets, mesh_ok, .. } = d;
    for (name, ids) in &file.node_sets {
        let mut set = Vec::new();
        for (k, id) in ids.iter().enumerate() {
            match mesh.node_index(*id) {
                Some(i) => set.push(i),
                None => p.push(
                    format!("node_sets.{name}[{k}]"),
                    format!("node set \"{name}\""),
                    format!("node {id} does not exist"),
                ),
            }
        }
        node_sets.insert(name.clone(), set);
    }
    let sides = SideMap::new(mesh);
    // (the elements built, wanted only when some could not be)
    let built: std::collections::HashSet<u64> =
        if *mesh_ok { Default::default() } else { mesh.solids.iter().map(|e| e.id).collect() };
    let broken_at = |edge: &[u64]| {
        file.elements
            .iter()
            .find(|e| !*mesh_ok && !built.contains(&e.id) && edge.iter().any(|n| e.nodes.contains(n)))
            .map(|e| e.id)
    };
    for (name, edges) in &file.edge_sets {
        let entity = format!("edge set \"{name}\"");
        let mut list = Vec::new();
        for (k, edge) in edges.iter().enumerate() {
            let field = format!("edge_sets.{name}[{k}]");
            let idx: Option<Vec<NodeIndex>> = edge.iter().map(|id| mesh.node_index(*id)).collect();
            let Some(idx) = idx else {
                let missing: Vec<String> =
                    edge.iter().filter(|id| mesh.node_index(**id).is_none()).map(|id| id.to_string()).collect();
                p.push(field, &entity, format!("node {} does not exist", missing.join(", ")));
                continue;
            };
            if idx.len() != 2 && idx.len() != 3 {
                p.push(field, &entity, format!("an edge has 2 nodes (or 3 for a quadratic side), found {}", idx.len()));
                continue;
            }
            let found = sides.between(idx[0], idx[1]);
            match found.as_slice() {
                [] => match broken_at(edge) {
                    // an element of the file at these nodes that could not be built: its own
                    // problem is the one to fix, and this edge's follows from it
                    Some(id) => p.push(
                        field,
                        &entity,
                        format!(
                            "nodes {} and {} are not the corners of an element side; element {id} at them has a problem \
                             of its own (above): fix that first",
                            edge[0], edge[1]
                        ),
                    ),
                    None => p.push(field, &entity, format!("nodes {} and {} are not the corners of an element side", edge[0], edge[1])),
                },
                [s] => {
                    let solid = &mesh.solids[s.solid];
                    let local = solid
                        .kind
                        .sides()
                        .iter()
                        .position(|side| {
                            let (a, b) = (solid.nodes[side[0]], solid.nodes[side[1]]);
                            (a == idx[0] && b == idx[1]) || (a == idx[1] && b == idx[0])
                        })
                        .unwrap_or(0);
                    let side_nodes = &solid.kind.sides()[local];
                    if side_nodes.len() != idx.len() {
                        p.push(field, &entity, format!("the side belongs to a {} element and has {} nodes, found {}", solid.kind.name(), side_nodes.len(), idx.len()));
                    } else if idx.len() == 3 && solid.nodes[side_nodes[2]] != idx[2] {
                        p.push(field, &entity, format!("node {} is not the mid-side node of side {}–{}", edge[2], edge[0], edge[1]));
                    } else {
                        list.push(LoadedSide { solid: s.solid, side: local });
                    }
                }
                _ => p.push(field, &entity, format!("the side {}–{} lies inside the soil (elements on both sides): a traction needs a boundary side", edge[0], edge[1])),
            }
        }
        edge_sets.insert(name.clone(), list);
    }
}

/// Element sets: soil element ids → indices.
pub(super) fn element_sets(d: &mut Draft, file: &ModelFile, p: &mut Problems) {
    let Draft { mesh, element_sets, .. } = d;
    let solid_index: HashMap<u64, usize> = mesh.solids.iter().enumerate().map(|(i, e)| (e.id, i)).collect();
    for (name, ids) in &file.element_sets {
        let mut set = Vec::new();
        for (k, id) in ids.iter().enumerate() {
            match solid_index.get(id) {
                Some(&i) => set.push(i),
                None => p.push(
                    format!("element_sets.{name}[{k}]"),
                    format!("element {id}"),
                    "no soil element has this id (element sets hold soil elements)",
                ),
            }
        }
        element_sets.insert(name.clone(), set);
    }
}
