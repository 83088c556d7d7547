//! Interfaces: a reinforcement path that splits the soil (with its stack of layers), or a slave
//! line and its master face; the geometry's own problems reported under the interface's fields.

use super::materials::shear_law;
use super::Draft;
use crate::interface::{bearing, embed, pair, split, Bearing, Dilation, GeometryProblem};
use crate::mesh::{NodeIndex, SideMap};
use crate::model::file::*;
use crate::model::problems::Problems;
use std::collections::HashSet;

/// Every interface, and the twins a split made in the node sets.
pub(super) fn interfaces(d: &mut Draft, file: &ModelFile, p: &mut Problems) {
    let Draft { mesh, mesh_ok, element_ids, reinf_index, node_sets, interfaces, twins, .. } = d;
    let mut names = HashSet::new();
    // element ids above `MAX_ID` are refused, and then no interface is built
    let mut next_bar_id = element_ids.iter().max().copied().unwrap_or(0).saturating_add(1);
    for (k, spec) in file.interfaces.iter().enumerate() {
        let field = format!("interfaces[{k}]");
        let entity = format!("interface \"{}\"", spec.name);
        if !names.insert(spec.name.clone()) {
            p.push(format!("{field}.name"), &entity, "duplicate interface name");
        }
        let law = shear_law(&spec.law, &format!("{field}.law"), &entity, p);
        let lower_law = spec.lower_law.as_ref().map(|l| shear_law(l, &format!("{field}.lower_law"), &entity, p));
        let (dilation, bearing) = extras(spec, &field, &entity, p);
        if !*mesh_ok {
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
                let mut stack = split::Stack {
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
                    if let Some(l) = shear_law(&layer.law, &format!("{lf}.law"), &le, p) {
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
                if let Some(free) = r.free_length {
                    if !(free.is_finite() && free > 0.0) {
                        p.push(
                            format!("{field}.reinforcement.free_length"),
                            &entity,
                            format!("must be a positive length (got {free})"),
                        );
                    }
                    if !r.stack.is_empty() {
                        p.push(
                            format!("{field}.reinforcement.free_length"),
                            &entity,
                            "a free length is not yet supported for a stack of geosynthetics",
                        );
                    }
                }
                if spec.bearing.is_some() && file.analysis.geometry.is_axisymmetric() {
                    p.push(
                        format!("{field}.bearing"),
                        &entity,
                        "passive bearing is that of a geogrid's transverse members, which an axisymmetric model cannot have: leave it out, or count the bearing of a nail's ribs or an anchor's bulb in the shaft's law",
                    );
                }
                if spec.bearing.is_some() && !r.stack.is_empty() {
                    p.push(
                        format!("{field}.bearing"),
                        &entity,
                        "passive bearing is not yet supported for a stack of geosynthetics: give it to a single geogrid",
                    );
                }
                if r.mode == ReinforcementMode::Embedded {
                    if spec.dilation.is_some() {
                        p.push(
                            format!("{field}.dilation"),
                            &entity,
                            "an embedded reinforcement's row holds it on a line through continuous soil, which cannot open: dilatancy needs the soil split along the reinforcement (leave out `mode`)",
                        );
                    }
                    if !r.stack.is_empty() {
                        p.push(
                            format!("{field}.reinforcement.stack"),
                            &entity,
                            "an embedded reinforcement takes no stack: lay a stack of geosynthetics in the split mode (leave out `mode`)",
                        );
                    }
                    if spec.lower_law.is_some() {
                        p.push(
                            format!("{field}.lower_law"),
                            &entity,
                            "an embedded reinforcement has the same soil on both faces and one law for both: leave out lower_law, or split the soil (leave out `mode`)",
                        );
                    }
                }
                if p.len() > before {
                    continue;
                }
                let sides_now = SideMap::new(mesh);
                let split = if r.mode == ReinforcementMode::Embedded {
                    embed::embed_reinforcement(
                        mesh,
                        &sides_now,
                        &spec.name,
                        &r.path,
                        r.free_length,
                        material,
                        stack.upper.clone(),
                        &mut next_bar_id,
                    )
                } else {
                    split::split_reinforcement(
                        mesh,
                        &sides_now,
                        &spec.name,
                        &r.path,
                        r.free_length,
                        &stack,
                        &mut next_bar_id,
                    )
                };
                match split {
                    Ok((mut interface, record)) => {
                        // the faces against the soil (not those between the layers of a stack)
                        for face in interface
                            .faces
                            .iter_mut()
                            .filter(|f| matches!(f.label.as_str(), "upper" | "lower" | "embedded"))
                        {
                            face.dilation = dilation;
                            face.bearing = bearing;
                        }
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
                    Err(found) => report_geometry(p, &format!("{field}.reinforcement"), &entity, found),
                }
            }
            (None, Some(slave), Some(master)) => {
                if spec.lower_law.is_some() {
                    p.push(format!("{field}.lower_law"), &entity, "lower_law applies only to a reinforcement");
                }
                if spec.bearing.is_some() {
                    p.push(
                        format!("{field}.bearing"),
                        &entity,
                        "passive bearing is that of a geogrid's transverse members: it applies only to a reinforcement",
                    );
                }
                let Some(law) = law else { continue };
                let sides_now = SideMap::new(mesh);
                match pair::pair(mesh, &sides_now, &spec.name, slave, master, spec.master_normal, law) {
                    Ok(mut i) => {
                        for face in &mut i.faces {
                            face.dilation = dilation;
                        }
                        interfaces.push(i)
                    }
                    Err(found) => report_geometry(p, &field, &entity, found),
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
}

/// Report an interface's geometry problems under the interface's field.
fn report_geometry(p: &mut Problems, field: &str, entity: &str, found: Vec<GeometryProblem>) {
    for g in found {
        p.push(format!("{field}.{}", g.place), entity, g.message);
    }
}

/// The interface's dilatancy and passive bearing, checked; the laws they need are checked here too
/// (dilatancy needs a plastic slip: a law with a strength that slides, not `tie`, `linear` or
/// `hyperbolic`).
fn extras(spec: &InterfaceSpec, field: &str, entity: &str, p: &mut Problems) -> (Option<Dilation>, Option<Bearing>) {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let dilation = spec.dilation.as_ref().and_then(|d| {
        let before = p.len();
        if !(d.angle.is_finite() && (0.0..45.0).contains(&d.angle)) {
            p.push(format!("{field}.dilation.angle"), entity, format!("must be at least 0 and below 45 degrees (got {})", d.angle));
        }
        if !positive(d.max_dilation) {
            p.push(format!("{field}.dilation.max_dilation"), entity, format!("must be a positive length (got {})", d.max_dilation));
        }
        let laws = std::iter::once(("law", &spec.law)).chain(spec.lower_law.as_ref().map(|l| ("lower_law", l)));
        for (name, law) in laws {
            if matches!(law, ShearLawSpec::Tie | ShearLawSpec::Linear { .. } | ShearLawSpec::Hyperbolic { .. }) {
                p.push(
                    format!("{field}.{name}"),
                    entity,
                    "dilatancy grows with the plastic slip, and this law has none: use coulomb, peak-residual or softening",
                );
            }
        }
        (p.len() == before).then(|| Dilation { tan_angle: d.angle.to_radians().tan(), max: d.max_dilation })
    });
    let bearing = spec.bearing.as_ref().and_then(|b| {
        let before = p.len();
        let f = |name: &str| format!("{field}.bearing.{name}");
        if !positive(b.member_spacing) {
            p.push(f("member_spacing"), entity, format!("must be a positive length (got {})", b.member_spacing));
        }
        if !positive(b.member_thickness) || !(b.member_thickness < b.member_spacing) {
            p.push(
                f("member_thickness"),
                entity,
                format!(
                    "must be a positive length below the spacing (got {} with spacing {})",
                    b.member_thickness, b.member_spacing
                ),
            );
        }
        if !(b.bearing_fraction > 0.0 && b.bearing_fraction <= 1.0) {
            p.push(
                f("bearing_fraction"),
                entity,
                format!("must be above 0 and at most 1 (got {})", b.bearing_fraction),
            );
        }
        if !positive(b.mobilisation_displacement) {
            p.push(
                f("mobilisation_displacement"),
                entity,
                format!("must be a positive length (got {})", b.mobilisation_displacement),
            );
        }
        if matches!(spec.law, ShearLawSpec::Tie) {
            p.push(
                format!("{field}.law"),
                entity,
                "a tied reinforcement does not slide, and its members cannot bear: give a sliding law",
            );
        }
        let ratio = match (b.formula, b.friction_angle, b.ratio) {
            (BearingFormula::Ratio, None, Some(r)) if positive(r) => Some(r),
            (BearingFormula::Ratio, None, Some(r)) => {
                p.push(f("ratio"), entity, format!("σb/σn must be positive (got {r})"));
                None
            }
            (BearingFormula::Ratio, _, _) => {
                p.push(f("ratio"), entity, "the `ratio` formula takes `ratio` (σb/σn) and no friction_angle");
                None
            }
            (formula, Some(phi), None) if phi.is_finite() && phi > 0.0 && phi < 60.0 => {
                let tan_phi = phi.to_radians().tan();
                Some(if formula == BearingFormula::GeneralShear {
                    bearing::general_shear_ratio(tan_phi)
                } else {
                    bearing::punching_shear_ratio(tan_phi)
                })
            }
            (_, Some(phi), None) => {
                p.push(f("friction_angle"), entity, format!("must be above 0 and below 60 degrees (got {phi})"));
                None
            }
            (formula, _, _) => {
                let name = if formula == BearingFormula::GeneralShear { "general-shear" } else { "punching-shear" };
                p.push(
                    f("friction_angle"),
                    entity,
                    format!("the `{name}` formula takes the soil's friction_angle and no ratio"),
                );
                None
            }
        };
        let ratio = ratio?;
        (p.len() == before).then(|| {
            Bearing::new(b.member_spacing, b.member_thickness, b.bearing_fraction, ratio, b.mobilisation_displacement)
        })
    });
    (dilation, bearing)
}
