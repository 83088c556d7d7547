//! Passive bearing of a geogrid's transverse members in a rigid pull-out box.
//!
//! Reference: Jewell, Milligan, Sarsby & Dubois (1984), "Interaction between soil and geogrids",
//! Proc. Symposium on Polymer Grid Reinforcement, Thomas Telford, pp. 18–30 (and Jewell 1996, CIRIA
//! SP123, §6.3): a member of thickness B bears σb on a fraction αb of the width, with
//! σb/σn = exp((π/2 + φ′)·tan φ′)·tan²(π/4 + φ′/2) in general shear and exp((π/2)·tan φ′)·tan(π/4 + φ′/2)
//! by punching; a grid with members every S resists with (number of members)·αb·B·σb, and with
//! friction on both faces 2·σn·tan δ per unit length besides (Jewell's pull-out resistance, the
//! two added).
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
//! bearing part apart; the punching bound gives less than general shear by the formulas' ratio.

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::{BearingFormula, BearingSpec, ReinforcementMode, ShearLawSpec};
use geoslip::model::Model;

const Q: f64 = 40.0;
const S: f64 = 0.05;
const B: f64 = 0.005;
const ALPHA_B: f64 = 0.8;
const PHI_SOIL: f64 = 32.0;
const PULL: f64 = 0.05;
/// Members left in the box after the pull: (0.8 − 0.05)/0.05.
const MEMBERS_IN: f64 = 15.0;

fn general_shear_ratio(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    ((std::f64::consts::FRAC_PI_2 + phi) * phi.tan()).exp() * (std::f64::consts::FRAC_PI_4 + phi / 2.0).tan().powi(2)
}

fn punching_shear_ratio(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    (std::f64::consts::FRAC_PI_2 * phi.tan()).exp() * (std::f64::consts::FRAC_PI_4 + phi / 2.0).tan()
}

fn rigid_box(friction_angle: f64, formula: BearingFormula) -> Model {
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
        law: ShearLawSpec::Coulomb { shear_stiffness: 2.0e4, cohesion: 0.0, friction_angle },
        surcharge: Q,
        pull: PULL,
        steps: 25,
        ..PullOutBox::default()
    }
    .model();
    file.interfaces[0].reinforcement.as_mut().unwrap().mode = ReinforcementMode::Embedded;
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
    common::model(&file, "rigid-bearing-box")
}

/// One member's bearing force per unit width: αb·B·σb.
fn member_force(ratio: f64) -> f64 {
    ALPHA_B * B * ratio * Q
}

#[test]
fn a_bearing_only_grid_resists_with_its_members_bearing_force() {
    let model = rigid_box(0.0, BearingFormula::GeneralShear);
    for backend in [Backend::Dense, Backend::Faer] {
        let c = common::run(&model, backend);
        let forces = common::head_forces(&model, &c, "grid.head");
        let expected = MEMBERS_IN * member_force(general_shear_ratio(PHI_SOIL));
        let last = *forces.last().unwrap();
        assert!(common::relative_error(last, expected) < 1e-6, "{backend:?}: {last} against {expected}");
        // the bearing is all of the resistance, and the points report it as such
        let (_, results) = c.steps.last().unwrap();
        for p in results.interface_points.iter().filter(|p| p.tributary > 0.0 && p.state == "active") {
            assert!((p.tau - p.bearing).abs() < 1e-9 * p.bearing.abs(), "{p:?}");
        }
        // mobilised linearly: at the first step's 2 mm (half of δb) half the full bearing on the
        // 0.8 m less the 2 mm already out; the soil's own shear strain (about τ·H/G = 1 µm) takes
        // some 5e-4 of that slip while the members are not fully mobilised
        let first = forces[0];
        let half = 0.5 * (0.8 - 0.002) / S * member_force(general_shear_ratio(PHI_SOIL));
        assert!(common::relative_error(first, half) < 1e-3, "{backend:?}: {first} against {half}");
    }
}

#[test]
fn friction_and_bearing_add_and_are_reported_apart() {
    let phi = 25.0f64;
    let model = rigid_box(phi, BearingFormula::GeneralShear);
    let c = common::run(&model, Backend::Faer);
    let last = *common::head_forces(&model, &c, "grid.head").last().unwrap();
    let bearing = MEMBERS_IN * member_force(general_shear_ratio(PHI_SOIL));
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
    let expected = MEMBERS_IN * member_force(punching_shear_ratio(PHI_SOIL));
    assert!(common::relative_error(fp, expected) < 1e-6, "{fp} against {expected}");
    let ratio = general_shear_ratio(PHI_SOIL) / punching_shear_ratio(PHI_SOIL);
    assert!(common::relative_error(fg / fp, ratio) < 1e-6, "{} against {ratio}", fg / fp);
}
