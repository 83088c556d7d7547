//! Every connected body must be held: a model whose soil, bars and interfaces leave a body free to
//! translate or rotate has no unique answer.

use crate::interface::Interface;
use crate::mesh::{Mesh, NodeIndex};
use crate::model::file::Direction;
use crate::model::problems::Problems;
use crate::model::StagePlan;
use std::collections::{BTreeMap, HashMap};

/// Every connected body (soil, bars and the interfaces that join them) must be held against both
/// translations and the rotation by the supports and the first stage's prescribed displacements.
pub(super) fn check_free_bodies(
    mesh: &Mesh,
    interfaces: &[Interface],
    supports: &[(NodeIndex, Direction)],
    first_stage: Option<&StagePlan>,
    p: &mut Problems,
) {
    let n = mesh.nodes.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut used = vec![false; n];
    let join = |parent: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (find(parent, a), find(parent, b));
        parent[ra] = rb;
    };
    for s in &mesh.solids {
        for w in s.nodes.windows(2) {
            join(&mut parent, w[0], w[1]);
        }
        for &v in &s.nodes {
            used[v] = true;
        }
    }
    for b in &mesh.bars {
        join(&mut parent, b.nodes[0], b.nodes[1]);
        used[b.nodes[0]] = true;
        used[b.nodes[1]] = true;
    }
    for i in interfaces {
        for f in &i.faces {
            for pt in &f.points {
                join(&mut parent, pt.slave, f.master[pt.segment]);
                join(&mut parent, pt.slave, f.master[pt.segment + 1]);
            }
            // a rigid master face (no soil element) is made of nodes used by the interface alone
            if f.fixed_normal.is_some() {
                for &m in &f.master {
                    used[m] = true;
                }
                for w in f.master.windows(2) {
                    join(&mut parent, w[0], w[1]);
                }
            }
        }
    }
    for (i, &u) in used.iter().enumerate() {
        if !u {
            p.push(
                "nodes",
                format!("node {}", mesh.node_id(i)),
                "the node belongs to no element or bar: remove it or connect it",
            );
        }
    }
    let mut held: Vec<(NodeIndex, Direction)> = supports.to_vec();
    if let Some(s) = first_stage {
        held.extend(s.prescribed.iter().map(|&(n, d, _)| (n, d)));
    }
    let mut bodies: BTreeMap<usize, Vec<NodeIndex>> = BTreeMap::new();
    for i in (0..n).filter(|&i| used[i]) {
        bodies.entry(find(&mut parent, i)).or_default().push(i);
    }
    let mut held_by_body: HashMap<usize, Vec<(NodeIndex, Direction)>> = HashMap::new();
    for &(node, d) in &held {
        held_by_body.entry(find(&mut parent, node)).or_default().push((node, d));
    }
    for (root, nodes) in bodies {
        let c = nodes.iter().fold([0.0, 0.0], |acc, &i| {
            let x = mesh.position(i);
            [acc[0] + x[0] / nodes.len() as f64, acc[1] + x[1] / nodes.len() as f64]
        });
        let rows: Vec<[f64; 3]> = held_by_body
            .get(&root)
            .map(|v| {
                v.iter()
                    .map(|&(i, d)| {
                        let x = mesh.position(i);
                        match d {
                            Direction::X => [1.0, 0.0, -(x[1] - c[1])],
                            Direction::Y => [0.0, 1.0, x[0] - c[0]],
                        }
                    })
                    .collect()
            })
            .unwrap_or_default();
        // a body of revolution cannot move radially or rotate without straining its hoops: only a
        // translation along the axis is free
        let free = if mesh.geometry.is_axisymmetric() {
            if rows.iter().any(|r| r[1] != 0.0) {
                Vec::new()
            } else {
                vec!["translate along the axis (y)"]
            }
        } else {
            free_rigid_modes(&rows, mesh.characteristic_length())
        };
        if !free.is_empty() {
            let mut ids: Vec<u64> = nodes.iter().map(|&i| mesh.node_id(i)).collect();
            ids.sort_unstable();
            let shown: Vec<String> = ids.iter().take(8).map(|i| i.to_string()).collect();
            let more = if ids.len() > 8 { format!(" and {} more", ids.len() - 8) } else { String::new() };
            p.push(
                "supports",
                format!("the body of nodes {}{more}", shown.join(", ")),
                format!("is free to {} in the first stage: add supports", free.join(" and ")),
            );
        }
    }
}

/// Which rigid-body modes (translate in x, translate in y, rotate) the held DOFs leave free.
fn free_rigid_modes(rows: &[[f64; 3]], length: f64) -> Vec<&'static str> {
    // Scale rotation by a length so that the three columns are comparable, then test each mode
    // against the span of the rows.
    let scaled: Vec<[f64; 3]> = rows.iter().map(|r| [r[0], r[1], r[2] / length.max(1e-300)]).collect();
    // Orthonormal basis of the row space.
    let mut basis: Vec<[f64; 3]> = Vec::new();
    for r in &scaled {
        let mut v = *r;
        for b in &basis {
            let d = v[0] * b[0] + v[1] * b[1] + v[2] * b[2];
            for k in 0..3 {
                v[k] -= d * b[k];
            }
        }
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if norm > 1e-8 {
            basis.push([v[0] / norm, v[1] / norm, v[2] / norm]);
        }
    }
    if basis.len() == 3 {
        return Vec::new();
    }
    // A mode m is free when it is orthogonal to the row space's complement test: project it out.
    let modes = [([1.0, 0.0, 0.0], "translate in x"), ([0.0, 1.0, 0.0], "translate in y"), ([0.0, 0.0, 1.0], "rotate")];
    let mut free = Vec::new();
    for (m, name) in modes {
        // m is restrained if some held row has a component along it, i.e. m is not orthogonal to the
        // row space.
        let along: f64 = basis.iter().map(|b| (b[0] * m[0] + b[1] * m[1] + b[2] * m[2]).powi(2)).sum();
        if along < 1e-12 {
            free.push(name);
        }
    }
    if free.is_empty() {
        // Rank < 3 but every single mode is touched: a combination is free.
        free.push("move as a rigid body");
    }
    free
}
