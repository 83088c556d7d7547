//! A drained triaxial test on a cylindrical sample of Duncan–Chang soil, axisymmetric: loading,
//! unloading, reloading and failure.
//!
//! Reference: the hyperbola of Duncan & Chang (1970) under a constant cell pressure σ3,
//!
//! ```text
//! (σ1 − σ3) = ε1 / (1/Ei + ε1·Rf/(σ1 − σ3)f),   Ei = K·pa·(σ3/pa)^n,
//! (σ1 − σ3)f = (2c·cos φ + 2σ3·sin φ)/(1 − sin φ)
//! ```
//!
//! with ε1 the axial strain since shearing began; unloading and reloading at
//! Eur = Kur·pa·(σ3/pa)^n, Δ(σ1 − σ3) = Eur·Δε1; the volume strain Δεv = Δ(σ1 − σ3)/(3B),
//! B = Kb·pa·(σ3/pa)^m, while B lies within its bounds; and (σ1 − σ3)f once the strain passes
//! (σ1 − σ3)f/(Ei·(1 − Rf)) (docs/verification.md §11). The stress is uniform,
//! so every Gauss point of every element must follow it.
//!
//! ```text
//!   z ↑   q (cell pressure on the top; then the top pushed down, lifted, pushed again)
//!         +--------+
//!   axis  |        | ← q  (cell pressure on the side)
//!         +--------+
//!         ////////// uz = 0
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

/// The cell pressure σ3 [kPa].
const Q: f64 = 100.0;
const RADIUS: f64 = 0.5;
const HEIGHT: f64 = 1.0;
/// Atmospheric pressure in kN and m, the default of a model in those units.
const PA: f64 = 101.325;
const K: f64 = 500.0;
const N: f64 = 0.5;
const RF: f64 = 0.8;
const KB: f64 = 300.0;
const M: f64 = 0.25;
const KUR: f64 = 1200.0;
const C: f64 = 5.0;
const PHI: f64 = 36.0;

/// Axial strain of each shearing stage and its step count: load to 0.012, unload by 0.001 (q from
/// about 234 to 113 kPa), and reload to 0.035, past failure at about 0.030.
const STAGES: [(f64, usize); 3] = [(0.012, 60), (-0.001, 5), (0.024, 120)];

fn triaxial(kind: SolidKind) -> ModelFile {
    let mut sand = SoilMaterial::linear_elastic(1.0, 0.3, 0.0);
    sand.model = SoilModel::DuncanChang;
    (sand.youngs_modulus, sand.poissons_ratio) = (None, None);
    sand.hyperbolic = Some(HyperbolicParameters {
        modulus_number: K,
        n: N,
        failure_ratio: RF,
        bulk_modulus_number: KB,
        m: M,
        unloading_modulus_number: KUR,
        delta_phi: 0.0,
        pa: None,
    });
    sand.cohesion = C;
    sand.friction_angle = PHI;
    let pressure = |set: &str| LoadSpec::EdgeTraction { name: None, edge_set: set.into(), pressure: Q, shear: 0.0 };
    let mut stages = vec![Stage {
        name: "cell pressure".into(),
        load_factors: vec![0.25, 0.5, 0.75, 1.0],
        loads: vec![pressure("side"), pressure("top")],
        ..Default::default()
    }];
    stages.extend(common::shearing_stages(&STAGES, HEIGHT));
    common::triaxial_sample(kind, (RADIUS, HEIGHT), sand, stages, 1e-9)
}

