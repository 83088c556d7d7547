//! Reinforcement limits: a tension-only geogrid pushed instead of pulled, and a reinforcement that
//! ruptures before it pulls out.
//!
//! Reference: statics of a two-node bar on interface springs (docs/verification.md §1–2 setting: rigid
//! soil, n_f = 2 faces, lumped springs Ks·ℓ with ℓ = h/2 at the head).
//! - Tension-only: pushed by u at its head, the grid carries no compression, so only the head point's
//!   springs resist: P = n_f·Ks·(h/2)·u.
//! - Rupture: the pull-out force can never exceed T_ult (here below the pull-out capacity
//!   n_f·τ·L = 10 kN/m); once the head bar breaks, the grid behind it is left in the soil and the head
//!   carries only its own springs.

mod common;

use common::slip::{bar_in_rigid_soil, pullout_curve};
use geoslip::linsol::Backend;
use geoslip::model::file::{ReassociationRule, ShearLawSpec};

#[test]
fn a_tension_only_grid_carries_no_compression() {
    let ks = 2000.0;
    let mut file = bar_in_rigid_soil(
        1.0,
        20,
        1000.0,
        ShearLawSpec::Linear { shear_stiffness: ks },
        -0.001,
        1,
        ReassociationRule::None,
    );
    file.materials.reinforcement.get_mut("grid").unwrap().tension_only = true;
    let model = common::model(&file, "tension-only.toml");
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let (u, p) = *pullout_curve(&model, &c).last().unwrap();
        assert!((u + 0.001).abs() < 1e-15);
        // pushing: the reaction opposes the push (negative pull-out force)
        let exact = -2.0 * ks * 0.025 * 0.001;
        assert!((p - exact).abs() < 1e-9 * exact.abs(), "{backend:?}: P = {p}, expected {exact}");
        let last = c.last().unwrap();
        assert!(last.bar_forces.iter().all(|b| b.axial_force.abs() < 1e-9));
        let head_bar = last.bar_forces.iter().min_by(|a, b| a.midpoint[0].total_cmp(&b.midpoint[0])).unwrap();
        assert_eq!(head_bar.state, "slack");
    }
}

#[test]
fn a_grid_ruptures_at_its_strength_and_the_run_reports_it() {
    let law = ShearLawSpec::Coulomb { shear_stiffness: 2000.0, cohesion: 5.0, friction_angle: 0.0 };
    let mut file = bar_in_rigid_soil(1.0, 20, 1000.0, law, 0.02, 40, ReassociationRule::None);
    file.materials.reinforcement.get_mut("grid").unwrap().rupture_strength = Some(6.0);
    let model = common::model(&file, "rupture.toml");
    let c = common::run(&model, Backend::available()[0]);
    let curve = pullout_curve(&model, &c);
    let peak = curve.iter().map(|&(_, p)| p).fold(f64::MIN, f64::max);
    assert!(peak <= 6.0 + 1e-9, "the pull {peak} exceeded T_ult");
    assert!(peak > 5.5, "the pull never approached T_ult: {peak}");
    let ruptured: Vec<_> =
        c.steps.iter().flat_map(|(r, _)| r.state_changes.iter().filter(|s| s.contains("ruptured"))).collect();
    assert!(!ruptured.is_empty(), "no rupture was reported");
    let last = c.last().unwrap();
    assert!(last.bar_forces.iter().any(|b| b.state == "ruptured"));
    // after the rupture the head holds only its own springs, at their strength: n_f·τ·h/2
    let (_, p_end) = *curve.last().unwrap();
    assert!((p_end - 2.0 * 5.0 * 0.025).abs() < 1e-6, "P after rupture {p_end}");
}
