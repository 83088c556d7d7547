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
