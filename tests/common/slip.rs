//! A reinforcement in a rigid, fixed soil block: the setting of the 1-D closed forms
//! (docs/verification.md, Conventions: "assume a rigid surrounding medium").
#![allow(dead_code)]

use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

/// Bar of length `length` through a fixed soil block from x = 0 (head, front face) to x = length,
/// `elements` bars, pulled at the head by `pull` (towards −x) in `steps` equal increments.
pub fn bar_in_rigid_soil(
    length: f64,
    elements: usize,
    axial_stiffness: f64,
    law: ShearLawSpec,
    pull: f64,
    steps: usize,
    reassociation: ReassociationRule,
) -> ModelFile {
    let block = Block::new(SolidKind::Quad4, (0.0, -0.1), (length, 0.2), (elements, 2), "bed", 1, 1);
    let path: Vec<u64> = (0..=elements).map(|i| block.node(i, 1)).collect();
    let mut node_sets = BTreeMap::new();
    node_sets.insert("soil".into(), block.nodes.iter().map(|n| n.0).collect());
    let mut soil = BTreeMap::new();
    soil.insert("bed".into(), SoilMaterial::linear_elastic(1.0e5, 0.3, 0.0));
    let mut reinforcement = BTreeMap::new();
    reinforcement.insert(
        "grid".into(),
        ReinforcementMaterial { axial_stiffness, tension_only: false, rupture_strength: None, weight: None },
    );
    ModelFile {
        title: "reinforcement in rigid soil".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement },
        nodes: block.nodes,
        elements: block.elements,
        bars: Vec::new(),
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![support("soil", &[Direction::X, Direction::Y])],
        interfaces: vec![InterfaceSpec {
            name: "grid".into(),
            reinforcement: Some(ReinforcementPath {
                path,
                line: None,
                head: None,
                material: "grid".into(),
                stack: Vec::new(),
                free_length: None,
                mode: Default::default(),
            }),
            law,
            ..Default::default()
        }],
        stages: vec![Stage {
            name: "pull".into(),
            load_factors: (1..=steps).map(|k| k as f64 / steps as f64).collect(),
            loads: Vec::new(),
            prescribed: vec![PrescribedDisplacement {
                node: None,
                nodes: None,
                set: Some("grid.head".into()),
                ux: Some(-pull),
                uy: None,
            }],
            ..Default::default()
        }],
        analysis: AnalysisSettings { reassociation, ..AnalysisSettings::default() },
        mesh: None,
        series: None,
        design: None,
    }
}

/// (head displacement, pull-out force) of every step: the force is minus the head's x reaction.
pub fn pullout_curve(model: &geoslip::model::Model, c: &geoslip::analysis::Collect) -> Vec<(f64, f64)> {
    let head = model.node_sets["grid.head"][0];
    c.steps.iter().map(|(_, r)| (-r.displacement_vector[2 * head], -r.reaction_vector[2 * head])).collect()
}

/// The progressive-slip closed form (docs/verification.md §2) of the reference parameters used by the
/// tests: EA = 1000 kN/m, Ks = 2000 kN/m³, τmax = 5 kPa (cohesion), α = √(n_f·Ks/EA) = 2, n_f = 2,
/// L = 1 m.
pub mod progressive {
    pub const EA: f64 = 1000.0;
    pub const KS: f64 = 2000.0;
    pub const TAU: f64 = 5.0;
    pub const ALPHA: f64 = 2.0;
    pub const NF: f64 = 2.0;
    pub const L: f64 = 1.0;

    /// (u_head, P) with the slip front at `sf` from the head:
    /// P = n_f·τmax·[s_f + tanh(α(L−s_f))/α], u_head = u_y + T_e·s_f/EA + n_f·τmax·s_f²/(2·EA),
    /// T_e = (n_f·τmax/α)·tanh(α(L−s_f)).
    pub fn at_slip_front(sf: f64) -> (f64, f64) {
        let p = NF * TAU * (sf + (ALPHA * (L - sf)).tanh() / ALPHA);
        let te = NF * TAU / ALPHA * (ALPHA * (L - sf)).tanh();
        let u = TAU / KS + te * sf / EA + NF * TAU * sf * sf / (2.0 * EA);
        (u, p)
    }
}
