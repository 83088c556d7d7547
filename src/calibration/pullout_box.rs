//! A pull-out curve from the finite-element model of the test: the box built from the test's
//! geometry (`meshgen::PullOutBox`: soil split along a reinforcement at mid-height, base fixed,
//! front and back walls rigid in x, the surcharge on top), run by geoslip with the trial law, the
//! head force read at each pull step and interpolated at the measured displacements.

use super::error::CalibrationError;
use super::spec::{PullOutBoxSpec, PullOutSpec};
use crate::analysis::{self, Collect, RunOptions};
use crate::linsol::Backend;
use crate::meshgen::PullOutBox;
use crate::model::file::ShearLawSpec;
use crate::model::Model;
use std::path::Path;

const DEFAULT_ELEMENTS: usize = 40;
const DEFAULT_STEPS: usize = 40;

/// The box of a test, ready to take a law and a surcharge.
#[derive(Debug, Clone)]
pub struct TestBox {
    template: PullOutBox,
    /// The reinforcement's length in the mesh (the embedded length on the box's element columns).
    pub embedded_length: f64,
}

impl TestBox {
    pub fn new(pull_out: &PullOutSpec, b: &PullOutBoxSpec, largest_displacement: f64) -> TestBox {
        let nx = b.elements.unwrap_or(DEFAULT_ELEMENTS);
        let h = b.length / nx as f64;
        let ny_half = ((0.5 * b.height / h).round() as usize).clamp(1, nx);
        let template = PullOutBox {
            length: b.length,
            height: b.height,
            embedded: pull_out.embedded_length,
            nx,
            ny_half,
            youngs_modulus: b.youngs_modulus,
            poissons_ratio: b.poissons_ratio,
            unit_weight: b.unit_weight,
            axial_stiffness: pull_out.axial_stiffness,
            pull: largest_displacement,
            steps: b.steps.unwrap_or(DEFAULT_STEPS),
            ..PullOutBox::default()
        };
        let cells = ((pull_out.embedded_length / h).round()).clamp(1.0, nx as f64);
        TestBox { template, embedded_length: cells * h }
    }

    /// The pull-out force at each of `displacements` with `law` under `surcharge`.
    ///
    /// # Errors
    /// [`CalibrationError::Model`] when the run fails (no equilibrium, a singular system).
    pub fn curve(
        &self,
        law: ShearLawSpec,
        surcharge: f64,
        displacements: &[f64],
    ) -> Result<Vec<f64>, CalibrationError> {
        let condition = format!("a surcharge of {surcharge} kPa");
        let fail = |e: crate::Error| CalibrationError::Model { condition: condition.clone(), source: Box::new(e) };
        let file = PullOutBox { law, surcharge, ..self.template.clone() }.model();
        let model = Model::from_file(Path::new("pull-out box"), &file).map_err(|e| fail(e.into()))?;
        let mut sink = Collect::default();
        analysis::run(&model, &RunOptions::for_model(&model, Backend::Auto), &mut sink).map_err(fail)?;
        let head: Vec<u64> = model.node_sets["grid.head"].iter().map(|&n| model.mesh.node_id(n)).collect();
        // (displacement, force) at the confinement's end and after each pull step
        let points: Vec<(f64, f64)> = std::iter::once((0.0, 0.0))
            .chain(sink.steps.iter().filter(|(r, _)| r.stage_index == 1).map(|(r, s)| {
                let force = s.reactions.iter().filter(|r| head.contains(&r.node)).filter_map(|r| r.rx).sum::<f64>();
                (self.template.pull * r.load_factor, force.abs())
            }))
            .collect();
        Ok(displacements.iter().map(|&u| interpolate(&points, u.abs())).collect())
    }
}

/// Linear interpolation in a table sorted by x (held at its ends).
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    match points.iter().position(|&(px, _)| px >= x) {
        None => points.last().map_or(0.0, |p| p.1),
        Some(0) => points[0].1,
        Some(i) => {
            let ((x0, y0), (x1, y1)) = (points[i - 1], points[i]);
            if x1 == x0 {
                y1
            } else {
                y0 + (y1 - y0) * (x - x0) / (x1 - x0)
            }
        }
    }
}
