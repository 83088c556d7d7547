//! Passive bearing of a geogrid's transverse members in a rigid pull-out box.
//!
//! Reference: docs/verification.md §8. Jewell, Milligan, Sarsby & Dubois (1984), "Interaction
//! between soil and geogrids", Proc. Symposium on Polymer Grid Reinforcement, Thomas Telford,
//! pp. 18–30, as quoted by Jewell (1996), CIRIA SP123, §6.3, and Palmeira (2009): a member of
//! thickness B bears σb on a fraction αb of the width, with φ′ the soil's peak angle
//! σb/σn = exp(π·tan φ′)·tan²(π/4 + φ′/2) in general shear (the upper bound) and
//! exp((π/2 + φ′)·tan φ′)·tan(π/4 + φ′/2) by punching (the lower bound); a grid with members every
//! S resists with (number of members)·αb·B·σb, and with friction on both faces 2·(c + σn·tan δ)
//! per unit length besides (Jewell's pull-out resistance, the two added).
//!
//! Model: the pull-out box of `meshgen::PullOutBox` made rigid (E = 10 GPa, weightless), 1.0 m long,
//! 0.4 m high, 20 × 8 quad4 (h = 0.05 m); a grid embedded in the continuous soil (its σn the soil's,
//! q) on the soil's nodes over 0.8 m from the front with
//! EA = 10⁹ kN/m (inextensible: its stretch moves its tail by 10⁻⁸ m); members every S = 0.05 m
//! (16 in the box), B = 5 mm, αb = 0.8, φ′ = 32°, mobilised over δb = 4 mm; q = 40 kPa with σn
//! frozen at it. The head is pulled out by exactly one member spacing, 50 mm, in 25 steps: 15
//! members are then still in the box. Goal: the head force equals 15 members' bearing force to
//! 1e-6 (bearing only: a Coulomb law with c = 0, φ = 0 carries no friction); with friction φ = 25°
//! on both faces the force is that plus 2·q·tan 25°·0.75 m, and the report's summary puts the
//! bearing part apart; with cohesion as well it is 2·0.75 m·(c + q·tan 25°) plus the bearing; the
//! punching bound gives less than general shear by the formulas' ratio.
//!
//! Numbers (docs/verification.md §8): at φ′ = 32°, σb/σn = 23.1768 (general shear) and 6.82484
//! (punching), a ratio of 3.39595; one member αb·B·σb = 3.70828 and 1.09197 kN/m, 15 members
//! 55.6243 and 16.3796 kN/m; friction at 25° 27.9785 kN/m; with c = 5 kPa as well 35.4785 kN/m.

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::{
    BearingFormula, BearingSpec, LoadSpec, ModelFile, ReinforcementMode, Scheme, ShearLawSpec, StrengthReductionSpec,
};
use geoslip::model::Model;

const Q: f64 = 40.0;
const S: f64 = 0.05;
const B: f64 = 0.005;
const ALPHA_B: f64 = 0.8;
const PHI_SOIL: f64 = 32.0;
const PULL: f64 = 0.05;
/// Members left in the box after the pull: (0.8 − 0.05)/0.05.
const MEMBERS_IN: f64 = 15.0;

// Jewell et al.'s (1984) bounds of σb/σn at the soil's peak angle φ′ in degrees, written here
// apart from `geoslip::interface::bearing` (so that a wrong formula in either place fails): with
// Kp = tan²(45° + φ′/2) = (1 + sin φ′)/(1 − sin φ′), the general-shear (upper) bound is
// e^(π·tan φ′)·Kp, the Prandtl–Reissner Nq, and the punching (lower) bound is
// e^((π/2 + φ′)·tan φ′)·√Kp. `the_tests_bounds_are_the_published_values` pins them to the
// numbers of docs/verification.md §8.

fn jewell_general_shear(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    let kp = (1.0 + phi.sin()) / (1.0 - phi.sin());
    (std::f64::consts::PI * phi.tan()).exp() * kp
}

fn jewell_punching(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    let kp = (1.0 + phi.sin()) / (1.0 - phi.sin());
    ((std::f64::consts::FRAC_PI_2 + phi) * phi.tan()).exp() * kp.sqrt()
}

fn rigid_box(friction_angle: f64, formula: BearingFormula) -> Model {
    rigid_box_with_cohesion(0.0, friction_angle, formula)
}

fn rigid_box_with_cohesion(cohesion: f64, friction_angle: f64, formula: BearingFormula) -> Model {
    common::model(&rigid_box_file(cohesion, friction_angle, formula, ReinforcementMode::Embedded), "rigid-bearing-box")
}

