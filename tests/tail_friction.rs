//! Friction to the tail of a reinforcement that ends inside the soil (split mode).
//!
//! Reference: the fully plastic limit of the progressive-slip solution
//! (docs/verification.md §2): once every point of a two-face reinforcement of embedded
//! length L slides under a normal stress σn, it carries P_ult = n_f·τmax·L with τmax = σn·tan φ,
//! and with large slip n_f·τmax·(L − u) once its head has moved u out of the soil. The tail, where
//! both faces meet at one soil node, must count: without it the force is n_f·τmax·(L − h/2 − u).
//!
//! Model: the issue's pull-out box: a 2 m × 1 m weightless elastic block (E = 10 MPa, ν = 0.3),
//! 20 × 10 quad4 (h = 0.1 m), a reinforcement at mid-height from x = 0 to 1.6 m on the soil's nodes
//! (EA = 10⁶ kN/m, nearly rigid), Coulomb faces (Ks = 2000 kPa/m, c = 0, φ = 30°), σn frozen at the 20 kPa
//! surcharge, the head pulled 10 mm in 10 steps.

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;

#[test]
fn a_fully_sliding_two_face_reinforcement_carries_two_tau_l() {
    let mut file = PullOutBox { axial_stiffness: 1.0e6, pull: 0.01, steps: 10, ..common::issue_pullout_box() }.model();
    file.stages[1].freeze_normal_stress = Some(true);
    let model = common::model(&file, "tail-friction.toml");
    let c = common::run(&model, Backend::available()[0]);
    // the tail's points (on both faces) slide under the frozen σn, and report it as the σn used
    let (_, last) = c.steps.last().unwrap();
    let tail_x = last.interface_points.iter().filter(|p| p.face != "slit").map(|p| p.x[0]).fold(f64::MIN, f64::max);
    let tail: Vec<_> = last.interface_points.iter().filter(|p| p.face != "slit" && p.x[0] == tail_x).collect();
    assert_eq!(tail.len(), 2, "the tail's point on each face");
    for p in tail {
        assert!((p.sigma_n - 20.0).abs() < 1e-9, "{} face's tail: σn {} against the frozen 20 kPa", p.face, p.sigma_n);
        let strength = 20.0 * 30f64.to_radians().tan();
        assert!((p.tau.abs() - strength).abs() < 1e-9 * strength, "{} face's tail: τ {}", p.face, p.tau);
        assert!(p.sliding, "{} face's tail slides", p.face);
    }
    let forces = common::head_forces(&model, &c, "grid.head");
    // every point slides once the head has moved past u_y = τmax/Ks = 5.8 mm; the embedded length
    // is then L − u (the large-slip form of §2), u the head's displacement (a nearly rigid bar)
    let tau_max = 20.0 * 30f64.to_radians().tan();
    common::assert_sliding_plateau(&forces, 8, 0.001, 1.6, tau_max, 1e-3);
}

#[test]
fn an_embedded_reinforcement_carries_two_tau_l_to_its_tail() {
    // the same box with the grid embedded in the continuous soil: its tail point has its full
    // tributary length and the soil's σn, so the plateau is the same n_f·τmax·(L − u)
    let mut file = PullOutBox { axial_stiffness: 1.0e6, pull: 0.01, steps: 10, ..common::issue_pullout_box() }.model();
    file.interfaces[0].reinforcement.as_mut().unwrap().mode = geoslip::model::file::ReinforcementMode::Embedded;
    file.stages[1].freeze_normal_stress = Some(true);
    let model = common::model(&file, "tail-friction-embedded.toml");
    let c = common::run(&model, Backend::available()[0]);
    let forces = common::head_forces(&model, &c, "grid.head");
    let tau_max = 20.0 * 30f64.to_radians().tan();
    common::assert_sliding_plateau(&forces, 8, 0.001, 1.6, tau_max, 1e-3);
}
