//! The checked mesh: nodes, soil elements and bars, addressed by dense indices.
//!
//! Ids are the user's (or, for what geoslip creates when it splits the soil along a reinforcement,
//! ids after the largest one in the file). Every index stored here is valid by construction: the
//! validator builds a `Mesh` only after every reference has been resolved.

use crate::element::geometry::Geometry;
use crate::element::solid::SolidKind;
use std::collections::HashMap;

pub type NodeIndex = usize;

#[derive(Debug, Clone)]
pub struct Node {
    pub id: u64,
    /// Reference position [length].
    pub x: [f64; 2],
}

#[derive(Debug, Clone)]
pub struct Solid {
    pub id: u64,
    pub kind: SolidKind,
    pub nodes: Vec<NodeIndex>,
    /// Index into `Model::soils`.
    pub material: usize,
}

#[derive(Debug, Clone)]
pub struct Bar {
    pub id: u64,
    pub nodes: [NodeIndex; 2],
    /// Index into `Model::reinforcements`.
    pub material: usize,
}

#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub nodes: Vec<Node>,
    pub solids: Vec<Solid>,
    pub bars: Vec<Bar>,
    /// Plane strain or axisymmetric: what a length and an area of the mesh weigh.
    pub geometry: Geometry,
    index_of_id: HashMap<u64, NodeIndex>,
}

impl SolidKind {
    pub fn node_count(self) -> usize {
        match self {
            SolidKind::Tri3 => 3,
            SolidKind::Tri6 => 6,
            SolidKind::Quad4 => 4,
            SolidKind::Quad8 => 8,
        }
    }

    pub fn corner_count(self) -> usize {
        match self {
            SolidKind::Tri3 | SolidKind::Tri6 => 3,
            SolidKind::Quad4 | SolidKind::Quad8 => 4,
        }
    }

    pub fn is_quadratic(self) -> bool {
        matches!(self, SolidKind::Tri6 | SolidKind::Quad8)
    }

    pub fn name(self) -> &'static str {
        match self {
            SolidKind::Tri3 => "tri3",
            SolidKind::Tri6 => "tri6",
            SolidKind::Quad4 => "quad4",
            SolidKind::Quad8 => "quad8",
        }
    }

    /// Local node positions of each side: `[corner a, corner b, mid-side (quadratic only)]`,
    /// counter-clockwise, so that the solid lies to the left of a → b.
    pub fn sides(self) -> &'static [&'static [usize]] {
        match self {
            SolidKind::Tri3 => &[&[0, 1], &[1, 2], &[2, 0]],
            SolidKind::Quad4 => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
            SolidKind::Tri6 => &[&[0, 1, 3], &[1, 2, 4], &[2, 0, 5]],
            SolidKind::Quad8 => &[&[0, 1, 4], &[1, 2, 5], &[2, 3, 6], &[3, 0, 7]],
        }
    }
}

/// A side of a soil element, as found by [`Mesh::side_between`].
#[derive(Debug, Clone, Copy)]
pub struct SolidSide {
    pub solid: usize,
    /// True when the solid lies to the left of the direction a → b asked for.
    pub solid_on_left: bool,
    pub quadratic: bool,
}

/// Soil element sides keyed by their (sorted) corner nodes, built once per mesh: one array sorted
/// by key (a hash map of vectors took an allocation per side and grew faster than the mesh).
#[derive(Debug, Clone, Default)]
pub struct SideMap {
    /// (sorted corner pair, (element, its corners in its own order, quadratic side)), by key.
    sides: Vec<((NodeIndex, NodeIndex), SideOwner)>,
}

type SideOwner = (usize, [NodeIndex; 2], bool);

