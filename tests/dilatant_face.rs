//! Dilatancy on the multiplier: a soil column sliding on a rigid base whose face dilates.
//!
//! Reference: docs/verification.md §9: one-dimensional confined compression of a linear elastic column (plane strain, no
//! lateral strain): σ_yy changes by M·Δε_yy, M = E(1 − ν)/((1 + ν)(1 − 2ν)) the confined modulus.
//! The face's tie holds the column's base above the base plate by the dilation d = tan ψ·κ (κ the
//! plastic slip), up to d_max. With the lid held after the surcharge q, the column (height H) is
//! shortened by d, and
//!
//! ```text
//! σn = q + M·d/H,   d = min(tan ψ·κ, d_max),   κ = s − τ/Ks (sliding),   τ = σn·tan φ
//! ⇒ κ = (s − q·tan φ/Ks) / (1 + M·tan ψ·tan φ/(H·Ks))   while tan ψ·κ < d_max,
//! ```
//!
//! s the slip; before sliding (s ≤ q·tan φ/Ks) κ = 0 and σn = q. With the lid free, the column
//! rises by d and σn stays q.
//!
//! Model: `meshgen::block_on_rigid_base` (a 1 m × 0.5 m block of 4 × 2 quad4, E = 10 MPa, ν = 0.3,
//! weightless, every node's ux prescribed, on a rigid base by a slave/master pair) with a Coulomb face
//! (Ks = 10 000 kPa/m, c = 0, φ = 30°), ψ = 10°, d_max = 2 mm, q = 50 kPa; the block slides 20 mm in 40
//! steps. Goal: σn at every point to 1e-6 of the closed form at every step, on the dense reference
//! and faer (both iteration schemes), with the lid held; the cap reached and held; with the lid free, σn = q and the block
//! lifted by d.
//!
//! With the lid free σn stays q whatever the law, so the lift is d = min(tan ψ·κ, d_max) with κ the
//! law's own plastic slip: for peak-residual, τ = τp = q·tan φ up to the peak slip q·tan φ/Ks and
//! τr = q·tan φr after it, so κ = s − τr/Ks once past the peak; for softening (the strength falling
//! linearly from τp to τr over κs of plastic slip) κ = (s − τp/Ks)/(1 − (τp − τr)/(κs·Ks)) until
//! κ = κs, then s − τr/Ks. Through a reversal (Coulomb, out to +a and back to 0) the plastic slip of
//! both directions adds: κ = (a − τp/Ks) + (a − s − 2τp/Ks) once sliding back, κ from either
//! direction counted (docs/model-format.md).

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::block_on_rigid_base;
use geoslip::model::file::{DilationSpec, ShearLawSpec};
use geoslip::model::Scheme;

const Q: f64 = 50.0;
const E: f64 = 1.0e4;
const NU: f64 = 0.3;
const H: f64 = 0.5;
const KS: f64 = 1.0e4;
const PHI: f64 = 30.0;
const PSI: f64 = 10.0;
const D_MAX: f64 = 0.002;
const SLIDE: f64 = 0.02;
const STEPS: usize = 40;

fn confined_modulus() -> f64 {
    E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU))
}

/// σn and the dilation at slip s with the lid held.
fn held_lid(s: f64) -> (f64, f64) {
    let (tan_phi, tan_psi, m) = (PHI.to_radians().tan(), PSI.to_radians().tan(), confined_modulus());
    let start = Q * tan_phi / KS;
    if s <= start {
        return (Q, 0.0);
    }
    let kappa = (s - start) / (1.0 + m * tan_psi * tan_phi / (H * KS));
    let d = (tan_psi * kappa).min(D_MAX);
    (Q + m * d / H, d)
}

fn model(lid_held: bool, scheme: Scheme) -> geoslip::model::Model {
    let law = ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: 0.0, friction_angle: PHI };
    let factors = (1..=STEPS).map(|k| k as f64 / STEPS as f64).collect();
    let mut file = block_on_rigid_base(law, Q, SLIDE, factors);
    file.interfaces[0].dilation = Some(DilationSpec { angle: PSI, max_dilation: D_MAX });
    if lid_held {
        let lid: Vec<u64> = file.nodes.iter().filter(|n| (n.2 - H).abs() < 1e-12).map(|n| n.0).collect();
        assert_eq!(lid.len(), 5);
        file.node_sets.insert("lid".into(), lid);
        file.stages[1].prescribed.push(common::prescribed("lid", None, Some(0.0)));
    }
    file.analysis.scheme = scheme;
    common::model(&file, "dilatant-block")
}

