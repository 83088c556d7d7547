//! The force balance of a reinforcement pulled at a grip off its slave line.
//!
//! Reference: statics of the reinforcement as a free body: the forces applied to its nodes (the
//! reactions of the held grip and the loads) equal the forces its interface carries, at every step;
//! once every point slides on a Coulomb face with c = 0, the pull is tan φ times the normal force
//! (docs/verification.md §4, the Coulomb block on a rigid base).
//!
//! ```text
//!          ↓ 1 kN/m on each of the 11 grid nodes
//!   grip o----o====o====o==   …   ==o      grid: bars on a rigid base, slave line o=o
//!       ←    ▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲      base: fixed master nodes at the grid's positions
//!   pulled 20 mm; the grip 0.15 m in front of the first slave node, held vertically
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;
use std::collections::BTreeMap;

fn gripped_strip() -> ModelFile {
    let grid: Vec<u64> = (1..=11).collect();
    let base: Vec<u64> = (1001..=1011).collect();
    let mut nodes: Vec<NodeRow> = Vec::new();
    for i in 0..11 {
        nodes.push(NodeRow(grid[i], 0.1 * i as f64, 0.0));
        nodes.push(NodeRow(base[i], 0.1 * i as f64, 0.0));
    }
    nodes.push(NodeRow(100, -0.15, 0.0));
    let mut bars = vec![BarRow { id: 1, nodes: [100, 1], material: "grid".into() }];
    for i in 0..10 {
        bars.push(BarRow { id: 2 + i as u64, nodes: [grid[i], grid[i + 1]], material: "grid".into() });
    }
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), base.clone());
    node_sets.insert("grid".into(), grid.clone());
    node_sets.insert("grip".into(), vec![100]);
    let mut reinforcement = BTreeMap::new();
    reinforcement.insert(
        "grid".into(),
        ReinforcementMaterial { axial_stiffness: 1000.0, tension_only: false, rupture_strength: None, weight: None },
    );
    ModelFile {
        title: "gripped strip".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil: BTreeMap::new(), reinforcement },
        nodes,
        elements: Vec::new(),
        bars,
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![
            geoslip::meshgen::support("base", &[Direction::X, Direction::Y]),
            geoslip::meshgen::support("grip", &[Direction::Y]),
        ],
        interfaces: vec![InterfaceSpec {
            name: "strip".into(),
            slave: Some(grid),
            master: Some(base),
            master_normal: Some([0.0, -1.0]),
            law: ShearLawSpec::Coulomb { shear_stiffness: 1000.0, cohesion: 0.0, friction_angle: 30.0 },
            ..Default::default()
        }],
        stages: vec![
            Stage {
                name: "load".into(),
                loads: vec![LoadSpec::Point { node: None, nodes: None, set: Some("grid".into()), fx: 0.0, fy: -1.0 }],
                ..Default::default()
            },
            Stage {
                name: "pull".into(),
                load_factors: (1..=10).map(|k| k as f64 / 10.0).collect(),
                prescribed: vec![common::prescribed("grip", Some(-0.02), None)],
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
fn the_pull_at_the_grip_balances_the_interface() {
    let model = common::model(&gripped_strip(), "gripped-strip.toml");
    let c = common::run(&model, Backend::available()[0]);
    for (record, _) in &c.steps {
        let [b] = record.balance.as_slice() else { panic!("step {}: balances {:?}", record.step, record.balance) };
        assert!(b.mismatch < 1e-9, "step {}: {b:?}", record.step);
    }
    let (record, _) = c.steps.last().unwrap();
    let b = &record.balance[0];
    let pull = 11.0 * 30f64.to_radians().tan();
    assert!(common::relative_error(-b.applied[0], pull) < 1e-8, "pull {:?} against 11·tan φ = {pull}", b.applied);
}