fn rigid_box_file(cohesion: f64, friction_angle: f64, formula: BearingFormula, mode: ReinforcementMode) -> ModelFile {
    let mut file = PullOutBox {
        length: 1.0,
        height: 0.4,
        embedded: 0.8,
        nx: 20,
        ny_half: 4,
        youngs_modulus: 1.0e7,
        poissons_ratio: 0.3,
        unit_weight: 0.0,
        axial_stiffness: 1.0e9,
        law: ShearLawSpec::Coulomb { shear_stiffness: 2.0e4, cohesion, friction_angle },
        surcharge: Q,
        pull: PULL,
        steps: 25,
        ..PullOutBox::default()
    }
    .model();
    file.interfaces[0].reinforcement.as_mut().unwrap().mode = mode;
    file.interfaces[0].bearing = Some(BearingSpec {
        member_spacing: S,
        member_thickness: B,
        bearing_fraction: ALPHA_B,
        formula,
        friction_angle: Some(PHI_SOIL),
        ratio: None,
        mobilisation_displacement: 0.004,
    });
    file.analysis.freeze_normal_stress = true;
    file
}

/// One member's bearing force per unit width: αb·B·σb.
fn member_force(ratio: f64) -> f64 {
    ALPHA_B * B * ratio * Q
}

#[test]
fn the_tests_bounds_are_the_published_values() {
    // docs/verification.md §8, computed there with python3 and written to 6 significant figures
    // (good to 5e-6 relative, hence 1e-5): at 30°, 18.4011 (general shear) and 5.80376 (punching);
    // at the tests' 32°, 23.1768 and 6.82484
    for (phi, general, punching) in [(30.0, 18.4011, 5.80376), (PHI_SOIL, 23.1768, 6.82484)] {
        let g = jewell_general_shear(phi);
        assert!(common::relative_error(g, general) < 1e-5, "general shear at {phi}°: {g} against {general}");
        let p = jewell_punching(phi);
        assert!(common::relative_error(p, punching) < 1e-5, "punching at {phi}°: {p} against {punching}");
    }
}

#[test]
fn a_bearing_only_grid_resists_with_its_members_bearing_force() {
    let model = rigid_box(0.0, BearingFormula::GeneralShear);
    for backend in [Backend::Dense, Backend::Faer] {
        let c = common::run(&model, backend);
        let forces = common::head_forces(&model, &c, "grid.head");
        let expected = MEMBERS_IN * member_force(jewell_general_shear(PHI_SOIL));
        let last = *forces.last().unwrap();
        assert!(common::relative_error(last, expected) < 1e-6, "{backend:?}: {last} against {expected}");
        // the bearing is all of the resistance, and the points report it as such
        let (_, results) = c.steps.last().unwrap();
        for p in results.interface_points.iter().filter(|p| p.tributary > 0.0 && p.state == "active") {
            assert!((p.tau - p.bearing).abs() < 1e-9 * p.bearing.abs(), "{p:?}");
        }
        // mobilised linearly: at the first step's 2 mm (half of δb) half the full bearing on the
        // 0.8 m less the 2 mm already out, 29.5921 kN/m; the soil's own strain (it moves about 1 µm
        // on the grid's line) takes some 4e-4 of that slip while the members are not fully
        // mobilised (docs/verification.md §8), hence 1e-3
        let first = forces[0];
        let half = 0.5 * (0.8 - 0.002) / S * member_force(jewell_general_shear(PHI_SOIL));
        assert!(common::relative_error(first, half) < 1e-3, "{backend:?}: {first} against {half}");
    }
}

#[test]
fn friction_and_bearing_add_and_are_reported_apart() {
    let phi = 25.0f64;
    let model = rigid_box(phi, BearingFormula::GeneralShear);
    let c = common::run(&model, Backend::Faer);
    let last = *common::head_forces(&model, &c, "grid.head").last().unwrap();
    let bearing = MEMBERS_IN * member_force(jewell_general_shear(PHI_SOIL));
    let friction = 2.0 * Q * phi.to_radians().tan() * (0.8 - PULL);
    assert!(common::relative_error(last, bearing + friction) < 1e-6, "{last} against {bearing} + {friction}");
    let (record, _) = c.steps.last().unwrap();
    let balance = record.balance.iter().find(|b| b.interface == "grid").expect("the grid's balance");
    let carried = balance.bearing_force.expect("the bearing part");
    assert!(common::relative_error(carried[0].abs(), bearing) < 1e-6, "{carried:?} against {bearing}");
    assert!(common::relative_error(balance.interface_force[0].abs(), bearing + friction) < 1e-6);
}

