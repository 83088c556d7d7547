//! Stages: load factors, loads, prescribed displacements, soil and reinforcement placed and
//! removed, water, initial stresses and strength reduction.

use super::{dynamic, Draft};
use crate::model::file::*;
use crate::model::problems::Problems;
use crate::model::{Load, Model, StagePlan, StrengthReduction, WaterTable};
use std::collections::HashSet;

/// Where in the file a stage's problems are: its field and the entity messages name.
struct At {
    field: String,
    entity: String,
}

/// Every stage, in order (`source`: the model file, whose folder a record file is read from).
pub(super) fn stages(d: &mut Draft, file: &ModelFile, source: &std::path::Path, p: &mut Problems) {
    let water_weight = Model::default_water_weight(&file.units);

    if file.stages.is_empty() {
        p.push(
            "stages",
            None,
            "the model has no stages: add at least one [[stages]] with loads or prescribed displacements",
        );
    }
    let mut placed: HashSet<usize> = HashSet::new();
    let mut placed_bars: HashSet<usize> = HashSet::new();
    let mut stage_names = HashSet::new();
    for (k, s) in file.stages.iter().enumerate() {
        let at = At { field: format!("stages[{k}]"), entity: format!("stage \"{}\"", s.name) };
        let At { field, entity } = &at;
        if !stage_names.insert(s.name.clone()) {
            p.push(format!("{field}.name"), entity, "duplicate stage name");
        }
        let dynamic = s
            .dynamic
            .as_ref()
            .map(|spec| dynamic::dynamic(spec, s, source, &file.units, &d.node_sets, &d.edge_sets, field, entity, p));
        let from_history = s.history.as_ref().filter(|_| s.dynamic.is_none()).map(|h| history(h, s, &at, p));
        let (lf, reversals) = match (&from_history, &dynamic) {
            (Some(Some((factors, reversals))), _) => (factors, reversals.clone()),
            (_, Some(Some((_, factors)))) => (factors, Vec::new()),
            _ => (&s.load_factors, Vec::new()),
        };
        if from_history.is_none() && s.dynamic.is_none() {
            // (a history's factors were checked with it)
            load_factors(lf, &format!("{field}.load_factors"), entity, p);
        }
        let loads = loads(d, s, &at, p);
        let prescribed = prescribed(d, s, &at, p);
        let (activate, activate_bars) = named_sets(d, &s.activate, "activate", &at, p);
        let (deactivate, _) = named_sets(d, &s.deactivate, "deactivate", &at, p);
        for &b in &activate_bars {
            if !placed_bars.insert(b) {
                p.push(format!("{field}.activate"), format!("bar {}", d.mesh.bars[b].id), "is placed twice");
            }
        }
        for &e in &activate {
            if !placed.insert(e) {
                p.push(
                    format!("{field}.activate"),
                    format!("element {}", d.mesh.solids[e].id),
                    "is placed twice (in two stages, or in two sets of one stage)",
                );
            }
        }
        let water = s.water.as_ref().map(|w| water(w, water_weight, &at, p));
        let strength_reduction = s.strength_reduction.as_ref().map(|r| strength_reduction(r, s, k, &at, p));
        d.stages.push(StagePlan {
            name: s.name.clone(),
            strength_reduction,
            load_factors: lf.clone(),
            reversals,
            cyclic: from_history.is_some(),
            loads,
            prescribed,
            activate,
            deactivate,
            activate_bars,
            k0: s.initial_stress == Some(InitialStress::K0),
            water,
            freeze_normal_stress: s.freeze_normal_stress,
            dynamic: dynamic.and_then(|d| d.map(|(plan, _)| plan)),
        });
    }
    absorbing_sides_present(d, p);
    compaction(d, file, &mut stage_names, p);
}

/// Each dynamic stage's absorbing sides belong to soil present in it.
fn absorbing_sides_present(d: &Draft, p: &mut Problems) {
    let mut present = vec![true; d.mesh.solids.len()];
    for plan in &d.stages {
        for &e in &plan.activate {
            present[e] = false;
        }
    }
    for (k, plan) in d.stages.iter().enumerate() {
        for &e in &plan.deactivate {
            present[e] = false;
        }
        for &e in &plan.activate {
            present[e] = true;
        }
        let absorbing = plan.dynamic.iter().flat_map(|dynamic| &dynamic.absorbing);
        if let Some(a) = absorbing.into_iter().find(|a| !present[a.side.solid]) {
            p.push(
                format!("stages[{k}].dynamic"),
                format!("stage \"{}\"", plan.name),
                format!(
                    "an absorbing side belongs to element {}, which is not present in this stage",
                    d.mesh.solids[a.side.solid].id
                ),
            );
        }
    }
}