/// Each step of the sliding stage: (slip, the points' σn, the points' dilation, the lid's uy).
fn sliding_steps(c: &geoslip::analysis::Collect) -> Vec<(f64, Vec<f64>, Vec<f64>, f64)> {
    c.steps
        .iter()
        .filter(|(r, _)| r.stage_index == 1)
        .map(|(r, s)| {
            let points: Vec<_> = s.interface_points.iter().filter(|p| p.tributary > 0.0).collect();
            let lid = s.displacements.iter().find(|d| (d.1[1] - H).abs() < 1e-12).map(|d| d.2[1]).unwrap();
            (
                SLIDE * r.load_factor,
                points.iter().map(|p| p.sigma_n).collect(),
                points.iter().map(|p| p.dilation).collect(),
                lid,
            )
        })
        .collect()
}

#[test]
fn with_the_lid_held_the_normal_stress_rises_by_the_columns_confined_modulus() {
    for (backend, scheme) in [
        (Backend::Dense, Scheme::ConstantStiffness),
        (Backend::Faer, Scheme::ConstantStiffness),
        (Backend::Faer, Scheme::Newton),
    ] {
        let model = model(true, scheme);
        let c = common::run(&model, backend);
        let steps = sliding_steps(&c);
        assert_eq!(steps.len(), STEPS);
        let mut capped = 0;
        for (s, sigma, dilation, _) in &steps {
            let (expected, d) = held_lid(*s);
            for (sn, dl) in sigma.iter().zip(dilation) {
                assert!(
                    common::relative_error(*sn, expected) < 1e-6,
                    "{backend:?} at s = {s}: σn {sn} against {expected}"
                );
                assert!((dl - d).abs() < 1e-9, "{backend:?} at s = {s}: dilation {dl} against {d}");
            }
            if d == D_MAX {
                capped += 1;
            }
        }
        // the cap is reached (at κ = 11.3 mm) and σn stops rising there
        assert!(capped >= 5, "{backend:?}: {capped} steps at the largest dilation");
        let top = Q + confined_modulus() * D_MAX / H;
        assert!(common::relative_error(steps.last().unwrap().1[0], top) < 1e-6);
    }
}

#[test]
fn with_the_lid_free_the_normal_stress_stays_the_surcharge_and_the_column_rises() {
    let model = model(false, Scheme::ConstantStiffness);
    let c = common::run(&model, Backend::Faer);
    let steps = sliding_steps(&c);
    let before = c.steps.iter().find(|(r, _)| r.stage_index == 0).map(|(_, s)| s).unwrap();
    let lid_before = before.displacements.iter().find(|d| (d.1[1] - H).abs() < 1e-12).map(|d| d.2[1]).unwrap();
    let tan_psi = PSI.to_radians().tan();
    let tan_phi = PHI.to_radians().tan();
    for (s, sigma, dilation, lid) in &steps {
        for sn in sigma {
            assert!(common::relative_error(*sn, Q) < 1e-9, "at s = {s}: σn {sn}");
        }
        // σn = q: κ = s − q·tan φ/Ks once sliding
        let d = (tan_psi * (s - Q * tan_phi / KS).max(0.0)).min(D_MAX);
        assert!((dilation[0] - d).abs() < 1e-9, "at s = {s}: dilation {} against {d}", dilation[0]);
        assert!((lid - lid_before - d).abs() < 1e-9, "at s = {s}: the lid rose {} against {d}", lid - lid_before);
    }
}

