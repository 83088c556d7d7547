//! A singular model names what is unconstrained, whichever backend finds it.
//!
//! Reference: the structure of the system itself. A two-node bar hanging from a soil node, with no
//! interface holding its free end, leaves that end's transverse DOF with no stiffness and no
//! constraint (a 2-node bar has no transverse stiffness; shared/DESIGN.md §1). The model is
//! tests/bad-models/run-singular-hanging-bar.toml: its free bar node is node 7, so every backend must
//! report "node 7 uy" as singular: the dense reference through its zero pivot, MUMPS through
//! PIVNUL_LIST (INFOG(28) > 0 with ICNTL(24) = 1), UMFPACK through its singular-matrix warning and faer
//! through the residual check, both followed by geoslip's structural diagnosis. The node is named
//! with its position (3, 1) from the model's node list, and, the matrix being singular at the
//! model's start, at once (not cut back).

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::model::Model;
use std::path::Path;

#[test]
fn every_backend_names_the_free_node_of_a_singular_model() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-models/run-singular-hanging-bar.toml");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for backend in Backend::available() {
        let options = RunOptions { backend, ..RunOptions::default() };
        let err = analysis::run(&model, &options, &mut Collect::default()).expect_err("the model is singular");
        let message = err.to_string();
        assert!(message.contains("singular"), "{backend:?}: {message}");
        assert!(message.contains("node 7 uy (at x = 3.000, y = 1.000)"), "{backend:?}: {message}");
        assert!(message.contains("run-singular-hanging-bar.toml"), "{backend:?}: {message}");
        // singular at the last equilibrium (the model's start): the model's, named at once, not
        // cut back as a matrix singular where an iteration went would be
        assert!(matches!(err, geoslip::Error::Solve { .. }), "{backend:?}: {message}");
    }
}

/// The same model with the soil made Duncan–Chang and Newton's iteration: a nonlinear-elastic soil
/// always gives its own tangent, so falling back to the elastic soil stiffness (the recovery for a
/// yielded tangent) leaves the matrix singular; the next singular matrix is diagnosed, within the
/// increment, instead of every iteration falling back again.
#[test]
fn a_hyperbolic_soil_names_the_free_node_too() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-models/run-singular-hanging-bar.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text
        .replace(
            "youngs_modulus = 10000.0\npoissons_ratio = 0.3\n",
            "model = \"duncan-chang\"\ncohesion = 5.0\nfriction_angle = 30.0\n\
             hyperbolic = { K = 300.0, n = 0.5, Rf = 0.8, Kb = 150.0, m = 0.25, Kur = 600.0 }\n",
        )
        .replace("[node_sets]", "[analysis]\nscheme = \"newton\"\n\n[node_sets]");
    assert!(text.contains("duncan-chang") && text.contains("newton"));
    let file = geoslip::model::parse(&path, &text).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::from_file(&path, &file).unwrap_or_else(|e| panic!("{e}"));
    let options = RunOptions { backend: Backend::Dense, ..RunOptions::default() };
    let err = analysis::run(&model, &options, &mut Collect::default()).expect_err("the model is singular");
    let message = err.to_string();
    assert!(message.contains("singular"), "{message}");
    assert!(message.contains("node 7 uy"), "{message}");
    assert!(matches!(err, geoslip::Error::Solve { .. }), "{message}");
}
