//! Splitting the soil along a reinforcement path: the path's soil nodes are doubled, the bars of
//! each layer of the stack laid between the two soil faces, and the faces and the slit behind the
//! tail created. Geometry only: what is wrong with the path comes back as [`GeometryProblem`]s, which
//! the model's validation reports with the field they belong to.

use super::{
    cross, points_on, sub, unit, ContactFace, GeometryProblem, GeometryProblems, Interface, NormalState, ShearLaw,
};
use crate::mesh::{Bar, Mesh, NodeIndex, SideMap};
use std::collections::HashMap;

/// What a reinforcement split created, for node sets and supports to follow.
#[derive(Debug, Default)]
pub struct SplitRecord {
    /// Original soil node → its twin on the other side of the slit.
    pub twins: HashMap<NodeIndex, NodeIndex>,
    /// Named node sets created: `<name>.head`, `<name>.tail`, `<name>.reinforcement`.
    pub node_sets: Vec<(String, Vec<NodeIndex>)>,
    /// The slit behind the reinforcement, a soil-to-soil contact uncovered as the reinforcement slides.
    pub slit: Option<Interface>,
}

/// Counter-clockwise angle from `from` to `to`, in [0, 2π).
fn ccw_angle(from: [f64; 2], to: [f64; 2]) -> f64 {
    let a = cross(from, to).atan2(from[0] * to[0] + from[1] * to[1]);
    if a < 0.0 {
        a + 2.0 * std::f64::consts::PI
    } else {
        a
    }
}

/// The geosynthetics laid along one reinforcement path and the laws of their contacts.
#[derive(Debug, Clone)]
pub struct Stack {
    /// Layers from the bottom up: (name, reinforcement material). The first is the interface's own.
    pub layers: Vec<(String, usize)>,
    /// The soil above against the top layer.
    pub upper: ShearLaw,
    /// The bottom layer against the soil below.
    pub lower: ShearLaw,
    /// `between[k]`: layer k + 1 sliding on layer k.
    pub between: Vec<ShearLaw>,
}

