//! The three iteration schemes on a frictional pull-out reach the same equilibrium, and the
//! consistent Newton tangent converges in fewer iterations than the paper's constant stiffness.
//!
//! Reference: the equilibrium equations themselves (every scheme solves the same residual to the same
//! tolerance, so their answers must agree to it), and the convergence theory of Newton's method
//! (quadratic with the consistent tangent, linear with a fixed or lagged one; e.g. Crisfield,
//! Non-linear Finite Element Analysis of Solids and Structures, vol. 1, ch. 9).
//!
//! Model: the generated pull-out box with a purely frictional interface (Ks = 540 kN/m³, c = 0,
//! φ = 30°, so τ depends on σn everywhere), q = 10 kPa, pulled 40 mm in 8 increments, far enough for
//! most of the grid to slide; and, for Newton's rate under large slip, the same box as issue #15
//! measures it (elastic soil, σn frozen at 20 kPa, pulled 20 mm in 20 increments).

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::{Scheme, ShearLawSpec};

/// The model file above, iterated by `scheme`.
fn frictional_box(scheme: Scheme) -> geoslip::model::file::ModelFile {
    let mut file = PullOutBox {
        law: ShearLawSpec::Coulomb { shear_stiffness: 540.0, cohesion: 0.0, friction_angle: 30.0 },
        surcharge: 10.0,
        pull: 0.04,
        steps: 8,
        ..PullOutBox::default()
    }
    .model();
    file.analysis.scheme = scheme;
    file.analysis.force_tolerance = 1e-10;
    file
}

/// The model above, iterated by `scheme`, with σn frozen or not.
fn frictional_pullout(scheme: Scheme, frozen: bool) -> geoslip::model::Model {
    let mut file = frictional_box(scheme);
    file.analysis.freeze_normal_stress = frozen;
    common::model(&file, "frictional-pullout.toml")
}

#[test]
fn schemes_agree_and_the_consistent_tangent_converges_fastest() {
    let mut runs = Vec::new();
    for scheme in [Scheme::ConstantStiffness, Scheme::NewtonSymmetric, Scheme::Newton] {
        let model = frictional_pullout(scheme, false);
        // faer, which repeats to the bit: docs/model-format.md quotes these iteration counts
        let c = common::run(&model, Backend::Faer);
        let head = model.node_sets["grid.head"][0];
        let pull = -c.last().unwrap().reaction_vector[2 * head];
        let iterations: usize = c.steps.iter().map(|(r, _)| r.iterations).sum();
        let sliding = c.last().map(|_| c.steps.last().unwrap().0.sliding_points).unwrap();
        runs.push((scheme, pull, iterations, sliding));
    }
    let (_, reference, constant_iterations, sliding) = runs[0];
    assert!(sliding > 10, "the test must slide: {sliding} points sliding");
    for &(scheme, pull, _, _) in &runs {
        assert!(((pull - reference) / reference).abs() < 1e-6, "{scheme:?}: pull {pull} vs {reference}");
    }
    for (id, run) in
        ["iterations.constant-stiffness", "iterations.newton-symmetric", "iterations.newton"].iter().zip(&runs)
    {
        common::doc_number(id, run.2.to_string());
    }
    let newton_iterations = runs[2].2;
    assert!(
        newton_iterations < constant_iterations,
        "Newton {newton_iterations} vs constant stiffness {constant_iterations}"
    );
    assert!(
        newton_iterations < runs[1].2,
        "the consistent tangent {newton_iterations} vs the lagged one {}",
        runs[1].2
    );
}

#[test]
fn newton_factorises_symmetric_where_its_tangent_is_and_reaches_the_same_equilibrium() {
    // With σn frozen and no large slip, nothing couples τ to σn or to the stretch of the grid: the
    // consistent tangent is symmetric, and every backend takes it as such (MUMPS LDLᵀ on the lower
    // triangle). Unfrozen, the frictional interface's tangent is unsymmetric; under large slip
    // (re-association on) each spring's force τ·ℓ follows its tributary length, and the tangent's
    // row ⊗ ∂(τ·ℓ)/∂u is unsymmetric too: both are factorised as LU. All reach the
    // constant-stiffness answer.
    use geoslip::analysis::{self, Collect, RunOptions};
    use geoslip::model::file::ReassociationRule;
    let solve = |scheme: Scheme, frozen: bool, large_slip: bool, backend: Backend| {
        let mut file = frictional_box(scheme);
        file.analysis.freeze_normal_stress = frozen;
        if !large_slip {
            file.analysis.reassociation = ReassociationRule::None;
        }
        let model = common::model(&file, "frictional-pullout.toml");
        let mut collect = Collect::default();
        let options = RunOptions::for_model(&model, backend);
        let stats = analysis::run(&model, &options, &mut collect).unwrap_or_else(|e| panic!("{e}"));
        let head = model.node_sets["grid.head"][0];
        (-collect.last().unwrap().reaction_vector[2 * head], stats.solver.symmetric)
    };
    for backend in Backend::available() {
        for (frozen, large_slip) in [(true, false), (true, true), (false, true)] {
            let (reference, reference_symmetric) = solve(Scheme::ConstantStiffness, frozen, large_slip, backend);
            assert!(reference_symmetric);
            let (pull, symmetric) = solve(Scheme::Newton, frozen, large_slip, backend);
            let case = format!("{backend:?}, frozen σn {frozen}, large slip {large_slip}");
            assert_eq!(symmetric, frozen && !large_slip, "{case}");
            assert!(((pull - reference) / reference).abs() < 1e-6, "{case}: pull {pull} vs {reference}");
        }
    }
}

