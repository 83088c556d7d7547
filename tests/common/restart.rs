//! Runs continued from a saved step, against the same run uninterrupted (tests/restart.rs,
//! tests/restart_examples.rs).
#![allow(dead_code)]

use super::Saved;
use geoslip::analysis::{self, Checkpoint, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::model::Model;
use geoslip::output::checkpoints::{self, From};

pub fn run_saving(model: &Model, backend: Backend) -> Saved {
    let mut saved = Saved::default();
    analysis::run(model, &RunOptions::for_model(model, backend), &mut saved).unwrap_or_else(|e| panic!("{e}"));
    saved
}

/// The saved state of `stage:step`, through its file: written by the output module, read back and
/// checked against `model`.
pub fn through_file(saved: &Saved, stage: &str, step: usize, model: &Model) -> Result<Checkpoint, geoslip::Error> {
    let dir = tempfile::tempdir().unwrap();
    super::write_saved_steps(dir.path(), &saved.checkpoints);
    checkpoints::read(dir.path(), &From { stage: stage.into(), step }, model, None)
}

pub fn resume(model: &Model, backend: Backend, checkpoint: Checkpoint) -> Collect {
    let mut c = Collect::default();
    analysis::resume(model, &RunOptions::for_model(model, backend), checkpoint, &mut c)
        .unwrap_or_else(|e| panic!("{e}"));
    c
}

pub fn largest(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300)
}

/// Every field of `continued` against the same steps of `straight` (from its step `first` on), to
/// 1e-12 of each field's largest value, with the same iterations.
pub fn assert_same_steps(straight: &Collect, first: usize, continued: &Collect, what: &str) {
    assert_steps_within(straight, first, continued, what, 1e-12, true);
}

/// As [`assert_same_steps`], to `tolerance` of each field's largest value, the iterations compared
/// when `same_iterations`. Returns the largest relative difference found.
pub fn assert_steps_within(
    straight: &Collect,
    first: usize,
    continued: &Collect,
    what: &str,
    tolerance: f64,
    same_iterations: bool,
) -> f64 {
    let mut worst: f64 = 0.0;
    assert_eq!(continued.steps.len(), straight.steps.len() - first, "{what}: number of steps");
    for ((ra, a), (rb, b)) in straight.steps[first..].iter().zip(&continued.steps) {
        assert_eq!((ra.stage.as_str(), ra.step), (rb.stage.as_str(), rb.step), "{what}: step numbering");
        let fields: [(&str, Vec<f64>, Vec<f64>); 5] = [
            ("displacement", a.displacement_vector.clone(), b.displacement_vector.clone()),
            ("reaction", a.reaction_vector.clone(), b.reaction_vector.clone()),
            (
                "tau",
                a.interface_points.iter().map(|p| p.tau).collect(),
                b.interface_points.iter().map(|p| p.tau).collect(),
            ),
            (
                "sigma_n",
                a.interface_points.iter().map(|p| p.sigma_n).collect(),
                b.interface_points.iter().map(|p| p.sigma_n).collect(),
            ),
            (
                "bar force",
                a.bar_forces.iter().map(|f| f.axial_force).collect(),
                b.bar_forces.iter().map(|f| f.axial_force).collect(),
            ),
        ];
        for (name, x, y) in fields {
            assert_eq!(x.len(), y.len(), "{what}: {name} sizes at {} step {}", ra.stage, ra.step);
            let scale = largest(x.iter().copied());
            let diff = largest(x.iter().zip(&y).map(|(p, q)| p - q));
            if diff >= 1e-250 {
                worst = worst.max(diff / scale);
            }
            assert!(
                diff <= tolerance * scale || diff < 1e-250,
                "{what}: {name} at stage {} step {} differs by {diff:.2e} of {scale:.2e}",
                ra.stage,
                ra.step
            );
        }
        if same_iterations {
            assert_eq!(ra.iterations, rb.iterations, "{what}: iterations at {} step {}", ra.stage, ra.step);
        }
    }
    worst
}
