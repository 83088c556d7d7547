//! Separation: an uplifted block releases its base constraints, and no active multiplier is
//! tensile.
//!
//! Reference: the contact conditions themselves (the Signorini conditions of unilateral contact,
//! e.g. Wriggers, Computational Contact Mechanics, 2006, §4.1): on every point of the interface
//! g ≤ 0, λ ≥ 0 and λ·g = 0, with λ > 0 compression and g > 0 overlap (shared/DESIGN.md §1). A
//! soil block resting under its own weight on a rigid base is lifted at one top corner; the lifted
//! end must open (released rows, λ = 0, a gap) while the rest stays pressed (active rows, λ ≥ 0).
//!
//! ```text
//!                          ↑ uy = 0.02 m at this corner
//!             +----+----+----+----+
//!             |   γ = 20 kN/m³     |
//!             +----+----+----+----+        slave: the block's base
//!   o====o====o====o====o====o====o====o   master: rigid base (fixed nodes)
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::Block;
use geoslip::model::file::*;
use std::collections::BTreeMap;

fn lifted_block() -> ModelFile {
    let block = Block::new(SolidKind::Quad4, (0.0, 0.0), (1.0, 0.5), (8, 4), "soil", 1, 1);
    let mut nodes = block.nodes.clone();
    let base: Vec<u64> = (0..=12).map(|i| 1000 + i as u64).collect();
    for (i, id) in base.iter().enumerate() {
        nodes.push(NodeRow(*id, -0.25 + 0.125 * i as f64, 0.0));
    }
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), base.clone());
    let mut soil = BTreeMap::new();
    soil.insert("soil".into(), SoilMaterial::linear_elastic(1.0e4, 0.3, 20.0));
    ModelFile {
        title: "lifted block".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes,
        elements: block.elements.clone(),
        bars: Vec::new(),
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![geoslip::meshgen::support("base", &[Direction::X, Direction::Y])],
        interfaces: vec![InterfaceSpec {
            name: "base".into(),
            slave: Some(block.row_nodes(0)),
            master: Some(base),
            master_normal: Some([0.0, -1.0]),
            law: ShearLawSpec::Coulomb { shear_stiffness: 5000.0, cohesion: 2.0, friction_angle: 30.0 },
            ..Default::default()
        }],
        stages: vec![
            Stage {
                name: "self-weight".into(),
                load_factors: vec![1.0],
                loads: vec![LoadSpec::Gravity { factor: 1.0 }],
                prescribed: vec![],
                ..Default::default()
            },
            Stage {
                name: "uplift".into(),
                load_factors: vec![0.25, 0.5, 0.75, 1.0],
                loads: Vec::new(),
                prescribed: vec![PrescribedDisplacement {
                    node: Some(block.node(8, 4)),
                    nodes: None,
                    set: None,
                    ux: None,
                    uy: Some(0.02),
                }],
                ..Default::default()
            },
        ],
        analysis: AnalysisSettings::default(),
        mesh: None,
        series: None,
        design: None,
    }
}

#[test]
fn the_lifted_end_opens_and_no_active_multiplier_is_tensile() {
    let model = common::model(&lifted_block(), "separation.toml");
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        // under self-weight alone every point is pressed and the contact carries the weight,
        // 20·0.5·1 = 10 kN/m
        let (_, first) = &c.steps[0];
        for p in &first.interface_points {
            assert_eq!(p.state, "active");
            assert!(p.lambda > 0.0, "{backend:?}: λ {} at node {}", p.lambda, p.slave_node);
        }
        let weight: f64 = first.interface_points.iter().map(|p| p.lambda).sum();
        assert!((weight - 10.0).abs() < 1e-9, "{backend:?}: contact force {weight}");
        let (record, last) = c.steps.last().unwrap();
        let released: Vec<_> = last.interface_points.iter().filter(|p| p.state == "released").collect();
        let active: Vec<_> = last.interface_points.iter().filter(|p| p.state == "active").collect();
        assert!(!released.is_empty(), "{backend:?}: the lifted end did not open");
        assert!(!active.is_empty(), "{backend:?}: the whole block lifted off");
        // the opened points are the ones under the lifted end, and they are open
        let left_most_released = released.iter().map(|p| p.x[0]).fold(f64::MAX, f64::min);
        assert!(active.iter().all(|p| p.x[0] < left_most_released), "{backend:?}: contact is not one connected zone");
        for p in &released {
            assert_eq!(p.lambda, 0.0);
            let node = model.mesh.node_index(p.slave_node).unwrap();
            assert!(
                last.displacement_vector[2 * node + 1] > 0.0,
                "{backend:?}: released node {} did not lift",
                p.slave_node
            );
        }
        for p in &active {
            assert!(p.lambda >= -1e-9, "{backend:?}: tensile λ {} at active node {}", p.lambda, p.slave_node);
        }
        // the block's weight (20·0.5·1 = 10 kN/m) is carried by the contact and the lifting force
        let contact: f64 = active.iter().map(|p| p.lambda).sum();
        let lift = last.reaction_vector[2 * model
            .mesh
            .node_index(
                geoslip::meshgen::Block::new(SolidKind::Quad4, (0.0, 0.0), (1.0, 0.5), (8, 4), "soil", 1, 1).node(8, 4),
            )
            .unwrap()
            + 1];
        assert!((contact + lift - 10.0).abs() < 1e-6, "{backend:?}: contact {contact} + lift {lift} ≠ weight 10");
        let _ = record;
    }
}
