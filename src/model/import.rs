//! Fill a model file's nodes, soil elements and named sets from a Gmsh mesh, before the model is
//! checked as if the user had written them inline.
//!
//! - Physical surfaces → soil elements, each with the material `mesh.materials` names for it.
//! - Physical curves → a node set of the same name, and an edge set too when the curve lies on the
//!   soil's boundary.
//! - Physical points → a node set.
//! - A reinforcement `line` → the node path along that physical curve, head first.
//!
//! Elements that Gmsh wrote clockwise (a surface whose curve loop runs clockwise) are renumbered
//! counter-clockwise, and the run's notes say how many.

use super::file::{MeshSource, ModelFile, NodeRow, SolidElementRow, SolidKind};
use super::problems::Problems;
use super::LoadOptions;
use crate::gmsh::{GeneratedMesh, GmshElement, GmshKind, GmshMesh};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// What was read, for the run report.
#[derive(Debug, Clone)]
pub struct MeshRecord {
    /// The `.msh` or `.geo` file named by the model.
    pub file: PathBuf,
    /// `4.1` or `2.2`.
    pub format: String,
    pub generated: Option<GeneratedMesh>,
    pub nodes: usize,
    pub soil_elements: usize,
    /// Elements Gmsh wrote clockwise, renumbered counter-clockwise.
    pub flipped: usize,
    /// Physical group names by dimension (0 points, 1 curves, 2 surfaces).
    pub groups: Vec<(usize, String)>,
}

/// Read the mesh the model names and write its parts into `file`. Problems go to `p`, under the
/// field `mesh.…` or the interface's field, naming the mesh file.
pub(super) fn import(
    source: &Path,
    file: &mut ModelFile,
    p: &mut Problems,
    options: LoadOptions,
) -> Option<MeshRecord> {
    let spec = file.mesh.clone()?;
    let dir = source.parent().unwrap_or(Path::new("."));
    let path = dir.join(&spec.file);
    let is_geo = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("geo"));
    let read = if is_geo {
        crate::gmsh::mesh_geometry(
            &path,
            crate::gmsh::MeshingOptions {
                trust_script: options.trust_geo,
                memory_limit_mb: options.memory_limit_mb,
                time_limit_s: options.gmsh_time_limit_s,
            },
        )
        .map(|(m, g)| (m, Some(g)))
    } else {
        GmshMesh::read_within(&path, options.memory_limit()).map(|m| (m, None))
    };
    let (mesh, generated) = match read {
        Ok(x) => x,
        Err(e) => {
            p.push("mesh.file", None, e.to_string());
            return None;
        }
    };
    let shown = path.display().to_string();
    if !file.nodes.is_empty() || !file.elements.is_empty() {
        p.push("mesh", None, "give nodes and elements either inline or through `mesh`, not both");
        return None;
    }

    let SoilElements { flipped, used, corner_edges, coords } = soil_elements(&mesh, &spec, file, p, &shown);
    nodes(&mesh, &used, file, p, &shown);

    // Named sets from physical curves and points.
    let mut lines_of: BTreeMap<&str, Vec<&GmshElement>> = BTreeMap::new();
    let mut points_of: BTreeMap<&str, Vec<u64>> = BTreeMap::new();
    for e in &mesh.elements {
        for &g in &e.groups {
            let name = mesh.groups[g].name.as_str();
            match e.kind {
                GmshKind::Line2 | GmshKind::Line3 => lines_of.entry(name).or_default().push(e),
                GmshKind::Point => points_of.entry(name).or_default().extend(e.nodes.iter().copied()),
                _ => {}
            }
        }
    }
    // A curve inside the soil (a reinforcement line) gives a node set only: tractions act on the boundary.
    let boundary_edge = |a: u64, b: u64| corner_edges.get(&(a.min(b), a.max(b))) == Some(&1);
    for (name, elements) in &lines_of {
        let edges: Vec<Vec<u64>> = elements.iter().map(|e| e.nodes.clone()).collect();
        let on_boundary = edges.iter().all(|e| boundary_edge(e[0], e[1]));
        let mut nodes: Vec<u64> = edges.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        add_set(file, p, name, nodes, on_boundary.then_some(edges), &shown);
    }
    for (name, nodes) in &points_of {
        let mut nodes = nodes.clone();
        nodes.sort_unstable();
        nodes.dedup();
        add_set(file, p, name, nodes, None, &shown);
    }

    reinforcement_paths(file, p, &lines_of, &coords, &corner_edges, &shown);

    let mut groups: Vec<(usize, String)> = mesh.groups.iter().map(|g| (g.dim, g.name.clone())).collect();
    groups.sort();
    Some(MeshRecord {
        file: path,
        format: mesh.format.clone(),
        generated,
        nodes: file.nodes.len(),
        soil_elements: file.elements.len(),
        flipped,
        groups,
    })
}

