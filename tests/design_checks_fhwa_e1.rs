//! The pull-out resistance of geogrid layers beyond Rankine's plane, against a worked design
//! example.
//!
//! Reference: FHWA-NHI-10-025 (GEC 011 Volume II, 2009), Appendix E, Example E1: a geogrid wall
//! with a modular block facing, H = 20 ft, L = 18 ft, eleven layers, reinforced fill γ = 125 pcf,
//! φ = 34°, under a 2H:1V broken backslope; F* = 0.45 and α = 0.8 (p. E1-16), C = 2, Rc = 1
//! (docs/verification.md §12). Its Table E1-7.5 gives, per layer, La, Le, the height of soil Zp
//! over the middle of Le (the backslope's), and Pr.
//!
//! The table's numbers were read from a transcription of it (the manual's page with the table was
//! not seen); all eleven rows satisfy Pr = F*·α·γ·Zp·Le·C to the lb/ft, which is good evidence that
//! they were copied right.
//!
//! Checked: the default F* = 0.67·tan φ gives the example's 0.45; La = (H − Z)·tan(45° − φ/2)
//! within 0.015 ft of the printed La (the example rounds tan 28° to 0.532, 0.01 ft at most);
//! Pr from the printed Le and Zp within 1 lb/ft (its rounding); Pr from La computed afresh within
//! 0.3 % (measured 0.10 %).

use geoslip::design::pullout;
use geoslip::design::ReinforcementKind;

const H: f64 = 20.0; // ft
const L: f64 = 18.0; // ft
const UNIT_WEIGHT: f64 = 125.0; // pcf
const F_STAR: f64 = 0.45;
const ALPHA: f64 = 0.8;

/// Table E1-7.5: Z, La, Le, Zp [ft], Pr [lb/ft].
const TABLE: [(f64, f64, f64, f64, f64); 11] = [
    (0.67, 10.28, 7.72, 7.74, 5378.0),
    (2.67, 9.22, 8.78, 9.47, 7483.0),
    (4.67, 8.16, 9.84, 11.21, 9928.0),
    (6.67, 7.09, 10.91, 12.94, 12706.0),
    (8.67, 6.03, 11.97, 14.68, 15815.0),
    (10.67, 4.96, 13.04, 16.41, 19259.0),
    (12.67, 3.90, 14.10, 18.14, 23020.0),
    (14.67, 2.84, 15.16, 19.88, 27124.0),
    (16.67, 1.77, 16.23, 21.61, 31566.0),
    (18.67, 0.71, 17.29, 23.35, 36335.0),
    (19.33, 0.36, 17.64, 23.92, 37975.0),
];

fn friction_angle() -> f64 {
    34f64.to_radians()
}

#[test]
fn the_default_pullout_factor_is_the_example_s() {
    let f = pullout::geosynthetic_pullout_factor(friction_angle());
    assert!((f - F_STAR).abs() <= 0.005, "F* = {f}");
}

#[test]
fn the_active_zone_and_the_resistance_of_every_layer_are_the_example_s() {
    for &(z, la, le, zp, pr) in &TABLE {
        let active = pullout::active_zone_width(ReinforcementKind::Geogrid, H, z, friction_angle());
        assert!((active - la).abs() <= 0.015, "Z = {z} ft: La = {active:.4} ft, the example's {la}");
        // with the example's own La and the soil over the middle of Le
        let r = pullout::resistance(F_STAR, ALPHA, UNIT_WEIGHT * zp, L, la, 1.0);
        assert!((r.embedment - le).abs() <= 1e-9, "Z = {z} ft: Le = {}", r.embedment);
        assert!((r.resistance - pr).abs() <= 1.0, "Z = {z} ft: Pr = {:.1} lb/ft, the example's {pr}", r.resistance);
        // with La computed afresh (and Zp over the middle of that Le, under the 2H:1V slope that
        // rises from the face to x = L)
        let zp_afresh = z + 0.5 * (0.5 * (active + L));
        let r = pullout::resistance(F_STAR, ALPHA, UNIT_WEIGHT * zp_afresh, L, active, 1.0);
        assert!(
            (r.resistance - pr).abs() <= 3e-3 * pr,
            "Z = {z} ft: Pr = {:.1} lb/ft, the example's {pr}",
            r.resistance
        );
    }
}