impl SideMap {
    pub fn new(mesh: &Mesh) -> Self {
        let mut sides = Vec::with_capacity(mesh.solids.iter().map(|solid| solid.kind.sides().len()).sum());
        for (s, solid) in mesh.solids.iter().enumerate() {
            for side in solid.kind.sides() {
                let (p, q) = (solid.nodes[side[0]], solid.nodes[side[1]]);
                sides.push(((p.min(q), p.max(q)), (s, [p, q], side.len() == 3)));
            }
        }
        // stable: the owners of one side stay in element order
        sides.sort_by_key(|&(key, _)| key);
        SideMap { sides }
    }

    /// The owners of the side with sorted corners `key`.
    fn owners(&self, key: (NodeIndex, NodeIndex)) -> &[((NodeIndex, NodeIndex), SideOwner)] {
        let start = self.sides.partition_point(|&(k, _)| k < key);
        let end = start + self.sides[start..].partition_point(|&(k, _)| k == key);
        &self.sides[start..end]
    }

    /// Every soil element side joining corner nodes `a` and `b` (in either order).
    pub fn between(&self, a: NodeIndex, b: NodeIndex) -> Vec<SolidSide> {
        self.owners((a.min(b), a.max(b)))
            .iter()
            .map(|&(_, (solid, [p, _], quadratic))| SolidSide { solid, solid_on_left: p == a, quadratic })
            .collect()
    }

    /// Corner nodes that lie on the mesh boundary (on a side that belongs to one element only).
    pub fn boundary_nodes(&self, node_count: usize) -> Vec<bool> {
        let mut on_boundary = vec![false; node_count];
        for group in self.sides.chunk_by(|a, b| a.0 == b.0) {
            if let [((p, q), _)] = group {
                on_boundary[*p] = true;
                on_boundary[*q] = true;
            }
        }
        on_boundary
    }
}

impl Mesh {
    pub fn add_node(&mut self, id: u64, x: [f64; 2]) -> NodeIndex {
        let index = self.nodes.len();
        self.nodes.push(Node { id, x });
        self.index_of_id.insert(id, index);
        index
    }

    pub fn node_index(&self, id: u64) -> Option<NodeIndex> {
        self.index_of_id.get(&id).copied()
    }

    pub fn node_id(&self, index: NodeIndex) -> u64 {
        self.nodes[index].id
    }

    pub fn max_node_id(&self) -> u64 {
        self.nodes.iter().map(|n| n.id).max().unwrap_or(0)
    }

    pub fn position(&self, index: NodeIndex) -> [f64; 2] {
        self.nodes[index].x
    }

    /// Centroid of a soil element's corners.
    pub fn centroid(&self, solid: usize) -> [f64; 2] {
        let s = &self.solids[solid];
        let n = s.kind.corner_count();
        let mut c = [0.0; 2];
        for &v in &s.nodes[..n] {
            c[0] += self.nodes[v].x[0] / n as f64;
            c[1] += self.nodes[v].x[1] / n as f64;
        }
        c
    }

    /// Typical element size, used to scale geometric tolerances.
    pub fn characteristic_length(&self) -> f64 {
        let mut total = 0.0;
        let mut count = 0usize;
        for s in &self.solids {
            let a = self.nodes[s.nodes[0]].x;
            let b = self.nodes[s.nodes[1]].x;
            total += ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
            count += 1;
        }
        for b in &self.bars {
            let p = self.nodes[b.nodes[0]].x;
            let q = self.nodes[b.nodes[1]].x;
            total += ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
            count += 1;
        }
        if count == 0 {
            1.0
        } else {
            total / count as f64
        }
    }
}

/// Memory a model of `nodes` nodes whose soil element matrices hold `element_matrix_entries`
/// entries in all takes, MB, before the solver's own: about 70 bytes per entry (the matrices, an
/// iteration's triplets, the triplet-to-CSC refill map and the CSC matrix with the copy kept to
/// detect unchanged values) and 200 per node, calibrated against `geoslip bench`'s "model and
/// assembly only" rows (docs/performance.md).
pub fn memory_estimate_mb(nodes: usize, element_matrix_entries: f64) -> f64 {
    (70.0 * element_matrix_entries + 200.0 * nodes as f64) / (1024.0 * 1024.0)
}
