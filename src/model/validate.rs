//! Turn a parsed [`ModelFile`] into a checked [`Model`], listing every problem found.

use super::file::*;
use super::problems::Problems;
use super::{Load, LoadedSide, Model, StagePlan};
use crate::element::solid::{mapped_points, BadJacobian, Integration};
use crate::error::ModelError;
use crate::interface::{build, Interface, ShearLaw};
use crate::mesh::{Bar, Mesh, NodeIndex, SideMap, Solid};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;

pub(super) fn validate(source: &Path, file: &ModelFile) -> Result<Model, ModelError> {
    let mut p = Problems::default();
    let notes: Vec<String> = Vec::new();

    // Materials.
    let soils: Vec<(String, SoilMaterial)> = file.materials.soil.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    for (name, m) in &soils {
        let entity = format!("soil material \"{name}\"");
        let f = |field: &str| format!("materials.soil.{name}.{field}");
        if !(m.youngs_modulus.is_finite() && m.youngs_modulus > 0.0) {
            p.push(f("youngs_modulus"), &entity, format!("must be a positive number, found {}", m.youngs_modulus));
        }
        if !(m.poissons_ratio.is_finite() && (0.0..0.5).contains(&m.poissons_ratio)) {
            p.push(f("poissons_ratio"), &entity, format!("must be in [0, 0.5), found {}", m.poissons_ratio));
        }
        if !(m.unit_weight.is_finite() && m.unit_weight >= 0.0) {
            p.push(f("unit_weight"), &entity, format!("must be zero or positive, found {}", m.unit_weight));
        }
        if let Some(g) = m.saturated_unit_weight {
            if !(g.is_finite() && g >= 0.0) {
                p.push(f("saturated_unit_weight"), &entity, format!("must be zero or positive, found {g}"));
            }
        }
        if let Some(k0) = m.k0 {
            if !(k0.is_finite() && k0 > 0.0) {
                p.push(f("k0"), &entity, format!("must be a positive number, found {k0}"));
            }
        }
        let plastic = m.model == SoilModel::MohrCoulomb;
        if plastic {
            if !(m.cohesion.is_finite() && m.cohesion >= 0.0) {
                p.push(f("cohesion"), &entity, format!("must be zero or positive, found {}", m.cohesion));
            }
            if !(m.friction_angle.is_finite() && (0.0..90.0).contains(&m.friction_angle)) {
                p.push(f("friction_angle"), &entity, format!("must be in [0, 90) degrees, found {}", m.friction_angle));
            } else if m.cohesion == 0.0 && m.friction_angle == 0.0 {
                p.push(f("cohesion"), &entity, "a Mohr–Coulomb soil with c = 0 and φ = 0 has no strength");
            }
            if !(m.dilatancy_angle.is_finite() && m.dilatancy_angle >= 0.0 && m.dilatancy_angle <= m.friction_angle) {
                p.push(
                    f("dilatancy_angle"),
                    &entity,
                    format!(
                        "must be in [0, friction_angle = {}] degrees, found {}",
                        m.friction_angle, m.dilatancy_angle
                    ),
                );
            }
            if let Some(t) = m.tensile_strength {
                if !(t.is_finite() && t >= 0.0) {
                    p.push(f("tensile_strength"), &entity, format!("must be zero or positive, found {t}"));
                }
            }
        } else {
            for (field, given) in [
                ("cohesion", m.cohesion != 0.0),
                ("friction_angle", m.friction_angle != 0.0),
                ("dilatancy_angle", m.dilatancy_angle != 0.0),
                ("tensile_strength", m.tensile_strength.is_some()),
            ] {
                if given {
                    p.push(f(field), &entity, "is a strength parameter: set model = \"mohr-coulomb\" to use it");
                }
            }
        }
    }
    let reinforcements: Vec<(String, ReinforcementMaterial)> =
        file.materials.reinforcement.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    for (name, m) in &reinforcements {
        let entity = format!("reinforcement material \"{name}\"");
        let f = |field: &str| format!("materials.reinforcement.{name}.{field}");
        if !(m.axial_stiffness.is_finite() && m.axial_stiffness > 0.0) {
            p.push(f("axial_stiffness"), &entity, format!("must be a positive number, found {}", m.axial_stiffness));
        }
        if let Some(t) = m.rupture_strength {
            if !(t.is_finite() && t > 0.0) {
                p.push(f("rupture_strength"), &entity, format!("must be a positive number, found {t}"));
            }
        }
    }
    let soil_index: HashMap<&str, usize> = soils.iter().enumerate().map(|(i, (n, _))| (n.as_str(), i)).collect();
    let reinf_index: HashMap<&str, usize> =
        reinforcements.iter().enumerate().map(|(i, (n, _))| (n.as_str(), i)).collect();

    // Nodes.
    let mut mesh = Mesh::default();
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
        mesh.add_node(*id, [*x, *y]);
    }

    // Soil elements and bars share one id space.
    let mut element_ids: HashSet<u64> = HashSet::new();
    let mut mesh_ok = true;
    for (k, e) in file.elements.iter().enumerate() {
        let entity = format!("element {}", e.id);
        let field = format!("elements[{k}]");
        let before = p.len();
        if !element_ids.insert(e.id) {
            p.push(format!("{field}.id"), &entity, format!("duplicate element id {}", e.id));
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
            mesh_ok = false;
        }
        if p.len() == before && finite {
            if let Err(BadJacobian { det }) = mapped_points(e.kind, &coords, Integration::Full) {
                let msg = if det < 0.0 {
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
            mesh_ok = false;
        }
    }
    for (k, b) in file.bars.iter().enumerate() {
        let entity = format!("bar {}", b.id);
        let field = format!("bars[{k}]");
        let before = p.len();
        if !element_ids.insert(b.id) {
            p.push(format!("{field}.id"), &entity, format!("duplicate element id {}", b.id));
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
            mesh_ok = false;
        }
    }
    if file.elements.is_empty() && file.bars.is_empty() {
        p.push("elements", None, "the model has no elements");
    }

    // Node sets and edge sets (edges resolve to element sides, which survive a split).
    let mut node_sets: BTreeMap<String, Vec<NodeIndex>> = BTreeMap::new();
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
    let sides = SideMap::new(&mesh);
    let mut edge_sets: BTreeMap<String, Vec<LoadedSide>> = BTreeMap::new();
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
                [] => p.push(field, &entity, format!("nodes {} and {} are not the corners of an element side", edge[0], edge[1])),
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

    // Interfaces.
    let mut interfaces: Vec<Interface> = Vec::new();
    let mut twins: HashMap<NodeIndex, NodeIndex> = HashMap::new();
    let mut names = HashSet::new();
    let mut next_bar_id = element_ids.iter().max().copied().unwrap_or(0) + 1;
    for (k, spec) in file.interfaces.iter().enumerate() {
        let field = format!("interfaces[{k}]");
        let entity = format!("interface \"{}\"", spec.name);
        if !names.insert(spec.name.clone()) {
            p.push(format!("{field}.name"), &entity, "duplicate interface name");
        }
        let law = shear_law(&spec.law, &format!("{field}.law"), &entity, &mut p);
        let lower_law = spec.lower_law.as_ref().map(|l| shear_law(l, &format!("{field}.lower_law"), &entity, &mut p));
        if !mesh_ok {
            continue;
        }
        match (&spec.reinforcement, &spec.slave, &spec.master) {
            (Some(r), None, None) => {
                let Some(&material) = reinf_index.get(r.material.as_str()) else {
                    p.push(
                        format!("{field}.reinforcement.material"),
                        &entity,
                        format!("no reinforcement material named \"{}\"", r.material),
                    );
                    continue;
                };
                if spec.master_normal.is_some() {
                    p.push(
                        format!("{field}.master_normal"),
                        &entity,
                        "master_normal applies only to slave/master pairs",
                    );
                }
                if r.line.is_some() && file.mesh.is_none() {
                    p.push(
                        format!("{field}.reinforcement.line"),
                        &entity,
                        "`line` names a physical curve of a Gmsh mesh, and the model has no `mesh`; give `path` instead",
                    );
                    continue;
                }
                let Some(law) = law else { continue };
                let lower = match lower_law {
                    Some(Some(l)) => l,
                    Some(None) => continue,
                    None => law.clone(),
                };
                let mut stack = build::Stack {
                    layers: vec![(spec.name.clone(), material)],
                    upper: law,
                    lower,
                    between: Vec::new(),
                };
                let before = p.len();
                for (j, layer) in r.stack.iter().enumerate() {
                    let lf = format!("{field}.reinforcement.stack[{j}]");
                    let le = format!("{entity}, layer \"{}\"", layer.name);
                    if !names.insert(layer.name.clone()) {
                        p.push(format!("{lf}.name"), &le, "the name is already used by an interface or another layer");
                    }
                    match reinf_index.get(layer.material.as_str()) {
                        Some(&m) => stack.layers.push((layer.name.clone(), m)),
                        None => p.push(
                            format!("{lf}.material"),
                            &le,
                            format!("no reinforcement material named \"{}\"", layer.material),
                        ),
                    }
                    if let Some(l) = shear_law(&layer.law, &format!("{lf}.law"), &le, &mut p) {
                        stack.between.push(l);
                    }
                }
                let laws = || std::iter::once(&stack.upper).chain(&stack.between).chain(std::iter::once(&stack.lower));
                if laws().any(|l| l.is_tie()) && !laws().all(|l| l.is_tie()) {
                    p.push(
                        format!("{field}.lower_law"),
                        &entity,
                        "a `tie` law cannot be mixed with sliding laws in one reinforcement: tie every face or none",
                    );
                }
                if p.len() > before {
                    continue;
                }
                let sides_now = SideMap::new(&mesh);
                if let Some((interface, record)) = build::split_reinforcement(
                    &mut mesh,
                    &sides_now,
                    &spec.name,
                    &r.path,
                    &stack,
                    &mut next_bar_id,
                    &format!("{field}.reinforcement"),
                    &mut p,
                ) {
                    for (orig, twin) in record.twins {
                        twins.insert(orig, twin);
                    }
                    for (name, set) in record.node_sets {
                        node_sets.insert(name, set);
                    }
                    let index = interfaces.len();
                    interfaces.push(interface);
                    if let Some(mut slit) = record.slit {
                        slit.slit_of = Some(index);
                        interfaces.push(slit);
                    }
                }
            }
            (None, Some(slave), Some(master)) => {
                if spec.lower_law.is_some() {
                    p.push(format!("{field}.lower_law"), &entity, "lower_law applies only to a reinforcement");
                }
                let Some(law) = law else { continue };
                let sides_now = SideMap::new(&mesh);
                if let Some(i) =
                    build::pair(&mesh, &sides_now, &spec.name, slave, master, spec.master_normal, law, &field, &mut p)
                {
                    interfaces.push(i);
                }
            }
            _ => p.push(
                field,
                &entity,
                "give either `reinforcement` (a path to split the soil along) or both `slave` and `master`",
            ),
        }
    }
    // A split node's twin belongs to every set the original belongs to.
    for set in node_sets.values_mut() {
        let extra: Vec<NodeIndex> = set.iter().filter_map(|n| twins.get(n).copied()).collect();
        set.extend(extra);
    }

    // Targets of supports, loads and prescribed displacements.
    let resolve = |node: Option<u64>,
                   nodes: Option<&[u64]>,
                   set: Option<&str>,
                   field: &str,
                   p: &mut Problems,
                   with_twins: bool|
     -> Vec<NodeIndex> {
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
            match mesh.node_index(id) {
                Some(i) => {
                    out.push(i);
                    if with_twins {
                        out.extend(twins.get(&i));
                    }
                }
                None => p.push(field, format!("node {id}"), format!("node {id} does not exist")),
            }
        }
        if let Some(s) = set {
            match node_sets.get(s) {
                Some(v) => out.extend(v),
                None => p.push(field, format!("node set \"{s}\""), format!("no node set named \"{s}\"")),
            }
        }
        out
    };

    let mut supported: HashSet<(NodeIndex, Direction)> = HashSet::new();
    let mut supports = Vec::new();
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
        for n in resolve(t.node, t.nodes, t.set, &field, &mut p, true) {
            for &d in &s.fix {
                if supported.insert((n, d)) {
                    supports.push((n, d));
                }
            }
        }
    }

    // Element sets: soil element ids → indices.
    let solid_index: HashMap<u64, usize> = mesh.solids.iter().enumerate().map(|(i, e)| (e.id, i)).collect();
    let mut element_sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
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
    let water_weight = Model::default_water_weight(&file.units);

    if file.stages.is_empty() {
        p.push(
            "stages",
            None,
            "the model has no stages: add at least one [[stages]] with loads or prescribed displacements",
        );
    }
    let mut stages = Vec::new();
    let mut placed: HashSet<usize> = HashSet::new();
    let mut placed_bars: HashSet<usize> = HashSet::new();
    let mut stage_names = HashSet::new();
    for (k, s) in file.stages.iter().enumerate() {
        let field = format!("stages[{k}]");
        let entity = format!("stage \"{}\"", s.name);
        if !stage_names.insert(s.name.clone()) {
            p.push(format!("{field}.name"), &entity, "duplicate stage name");
        }
        let lf = &s.load_factors;
        if lf.is_empty()
            || lf.iter().any(|f| !f.is_finite() || *f <= 0.0 || *f > 1.0 + 1e-12)
            || lf.windows(2).any(|w| w[1] <= w[0])
            || (lf[lf.len() - 1] - 1.0).abs() > 1e-12
        {
            p.push(
                format!("{field}.load_factors"),
                &entity,
                format!("load factors must increase within (0, 1] and end at 1.0, found {lf:?}"),
            );
        }
        let mut loads = Vec::new();
        for (j, l) in s.loads.iter().enumerate() {
            let lfield = format!("{field}.loads[{j}]");
            match l {
                LoadSpec::EdgeTraction { edge_set, pressure, shear, .. } => {
                    if !(pressure.is_finite() && shear.is_finite()) {
                        p.push(&lfield, &entity, "pressure and shear must be finite numbers");
                    }
                    match edge_sets.get(edge_set) {
                        Some(sides) => {
                            loads.push(Load::EdgeTraction { sides: sides.clone(), pressure: *pressure, shear: *shear })
                        }
                        None => {
                            p.push(format!("{lfield}.edge_set"), &entity, format!("no edge set named \"{edge_set}\""))
                        }
                    }
                }
                LoadSpec::Point { node, nodes, set, fx, fy } => {
                    if !(fx.is_finite() && fy.is_finite()) {
                        p.push(&lfield, &entity, "fx and fy must be finite numbers");
                    }
                    for n in resolve(*node, nodes.as_deref(), set.as_deref(), &lfield, &mut p, false) {
                        loads.push(Load::Point { node: n, force: [*fx, *fy] });
                    }
                }
                LoadSpec::Gravity { factor } => {
                    if !factor.is_finite() {
                        p.push(format!("{lfield}.factor"), &entity, "must be a finite number");
                    }
                    if soils.iter().all(|(_, m)| m.unit_weight == 0.0) {
                        p.push(&lfield, &entity, "gravity is applied but every soil material has unit_weight 0");
                    }
                    loads.push(Load::Gravity { factor: *factor });
                }
            }
        }
        let mut prescribed = Vec::new();
        let mut seen = HashSet::new();
        for (j, d) in s.prescribed.iter().enumerate() {
            let pfield = format!("{field}.prescribed[{j}]");
            if d.ux.is_none() && d.uy.is_none() {
                p.push(&pfield, &entity, "give ux, uy or both");
            }
            let t = d.target();
            for n in resolve(t.node, t.nodes, t.set, &pfield, &mut p, false) {
                for (dir, v) in [(Direction::X, d.ux), (Direction::Y, d.uy)] {
                    let Some(v) = v else { continue };
                    let label = format!("node {} {}", mesh.node_id(n), if dir == Direction::X { "ux" } else { "uy" });
                    if !v.is_finite() {
                        p.push(&pfield, &label, "the displacement must be a finite number");
                    } else if supported.contains(&(n, dir)) {
                        p.push(&pfield, &label, "this DOF is a fixed support; it cannot also be prescribed");
                    } else if !seen.insert((n, dir)) {
                        p.push(&pfield, &label, "this DOF is prescribed twice in the same stage");
                    } else {
                        prescribed.push((n, dir, v));
                    }
                }
            }
        }
        let sets = |names: &[String], key: &str, p: &mut Problems| -> (Vec<usize>, Vec<usize>) {
            let mut out = Vec::new();
            let mut bars = Vec::new();
            for (j, name) in names.iter().enumerate() {
                // a reinforcement interface by name: its bars
                let reinforcement = node_sets.get(&format!("{name}.reinforcement")).filter(|_| key == "activate");
                match (element_sets.get(name), reinforcement) {
                    (Some(set), _) => out.extend(set.iter().copied()),
                    (None, Some(nodes)) => {
                        let nodes: HashSet<usize> = nodes.iter().copied().collect();
                        bars.extend(
                            mesh.bars
                                .iter()
                                .enumerate()
                                .filter(|(_, b)| b.nodes.iter().all(|n| nodes.contains(n)))
                                .map(|(i, _)| i),
                        );
                    }
                    (None, None) => p.push(
                        format!("{field}.{key}[{j}]"),
                        &entity,
                        format!(
                            "no element set{} named \"{name}\"{}",
                            if key == "activate" { " or reinforcement" } else { "" },
                            if element_sets.is_empty() {
                                String::new()
                            } else {
                                format!("; there are: {}", element_sets.keys().cloned().collect::<Vec<_>>().join(", "))
                            }
                        ),
                    ),
                }
            }
            (out, bars)
        };
        let (activate, activate_bars) = sets(&s.activate, "activate", &mut p);
        let (deactivate, _) = sets(&s.deactivate, "deactivate", &mut p);
        for &b in &activate_bars {
            if !placed_bars.insert(b) {
                p.push(format!("{field}.activate"), format!("bar {}", mesh.bars[b].id), "is placed twice");
            }
        }
        for &e in &activate {
            if !placed.insert(e) {
                p.push(
                    format!("{field}.activate"),
                    format!("element {}", mesh.solids[e].id),
                    "is placed twice (in two stages, or in two sets of one stage)",
                );
            }
        }
        let water = s.water.as_ref().map(|w| {
            let wfield = format!("{field}.water");
            let given = [w.level.is_some(), w.line.is_some(), w.none].iter().filter(|&&g| g).count();
            if given != 1 {
                p.push(&wfield, &entity, "give exactly one of `level`, `line` or `none = true`");
            }
            let unit_weight = w.unit_weight.unwrap_or(water_weight);
            if !(unit_weight.is_finite() && unit_weight > 0.0) {
                p.push(format!("{wfield}.unit_weight"), &entity, format!("must be positive, found {unit_weight}"));
            }
            let line = match (&w.level, &w.line) {
                (Some(y), _) => vec![[0.0, *y]],
                (_, Some(line)) => line.clone(),
                _ => Vec::new(),
            };
            if line.iter().any(|q| !(q[0].is_finite() && q[1].is_finite())) {
                p.push(&wfield, &entity, "the water table's coordinates must be finite numbers");
            }
            if w.line.is_some() && (line.is_empty() || line.windows(2).any(|q| !(q[1][0] > q[0][0]))) {
                p.push(format!("{wfield}.line"), &entity, "give at least one point, with x strictly increasing");
            }
            (!w.none && !line.is_empty()).then_some(super::WaterTable { line, unit_weight })
        });
        let strength_reduction = s.strength_reduction.as_ref().map(|r| {
            let rfield = format!("{field}.strength_reduction");
            let tolerance = r.tolerance.unwrap_or(0.002);
            let max_factor = r.max_factor.unwrap_or(10.0);
            if !(tolerance > 0.0 && tolerance <= 0.1) {
                p.push(format!("{rfield}.tolerance"), &entity, format!("must be in (0, 0.1], found {tolerance}"));
            }
            if !(max_factor > 1.0 && max_factor.is_finite()) {
                p.push(
                    format!("{rfield}.max_factor"),
                    &entity,
                    format!("must be a number above 1, found {max_factor}"),
                );
            }
            let busy = !s.loads.is_empty()
                || !s.prescribed.is_empty()
                || !s.activate.is_empty()
                || !s.deactivate.is_empty()
                || s.water.is_some()
                || s.initial_stress.is_some();
            if busy {
                p.push(
                    &rfield,
                    &entity,
                    "a strength-reduction stage changes nothing but the strengths: move its loads, prescribed \
                     displacements, activations, water and initial stresses to a stage before it",
                );
            }
            if k == 0 {
                p.push(&rfield, &entity, "a strength-reduction stage needs a stage before it that loads the model");
            }
            super::StrengthReduction { soil: r.reduce == ReducedStrengths::SoilAndInterfaces, tolerance, max_factor }
        });
        stages.push(StagePlan {
            name: s.name.clone(),
            strength_reduction,
            load_factors: lf.clone(),
            loads,
            prescribed,
            activate,
            deactivate,
            activate_bars,
            k0: s.initial_stress == Some(InitialStress::K0),
            water,
        });
    }

    let a = &file.analysis;
    if !(a.force_tolerance.is_finite() && a.force_tolerance > 0.0 && a.force_tolerance < 1.0) {
        p.push("analysis.force_tolerance", None, format!("must be in (0, 1), found {}", a.force_tolerance));
    }
    if !(a.displacement_tolerance.is_finite() && a.displacement_tolerance > 0.0 && a.displacement_tolerance < 1.0) {
        p.push(
            "analysis.displacement_tolerance",
            None,
            format!("must be in (0, 1), found {}", a.displacement_tolerance),
        );
    }
    if a.max_iterations == 0 {
        p.push("analysis.max_iterations", None, "must be at least 1");
    }
    if p.is_empty() {
        check_free_bodies(&mesh, &interfaces, &supports, stages.first(), &mut p);
    }
    if p.is_empty() {
        Ok(Model {
            source: source.to_path_buf(),
            title: file.title.clone(),
            units: file.units.clone(),
            mesh,
            soils,
            reinforcements,
            node_sets,
            element_sets,
            supports,
            interfaces,
            stages,
            notes,
            analysis: file.analysis.clone(),
            mesh_source: None,
        })
    } else {
        Err(ModelError { file: source.to_path_buf(), problems: p.into_vec() })
    }
}