/// What reading the soil elements found out about the mesh.
struct SoilElements {
    /// Elements Gmsh wrote clockwise, renumbered counter-clockwise.
    flipped: usize,
    /// The nodes the soil elements use.
    used: BTreeSet<u64>,
    /// How many soil elements share each corner edge (1: the soil's boundary).
    corner_edges: HashMap<(u64, u64), usize>,
    coords: HashMap<u64, [f64; 3]>,
}

/// Soil elements from the physical surfaces named in `mesh.materials`; every physical surface is
/// an element set too.
fn soil_elements(
    mesh: &GmshMesh,
    spec: &MeshSource,
    file: &mut ModelFile,
    p: &mut Problems,
    shown: &str,
) -> SoilElements {
    let surfaces: BTreeMap<&str, usize> =
        mesh.groups.iter().enumerate().filter(|(_, g)| g.dim == 2).map(|(i, g)| (g.name.as_str(), i)).collect();
    let mut material_of: HashMap<usize, &str> = HashMap::new();
    for (group, material) in &spec.materials {
        match surfaces.get(group.as_str()) {
            Some(&g) => {
                material_of.insert(g, material.as_str());
            }
            None => p.push(
                format!("mesh.materials.{group}"),
                format!("physical surface \"{group}\""),
                format!("{shown} has no physical surface named \"{group}\"; it has: {}", list(surfaces.keys())),
            ),
        }
    }
    let mut unassigned: BTreeMap<String, usize> = BTreeMap::new();
    let mut unsupported: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    let mut flipped = 0usize;
    let mut used: BTreeSet<u64> = BTreeSet::new();
    let mut corner_edges: HashMap<(u64, u64), usize> = HashMap::new();
    let coords: HashMap<u64, [f64; 3]> = mesh.nodes.iter().copied().collect();
    for e in mesh.elements.iter().filter(|e| e.kind.dim() == Some(2) || matches!(e.kind, GmshKind::Other(_))) {
        let kind = match e.kind {
            GmshKind::Tri3 => SolidKind::Tri3,
            GmshKind::Tri6 => SolidKind::Tri6,
            GmshKind::Quad4 => SolidKind::Quad4,
            GmshKind::Quad8 => SolidKind::Quad8,
            other => {
                unsupported.entry(other.describe()).or_default().push(e.tag);
                continue;
            }
        };
        // every physical surface is an element set too (for staged construction)
        for &g in &e.groups {
            if mesh.groups[g].dim == 2 {
                file.element_sets.entry(mesh.groups[g].name.clone()).or_default().push(e.tag);
            }
        }
        let materials: Vec<&str> = e.groups.iter().filter_map(|g| material_of.get(g).copied()).collect();
        let material = match materials.as_slice() {
            [m] => m.to_string(),
            [] => {
                let names: Vec<&str> = e.groups.iter().map(|&g| mesh.groups[g].name.as_str()).collect();
                let key = if names.is_empty() { "(no physical surface)".to_string() } else { names.join(", ") };
                *unassigned.entry(key).or_default() += 1;
                continue;
            }
            many => {
                p.push(
                    "mesh.materials",
                    format!("element {}", e.tag),
                    format!(
                        "the element is in several physical surfaces with materials ({}): keep one",
                        many.join(", ")
                    ),
                );
                continue;
            }
        };
        let nodes = counter_clockwise(&coords, e, kind, &mut flipped);
        let corners = kind_corners(kind);
        for k in 0..corners {
            let (a, b) = (nodes[k], nodes[(k + 1) % corners]);
            *corner_edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
        used.extend(nodes.iter().copied());
        file.elements.push(SolidElementRow { id: e.tag, kind, nodes, material });
    }
    for (what, tags) in &unsupported {
        p.push(
            "mesh.file",
            format!("element {}", tags[0]),
            format!(
                "{shown}: {} {what} element{} cannot be used as soil (geoslip takes 3- and 6-node triangles and 4- and \
                 8-node quadrangles; for 8-node quadrangles set Mesh.SecondOrderIncomplete = 1)",
                tags.len(),
                if tags.len() == 1 { "" } else { "s" }
            ),
        );
    }
    for (groups, count) in &unassigned {
        p.push(
            "mesh.materials",
            format!("physical surface {groups}"),
            format!(
                "{count} surface element(s) of {shown} have no material: name their physical surface in mesh.materials"
            ),
        );
    }
    if file.elements.is_empty() && p.is_empty() {
        p.push("mesh.file", None, format!("{shown} has no surface elements in a physical surface"));
    }
    SoilElements { flipped, used, corner_edges, coords }
}

/// Nodes: those the soil uses, x–y plane only.
fn nodes(mesh: &GmshMesh, used: &BTreeSet<u64>, file: &mut ModelFile, p: &mut Problems, shown: &str) {
    let extent = mesh.nodes.iter().fold(0.0f64, |m, (_, x)| m.max(x[0].abs()).max(x[1].abs()));
    let mut seen = BTreeSet::new();
    for (tag, x) in &mesh.nodes {
        if !used.contains(tag) || !seen.insert(*tag) {
            continue;
        }
        if x[2].abs() > 1e-9 * extent.max(1.0) {
            p.push(
                "mesh.file",
                format!("node {tag}"),
                format!("{shown}: the node has z = {}; a 2-D mesh lies in the x–y plane", x[2]),
            );
        }
        file.nodes.push(NodeRow(*tag, x[0], x[1]));
    }
    for tag in used.difference(&seen) {
        p.push(
            "mesh.file",
            format!("node {tag}"),
            format!("{shown}: an element uses node {tag}, which the file does not list"),
        );
    }
}

/// Reinforcement lines → paths, from the head (the end on the soil's boundary, or the one nearest
/// `head`) to the tail.
fn reinforcement_paths(
    file: &mut ModelFile,
    p: &mut Problems,
    lines_of: &BTreeMap<&str, Vec<&GmshElement>>,
    coords: &HashMap<u64, [f64; 3]>,
    corner_edges: &HashMap<(u64, u64), usize>,
    shown: &str,
) {
    let on_boundary = |n: u64| corner_edges.iter().any(|(&(a, b), &count)| count == 1 && (a == n || b == n));
    for (k, spec) in file.interfaces.iter_mut().enumerate() {
        let Some(r) = spec.reinforcement.as_mut() else { continue };
        let Some(line) = r.line.clone() else { continue };
        let field = format!("interfaces[{k}].reinforcement.line");
        let entity = format!("interface \"{}\"", spec.name);
        if !r.path.is_empty() {
            p.push(&field, &entity, "give either `path` or `line`, not both");
            continue;
        }
        let Some(elements) = lines_of.get(line.as_str()) else {
            p.push(
                &field,
                &entity,
                format!("{shown} has no physical curve named \"{line}\"; it has: {}", list(lines_of.keys())),
            );
            continue;
        };
        match chain(elements) {
            Err(message) => p.push(&field, &entity, format!("{shown}, physical curve \"{line}\": {message}")),
            Ok(mut path) => {
                let ends = [path[0], path[path.len() - 1]];
                let head = match r.head {
                    Some(h) => {
                        let d = |n: u64| coords.get(&n).map_or(f64::INFINITY, |x| (x[0] - h[0]).hypot(x[1] - h[1]));
                        if d(ends[0]) <= d(ends[1]) {
                            ends[0]
                        } else {
                            ends[1]
                        }
                    }
                    None => match (on_boundary(ends[0]), on_boundary(ends[1])) {
                        (true, false) => ends[0],
                        (false, true) => ends[1],
                        (both, _) => {
                            p.push(
                                format!("interfaces[{k}].reinforcement.head"),
                                &entity,
                                format!(
                                    "{} ends of physical curve \"{line}\" (nodes {} and {}) lie on the soil's boundary: give `head = [x, y]` near the end that is pulled",
                                    if both { "both" } else { "neither of the" },
                                    ends[0],
                                    ends[1]
                                ),
                            );
                            continue;
                        }
                    },
                };
                if head != path[0] {
                    path.reverse();
                }
                r.path = path;
            }
        }
    }
}

fn list<'a>(names: impl Iterator<Item = &'a &'a str>) -> String {
    let v: Vec<String> = names.map(|n| format!("\"{n}\"")).collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

fn add_set(
    file: &mut ModelFile,
    p: &mut Problems,
    name: &str,
    nodes: Vec<u64>,
    edges: Option<Vec<Vec<u64>>>,
    shown: &str,
) {
    if file.node_sets.contains_key(name) {
        p.push(
            format!("node_sets.{name}"),
            format!("set \"{name}\""),
            format!("a physical group of {shown} has this name too: rename one of them"),
        );
        return;
    }
    file.node_sets.insert(name.to_string(), nodes);
    if let Some(edges) = edges {
        if file.edge_sets.contains_key(name) {
            p.push(
                format!("edge_sets.{name}"),
                format!("set \"{name}\""),
                format!("a physical curve of {shown} has this name too: rename one of them"),
            );
            return;
        }
        file.edge_sets.insert(name.to_string(), edges);
    }
}

fn kind_corners(kind: SolidKind) -> usize {
    match kind {
        SolidKind::Tri3 | SolidKind::Tri6 => 3,
        SolidKind::Quad4 | SolidKind::Quad8 => 4,
    }
}

/// The element's nodes in counter-clockwise order (corners, then mid-sides in Gmsh order).
fn counter_clockwise(
    coords: &HashMap<u64, [f64; 3]>,
    e: &GmshElement,
    kind: SolidKind,
    flipped: &mut usize,
) -> Vec<u64> {
    let corners = kind_corners(kind);
    let xy = |tag: u64| coords.get(&tag).map(|x| [x[0], x[1]]);
    // Signed area of the corner polygon; a node that cannot be found is reported later.
    let pts: Option<Vec<[f64; 2]>> = e.nodes[..corners].iter().map(|&t| xy(t)).collect();
    let Some(pts) = pts else { return e.nodes.clone() };
    let area: f64 = (0..corners)
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % corners]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    if area >= 0.0 {
        return e.nodes.clone();
    }
    *flipped += 1;
    let n = &e.nodes;
    match kind {
        SolidKind::Tri3 => vec![n[0], n[2], n[1]],
        SolidKind::Quad4 => vec![n[0], n[3], n[2], n[1]],
        // Mid-sides: side k runs from corner k to corner k+1.
        SolidKind::Tri6 => vec![n[0], n[2], n[1], n[5], n[4], n[3]],
        SolidKind::Quad8 => vec![n[0], n[3], n[2], n[1], n[7], n[6], n[5], n[4]],
    }
}

