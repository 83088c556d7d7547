//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod slip;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::model::file::ModelFile;
use geoslip::model::Model;
use std::path::Path;

/// Check a model built in code; panics with the full problem list if it is rejected.
pub fn model(file: &ModelFile, name: &str) -> Model {
    Model::from_file(Path::new(name), file).unwrap_or_else(|e| panic!("{e}"))
}

/// Run a model on a backend and keep every step.
pub fn run(model: &Model, backend: Backend) -> Collect {
    let mut sink = Collect::default();
    analysis::run(model, &RunOptions::for_model(model, backend), &mut sink).unwrap_or_else(|e| panic!("{e}"));
    sink
}

/// Displacement of node `id` in the last step.
pub fn displacement(c: &Collect, id: u64) -> [f64; 2] {
    let r = c.last().expect("at least one step");
    r.displacements.iter().find(|(n, _, _)| *n == id).map(|(_, _, d)| *d).unwrap_or_else(|| panic!("no node {id}"))
}

pub fn relative_error(value: f64, exact: f64) -> f64 {
    ((value - exact) / exact).abs()
}

/// A soil-only model (no bars, no interfaces, no edge sets) in kN and m.
#[allow(clippy::too_many_arguments)]
pub fn soil_model(
    title: &str,
    nodes: Vec<geoslip::model::file::NodeRow>,
    elements: Vec<geoslip::model::file::SolidElementRow>,
    soil: std::collections::BTreeMap<String, geoslip::model::file::SoilMaterial>,
    node_sets: std::collections::BTreeMap<String, Vec<u64>>,
    supports: Vec<geoslip::model::file::Support>,
    stages: Vec<geoslip::model::file::Stage>,
    analysis: geoslip::model::file::AnalysisSettings,
) -> ModelFile {
    use geoslip::model::file::*;
    ModelFile {
        title: title.into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: Default::default() },
        nodes,
        elements,
        bars: Vec::new(),
        node_sets,
        edge_sets: Default::default(),
        element_sets: Default::default(),
        supports,
        interfaces: Vec::new(),
        stages,
        analysis,
        mesh: None,
        series: None,
    }
}

/// Two blocks stacked: `upper` sits on `lower`'s top row, whose nodes it takes over. Returns the
/// nodes, the elements, and the renaming of `upper`'s bottom-row nodes.
pub fn stack(
    lower: &geoslip::meshgen::Block,
    upper: &geoslip::meshgen::Block,
) -> (
    Vec<geoslip::model::file::NodeRow>,
    Vec<geoslip::model::file::SolidElementRow>,
    std::collections::BTreeMap<u64, u64>,
) {
    let rename: std::collections::BTreeMap<u64, u64> =
        upper.row_nodes(0).into_iter().zip(lower.row_nodes(lower.ny)).collect();
    let mut nodes = lower.nodes.clone();
    nodes.extend(upper.nodes.iter().filter(|n| !rename.contains_key(&n.0)).cloned());
    let mut elements = lower.elements.clone();
    for e in &upper.elements {
        let mut e = e.clone();
        e.nodes = e.nodes.iter().map(|n| *rename.get(n).unwrap_or(n)).collect();
        elements.push(e);
    }
    (nodes, elements, rename)
}

/// A prescribed displacement of a node set.
pub fn prescribed(set: &str, ux: Option<f64>, uy: Option<f64>) -> geoslip::model::file::PrescribedDisplacement {
    geoslip::model::file::PrescribedDisplacement { node: None, nodes: None, set: Some(set.into()), ux, uy }
}

/// Newton's method with the consistent tangent, to a relative tolerance on force and displacement.
pub fn newton(tolerance: f64) -> geoslip::model::file::AnalysisSettings {
    geoslip::model::file::AnalysisSettings {
        scheme: geoslip::model::file::Scheme::Newton,
        force_tolerance: tolerance,
        displacement_tolerance: tolerance,
        ..Default::default()
    }
}
