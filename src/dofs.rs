//! DOF numbering: unknowns are `[u_free | λ]`.
//!
//! Displacement DOF `2·node + d` (d = 0 for x, 1 for y) gets an equation number unless it is held
//! (a support, or a DOF prescribed in this or an earlier stage): held DOFs are eliminated, not
//! imposed by multipliers. Multipliers follow, one per normal row of every interface point and one
//! per tangential row of every `tie` point, in a fixed order that does not change between stages.

use crate::interface::Interface;
pub use crate::interface::{multipliers, MultiplierRef};
use crate::mesh::Mesh;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A displacement direction (the model file's `direction`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, JsonSchema)]
pub enum Direction {
    #[serde(rename = "x")]
    X,
    #[serde(rename = "y")]
    Y,
}

/// The global DOF `2·node + d` of a node's displacement in a direction.
pub fn dof(node: usize, d: Direction) -> usize {
    2 * node + if d == Direction::X { 0 } else { 1 }
}

#[derive(Debug, Clone)]
pub struct DofMap {
    /// Equation number of each displacement DOF, `None` when held. Set by [`DofMap::new`] and not
    /// changed after: `equation_key` is made from it there.
    pub equation: Vec<Option<usize>>,
    pub free_count: usize,
    pub multipliers: Vec<MultiplierRef>,
    /// A fingerprint of `equation`, made once (a matrix's key hashes it every iteration).
    equation_key: u64,
}

impl DofMap {
    pub fn new(node_count: usize, held: &[bool], interfaces: &[Interface]) -> DofMap {
        let mut equation = vec![None; 2 * node_count];
        let mut next = 0;
        for (dof, eq) in equation.iter_mut().enumerate() {
            if !held[dof] {
                *eq = Some(next);
                next += 1;
            }
        }
        let equation_key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::collections::hash_map::DefaultHasher::new();
            equation.hash(&mut h);
            h.finish()
        };
        DofMap { equation, free_count: next, multipliers: multipliers(interfaces), equation_key }
    }

    /// A fingerprint of which DOFs are free and their equation numbers.
    pub fn equation_key(&self) -> u64 {
        self.equation_key
    }

    /// Number of unknowns of the saddle-point system.
    pub fn size(&self) -> usize {
        self.free_count + self.multipliers.len()
    }

    pub fn multiplier_equation(&self, k: usize) -> usize {
        self.free_count + k
    }

    /// A readable name for unknown `eq`: `node 12 uy (at x = 1.500, y = 0.300)`, or
    /// `the normal multiplier of interface "grid-1" (upper face) at node 40`.
    pub fn describe(&self, eq: usize, mesh: &Mesh, interfaces: &[Interface]) -> String {
        if eq < self.free_count {
            if let Some(dof) = self.equation.iter().position(|e| *e == Some(eq)) {
                let dir = if dof % 2 == 0 { "ux" } else { "uy" };
                // (with its position: a node that splitting a reinforcement's line made is not
                // in the user's mesh file)
                let [x, y] = mesh.position(dof / 2);
                return format!("node {} {dir} (at x = {x:.3}, y = {y:.3})", mesh.node_id(dof / 2));
            }
        } else if let Some(m) = self.multipliers.get(eq - self.free_count) {
            let i = &interfaces[m.interface];
            let f = &i.faces[m.face];
            let kind = if m.tangential { "tangential" } else { "normal" };
            return format!(
                "the {kind} multiplier of interface \"{}\" ({}) at node {}",
                i.name,
                f.named(),
                mesh.node_id(f.points[m.point].slave)
            );
        }
        format!("unknown {eq}")
    }
}