/// The lid-free block's lift at every step of a run of `law` (the block's lid before sliding as
/// the datum) against `expected(s)`, with `history` the stage's factors of `SLIDE` (or `None`:
/// 40 equal steps out).
fn lift_follows(law: ShearLawSpec, history: Option<Vec<[f64; 2]>>, d_max: f64, expected: impl Fn(usize, f64) -> f64) {
    let mut file = block_on_rigid_base(law.clone(), Q, SLIDE, (1..=STEPS).map(|k| k as f64 / STEPS as f64).collect());
    file.interfaces[0].dilation = Some(DilationSpec { angle: PSI, max_dilation: d_max });
    if let Some(h) = history {
        file.stages[1].load_factors = vec![1.0];
        file.stages[1].history = Some(h);
        file.stages[1].history_increment = Some(0.025);
    }
    file.analysis.scheme = Scheme::Newton;
    let model = common::model(&file, "dilatant-block");
    let c = common::run(&model, Backend::Faer);
    let before = c.steps.iter().find(|(r, _)| r.stage_index == 0).map(|(_, s)| s).unwrap();
    let lid_before = before.displacements.iter().find(|d| (d.1[1] - H).abs() < 1e-12).map(|d| d.2[1]).unwrap();
    let mut branch = 0;
    let mut largest: f64 = 0.0;
    for (k, (s, sigma, dilation, lid)) in sliding_steps(&c).into_iter().enumerate() {
        let d = expected(branch, s);
        for sn in &sigma {
            assert!(common::relative_error(*sn, Q) < 1e-9, "{law:?} at s = {s}: σn {sn}");
        }
        assert!((dilation[0] - d).abs() < 1e-9, "{law:?} at s = {s}: dilation {} against {d}", dilation[0]);
        assert!(
            (lid - lid_before - d).abs() < 1e-9,
            "{law:?} at s = {s}: the lid rose {} against {d}",
            lid - lid_before
        );
        largest = largest.max(d);
        if c.steps.iter().filter(|(r, _)| r.stage_index == 1).nth(k).is_some_and(|(r, _)| r.reversal) {
            branch += 1;
        }
    }
    assert!(largest > 0.5 * d_max.min(0.002), "{law:?}: the face dilated only {largest}");
}

#[test]
fn with_the_lid_free_a_peak_residual_face_dilates_by_its_own_plastic_slip() {
    let law = ShearLawSpec::PeakResidual {
        shear_stiffness: KS,
        cohesion: 0.0,
        friction_angle: PHI,
        residual_cohesion: 0.0,
        residual_friction_angle: 20.0,
    };
    let (tp, tr) = (Q * PHI.to_radians().tan(), Q * 20f64.to_radians().tan());
    let tan_psi = PSI.to_radians().tan();
    lift_follows(law, None, 0.01, |_, s| if s <= tp / KS { 0.0 } else { (tan_psi * (s - tr / KS)).min(0.01) });
}

#[test]
fn with_the_lid_free_a_softening_face_dilates_by_its_own_plastic_slip() {
    let kappa_s = 0.005;
    let law = ShearLawSpec::Softening {
        shear_stiffness: KS,
        cohesion: 0.0,
        friction_angle: PHI,
        residual_cohesion: 0.0,
        residual_friction_angle: 20.0,
        softening_slip: kappa_s,
    };
    let (tp, tr) = (Q * PHI.to_radians().tan(), Q * 20f64.to_radians().tan());
    let tan_psi = PSI.to_radians().tan();
    lift_follows(law, None, 0.01, |_, s| {
        if s <= tp / KS {
            return 0.0;
        }
        let kappa = (s - tp / KS) / (1.0 - (tp - tr) / (kappa_s * KS));
        let kappa = if kappa < kappa_s { kappa } else { s - tr / KS };
        (tan_psi * kappa).min(0.01)
    });
}

#[test]
fn through_a_reversal_the_plastic_slip_of_both_directions_dilates() {
    // out to +10 mm (factor 0.5 of SLIDE), back to 0
    let law = ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: 0.0, friction_angle: PHI };
    let a = 0.5 * SLIDE;
    let tp = Q * PHI.to_radians().tan();
    let tan_psi = PSI.to_radians().tan();
    lift_follows(law, Some(vec![[1.0, 0.5], [2.0, 0.0]]), 0.01, |branch, s| {
        let out = if branch == 0 { (s - tp / KS).max(0.0) } else { a - tp / KS };
        let back = if branch == 0 { 0.0 } else { (a - s - 2.0 * tp / KS).max(0.0) };
        (tan_psi * (out + back)).min(0.01)
    });
}
