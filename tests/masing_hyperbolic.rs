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
//!
//! Whole runs (docs/verification.md §4, the block on a rigid base, with these curves): the block of
//! `common::block_on_rigid_base` on the same hyperbolic interface under q = 10 kPa,
//! - driven by displacement through +8, −4, +4, −8 and +8 mm: the force over its 1 m base on the
//!   closed-form curve of each branch at every step, to 1e-9 of τf (every node moves d: exact);
//! - driven by a horizontal force on its base nodes (the block made rigid, E = 10⁹ kPa; a force at
//!   the base's level puts no moment on it) through +8, −8 and +8 kN/m: its slip on the inverse curves s = s_r + 2·G((τ − τ_r)/2), G the inverse of the
//!   backbone, G(τ) = τ/(Ks·(1 − |τ|/τf)), to 1e-5 of the largest slip (the block's own shear
//!   strain is 5e-7 of it).

mod common;

use geoslip::interface::law::{ShearLaw, ShearState};
use geoslip::linsol::Backend;
use geoslip::model::file::{LoadSpec, Scheme, ShearLawSpec, SoilMaterial};

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

const LAW_SPEC: ShearLawSpec = ShearLawSpec::Hyperbolic { shear_stiffness: KS, cohesion: TF, friction_angle: 0.0 };

/// The inverse of the backbone: the slip at which it carries τ (|τ| < τf).
fn backbone_slip(tau: f64) -> f64 {
    tau / (KS * (1.0 - tau.abs() / TF))
}

#[test]
fn a_block_driven_through_loops_follows_the_masing_curves_at_every_step() {
    const A: f64 = 0.008;
    let mut file = common::block_on_rigid_base(LAW_SPEC, 10.0, A, vec![1.0]);
    // d = factor × 8 mm: +8, −4, +4, −8, +8 mm
    file.stages[1].load_factors = vec![1.0];
    file.stages[1].history = Some(vec![[1.0, 1.0], [2.0, -0.5], [3.0, 0.5], [4.0, -1.0], [5.0, 1.0]]);
    file.stages[1].history_increment = Some(0.05);
    let model = common::model(&file, "masing-block.toml");
    let c = common::run(&model, Backend::Faer);
    let f = backbone;
    let (tau_a, s_a) = (f(A), A);
    let tau_b = tau_a + 2.0 * f((-0.004 - s_a) / 2.0);
    let tau_c = tau_b + 2.0 * f((0.004 + 0.004) / 2.0);
    // the branch each step is on, by the history's segment (the step's place in the stage)
    let mut segment = 0;
    let mut last = 0.0;
    let mut checked = 0;
    for (record, step) in c.steps.iter().filter(|(r, _)| r.stage_index == 1) {
        let d = A * record.load_factor;
        let force: f64 = model.node_sets["block"].iter().map(|&n| step.reaction_vector[2 * n]).sum();
        let expected = match segment {
            0 => f(d),
            1 => tau_a + 2.0 * f((d - s_a) / 2.0),
            2 => tau_b + 2.0 * f((d + 0.004) / 2.0),
            // from +4 mm down: its own curve to −4 mm, then the curve from +8 mm again
            3 if d >= -0.004 => tau_c + 2.0 * f((d - 0.004) / 2.0),
            3 => tau_a + 2.0 * f((d - s_a) / 2.0),
            _ => -tau_a + 2.0 * f((d + A) / 2.0),
        };
        assert!((force - expected).abs() < 1e-9 * TF, "branch {segment}, d = {d}: {force} against {expected}");
        checked += 1;
        if record.reversal {
            segment += 1;
        }
        last = force;
    }
    assert_eq!(segment, 4, "four reversals");
    assert!(checked > 100, "{checked} steps");
    assert!((last - tau_a).abs() < 1e-9 * TF, "the outer loop closes at F(8 mm): {last}");
}

/// Under both schemes. With Newton's, the first step after a reversal runs into a singular matrix
/// where its iterations wander, and is cut back (before, that stopped the run), so that scheme takes
/// more, smaller steps, each on the same curves.
#[test]
fn a_block_driven_by_a_cyclic_force_slips_on_the_inverse_masing_curves() {
    for scheme in [Scheme::ConstantStiffness, Scheme::Newton] {
        block_driven_by_a_cyclic_force(scheme);
    }
}

fn block_driven_by_a_cyclic_force(scheme: Scheme) {
    const T: f64 = 8.0;
    let mut file = common::block_on_rigid_base(LAW_SPEC, 10.0, 0.0, vec![1.0]);
    file.materials.soil.insert("soil".into(), SoilMaterial::linear_elastic(1.0e9, 0.3, 0.0));
    file.analysis.scheme = scheme;
    file.analysis.max_iterations = 400;
    file.stages[0].prescribed.clear();
    file.stages[1].prescribed.clear();
    let shear = &mut file.stages[1];
    shear.load_factors = vec![1.0];
    // the force at the base's level, shared by its five nodes: no moment, so σn stays q and the
    // rigid block slips uniformly, τ = the force over the 1 m base
    let base = file.interfaces[0].slave.clone().expect("the block's base nodes");
    let shear = &mut file.stages[1];
    shear.loads =
        vec![LoadSpec::Point { node: None, nodes: Some(base.clone()), set: None, fx: T / base.len() as f64, fy: 0.0 }];
    shear.history = Some(vec![[1.0, 1.0], [2.0, -1.0], [3.0, 1.0]]);
    shear.history_increment = Some(0.1);
    let model = common::model(&file, "masing-block.toml");
    let c = common::run(&model, Backend::Faer);
    let s1 = backbone_slip(T);
    let block = &model.node_sets["block"];
    let mut segment = 0;
    let mut checked = 0;
    for (record, step) in c.steps.iter().filter(|(r, _)| r.stage_index == 1) {
        let tau = T * record.load_factor;
        let slip = block.iter().map(|&n| step.displacement_vector[2 * n]).sum::<f64>() / block.len() as f64;
        let expected = match segment {
            0 => backbone_slip(tau),
            1 => s1 + 2.0 * backbone_slip((tau - T) / 2.0),
            _ => -s1 + 2.0 * backbone_slip((tau + T) / 2.0),
        };
        assert!(
            (slip - expected).abs() < 1e-5 * s1,
            "{scheme:?}, branch {segment}, τ = {tau}: slip {slip} against {expected}"
        );
        checked += 1;
        if record.reversal {
            segment += 1;
        }
    }
    // fifty steps of 0.1 in the history, more where one was cut back
    assert_eq!(segment, 2, "{scheme:?}: two reversals");
    assert!(checked >= 50, "{scheme:?}: {checked} steps");
}
