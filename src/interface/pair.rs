//! Hand-made interfaces: a slave line and its master face given node by node (a block on a rigid
//! base, a tied soil-to-soil joint, double nodes made by hand). Geometry only: what is wrong comes
//! back as [`GeometryProblem`]s.

use super::{points_on, project, ContactFace, GeometryProblem, GeometryProblems, Interface, ShearLaw};
use crate::mesh::{Mesh, NodeIndex, SideMap};
use std::collections::HashMap;

/// The side of a rigid master face that `normal` (a unit vector) points into: whether it is the left
/// of each segment a → b. A segment whose own normal on that side is more than 60° from `normal`
/// is a problem: the face is not the one the normal describes.
fn rigid_side(mesh: &Mesh, master: &[NodeIndex], normal: [f64; 2], problems: &mut GeometryProblems) -> bool {
    let left_normal = |k: usize| {
        let (a, b) = (mesh.position(master[k]), mesh.position(master[k + 1]));
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = d[0].hypot(d[1]);
        // (a segment of no length has no normal: NaN, refused below)
        [-d[1] / len, d[0] / len]
    };
    let first = left_normal(0);
    let left = first[0] * normal[0] + first[1] * normal[1] >= 0.0;
    for k in 0..master.len() - 1 {
        let n = left_normal(k);
        let cos = (n[0] * normal[0] + n[1] * normal[1]) * if left { 1.0 } else { -1.0 };
        if cos.is_nan() {
            problems.push(
                format!("master[{k}..{}]", k + 1),
                format!(
                    "the master segment {}–{} has no length: its nodes are at the same place",
                    mesh.node_id(master[k]),
                    mesh.node_id(master[k + 1])
                ),
            );
        } else if cos < 0.5 {
            let side = if left { n } else { [-n[0], -n[1]] };
            problems.push(
                "master_normal",
                format!(
                    "master_normal [{:.4}, {:.4}] is {:.1}° from the normal [{:.4}, {:.4}] of the master segment {}–{} (at most 60°): give the normal into the master side of the face",
                    normal[0],
                    normal[1],
                    cos.clamp(-1.0, 1.0).acos().to_degrees(),
                    side[0],
                    side[1],
                    mesh.node_id(master[k]),
                    mesh.node_id(master[k + 1])
                ),
            );
        }
    }
    left
}

/// Associate a hand-made slave line with its master face.
pub fn pair(
    mesh: &Mesh,
    sides: &SideMap,
    name: &str,
    slave_ids: &[u64],
    master_ids: &[u64],
    master_normal: Option<[f64; 2]>,
    law: ShearLaw,
) -> Result<Interface, Vec<GeometryProblem>> {
    let mut problems = GeometryProblems::default();
    let mut resolve = |ids: &[u64], what: &str| -> Vec<NodeIndex> {
        let mut out = Vec::new();
        for (k, &id) in ids.iter().enumerate() {
            match mesh.node_index(id) {
                Some(i) => out.push(i),
                None => problems.push(format!("{what}[{k}]"), format!("node {id} does not exist")),
            }
        }
        out
    };
    let slave = resolve(slave_ids, "slave");
    let master = resolve(master_ids, "master");
    problems.check()?;
    if slave.len() < 2 {
        problems.push("slave", "a slave line needs at least 2 nodes");
    }
    if master.len() < 2 {
        problems.push("master", "a master face needs at least 2 nodes");
    }
    for (what, line) in [("slave", &slave), ("master", &master)] {
        let mut seen = HashMap::new();
        for (k, &n) in line.iter().enumerate() {
            if let Some(first) = seen.insert(n, k) {
                problems.push(
                    format!("{what}[{k}]"),
                    format!("node {} appears twice in the {what} line (first at position {first})", mesh.node_id(n)),
                );
            }
        }
    }
    if let Some(&s) = slave.iter().find(|s| master.contains(s)) {
        problems.push("slave", format!("node {} is on both the slave line and the master face", mesh.node_id(s)));
    }
    problems.check()?;
    let mut soil_left = None;
    let mut any_side = false;
    for k in 0..master.len() - 1 {
        let (a, b) = (mesh.node_id(master[k]), mesh.node_id(master[k + 1]));
        let found = sides.between(master[k], master[k + 1]);
        if found.iter().any(|s| s.quadratic) {
            problems.push(
                format!("master[{k}..{}]", k + 1),
                format!("the side {a}–{b} belongs to a quadratic element: interfaces on quadratic faces are not yet supported"),
            );
            continue;
        }
        match found.len() {
            0 => {}
            1 => {
                any_side = true;
                let left = found[0].solid_on_left;
                if *soil_left.get_or_insert(left) != left {
                    problems.push(
                        format!("master[{k}..{}]", k + 1),
                        format!("the side {a}–{b} has its soil on the other side from the rest of the master face"),
                    );
                }
            }
            _ => problems.push(
                format!("master[{k}..{}]", k + 1),
                format!("the side {a}–{b} has soil on both sides: a master face must be a free face of the soil (split the mesh, or use a reinforcement interface)"),
            ),
        }
        if found.is_empty() && master_normal.is_none() {
            problems.push(
                format!("master[{k}..{}]", k + 1),
                format!("nodes {a} and {b} are not joined by a soil element side; a master face with no soil (a rigid base) needs master_normal"),
            );
        }
    }
    let fixed_normal = match master_normal {
        Some(_) if any_side => {
            problems.push(
                "master_normal",
                "master_normal is only for a master face with no soil element; this face's normal comes from its soil",
            );
            None
        }
        Some(n) => {
            let l = (n[0] * n[0] + n[1] * n[1]).sqrt();
            if !(l.is_finite() && l > 0.0) {
                problems.push("master_normal", "master_normal must be a non-zero, finite vector");
                None
            } else {
                let n = [n[0] / l, n[1] / l];
                // it picks the side; each segment's normal is its own, within 60° of it
                soil_left = Some(rigid_side(mesh, &master, n, &mut problems));
                Some(n)
            }
        }
        None => None,
    };
    problems.check()?;
    let face = ContactFace {
        label: "face".into(),
        points: points_on(mesh, &master, &slave),
        master,
        soil_on_left: soil_left.unwrap_or(true),
        fixed_normal,
        law,
        embedded: None,
        dilation: None,
        bearing: None,
    };
    // Every slave node must sit on its master face.
    let tol = 1e-6 * mesh.characteristic_length();
    for (k, p) in face.points.iter().enumerate() {
        let x = mesh.position(p.slave);
        let (_, _, signed, outside) = project(mesh, &face.master, x);
        if outside {
            problems.push(
                format!("slave[{k}]"),
                format!(
                    "slave node {} does not face the master face (it projects beyond its ends)",
                    mesh.node_id(p.slave)
                ),
            );
        } else if signed.abs() > tol {
            problems.push(
                format!("slave[{k}]"),
                format!(
                    "slave node {} is {:.3e} off its master face: slave and master must start in contact",
                    mesh.node_id(p.slave),
                    signed.abs()
                ),
            );
        }
    }
    problems.check()?;
    Ok(Interface { name: name.to_string(), faces: vec![face], slit_of: None })
}