fn follows_the_hyperbola(kind: SolidKind) {
    let model = common::model(&triaxial(kind), "triaxial.toml");
    let ei = K * PA * (Q / PA).powf(N);
    let eur = KUR * PA * (Q / PA).powf(N);
    let bulk = KB * PA * (Q / PA).powf(M);
    let (s, c) = PHI.to_radians().sin_cos();
    let qf = (2.0 * C * c + 2.0 * Q * s) / (1.0 - s);
    let hyperbola = |e: f64| e / (1.0 / ei + e * RF / qf);
    let strain_at = |q: f64| q / (ei * (1.0 - RF * q / qf));
    for backend in Backend::available() {
        let run = common::run(&model, backend);
        let after_cell = run.steps.iter().rev().find(|(r, _)| r.stage_index == 0).unwrap();
        let strain_0 = after_cell.1.stresses(&model)[0].strain;
        let mut worst_volume = 0.0f64;
        // (axial strain since shearing began, q) at each step, the same at every Gauss point
        let mut curve: Vec<(usize, f64, f64)> = Vec::new();
        for (record, step) in run.steps.iter().filter(|(r, _)| r.stage_index > 0) {
            let done: f64 = STAGES[..record.stage_index - 1].iter().map(|s| s.0).sum();
            let axial = done + STAGES[record.stage_index - 1].0 * record.load_factor;
            let q = step.stresses(&model)[0].stress[0] - step.stresses(&model)[0].stress[1];
            for p in step.stresses(&model) {
                let [sr, sz, trz, st] = p.stress;
                assert!((sr - sz - q).abs() < 1e-6 * qf, "{kind:?}/{backend:?}: the stress is not uniform");
                assert!(
                    (sr + Q).abs() < 1e-6 * Q && (st + Q).abs() < 1e-6 * Q && trz.abs() < 1e-6 * Q,
                    "{kind:?}/{backend:?} at {axial}: σr {sr}, σθ {st}, τ {trz}"
                );
                assert_eq!(p.yield_state.is_plastic(), q > qf * (1.0 - 1e-9), "{kind:?}/{backend:?} at {axial}");
                if record.stage_index == 1 {
                    let volume = -(p.strain[0] - strain_0[0]) * 2.0 - (p.strain[1] - strain_0[1]);
                    let expected = q / (3.0 * bulk);
                    worst_volume = worst_volume.max((volume - expected).abs() / expected);
                    assert!(
                        (volume - expected).abs() < 1e-4 * expected,
                        "{kind:?}/{backend:?} at ε1 = {axial:.5}: εv {volume} against {expected}"
                    );
                }
            }
            curve.push((record.stage_index, axial, q));
        }
        let stage = |k: usize| curve.iter().filter(move |c| c.0 == k).map(|c| (c.1, c.2));
        // loading: the hyperbola
        let mut worst = 0.0f64;
        for (e, q) in stage(1) {
            worst = worst.max((q - hyperbola(e)).abs() / qf);
            assert!((q - hyperbola(e)).abs() < 1e-4 * qf, "{kind:?}/{backend:?}: loading at ε1 = {e:.5}: q {q}");
        }
        eprintln!("{kind:?}/{backend:?}: loading's largest error {worst:.1e} of (σ1 − σ3)f, εv's {worst_volume:.1e}");
        // unloading: at Eur once past the band (a drop of the stress state, here of q, by
        // RELOAD_BAND)
        let (top, band) = (hyperbola(STAGES[0].0), geoslip::element::duncan_chang::RELOAD_BAND);
        let unloading: Vec<(f64, f64)> = stage(2).collect();
        let past_band: Vec<(f64, f64)> = unloading.iter().copied().filter(|u| u.1 < (1.0 - band) * top).collect();
        assert!(past_band.len() >= 3);
        for w in past_band.windows(2) {
            let slope = (w[0].1 - w[1].1) / (w[0].0 - w[1].0);
            assert!((slope - eur).abs() < 1e-5 * eur, "{kind:?}/{backend:?}: unloading slope {slope}, Eur {eur}");
        }
        // reloading: at Eur up to the band below where unloading began; past it, the hyperbola
        // again where unloading left it (the path is reversible: along the same stress path the
        // moduli, the band's included, are the same both ways), so with no offset in strain to the
        // integration's error; then failure
        let end = *unloading.last().unwrap();
        let mut offsets = Vec::new();
        for (e, q) in stage(3) {
            if q < (1.0 - band) * top {
                let expected = end.1 + eur * (e - end.0);
                assert!((q - expected).abs() < 1e-6 * qf, "{kind:?}/{backend:?}: reloading at {e:.5}: q {q}");
            } else if q > (1.0 + band) * top && q < 0.99 * qf {
                offsets.push(e - strain_at(q));
            } else if q > qf * (1.0 - 1e-9) {
                assert!((q - qf).abs() < 1e-7 * qf);
            }
        }
        let (lo, hi) = offsets.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &o| (a.min(o), b.max(o)));
        assert!(offsets.len() > 50 && lo > -2e-6 && hi < 2e-6, "{kind:?}/{backend:?}: offsets {lo}..{hi}");
        eprintln!("{kind:?}/{backend:?}: reloaded curve's offset from the hyperbola {lo:.6e}..{hi:.6e}");
        assert!(hi - lo < 6e-7, "{kind:?}/{backend:?}: not the hyperbola: offsets {lo}..{hi}");
        assert!(curve.last().unwrap().2 > qf * (1.0 - 1e-9), "{kind:?}/{backend:?}: no failure");
    }
}

#[test]
fn quad4_sample_follows_the_hyperbola() {
    follows_the_hyperbola(SolidKind::Quad4);
}

#[test]
fn tri6_sample_follows_the_hyperbola() {
    follows_the_hyperbola(SolidKind::Tri6);
}
