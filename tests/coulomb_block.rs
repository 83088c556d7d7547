//! A soil block sliding on a rigid base (the Coulomb block).
//!
//! Reference: docs/verification.md §4: with the tangential displacement d applied to
//! every node of the block, the base shear is F = min(Ks·A·d, c·A + μ·N), with A the contact length
//! (per metre width), N the normal force and μ = tan φ.
//!
//! Parameters: a 1 m × 0.5 m quad4 block (4 × 2 elements), E = 10 MPa, ν = 0.3, weightless; a
//! surcharge q = 10 kPa on top (N = 10 kN/m); base interface Coulomb with Ks = 1000 kN/m³,
//! c = 1 kPa, φ = 30°; the base is a rigid master face (its nodes fixed, `master_normal` pointing
//! down into it). Goal: exact (to solver precision) before and after sliding.
//!
//! ```text
//!               q q q q q
//!             +----+----+----+----+   → d on every node
//!             |                   |
//!             +----+----+----+----+   slave: the block's base
//!   o====o====o====o====o====o====o====o====o   master: rigid base (fixed nodes), longer than the block
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

const KS: f64 = 1000.0;
const C: f64 = 1.0;
const Q: f64 = 10.0;

fn block_on_base(d: f64) -> ModelFile {
    common::block_on_rigid_base(
        ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: C, friction_angle: 30.0 },
        Q,
        d,
        vec![0.25, 0.5, 0.75, 1.0],
    )
}

fn base_shear(d: f64, backend: Backend) -> f64 {
    let model = common::model(&block_on_base(d), "coulomb-block.toml");
    let c = common::run(&model, backend);
    let r = c.last().unwrap();
    let block = &model.node_sets["block"];
    // the force that drives the block equals the base shear
    block.iter().map(|&n| r.reaction_vector[2 * n]).sum()
}

#[test]
fn base_shear_is_min_of_elastic_and_coulomb() {
    let strength = C * 1.0 + (30f64).to_radians().tan() * Q * 1.0;
    for backend in Backend::available() {
        for d in [0.002, 0.02, 0.05] {
            let exact = (KS * 1.0 * d).min(strength);
            let f = base_shear(d, backend);
            assert!((f - exact).abs() < 1e-9 * exact, "{backend:?}, d = {d}: F = {f}, expected {exact}");
        }
    }
}

/// The three iteration schemes reach the same sliding force on every backend (the consistent Newton
/// tangent is unsymmetric: MUMPS runs it with SYM=0), in no more iterations than the paper's
/// constant stiffness.
#[test]
fn every_scheme_gives_the_coulomb_force_and_newton_converges_fastest() {
    let strength = C * 1.0 + (30f64).to_radians().tan() * Q * 1.0;
    let mut iterations = Vec::new();
    for scheme in [Scheme::ConstantStiffness, Scheme::NewtonSymmetric, Scheme::Newton] {
        let mut file = block_on_base(0.05);
        file.analysis.scheme = scheme;
        let model = common::model(&file, "coulomb-block.toml");
        for backend in Backend::available() {
            let c = common::run(&model, backend);
            let r = c.last().unwrap();
            let f: f64 = model.node_sets["block"].iter().map(|&n| r.reaction_vector[2 * n]).sum();
            assert!((f - strength).abs() < 1e-9 * strength, "{scheme:?}/{backend:?}: F = {f}");
            if backend == Backend::Dense {
                iterations.push(c.steps.iter().map(|(rec, _)| rec.iterations).sum::<usize>());
            }
        }
    }
    assert!(
        iterations[2] <= iterations[0],
        "Newton {} iterations, constant stiffness {}",
        iterations[2],
        iterations[0]
    );
}

/// With `freeze_normal_stress`, σn is held at its value at the start of each stage (as programs that
/// fix σn do): a second surcharge added while the block slides does not raise its strength, which
/// stays c·A + μ·q·A from the first stage; without the option it rises to c·A + μ·2q·A.
#[test]
fn a_frozen_normal_stress_keeps_the_strength_of_the_stage_start() {
    let mu = (30f64).to_radians().tan();
    for (freeze, q_effective) in [(true, Q), (false, 2.0 * Q)] {
        let mut file = block_on_base(0.05);
        file.stages[1].loads =
            vec![LoadSpec::EdgeTraction { name: None, edge_set: "top".into(), pressure: Q, shear: 0.0 }];
        file.analysis.freeze_normal_stress = freeze;
        let model = common::model(&file, "coulomb-block.toml");
        let c = common::run(&model, Backend::available()[0]);
        let r = c.last().unwrap();
        let f: f64 = model.node_sets["block"].iter().map(|&n| r.reaction_vector[2 * n]).sum();
        let exact = C + mu * q_effective;
        assert!((f - exact).abs() < 1e-9 * exact, "freeze = {freeze}: F = {f}, expected {exact}");
    }
}

/// Effective stress (Terzaghi): with the water table 0.25 m above the base (on an element
/// boundary: the weight is integrated at the Gauss points), the interface strength acts on
/// σn′ = σn − p. The block weighs γ = 18 kN/m³ above the water and 20 below, so
/// N′ = q·A + 18·0.25·A + (20 − γw)·0.25·A, and the sliding force is c·A + μ·N′.
#[test]
fn under_water_the_interface_strength_uses_the_effective_normal_stress() {
    let mu = (30f64).to_radians().tan();
    let mut file = block_on_base(0.05);
    let soil = file.materials.soil.get_mut("soil").unwrap();
    soil.unit_weight = 18.0;
    soil.saturated_unit_weight = Some(20.0);
    file.stages[0].loads.push(LoadSpec::Gravity { factor: 1.0 });
    file.stages[0].water = Some(WaterTable { level: Some(0.25), line: None, none: false, unit_weight: None });
    let model = common::model(&file, "coulomb-block.toml");
    let gamma_w = geoslip::model::Model::default_water_weight(&model.units);
    let n_effective = Q + 18.0 * 0.25 + (20.0 - gamma_w) * 0.25;
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let r = c.last().unwrap();
        let f: f64 = model.node_sets["block"].iter().map(|&n| r.reaction_vector[2 * n]).sum();
        let exact = C + mu * n_effective;
        assert!((f - exact).abs() < 1e-9 * exact, "{backend:?}: F = {f}, expected c·A + μ·N′ = {exact}");
        // the contact itself carries the total stress: N′ + p·A
        let total: f64 = r.interface_points.iter().map(|p| p.lambda).sum();
        let expected_total = n_effective + gamma_w * 0.25;
        assert!((total - expected_total).abs() < 1e-9 * expected_total, "{backend:?}: N = {total}");
    }
}
