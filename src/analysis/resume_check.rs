//! What a saved step must hold before a run continues from it. A saved step is a file, and a file
//! may come from anyone: it is checked field by field against the model it is to continue, so that
//! no index it carries points outside the model, no length differs from the model's, and no number
//! is other than finite. A saved step that passes can be wrong only in values a run could itself
//! have reached.

use super::checkpoint::Checkpoint;
use crate::interface::{multipliers, ContactFace, Interface, NormalState};
use crate::model::Model;

/// The first field of a saved step that does not fit the model, as a message.
pub type Misfit = String;

fn finite(values: &[f64], what: &str) -> Result<(), Misfit> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(format!("{what}[{i}] is {}, not a finite number", values[i])),
        None => Ok(()),
    }
}

fn length(values: &[f64], expected: usize, what: &str) -> Result<(), Misfit> {
    if values.len() != expected {
        return Err(format!("{what} holds {} values and the model needs {expected}", values.len()));
    }
    finite(values, what)
}

/// Check every field of `saved` against `model`, for a continuation of stage `stage_index` from
/// converged step `step` (what the file's name says it holds).
///
/// # Errors
/// The first field that does not fit, named.
pub fn check(saved: &Checkpoint, model: &Model, stage_index: usize, step: usize) -> Result<(), Misfit> {
    let Some(stage) = model.stages.get(saved.stage_index) else {
        return Err(format!("its stage index {} is past the model's {} stages", saved.stage_index, model.stages.len()));
    };
    if saved.stage_index != stage_index || saved.step != step {
        return Err(format!(
            "it holds stage {} step {}, and its name says stage {} step {step}",
            saved.stage_index + 1,
            saved.step,
            stage_index + 1
        ));
    }
    if stage.dynamic.is_some() {
        return Err(format!("its stage \"{}\" is dynamic, and a dynamic stage keeps no saved steps", stage.name));
    }
    if saved.stage != stage.name {
        return Err(format!(
            "it names its stage \"{}\", and that stage of the model is \"{}\"",
            saved.stage, stage.name
        ));
    }
    let dofs = 2 * model.mesh.nodes.len();
    let s = &saved.state;
    length(&s.u, dofs, "u")?;
    length(&s.f_ext, dofs, "f_ext")?;
    length(&s.u_committed, dofs, "u_committed")?;
    length(&s.lambda, multipliers(&model.interfaces).len(), "lambda")?;
    if let Some(from) = &s.soil_sigma_from {
        length(from, dofs, "soil_sigma_from")?;
    }
    if !s.placed.is_empty() && s.placed.len() != model.mesh.nodes.len() {
        return Err(format!("placed holds {} nodes and the model has {}", s.placed.len(), model.mesh.nodes.len()));
    }
    let bars = model.mesh.bars.len();
    if s.bars.ruptured.len() != bars || s.bars.absent.len() != bars {
        return Err(format!("the bar states are for {} bars and the model has {bars}", s.bars.ruptured.len()));
    }
    length(&s.bars.placed_stretch, bars, "placed_stretch")?;
    check_soil(saved, model)?;
    check_interfaces(&s.interfaces, &model.interfaces, s.lambda.len())?;
    if let Some(frozen) = &s.frozen_sigma_n {
        let springs: usize =
            model.interfaces.iter().filter(|i| !i.is_tie()).flat_map(|i| &i.faces).map(|f| f.points.len()).sum();
        length(frozen, springs, "frozen_sigma_n")?;
    }

    if saved.held.len() != dofs {
        return Err(format!("held holds {} DOFs and the model has {dofs}", saved.held.len()));
    }
    finite(&[saved.gravity], "gravity")?;
    length(&saved.applied_weight, dofs, "applied_weight")?;
    let p = &saved.progress;
    for (values, what) in
        [(&p.force, "force"), (&p.f_ext_start, "f_ext_start"), (&p.unbalance, "unbalance"), (&p.u_start, "u_start")]
    {
        if !values.is_empty() {
            length(values, dofs, what)?;
        }
    }
    finite(&p.targets, "targets")?;
    finite(&[p.reached], "reached")?;
    if p.cutbacks > model.analysis.max_cutbacks {
        return Err(format!(
            "it counts {} cutbacks, more than max_cutbacks = {}",
            p.cutbacks, model.analysis.max_cutbacks
        ));
    }
    // each cutback of the increment in progress puts one midpoint before the plan's factors
    if p.targets.len() > stage.load_factors.len() + p.cutbacks {
        return Err(format!(
            "it has {} load factors still to reach, more than the stage's {} and its {} cutbacks' midpoints",
            p.targets.len(),
            stage.load_factors.len(),
            p.cutbacks
        ));
    }
    if p.planned > stage.load_factors.len() {
        return Err(format!("it has reached step {} of a stage of {}", p.planned, stage.load_factors.len()));
    }
    if let Some(last) = &p.last {
        length(&last.u_before, dofs, "last.u_before")?;
        length(&last.lambda_before, s.lambda.len(), "last.lambda_before")?;
        finite(&[last.from, last.to], "last increment's load factors")?;
    }
    Ok(())
}

