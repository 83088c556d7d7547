//! A pull-out curve from the finite-element model of the test: the box built from the test's
//! geometry (`meshgen::PullOutBox`: soil split along a reinforcement at mid-height, base fixed,
//! front and back walls rigid in x, the surcharge on top), run by geoslip with the trial law, the
//! head force read at each pull step and interpolated at the measured displacements.
//!
//! A run keeps only that: the head force after each step ([`HeadForces`]), not the steps' full
//! results, so that a fit's memory is that of one run of the box, whatever its steps.

use super::error::CalibrationError;
use super::spec::{PullOutBoxSpec, PullOutSpec};
use crate::analysis::results::StepResults;
use crate::analysis::RunStats;
use crate::analysis::{self, RunOptions, StepRecord, StepSink};
use crate::linsol::Backend;
use crate::meshgen::PullOutBox;
use crate::model::file::ShearLawSpec;
use crate::model::Model;
use std::collections::HashSet;
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
        let model = Model::from_file(Path::new("pull-out box"), &file).map_err(|e| fail(refused(&e)))?;
        let Some(head) = model.node_sets.get("grid.head") else {
            return Err(fail(refused(&crate::ModelError { file: "pull-out box".into(), problems: Vec::new() })));
        };
        let mut sink = HeadForces {
            head: head.iter().map(|&n| model.mesh.node_id(n)).collect(),
            pull: self.template.pull,
            // (displacement, force) at the confinement's end, then after each pull step
            points: vec![(0.0, 0.0)],
        };
        analysis::run(&model, &RunOptions::for_model(&model, Backend::Auto), &mut sink)
            .map_err(|e| fail(run_failed(e, self.template.steps)))?;
        Ok(displacements.iter().map(|&u| interpolate(&sink.points, u.abs())).collect())
    }
}

/// What a fit needs of a run of the box: the head's (displacement, force) after each pull step.
struct HeadForces {
    /// The head's node ids.
    head: HashSet<u64>,
    /// The head displacement at a load factor of 1.
    pull: f64,
    points: Vec<(f64, f64)>,
}

impl StepSink for HeadForces {
    fn step_done(
        &mut self,
        _: &crate::model::Model,
        step: &StepResults,
        record: &StepRecord,
        _: &RunStats,
    ) -> Result<(), crate::Error> {
        // stage 0 is the surcharge, stage 1 the pull
        if record.stage_index == 1 {
            let force: f64 = step.reactions.iter().filter(|r| self.head.contains(&r.node)).filter_map(|r| r.rx).sum();
            self.points.push((self.pull * record.load_factor, force.abs()));
        }
        Ok(())
    }
}

/// A run's failure in the calibration file's terms: the pull step of `[pull_out.box]`'s `steps`,
/// not the built model's stages and settings (a solver's own failure is passed on as it is).
fn run_failed(e: crate::Error, steps: usize) -> crate::Error {
    let at = |stage: &str, step: usize| {
        if stage == "surcharge" {
            "under the surcharge".to_string()
        } else {
            format!("at pull step {step} of {steps}")
        }
    };
    let message = match &e {
        crate::Error::NotConverged { stage, step, iterations, .. } => Some(format!(
            "no equilibrium {} after {iterations} iterations with the trial law: more pull steps (steps under \
             [pull_out.box]) may help",
            at(stage, *step)
        )),
        crate::Error::NonFinite { stage, step, .. } => {
            Some(format!("a number that is not finite appeared {} with the trial law", at(stage, *step)))
        }
        _ => None,
    };
    match message {
        Some(message) => crate::Error::Parse { path: "pull-out box".into(), message },
        None => e,
    }
}

/// The box refused as the calibration file's terms say it, never by the fields of the model the
/// calibration builds (which the user never wrote): the trial law's parameter by its name, or the
/// box of `[pull_out]` and `[pull_out.box]`.
fn refused(e: &crate::ModelError) -> crate::Error {
    let law: Vec<String> = e
        .problems
        .iter()
        .filter(|p| p.field.contains(".law"))
        .map(|p| match p.field.rsplit_once(".law.") {
            Some((_, name)) => format!("{name} {}", p.message),
            None => p.message.clone(),
        })
        .collect();
    let message = if !law.is_empty() {
        format!("the trial law is refused: {}", law.join("; "))
    } else {
        let each: Vec<&str> = e.problems.iter().map(|p| p.message.as_str()).collect();
        format!(
            "the box that [pull_out] and [pull_out.box] describe cannot be built{}{}",
            if each.is_empty() { "" } else { ": " },
            each.join("; ")
        )
    };
    crate::Error::Parse { path: "pull-out box".into(), message }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Collect;
    use crate::calibration::spec::PullOutModel;

    fn test_box(steps: usize) -> TestBox {
        let pull_out = PullOutSpec {
            embedded_length: 0.4,
            axial_stiffness: 2000.0,
            faces: 2,
            model: PullOutModel::FiniteElement,
            box_: None,
        };
        let b = PullOutBoxSpec {
            length: 0.5,
            height: 0.2,
            youngs_modulus: 20_000.0,
            poissons_ratio: 0.3,
            unit_weight: 0.0,
            elements: Some(10),
            steps: Some(steps),
        };
        TestBox::new(&pull_out, &b, 0.004)
    }

    #[test]
    fn a_refused_trial_law_is_named_by_its_parameter_not_by_the_built_model_s_fields() {
        let law = ShearLawSpec::Coulomb { shear_stiffness: 2e4, cohesion: -1e-4, friction_angle: 30.0 };
        let e = test_box(2).curve(law, 20.0, &[0.001]).unwrap_err().to_string();
        assert!(e.contains("cohesion must be zero or positive, found -0.0001"), "{e}");
        for internal in ["interfaces[", "stages[", "grid.head", ".law", "node set"] {
            assert!(!e.contains(internal), "{internal} in: {e}");
        }
    }

    /// The head forces kept step by step are those of the run's full results (`Collect`, which
    /// keeps every step's every node and Gauss point).
    #[test]
    fn the_head_forces_kept_are_those_of_the_full_results() {
        let b = test_box(4);
        let law = ShearLawSpec::Coulomb { shear_stiffness: 2e4, cohesion: 0.0, friction_angle: 30.0 };
        let steps: Vec<f64> = (1..=4).map(|k| 0.004 * k as f64 / 4.0).collect();
        let kept = b.curve(law.clone(), 20.0, &steps).unwrap_or_else(|e| panic!("{e}"));
        let file = PullOutBox { law, surcharge: 20.0, ..b.template.clone() }.model();
        let model = Model::from_file(Path::new("pull-out box"), &file).unwrap();
        let mut all = Collect::default();
        analysis::run(&model, &RunOptions::for_model(&model, Backend::Auto), &mut all).unwrap();
        let head: Vec<u64> = model.node_sets["grid.head"].iter().map(|&n| model.mesh.node_id(n)).collect();
        let full: Vec<f64> = all
            .steps
            .iter()
            .filter(|(r, _)| r.stage_index == 1)
            .map(|(_, s)| s.reactions.iter().filter(|r| head.contains(&r.node)).filter_map(|r| r.rx).sum::<f64>().abs())
            .collect();
        assert_eq!(full.len(), 4);
        assert!(full.iter().all(|&p| p > 0.0), "{full:?}");
        for (k, (a, b)) in kept.iter().zip(&full).enumerate() {
            assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "step {}: {a} against {b}", k + 1);
        }
    }
}
