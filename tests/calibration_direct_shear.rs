//! Calibration of a peak–residual law (peak, softening to a residual) from three direct-shear
//! curves.
//!
//! Reference: docs/verification.md §4, the Coulomb block: a block sheared over a rigid base with
//! every node displaced d carries τ(d), the law at slip d under σn. The measured curves are that
//! law written here in the test's own words from docs/model-format.md ("the strength falls linearly
//! from τp to τr over that plastic slip"; "τ = Ks·s/(1 + Ks·|s|/τp)"), not made by geoslip: q = 50,
//! 100, 200 kPa, d to 25 mm in 100 steps, with the softening law Ks = 20 000 kPa/m, c = 15 kPa,
//! φ = 30°, c_r = 8 kPa, φ_r = 22°, softening slip 10 mm; then 2 % noise is added (each value times
//! 1 + a Gaussian of standard deviation 0.02, fixed seed). The fit uses geoslip's law code, so a
//! law that departs from its documented curve fails here. `the_finite_element_block_follows_the_
//! closed_form_curves` checks that geoslip's block model gives those curves too.
//!
//! Goal (the issue's): every parameter within 3 % of the value that made the curves and inside its
//! 95 % interval; with one normal stress the fit refuses to give c and φ.

mod common;

use geoslip::calibration::{self, report, spec, CalibrationError};
use geoslip::linsol::Backend;
use geoslip::model::file::*;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::fmt::Write as _;
use std::path::Path;

const LAW: ShearLawSpec = ShearLawSpec::Softening {
    shear_stiffness: 20_000.0,
    cohesion: 15.0,
    friction_angle: 30.0,
    residual_cohesion: 8.0,
    residual_friction_angle: 22.0,
    softening_slip: 0.010,
};
const TRUE_VALUES: [(&str, f64); 6] = [
    ("shear_stiffness", 20_000.0),
    ("cohesion", 15.0),
    ("friction_angle", 30.0),
    ("residual_cohesion", 8.0),
    ("residual_friction_angle", 22.0),
    ("softening_slip", 0.010),
];
const STEPS: usize = 100;
const TRAVEL: f64 = 0.025;

/// The block on a rigid base under `q`, sheared to `TRAVEL` in `STEPS` steps.
fn shear_box(law: ShearLawSpec, q: f64) -> ModelFile {
    common::block_on_rigid_base(law, q, TRAVEL, (1..=STEPS).map(|k| k as f64 / STEPS as f64).collect())
}

/// The measured curves as a lab would give them: CSV in mm and kPa, with 2 % noise.
fn measured_csv(normal_stresses: &[f64], seed: u64) -> String {
    measured_csv_of(LAW, normal_stresses, seed)
}

/// The monotonic curve τ(d) of `law` under σn = `q`, from its documented definition
/// (`common::law_curve`).
fn closed_form(law: &ShearLawSpec, q: f64, d: f64) -> f64 {
    common::law_curve::monotonic(law, q, d)
}

fn measured_csv_of(law: ShearLawSpec, normal_stresses: &[f64], seed: u64) -> String {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut csv = String::from("normal_stress [kPa],slip [mm],shear_stress [kPa]\n");
    // each value off by a relative error of standard deviation 2 %
    let noise = Normal::new(0.0, 0.02).unwrap();
    for &q in normal_stresses {
        for k in 0..=STEPS {
            let d = TRAVEL * k as f64 / STEPS as f64;
            let tau = closed_form(&law, q, d);
            let _ = writeln!(csv, "{q},{},{}", 1e3 * d, tau * (1.0 + noise.sample(&mut rng)));
        }
    }
    csv
}

fn calibration_file(dir: &Path, csv: &str) -> spec::CalibrationSpec {
    calibration_file_of(dir, csv, "softening")
}

