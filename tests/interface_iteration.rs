//! The interface iteration (the elastic soil condensed onto the interface's unknowns, the
//! iterations on the interface alone) reaches the equilibrium the full system reaches, on every
//! backend, with both schemes; and the fully sliding grid carries the Coulomb force.
//!
//! Reference: the equilibrium equations themselves — the condensed system is the full one with the
//! interior eliminated exactly (S = L_KK − L_KI L_II⁻¹ L_IK), so both iterations solve the same
//! residual to the same tolerance and their answers must agree to it; the dense reference (Gauss
//! elimination with complete pivoting, which never condenses) is the independent solver. The
//! sliding force: a grid of embedded length L under a frozen normal stress q on two faces carries
//! T = 2·q·tan φ·L once every point slides (docs/verification.md §2, the fully plastic
//! limit of the progressive-slip solution).
//!
//! Model: the generated pull-out box (1 m × 0.6 m, 40 × 12 quad4, grid over 0.8 m at mid-height,
//! EA = 1000 kN/m), Coulomb faces (Ks = 540 kN/m³, c = 0, φ = 30°), q = 10 kPa frozen, pulled 40 mm
//! in 8 increments: every point slides by the end.

mod common;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::{Backend, SolverOptions};
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::{Scheme, ShearLawSpec};
use geoslip::model::Model;

fn frictional_pullout(scheme: Scheme) -> Model {
    let mut file = PullOutBox {
        law: ShearLawSpec::Coulomb { shear_stiffness: 540.0, cohesion: 0.0, friction_angle: 30.0 },
        surcharge: 10.0,
        pull: 0.04,
        steps: 8,
        nx: 40,
        ny_half: 6,
        ..PullOutBox::default()
    }
    .model();
    file.analysis.scheme = scheme;
    file.analysis.freeze_normal_stress = true;
    file.analysis.force_tolerance = 1e-10;
    common::model(&file, "frictional-pullout.toml")
}

fn run(model: &Model, backend: Backend, condense: bool) -> (Collect, geoslip::analysis::RunStats) {
    let options = RunOptions {
        solver: SolverOptions { condense, ..SolverOptions::default() },
        ..RunOptions::for_model(model, backend)
    };
    let mut sink = Collect::default();
    let stats = analysis::run(model, &options, &mut sink).unwrap_or_else(|e| panic!("{}: {e}", backend.name()));
    (sink, stats)
}

#[test]
fn the_condensed_iteration_reaches_the_full_systems_equilibrium_on_every_backend() {
    for scheme in [Scheme::ConstantStiffness, Scheme::Newton] {
        let model = frictional_pullout(scheme);
        let (reference, _) = run(&model, Backend::Dense, true);
        let expected = common::head_forces(&model, &reference, "grid.head");
        for backend in Backend::available().into_iter().filter(|&b| b != Backend::Dense) {
            for condense in [true, false] {
                let (c, stats) = run(&model, backend, condense);
                assert_eq!(
                    stats.solver.condensed_unknowns.is_some(),
                    condense,
                    "{} {scheme:?}: condensed {condense}",
                    backend.name()
                );
                let forces = common::head_forces(&model, &c, "grid.head");
                assert_eq!(forces.len(), expected.len());
                for (k, (f, e)) in forces.iter().zip(&expected).enumerate() {
                    assert!(
                        (f - e).abs() <= 1e-7 * e.abs().max(1.0),
                        "{} {scheme:?} condensed {condense}: step {}: {f} against the dense reference's {e}",
                        backend.name(),
                        k + 1
                    );
                }
                // every soil node too, to the same tolerance against the largest displacement
                let (a, b) = (c.last().expect("steps"), reference.last().expect("steps"));
                let scale = b.displacements.iter().map(|d| d.2[0].abs().max(d.2[1].abs())).fold(0.0, f64::max);
                for (p, q) in a.displacements.iter().zip(&b.displacements) {
                    for d in 0..2 {
                        assert!(
                            (p.2[d] - q.2[d]).abs() <= 1e-7 * scale,
                            "{} {scheme:?} condensed {condense}: node {} moved {:?}, the reference {:?}",
                            backend.name(),
                            p.0,
                            p.2,
                            q.2
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn the_interface_iteration_needs_few_sparse_solves() {
    // the constant-stiffness scheme iterates many times per increment; condensed, those iterations
    // are on the interface alone: a sparse solve for the first iteration and one for the interior to
    // follow, where the full system needs one per iteration
    let model = frictional_pullout(Scheme::ConstantStiffness);
    let backend = Backend::available()[0];
    let (_, condensed) = run(&model, backend, true);
    let (_, full) = run(&model, backend, false);
    assert_eq!(condensed.iterations, full.iterations, "the same iterates");
    assert!(full.solver.solves >= condensed.iterations, "full: {} solves", full.solver.solves);
    assert!(
        condensed.solver.solves * 2 < full.solver.solves,
        "condensed: {} sparse solves against {} on the full system",
        condensed.solver.solves,
        full.solver.solves
    );
    assert!(
        condensed.solver.factorizations <= 3,
        "condensed: {} sparse factorisations",
        condensed.solver.factorizations
    );
}

#[test]
fn a_pulled_increment_costs_one_sparse_solve() {
    // the interior is in balance when a pull increment starts (the last increment's end left it so)
    // and the pull moves the head, a kept unknown, alone: the iterations start on the interface and
    // the one sparse solve is the interior following at the end; an increment that loads the soil
    // (the surcharge) solves its first iteration condensed, and has a second solve
    let model = frictional_pullout(Scheme::ConstantStiffness);
    let backend = Backend::available()[0];
    let (c, condensed) = run(&model, backend, true);
    let first_stage = c.steps.iter().filter(|(r, _)| r.stage_index == 0).count();
    let pulled = c.steps.len() - first_stage;
    assert_eq!(pulled, 8, "the pull's increments");
    assert!(
        condensed.solver.solves <= 2 * first_stage + pulled,
        "{} sparse solves for {first_stage} loading and {pulled} pulled increments",
        condensed.solver.solves
    );
}

#[test]
fn the_sliding_grid_carries_the_coulomb_force() {
    let model = frictional_pullout(Scheme::Newton);
    let (c, _) = run(&model, Backend::available()[0], true);
    let last = *common::head_forces(&model, &c, "grid.head").last().unwrap();
    // the length in contact at the end: the grid's 0.8 m less what has left the box at the front
    // (the head's 40 mm less the grid's stretch), less at most half an element (0.0125 m) for the
    // front point's half tributary; bound the force between the full and the shortest length
    let (q, phi) = (10.0f64, 30f64.to_radians());
    let full = 2.0 * q * phi.tan() * 0.8;
    let shortened = 2.0 * q * phi.tan() * (0.8 - 0.04 - 0.0125);
    assert!(
        last <= full * (1.0 + 1e-6) && last >= shortened * (1.0 - 1e-6),
        "sliding force {last} kN/m, expected between {shortened} and {full}"
    );
}
