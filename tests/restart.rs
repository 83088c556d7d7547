//! Runs that continue from a saved step.
//!
//! Reference: the run itself, uninterrupted. A run continued from the saved state of step k
//! (written to its file and read back) must make every later step as the straight run made it,
//! to 1e-12 of each field's scale, on every backend; a model with a stage added after the saved
//! step must give that stage as the longer model run from the start; a changed mesh, material,
//! interface, support or earlier stage is refused with the reason.
//!
//! The model: the pull-out box of `geoslip::meshgen::PullOutBox` (surcharge, then the grid pulled
//! 12 mm in 8 steps) with a Coulomb interface, so that the continued steps carry slip, plastic slip
//! and sliding points across the restart, and the large-slip re-association.

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::*;

use common::restart::{assert_same_steps, resume, run_saving, through_file};

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
fn a_changed_mesh_material_interface_support_or_earlier_stage_is_refused_with_the_reason() {
    let model = common::model(&pullout(0.012, 8), "restart.toml");
    let saved = run_saving(&model, Backend::Faer);

    let mut moved = pullout(0.012, 8);
    moved.nodes[0].1 -= 0.01;
    let moved = common::model(&moved, "moved.toml");
    let e = through_file(&saved, "pull-out", 3, &moved).unwrap_err().to_string();
    assert!(e.contains("cannot continue from it") && e.contains("the mesh"), "{e}");

    let mut softer = pullout(0.012, 8);
    softer.materials.soil.values_mut().for_each(|m| m.youngs_modulus = m.youngs_modulus.map(|e| e * 0.5));
    let e = through_file(&saved, "pull-out", 3, &common::model(&softer, "softer.toml")).unwrap_err().to_string();
    assert!(e.contains("the materials changed"), "{e}");

    let mut rougher = pullout(0.012, 8);
    rougher.interfaces[0].law =
        ShearLawSpec::Coulomb { shear_stiffness: 20_000.0, cohesion: 2.0, friction_angle: 30.0 };
    let e = through_file(&saved, "pull-out", 3, &common::model(&rougher, "rougher.toml")).unwrap_err().to_string();
    assert!(e.contains("the interfaces changed"), "{e}");

    let mut held = pullout(0.012, 8);
    held.supports.pop();
    let e = through_file(&saved, "pull-out", 3, &common::model(&held, "held.toml")).unwrap_err().to_string();
    assert!(e.contains("the supports changed"), "{e}");

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