/// Chain line elements into one path of corner nodes, from one end to the other.
fn chain(elements: &[&GmshElement]) -> Result<Vec<u64>, String> {
    if elements.iter().any(|e| e.kind == GmshKind::Line3) {
        return Err(
            "it is meshed with 3-node lines; a reinforcement runs along linear element sides (mesh it first order)"
                .into(),
        );
    }
    let mut next: HashMap<u64, Vec<u64>> = HashMap::new();
    for e in elements {
        let (a, b) = (e.nodes[0], e.nodes[1]);
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    if let Some((n, _)) = next.iter().find(|(_, v)| v.len() > 2) {
        return Err(format!("node {n} joins more than two of its segments: a reinforcement is one unbranched line"));
    }
    let ends: Vec<u64> = {
        let mut e: Vec<u64> = next.iter().filter(|(_, v)| v.len() == 1).map(|(&n, _)| n).collect();
        e.sort_unstable();
        e
    };
    if ends.len() != 2 {
        return Err("its segments do not form one open line (it is closed or in pieces)".into());
    }
    let mut path = vec![ends[0]];
    let mut prev = None;
    let mut at = ends[0];
    while let Some(&n) = next[&at].iter().find(|&&n| Some(n) != prev) {
        path.push(n);
        prev = Some(at);
        at = n;
        if path.len() > next.len() {
            break;
        }
    }
    if path.len() != next.len() {
        return Err("its segments do not form one open line (it is in pieces)".into());
    }
    Ok(path)
}
