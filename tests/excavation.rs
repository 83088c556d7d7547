//! Excavation of the top layer of level ground: one-dimensional unloading.
//!
//! Reference: one-dimensional (oedometric) unloading of an elastic layer (docs/verification.md §5, with
//! M = E(1−ν)/((1+ν)(1−2ν))): removing a layer of thickness t and unit weight γ from level ground of
//! height H unloads the rest by Δσv = γt everywhere, so the remaining ground heaves by
//! u(y) = γ·t·y/M at height y, and σ′v = γ(H − y) − γt, σ′h = K0·γ(H − y) − ν/(1 − ν)·γt.
//!
//! Goal: after K0 initial stresses, deactivating the top layer (over two load factors) gives these
//! displacements and stresses exactly (quad8: the fields are linear), and the removed soil leaves no
//! trace in the results.
//!
//! ```text
//!   y = 4  +--+  removed ("cut")
//!   y = 3  +--+
//!          |  |  remains
//!   y = 0  +--+  fixed; sides ux = 0
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

const E: f64 = 2.0e4;
const NU: f64 = 0.3;
const GAMMA: f64 = 18.0;
const K0: f64 = 0.55;
const H: f64 = 4.0;
const CUT: f64 = 1.0;

#[test]
fn removing_the_top_layer_heaves_and_unloads_the_rest_as_one_dimensional_unloading() {
    let block = Block::new(SolidKind::Quad8, (0.0, 0.0), (1.0, H), (1, 8), "ground", 1, 1);
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), block.row_nodes(0));
    let mut sides = block.column_nodes(0);
    sides.extend(block.column_nodes(block.nx));
    node_sets.insert("sides".into(), sides);
    let mut ground = SoilMaterial::linear_elastic(E, NU, GAMMA);
    ground.k0 = Some(K0);
    let mut soil = BTreeMap::new();
    soil.insert("ground".into(), ground);
    let mut file = geoslip::model::file::ModelFile {
        title: "excavation".into(),
        materials: geoslip::model::file::Materials { soil, ..Default::default() },
        nodes: block.nodes,
        elements: block.elements,
        node_sets,
        supports: vec![support("base", &[Direction::X, Direction::Y]), support("sides", &[Direction::X])],
        stages: vec![
            Stage {
                name: "geostatic".into(),
                load_factors: vec![1.0],
                loads: vec![LoadSpec::Gravity { factor: 1.0 }],
                initial_stress: Some(InitialStress::K0),
                ..Default::default()
            },
            Stage {
                name: "excavate".into(),
                load_factors: vec![0.5, 1.0],
                deactivate: vec!["cut".into()],
                ..Default::default()
            },
        ],
        analysis: AnalysisSettings::default(),
        ..Default::default()
    };
    // the top two element rows (y from 3 to 4)
    file.element_sets.insert("cut".into(), vec![7, 8]);
    let model = common::model(&file, "excavation.toml");
    let c = common::run(&model, Backend::Auto);
    let r = c.last().unwrap();
    let m = E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let scale = GAMMA * CUT * (H - CUT) / m;
    for &(id, x, d) in &r.displacements {
        let y = x[1];
        let expected = if y <= H - CUT + 1e-9 { GAMMA * CUT * y / m } else { 0.0 };
        if y <= H - CUT + 1e-9 {
            assert!((d[1] - expected).abs() < 1e-9 * scale, "node {id} at y = {y}: uy {} against {expected}", d[1]);
        }
    }
    assert!(r.stresses(&model).iter().all(|g| g.element <= 6), "the removed elements have no results");
    for g in r.stresses(&model) {
        let y = g.x[1];
        let sv = GAMMA * (H - y) - GAMMA * CUT;
        let sh = K0 * GAMMA * (H - y) - NU / (1.0 - NU) * GAMMA * CUT;
        assert!((-g.stress[1] - sv).abs() < 1e-9 * GAMMA * H, "σ′v at y = {y}: {} against {sv}", -g.stress[1]);
        assert!((-g.stress[0] - sh).abs() < 1e-9 * GAMMA * H, "σ′h at y = {y}: {} against {sh}", -g.stress[0]);
    }
}
