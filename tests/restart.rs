//! Runs that continue from a saved step.
//!
//! Reference: the run itself, uninterrupted. A run continued from the saved state of step k
//! (written to its file and read back) must make every later step as the straight run made it,
//! to 1e-12 of each field's scale, on every backend; a model with a stage added after the saved
//! step must give that stage as the longer model run from the start; a changed mesh, material or
//! earlier stage is refused with the reason.
//!
//! The model: the pull-out box of `geoslip::meshgen::PullOutBox` (surcharge, then the grid pulled
//! 12 mm in 8 steps) with a Coulomb interface, so that the continued steps carry slip, plastic slip
//! and sliding points across the restart, and the large-slip re-association.

mod common;

use geoslip::analysis::{self, Checkpoint, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::*;
use geoslip::model::Model;
use geoslip::output::checkpoints::{self, From};

use common::Saved;

fn pullout(pull: f64, steps: usize) -> ModelFile {
    PullOutBox {
        nx: 10,
        ny_half: 2,
        law: ShearLawSpec::Coulomb { shear_stiffness: 20_000.0, cohesion: 2.0, friction_angle: 25.0 },
        pull,
        steps,
        ..PullOutBox::default()
    }
    .model()
}

fn run_saving(model: &Model, backend: Backend) -> Saved {
    let mut saved = Saved::default();
    analysis::run(model, &RunOptions::for_model(model, backend), &mut saved).unwrap_or_else(|e| panic!("{e}"));
    saved
}

/// The saved state of `stage:step`, through its file: written by the output module, read back and
/// checked against `model`.
fn through_file(saved: &Saved, stage: &str, step: usize, model: &Model) -> Result<Checkpoint, geoslip::Error> {
    let dir = tempfile::tempdir().unwrap();
    common::write_saved_steps(dir.path(), &saved.checkpoints);
    checkpoints::read(dir.path(), &From { stage: stage.into(), step }, model, None)
}

fn resume(model: &Model, backend: Backend, checkpoint: Checkpoint) -> Collect {
    let mut c = Collect::default();
    analysis::resume(model, &RunOptions::for_model(model, backend), checkpoint, &mut c)
        .unwrap_or_else(|e| panic!("{e}"));
    c
}

fn largest(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300)
}

/// Every field of `continued` against the same steps of `straight` (from its step `first` on), to
/// 1e-12 of each field's largest value.
fn assert_same_steps(straight: &Collect, first: usize, continued: &Collect, what: &str) {
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
            assert!(
                diff <= 1e-12 * scale || diff < 1e-250,
                "{what}: {name} at stage {} step {} differs by {diff:.2e} of {scale:.2e}",
                ra.stage,
                ra.step
            );
        }
        assert_eq!(ra.iterations, rb.iterations, "{what}: iterations at {} step {}", ra.stage, ra.step);
    }
}

#[test]
fn a_run_continued_from_a_saved_step_makes_the_same_later_steps_on_every_backend() {
    let model = common::model(&pullout(0.012, 8), "restart.toml");
    for backend in Backend::available() {
        let straight = run_saving(&model, backend);
        assert_eq!(straight.checkpoints.len(), straight.steps.steps.len(), "{backend:?}: a saved state per step");
        // the front of the grid slides by the third pull step, and all of it before the end
        let sliding: Vec<usize> = straight.steps.steps.iter().map(|(r, _)| r.sliding_points).collect();
        assert!(sliding[3] > 0 && sliding[3] < sliding[8], "{backend:?}: sliding points {sliding:?}");
        // from within the pull-out (steps 1..=3 done), and from the end of the surcharge stage
        for (stage, step, done) in [("pull-out", 3, 4), ("surcharge", 1, 1), ("2", 7, 8)] {
            let checkpoint = through_file(&straight, stage, step, &model).unwrap_or_else(|e| panic!("{e}"));
            let continued = resume(&model, backend, checkpoint);
            assert_same_steps(&straight.steps, done, &continued, &format!("{backend:?} from {stage}:{step}"));
        }
    }
}

/// With `extrapolation = "linear"` the saved step carries the stage's last increment, so the
/// continued run starts its next increment from the same extrapolated iterate.
#[test]
fn a_run_with_extrapolated_iterates_continues_with_the_same_iterations() {
    let mut file = pullout(0.012, 8);
    file.analysis.extrapolation = Extrapolation::Linear;
    let model = common::model(&file, "restart-extrapolated.toml");
    let straight = run_saving(&model, Backend::Faer);
    let checkpoint = through_file(&straight, "pull-out", 3, &model).unwrap_or_else(|e| panic!("{e}"));
    assert!(checkpoint.progress.last.is_some(), "the saved step carries the last increment");
    let continued = resume(&model, Backend::Faer, checkpoint);
    assert_same_steps(&straight.steps, 4, &continued, "extrapolated, from pull-out:3");
}

#[test]
fn a_stage_added_after_the_saved_step_runs_as_in_the_longer_model() {
    let short = common::model(&pullout(0.012, 8), "restart-short.toml");
    let mut longer_file = pullout(0.012, 8);
    let mut more = longer_file.stages[1].clone();
    more.name = "pull-out further".into();
    more.load_factors = vec![0.25, 0.5, 0.75, 1.0];
    more.prescribed[0].ux = Some(-0.006);
    longer_file.stages.push(more);
    let longer = common::model(&longer_file, "restart-longer.toml");
    for backend in Backend::available() {
        let saved = run_saving(&short, backend);
        let from_scratch = run_saving(&longer, backend);
        let checkpoint = through_file(&saved, "pull-out", 8, &longer).unwrap_or_else(|e| panic!("{e}"));
        let continued = resume(&longer, backend, checkpoint);
        assert_eq!(continued.steps.len(), 4, "{backend:?}: the added stage's steps");
        assert_same_steps(&from_scratch.steps, 1 + 8, &continued, &format!("{backend:?}, stage added"));
    }
}

#[test]
fn a_changed_mesh_material_or_earlier_stage_is_refused_with_the_reason() {
    let model = common::model(&pullout(0.012, 8), "restart.toml");
    let saved = run_saving(&model, Backend::Faer);

    let mut moved = pullout(0.012, 8);
    moved.nodes[0].1 -= 0.01;
    let moved = common::model(&moved, "moved.toml");
    let e = through_file(&saved, "pull-out", 3, &moved).unwrap_err().to_string();
    assert!(e.contains("cannot continue from it") && e.contains("the mesh"), "{e}");

    let mut softer = pullout(0.012, 8);
    softer.materials.soil.values_mut().for_each(|m| m.youngs_modulus *= 0.5);
    let e = through_file(&saved, "pull-out", 3, &common::model(&softer, "softer.toml")).unwrap_err().to_string();
    assert!(e.contains("the materials changed"), "{e}");

    let mut faster = pullout(0.012, 8);
    faster.stages[1].load_factors = vec![0.5, 1.0];
    let e = through_file(&saved, "pull-out", 1, &common::model(&faster, "faster.toml")).unwrap_err().to_string();
    assert!(e.contains("stage 2 (\"pull-out\") changed"), "{e}");
    // but the stage after the saved one may change: from the end of the surcharge stage it is fine
    assert!(through_file(&saved, "surcharge", 1, &common::model(&faster, "faster.toml")).is_ok());

    let e = through_file(&saved, "pull-out", 9, &model).unwrap_err().to_string();
    assert!(e.contains("no saved step pull-out:9") && e.contains("stage-2-step-00008"), "{e}");
    let e = through_file(&saved, "pulled", 1, &model).unwrap_err().to_string();
    assert!(e.contains("no stage \"pulled\""), "{e}");
}
