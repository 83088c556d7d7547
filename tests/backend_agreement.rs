//! Every backend gives the reference backend's answers on every model.
//!
//! Reference: the dense Gauss elimination with complete pivoting (Golub & Van Loan, Matrix
//! Computations, §3.4.2), an independent solution path from faer's sparse LU. Goal: on every file
//! in examples/ and on the generated pull-out boxes of every element type, displacements,
//! multipliers, reactions and bar forces agree to 1e-10 relative (displacements to the largest
//! displacement, forces to the largest force of the step).

mod common;

use geoslip::analysis::Collect;
use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::SolidKind;
use geoslip::model::Model;
use std::path::Path;

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0f64, |m, x| m.max(x.abs()))
}

fn assert_agree(name: &str, reference: &Collect, other: &Collect, backend: Backend) {
    assert_eq!(reference.steps.len(), other.steps.len());
    for ((rec, a), (_, b)) in reference.steps.iter().zip(&other.steps) {
        let what = format!("{name}, stage \"{}\" step {}, {backend:?}", rec.stage, rec.step);
        // Forces share one scale (reactions, multipliers and bar forces are all force per width),
        // so that a quantity that is zero up to round-off is compared with the forces around it.
        let force_scale = max_abs(
            a.reaction_vector
                .iter()
                .copied()
                .chain(a.interface_points.iter().map(|p| p.lambda))
                .chain(a.bar_forces.iter().map(|b| b.axial_force)),
        )
        .max(f64::MIN_POSITIVE);
        let compare = |label: &str, x: Vec<f64>, y: Vec<f64>, scale: f64| {
            let diff = max_abs(x.iter().zip(&y).map(|(p, q)| p - q));
            assert!(diff <= 1e-10 * scale, "{what}: {label} differ by {diff:e} (scale {scale:e})");
        };
        let u_scale = max_abs(a.displacement_vector.iter().copied()).max(f64::MIN_POSITIVE);
        compare("displacements", a.displacement_vector.clone(), b.displacement_vector.clone(), u_scale);
        compare("reactions", a.reaction_vector.clone(), b.reaction_vector.clone(), force_scale);
        compare(
            "multipliers",
            a.interface_points.iter().map(|p| p.lambda).collect(),
            b.interface_points.iter().map(|p| p.lambda).collect(),
            force_scale,
        );
        compare(
            "bar forces",
            a.bar_forces.iter().map(|p| p.axial_force).collect(),
            b.bar_forces.iter().map(|p| p.axial_force).collect(),
            force_scale,
        );
    }
}

fn every_backend_agrees(name: &str, model: &Model) {
    let reference = common::run(model, Backend::Dense);
    for backend in Backend::available().into_iter().filter(|b| *b != Backend::Dense) {
        let other = common::run(model, backend);
        assert_agree(name, &reference, &other, backend);
    }
}

#[test]
fn every_example_runs_and_every_backend_agrees() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    // the model files in examples/ and in its folders (a Gmsh example keeps its .geo beside it)
    let mut paths: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    for sub in paths.clone().iter().filter(|p| p.is_dir()) {
        paths.extend(std::fs::read_dir(sub).unwrap().map(|e| e.unwrap().path()));
    }
    let mut files: Vec<_> =
        paths.into_iter().filter(|p| p.extension().is_some_and(|e| e == "toml" || e == "json")).collect();
    files.sort();
    assert!(files.iter().any(|p| p.ends_with("lab-pullout/lab-pullout.toml")), "the Gmsh example is included");
    for path in files {
        let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
        every_backend_agrees(&path.display().to_string(), &model);
    }
}

#[test]
fn generated_pullout_boxes_agree_on_every_backend() {
    for kind in [SolidKind::Tri3, SolidKind::Quad4] {
        let file = PullOutBox { kind, nx: 10, ny_half: 2, steps: 2, ..PullOutBox::default() }.model();
        let model = common::model(&file, "pullout-box.toml");
        every_backend_agrees(&format!("pull-out box ({kind:?})"), &model);
    }
}

/// shared/DESIGN.md §2: with Kc of full row rank, K positive definite on its null space and the
/// supports eliminated, the symmetric indefinite factorisation has exactly as many negative pivots as
/// active multipliers (Sylvester's law of inertia for the saddle-point matrix). geoslip warns when
/// MUMPS's INFOG(12) differs; on the examples it must not.
#[test]
fn mumps_inertia_equals_the_active_multipliers_on_every_example() {
    if !Backend::available().contains(&Backend::Mumps) {
        return; // this build has no MUMPS: nothing reports an inertia
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for name in ["pullout-box.toml", "annotated-pullout.toml"] {
        let model = Model::load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
        let options = geoslip::analysis::RunOptions { backend: Backend::Mumps, ..Default::default() };
        let stats = geoslip::analysis::run(&model, &options, &mut Collect::default()).unwrap();
        assert!(stats.factorizations > 0);
        assert!(stats.warnings.is_empty(), "{name}: {:?}", stats.warnings);
    }
}
