//! Initial stresses: the K0 procedure and gravity loading of level ground, dry and with a water
//! table.
//!
//! Reference: the geostatic state of level ground (e.g. Potts & Zdravković, Finite Element Analysis
//! in Geotechnical Engineering: Theory (1999) §3.7; Craig's Soil Mechanics, 8th ed. (2012) §3.4):
//! σv = Σγᵢ·Δzᵢ (saturated unit weight below the water table), p = γw·(z − z_w),
//! σ′v = σv − p, σ′h = K0·σ′v; and one-dimensional compression under self-weight
//! (docs/verification.md §5): σ′h = ν/(1 − ν)·σ′v.
//!
//! Goal: the K0 procedure gives σ′v = γz (with layers and water) exactly at the Gauss points of
//! quad4 and quad8 elements, in equilibrium with the soil's weight (no displacement); gravity
//! loading of a laterally confined quad8 column gives the same σ′v exactly at the Gauss points and
//! σ′h = ν/(1−ν)·σ′v.
//!
//! ```text
//!   y = 6  +--+   ground surface
//!          |  |   layer "upper": γ = 18 above the water, 20 below; K0 from φ = 30°
//!   y = 4  |~~|   water table
//!   y = 3  +--+
//!          |  |   layer "lower": γ = 19 / 21, K0 = 0.6 given
//!   y = 0  +--+   fixed; sides ux = 0
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

const GAMMA_W: f64 = 10.0;

fn layered_column(kind: SolidKind, k0_procedure: bool, water: bool) -> ModelFile {
    let lower = Block::new(kind, (0.0, 0.0), (1.0, 3.0), (1, 6), "lower", 1, 1);
    // the upper block shares the lower block's top row
    let upper = Block::new(kind, (0.0, 3.0), (1.0, 3.0), (1, 6), "upper", 10_000, 1_000);
    let (nodes, elements, rename) = common::stack(&lower, &upper);
    let mut sides = lower.column_nodes(0);
    sides.extend(lower.column_nodes(lower.nx));
    sides.extend(upper.column_nodes(0).into_iter().filter(|n| !rename.contains_key(n)));
    sides.extend(upper.column_nodes(upper.nx).into_iter().filter(|n| !rename.contains_key(n)));
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), lower.row_nodes(0));
    node_sets.insert("sides".into(), sides);
    let mut upper_soil = SoilMaterial::linear_elastic(2.0e4, 0.3, 18.0);
    upper_soil.saturated_unit_weight = Some(20.0);
    upper_soil.model = SoilModel::MohrCoulomb;
    upper_soil.friction_angle = 30.0;
    upper_soil.cohesion = 2.0;
    let mut lower_soil = SoilMaterial::linear_elastic(5.0e4, 0.25, 19.0);
    lower_soil.saturated_unit_weight = Some(21.0);
    lower_soil.k0 = Some(0.6);
    let mut soil = BTreeMap::new();
    soil.insert("upper".into(), upper_soil);
    soil.insert("lower".into(), lower_soil);
    geoslip::model::file::ModelFile {
        title: "level ground".into(),
        materials: geoslip::model::file::Materials { soil, ..Default::default() },
        nodes,
        elements,
        node_sets,
        supports: vec![support("base", &[Direction::X, Direction::Y]), support("sides", &[Direction::X])],
        stages: vec![Stage {
            name: "geostatic".into(),
            load_factors: vec![1.0],
            loads: vec![LoadSpec::Gravity { factor: 1.0 }],
            initial_stress: k0_procedure.then_some(InitialStress::K0),
            water: water.then_some(WaterTable {
                level: Some(4.0),
                line: None,
                none: false,
                unit_weight: Some(GAMMA_W),
            }),
            ..Default::default()
        }],
        analysis: AnalysisSettings { scheme: Scheme::Newton, ..AnalysisSettings::default() },
        ..Default::default()
    }
}

/// Total vertical stress, pore pressure and K0 at height y of the layered column.
fn geostatic(y: f64, water: bool) -> (f64, f64, f64) {
    let wet = |from: f64, to: f64| if water { (to.min(4.0) - from).max(0.0) } else { 0.0 };
    let weight = |from: f64, to: f64, dry_g: f64, sat_g: f64| {
        let w = wet(from, to);
        sat_g * w + dry_g * (to - from - w)
    };
    let (sigma_v, k0) = if y >= 3.0 {
        (weight(y, 6.0, 18.0, 20.0), 1.0 - 30f64.to_radians().sin())
    } else {
        (weight(3.0, 6.0, 18.0, 20.0) + weight(y, 3.0, 19.0, 21.0), 0.6)
    };
    let p = if water { (GAMMA_W * (4.0 - y)).max(0.0) } else { 0.0 };
    (sigma_v, p, k0)
}

fn k0_procedure_is_exact(kind: SolidKind, water: bool) {
    let model = common::model(&layered_column(kind, true, water), "level-ground.toml");
    let c = common::run(&model, Backend::Auto);
    let r = c.last().unwrap();
    assert!(!r.stresses(&model).is_empty());
    for g in r.stresses(&model) {
        let (sigma_v, p, k0) = geostatic(g.x[1], water);
        let effective = sigma_v - p;
        assert!((g.pore_pressure - p).abs() < 1e-10 * sigma_v.max(1.0), "{kind:?} p at y = {}", g.x[1]);
        assert!(
            (-g.stress[1] - effective).abs() < 1e-9 * sigma_v.max(1.0),
            "{kind:?} σ′v at y = {}: {} vs {effective}",
            g.x[1],
            -g.stress[1]
        );
        assert!((-g.stress[0] - k0 * effective).abs() < 1e-9 * sigma_v.max(1.0), "{kind:?} σ′h at y = {}", g.x[1]);
        assert!(g.stress[2].abs() < 1e-9 * sigma_v.max(1.0));
    }
    // in equilibrium with the weight as it stands: nothing moves
    let moved = r.displacements.iter().fold(0.0f64, |m, (_, _, d)| m.max(d[0].abs()).max(d[1].abs()));
    assert!(moved < 1e-12, "{kind:?}: the K0 state moved the ground by {moved:e} m");
}

#[test]
fn k0_stresses_of_layered_ground_are_exact_at_the_gauss_points() {
    for kind in [SolidKind::Quad4, SolidKind::Quad8] {
        k0_procedure_is_exact(kind, false);
        k0_procedure_is_exact(kind, true);
    }
}

#[test]
fn gravity_loading_of_a_confined_quad8_column_is_exact() {
    // one elastic layer, so that σ′h = ν/(1−ν)·σ′v holds everywhere
    let mut file = layered_column(SolidKind::Quad8, false, true);
    file.materials.soil.insert("upper".into(), {
        let mut m = SoilMaterial::linear_elastic(5.0e4, 0.25, 19.0);
        m.saturated_unit_weight = Some(21.0);
        m
    });
    let model = common::model(&file, "level-ground.toml");
    let c = common::run(&model, Backend::Auto);
    let r = c.last().unwrap();
    for g in r.stresses(&model) {
        let y = g.x[1];
        let wet = (4.0 - y).max(0.0);
        let sigma_v = 21.0 * wet + 19.0 * (6.0 - y - wet);
        let effective = sigma_v - GAMMA_W * wet;
        assert!((-g.stress[1] - effective).abs() < 1e-8 * sigma_v, "σ′v at y = {y}: {} vs {effective}", -g.stress[1]);
        let lateral = 0.25 / 0.75 * effective;
        assert!((-g.stress[0] - lateral).abs() < 1e-8 * sigma_v, "σ′h at y = {y}");
    }
}
