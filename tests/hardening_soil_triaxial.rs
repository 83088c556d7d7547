//! A drained triaxial test on a cylindrical sample of hardening soil, axisymmetric: isotropic
//! consolidation to 400 kPa, swelling to 100 kPa, then shearing at 100 kPa with an unloading and a
//! reloading, to failure.
//!
//! Reference: Schanz, Vermeer & Bonnier (1999), the model's definition (docs/verification.md §14):
//! - swelling is elastic at Eur = Eurref·r^m, r = (c·cos φ + σ3·sin φ)/(c·cos φ + pref·sin φ), νur;
//!   under isotropic stress p the volume strain is dεv = 3(1 − 2νur)·dp/Eur, which integrates to
//!   Δεv = 3(1 − 2νur)·R^m/(Eurref·sin φ·(1 − m))·[(c·cos φ + p·sin φ)^(1 − m)] between the pressures,
//!   R = c·cos φ + pref·sin φ;
//! - primary shearing under constant σ3, with the cap shut (the sample was consolidated to four times
//!   the cell pressure), follows the hyperbola ε1 = q/(Ei·(1 − q/qa)), Ei = 2·E50/(2 − Rf),
//!   E50 = E50ref·r^m, qa = qf/Rf, qf = 2(c·cos φ + σ3·sin φ)/(1 − sin φ), with ε1 the axial strain
//!   since shearing began, and with ψ = 0 its volume strain is elastic alone, q·(1 − 2νur)/Eur;
//! - unloading and reloading are elastic at Eur, and reloading rejoins the hyperbola where
//!   unloading left it; past ε1 = qf/(Ei·(1 − Rf)) the deviator stays at qf.
//!
//! The stress is uniform, so every Gauss point of every element must follow it, on every backend.
//!
//! ```text
//!   z ↑   p (cell pressure on the top; then the top pushed down, lifted, pushed again)
//!         +--------+
//!   axis  |        | ← p  (cell pressure on the side)
//!         +--------+
//!         ////////// uz = 0
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

/// Consolidation and cell pressure [kPa].
const CONSOLIDATION: f64 = 400.0;
const CELL: f64 = 100.0;
const RADIUS: f64 = 0.5;
const HEIGHT: f64 = 1.0;
const E50_REF: f64 = 30_000.0;
const EUR_REF: f64 = 90_000.0;
const NU_UR: f64 = 0.2;
const M: f64 = 0.5;
const PREF: f64 = 100.0;
const RF: f64 = 0.9;
const C: f64 = 5.0;
const PHI: f64 = 35.0;

/// Axial strain of each shearing stage and its step count: load to 0.004 (q about 165 of its
/// strength 288 kPa), unload by 0.0005, reload to 0.06, past failure at about 0.053.
const SHEARING: [(f64, usize); 3] = [(0.004, 40), (-0.0005, 5), (0.0565, 150)];

fn triaxial(kind: SolidKind) -> ModelFile {
    let mut sand = SoilMaterial::linear_elastic(1.0, 0.3, 0.0);
    sand.model = SoilModel::HardeningSoil;
    (sand.youngs_modulus, sand.poissons_ratio) = (None, None);
    sand.hardening = Some(HardeningSoilParameters {
        secant_modulus: E50_REF,
        oedometer_modulus: None,
        unloading_modulus: Some(EUR_REF),
        m: M,
        p_ref: Some(PREF),
        nu_ur: Some(NU_UR),
        failure_ratio: Some(RF),
        k0_nc: None,
    });
    sand.cohesion = C;
    sand.friction_angle = PHI;
    let pressure =
        |set: &str, p: f64| LoadSpec::EdgeTraction { name: None, edge_set: set.into(), pressure: p, shear: 0.0 };
    let mut stages = vec![
        Stage {
            name: "consolidation".into(),
            load_factors: (1..=10).map(|i| i as f64 / 10.0).collect(),
            loads: vec![pressure("side", CONSOLIDATION), pressure("top", CONSOLIDATION)],
            ..Default::default()
        },
        Stage {
            name: "swelling".into(),
            load_factors: (1..=6).map(|i| i as f64 / 6.0).collect(),
            loads: vec![pressure("side", CELL - CONSOLIDATION), pressure("top", CELL - CONSOLIDATION)],
            ..Default::default()
        },
    ];
    stages.extend(common::shearing_stages(&SHEARING, HEIGHT));
    common::triaxial_sample(kind, (RADIUS, HEIGHT), sand, stages, 1e-9)
}

