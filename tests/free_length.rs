//! A reinforcement drawn from a grip in front of the soil: its free length touches no soil, and its
//! embedded length is exact at the face.
//!
//! Reference: docs/verification.md §2, large slip: once every embedded point slides under a normal
//! stress σn, a two-face reinforcement carries n_f·τmax·(L − u), L its embedded length and u the
//! slip (a nearly rigid bar: the head's displacement), τmax = σn·tan φ; the free length in front of
//! the face adds nothing. Pulled on until its tail passes the face, it carries n_f·τmax·(L − u)
//! while that is positive, and nothing once it is out.
//!
//! Model: the pull-out box of issue #16 (2 m × 1 m weightless block, 20 × 10 quad4, h = 0.1 m,
//! Coulomb faces Ks = 2000 kPa/m, φ = 30°, σn frozen at the 20 kPa surcharge in the pull-out stage),
//! a nearly rigid grid (EA = 10⁶ kN/m) with a free length of 0.15 m in front of the face.

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::ModelFile;

fn gripped_box(embedded: f64, pull: f64, steps: usize) -> ModelFile {
    let mut file = PullOutBox { embedded, axial_stiffness: 1.0e6, pull, steps, ..common::issue_pullout_box() }.model();
    file.stages[1].freeze_normal_stress = Some(true);
    let r = file.interfaces[0].reinforcement.as_mut().unwrap();
    r.free_length = Some(0.15);
    file
}

#[test]
fn the_free_length_adds_nothing_and_the_embedded_length_is_exact_at_the_face() {
    let model = common::model(&gripped_box(1.6, 0.01, 10), "free-length.toml");
    // the head is the grip, 0.15 m in front of the face
    let head = model.node_sets["grid.head"][0];
    assert!((model.mesh.position(head)[0] + 0.15).abs() < 1e-12, "head at {:?}", model.mesh.position(head));
    let c = common::run(&model, Backend::available()[0]);
    let forces = common::head_forces(&model, &c, "grid.head");
    let tau_max = 20.0 * 30f64.to_radians().tan();
    // measured 2.2e-5 above: the grid's stretch (EA = 10⁶ kN/m) between the head and the face
    common::assert_sliding_plateau(&forces, 8, 0.001, 1.6, tau_max, 1e-4);
    // the free length's points touch nothing
    let (_, last) = c.steps.last().unwrap();
    for p in last.interface_points.iter().filter(|p| p.face != "slit" && p.x[0] < -1e-9) {
        assert!(p.state == "outside" || p.state == "held", "node {} at x = {}: {}", p.slave_node, p.x[0], p.state);
        assert_eq!(p.tau, 0.0);
    }
}

#[test]
fn pulled_through_the_face_it_loses_contact_point_by_point() {
    // 0.3 m embedded (three elements), pulled 0.4 m in 40 steps
    let model = common::model(&gripped_box(0.3, 0.4, 40), "free-length-out.toml");
    let c = common::run(&model, Backend::available()[0]);
    let forces = common::head_forces(&model, &c, "grid.head");
    let tau_max = 20.0 * 30f64.to_radians().tan();
    let mut contact_before = usize::MAX; // points facing the soil in the step before
    for (k, ((_, step), &force)) in c.steps.iter().skip(1).zip(&forces).enumerate() {
        let u = 0.01 * (k + 1) as f64;
        let bound = 2.0 * tau_max * (0.3 - u).max(0.0);
        // exact while every embedded point stays pressed (the first 5 cm); later the normal
        // multipliers of points between soil nodes oscillate and one may open, so the force is
        // bounded by the closed form, not equal to it (issue #16, item 4); the tolerance covers the
        // grid's stretch between the grip and the face (u there is the head's less F·0.15/EA)
        let tolerance = 1e-4 * 2.0 * tau_max * 0.3;
        assert!(force <= bound + tolerance, "step {}: force {force} kN/m above n_f·τmax·(L − u) = {bound}", k + 1);
        // and from below: where a point between soil nodes opens, the force falls short by at
        // most 17 % (measured at u = 0.06 m); between such steps it is the closed form again
        assert!(force >= 0.8 * bound - tolerance, "step {}: force {force} kN/m below 0.8 of {bound}", k + 1);
        if u <= 0.05 {
            assert!((force - bound).abs() <= tolerance, "step {}: force {force} kN/m against {bound}", k + 1);
        }
        // the points still facing the soil (some tributary length inside it)
        let facing = step.interface_points.iter().filter(|p| p.face != "slit" && p.tributary > 0.0).count();
        assert!(facing <= contact_before, "step {}: {facing} points face the soil, {contact_before} before", k + 1);
        contact_before = facing;
    }
    assert_eq!(contact_before, 0, "out of the soil, no point faces it");
    assert!(forces.last().unwrap().abs() < 1e-9, "no force once out: {}", forces.last().unwrap());
}

#[test]
fn a_free_length_that_is_not_a_positive_length_is_refused_by_name() {
    for bad in [-0.1, 0.0, f64::NAN, 1.0e9] {
        let mut file = gripped_box(1.6, 0.01, 1);
        file.interfaces[0].reinforcement.as_mut().unwrap().free_length = Some(bad);
        let error = geoslip::model::Model::from_file(std::path::Path::new("bad.toml"), &file).unwrap_err().to_string();
        assert!(error.contains("free_length") && error.contains("grid"), "{bad}: {error}");
    }
}

#[test]
fn embedded_and_pulled_through_the_face_it_follows_the_closed_form_to_the_end() {
    // the same grip and pull with the grid embedded in the continuous soil: its rows never open,
    // so the force is n_f·τmax·(L − u) at every step until the tail leaves the soil
    let mut file = gripped_box(0.3, 0.4, 40);
    file.interfaces[0].reinforcement.as_mut().unwrap().mode = geoslip::model::file::ReinforcementMode::Embedded;
    let model = common::model(&file, "free-length-embedded.toml");
    let c = common::run(&model, Backend::available()[0]);
    let forces = common::head_forces(&model, &c, "grid.head");
    let tau_max = 20.0 * 30f64.to_radians().tan();
    let tolerance = 1e-4 * 2.0 * tau_max * 0.3;
    for (k, &force) in forces.iter().enumerate() {
        let u = 0.01 * (k + 1) as f64;
        let exact = 2.0 * tau_max * (0.3 - u).max(0.0);
        assert!((force - exact).abs() <= tolerance, "step {}: force {force} kN/m against {exact}", k + 1);
    }
    let (_, last) = c.steps.last().unwrap();
    assert!(last.interface_points.iter().all(|p| p.tributary == 0.0 && p.tau == 0.0), "out of the soil");
}
