//! A fill column built in lifts, each placed stress-free on the ground it lands on.
//!
//! Reference: one-dimensional compression of a layered fill built in stages (the classical
//! embankment-settlement analysis, e.g. Potts & Zdravković, Finite Element Analysis in
//! Geotechnical Engineering: Application (2001) §1.6 on simulating construction; docs/verification.md
//! §5 for the constrained modulus M = E(1−ν)/((1+ν)(1−2ν))).
//!
//! With lift tops y₁ < y₂ < … < y_n and σⱼ(ζ) = γ·(yⱼ − ζ)⁺ the vertical stress once j lifts are in
//! place, a point at height y in lift i is placed where the ground below it then stood, and moves
//! afterwards with the compression of everything beneath it:
//!
//! ```text
//! settlement after stage j:  Dⱼ(y) = D_{i−1}(y_{i−1}) + (1/M)·∫₀^y [σⱼ(ζ) − σ_{i−1}(ζ)] dζ
//! ```
//!
//! Goal: quad8 elements (quadratic displacement, exact here) reproduce Dⱼ at every node after every
//! lift, and the final strains are −γ(H − y)/M: each lift was placed stress-free. Switching gravity
//! on for the whole column at once ends with the same settlement profile, γ(H·y − y²/2)/M (each
//! lift placed on the deformed column settles by what the soil above it adds, as the whole column
//! does), which the test also checks.
//!
//! ```text
//!   y = 4 +--+  lift 4
//!   y = 3 +--+  lift 3
//!   y = 2 +--+  lift 2
//!   y = 1 +--+  lift 1
//!   y = 0 ////  fixed; sides ux = 0
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

const E: f64 = 1.0e4;
const NU: f64 = 0.3;
const GAMMA: f64 = 20.0;
const LIFTS: usize = 4;

fn constrained_modulus() -> f64 {
    E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU))
}

fn column(staged: bool) -> ModelFile {
    let block = Block::new(SolidKind::Quad8, (0.0, 0.0), (1.0, LIFTS as f64), (1, 2 * LIFTS), "fill", 1, 1);
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), block.row_nodes(0));
    let mut sides = block.column_nodes(0);
    sides.extend(block.column_nodes(block.nx));
    node_sets.insert("sides".into(), sides);
    // two element rows per lift, numbered bottom up
    let mut element_sets = BTreeMap::new();
    for lift in 0..LIFTS {
        element_sets.insert(format!("lift-{}", lift + 1), vec![(2 * lift + 1) as u64, (2 * lift + 2) as u64]);
    }
    let mut soil = BTreeMap::new();
    soil.insert("fill".into(), SoilMaterial::linear_elastic(E, NU, GAMMA));
    let stages = if staged {
        (0..LIFTS)
            .map(|lift| Stage {
                name: format!("lift {}", lift + 1),
                load_factors: vec![0.5, 1.0],
                loads: if lift == 0 { vec![LoadSpec::Gravity { factor: 1.0 }] } else { Vec::new() },
                activate: vec![format!("lift-{}", lift + 1)],
                ..Default::default()
            })
            .collect()
    } else {
        vec![Stage {
            name: "gravity".into(),
            load_factors: vec![1.0],
            loads: vec![LoadSpec::Gravity { factor: 1.0 }],
            ..Default::default()
        }]
    };
    {
        let mut file = geoslip::model::file::ModelFile {
            title: "fill built in lifts".into(),
            materials: geoslip::model::file::Materials { soil, ..Default::default() },
            nodes: block.nodes,
            elements: block.elements,
            node_sets,
            supports: vec![support("base", &[Direction::X, Direction::Y]), support("sides", &[Direction::X])],
            stages,
            analysis: AnalysisSettings::default(),
            ..Default::default()
        };
        file.element_sets = element_sets;
        file
    }
}

/// Dⱼ(y): the settlement (positive down) of a point at height y after j lifts.
fn settlement(j: usize, y: f64) -> f64 {
    let m = constrained_modulus();
    let top = |k: usize| k as f64; // lift k ends at y = k
                                   // ∫₀^y σ_k(ζ) dζ with σ_k(ζ) = γ·(y_k − ζ)⁺
    let integral = |k: usize, y: f64| {
        let h = top(k);
        let b = y.min(h);
        GAMMA * (h * b - 0.5 * b * b)
    };
    // the lift the point belongs to
    let i = ((y - 1e-12).ceil() as usize).max(1);
    if i > j {
        return 0.0;
    }
    let placed_at = if i == 1 { 0.0 } else { settlement(i - 1, top(i - 1)) };
    placed_at + (integral(j, y) - integral(i - 1, y)) / m
}