fn follows_the_model(kind: SolidKind, backends: &[Backend]) {
    let model = common::model(&triaxial(kind), "triaxial.toml");
    let (sin, cos) = PHI.to_radians().sin_cos();
    let reference = C * cos + PREF * sin;
    let r = |sigma_3: f64| (C * cos + sigma_3 * sin) / reference;
    let eur = EUR_REF * r(CELL).powf(M);
    let ei = 2.0 * E50_REF * r(CELL).powf(M) / (2.0 - RF);
    let qf = 2.0 * (C * cos + CELL * sin) / (1.0 - sin);
    let qa = qf / RF;
    // the deviator on the hyperbola at axial strain e
    let hyperbola = |e: f64| e * ei * qa / (qa + e * ei);
    let at_failure = qf / (ei * (1.0 - RF));
    // swelling: the volume strain between the two pressures
    let integral = |p: f64| (C * cos + p * sin).powf(1.0 - M);
    let swelling = 3.0 * (1.0 - 2.0 * NU_UR) * reference.powf(M) / (EUR_REF * sin * (1.0 - M))
        * (integral(CONSOLIDATION) - integral(CELL));
    for &backend in backends {
        let run = common::run(&model, backend);
        let last_of = |stage: usize| &run.steps.iter().rev().find(|(r, _)| r.stage_index == stage).unwrap().1;
        let volume = |strain: [f64; 3]| -(strain[0] * 2.0 + strain[1]);
        let (consolidated, swollen) = (last_of(0), last_of(1));
        let measured = volume(consolidated.stresses(&model)[0].strain) - volume(swollen.stresses(&model)[0].strain);
        assert!(
            (measured - swelling).abs() < 1e-5 * swelling,
            "{kind:?}/{backend:?}: swelling εv {measured} against {swelling}"
        );
        let strain_0 = swollen.stresses(&model)[0].strain;
        let (mut worst, mut worst_volume) = (0.0f64, 0.0f64);
        let mut curve: Vec<(usize, f64, f64)> = Vec::new();
        for (record, step) in run.steps.iter().filter(|(r, _)| r.stage_index > 1) {
            let shear = record.stage_index - 2;
            let done: f64 = SHEARING[..shear].iter().map(|s| s.0).sum();
            let axial = done + SHEARING[shear].0 * record.load_factor;
            let q = step.stresses(&model)[0].stress[0] - step.stresses(&model)[0].stress[1];
            for p in step.stresses(&model) {
                let [sr, sz, trz, st] = p.stress;
                assert!((sr - sz - q).abs() < 1e-6 * qf, "{kind:?}/{backend:?}: the stress is not uniform");
                assert!(
                    (sr + CELL).abs() < 1e-6 * CELL && (st + CELL).abs() < 1e-6 * CELL && trz.abs() < 1e-6 * CELL,
                    "{kind:?}/{backend:?} at {axial}: σr {sr}, σθ {st}, τ {trz}"
                );
                if shear == 0 {
                    let volume = volume(p.strain) - volume(strain_0);
                    let expected = q * (1.0 - 2.0 * NU_UR) / eur;
                    worst_volume = worst_volume.max((volume - expected).abs() / axial);
                    assert!(
                        (volume - expected).abs() < 1e-4 * axial,
                        "{kind:?}/{backend:?} at ε1 = {axial:.5}: εv {volume} against {expected}"
                    );
                }
            }
            curve.push((shear, axial, q));
        }
        let stage = |k: usize| curve.iter().filter(move |c| c.0 == k).map(|c| (c.1, c.2));
        // primary loading: the hyperbola
        for (e, q) in stage(0) {
            worst = worst.max((q - hyperbola(e)).abs() / qf);
            assert!((q - hyperbola(e)).abs() < 1e-4 * qf, "{kind:?}/{backend:?}: loading at ε1 = {e:.5}: q {q}");
        }
        // unloading at Eur
        let top = stage(0).last().unwrap();
        let mut previous = top;
        for (e, q) in stage(1) {
            let slope = (previous.1 - q) / (previous.0 - e);
            assert!((slope - eur).abs() < 1e-5 * eur, "{kind:?}/{backend:?}: unloading slope {slope}, Eur {eur}");
            previous = (e, q);
        }
        // reloading: at Eur back to where unloading began, then the hyperbola itself, then failure
        for (e, q) in stage(2) {
            let expected = if e <= top.0 {
                top.1 + eur * (e - top.0)
            } else if e < at_failure {
                hyperbola(e)
            } else {
                qf
            };
            worst = worst.max((q - expected).abs() / qf);
            assert!(
                (q - expected).abs() < 1e-4 * qf,
                "{kind:?}/{backend:?}: reloading at ε1 = {e:.5}: q {q} against {expected}"
            );
        }
        assert!(curve.last().unwrap().2 > qf * (1.0 - 1e-9), "{kind:?}/{backend:?}: no failure");
        eprintln!("{kind:?}/{backend:?}: largest error of q {worst:.1e} of qf, of εv {worst_volume:.1e} of ε1");
    }
}

#[test]
fn quad4_sample_follows_the_model() {
    follows_the_model(SolidKind::Quad4, &Backend::available());
}

#[test]
fn tri6_sample_follows_the_model() {
    // one backend: the linear solvers are compared on quad4
    follows_the_model(SolidKind::Tri6, &[Backend::Faer]);
}
