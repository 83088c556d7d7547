//! Elastic shear-lag pull-out of a reinforcement on a rigid bed.
//!
//! Reference: docs/verification.md §1 (the shear-lag solution of a bar on elastic
//! springs, e.g. Abramento & Whittle 1995; Chan, Yi & Scott 1993 use the same Ks idealisation):
//! T(x) = P·sinh(α(L−x))/sinh(αL), u(x) = P·cosh(α(L−x))/(EA·α·sinh αL), α = sqrt(n_f·Ks/EA),
//! head stiffness K = EA·α·tanh(αL).
//!
//! Parameters (the reference's example): EA = 1000 kN/m, Ks = 2000 kN/m³ per face, L = 1 m,
//! P = 10 kN/m, n_f = 2 → α = 2, αL = 2, K = 1928.055 kN/m/m; 20 bar elements (expected
//! discretisation error +0.12 %); test tolerance 0.5 %. The closed form keeps the embedded length
//! fixed, so the model runs small-slip (`reassociation = "none"`).
//!
//! ```text
//!   fixed soil  ////////////////////////////   upper face (Ks)
//!   P <-- o----o----o----o-- … --o----o        reinforcement, 20 bars, head at x = 0
//!   fixed soil  ////////////////////////////   lower face (Ks)
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

const EA: f64 = 1000.0;
const KS: f64 = 2000.0;
const L: f64 = 1.0;
const P: f64 = 10.0;
const ALPHA: f64 = 2.0;

fn exact_head_stiffness() -> f64 {
    EA * ALPHA * (ALPHA * L).tanh()
}

fn bar_on_rigid_bed(control: &str) -> ModelFile {
    // 20 bars of EA through a fixed soil block; the closed form holds the embedded length fixed:
    // small slip, no re-association
    let law = ShearLawSpec::Linear { shear_stiffness: KS };
    let mut file = common::slip::bar_in_rigid_soil(L, 20, EA, law, 0.0, 1, ReassociationRule::None);
    let head = Some("grid.head".to_string());
    let stage = &mut file.stages[0];
    if control == "load" {
        stage.prescribed.clear();
        stage.loads = vec![LoadSpec::Point { node: None, nodes: None, set: head, fx: -P, fy: 0.0 }];
    } else {
        stage.prescribed[0].ux = Some(-P / exact_head_stiffness());
    }
    file
}

fn head_and_tail(c: &geoslip::analysis::Collect, model: &geoslip::model::Model) -> (f64, f64) {
    let bars = &model.node_sets["grid.reinforcement"];
    let head = model.mesh.node_id(bars[0]);
    let tail = model.mesh.node_id(*bars.last().unwrap());
    (common::displacement(c, head)[0], common::displacement(c, tail)[0])
}

/// The head stiffness within 0.5 % of the closed form (and, as expected of lumped nodal springs,
/// slightly stiffer: +0.12 % at 20 elements), the tail's displacement within 1 %.
fn assert_head_and_tail(c: &geoslip::analysis::Collect, model: &geoslip::model::Model, backend: Backend) {
    let (u_head, u_tail) = head_and_tail(c, model);
    let k = P / -u_head;
    let err = (k - exact_head_stiffness()) / exact_head_stiffness();
    assert!(err.abs() < 0.005, "{backend:?}: K = {k}, error {err}");
    assert!(err > 0.0 && err < 0.002, "{backend:?}: error {err} outside the expected +0.12 %");
    // u_tail = P/(EA·α·sinh αL) = 1.37860 mm
    let exact_tail = P / (EA * ALPHA * (ALPHA * L).sinh());
    assert!(common::relative_error(-u_tail, exact_tail) < 0.01, "{backend:?}: u_tail {u_tail}");
}

#[test]
fn head_stiffness_under_load_control_within_half_a_percent() {
    let model = common::model(&bar_on_rigid_bed("load"), "shear-lag.toml");
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        assert_head_and_tail(&c, &model, backend);

        let r = c.last().unwrap();
        // T(0.5) = P·sinh(1)/sinh(2) = 3.24027: the bars either side of x = 0.5
        let t_mid: Vec<f64> =
            r.bar_forces.iter().filter(|b| (b.midpoint[0] - 0.5).abs() < 0.03).map(|b| b.axial_force).collect();
        assert_eq!(t_mid.len(), 2);
        let t = 0.5 * (t_mid[0] + t_mid[1]);
        assert!(common::relative_error(t, P * 1f64.sinh() / 2f64.sinh()) < 0.01, "T(0.5) = {t}");

        // Equilibrium: the shear transferred over both faces balances the pull.
        let shear: f64 = r.interface_points.iter().filter(|p| p.face != "slit").map(|p| p.tau * p.tributary).sum();
        assert!((shear - P).abs() < 1e-9 * P, "interface shear {shear} vs pull {P}");
        // τ = Ks·slip on each face, slip positive towards the head
        assert!(r
            .interface_points
            .iter()
            .filter(|p| p.face != "slit")
            .all(|p| p.slip > 0.0 && (p.tau - KS * p.slip).abs() < 1e-9));
    }
}

#[test]
fn head_stiffness_under_displacement_control_within_half_a_percent() {
    let model = common::model(&bar_on_rigid_bed("displacement"), "shear-lag.toml");
    let c = common::run(&model, Backend::Faer);
    let r = c.last().unwrap();
    let head = model.node_sets["grid.head"][0];
    let reaction = r.reaction_vector[2 * head];
    let u = P / exact_head_stiffness();
    // the head's reaction is the pull-out force, pointing out of the soil (−x)
    let k = -reaction / u;
    assert!(common::relative_error(k, exact_head_stiffness()) < 0.005, "K = {k}");
}

#[test]
fn embedded_reinforcement_meets_the_same_closed_form() {
    // the same bar tied into the fixed soil without splitting it: one embedded face standing for
    // both (n_f = 2), so α and the head stiffness are the same
    let mut file = bar_on_rigid_bed("load");
    file.interfaces[0].reinforcement.as_mut().unwrap().mode = ReinforcementMode::Embedded;
    let model = common::model(&file, "shear-lag-embedded.toml");
    assert_eq!(model.interfaces.len(), 1, "no slit: the soil is not split");
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        assert_head_and_tail(&c, &model, backend);
        let r = c.last().unwrap();
        let shear: f64 = r.interface_points.iter().map(|p| 2.0 * p.tau * p.tributary).sum();
        assert!((shear - P).abs() < 1e-9 * P, "{backend:?}: both faces' shear {shear} vs pull {P}");
    }
}