fn calibration_file_of(dir: &Path, csv: &str, law: &str) -> spec::CalibrationSpec {
    std::fs::write(dir.join("direct-shear.csv"), csv).unwrap();
    let toml = format!(
        "title = \"geotextile on sand\"\ntest = \"direct-shear\"\ndata = \"direct-shear.csv\"\nlaw = \"{law}\"\n"
    );
    std::fs::write(dir.join("calibration.toml"), toml).unwrap();
    spec::load(&dir.join("calibration.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// geoslip's finite-element block (a 1 m × 0.5 m block, 4 × 2 quad4, on a rigid base,
/// `common::block_on_rigid_base`) gives the curves the test writes: every node of the block moves d,
/// so the force over its 1 m contact is τ(d), to round-off (1e-9 of the peak).
#[test]
fn the_finite_element_block_follows_the_closed_form_curves() {
    let hyperbolic = ShearLawSpec::Hyperbolic { shear_stiffness: 20_000.0, cohesion: 15.0, friction_angle: 30.0 };
    for (law, q) in [(LAW, 50.0), (LAW, 200.0), (hyperbolic, 100.0)] {
        let model = common::model(&shear_box(law.clone(), q), "direct-shear.toml");
        let c = common::run(&model, Backend::available()[0]);
        let peak = closed_form(&law, q, TRAVEL).max(15.0 + q * 30f64.to_radians().tan());
        for (r, s) in c.steps.iter().filter(|(r, _)| r.stage_index == 1) {
            let d = TRAVEL * r.load_factor;
            let f: f64 = model.node_sets["block"].iter().map(|&n| s.reaction_vector[2 * n]).sum();
            let expected = closed_form(&law, q, d);
            assert!((f - expected).abs() < 1e-9 * peak, "{law:?}, q = {q}, d = {d}: {f} against {expected}");
        }
    }
}

#[test]
fn three_direct_shear_curves_give_back_the_peak_residual_law() {
    let dir = tempfile::tempdir().unwrap();
    let spec = calibration_file(dir.path(), &measured_csv(&[50.0, 100.0, 200.0], 2026));
    let c = calibration::calibrate(&spec).unwrap_or_else(|e| panic!("{e}"));
    for (name, truth) in TRUE_VALUES {
        let p = c.parameters.iter().find(|p| p.name == name).unwrap();
        let (lo, hi) = p.interval.unwrap();
        assert!((p.value - truth).abs() < 0.03 * truth, "{name}: {} against {truth}", p.value);
        assert!(lo <= truth && truth <= hi, "{name}: {truth} outside the 95 % interval {lo} … {hi}");
    }
    // the written law is the fitted one, ready for a model
    report::write(&c, dir.path()).unwrap();
    let block = std::fs::read_to_string(dir.path().join("interface-law.toml")).unwrap();
    #[derive(serde::Deserialize)]
    struct Pasted {
        law: ShearLawSpec,
    }
    let pasted: Pasted = toml::from_str(&block).unwrap_or_else(|e| panic!("{e}\n{block}"));
    match pasted.law {
        ShearLawSpec::Softening { shear_stiffness, friction_angle, .. } => {
            assert!((shear_stiffness - c.parameters[0].value).abs() < 1e-4 * c.parameters[0].value);
            assert!((friction_angle - c.parameters[2].value).abs() < 1e-4 * c.parameters[2].value);
        }
        other => panic!("{other:?}"),
    }
    for f in ["calibration.md", "calibration.json", "fitted-curves.png", "fitted-curves.svg"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
}

#[test]
fn one_normal_stress_cannot_give_cohesion_and_friction_apart() {
    let dir = tempfile::tempdir().unwrap();
    let spec = calibration_file(dir.path(), &measured_csv(&[100.0], 7));
    match calibration::calibrate(&spec) {
        Err(CalibrationError::Unidentifiable { parameters, reason }) => {
            assert!(
                parameters.iter().any(|p| p == "cohesion") && parameters.iter().any(|p| p == "friction_angle"),
                "{parameters:?}: {reason}"
            );
            assert!(reason.contains("one normal stress (100 kPa)"), "{reason}");
        }
        Ok(c) => panic!("a number was given: {:?}", c.parameters),
        Err(e) => panic!("{e}"),
    }
}

/// The intervals mean what they say: over twelve noise seeds, at least 85 % of the 72 intervals
/// hold the value that made the curves (95 % expected; fewer than 62 of 72 has a binomial probability
/// below 1e-4 for intervals that are right), and every parameter but the adhesions is within 3 %.
#[test]
fn the_95_percent_intervals_hold_the_true_values_about_95_percent_of_the_time() {
    let (mut held, mut total) = (0, 0);
    for seed in 1..=12 {
        let dir = tempfile::tempdir().unwrap();
        let spec = calibration_file(dir.path(), &measured_csv(&[25.0, 50.0, 100.0], seed));
        let c = calibration::calibrate(&spec).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        for (name, truth) in TRUE_VALUES {
            let p = c.parameters.iter().find(|p| p.name == name).unwrap();
            let (lo, hi) = p.interval.unwrap();
            total += 1;
            held += usize::from(lo <= truth && truth <= hi);
            if !name.contains("cohesion") {
                assert!((p.value - truth).abs() < 0.03 * truth, "seed {seed}, {name}: {} against {truth}", p.value);
            }
        }
    }
    assert!(held * 100 >= 85 * total, "{held} of {total} intervals hold the true value");
}

/// The hyperbolic law (initial slope Ks, asymptote c + σn·tan φ) from the same block: Ks = 20 000
/// kPa/m, c = 15 kPa, φ = 30°, at σn = 25, 50, 100 kPa, 2 % noise (seed 2026); the curves reach 87–95 %
/// of their asymptotes by 25 mm.
#[test]
fn three_direct_shear_curves_give_back_the_hyperbolic_law() {
    let law = ShearLawSpec::Hyperbolic { shear_stiffness: 20_000.0, cohesion: 15.0, friction_angle: 30.0 };
    let dir = tempfile::tempdir().unwrap();
    let spec = calibration_file_of(dir.path(), &measured_csv_of(law, &[25.0, 50.0, 100.0], 2026), "hyperbolic");
    let c = calibration::calibrate(&spec).unwrap_or_else(|e| panic!("{e}"));
    for (name, truth) in [("shear_stiffness", 20_000.0), ("cohesion", 15.0), ("friction_angle", 30.0)] {
        let p = c.parameters.iter().find(|p| p.name == name).unwrap();
        let (lo, hi) = p.interval.unwrap();
        assert!((p.value - truth).abs() < 0.03 * truth, "{name}: {} against {truth}", p.value);
        assert!(lo <= truth && truth <= hi, "{name}: {truth} outside the 95 % interval {lo} … {hi}");
    }
}
