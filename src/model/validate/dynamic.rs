//! A dynamic stage: its time step and duration, the HHT-α parameter, Rayleigh damping and the base
//! motion (read from its record file, relative to the model file). A dynamic stage changes nothing
//! else: its loads, displacements, soil and water belong to the stages around it.

use crate::model::file::*;
use crate::model::ground_motion::{self, GroundMotion};
use crate::model::problems::Problems;
use crate::model::{AbsorbingSide, DynamicPlan, HalfSpace, LoadedSide, Model};
use std::collections::BTreeMap;
use std::path::Path;

/// The most time steps a dynamic stage may take.
pub const MAX_TIME_STEPS: usize = 1_000_000;

/// The standard acceleration of gravity [m/s²].
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// A dynamic stage's plan and its steps' factors (t/duration at each step); `None` with the
/// problems pushed when it is not sound.
#[allow(clippy::too_many_arguments)]
pub(super) fn dynamic(
    spec: &DynamicSpec,
    s: &Stage,
    source: &Path,
    units: &Units,
    node_sets: &BTreeMap<String, Vec<crate::mesh::NodeIndex>>,
    edge_sets: &BTreeMap<String, Vec<LoadedSide>>,
    field: &str,
    entity: &str,
    p: &mut Problems,
) -> Option<(DynamicPlan, Vec<f64>)> {
    let dfield = format!("{field}.dynamic");
    let before = p.len();
    let busy = [
        (!s.loads.is_empty(), "loads"),
        (!s.prescribed.is_empty(), "prescribed displacements"),
        (!s.activate.is_empty() || !s.deactivate.is_empty(), "soil placed or removed"),
        (s.water.is_some(), "a water table"),
        (s.initial_stress.is_some(), "initial stresses"),
        (s.history.is_some() || s.load_factors != [1.0], "load factors"),
        (s.strength_reduction.is_some(), "a strength reduction"),
        (s.compaction.is_some(), "a compaction"),
    ];
    let found: Vec<&str> = busy.iter().filter(|(b, _)| *b).map(|(_, what)| *what).collect();
    if !found.is_empty() {
        p.push(
            &dfield,
            entity,
            format!(
                "a dynamic stage takes only its base motion; move its {} to a stage before or after it",
                found.join(", ")
            ),
        );
    }
    let (dt, duration) = (spec.time_step, spec.duration);
    if !(dt.is_finite() && dt > 0.0) {
        p.push(format!("{dfield}.time_step"), entity, format!("must be a positive number of seconds, found {dt}"));
    }
    if !(duration.is_finite() && duration > 0.0) {
        p.push(format!("{dfield}.duration"), entity, format!("must be a positive number of seconds, found {duration}"));
    }
    let steps = (duration / dt - 1e-9).ceil();
    // (an infinite or NaN count, from a finite step and duration far apart, is refused as well)
    if dt > 0.0 && duration > 0.0 && !(steps <= MAX_TIME_STEPS as f64) {
        p.push(
            format!("{dfield}.time_step"),
            entity,
            format!("{duration:?} s in steps of {dt:?} s makes {steps:e} steps; a dynamic stage takes at most {MAX_TIME_STEPS}"),
        );
    }
    if !(-1.0 / 3.0..=0.0).contains(&spec.alpha) {
        p.push(format!("{dfield}.alpha"), entity, format!("HHT's α must be in [−1/3, 0], found {}", spec.alpha));
    }
    let rayleigh = spec.damping.as_ref().map_or(Some([0.0, 0.0]), |d| rayleigh(d, &dfield, entity, p));
    let metre = Model::metre(units);
    let dir = source.parent().unwrap_or(Path::new("."));
    let mut base_motion = Vec::new();
    for (k, motion) in spec.base_motion.iter().enumerate() {
        let mfield = format!("{dfield}.base_motion[{k}]");
        if spec.base_motion[..k].iter().any(|m| m.direction == motion.direction) {
            p.push(format!("{mfield}.direction"), entity, "a second motion in the same direction");
        }
        if let Some(m) = base(motion, dir, metre, &mfield, entity, p) {
            base_motion.push((motion.direction, m));
        }
    }
    for (k, name) in spec.record.iter().enumerate() {
        if !node_sets.contains_key(name) {
            p.push(format!("{dfield}.record[{k}]"), entity, format!("no node set \"{name}\""));
        }
    }
    let gravity = STANDARD_GRAVITY * metre;
    let absorbing = absorbing(spec, edge_sets, gravity, &dfield, entity, p);
    if p.len() > before {
        return None;
    }
    let steps = steps.max(1.0) as usize;
    let factors = (1..=steps).map(|k| if k == steps { 1.0 } else { k as f64 * dt / duration }).collect();
    let plan = DynamicPlan {
        time_step: dt,
        duration,
        alpha: spec.alpha,
        rayleigh: rayleigh?,
        lumping: spec.mass,
        base_motion,
        gravity,
        record: spec.record.clone(),
        absorbing,
        compliant_base: spec.compliant_base.is_some(),
    };
    Some((plan, factors))
}

