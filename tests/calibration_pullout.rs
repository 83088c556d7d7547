//! Calibration of Ks and φ from three pull-out curves.
//!
//! Reference: docs/verification.md §1–2, the progressive slip of an elastic–perfectly
//! plastic interface along an extensible reinforcement on a rigid soil at constant σn (with the
//! large-slip form: what has left the soil carries no shear). The measured curves are made by
//! geoslip's finite-element pull-out box: a 1.0 m × 0.2 m block of very stiff soil (E = 10⁷ kPa,
//! 40 × 8 quad4), a steel strip at mid-height over 0.8 m (EA = 200 000 kN/m, two faces), Coulomb faces
//! with Ks = 10 000 kPa/m, c = 0, φ = 30°, σn frozen at the surcharge q = 25, 50, 100 kPa, the head
//! pulled 20 mm in 80 steps (αL = 0.25; every point slides from 1.5 to 6 mm on, then the force
//! falls as the strip leaves the soil); then 2 % noise
//! (each value off by a relative error of standard deviation 2 %, fixed seed). The fit uses the
//! closed form with c held at 0.
//!
//! Goal (the issue's): Ks and φ within 3 % and inside their 95 % intervals.
//!
//! The closed form is small-strain: it counts the shear over the reinforcement's length at rest,
//! where the box counts it over the stretched length in the soil. With an extensible grid (EA =
//! 2000 kN/m in this box) the two differ by up to 2 % (the mean strain), 0.2 % at 20 000 kN/m; at
//! the test's precision (φ's standard error is 0.1 %) even that shows, so this test uses a steel strip,
//! and docs/calibration.md sends extensible reinforcement to the finite-element model.

mod common;

use geoslip::calibration::{self, spec};
use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::ShearLawSpec;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::fmt::Write as _;

const KS: f64 = 10_000.0;
const PHI: f64 = 30.0;
const PULL: f64 = 0.02;
const STEPS: usize = 80;

/// The head force after each pull step of the box under `q`.
fn pull_out_curve(q: f64) -> Vec<(f64, f64)> {
    let mut file = PullOutBox {
        length: 1.0,
        height: 0.2,
        embedded: 0.8,
        nx: 40,
        ny_half: 4,
        youngs_modulus: 1.0e7,
        poissons_ratio: 0.3,
        unit_weight: 0.0,
        axial_stiffness: 200_000.0,
        law: ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: 0.0, friction_angle: PHI },
        surcharge: q,
        pull: PULL,
        steps: STEPS,
        ..PullOutBox::default()
    }
    .model();
    file.stages[1].freeze_normal_stress = Some(true);
    let model = common::model(&file, "pull-out.toml");
    let c = common::run(&model, Backend::available()[0]);
    let forces = common::head_forces(&model, &c, "grid.head");
    forces.into_iter().enumerate().map(|(k, p)| (PULL * (k + 1) as f64 / STEPS as f64, p)).collect()
}

#[test]
fn the_closed_form_follows_the_finite_element_box_it_stands_for() {
    // the model of the fit against the curves it is fitted to, without noise: the discretisation
    // (h = 25 mm, αh = 0.008), the strain (≤ 0.02 %) and the points leaving the soil one by one are
    // all that differ
    let r = calibration::pullout_closed_form::Reinforcement { length: 0.8, axial_stiffness: 200_000.0, faces: 2.0 };
    for q in [25.0, 100.0] {
        let tau = q * PHI.to_radians().tan();
        for (u, p) in pull_out_curve(q) {
            let closed = calibration::pullout_closed_form::force(&r, KS, tau, u);
            assert!((p - closed).abs() < 0.005 * p, "q = {q}, u = {u}: box {p}, closed form {closed}");
        }
    }
}

