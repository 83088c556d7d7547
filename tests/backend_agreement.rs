//! Every backend gives the reference backend's answers on every model.
//!
//! Reference: the dense Gauss elimination with complete pivoting (Golub & Van Loan, Matrix
//! Computations, §3.4.2), an independent solution path from faer's sparse LU. Goal: on every file
//! in examples/ (but the reinforced and the seismic wall, too large for the dense reference: see
//! tests/reinforced_wall_example.rs and tests/seismic_wall_example.rs; the embedded pull-out boxes, above 450 nodes, against faer's
//! LU instead, which the dense reference checks on every smaller model), on yielding Mohr–Coulomb soil, and on the generated pull-out
//! boxes of every element type, displacements,
//! multipliers, reactions and bar forces agree to 1e-10 relative (displacements to the largest
//! displacement, forces to the largest force of the step); from a dynamic stage's 100th step on, to
//! 1e-6 (`DYNAMIC_STEPS_AT_ROUND_OFF`).

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
    // past a dynamic stage's first steps (and in the stages after it)
    let mut shaken = false;
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
        shaken |= rec.time.is_some() && rec.step > DYNAMIC_STEPS_AT_ROUND_OFF;
        let tolerance = if shaken { 1e-6 } else { 1e-10 };
        let compare = |label: &str, x: Vec<f64>, y: Vec<f64>, scale: f64| {
            let diff = max_abs(x.iter().zip(&y).map(|(p, q)| p - q));
            assert!(diff <= tolerance * scale, "{what}: {label} differ by {diff:e} (scale {scale:e})");
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
    agree_with(name, model, Backend::Dense);
}

/// Every available backend but `reference` (and the dense one, unless it is the reference) against
/// `reference`'s answers.
fn agree_with(name: &str, model: &Model, reference_backend: Backend) {
    let reference = common::run(model, reference_backend);
    let others = Backend::available().into_iter().filter(|b| *b != reference_backend);
    for backend in others.filter(|b| *b != Backend::Dense || reference_backend == Backend::Dense) {
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
    // (examples/calibration/ holds calibration files, not models)
    let mut files: Vec<_> = paths
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml" || e == "json"))
        .filter(|p| !p.parent().is_some_and(|d| d.ends_with("calibration")))
        .collect();
    files.sort();
    assert!(files.iter().any(|p| p.ends_with("lab-pullout/lab-pullout.toml")), "the Gmsh example is included");
    for path in files {
        let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
        if model.mesh.nodes.len() > LARGEST_EXAMPLE_NODES {
            // the reinforced wall and the seismic wall on its mesh: ~2700 unknowns over ~1600
            // iterations is hours for the dense reference; tests/reinforced_wall_example.rs and
            // tests/seismic_wall_example.rs run them, and the yielding-soil model below checks the
            // same code path on every backend
            continue;
        }
        let started = std::time::Instant::now();
        if model.mesh.nodes.len() > LARGEST_DENSE_REFERENCE_NODES {
            // the embedded pull-out boxes: a minute each on the dense reference in a debug build
            // (2 s on a sparse backend), so the sparse backends are compared with faer's LU there
            // (the dense reference is checked against faer on every smaller example, and in
            // tests/solver_crosscheck.rs)
            agree_with(&path.display().to_string(), &model, Backend::Faer);
        } else {
            every_backend_agrees(&path.display().to_string(), &model);
        }
        eprintln!("{}: {:.1} s", path.display(), started.elapsed().as_secs_f64());
    }
}

/// A dynamic stage's steps compared to round-off, 1e-10 (measured on the seismic liner: 1e-11).
/// From its 100th step on, and in the stages after it, 1e-6: a stick–slip history carries the
/// backends' round-off from step to step (where a point sticks again moves with the last bits of
/// its slip velocity, and a re-closing contact's impact multiplies it), measured on the seismic
/// liner at 2e-9 in the displacements and 1.5e-7 in the multipliers and reactions.
const DYNAMIC_STEPS_AT_ROUND_OFF: usize = 100;

/// Examples larger than this are left to their own tests (the dense reference is O(n³)).
const LARGEST_EXAMPLE_NODES: usize = 800;
/// Examples larger than this take faer's sparse LU as the reference instead of the dense one.
const LARGEST_DENSE_REFERENCE_NODES: usize = 450;

/// Yielding Mohr–Coulomb soil under Newton's method with the consistent tangent (a rigid footing
/// pushed into Tresca clay, as in tests/strip_footing.rs but coarse): the unsymmetric path with
/// Gauss-point state, line search and plastic tangents gives the reference's answers on every
/// backend.
#[test]
fn yielding_soil_agrees_on_every_backend() {
    use geoslip::meshgen::{support, Block};
    use geoslip::model::file::*;
    use std::collections::BTreeMap;
    let block = Block::new(SolidKind::Quad8, (0.0, -2.0), (3.0, 2.0), (6, 4), "clay", 1, 1);
    let footing: Vec<u64> = block
        .row_nodes(block.ny)
        .into_iter()
        .filter(|id| block.nodes.iter().any(|n| n.0 == *id && n.1 <= 1.0))
        .collect();
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), block.row_nodes(0));
    node_sets.insert("axis".into(), block.column_nodes(0));
    node_sets.insert("far".into(), block.column_nodes(block.nx));
    node_sets.insert("footing".into(), footing);
    let mut clay = geoslip::model::file::SoilMaterial::linear_elastic(3.0e4, 0.45, 0.0);
    clay.model = SoilModel::MohrCoulomb;
    clay.cohesion = 100.0;
    let mut soil = BTreeMap::new();
    soil.insert("clay".into(), clay);
    let file = geoslip::model::file::ModelFile {
        title: "coarse footing".into(),
        materials: geoslip::model::file::Materials { soil, ..Default::default() },
        nodes: block.nodes,
        elements: block.elements,
        node_sets,
        supports: vec![
            support("base", &[Direction::X, Direction::Y]),
            support("axis", &[Direction::X]),
            support("far", &[Direction::X]),
        ],
        stages: vec![Stage {
            name: "push".into(),
            load_factors: vec![0.2, 0.4, 0.6, 0.8, 1.0],
            prescribed: vec![common::prescribed("footing", None, Some(-0.05))],
            ..Default::default()
        }],
        analysis: AnalysisSettings { scheme: Scheme::Newton, ..AnalysisSettings::default() },
        ..Default::default()
    };
    let model = common::model(&file, "coarse-footing.toml");
    let reference = common::run(&model, Backend::Dense);
    let yielding: usize = reference.steps.iter().map(|(rec, _)| rec.yielding_points).max().unwrap_or(0);
    assert!(yielding > 0, "the footing must yield the soil for this test to mean anything");
    every_backend_agrees("coarse footing (yielding soil)", &model);
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
        assert!(stats.solver.factorizations > 0);
        assert!(stats.warnings.is_empty(), "{name}: {:?}", stats.warnings);
    }
}
