//! The Simplified Method and the pull-out resistance against a worked design example.
//!
//! Reference: FHWA-NHI-10-025 (GEC 011 Volume II, 2009), Appendix E, Example E4, "Segmental
//! precast panel MSE wall with level backfill and live load surcharge" (docs/verification.md §12):
//! a wall of design height H = 25.64 ft with ten layers of steel bar mats, L = 18 ft, in a fill of
//! γ = 125 pcf and φ = 34°, under a traffic surcharge q = 0.25 ksf (2 ft of soil), with 5 ft wide
//! panels.
//!
//! Every number of the example's Table E4-7.4 (p. E4-18) that the methods give is checked, layer
//! by layer: σH, T_max per panel, F*, Le and φ·Pr, with the tributary zones of Table E4-7.1
//! (p. E4-11) and the hand calculation of level 4 (pp. E4-13, E4-16 and E4-17).
//!
//! Tolerances: σH, F* and Le are printed to 2, 3 and 2 decimals, and must round to the printed
//! value (half a unit of their last place). T_max and φ·Pr come, as the manual says on p. E4-18,
//! from an unrounded spreadsheet whose values differ from the long-hand ones "by less than 0.2 in
//! most cases"; they must agree within 0.5 % (measured: at most 0.21 % and 0.23 %).

use geoslip::design::pullout;
use geoslip::design::simplified;
use geoslip::design::ReinforcementKind;

const H: f64 = 25.64; // ft
const L: f64 = 18.0; // ft
const UNIT_WEIGHT: f64 = 0.125; // kcf
const SURCHARGE: f64 = 0.25; // ksf
const PANEL_WIDTH: f64 = 5.0; // ft
const TRANSITION: f64 = 20.0; // ft
const WIRE: f64 = 0.374; // in, W11 transverse wires

/// Table E4-7.4, per level: Z [ft], transverse wire spacing St [in] (Table E4-7.3), σH [ksf],
/// T_max [k per 5 ft panel], F*, Le [ft], φ·Pr [k/ft].
const TABLE: [(f64, f64, f64, f64, f64, f64, f64); 10] = [
    (1.87, 6.0, 0.40, 6.25, 1.188, 10.31, 5.16),
    (4.37, 6.0, 0.67, 8.36, 1.110, 10.31, 11.25),
    (6.87, 6.0, 0.86, 10.80, 1.033, 10.31, 16.47),
    (9.37, 6.0, 1.02, 12.77, 0.955, 10.31, 20.75),
    (11.87, 12.0, 1.14, 14.26, 0.438, 10.31, 12.06),
    (14.37, 12.0, 1.22, 15.23, 0.399, 11.24, 14.50),
    (16.87, 12.0, 1.26, 15.71, 0.360, 12.74, 17.41),
    (19.37, 18.0, 1.28, 16.03, 0.214, 14.24, 13.27),
    (21.87, 18.0, 1.37, 17.10, 0.208, 15.74, 16.12),
    (24.37, 18.0, 1.51, 19.05, 0.208, 17.24, 19.66),
];

fn friction_angle() -> f64 {
    34f64.to_radians()
}

/// The tributary zone of level k (Table E4-7.1): from the top of the wall, or halfway to the
/// level above, to halfway to the level below, or the bottom of the wall.
fn zone(k: usize) -> (f64, f64) {
    let top = if k == 0 { 0.0 } else { 0.5 * (TABLE[k - 1].0 + TABLE[k].0) };
    let bottom = if k + 1 == TABLE.len() { H } else { 0.5 * (TABLE[k].0 + TABLE[k + 1].0) };
    (top, bottom)
}

/// `value` rounds to `printed`, given to `decimals` places.
fn rounds_to(value: f64, printed: f64, decimals: i32) -> bool {
    (value - printed).abs() <= 0.5 * 10f64.powi(-decimals) + 1e-12
}