/// Split the soil along `path` (head on the front face first) and create the reinforcement.
///
/// A stack of geosynthetics gets one set of bars per layer at the same positions: the soil above
/// bears on the top layer, each layer on the one below it (a face whose master is that layer's
/// bars), and the bottom layer on the soil below.
///
/// The path's nodes are doubled from the head to the tail; the tail is doubled only when it lies on
/// the mesh boundary (otherwise the slit ends there, and both faces meet at the tail node). The soil
/// to the left of head → tail keeps the original nodes; the soil to the right gets the twins.
pub fn split_reinforcement(
    mesh: &mut Mesh,
    sides: &SideMap,
    name: &str,
    path_ids: &[u64],
    free_length: Option<f64>,
    stack: &Stack,
    next_bar_id: &mut u64,
) -> Result<(Interface, SplitRecord), Vec<GeometryProblem>> {
    let (path, boundary) = checked_path(mesh, sides, path_ids)?;
    let mut problems = GeometryProblems::default();
    let free = match free_length {
        Some(length) => free_positions(mesh, &path, length)?,
        None => Vec::new(),
    };

    // Elements touching each node to be split, and whether they lie left of head → tail.
    let tail = path.len() - 1;
    let split_count = if boundary[path[tail]] { path.len() } else { tail };
    // (a list for each node of the path only: one for every node of the mesh grew faster than it)
    const NONE: usize = usize::MAX;
    let mut slot = vec![NONE; mesh.nodes.len()];
    let mut touching: Vec<Vec<usize>> = Vec::with_capacity(path.len());
    for &p in &path {
        if slot[p] == NONE {
            slot[p] = touching.len();
            touching.push(Vec::new());
        }
    }
    for (s, solid) in mesh.solids.iter().enumerate() {
        for &v in &solid.nodes {
            if slot[v] != NONE {
                touching[slot[v]].push(s);
            }
        }
    }
    for &p in &path {
        for &s in &touching[slot[p]] {
            if mesh.solids[s].kind.is_quadratic() {
                problems.push(
                    "path",
                    format!("element {} ({}) touches the reinforcement path: interfaces on quadratic faces are not yet supported", mesh.solids[s].id, mesh.solids[s].kind.name()),
                );
                problems.check()?;
            }
        }
    }
    let mut record = SplitRecord::default();
    let mut next_id = mesh.max_node_id() + 1;
    for k in 0..split_count {
        let p = path[k];
        let x = mesh.position(p);
        let ahead = if k < tail { Some(sub(mesh.position(path[k + 1]), x)) } else { None };
        let behind = if k > 0 { Some(sub(mesh.position(path[k - 1]), x)) } else { None };
        let twin = mesh.add_node(next_id, x);
        next_id += 1;
        record.twins.insert(p, twin);
        for &s in &touching[slot[p]] {
            let c = sub(mesh.centroid(s), x);
            let left = match (ahead, behind) {
                (Some(b), Some(a)) => ccw_angle(b, c) < ccw_angle(b, a),
                (Some(b), None) => cross(b, c) > 0.0,
                (None, Some(a)) => cross([-a[0], -a[1]], c) > 0.0,
                (None, None) => true,
            };
            if !left {
                for v in mesh.solids[s].nodes.iter_mut() {
                    if *v == p {
                        *v = twin;
                    }
                }
            }
        }
    }

    // Reinforcement nodes and bars, layer by layer from the bottom up.
    // (a free length's nodes first, in front of the head)
    let mut layer_nodes: Vec<Vec<NodeIndex>> = Vec::with_capacity(stack.layers.len());
    for (_, material) in &stack.layers {
        let mut nodes = Vec::with_capacity(free.len() + path.len());
        let positions: Vec<[f64; 2]> = free.iter().copied().chain(path.iter().map(|&p| mesh.position(p))).collect();
        for x in positions {
            nodes.push(mesh.add_node(next_id, x));
            next_id += 1;
        }
        for k in 0..nodes.len() - 1 {
            mesh.bars.push(Bar { id: *next_bar_id, nodes: [nodes[k], nodes[k + 1]], material: *material });
            *next_bar_id += 1;
        }
        layer_nodes.push(nodes);
    }
    let bottom = layer_nodes[0].clone();
    let top = layer_nodes[layer_nodes.len() - 1].clone();

    // The face whose soil is on the left of head → tail is "upper" when that side is up.
    let d = unit(sub(mesh.position(path[1]), mesh.position(path[0])));
    let left_normal = [-d[1], d[0]];
    let left_is_upper = left_normal[1] > 1e-12 || (left_normal[1].abs() <= 1e-12 && left_normal[0] < 0.0);
    let left_master = path.clone();
    let right_master: Vec<NodeIndex> = path.iter().map(|p| *record.twins.get(p).unwrap_or(p)).collect();
    // the upper soil bears on the top layer, the bottom layer on the lower soil
    let (upper_master, lower_master) =
        if left_is_upper { (left_master, right_master) } else { (right_master, left_master) };
    let mut faces = vec![ContactFace {
        label: "upper".into(),
        points: points_on(mesh, &upper_master, &top),
        master: upper_master,
        soil_on_left: left_is_upper,
        fixed_normal: None,
        law: stack.upper.clone(),
        embedded: None,
        dilation: None,
        bearing: None,
    }];
    for (k, law) in stack.between.iter().enumerate() {
        // layer k + 1 on layer k: the normal points from it into layer k, on the lower side
        faces.push(ContactFace {
            label: format!("{} on {}", stack.layers[k + 1].0, stack.layers[k].0),
            points: points_on(mesh, &layer_nodes[k], &layer_nodes[k + 1]),
            master: layer_nodes[k].clone(),
            soil_on_left: !left_is_upper,
            fixed_normal: None,
            law: law.clone(),
            embedded: None,
            dilation: None,
            bearing: None,
        });
    }
    faces.push(ContactFace {
        label: "lower".into(),
        points: points_on(mesh, &lower_master, &bottom),
        master: lower_master,
        soil_on_left: !left_is_upper,
        fixed_normal: None,
        law: stack.lower.clone(),
        embedded: None,
        dilation: None,
        bearing: None,
    });
    if split_count < path.len() {
        // the tail is a slit tip: the faces end at one soil node; the lower face's row there
        // repeats the others (their sum), and they carry it
        if let Some(p) = faces.last_mut().and_then(|f| f.points.last_mut()) {
            p.slit_tip = true;
        }
        // and no face's row there measures that face's pressure: the tail takes its neighbour's
        for face in faces.iter_mut() {
            let n = face.points.len();
            if n >= 2 {
                face.points[n - 1].pressure_from = Some(n - 2);
            }
        }
    }
    // The slit: the right side's doubled nodes against the left side's face. The reinforcement fills
    // it now; behind a sliding tail its two soil faces must not pass through each other.
    let slit_slaves: Vec<NodeIndex> = path.iter().filter_map(|p| record.twins.get(p).copied()).collect();
    let slit = (slit_slaves.len() >= 2).then(|| {
        let mut points = points_on(mesh, &path, &slit_slaves);
        for p in points.iter_mut() {
            p.normal_state = NormalState::Covered;
        }
        Interface {
            name: format!("{name}.slit"),
            faces: vec![ContactFace {
                label: "slit".into(),
                points,
                master: path.clone(),
                soil_on_left: true,
                fixed_normal: None,
                law: stack.upper.clone(),
                embedded: None,
                dilation: None,
                bearing: None,
            }],
            slit_of: None, // set by the caller, which knows the reinforcement's index
        }
    });
    // a free length's points face no soil yet
    for face in faces.iter_mut() {
        for point in face.points.iter_mut().take(free.len()) {
            point.normal_state = NormalState::Outside;
        }
    }
    for (k, nodes) in layer_nodes.into_iter().enumerate() {
        let layer = if k == 0 { name } else { stack.layers[k].0.as_str() };
        record.node_sets.push((format!("{layer}.head"), vec![nodes[0]]));
        record.node_sets.push((format!("{layer}.tail"), vec![nodes[nodes.len() - 1]]));
        record.node_sets.push((format!("{layer}.reinforcement"), nodes));
    }
    record.slit = slit;
    Ok((Interface { name: name.to_string(), faces, slit_of: None }, record))
}

