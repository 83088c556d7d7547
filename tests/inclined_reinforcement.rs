//! A reinforcement in any orientation: the elastic shear-lag pull-out on a rigid bed, turned.
//!
//! Reference: docs/verification.md §1: head stiffness K = EA·α·tanh(αL),
//! α = sqrt(n_f·Ks/EA). The closed form does not know the direction of the bar: a geosynthetic on a
//! slope (or in a vertical anchor trench) must give the same K as a horizontal one.
//!
//! Parameters as in tests/shear_lag_pullout.rs (EA = 1000 kN/m, Ks = 2000 kN/m³, L = 1 m,
//! αL = 2, 20 bars, K = 1928.055 kN/m/m); the whole model (soil block, reinforcement, load) is
//! turned by θ = 1°, 18.43° (a 3H:1V slope), 45° and 90°. Goal: K within 0.5 % at every angle, the
//! head moving along the bar only. (A turned model once lost its normal rows to round-off tension:
//! see `hold_free_reinforcement_nodes`.)
//!
//! ```text
//!               o  tail
//!             /
//!           /   fixed soil on both faces
//!   P ↙   o  head (at the origin), pulled along the bar
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

const EA: f64 = 1000.0;
const KS: f64 = 2000.0;
const L: f64 = 1.0;
const P: f64 = 10.0;
const ALPHA: f64 = 2.0;

fn turned_bar(theta_deg: f64) -> ModelFile {
    let law = ShearLawSpec::Linear { shear_stiffness: KS };
    let mut file = common::slip::bar_in_rigid_soil(L, 20, EA, law, 0.0, 1, ReassociationRule::None);
    let (s, c) = theta_deg.to_radians().sin_cos();
    for n in &mut file.nodes {
        let (x, y) = (n.1, n.2);
        n.1 = c * x - s * y;
        n.2 = s * x + c * y;
    }
    let stage = &mut file.stages[0];
    stage.prescribed.clear();
    stage.loads =
        vec![LoadSpec::Point { node: None, nodes: None, set: Some("grid.head".into()), fx: -P * c, fy: -P * s }];
    file
}

#[test]
fn head_stiffness_is_the_same_in_every_direction() {
    let exact = EA * ALPHA * (ALPHA * L).tanh();
    for theta in [1.0f64, 18.43, 45.0, 90.0] {
        let model = common::model(&turned_bar(theta), "inclined.toml");
        for backend in Backend::available() {
            let c = common::run(&model, backend);
            let head = model.mesh.node_id(model.node_sets["grid.head"][0]);
            let u = common::displacement(&c, head);
            let (s, co) = theta.to_radians().sin_cos();
            let along = -(u[0] * co + u[1] * s);
            let across = -u[0] * s + u[1] * co;
            let k = P / along;
            assert!(
                common::relative_error(k, exact) < 0.005,
                "θ = {theta}°, {backend:?}: K = {k:.3} against {exact:.3}"
            );
            assert!(
                across.abs() < 1e-9 * along,
                "θ = {theta}°, {backend:?}: the head moved {across:e} m across the bar"
            );
        }
    }
}
