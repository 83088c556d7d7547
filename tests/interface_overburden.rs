//! The normal multipliers of a reinforcement carry the overburden exactly.
//!
//! Reference: docs/verification.md §5, the plane-strain oedometer: in a laterally
//! confined column (frictionless rigid walls, fixed base) under a surcharge q and self-weight γ, the
//! vertical stress at depth z is σv = q + γ·z. A reinforcement at depth z, held to the soil by
//! Lagrange multipliers, must therefore carry σn = λ/ℓ = q + γ·z at every point of both faces,
//! with the consistent tributary length ℓ (half a segment at the ends), and the soil stresses must
//! be undisturbed by the split.
//!
//! Model: examples/annotated-pullout.toml (0.8 m × 0.4 m, grid at z = 0.2 m, q = 20 kPa,
//! γ = 19 kN/m³ → σn = 23.8 kPa), its first stage.

mod common;

use geoslip::linsol::Backend;
use geoslip::model::Model;
use std::path::Path;

#[test]
fn normal_stress_on_both_faces_equals_the_overburden() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/annotated-pullout.toml");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let (_, first) = &c.steps[0];
        let exact = 20.0 + 19.0 * 0.2;
        // the slit behind the grid is still covered by it: no contact there yet
        let (slit, faces): (Vec<_>, Vec<_>) = first.interface_points.iter().partition(|p| p.face == "slit");
        assert!(slit.iter().all(|p| p.state == "covered" && p.lambda == 0.0));
        assert_eq!(faces.len(), 10, "5 stations × 2 faces");
        for p in faces {
            assert!(
                (p.sigma_n - exact).abs() < 1e-9 * exact,
                "{} face at node {}: σn {}",
                p.face,
                p.slave_node,
                p.sigma_n
            );
            assert!(p.tau.abs() < 1e-9 * exact);
        }
        // and the soil's vertical stress is the oedometric one, σyy = −(q + γ(0.4 − y)); a quad4's
        // εyy is constant in y, so each element carries the value at its mid-height (y = 0.1 or 0.3)
        for s in first.stresses(&model) {
            let mid = if s.x[1] < 0.2 { 0.1 } else { 0.3 };
            let exact = -(20.0 + 19.0 * (0.4 - mid));
            assert!((s.stress[1] - exact).abs() < 1e-9 * 30.0, "element {}: σyy {} vs {exact}", s.element, s.stress[1]);
        }
    }
}