/// Load factors at `field`: at most `MAX_LOAD_FACTORS`, increasing within (0, 1], ending at 1.
fn load_factors(lf: &[f64], field: &str, entity: &str, p: &mut Problems) {
    if lf.len() > super::MAX_LOAD_FACTORS {
        p.push(field, entity, format!("at most {} load factors a stage, found {}", super::MAX_LOAD_FACTORS, lf.len()));
    } else if lf.is_empty()
        || lf.iter().any(|f| !f.is_finite() || *f <= 0.0 || *f > 1.0 + 1e-12)
        || lf.windows(2).any(|w| w[1] <= w[0])
        || (lf[lf.len() - 1] - 1.0).abs() > 1e-12
    {
        p.push(field, entity, format!("load factors must increase within (0, 1] and end at 1.0, found {lf:?}"));
    }
}

/// After each stage that compacts its lift, two more: one that applies the compaction pressure on
/// the lift's surface over the compaction's load factors, one that removes it the same way.
fn compaction(d: &mut Draft, file: &ModelFile, stage_names: &mut HashSet<String>, p: &mut Problems) {
    if file.stages.iter().all(|s| s.compaction.is_none()) || d.stages.len() != file.stages.len() {
        return;
    }
    // each element's presence after each stage, and the elements on each side (by its corners)
    let mut present = vec![true; d.mesh.solids.len()];
    for plan in &d.stages {
        for &e in &plan.activate {
            present[e] = false;
        }
    }
    let mut on_side: std::collections::HashMap<(usize, usize), Vec<usize>> = std::collections::HashMap::new();
    for (e, solid) in d.mesh.solids.iter().enumerate() {
        for side in solid.kind.sides() {
            let (a, b) = (solid.nodes[side[0]], solid.nodes[side[1]]);
            on_side.entry((a.min(b), a.max(b))).or_default().push(e);
        }
    }
    let plans = std::mem::take(&mut d.stages);
    for (k, (plan, s)) in plans.into_iter().zip(&file.stages).enumerate() {
        for &e in &plan.deactivate {
            present[e] = false;
        }
        for &e in &plan.activate {
            present[e] = true;
        }
        let surface = s.compaction.as_ref().and_then(|c| {
            let at = At { field: format!("stages[{k}].compaction"), entity: format!("stage \"{}\"", s.name) };
            compacted_sides(d, c, &plan, &present, &on_side, &at, p).map(|sides| (c, sides))
        });
        d.stages.push(plan);
        let Some((c, sides)) = surface else { continue };
        for (suffix, pressure) in [("compaction", c.pressure), ("compaction removed", -c.pressure)] {
            let name = format!("{}: {suffix}", s.name);
            if !stage_names.insert(name.clone()) {
                p.push(
                    format!("stages[{k}].compaction"),
                    format!("stage \"{}\"", s.name),
                    format!("adds the stage \"{name}\", but the model has a stage of that name"),
                );
            }
            d.stages.push(StagePlan {
                name,
                load_factors: c.load_factors.clone(),
                loads: vec![Load::EdgeTraction { sides: sides.clone(), pressure, shear: 0.0 }],
                ..StagePlan::default()
            });
        }
    }
}