#[test]
fn the_punching_bound_is_below_general_shear_by_the_formulas_ratio() {
    let general = rigid_box(0.0, BearingFormula::GeneralShear);
    let punching = rigid_box(0.0, BearingFormula::PunchingShear);
    let fg = *common::head_forces(&general, &common::run(&general, Backend::Faer), "grid.head").last().unwrap();
    let fp = *common::head_forces(&punching, &common::run(&punching, Backend::Faer), "grid.head").last().unwrap();
    let expected = MEMBERS_IN * member_force(jewell_punching(PHI_SOIL));
    assert!(common::relative_error(fp, expected) < 1e-6, "{fp} against {expected}");
    let ratio = jewell_general_shear(PHI_SOIL) / jewell_punching(PHI_SOIL);
    assert!(common::relative_error(fg / fp, ratio) < 1e-6, "{} against {ratio}", fg / fp);
}

#[test]
fn cohesion_friction_and_punching_bearing_add_as_the_closed_form_splits_them() {
    // docs/verification.md §8, the embedded grid once every point in the box slides and every
    // member bears fully: F = 2·L_in·(c + q·tan φ) + (L_in/S)·αb·B·R·q with L_in = 0.8 − 0.05 m,
    // c = 5 kPa, φ = 25°, R the punching bound at φ′ = 32°: 35.4785 + 16.3796 = 51.8581 kN/m;
    // to 1e-6 as the other tests at full mobilisation (every point slides and every member bears
    // its full σb, so the soil's strain does not enter)
    let cohesion = 5.0_f64;
    let phi = 25.0_f64;
    let model = rigid_box_with_cohesion(cohesion, phi, BearingFormula::PunchingShear);
    let c = common::run(&model, Backend::Faer);
    let last = *common::head_forces(&model, &c, "grid.head").last().unwrap();
    let l_in = 0.8 - PULL;
    let friction = 2.0 * l_in * (cohesion + Q * phi.to_radians().tan());
    let bearing = l_in / S * ALPHA_B * B * jewell_punching(PHI_SOIL) * Q;
    assert!(common::relative_error(last, friction + bearing) < 1e-6, "{last} against {friction} + {bearing}");
    // the same against the section's number, to its 6 significant figures
    assert!(common::relative_error(last, 51.8581) < 1e-5, "{last} against 51.8581");
    let (record, _) = c.steps.last().unwrap();
    let balance = record.balance.iter().find(|b| b.interface == "grid").expect("the grid's balance");
    let carried = balance.bearing_force.expect("the bearing part");
    assert!(common::relative_error(carried[0].abs(), bearing) < 1e-6, "{carried:?} against {bearing}");
}

/// Friction on both faces at 25° plus general-shear bearing, per metre of grid in the box:
/// 2·q·tan 25° + αb·B·σb/S (docs/verification.md §8).
fn resistance_per_metre() -> f64 {
    2.0 * Q * 25f64.to_radians().tan() + member_force(jewell_general_shear(PHI_SOIL)) / S
}

#[test]
fn split_mode_and_the_newton_scheme_give_the_members_and_friction_of_the_closed_form() {
    // docs/verification.md §8.3 and §8.6. With σn frozen at q on both faces the split and the
    // embedded forms agree: F = L_in·111.4703 kN/m once every member bears fully. In split mode each
    // face is a contact face of its own, with half the members' bearing; with the Newton scheme the
    // bearing's tangent enters the matrix instead of Ks + τb,max/δb. Checked at 10 mm of pull
    // (2.5 δb; L_in = 0.79 m: 88.0615 kN/m) and, embedded, at the end (0.75 m: 83.6027 kN/m). At
    // full mobilisation the soil's strain does not enter (1e-6, as above). In split mode the
    // grid's front point opens on its lower face as the head leaves the slot, and closes again: its
    // bearing then starts from zero (docs/model-format.md), so the end is not the closed form's.
    for mode in [ReinforcementMode::Split, ReinforcementMode::Embedded] {
        for scheme in [Scheme::ConstantStiffness, Scheme::Newton] {
            let mut file = rigid_box_file(0.0, 25.0, BearingFormula::GeneralShear, mode);
            file.analysis.scheme = scheme;
            let model = common::model(&file, "rigid-bearing-box");
            let c = common::run(&model, Backend::Faer);
            let forces = common::head_forces(&model, &c, "grid.head");
            // 2 mm a step: the fifth pull step is at 10 mm
            let at_10mm = (0.8 - 0.010) * resistance_per_metre();
            assert!(
                common::relative_error(forces[4], at_10mm) < 1e-6,
                "{mode:?}, {scheme:?}: {} against {at_10mm} at 10 mm",
                forces[4]
            );
            if mode == ReinforcementMode::Embedded {
                let end = (0.8 - PULL) * resistance_per_metre();
                let last = *forces.last().unwrap();
                assert!(common::relative_error(last, end) < 1e-6, "{scheme:?}: {last} against {end}");
            }
        }
    }
}

