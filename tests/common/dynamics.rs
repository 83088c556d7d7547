//! Models of the dynamic tests: a column in simple shear, and a dynamic stage shaking the base in x.

use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

/// g [m/s²], as geoslip takes a density from a unit weight.
pub const G: f64 = 9.80665;

/// A dynamic stage's spec: Δt, duration, HHT α, damping and mass, the base shaken in x by
/// `samples` [(t, m/s²)].
pub fn shaking_in_x(
    time_step: f64,
    duration: f64,
    alpha: f64,
    damping: Option<RayleighDamping>,
    mass: Lumping,
    samples: Vec<[f64; 2]>,
) -> DynamicSpec {
    DynamicSpec {
        time_step,
        duration,
        alpha,
        damping,
        mass,
        base_motion: vec![BaseMotion {
            direction: Direction::X,
            file: None,
            samples: Some(samples),
            unit: Some(AccelerationUnit::MetrePerSecondSquared),
            scale: 1.0,
        }],
        record: Vec::new(),
        absorbing: Vec::new(),
        compliant_base: None,
    }
}

/// A column `width` × `height` of `elements` quad4 elements stacked, in simple shear (every y
/// held, the base held in x), linear elastic with shear modulus `shear_modulus` (ν = 0.3) and
/// density `density`, under one dynamic stage `dynamic`; force tolerance `tolerance`.
pub fn shear_column(
    width: f64,
    height: f64,
    elements: usize,
    shear_modulus: f64,
    density: f64,
    dynamic: DynamicSpec,
    tolerance: f64,
) -> ModelFile {
    let block = Block::new(SolidKind::Quad4, (0.0, 0.0), (width, height), (1, elements), "soil", 1, 1);
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), block.row_nodes(0));
    node_sets.insert("all".into(), block.nodes.iter().map(|n| n.0).collect());
    let nu = 0.3;
    let mut soil = BTreeMap::new();
    soil.insert("soil".into(), SoilMaterial::linear_elastic(2.0 * shear_modulus * (1.0 + nu), nu, density * G));
    ModelFile {
        title: "shear column".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes: block.nodes,
        elements: block.elements,
        bars: Vec::new(),
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![support("base", &[Direction::X]), support("all", &[Direction::Y])],
        interfaces: Vec::new(),
        stages: vec![Stage { name: "shaking".into(), dynamic: Some(dynamic), ..Default::default() }],
        analysis: AnalysisSettings { force_tolerance: tolerance, ..Default::default() },
        mesh: None,
        series: None,
        design: None,
    }
}
