//! Large slip: a nearly rigid reinforcement pulled out through the front face.
//!
//! Reference: docs/verification.md §2, "Large slip: a bar pulled out through the front
//! face". Once every point slides, only the embedded length L − u resists:
//! P = n_f·τmax·(L − u). A small-slip program stays at n_f·τmax·L, which is wrong.
//!
//! Parameters: L = 1 m, 20 bar elements (h = 0.05 m), EA = 1e6 kN/m ≫ n_f·τmax·L, a cohesive
//! interface τmax = c = 5 kPa with Ks = 2000 kN/m³, rigid fixed soil, pulled 0.5 m in 25 increments
//! of 0.02 m. Checked at u = 0.32 m and 0.46 m, which are not node crossings (6.4 h and 9.2 h): the
//! tributary lengths are clipped to the embedded part, so P falls smoothly rather than in steps of
//! n_f·τmax·h. Goal: within 1 %; the small-slip model must miss by more.
//!
//! ```text
//!      front face
//!   P <--o--o--o--|--o--o--o--o--o--o--o--o       the part left of the face carries nothing
//!                 |///////// rigid soil /////
//! ```

mod common;

use common::slip::{bar_in_rigid_soil, pullout_curve};
use geoslip::linsol::Backend;
use geoslip::model::file::{ReassociationRule, ShearLawSpec};

const TAU: f64 = 5.0;

fn curve(rule: ReassociationRule, backend: Backend) -> Vec<(f64, f64)> {
    let law = ShearLawSpec::Coulomb { shear_stiffness: 2000.0, cohesion: TAU, friction_angle: 0.0 };
    let file = bar_in_rigid_soil(1.0, 20, 1.0e6, law, 0.5, 25, rule);
    let model = common::model(&file, "large-slip.toml");
    let c = common::run(&model, backend);
    for (rec, _) in &c.steps {
        for b in &rec.balance {
            assert!(b.mismatch < 1e-7, "step {}: the interface forces do not balance the pull: {b:?}", rec.step);
        }
    }
    pullout_curve(&model, &c)
}

fn at(curve: &[(f64, f64)], u: f64) -> f64 {
    // the curve is linear between steps once everything slides: interpolate
    let k = curve.iter().position(|&(x, _)| x >= u - 1e-12).expect("the pull reaches u");
    let (u0, p0) = curve[k - 1];
    let (u1, p1) = curve[k];
    p0 + (p1 - p0) * (u - u0) / (u1 - u0)
}

#[test]
fn pullout_force_follows_the_embedded_length() {
    for backend in Backend::available() {
        let c = curve(ReassociationRule::Segment, backend);
        for u in [0.32, 0.46] {
            let exact = 2.0 * TAU * (1.0 - u);
            let p = at(&c, u);
            assert!(((p - exact) / exact).abs() < 0.01, "{backend:?}: P({u}) = {p}, expected {exact}");
        }
    }
}

#[test]
fn mortar_ties_follow_it_as_closely() {
    // segment-to-segment ties average the soil over each point's part of the grid; on a rigid soil
    // they change nothing that the closed form sees
    for backend in Backend::available() {
        let c = curve(ReassociationRule::Mortar, backend);
        for u in [0.32, 0.46] {
            let exact = 2.0 * TAU * (1.0 - u);
            let p = at(&c, u);
            assert!(((p - exact) / exact).abs() < 0.01, "{backend:?}: mortar: P({u}) = {p}, expected {exact}");
        }
    }
}

#[test]
fn the_paper_nearest_node_approximation_also_follows_it_at_the_steps() {
    // nearest-node re-association snaps each tie to a soil node; the resistance still follows the
    // embedded length, with the step-to-step noise of the node snapping
    let c = curve(ReassociationRule::NearestNode, Backend::Faer);
    for u in [0.32, 0.46] {
        let exact = 2.0 * TAU * (1.0 - u);
        let p = at(&c, u);
        assert!(((p - exact) / exact).abs() < 0.05, "nearest node: P({u}) = {p}, expected {exact}");
    }
}

#[test]
fn a_small_slip_model_stays_at_the_full_length_and_fails_this_test() {
    let c = curve(ReassociationRule::None, Backend::Faer);
    for u in [0.32, 0.46] {
        let exact = 2.0 * TAU * (1.0 - u);
        let p = at(&c, u);
        assert!((p - 2.0 * TAU).abs() < 1e-6, "small slip keeps n_f·τ·L, found {p}");
        assert!(((p - exact) / exact).abs() > 0.01, "small slip should miss the large-slip answer");
    }
}
