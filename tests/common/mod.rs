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
