//! A reinforcement embedded in continuous soil: bars laid along a path of soil element sides,
//! the soil left whole. Each reinforcement point is tied normally to the soil's line by a Lagrange
//! multiplier row (as a contact row, but never released: one continuous soil cannot open), and its
//! shear spring stands for both faces, with σn the soil's own normal stress on the line (see
//! [`super::Embedding`]). As the reinforcement slides, each point is associated again with the side
//! of the soil it now lies on, its law's state carried. Geometry only, like [`super::split`].

use super::split::{checked_path, free_positions, SplitRecord};
use super::{points_on, ContactFace, Embedding, GeometryProblem, Interface, NormalState, ShearLaw};
use crate::mesh::{Bar, Mesh, SideMap};

/// Lay reinforcement `material` along `path_ids` (head on the front face first) inside the soil,
/// with `free_length` in front of the head, and create its one embedded face with `law`.
pub fn embed_reinforcement(
    mesh: &mut Mesh,
    sides: &SideMap,
    name: &str,
    path_ids: &[u64],
    free_length: Option<f64>,
    material: usize,
    law: ShearLaw,
    next_bar_id: &mut u64,
) -> Result<(Interface, SplitRecord), Vec<GeometryProblem>> {
    let (path, _) = checked_path(mesh, sides, path_ids)?;
    let free = match free_length {
        Some(length) => free_positions(mesh, &path, length)?,
        None => Vec::new(),
    };
    let hosts: Vec<Vec<usize>> =
        path.windows(2).map(|w| sides.between(w[0], w[1]).into_iter().map(|s| s.solid).collect()).collect();

    let mut next_id = mesh.max_node_id() + 1;
    let positions: Vec<[f64; 2]> = free.iter().copied().chain(path.iter().map(|&p| mesh.position(p))).collect();
    let mut nodes = Vec::with_capacity(positions.len());
    for x in positions {
        nodes.push(mesh.add_node(next_id, x));
        next_id += 1;
    }
    for k in 0..nodes.len() - 1 {
        mesh.bars.push(Bar { id: *next_bar_id, nodes: [nodes[k], nodes[k + 1]], material });
        *next_bar_id += 1;
    }
    let mut points = points_on(mesh, &path, &nodes);
    // a free length's points lie in front of the soil
    for point in points.iter_mut().take(free.len()) {
        point.normal_state = NormalState::Outside;
    }
    let face = ContactFace {
        label: "embedded".into(),
        points,
        master: path,
        soil_on_left: true,
        fixed_normal: None,
        law,
        embedded: Some(Embedding { hosts }),
        dilation: None,
        bearing: None,
    };
    let record = SplitRecord {
        node_sets: vec![
            (format!("{name}.head"), vec![nodes[0]]),
            (format!("{name}.tail"), vec![nodes[nodes.len() - 1]]),
            (format!("{name}.reinforcement"), nodes),
        ],
        ..Default::default()
    };
    Ok((Interface { name: name.to_string(), faces: vec![face], slit_of: None }, record))
}
