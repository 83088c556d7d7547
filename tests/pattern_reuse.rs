//! Reserved segments: a reinforcement that slides along deformable soil keeps the sparsity pattern,
//! so the symbolic analysis is redone about once per `reserved_segments` of slip, and the answers
//! are those of a run that re-analyses at every re-association.
//!
//! Reference: issue #6's target, at most 1 + (slip ÷ reserved window) analyses per stage, and
//! docs/verification.md §2, "Large slip": once every point slides, the pull-out force
//! is P = n_f·τmax·(L − u). The box: L = 0.8 m embedded in a 1 m long, 0.6 m high soil block of 40 × 6
//! quad4 elements (h = 0.025 m), a nearly inextensible grid (EA = 10⁶ kN/m), Coulomb interface
//! (c = 0, φ = 30°) under q = 50 kPa (σn = q: no self-weight is applied), pulled 0.1 m = 4 h in 20
//! increments. With 2 segments reserved on either side: one analysis for the surcharge stage, then
//! at most 1 + 4/2 for the pull. The reservation is about the full system's pattern: these runs
//! solve the full system in every iteration (`condense: false`); a condensed run analyses only when
//! its soil changes.

mod common;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::{Backend, SolverOptions};
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::ShearLawSpec;

fn run(reserved: usize, backend: Backend) -> (Vec<(f64, f64)>, usize) {
    let mut file = PullOutBox {
        nx: 40,
        ny_half: 3,
        axial_stiffness: 1.0e6,
        law: ShearLawSpec::Coulomb { shear_stiffness: 20_000.0, cohesion: 0.0, friction_angle: 30.0 },
        pull: 0.1,
        steps: 20,
        ..PullOutBox::default()
    }
    .model();
    file.analysis.reserved_segments = reserved;
    let model = common::model(&file, "sliding-grid.toml");
    let mut sink = Collect::default();
    let options = RunOptions {
        solver: SolverOptions { condense: false, ..SolverOptions::default() },
        ..RunOptions::for_model(&model, backend)
    };
    let stats = analysis::run(&model, &options, &mut sink).unwrap_or_else(|e| panic!("{e}"));
    let head = model.node_sets["grid.head"][0];
    let curve =
        sink.steps.iter().map(|(_, r)| (-r.displacement_vector[2 * head], -r.reaction_vector[2 * head])).collect();
    (curve, stats.solver.analyses)
}

#[test]
fn sliding_within_the_reserved_segments_needs_no_new_analysis() {
    for backend in Backend::available().into_iter().filter(|b| *b != Backend::Dense) {
        let (reserved, analyses) = run(2, backend);
        let (plain, plain_analyses) = run(0, backend);
        eprintln!("{backend:?}: {analyses} analyses with 2 segments reserved, {plain_analyses} without");
        assert!(analyses <= 1 + (1 + 4 / 2), "{backend:?}: {analyses} analyses with 2 segments reserved");
        assert!(plain_analyses > analyses, "{backend:?}: {plain_analyses} analyses without a reservation");
        // the zeros in the pattern change nothing in the answers
        assert_eq!(reserved.len(), plain.len());
        for ((u, p), (v, q)) in reserved.iter().zip(&plain) {
            assert!(
                (u - v).abs() < 1e-12 && (p - q).abs() < 1e-8 * (1.0 + q.abs()),
                "{backend:?}: ({u}, {p}) against ({v}, {q})"
            );
        }
        // the large-slip closed form at the end, within the box's departures from uniform σn
        let (u, p) = *reserved.last().unwrap();
        let exact = 2.0 * 50.0 * 30f64.to_radians().tan() * (0.8 - u);
        eprintln!("{backend:?}: P({u:.4}) = {p:.3} kN/m, 2·q·tanφ·(L − u) = {exact:.3}");
        assert!(((p - exact) / exact).abs() < 0.1, "{backend:?}: P({u}) = {p}, expected about {exact}");
    }
}
