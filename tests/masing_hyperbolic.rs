//! The hyperbolic law unloaded and reloaded: Masing's rules.
//!
//! Reference: Masing (1926), as stated for soils with the extended rules by Kramer (1996, §6.4.2):
//! with the backbone τ = F(s) = Ks·s/(1 + Ks·|s|/τf), a reversal at (s_r, τ_r) starts the curve
//! τ = τ_r + 2·F((s − s_r)/2) (the backbone at twice its scale, through the reversal point), which
//! meets the backbone again at (−s_r, −τ_r) and then follows it; a curve that reaches the point
//! where an earlier curve was left continues on that curve.
//!
//! Parameters: Ks = 2000 kPa/m, c = 10 kPa, φ = 0 (τf = 10 kPa), at σn = 0. The law is driven
//! point by point as an increment's iterations would drive it (each from the committed state).
//! Goal: every point on its curve to 1e-12, and the loop closed.

use geoslip::interface::law::{ShearLaw, ShearState};

const KS: f64 = 2000.0;
const TF: f64 = 10.0;

fn backbone(s: f64) -> f64 {
    KS * s / (1.0 + KS * s.abs() / TF)
}

fn drive(law: &ShearLaw, state: &mut ShearState, s: f64) -> f64 {
    let r = law.response(state, s, 0.0);
    *state = r.state;
    r.tau
}

#[test]
fn unloading_and_reloading_follow_the_backbone_at_twice_its_scale() {
    let law = ShearLaw::Hyperbolic { shear_stiffness: KS, cohesion: TF, tan_friction: 0.0 };
    let mut state = ShearState::default();
    // first loading: the backbone
    for s in [0.001, 0.003, 0.005] {
        let tau = drive(&law, &mut state, s);
        assert!((tau - backbone(s)).abs() < 1e-12, "s = {s}: {tau}");
    }
    let (s_r, tau_r) = (0.005, backbone(0.005));
    // unloading from (5 mm, F(5 mm)): τ_r + 2F((s − s_r)/2)
    for s in [0.004, 0.0, -0.002, -0.0049] {
        let tau = drive(&law, &mut state, s);
        let masing = tau_r + 2.0 * backbone((s - s_r) / 2.0);
        assert!((tau - masing).abs() < 1e-12, "unloading, s = {s}: {tau} against {masing}");
        assert!(tau < backbone(s), "the unloading curve lies below the backbone until it meets it");
    }
    // it meets the backbone at (−s_r, −τ_r) and follows it beyond
    assert!((drive(&law, &mut state, -s_r) + tau_r).abs() < 1e-12);
    for s in [-0.006, -0.008] {
        let tau = drive(&law, &mut state, s);
        assert!((tau - backbone(s)).abs() < 1e-12, "back on the backbone, s = {s}: {tau}");
    }
    // reloading from (−8 mm, F(−8 mm)) to +8 mm and the loop closes there
    let (s_r, tau_r) = (-0.008, backbone(-0.008));
    for s in [-0.006, 0.0, 0.004] {
        let tau = drive(&law, &mut state, s);
        let masing = tau_r + 2.0 * backbone((s - s_r) / 2.0);
        assert!((tau - masing).abs() < 1e-12, "reloading, s = {s}: {tau} against {masing}");
    }
    assert!((drive(&law, &mut state, 0.008) - backbone(0.008)).abs() < 1e-12, "the loop closes at +8 mm");
}

#[test]
fn a_small_reversal_inside_a_loop_starts_a_branch_of_its_own() {
    // unload from 5 mm to 1 mm, reload to 3 mm: the reload starts at the new reversal (1 mm)
    let law = ShearLaw::Hyperbolic { shear_stiffness: KS, cohesion: TF, tan_friction: 0.0 };
    let mut state = ShearState::default();
    drive(&law, &mut state, 0.005);
    let tau_1 = drive(&law, &mut state, 0.001);
    let tau = drive(&law, &mut state, 0.003);
    let masing = tau_1 + 2.0 * backbone((0.003 - 0.001) / 2.0);
    assert!((tau - masing).abs() < 1e-12, "{tau} against {masing}");
    // reloaded on, it reaches the point where the first curve left the backbone (5 mm) and
    // follows the backbone from there
    let tau = drive(&law, &mut state, 0.005);
    assert!((tau - backbone(0.005)).abs() < 1e-12, "{tau} against the backbone's {}", backbone(0.005));
    let tau = drive(&law, &mut state, 0.010);
    assert!((tau - backbone(0.010)).abs() < 1e-12, "{tau} against the backbone's {}", backbone(0.010));
}

#[test]
fn an_inner_loop_rejoins_the_outer_loop_where_it_left_it() {
    // +8 mm, down to −4 mm, up to +4 mm, down to −8 mm: the last curve starts at +4 mm, reaches
    // −4 mm where the curve from +8 mm was left, continues on that curve to −8 mm, where it meets
    // the backbone (the stress never beyond the backbone's −F(8 mm) there)
    let law = ShearLaw::Hyperbolic { shear_stiffness: KS, cohesion: TF, tan_friction: 0.0 };
    let mut state = ShearState::default();
    let tau_a = drive(&law, &mut state, 0.008);
    let tau_b = drive(&law, &mut state, -0.004);
    assert!((tau_b - (tau_a + 2.0 * backbone(-0.006))).abs() < 1e-12);
    let tau_c = drive(&law, &mut state, 0.004);
    assert!((tau_c - (tau_b + 2.0 * backbone(0.004))).abs() < 1e-12);
    let tau = drive(&law, &mut state, 0.0);
    assert!((tau - (tau_c + 2.0 * backbone(-0.002))).abs() < 1e-12, "on the curve from +4 mm");
    let tau = drive(&law, &mut state, -0.004);
    assert!((tau - tau_b).abs() < 1e-12, "back at the point where the curve from +8 mm was left");
    let tau = drive(&law, &mut state, -0.006);
    assert!((tau - (tau_a + 2.0 * backbone(-0.007))).abs() < 1e-12, "on the curve from +8 mm again");
    let tau = drive(&law, &mut state, -0.008);
    assert!((tau + tau_a).abs() < 1e-12, "at the backbone's −F(8 mm)");
    let tau = drive(&law, &mut state, -0.009);
    assert!((tau - backbone(-0.009)).abs() < 1e-12 && state.reversals.is_empty(), "on the backbone beyond");
}
