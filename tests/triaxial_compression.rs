//! A drained triaxial compression test on a cylindrical Mohr–Coulomb sample, axisymmetric.
//!
//! Reference: the Mohr–Coulomb criterion in principal stresses (e.g. Wood, Soil Behaviour and
//! Critical State Soil Mechanics, 1990, §3; compression positive here for the magnitudes): with the
//! cell pressure σ3 = σr = σθ = q, the sample fails at σ1 = q·Nφ + 2c·√Nφ, Nφ = (1 + sin φ)/(1 − sin φ).
//! Triaxial compression lies on an edge of the Mohr–Coulomb pyramid (σ2 = σ3: the radial and the hoop
//! stress), so this checks the hoop stress as a principal stress of the return map and the 4 × 4
//! consistent tangent under Newton's method. The stress state is uniform: every Gauss point of every
//! element type must reach it to 1e-6 of q.
//!
//! ```text
//!   z ↑   q (cell pressure on the top, stage 1; then the top pushed down, stage 2)
//!         +--------+
//!   axis  |        | ← q  (cell pressure on the side)
//!         +--------+
//!         ////////// uz = 0
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

const Q: f64 = 100.0;
const C: f64 = 10.0;
const PHI: f64 = 30.0;
const RADIUS: f64 = 0.5;
const HEIGHT: f64 = 1.0;

fn triaxial(kind: SolidKind) -> ModelFile {
    let mut sand = SoilMaterial::linear_elastic(2.0e4, 0.3, 0.0);
    sand.model = SoilModel::MohrCoulomb;
    sand.cohesion = C;
    sand.friction_angle = PHI;
    sand.dilatancy_angle = PHI;
    let pressure = |set: &str| LoadSpec::EdgeTraction { name: None, edge_set: set.into(), pressure: Q, shear: 0.0 };
    let stages = vec![
        Stage {
            name: "cell pressure".into(),
            load_factors: vec![1.0],
            loads: vec![pressure("side"), pressure("top")],
            ..Default::default()
        },
        Stage {
            name: "compression".into(),
            load_factors: (1..=20).map(|k| k as f64 / 20.0).collect(),
            prescribed: vec![common::prescribed("top", None, Some(-0.03))],
            ..Default::default()
        },
    ];
    common::triaxial_sample(kind, (RADIUS, HEIGHT), sand, stages, 1e-9)
}

fn fails_at_the_mohr_coulomb_deviator(kind: SolidKind) {
    let model = common::model(&triaxial(kind), "triaxial.toml");
    let sin = PHI.to_radians().sin();
    let n_phi = (1.0 + sin) / (1.0 - sin);
    let sigma_1 = Q * n_phi + 2.0 * C * n_phi.sqrt();
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        // after the cell pressure: isotropic q everywhere
        for s in c.steps[0].1.stresses(&model) {
            for k in [0, 1, 3] {
                assert!((s.stress[k] + Q).abs() < 1e-6 * Q, "{kind:?}/{backend:?}: cell pressure {:?}", s.stress);
            }
        }
        let last = &c.last().unwrap();
        for s in last.stresses(&model) {
            let [sr, sz, trz, st] = s.stress;
            assert!((sr + Q).abs() < 1e-6 * Q && (st + Q).abs() < 1e-6 * Q, "{kind:?}/{backend:?}: σr {sr}, σθ {st}");
            assert!((sz + sigma_1).abs() < 1e-6 * Q, "{kind:?}/{backend:?}: σz {sz} against −{sigma_1}");
            assert!(trz.abs() < 1e-6 * Q);
        }
        assert!(
            last.stresses(&model).iter().all(|s| s.yield_state.is_plastic()),
            "{kind:?}/{backend:?}: not every point yields"
        );
    }
}

#[test]
fn quad4_sample_fails_at_the_mohr_coulomb_deviator() {
    fails_at_the_mohr_coulomb_deviator(SolidKind::Quad4);
}

#[test]
fn quad8_sample_fails_at_the_mohr_coulomb_deviator() {
    fails_at_the_mohr_coulomb_deviator(SolidKind::Quad8);
}

#[test]
fn tri6_sample_fails_at_the_mohr_coulomb_deviator() {
    fails_at_the_mohr_coulomb_deviator(SolidKind::Tri6);
}