/// Names what a support, load or prescribed displacement targets, as written: `node 3`,
/// `nodes 1, 2`, `node set "left"` (joined by "and" when several are given), or `no node, nodes or
/// set` when none is.
fn target_label(node: Option<u64>, nodes: Option<&[u64]>, set: Option<&str>) -> String {
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

fn shear_law(spec: &ShearLawSpec, field: &str, entity: &str, p: &mut Problems) -> Option<ShearLaw> {
    let before = p.len();
    let positive = |name: &str, v: f64, p: &mut Problems| {
        if !(v.is_finite() && v > 0.0) {
            p.push(format!("{field}.{name}"), entity, format!("must be a positive number, found {v}"));
        }
    };
    let non_negative = |name: &str, v: f64, p: &mut Problems| {
        if !(v.is_finite() && v >= 0.0) {
            p.push(format!("{field}.{name}"), entity, format!("must be zero or positive, found {v}"));
        }
    };
    let angle = |name: &str, v: f64, p: &mut Problems| -> f64 {
        if !(v.is_finite() && (0.0..90.0).contains(&v)) {
            p.push(format!("{field}.{name}"), entity, format!("must be an angle in degrees within [0, 90), found {v}"));
        }
        v.to_radians().tan()
    };
    let law = match *spec {
        ShearLawSpec::Tie => ShearLaw::Tie,
        ShearLawSpec::Linear { shear_stiffness } => {
            positive("shear_stiffness", shear_stiffness, p);
            ShearLaw::Linear { shear_stiffness }
        }
        ShearLawSpec::Coulomb { shear_stiffness, cohesion, friction_angle } => {
            positive("shear_stiffness", shear_stiffness, p);
            non_negative("cohesion", cohesion, p);
            let tan_friction = angle("friction_angle", friction_angle, p);
            ShearLaw::Coulomb { shear_stiffness, cohesion, tan_friction }
        }
        ShearLawSpec::Hyperbolic { shear_stiffness, cohesion, friction_angle } => {
            positive("shear_stiffness", shear_stiffness, p);
            non_negative("cohesion", cohesion, p);
            let tan_friction = angle("friction_angle", friction_angle, p);
            ShearLaw::Hyperbolic { shear_stiffness, cohesion, tan_friction }
        }
        ShearLawSpec::PeakResidual {
            shear_stiffness,
            cohesion,
            friction_angle,
            residual_cohesion,
            residual_friction_angle,
        }
        | ShearLawSpec::Softening {
            shear_stiffness,
            cohesion,
            friction_angle,
            residual_cohesion,
            residual_friction_angle,
            ..
        } => {
            positive("shear_stiffness", shear_stiffness, p);
            non_negative("cohesion", cohesion, p);
            non_negative("residual_cohesion", residual_cohesion, p);
            let tan_friction = angle("friction_angle", friction_angle, p);
            let residual_tan_friction = angle("residual_friction_angle", residual_friction_angle, p);
            if residual_cohesion > cohesion || residual_friction_angle > friction_angle {
                p.push(
                    field,
                    entity,
                    "the residual strength must not exceed the peak: residual_cohesion ≤ cohesion and residual_friction_angle ≤ friction_angle",
                );
            }
            match *spec {
                ShearLawSpec::Softening { softening_slip, .. } => {
                    positive("softening_slip", softening_slip, p);
                    ShearLaw::Softening {
                        shear_stiffness,
                        cohesion,
                        tan_friction,
                        residual_cohesion,
                        residual_tan_friction,
                        softening_slip,
                    }
                }
                _ => ShearLaw::PeakResidual {
                    shear_stiffness,
                    cohesion,
                    tan_friction,
                    residual_cohesion,
                    residual_tan_friction,
                },
            }
        }
    };
    if p.len() > before {
        return None;
    }
    Some(law)
}

/// Every connected body (soil, bars and the interfaces that join them) must be held against both
/// translations and the rotation by the supports and the first stage's prescribed displacements.
fn check_free_bodies(
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
        let free = free_rigid_modes(&rows, mesh.characteristic_length());
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