fn check_soil(saved: &Checkpoint, model: &Model) -> Result<(), Misfit> {
    let soil = &saved.state.soil;
    let solids = &model.mesh.solids;
    if soil.elements().len() != solids.len() {
        return Err(format!("it has {} soil elements and the model {}", soil.elements().len(), solids.len()));
    }
    let rule = model.integration();
    for (k, (e, solid)) in soil.elements().iter().zip(solids).enumerate() {
        let what = |field: &str| format!("soil element {k}'s {field}");
        let element_dofs = 2 * solid.nodes.len();
        let points = crate::element::solid::gauss_points(solid.kind, rule).len();
        if let Some(placed) = &e.placed {
            length(placed, element_dofs, &what("placed"))?;
        }
        if let Some(force) = &e.reference_force {
            length(force, element_dofs, &what("reference_force"))?;
        }
        if let Some(force) = &e.pore_force {
            length(force, element_dofs, &what("pore_force"))?;
        }
        if !e.points.is_empty() && e.points.len() != points {
            return Err(format!(
                "{} holds {} Gauss points and the element has {points}",
                what("stress"),
                e.points.len()
            ));
        }
        for point in &e.points {
            finite(&point.stress, &what("stress"))?;
            finite(&[point.plastic_strain], &what("plastic strain"))?;
            finite(&[point.largest_stress_state], &what("largest stress state"))?;
            finite(&[point.shear_hardening, point.preconsolidation], &what("hardening parameters"))?;
        }
        if !e.pore.is_empty() {
            length(&e.pore, points, &what("pore pressure"))?;
        }
    }
    if let Some(water) = &soil.water {
        if water.line.is_empty() {
            return Err("its water table has no points".into());
        }
        let flat: Vec<f64> = water.line.iter().flatten().copied().chain([water.unit_weight]).collect();
        finite(&flat, "water table")?;
    }
    Ok(())
}

/// The interfaces' state: the same interfaces, faces and points as the model's, each point on a
/// segment of its face, every index in range and every number finite.
fn check_interfaces(saved: &[Interface], model: &[Interface], multiplier_count: usize) -> Result<(), Misfit> {
    if saved.len() != model.len() {
        return Err(format!("it has {} interfaces and the model {}", saved.len(), model.len()));
    }
    for (a, b) in saved.iter().zip(model) {
        if a.name != b.name || a.slit_of != b.slit_of || a.faces.len() != b.faces.len() {
            return Err(format!("its interface \"{}\" is not the model's \"{}\"", a.name, b.name));
        }
        for (fa, fb) in a.faces.iter().zip(&b.faces) {
            check_face(fa, fb, multiplier_count)
                .map_err(|m| format!("interface \"{}\", {}: {m}", b.name, fb.named()))?;
        }
    }
    Ok(())
}

fn check_face(saved: &ContactFace, model: &ContactFace, multiplier_count: usize) -> Result<(), Misfit> {
    if saved.label != model.label
        || saved.master != model.master
        || saved.soil_on_left != model.soil_on_left
        || saved.points.len() != model.points.len()
    {
        return Err("its master path or its points are not the model's".into());
    }
    if format!("{:?}", saved.embedded) != format!("{:?}", model.embedded) {
        return Err("its host soil elements are not the model's".into());
    }
    let segments = model.master.len().saturating_sub(1);
    for (k, (p, q)) in saved.points.iter().zip(&model.points).enumerate() {
        let fail = |m: String| Err(format!("point {k}: {m}"));
        if p.slave != q.slave || p.slit_tip != q.slit_tip || p.pressure_from != q.pressure_from {
            return fail("its slave node is not the model's".into());
        }
        if p.segment >= segments {
            return fail(format!("its segment {} is past the face's {segments}", p.segment));
        }
        if let Some((lo, hi)) = p.reserved {
            if lo > hi || hi >= segments {
                return fail(format!("its reserved segments {lo}..={hi} are not within the face's {segments}"));
            }
        }
        if let Some(weights) = &p.weights {
            if let Some(&(i, _)) = weights.iter().find(|(i, _)| *i >= model.master.len()) {
                return fail(format!("a mortar weight names master node {i} of {}", model.master.len()));
            }
            let w: Vec<f64> = weights.iter().map(|(_, w)| *w).collect();
            finite(&w, "mortar weights").or_else(fail)?;
        }
        for state in [&p.normal_state, &p.tangential_state] {
            if let NormalState::Redundant { multiplier: Some(m), .. } = state {
                if *m >= multiplier_count {
                    return fail(format!("it is carried by multiplier {m} of {multiplier_count}"));
                }
            }
        }
        let sh = &p.shear;
        let mut numbers = vec![
            p.tangent[0],
            p.tangent[1],
            p.tributary,
            p.xi,
            p.gap0,
            sh.slip,
            sh.plastic_slip,
            sh.plastic_path,
            sh.tau,
            sh.direction,
            sh.bearing_slip,
            sh.bearing_tau,
        ];
        numbers.extend(sh.reversals.iter().flat_map(|&(s, t)| [s, t]));
        finite(&numbers, "its state").or_else(fail)?;
        if p.tributary < 0.0 {
            return fail(format!("its tributary length {} is negative", p.tributary));
        }
    }
    Ok(())
}