/// Rayleigh's a0 and a1: from a ratio at two frequencies or given.
fn rayleigh(d: &RayleighDamping, dfield: &str, entity: &str, p: &mut Problems) -> Option<[f64; 2]> {
    let field = format!("{dfield}.damping");
    match (d.ratio, d.frequencies, d.mass_coefficient, d.stiffness_coefficient) {
        (Some(ratio), Some([f1, f2]), None, None) => {
            let before = p.len();
            if !(0.0..1.0).contains(&ratio) {
                p.push(format!("{field}.ratio"), entity, format!("must be in [0, 1), found {ratio}"));
            }
            if !(f1.is_finite() && f1 > 0.0 && f2.is_finite() && f2 > f1) {
                p.push(
                    format!("{field}.frequencies"),
                    entity,
                    format!("give two frequencies 0 < f1 < f2 [Hz], found [{f1}, {f2}]"),
                );
            }
            if p.len() > before {
                return None;
            }
            let (w1, w2) = (2.0 * std::f64::consts::PI * f1, 2.0 * std::f64::consts::PI * f2);
            Some([2.0 * ratio * w1 * w2 / (w1 + w2), 2.0 * ratio / (w1 + w2)])
        }
        (None, None, a0, a1) if a0.is_some() || a1.is_some() => {
            let (a0, a1) = (a0.unwrap_or(0.0), a1.unwrap_or(0.0));
            let sound = |a: f64| a.is_finite() && a >= 0.0;
            if !(sound(a0) && sound(a1)) {
                p.push(&field, entity, format!("the coefficients must be ≥ 0, found a0 = {a0}, a1 = {a1}"));
                return None;
            }
            Some([a0, a1])
        }
        _ => {
            p.push(
                &field,
                entity,
                "give `ratio` with two `frequencies`, or `mass_coefficient` and/or `stiffness_coefficient`",
            );
            None
        }
    }
}

/// One direction's base motion in the model's units (length per s²).
fn base(m: &BaseMotion, dir: &Path, metre: f64, mfield: &str, entity: &str, p: &mut Problems) -> Option<GroundMotion> {
    if !(m.scale.is_finite()) {
        p.push(format!("{mfield}.scale"), entity, format!("must be a finite number, found {}", m.scale));
        return None;
    }
    let (samples, at2) = match (&m.file, &m.samples) {
        (Some(file), None) => {
            let path = dir.join(file);
            match ground_motion::read_record(&path) {
                Ok(samples) => (samples, ground_motion::is_at2(&path)),
                Err(e) => {
                    p.push(format!("{mfield}.file"), entity, format!("{}: {e}", path.display()));
                    return None;
                }
            }
        }
        (None, Some(samples)) => (samples.clone(), false),
        _ => {
            p.push(mfield, entity, "give the record as `file` or as `samples`, one of them");
            return None;
        }
    };
    let unit = match (m.unit, at2) {
        (Some(unit), _) => unit,
        (None, true) => AccelerationUnit::G,
        (None, false) => {
            p.push(format!("{mfield}.unit"), entity, "say the accelerations' unit: `g` or `m/s2`");
            return None;
        }
    };
    let per_unit = match unit {
        AccelerationUnit::G => STANDARD_GRAVITY,
        AccelerationUnit::MetrePerSecondSquared => 1.0,
    } * metre;
    match GroundMotion::from_samples(&samples, m.scale * per_unit) {
        Ok(motion) => Some(motion),
        Err(e) => {
            let at = if m.file.is_some() { format!("{mfield}.file") } else { format!("{mfield}.samples") };
            p.push(at, entity, e);
            None
        }
    }
}

