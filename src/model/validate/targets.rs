//! The nodes that supports, loads and prescribed displacements target: a node, a list of nodes
//! or a node set; and the supports.

use super::Draft;
use crate::mesh::NodeIndex;
use crate::model::file::*;
use crate::model::problems::Problems;

impl Draft {
    /// The nodes `target` names (with the twins a split made, when `with_twins`); what does not
    /// exist is reported under `field`.
    pub(super) fn resolve(
        &self,
        target: NodeTarget,
        field: &str,
        p: &mut Problems,
        with_twins: bool,
    ) -> Vec<NodeIndex> {
        let NodeTarget { node, nodes, set } = target;
        let given = node.is_some() as u8 + nodes.is_some() as u8 + set.is_some() as u8;
        if given != 1 {
            p.push(field, target_label(node, nodes, set), "give exactly one of `node`, `nodes` or `set`");
            return Vec::new();
        }
        let mut out = Vec::new();
        let ids: Vec<u64> = match (node, nodes) {
            (Some(n), _) => vec![n],
            (_, Some(ns)) => ns.to_vec(),
            _ => Vec::new(),
        };
        for id in ids {
            match self.mesh.node_index(id) {
                Some(i) => {
                    out.push(i);
                    if with_twins {
                        out.extend(self.twins.get(&i));
                    }
                }
                None => p.push(field, format!("node {id}"), format!("node {id} does not exist")),
            }
        }
        if let Some(s) = set {
            match self.node_sets.get(s) {
                Some(v) => out.extend(v),
                None => p.push(field, format!("node set \"{s}\""), format!("no node set named \"{s}\"")),
            }
        }
        out
    }
}

/// The supports: each node and direction once.
pub(super) fn supports(d: &mut Draft, file: &ModelFile, p: &mut Problems) {
    for (k, s) in file.supports.iter().enumerate() {
        let t = s.target();
        let field = format!("supports[{k}]");
        if s.fix.is_empty() {
            p.push(
                format!("{field}.fix"),
                target_label(t.node, t.nodes, t.set),
                "list the directions to fix: [\"x\"], [\"y\"] or [\"x\", \"y\"]",
            );
        }
        for n in d.resolve(t, &field, p, true) {
            for &dir in &s.fix {
                if d.supported.insert((n, dir)) {
                    d.supports.push((n, dir));
                }
            }
        }
    }
    // on the axis of an axisymmetric body the radial displacement is zero by symmetry
    if d.mesh.geometry.is_axisymmetric() {
        let tol = super::mesh::AXIS_TOLERANCE
            * d.mesh.nodes.iter().fold(0.0f64, |m, n| m.max(n.x[0].abs()).max(n.x[1].abs()));
        for n in 0..d.mesh.nodes.len() {
            if d.mesh.nodes[n].x[0].abs() <= tol && d.supported.insert((n, Direction::X)) {
                d.supports.push((n, Direction::X));
            }
        }
    }
}

/// Names what a support, load or prescribed displacement targets, as written: `node 3`,
/// `nodes 1, 2`, `node set "left"` (joined by "and" when several are given), or `no node, nodes or
/// set` when none is.
pub(super) fn target_label(node: Option<u64>, nodes: Option<&[u64]>, set: Option<&str>) -> String {
    let mut parts = Vec::new();
    if let Some(n) = node {
        parts.push(format!("node {n}"));
    }
    if let Some(ns) = nodes {
        let ids: Vec<String> = ns.iter().map(|i| i.to_string()).collect();
        parts.push(format!("nodes {}", ids.join(", ")));
    }
    if let Some(s) = set {
        parts.push(format!("node set \"{s}\""));
    }
    if parts.is_empty() {
        "no node, nodes or set".to_string()
    } else {
        parts.join(" and ")
    }
}