/// The sides a compaction presses on: its edge set, or the upward-facing sides of the elements the
/// stage places (of its material, if it names one) that no element present after the stage covers.
fn compacted_sides(
    d: &Draft,
    c: &CompactionSpec,
    plan: &StagePlan,
    present: &[bool],
    on_side: &std::collections::HashMap<(usize, usize), Vec<usize>>,
    at: &At,
    p: &mut Problems,
) -> Option<Vec<crate::model::LoadedSide>> {
    let At { field, entity } = at;
    let problems = p.len();
    if !(c.pressure.is_finite() && c.pressure > 0.0) {
        p.push(format!("{field}.pressure"), entity, format!("must be a pressure > 0, found {}", c.pressure));
    }
    load_factors(&c.load_factors, &format!("{field}.load_factors"), entity, p);
    if plan.strength_reduction.is_some() || plan.cyclic {
        p.push(field.as_str(), entity, "a strength-reduction stage or a stage with a history compacts nothing: compact the lift in the stage that places it");
    }
    let material = match &c.material {
        Some(name) => match d.soil_index.get(name) {
            Some(&m) => Some(m),
            None => {
                p.push(format!("{field}.material"), entity, format!("no soil material named \"{name}\""));
                None
            }
        },
        None => None,
    };
    let sides = match &c.edge_set {
        Some(name) => match d.edge_sets.get(name) {
            Some(sides) => sides.clone(),
            None => {
                p.push(format!("{field}.edge_set"), entity, format!("no edge set named \"{name}\""));
                Vec::new()
            }
        },
        None => {
            let mut sides = Vec::new();
            for &e in plan.activate.iter().filter(|&&e| material.is_none_or(|m| d.mesh.solids[e].material == m)) {
                let solid = &d.mesh.solids[e];
                for (k, side) in solid.kind.sides().iter().enumerate() {
                    let (a, b) = (solid.nodes[side[0]], solid.nodes[side[1]]);
                    let ([xa, ya], [xb, yb]) = (d.mesh.position(a), d.mesh.position(b));
                    // the solid lies to the left of a → b: its outward normal is (dy, −dx)
                    let upward = -(xb - xa) >= 0.5 * (xb - xa).hypot(yb - ya);
                    let covered = on_side[&(a.min(b), a.max(b))].iter().any(|&other| other != e && present[other]);
                    if upward && !covered {
                        sides.push(crate::model::LoadedSide { solid: e, side: k });
                    }
                }
            }
            sides
        }
    };
    if p.len() > problems {
        return None;
    }
    if sides.is_empty() {
        p.push(
            field.as_str(),
            entity,
            "finds no surface to press on: the stage places no soil with an upward-facing free side (give an edge_set)",
        );
        return None;
    }
    Some(sides)
}

/// The stage's loads.
fn loads(d: &Draft, s: &Stage, at: &At, p: &mut Problems) -> Vec<Load> {
    let At { field, entity } = at;
    let mut loads = Vec::new();
    for (j, l) in s.loads.iter().enumerate() {
        let lfield = format!("{field}.loads[{j}]");
        match l {
            LoadSpec::EdgeTraction { edge_set, pressure, shear, .. } => {
                if !(pressure.is_finite() && shear.is_finite()) {
                    p.push(&lfield, entity, "pressure and shear must be finite numbers");
                }
                match d.edge_sets.get(edge_set) {
                    Some(sides) => {
                        loads.push(Load::EdgeTraction { sides: sides.clone(), pressure: *pressure, shear: *shear })
                    }
                    None => p.push(format!("{lfield}.edge_set"), entity, format!("no edge set named \"{edge_set}\"")),
                }
            }
            LoadSpec::Point { node, nodes, set, fx, fy } => {
                if !(fx.is_finite() && fy.is_finite()) {
                    p.push(&lfield, entity, "fx and fy must be finite numbers");
                }
                for n in d.resolve(
                    NodeTarget { node: *node, nodes: nodes.as_deref(), set: set.as_deref() },
                    &lfield,
                    p,
                    false,
                ) {
                    loads.push(Load::Point { node: n, force: [*fx, *fy] });
                }
            }
            LoadSpec::Gravity { factor } => {
                if !factor.is_finite() {
                    p.push(format!("{lfield}.factor"), entity, "must be a finite number");
                }
                if d.soils.iter().all(|(_, m)| m.unit_weight == 0.0) {
                    p.push(&lfield, entity, "gravity is applied but every soil material has unit_weight 0");
                }
                loads.push(Load::Gravity { factor: *factor });
            }
            LoadSpec::PseudoStatic { kh, kv } => {
                // beyond ±10 g no earthquake; the bound keeps the forces' arithmetic far from overflow
                if !(kh.abs() <= 10.0 && kv.abs() <= 10.0) {
                    p.push(&lfield, entity, format!("kh and kv must be within ±10, found kh = {kh}, kv = {kv}"));
                }
                loads.push(Load::PseudoStatic { coefficients: [*kh, *kv] });
            }
        }
    }
    loads
}