/// The most nodes a free length may add (its spacing is at most the first segment's).
pub const MAX_FREE_NODES: usize = 10_000;

/// The positions of a free length's nodes in front of the head, from its front end back towards
/// the head (the head excluded): on the line of the first segment, spaced at most as that segment.
pub(super) fn free_positions(
    mesh: &Mesh,
    path: &[NodeIndex],
    length: f64,
) -> Result<Vec<[f64; 2]>, Vec<GeometryProblem>> {
    let (head, next) = (mesh.position(path[0]), mesh.position(path[1]));
    let back = sub(head, next);
    let segment = (back[0] * back[0] + back[1] * back[1]).sqrt();
    let count = (length / segment - 1e-9).ceil().max(1.0);
    if !(count <= MAX_FREE_NODES as f64) {
        let mut problems = GeometryProblems::default();
        problems.push(
            "free_length",
            format!(
                "{length} would need {count} nodes at the first segment's spacing ({segment}); at most {MAX_FREE_NODES}"
            ),
        );
        problems.check()?;
    }
    let count = count as usize;
    // each free bar as long as a millionth of the first segment at least: a shorter one puts its
    // nodes on one point in floating point (a bar of no length, no axis)
    if length / (count as f64) < 1e-6 * segment {
        let mut problems = GeometryProblems::default();
        problems.push(
            "free_length",
            format!("{length} is too short for a bar: at least a millionth of the first segment ({segment}), or none"),
        );
        problems.check()?;
    }
    let d = unit(back);
    Ok((0..count)
        .map(|k| {
            let at = length * (count - k) as f64 / count as f64;
            [head[0] + at * d[0], head[1] + at * d[1]]
        })
        .collect())
}

/// The path's nodes, checked: they exist, none twice, each pair joined by a linear soil side with
/// soil on both sides, the head on the mesh boundary. Also the mesh's boundary nodes.
pub(super) fn checked_path(
    mesh: &Mesh,
    sides: &SideMap,
    path_ids: &[u64],
) -> Result<(Vec<NodeIndex>, Vec<bool>), Vec<GeometryProblem>> {
    let mut problems = GeometryProblems::default();
    let mut path = Vec::new();
    for (k, &id) in path_ids.iter().enumerate() {
        match mesh.node_index(id) {
            Some(i) => path.push(i),
            None => problems.push(format!("path[{k}]"), format!("node {id} does not exist")),
        }
    }
    problems.check()?;
    if path.len() < 2 {
        problems.push("path", "a reinforcement path needs at least 2 nodes");
        problems.check()?;
    }
    let mut seen = HashMap::new();
    for (k, &p) in path.iter().enumerate() {
        if let Some(first) = seen.insert(p, k) {
            problems.push(
                format!("path[{k}]"),
                format!("node {} appears twice in the path (first at position {first})", mesh.node_id(p)),
            );
        }
    }
    for k in 0..path.len() - 1 {
        let found = sides.between(path[k], path[k + 1]);
        let (a, b) = (mesh.node_id(path[k]), mesh.node_id(path[k + 1]));
        if found.is_empty() {
            problems.push(
                format!("path[{k}..{}]", k + 1),
                format!("nodes {a} and {b} are not joined by a soil element side: the reinforcement path must run along element sides through the mesh"),
            );
        } else if found.iter().any(|s| s.quadratic) {
            problems.push(
                format!("path[{k}..{}]", k + 1),
                format!("the side {a}–{b} belongs to a quadratic element: interfaces on quadratic faces are not yet supported; mesh the soil along the reinforcement with tri3 or quad4"),
            );
        } else if found.len() == 1 {
            problems.push(
                format!("path[{k}..{}]", k + 1),
                format!("the side {a}–{b} is on the mesh boundary: a reinforcement path must run through the soil, with soil on both sides"),
            );
        }
    }
    let boundary = sides.boundary_nodes(mesh.nodes.len());
    if !boundary[path[0]] {
        problems.push(
            "path[0]",
            format!(
                "the head node {} is not on the mesh boundary: the path must start at the front face",
                mesh.node_id(path[0])
            ),
        );
    }
    problems.check()?;
    Ok((path, boundary))
}