#[test]
fn newton_under_large_slip_converges_in_at_most_three_iterations_a_pull_step() {
    // The elastic pull-out box of issue #15 (σn frozen, large slip, a point crossing the front
    // face), Newton from the extrapolated iterate. Each spring's force τ·ℓ follows its tributary
    // length ℓ, which the grid's stretch and its crossing of the front face move within an
    // increment; with that in the tangent the iteration is Newton's, quadratic (a pull step is one
    // correction, or two and the check that the second was the last), where without it the rate was
    // linear, about 1e-3 an iteration, and every pull step took 3 or 4 (mean 3.5 on this box). The
    // head forces are the constant-stiffness run's to 1e-6 of the peak.
    use geoslip::meshgen::PullOutBox;
    use geoslip::model::file::Extrapolation;
    let mut file = PullOutBox { pull: 0.02, steps: 20, ..common::issue_pullout_box() }.model();
    file.analysis.freeze_normal_stress = true;
    let reference_model = common::model(&file, "pullout-box.toml");
    let reference = common::run(&reference_model, Backend::Auto);
    file.analysis.scheme = Scheme::Newton;
    file.analysis.extrapolation = Extrapolation::Linear;
    let model = common::model(&file, "pullout-box-newton.toml");
    let c = common::run(&model, Backend::Auto);
    common::assert_same_head_forces((&reference_model, &reference), (&model, &c), 1e-6);
    let pull: Vec<_> = c.steps.iter().filter(|(r, _)| r.stage == "pull-out").map(|(r, _)| r).collect();
    assert_eq!(pull.len(), 20);
    let counts: Vec<usize> = pull.iter().map(|r| r.iterations).collect();
    eprintln!("iterations of the pull steps: {counts:?}");
    let mean = counts.iter().sum::<usize>() as f64 / counts.len() as f64;
    assert!(mean <= 2.5, "{mean} iterations a pull step");
    assert!(counts.iter().all(|&n| n <= 3), "a pull step took more than 3 iterations");
}

#[test]
fn schemes_agree_on_an_embedded_grid_whose_normal_stress_is_the_soils() {
    // The grid embedded in the continuous soil, σn not frozen: each point's σn is the soil's normal
    // stress across the grid, settled in passes over each increment (each pass holds σn at the last
    // pass's equilibrium), so every scheme solves the same problems and must find the same
    // equilibrium.
    let mut forces = Vec::new();
    for scheme in [Scheme::ConstantStiffness, Scheme::NewtonSymmetric, Scheme::Newton] {
        let mut file = frictional_box(scheme);
        file.interfaces[0].reinforcement.as_mut().unwrap().mode = geoslip::model::file::ReinforcementMode::Embedded;
        let model = common::model(&file, "embedded-pullout.toml");
        let c = common::run(&model, Backend::available()[0]);
        // σn is the soil's: the 10 kPa surcharge (the box's stages apply no weight), exactly at
        // the end of the surcharge stage, then changed by the pull near the grid
        let (_, surcharge) = &c.steps[0];
        for p in surcharge.interface_points.iter().filter(|p| p.state == "active") {
            assert!((p.sigma_n - 10.0).abs() < 1e-9, "{scheme:?}: node {} σn {}", p.slave_node, p.sigma_n);
        }
        let (_, last) = c.steps.last().unwrap();
        assert!(
            last.interface_points.iter().any(|p| p.state == "active" && (p.sigma_n - 10.0).abs() > 1e-3),
            "{scheme:?}: σn follows the soil's stress as the grid is pulled"
        );
        forces.push(common::head_forces(&model, &c, "grid.head"));
    }
    for other in &forces[1..] {
        for (k, (a, b)) in forces[0].iter().zip(other).enumerate() {
            assert!(common::relative_error(*b, *a) < 1e-6, "step {}: {a} against {b}", k + 1);
        }
    }
}