/// The stage's prescribed displacements: each DOF once, none on a support.
fn prescribed(d: &Draft, s: &Stage, at: &At, p: &mut Problems) -> Vec<(usize, Direction, f64)> {
    let At { field, entity } = at;
    let mut prescribed = Vec::new();
    let mut seen = HashSet::new();
    for (j, spec) in s.prescribed.iter().enumerate() {
        let pfield = format!("{field}.prescribed[{j}]");
        if spec.ux.is_none() && spec.uy.is_none() {
            p.push(&pfield, entity, "give ux, uy or both");
        }
        let t = spec.target();
        for n in d.resolve(t, &pfield, p, false) {
            for (dir, v) in [(Direction::X, spec.ux), (Direction::Y, spec.uy)] {
                let Some(v) = v else { continue };
                let label = format!("node {} {}", d.mesh.node_id(n), if dir == Direction::X { "ux" } else { "uy" });
                if !v.is_finite() {
                    p.push(&pfield, &label, "the displacement must be a finite number");
                } else if d.supported.contains(&(n, dir)) {
                    p.push(&pfield, &label, "this DOF is a fixed support; it cannot also be prescribed");
                } else if !seen.insert((n, dir)) {
                    p.push(&pfield, &label, "this DOF is prescribed twice in the same stage");
                } else {
                    prescribed.push((n, dir, v));
                }
            }
        }
    }
    prescribed
}

/// The soil elements (and, for `activate`, the reinforcements' bars) of the sets a stage names
/// under `key`.
fn named_sets(d: &Draft, names: &[String], key: &str, at: &At, p: &mut Problems) -> (Vec<usize>, Vec<usize>) {
    let At { field, entity } = at;
    let mut out = Vec::new();
    let mut bars = Vec::new();
    for (j, name) in names.iter().enumerate() {
        // a reinforcement interface by name: its bars
        let reinforcement = d.node_sets.get(&format!("{name}.reinforcement")).filter(|_| key == "activate");
        match (d.element_sets.get(name), reinforcement) {
            (Some(set), _) => out.extend(set.iter().copied()),
            (None, Some(nodes)) => {
                let nodes: HashSet<usize> = nodes.iter().copied().collect();
                bars.extend(
                    d.mesh
                        .bars
                        .iter()
                        .enumerate()
                        .filter(|(_, b)| b.nodes.iter().all(|n| nodes.contains(n)))
                        .map(|(i, _)| i),
                );
            }
            (None, None) => p.push(
                format!("{field}.{key}[{j}]"),
                entity,
                format!(
                    "no element set{} named \"{name}\"{}",
                    if key == "activate" { " or reinforcement" } else { "" },
                    if d.element_sets.is_empty() {
                        String::new()
                    } else {
                        format!("; there are: {}", d.element_sets.keys().cloned().collect::<Vec<_>>().join(", "))
                    }
                ),
            ),
        }
    }
    (out, bars)
}

/// The stage's water table (`None`: no water, or none given).
fn water(w: &crate::model::file::WaterTable, water_weight: f64, at: &At, p: &mut Problems) -> Option<WaterTable> {
    let At { field, entity } = at;
    let wfield = format!("{field}.water");
    let given = [w.level.is_some(), w.line.is_some(), w.none].iter().filter(|&&g| g).count();
    if given != 1 {
        p.push(&wfield, entity, "give exactly one of `level`, `line` or `none = true`");
    }
    let unit_weight = w.unit_weight.unwrap_or(water_weight);
    if !(unit_weight.is_finite() && unit_weight > 0.0) {
        p.push(format!("{wfield}.unit_weight"), entity, format!("must be positive, found {unit_weight}"));
    }
    let line = match (&w.level, &w.line) {
        (Some(y), _) => vec![[0.0, *y]],
        (_, Some(line)) => line.clone(),
        _ => Vec::new(),
    };
    if line.iter().any(|q| !(q[0].is_finite() && q[1].is_finite())) {
        p.push(&wfield, entity, "the water table's coordinates must be finite numbers");
    }
    if w.line.is_some() && (line.is_empty() || line.windows(2).any(|q| !(q[1][0] > q[0][0]))) {
        p.push(format!("{wfield}.line"), entity, "give at least one point, with x strictly increasing");
    }
    (!w.none && !line.is_empty()).then_some(WaterTable { line, unit_weight })
}