#[test]
fn a_reversal_unloads_the_members_with_their_mobilisation_slope_and_bears_the_other_way() {
    // docs/verification.md §8, reversal: the head pulled out 10 mm (every member fully bearing,
    // 2.5 δb), then pushed back 5 mm. The members unload with the slope τb,max/δb and bear in the
    // reversed direction: after 5 mm back, τb = τb,max·(1 − 5/4) = −0.25 τb,max. Friction unloads
    // with Ks and is fully reversed after 2·q·tan φ/Ks = 1.87 mm. So the head pushes with
    // (0.8 − 0.005 m)·(2·q·tan 25° + 0.25·αb·B·σb/S) = (0.795)·(37.305 + 18.541) = 44.398 kN/m.
    // The members are mobilised partly there, so the soil's own strain takes its share of the
    // slip as in the first step of `a_bearing_only_grid_…` (4e-4 there), hence 2e-3.
    for scheme in [Scheme::ConstantStiffness, Scheme::Newton] {
        let mut file = rigid_box_file(0.0, 25.0, BearingFormula::GeneralShear, ReinforcementMode::Embedded);
        file.analysis.scheme = scheme;
        let pull = &mut file.stages[1];
        pull.load_factors = vec![1.0];
        pull.history = Some(vec![[1.0, 0.2], [2.0, 0.1]]);
        pull.history_increment = Some(0.01);
        let model = common::model(&file, "rigid-bearing-box");
        let c = common::run(&model, Backend::Faer);
        let forces = common::head_forces(&model, &c, "grid.head");
        assert_eq!(forces.len(), 30, "{scheme:?}: 20 steps out, 10 back");
        let out = forces[19];
        let at_10mm = (0.8 - 0.010) * resistance_per_metre();
        assert!(common::relative_error(out, at_10mm) < 1e-6, "{scheme:?}: {out} against {at_10mm}");
        let last = *forces.last().unwrap();
        let tan = 25f64.to_radians().tan();
        let expected = (0.8 - 0.005) * (2.0 * Q * tan + 0.25 * member_force(jewell_general_shear(PHI_SOIL)) / S);
        assert!(common::relative_error(last, expected) < 2e-3, "{scheme:?}: {last} against {expected}");
    }
}

#[test]
fn strength_reduction_divides_the_members_bearing_with_the_friction() {
    // docs/verification.md §8, strength reduction: the head held by a force P, half of what the
    // grid resists once the members bear fully; a strength-reduction search divides c, tan φ and
    // the members' bearing by F. The grid slides out once the reduced resistance of what is still
    // in the box falls below P. The resistance (0.8 − s)·(friction + bearing(s))/F is largest at
    // the slip s = δb = 4 mm where the members have just become fully mobilised, so
    // FS = (0.8 − 0.004)·(2·q·tan 25° + αb·B·σb/S)/P = 0.796/0.4 = 1.99 exactly: the search's
    // bracket (tolerance 1e-3) must hold it.
    let full = 0.8 * resistance_per_metre();
    let p = 0.5 * full;
    let mut file = rigid_box_file(0.0, 25.0, BearingFormula::GeneralShear, ReinforcementMode::Embedded);
    file.analysis.scheme = Scheme::Newton;
    file.analysis.max_iterations = 200;
    let hold = &mut file.stages[1];
    hold.name = "held".into();
    hold.prescribed.clear();
    hold.load_factors = vec![0.25, 0.5, 0.75, 1.0];
    hold.loads = vec![LoadSpec::Point { node: None, nodes: None, set: Some("grid.head".into()), fx: -p, fy: 0.0 }];
    file.stages.push(geoslip::model::file::Stage {
        name: "factor of safety".into(),
        strength_reduction: Some(StrengthReductionSpec {
            reduce: geoslip::model::file::ReducedStrengths::Interfaces,
            tolerance: Some(1e-3),
            max_factor: None,
        }),
        ..Default::default()
    });
    let model = common::model(&file, "rigid-bearing-box");
    let c = common::run(&model, Backend::Faer);
    let fs = c.factors_of_safety.last().expect("the stage's FS");
    let exact = (0.8 - 0.004) * resistance_per_metre() / p;
    let failed = fs.failed_at.expect("the search bracketed FS");
    assert!(fs.value <= exact * (1.0 + 1e-6) && failed >= exact * (1.0 - 1e-6), "{fs:?} against {exact}");
    assert!(failed / fs.value - 1.0 < 2.5e-3, "{fs:?}");
}
