//! Pull-out resistance of a layer beyond the failure surface (AASHTO LRFD §11.10.6.3;
//! FHWA-NHI-10-024 §4.4.7b; as computed in FHWA-NHI-10-025 Examples E1 and E4):
//! Pr = F*·α·σv·Le·C·Rc per unit width, with C = 2 (a sheet, grid or mat resists on both faces).
//!
//! - σv is the weight of the fill above the layer, unfactored, without the surcharge (Example E4,
//!   p. E4-16: "use unfactored vertical stress for pullout resistance", the live load "not
//!   included").
//! - The failure surface, through the toe: for extensible (geosynthetic) reinforcement Rankine's
//!   plane at 45° + φ/2, so the active zone at depth Z is La = (H − Z)·tan(45° − φ/2) wide; for
//!   inextensible reinforcement the bilinear surface, La = 0.3·H above mid-height and 0.6·(H − Z)
//!   below it.
//! - F*: 0.67·tan φ for a geosynthetic without a pull-out test; for a bar mat or welded-wire grid
//!   the passive resistance of its transverse bars, 20·t/St at the crest falling linearly to
//!   10·t/St at 6 m (20 ft) and below (Example E4, p. E4-16).
//! - The check: φ·Pr ≥ T_max with φ = 0.90 (Example E4, Table E4-5.2).

use super::parameters::ReinforcementKind;

/// C: a sheet, grid or mat resists on its two faces.
pub const SURFACE_FACTOR: f64 = 2.0;
/// The resistance factor of pull-out, φ (AASHTO LRFD Table 11.5.7-1; Example E4, Table E4-5.2).
pub const RESISTANCE_FACTOR: f64 = 0.90;
/// The shortest embedment beyond the failure surface (AASHTO LRFD §11.10.6.3.2: 0.9 m, 3 ft).
pub const MINIMUM_EMBEDMENT_M: f64 = 0.9;

/// The width of the active zone at depth `depth` of a wall of height `height`, from the face to
/// the failure surface.
pub fn active_zone_width(kind: ReinforcementKind, height: f64, depth: f64, friction_angle: f64) -> f64 {
    let depth = depth.clamp(0.0, height);
    if kind.is_extensible() {
        // tan(45° − φ/2) = √Ka
        (height - depth) * super::simplified::active_coefficient(friction_angle).sqrt()
    } else if depth <= 0.5 * height {
        0.3 * height
    } else {
        0.6 * (height - depth)
    }
}

/// The default F* of a geosynthetic without a pull-out test, 0.67·tan φ.
pub fn geosynthetic_pullout_factor(friction_angle: f64) -> f64 {
    0.67 * friction_angle.tan()
}

/// F* of a bar mat or welded-wire grid at depth `depth`, from the thickness `bar_thickness` and
/// spacing `bar_spacing` of its transverse bars: 20·t/St at the crest to 10·t/St at
/// `transition_depth` (6 m; 20 ft) and below.
pub fn bar_mat_pullout_factor(bar_thickness: f64, bar_spacing: f64, depth: f64, transition_depth: f64) -> f64 {
    let s = (depth / transition_depth).clamp(0.0, 1.0);
    bar_thickness / bar_spacing * (20.0 + (10.0 - 20.0) * s)
}

/// A layer's pull-out resistance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulloutResistance {
    /// F* at the layer.
    pub pullout_factor: f64,
    /// La: from the face to the failure surface.
    pub active_length: f64,
    /// Le = L − La (zero when the layer ends inside the active zone).
    pub embedment: f64,
    /// Pr = F*·α·σv·Le·C·Rc, nominal.
    pub resistance: f64,
    /// φ·Pr.
    pub factored_resistance: f64,
}

/// Pr = F*·α·σv·Le·C·Rc and φ·Pr of a layer with F* `pullout_factor`, α `scale_correction` and
/// Rc `coverage_ratio`, under the vertical stress `vertical_stress`, with `active_length` of its
/// `length` inside the active zone.
pub fn resistance(
    pullout_factor: f64,
    scale_correction: f64,
    vertical_stress: f64,
    length: f64,
    active_length: f64,
    coverage_ratio: f64,
) -> PulloutResistance {
    let embedment = (length - active_length).max(0.0);
    let resistance = pullout_factor * scale_correction * vertical_stress * embedment * SURFACE_FACTOR * coverage_ratio;
    PulloutResistance {
        pullout_factor,
        active_length,
        embedment,
        resistance,
        factored_resistance: RESISTANCE_FACTOR * resistance,
    }
}