#[test]
fn the_simplified_method_gives_the_lateral_stress_and_load_of_every_level() {
    let ka = simplified::active_coefficient(friction_angle());
    for (k, &(z, _, sigma_h, t_max, ..)) in TABLE.iter().enumerate() {
        let (top, bottom) = zone(k);
        let load =
            simplified::layer_load(ReinforcementKind::BarMat, ka, UNIT_WEIGHT, top, bottom, SURCHARGE, TRANSITION);
        let factored_sigma_h = simplified::EARTH_LOAD_FACTOR * load.horizontal_stress;
        assert!(
            rounds_to(factored_sigma_h, sigma_h, 2),
            "level {} (Z = {z} ft): σH = {factored_sigma_h:.4} ksf, the example's {sigma_h}",
            k + 1
        );
        let per_panel = load.factored_max_tension * PANEL_WIDTH;
        assert!(
            (per_panel - t_max).abs() <= 5e-3 * t_max,
            "level {} (Z = {z} ft): T_max = {per_panel:.3} k per panel, the example's {t_max}",
            k + 1
        );
    }
}

#[test]
fn level_4_by_hand_gives_the_example_s_coefficients_and_stresses() {
    // p. E4-13: with Ka = 0.283, Kr(8.12 ft) = 0.558 and Kr(10.62 ft) = 0.512; σv-soil = 1.02 and
    // 1.33 ksf; σH-soil = 0.76 and 0.92 ksf, 0.84 on average; σH-surcharge 0.18 ksf; σH = 1.02 ksf
    let ka = 0.283;
    let kr = |z: f64| simplified::lateral_ratio(ReinforcementKind::BarMat, z, TRANSITION) * ka;
    assert!(rounds_to(kr(8.12), 0.558, 3), "Kr(8.12) = {}", kr(8.12));
    assert!(rounds_to(kr(10.62), 0.512, 3), "Kr(10.62) = {}", kr(10.62));
    let load = simplified::layer_load(ReinforcementKind::BarMat, ka, UNIT_WEIGHT, 8.12, 10.62, SURCHARGE, TRANSITION);
    let soil_only = simplified::layer_load(ReinforcementKind::BarMat, ka, UNIT_WEIGHT, 8.12, 10.62, 0.0, TRANSITION);
    let factored = |s: f64| simplified::EARTH_LOAD_FACTOR * s;
    assert!(
        rounds_to(factored(soil_only.horizontal_stress), 0.84, 2),
        "σH-soil {}",
        factored(soil_only.horizontal_stress)
    );
    let surcharge_part = factored(load.horizontal_stress - soil_only.horizontal_stress);
    assert!(rounds_to(surcharge_part, 0.18, 2), "σH-surcharge {surcharge_part}");
    assert!(rounds_to(factored(load.horizontal_stress), 1.02, 2), "σH {}", factored(load.horizontal_stress));
    // Svt = 2.50 ft, Atrib = 12.50 ft²: T_max = 12.75 k per panel (p. E4-13), to the printed 0.01
    // of σH's rounding
    let t = factored(load.horizontal_stress) * 2.5 * PANEL_WIDTH;
    assert!((t - 12.75).abs() <= 0.005 * 12.5 + 0.005, "T_max {t}");
}

#[test]
fn the_pullout_resistance_beyond_the_bilinear_surface_is_the_example_s() {
    for (k, &(z, spacing, _, _, f_star, le, phi_pr)) in TABLE.iter().enumerate() {
        let f = pullout::bar_mat_pullout_factor(WIRE, spacing, z, TRANSITION);
        assert!(rounds_to(f, f_star, 3), "level {}: F* = {f:.4}, the example's {f_star}", k + 1);
        let active = pullout::active_zone_width(ReinforcementKind::BarMat, H, z, friction_angle());
        // per foot of mat width, α = 1 (welded, inextensible), σv unfactored without the surcharge
        let r = pullout::resistance(f, 1.0, UNIT_WEIGHT * z, L, active, 1.0);
        assert!(rounds_to(r.embedment, le, 2), "level {}: Le = {:.4} ft, the example's {le}", k + 1, r.embedment);
        assert!(
            (r.factored_resistance - phi_pr).abs() <= 5e-3 * phi_pr,
            "level {}: φ·Pr = {:.3} k/ft, the example's {phi_pr}",
            k + 1,
            r.factored_resistance
        );
    }
    // level 4 by hand (pp. E4-16, E4-17): Le = 18 − 0.3·25.64 = 10.31 ft, Pr = 23.06 k/ft
    let r = pullout::resistance(0.955, 1.0, UNIT_WEIGHT * 9.37, L, 0.3 * H, 1.0);
    assert!(rounds_to(r.resistance, 23.06, 2), "Pr = {}", r.resistance);
    assert!(rounds_to(r.factored_resistance, 20.75, 2), "φ·Pr = {}", r.factored_resistance);
}