#[test]
fn three_pull_out_curves_give_back_ks_and_phi() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(2026);
    let noise = Normal::new(0.0, 0.02).unwrap();
    let mut csv = String::from("surcharge [kPa],displacement [mm],force [kN/m]\n");
    for q in [25.0, 50.0, 100.0] {
        for (u, p) in pull_out_curve(q) {
            let _ = writeln!(csv, "{q},{},{}", 1e3 * u, p * (1.0 + noise.sample(&mut rng)));
        }
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pull-out.csv"), csv).unwrap();
    let toml = "test = \"pull-out\"\ndata = \"pull-out.csv\"\nlaw = \"coulomb\"\n[fixed]\ncohesion = 0.0\n\
                [pull_out]\nembedded_length = 0.8\naxial_stiffness = 200000.0\n";
    std::fs::write(dir.path().join("calibration.toml"), toml).unwrap();
    let spec = spec::load(&dir.path().join("calibration.toml")).unwrap_or_else(|e| panic!("{e}"));
    let c = calibration::calibrate(&spec).unwrap_or_else(|e| panic!("{e}"));
    for (name, truth) in [("shear_stiffness", KS), ("friction_angle", PHI)] {
        let p = c.parameters.iter().find(|p| p.name == name).unwrap();
        let (lo, hi) = p.interval.unwrap();
        assert!((p.value - truth).abs() < 0.03 * truth, "{name}: {} against {truth}", p.value);
        assert!(lo <= truth && truth <= hi, "{name}: {truth} outside the 95 % interval {lo} … {hi}");
    }
    let cohesion = c.parameters.iter().find(|p| p.name == "cohesion").unwrap();
    assert!(!cohesion.fitted && cohesion.value == 0.0 && cohesion.interval.is_none());
}

/// The finite-element model of the test, for what the closed form does not cover: an extensible
/// grid (EA = 2000 kN/m) in a deformable soil (E = 20 MPa, ν = 0.3) with σn from the multipliers.
/// The curves are those of geoslip's pull-out box built by `meshgen` (0.5 m × 0.2 m, 10 × 4 quad4,
/// the grid over 0.4 m, Ks = 20 000 kPa/m, c = 0, φ = 30°, q = 20, 40, 80 kPa, 10 mm in 10 steps) with
/// 2 % noise; the calibration builds its own box from `[pull_out.box]` and runs it for every trial.
#[test]
fn the_finite_element_model_gives_back_ks_and_phi_of_an_extensible_grid() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(2026);
    let noise = Normal::new(0.0, 0.02).unwrap();
    let mut csv = String::from("surcharge [kPa],displacement [mm],force [N/m]\n");
    for q in [20.0, 40.0, 80.0] {
        let file = PullOutBox {
            length: 0.5,
            height: 0.2,
            embedded: 0.4,
            nx: 10,
            ny_half: 2,
            youngs_modulus: 20_000.0,
            poissons_ratio: 0.3,
            unit_weight: 0.0,
            axial_stiffness: 2000.0,
            law: ShearLawSpec::Coulomb { shear_stiffness: 20_000.0, cohesion: 0.0, friction_angle: PHI },
            surcharge: q,
            pull: 0.01,
            steps: 10,
            ..PullOutBox::default()
        }
        .model();
        let model = common::model(&file, "pull-out.toml");
        let c = common::run(&model, Backend::available()[0]);
        for (k, p) in common::head_forces(&model, &c, "grid.head").into_iter().enumerate() {
            let _ = writeln!(csv, "{q},{},{}", k + 1, 1e3 * p * (1.0 + noise.sample(&mut rng)));
        }
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pull-out.csv"), csv).unwrap();
    let toml = "test = \"pull-out\"\ndata = \"pull-out.csv\"\nlaw = \"coulomb\"\n[fixed]\ncohesion = 0.0\n\
                [pull_out]\nembedded_length = 0.4\naxial_stiffness = 2000.0\nmodel = \"finite-element\"\n\
                [pull_out.box]\nlength = 0.5\nheight = 0.2\nyoungs_modulus = 20000.0\npoissons_ratio = 0.3\n\
                elements = 10\nsteps = 10\n";
    std::fs::write(dir.path().join("calibration.toml"), toml).unwrap();
    let spec = spec::load(&dir.path().join("calibration.toml")).unwrap_or_else(|e| panic!("{e}"));
    let c = calibration::calibrate(&spec).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.box_embedded_length, Some(0.4));
    for (name, truth) in [("shear_stiffness", 20_000.0), ("friction_angle", PHI)] {
        let p = c.parameters.iter().find(|p| p.name == name).unwrap();
        let (lo, hi) = p.interval.unwrap();
        assert!((p.value - truth).abs() < 0.03 * truth, "{name}: {} against {truth}", p.value);
        assert!(lo <= truth && truth <= hi, "{name}: {truth} outside the 95 % interval {lo} … {hi}");
    }
}