/// A strength-reduction stage's settings; such a stage changes nothing else and follows one that
/// loads the model.
fn strength_reduction(r: &StrengthReductionSpec, s: &Stage, k: usize, at: &At, p: &mut Problems) -> StrengthReduction {
    let At { field, entity } = at;
    let rfield = format!("{field}.strength_reduction");
    let tolerance = r.tolerance.unwrap_or(0.002);
    let max_factor = r.max_factor.unwrap_or(10.0);
    // below 1e-6 the bracket of F cannot shrink to its width in floating point: the search would not end
    if !(1e-6..=0.1).contains(&tolerance) {
        p.push(format!("{rfield}.tolerance"), entity, format!("must be in [1e-6, 0.1], found {tolerance:?}"));
    }
    if !(max_factor > 1.0 && max_factor.is_finite()) {
        p.push(format!("{rfield}.max_factor"), entity, format!("must be a number above 1, found {max_factor}"));
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
            entity,
            "a strength-reduction stage changes nothing but the strengths: move its loads, prescribed \
             displacements, activations, water and initial stresses to a stage before it",
        );
    }
    if k == 0 {
        p.push(&rfield, entity, "a strength-reduction stage needs a stage before it that loads the model");
    }
    StrengthReduction { soil: r.reduce == ReducedStrengths::SoilAndInterfaces, tolerance, max_factor }
}

/// The steps of a `history` table: the factor at each step, and the steps where it reverses; `None`
/// (with the problems pushed) when the table is not sound.
fn history(rows: &[[f64; 2]], s: &Stage, at: &At, p: &mut Problems) -> Option<(Vec<f64>, Vec<usize>)> {
    let At { field, entity } = at;
    let before = p.len();
    if s.load_factors != [1.0] {
        p.push(format!("{field}.history"), entity, "give load_factors or history, not both");
    }
    if s.strength_reduction.is_some() {
        p.push(format!("{field}.history"), entity, "a strength-reduction stage takes no loading history");
    }
    if rows.is_empty() {
        p.push(format!("{field}.history"), entity, "the table has no rows");
    }
    for (k, [t, f]) in rows.iter().enumerate() {
        if !t.is_finite() || !f.is_finite() || f.abs() > super::MAX_HISTORY_FACTOR {
            p.push(
                format!("{field}.history[{k}]"),
                entity,
                format!("time and factor must be finite numbers, the factor within ±{:e}", super::MAX_HISTORY_FACTOR),
            );
        } else if k > 0 && !(*t > rows[k - 1][0]) {
            p.push(
                format!("{field}.history[{k}]"),
                entity,
                format!("the times must increase: {t} after {}", rows[k - 1][0]),
            );
        }
    }
    let increment = s.history_increment;
    if let Some(inc) = increment {
        if !(inc > 0.0 && inc.is_finite()) {
            p.push(format!("{field}.history_increment"), entity, format!("{inc} is not a positive number"));
        }
    }
    if p.len() > before {
        return None;
    }
    // each segment from the stage's start (factor 0) through the rows, in equal steps no larger
    // than the increment; counted before anything is allocated
    let mut factors: Vec<f64> = std::iter::once(0.0).chain(rows.iter().map(|r| r[1])).collect();
    factors.dedup();
    let pieces = |a: f64, b: f64| increment.map_or(1.0, |inc| ((b - a).abs() / inc).ceil().max(1.0));
    let steps: f64 = factors.windows(2).map(|w| pieces(w[0], w[1])).sum();
    if steps > super::MAX_LOAD_FACTORS as f64 {
        p.push(
            format!("{field}.history_increment"),
            entity,
            format!("the history makes {steps} steps; a stage has at most {}", super::MAX_LOAD_FACTORS),
        );
        return None;
    }
    if steps < 1.0 {
        p.push(format!("{field}.history"), entity, "the factor never leaves 0: the stage has no step");
        return None;
    }
    let mut out = Vec::with_capacity(steps as usize);
    let mut reversals = Vec::new();
    for (k, w) in factors.windows(2).enumerate() {
        let n = pieces(w[0], w[1]) as usize;
        out.extend((1..=n).map(|i| if i == n { w[1] } else { w[0] + (w[1] - w[0]) * i as f64 / n as f64 }));
        if let Some(next) = factors.get(k + 2) {
            if (w[1] - w[0]) * (next - w[1]) < 0.0 {
                reversals.push(out.len());
            }
        }
    }
    Some((out, reversals))
}
