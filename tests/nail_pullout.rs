//! A nail pulled out of rigid ground, axisymmetric: the shear-lag closed form with the shaft's
//! circumference as the perimeter, and the fully sliding ultimate.
//!
//! Reference: docs/verification.md §1 (the shear-lag solution of a bar on elastic
//! springs; a nail or anchor shaft is the same with the perimeter 2πr in place of n_f per metre
//! width, e.g. Randolph & Wroth 1978 for piles): with λ = √(2πr·Ks/EA), the head stiffness is
//! K = EA·λ·tanh(λL) and the tail moves P/(EA·λ·sinh λL); a shaft sliding over its whole length at
//! the strength τ carries 2πr·τ·L.
//!
//! Parameters: r = 0.05 m, EA = 50 000 kN (the member's), Ks = 20 000 kPa/m, L = 4 m → λ = 0.3545/m,
//! λL = 1.418; 40 bars (discretisation error of lumped springs ≈ (λh)²/12 ≈ 1e-4); tolerance 0.5 %.
//! Small slip (`reassociation = "none"`), as the closed form keeps the bonded length fixed.
//!
//! ```text
//!        P ↑
//!   axis  o   nail (bars, EA) at r = 0.05, its own nodes
//!   ¦     |‖  rigid ground (every node fixed) from r = 0.05; the nail's nodes
//!   ¦     |‖  are the slave line of a pair whose master is the ground's face
//!   ¦     o‖
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;
use std::f64::consts::PI;

const RADIUS: f64 = 0.05;
const EA: f64 = 50_000.0;
const KS: f64 = 20_000.0;
const L: f64 = 4.0;
const BARS: usize = 40;

fn lambda() -> f64 {
    (2.0 * PI * RADIUS * KS / EA).sqrt()
}

fn nail_in_rigid_ground(law: ShearLawSpec, stage: Stage) -> ModelFile {
    let block = Block::new(SolidKind::Quad4, (RADIUS, 0.0), (0.05, L), (1, BARS), "ground", 1, 1);
    let first = block.nodes.iter().map(|n| n.0).max().unwrap() + 1;
    // the nail's nodes from the head (top) down, beside the ground's face nodes
    let face = block.column_nodes(0);
    let mut nodes = block.nodes.clone();
    let nail: Vec<u64> = (0..=BARS).map(|k| first + k as u64).collect();
    for (k, &id) in nail.iter().enumerate() {
        nodes.push(NodeRow(id, RADIUS, L * (BARS - k) as f64 / BARS as f64));
    }
    let bars = (0..BARS)
        .map(|k| BarRow { id: 1000 + k as u64, nodes: [nail[k], nail[k + 1]], material: "nail".into() })
        .collect();
    let mut node_sets = BTreeMap::new();
    node_sets.insert("ground".into(), block.nodes.iter().map(|n| n.0).collect());
    node_sets.insert("nail.head".into(), vec![nail[0]]);
    let mut soil = BTreeMap::new();
    soil.insert("ground".into(), SoilMaterial::linear_elastic(1.0e5, 0.3, 0.0));
    let mut reinforcement = BTreeMap::new();
    reinforcement.insert(
        "nail".into(),
        ReinforcementMaterial { axial_stiffness: EA, tension_only: false, rupture_strength: None, weight: None },
    );
    ModelFile {
        title: "nail in rigid ground".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement },
        nodes,
        elements: block.elements,
        bars,
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![support("ground", &[Direction::X, Direction::Y])],
        interfaces: vec![InterfaceSpec {
            name: "shaft".into(),
            slave: Some(nail),
            master: Some(face.into_iter().rev().collect()),
            law,
            ..Default::default()
        }],
        stages: vec![stage],
        analysis: AnalysisSettings {
            geometry: Geometry::Axisymmetric,
            reassociation: ReassociationRule::None,
            ..AnalysisSettings::default()
        },
        mesh: None,
        series: None,
        design: None,
    }
}

fn head_and_tail(model: &geoslip::model::Model, c: &geoslip::analysis::Collect) -> ([f64; 2], [f64; 2]) {
    let head = model.node_sets["nail.head"][0];
    // the nail's tail: of the two nodes at (r, 0), the nail's has the larger id (the ground's is fixed)
    let tail = (0..model.mesh.nodes.len())
        .filter(|&n| model.mesh.position(n) == [RADIUS, 0.0])
        .max_by_key(|&n| model.mesh.node_id(n))
        .expect("the nail reaches z = 0");
    let r = c.last().unwrap();
    let at = |n: usize| [r.displacement_vector[2 * n], r.displacement_vector[2 * n + 1]];
    (at(head), at(tail))
}

#[test]
fn head_stiffness_follows_the_shear_lag_closed_form_with_the_circumference() {
    let p = 10.0;
    let stage = Stage {
        name: "pull".into(),
        load_factors: vec![1.0],
        loads: vec![LoadSpec::Point { node: None, nodes: None, set: Some("nail.head".into()), fx: 0.0, fy: p }],
        ..Default::default()
    };
    let model = common::model(
        &nail_in_rigid_ground(ShearLawSpec::Linear { shear_stiffness: KS }, stage),
        "nail-shear-lag.toml",
    );
    let l = lambda();
    let k_exact = EA * l * (l * L).tanh();
    let tail_exact = p / (EA * l * (l * L).sinh());
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let (head, tail) = head_and_tail(&model, &c);
        let k = p / head[1];
        let err = common::relative_error(k, k_exact);
        assert!(err < 0.005, "{backend:?}: head stiffness {k} kN/m against {k_exact} ({err:.2e})");
        assert!(common::relative_error(tail[1], tail_exact) < 0.005, "{backend:?}: tail {} vs {tail_exact}", tail[1]);
        // the nail stays on its shaft: no radial movement
        assert!(head[0].abs() < 1e-12 && tail[0].abs() < 1e-12);
        // the shaft's forces (totals over the circumference) balance the pull
        let r = c.last().unwrap();
        let shear: f64 = r.interface_points.iter().map(|q| q.tau * q.tributary).sum();
        assert!((shear - p).abs() < 1e-9 * p, "{backend:?}: Στ·A = {shear} kN against the pull {p} kN");
    }
}

#[test]
fn a_fully_sliding_shaft_carries_its_circumference_times_strength_times_length() {
    let tau = 50.0;
    let stage = Stage {
        name: "pull".into(),
        load_factors: (1..=10).map(|k| k as f64 / 10.0).collect(),
        prescribed: vec![PrescribedDisplacement {
            node: None,
            nodes: None,
            set: Some("nail.head".into()),
            ux: None,
            uy: Some(0.02),
        }],
        ..Default::default()
    };
    let law = ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: tau, friction_angle: 0.0 };
    let model = common::model(&nail_in_rigid_ground(law, stage), "nail-ultimate.toml");
    let head = model.node_sets["nail.head"][0];
    let ultimate = 2.0 * PI * RADIUS * tau * L;
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let r = c.last().unwrap();
        let force = r.reaction_vector[2 * head + 1];
        assert!(
            (force - ultimate).abs() < 1e-6 * ultimate,
            "{backend:?}: pull-out force {force} kN against 2πr·τ·L = {ultimate} kN"
        );
        assert!(r.interface_points.iter().all(|q| (q.tau - tau).abs() < 1e-9 * tau), "{backend:?}: a point sticks");
    }
}
