//! Tied-interface patch test on matching meshes.
//!
//! Reference: docs/verification.md §6, after Crisfield (2000), "Re-visiting the contact
//! patch test", Int. J. Numer. Meth. Engng 48, 435–449. Two blocks, each 1 m × 0.5 m, stacked and
//! joined by a `tie` interface (multipliers in the normal and tangential directions). E = 1e6 Pa,
//! ν = 0.3; the base held in y, the top pushed down 0.01 m, ux = 0 at the left corners.
//!
//! Exact: σx = τxy = 0, σy = E·ε/(1−ν²) = −10 989.01 Pa everywhere; the interface carries
//! σn = 10 989.01 Pa of compression. Goal: matching meshes pass to 1e-12.
//!
//! ```text
//!   uy = −0.01 on top
//!   +----+----+----+----+
//!   |    upper block    |      slave: its bottom nodes
//!   +----+----+----+----+  ←  tie
//!   +----+----+----+----+
//!   |    lower block    |      master: its top nodes
//!   +----+----+----+----+
//!   uy = 0 at the base
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::Block;
use geoslip::model::file::*;
use std::collections::BTreeMap;

const E: f64 = 1.0e6;
const NU: f64 = 0.3;

fn stacked_blocks(kind: SolidKind, nx: usize) -> ModelFile {
    let lower = Block::new(kind, (0.0, 0.0), (1.0, 0.5), (nx, 2), "soil", 1, 1);
    let upper = Block::new(kind, (0.0, 0.5), (1.0, 0.5), (nx, 2), "soil", 1001, 1001);
    let mut nodes = lower.nodes.clone();
    nodes.extend(upper.nodes.clone());
    let mut elements = lower.elements.clone();
    elements.extend(upper.elements.clone());
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), lower.row_nodes(0));
    node_sets.insert("top".into(), upper.row_nodes(2));
    node_sets.insert("left_corners".into(), vec![lower.node(0, 0), upper.node(0, 2)]);
    let mut soil = BTreeMap::new();
    soil.insert("soil".into(), SoilMaterial::linear_elastic(E, NU, 0.0));
    let target = |set: &str| (None, None, Some(set.to_string()));
    let (n0, ns0, s0) = target("base");
    let (n1, ns1, s1) = target("left_corners");
    ModelFile {
        title: "tied patch test".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Newton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes,
        elements,
        bars: Vec::new(),
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![
            Support { node: n0, nodes: ns0, set: s0, fix: vec![Direction::Y] },
            Support { node: n1, nodes: ns1, set: s1, fix: vec![Direction::X] },
        ],
        interfaces: vec![InterfaceSpec {
            name: "tie".into(),
            slave: Some(upper.row_nodes(0)),
            master: Some(lower.row_nodes(2)),
            law: ShearLawSpec::Tie,
            ..Default::default()
        }],
        stages: vec![Stage {
            name: "compress".into(),
            load_factors: vec![1.0],
            loads: Vec::new(),
            prescribed: vec![PrescribedDisplacement {
                node: None,
                nodes: None,
                set: Some("top".into()),
                ux: None,
                uy: Some(-0.01),
            }],
            ..Default::default()
        }],
        analysis: Default::default(),
        mesh: None,
        series: None,
        design: None,
    }
}

fn passes_to_round_off(kind: SolidKind) {
    let exact = -E * 0.01 / (1.0 - NU * NU);
    assert!((exact + 10_989.01).abs() < 0.01);
    let model = common::model(&stacked_blocks(kind, 4), "tied-patch.toml");
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let r = c.last().unwrap();
        for s in r.stresses(&model) {
            assert!(
                (s.stress[1] - exact).abs() <= 1e-12 * exact.abs(),
                "{kind:?}/{backend:?}: σy {} vs {exact}",
                s.stress[1]
            );
            assert!(s.stress[0].abs() <= 1e-12 * exact.abs(), "{kind:?}/{backend:?}: σx {}", s.stress[0]);
            assert!(s.stress[2].abs() <= 1e-12 * exact.abs(), "{kind:?}/{backend:?}: τxy {}", s.stress[2]);
        }
        for p in &r.interface_points {
            assert!(
                (p.sigma_n + exact).abs() <= 1e-12 * exact.abs(),
                "{kind:?}/{backend:?}: σn {} at node {}",
                p.sigma_n,
                p.slave_node
            );
            assert!(p.tau.abs() <= 1e-12 * exact.abs());
        }
    }
}

#[test]
fn tied_patch_quad4_matching_meshes() {
    passes_to_round_off(SolidKind::Quad4);
}

#[test]
fn tied_patch_tri3_matching_meshes() {
    passes_to_round_off(SolidKind::Tri3);
}