#[test]
fn lifts_are_placed_stress_free_on_the_deformed_ground() {
    let model = common::model(&column(true), "lifts.toml");
    let c = common::run(&model, Backend::Auto);
    // the last step of each stage
    let ends: Vec<_> =
        (0..LIFTS).map(|s| c.steps.iter().rev().find(|(rec, _)| rec.stage_index == s).unwrap()).collect();
    for (j, (_, r)) in ends.iter().enumerate() {
        for &(id, x, d) in &r.displacements {
            let y = x[1];
            if y > (j + 1) as f64 + 1e-9 {
                continue; // not placed yet
            }
            let exact = settlement(j + 1, y);
            assert!(
                (-d[1] - exact).abs() < 1e-9 * settlement(LIFTS, 2.0),
                "after lift {}: node {id} at y = {y}: settlement {} against {exact}",
                j + 1,
                -d[1]
            );
        }
    }
    // each lift was placed stress-free: the final strains are those of the final stresses
    let m = constrained_modulus();
    for g in ends[LIFTS - 1].1.stresses(&model) {
        let exact = -GAMMA * (LIFTS as f64 - g.x[1]) / m;
        assert!((g.strain[1] - exact).abs() < 1e-9 * GAMMA * LIFTS as f64 / m, "strain at y = {}", g.x[1]);
        assert!((g.stress[1] + GAMMA * (LIFTS as f64 - g.x[1])).abs() < 1e-8 * GAMMA * LIFTS as f64);
    }
}

/// Linear elasticity in one dimension does not remember the order of loading: the column switched
/// on at once ends with the same displacements, γ(H·y − y²/2)/M.
#[test]
fn gravity_switched_on_at_once_ends_the_same() {
    let model = common::model(&column(false), "all-at-once.toml");
    let c = common::run(&model, Backend::Auto);
    let r = c.last().unwrap();
    let (m, h) = (constrained_modulus(), LIFTS as f64);
    for &(id, x, d) in &r.displacements {
        let y = x[1];
        let exact = GAMMA * (h * y - 0.5 * y * y) / m;
        assert!((-d[1] - exact).abs() < 1e-9 * exact.max(1e-3), "node {id} at y = {y}: {} against {exact}", -d[1]);
        assert!((exact - settlement(LIFTS, y)).abs() < 1e-12);
    }
}

/// A weightless lift placed on ground that settled unevenly (soft soil on the left, stiff on the
/// right) takes the uneven displacements of the ground as its starting geometry: it carries no
/// stress and moves nothing.
#[test]
fn a_lift_on_uneven_ground_starts_stress_free() {
    let ground = Block::new(SolidKind::Quad4, (0.0, 0.0), (4.0, 1.0), (4, 2), "soft", 1, 1);
    let lift = Block::new(SolidKind::Quad4, (0.0, 1.0), (4.0, 0.5), (4, 1), "weightless", 1_000, 100);
    let lift_ids: Vec<u64> = lift.elements.iter().map(|e| e.id).collect();
    let (nodes, mut elements, _) = common::stack(&ground, &lift);
    for (k, e) in elements.iter_mut().enumerate().take(ground.elements.len()) {
        if k % 4 >= 2 {
            e.material = "stiff".into();
        }
    }
    let mut soil = BTreeMap::new();
    soil.insert("soft".into(), SoilMaterial::linear_elastic(2.0e3, 0.3, 20.0));
    soil.insert("stiff".into(), SoilMaterial::linear_elastic(2.0e5, 0.3, 20.0));
    soil.insert("weightless".into(), SoilMaterial::linear_elastic(1.0e4, 0.3, 0.0));
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), ground.row_nodes(0));
    let mut element_sets = BTreeMap::new();
    element_sets.insert("lift".into(), lift_ids.clone());
    let mut file = geoslip::model::file::ModelFile {
        title: "lift on uneven ground".into(),
        materials: geoslip::model::file::Materials { soil, ..Default::default() },
        nodes,
        elements,
        node_sets,
        supports: vec![support("base", &[Direction::X, Direction::Y])],
        stages: vec![
            Stage {
                name: "ground".into(),
                load_factors: vec![1.0],
                loads: vec![LoadSpec::Gravity { factor: 1.0 }],
                ..Default::default()
            },
            Stage { name: "lift".into(), load_factors: vec![1.0], activate: vec!["lift".into()], ..Default::default() },
        ],
        analysis: AnalysisSettings::default(),
        ..Default::default()
    };
    file.element_sets = element_sets;
    let model = common::model(&file, "uneven.toml");
    let c = common::run(&model, Backend::Auto);
    let (before, after) = (&c.steps[0].1, &c.steps[1].1);
    let uneven = before.displacements.iter().map(|d| d.2[1]).fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(uneven > 1e-3, "the ground must settle unevenly for this test to mean anything");
    for (b, a) in before.displacements.iter().zip(&after.displacements) {
        if before.displacement_vector.len() == after.displacement_vector.len() && b.2 != [0.0, 0.0] {
            assert!((a.2[0] - b.2[0]).abs() < 1e-12 && (a.2[1] - b.2[1]).abs() < 1e-12, "node {} moved", a.0);
        }
    }
    for g in after.stresses(&model).iter().filter(|g| lift_ids.contains(&g.element)) {
        assert!(g.stress.iter().all(|s| s.abs() < 1e-9), "element {} carries {:?}", g.element, g.stress);
    }
}
