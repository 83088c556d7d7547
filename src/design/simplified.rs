//! The Simplified Method of AASHTO LRFD §11.10.6.2.1 (FHWA-NHI-10-024 §4.4.7a): each layer
//! carries the lateral pressure σH = Kr·σv over its tributary height Svt, T_max = σH·Svt.
//!
//! As the manual's worked example computes it (FHWA-NHI-10-025 Example E4, pp. E4-10 to E4-13):
//! - σv = γ·z + q, with a uniform surcharge on the crest taken, inside the reinforced fill, as a
//!   vertical earth load (EV);
//! - Kr = (Kr/Ka)·Ka, where Kr/Ka is 1 for geosynthetics and falls linearly from 2.5 at the crest to
//!   1.2 at 6 m (20 ft) depth for bar mats and welded-wire grids, constant below;
//! - σH is the average of σH = Kr·σv at the top and the bottom of the layer's tributary zone;
//! - the factored load takes the load factor of vertical earth pressure, γP,EV = 1.35, on both the
//!   soil and the surcharge.

use super::parameters::ReinforcementKind;

/// The load factor of vertical earth pressure, EV, at its maximum (AASHTO LRFD Table 3.4.1-2;
/// Example E4, Table E4-5.1), applied to the soil's and the surcharge's lateral stress.
pub const EARTH_LOAD_FACTOR: f64 = 1.35;

/// Rankine's active earth pressure coefficient of a vertical face behind a horizontal backfill,
/// Ka = tan²(45° − φ/2), for a friction angle `friction_angle` in radians.
pub fn active_coefficient(friction_angle: f64) -> f64 {
    (std::f64::consts::FRAC_PI_4 - 0.5 * friction_angle).tan().powi(2)
}

/// Kr/Ka at depth `depth` below the crest (AASHTO LRFD Figure 11.10.6.2.1-3), the metallic curve
/// reaching its deep value at `transition_depth` (6 m; 20 ft).
pub fn lateral_ratio(kind: ReinforcementKind, depth: f64, transition_depth: f64) -> f64 {
    match kind {
        ReinforcementKind::Geogrid | ReinforcementKind::Geotextile => 1.0,
        ReinforcementKind::BarMat => {
            let s = (depth / transition_depth).clamp(0.0, 1.0);
            2.5 + (1.2 - 2.5) * s
        }
    }
}

/// A layer's load by the Simplified Method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimplifiedLoad {
    /// σH, unfactored, averaged over the tributary zone.
    pub horizontal_stress: f64,
    /// T_max = σH·Svt, unfactored.
    pub max_tension: f64,
    /// T_max with the load factor γP,EV.
    pub factored_max_tension: f64,
}

/// The Simplified Method's load per unit width of a layer whose tributary zone runs from depth
/// `zone_top` to `zone_bottom` below the crest, in a fill of unit weight `unit_weight` whose active
/// coefficient is `ka`, under a uniform surcharge `surcharge`.
pub fn layer_load(
    kind: ReinforcementKind,
    ka: f64,
    unit_weight: f64,
    zone_top: f64,
    zone_bottom: f64,
    surcharge: f64,
    transition_depth: f64,
) -> SimplifiedLoad {
    let sigma_h = |z: f64| lateral_ratio(kind, z, transition_depth) * ka * (unit_weight * z + surcharge);
    let horizontal_stress = 0.5 * (sigma_h(zone_top) + sigma_h(zone_bottom));
    let max_tension = horizontal_stress * (zone_bottom - zone_top);
    SimplifiedLoad { horizontal_stress, max_tension, factored_max_tension: EARTH_LOAD_FACTOR * max_tension }
}