/// The absorbing sides and the compliant base's, each side once.
fn absorbing(
    spec: &DynamicSpec,
    edge_sets: &BTreeMap<String, Vec<LoadedSide>>,
    gravity: f64,
    dfield: &str,
    entity: &str,
    p: &mut Problems,
) -> Vec<AbsorbingSide> {
    let mut sides: Vec<AbsorbingSide> = Vec::new();
    let mut add = |set: &str,
                   directions: &[Direction],
                   field: String,
                   half_space: Option<HalfSpace>,
                   input: bool,
                   p: &mut Problems| {
        let Some(list) = edge_sets.get(set) else {
            p.push(format!("{field}.edges"), entity, format!("no edge set \"{set}\""));
            return;
        };
        if directions.is_empty() {
            p.push(format!("{field}.directions"), entity, "give the directions the dashpots act in: x, y or both");
            return;
        }
        let directions = [directions.contains(&Direction::X), directions.contains(&Direction::Y)];
        for side in list {
            if sides.iter().any(|s| s.side == *side) {
                p.push(
                    field,
                    entity,
                    format!("edge set \"{set}\" has a side that is already absorbing (its dashpots would count twice)"),
                );
                return;
            }
            sides.push(AbsorbingSide { side: *side, half_space, input, directions });
        }
    };
    for (k, a) in spec.absorbing.iter().enumerate() {
        add(&a.edges, &a.directions, format!("{dfield}.absorbing[{k}]"), None, false, p);
    }
    if let Some(base) = &spec.compliant_base {
        let field = format!("{dfield}.compliant_base");
        let half_space = half_space(base, gravity, &field, entity, p);
        add(&base.edges, &base.directions, field, half_space, true, p);
    }
    sides
}

/// A compliant base's half-space: all three properties or none (the soil's own).
fn half_space(base: &CompliantBase, gravity: f64, field: &str, entity: &str, p: &mut Problems) -> Option<HalfSpace> {
    match (base.unit_weight, base.shear_wave_velocity, base.poissons_ratio) {
        (None, None, None) => None,
        (Some(gamma), Some(vs), Some(nu)) => {
            let before = p.len();
            if !(gamma.is_finite() && gamma > 0.0) {
                p.push(format!("{field}.unit_weight"), entity, format!("must be a positive number, found {gamma}"));
            }
            if !(vs.is_finite() && vs > 0.0) {
                p.push(
                    format!("{field}.shear_wave_velocity"),
                    entity,
                    format!("must be a positive number, found {vs}"),
                );
            }
            if !(nu > -1.0 && nu < 0.5) {
                p.push(format!("{field}.poissons_ratio"), entity, format!("must be in (−1, 0.5), found {nu}"));
            }
            if p.len() > before {
                return None;
            }
            let density = gamma / gravity;
            let shear = density * vs * vs;
            Some(HalfSpace::elastic(density, 2.0 * shear * (1.0 + nu), nu))
        }
        _ => {
            p.push(
                field,
                entity,
                "give the half-space's unit_weight, shear_wave_velocity and poissons_ratio, all three, or none (the soil's own)",
            );
            None
        }
    }
}
