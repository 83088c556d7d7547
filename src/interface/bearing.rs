//! Passive bearing of a geogrid's transverse members: the bounds of Jewell, Milligan, Sarsby &
//! Dubois (1984), "Interaction between soil and geogrids", Proc. Symposium on Polymer Grid
//! Reinforcement in Civil Engineering, Thomas Telford, London, pp. 18–30, as quoted by Jewell
//! (1996), "Soil reinforcement with geotextiles", CIRIA SP123, §6.3, and by Palmeira (2009),
//! "Soil–geosynthetic interaction: modelling and analysis", Geotextiles and Geomembranes 27(5),
//! 368–390.
//!
//! Members of thickness B every S along the reinforcement, a fraction αb of its width bearing: per
//! unit length of reinforcement they resist with (αb·B/S)·σb, σb the bearing stress on a member.
//! The bounds give σb as a multiple of the normal stress σn′ on the grid, φ′ the soil's peak angle
//! of shearing resistance (not the interface's angle):
//!
//! ```text
//! general shear (upper bound):   σb/σn′ = exp(π·tan φ′)·tan²(π/4 + φ′/2)
//! punching shear (lower bound):  σb/σn′ = exp((π/2 + φ′)·tan φ′)·tan(π/4 + φ′/2)
//! ```
//!
//! The general-shear mechanism is the strip footing's turned on its side, so the upper bound is
//! the Prandtl–Reissner bearing-capacity factor Nq (18.40 at φ′ = 30°, where the punching bound is
//! 5.804). Values, and the pull-out they give: docs/verification.md §8.
//!
//! The resistance is shared by the grid's two faces (half on each, per unit face area
//! τb,max = (αb·B/(2S))·(σb/σn′)·σn′ with each face's own σn′) and mobilised linearly over a stated
//! relative displacement δb: τb = τb,max·m, m = (s − s_b)/δb clipped to ±1, s_b the bearing's
//! plastic slip (it unloads with the same slope and bears again in the reversed direction).

/// A face's bearing contribution.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bearing {
    /// τb,max per unit σn′ on one face: αb·B·(σb/σn)/(2S).
    pub coefficient: f64,
    /// Displacement δb over which the bearing is mobilised [length].
    pub mobilisation: f64,
}

/// The bearing at a trial slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BearingResponse {
    pub tau: f64,
    /// dτb/ds at constant σn′.
    pub tangent: f64,
    /// dτb/dσn′ at constant slip.
    pub d_tau_d_sigma: f64,
    /// The bearing's plastic slip this slip would leave.
    pub plastic_slip: f64,
    /// Fully mobilised.
    pub full: bool,
}

/// σb/σn′ of a transverse member failing in general shear, Jewell et al.'s (1984) upper bound
/// exp(π·tan φ′)·tan²(π/4 + φ′/2); `tan_phi` is tan φ′, φ′ the soil's peak angle of shearing
/// resistance.
pub fn general_shear_ratio(tan_phi: f64) -> f64 {
    let phi = tan_phi.atan();
    (std::f64::consts::PI * tan_phi).exp() * (std::f64::consts::FRAC_PI_4 + phi / 2.0).tan().powi(2)
}

/// σb/σn′ of a transverse member failing by punching shear, Jewell et al.'s (1984) lower bound
/// exp((π/2 + φ′)·tan φ′)·tan(π/4 + φ′/2); `tan_phi` is tan φ′, φ′ the soil's peak angle of
/// shearing resistance.
pub fn punching_shear_ratio(tan_phi: f64) -> f64 {
    let phi = tan_phi.atan();
    ((std::f64::consts::FRAC_PI_2 + phi) * tan_phi).exp() * (std::f64::consts::FRAC_PI_4 + phi / 2.0).tan()
}

impl Bearing {
    /// From the members' geometry and σb/σn′: S, B, αb, the ratio, δb.
    pub fn new(spacing: f64, thickness: f64, fraction: f64, ratio: f64, mobilisation: f64) -> Bearing {
        Bearing { coefficient: fraction * thickness * ratio / (2.0 * spacing), mobilisation }
    }

    /// Full bearing stress on one face under σn′ (none in tension).
    pub fn full(&self, sigma_n: f64) -> f64 {
        self.coefficient * sigma_n.max(0.0)
    }

    /// The initial slope τb,max/δb under σn′.
    pub fn stiffness(&self, sigma_n: f64) -> f64 {
        self.full(sigma_n) / self.mobilisation
    }

    /// The bearing at slip `slip` from the committed plastic slip `plastic_slip`, under σn′.
    pub fn response(&self, plastic_slip: f64, slip: f64, sigma_n: f64) -> BearingResponse {
        let full = self.full(sigma_n);
        let coupling = if sigma_n > 0.0 { self.coefficient } else { 0.0 };
        let m = (slip - plastic_slip) / self.mobilisation;
        if m.abs() <= 1.0 {
            return BearingResponse {
                tau: full * m,
                tangent: full / self.mobilisation,
                d_tau_d_sigma: coupling * m,
                plastic_slip,
                full: false,
            };
        }
        let sign = m.signum();
        BearingResponse {
            tau: full * sign,
            tangent: 0.0,
            d_tau_d_sigma: coupling * sign,
            plastic_slip: slip - sign * self.mobilisation,
            full: true,
        }
    }
}

#[cfg(test)]
mod tests {
    //! The formulas against the published bounds' values, and the mobilisation's loop.
    use super::*;

    #[test]
    fn the_ratios_are_the_published_bounds_from_twenty_to_forty_degrees() {
        // (φ′ [°], general shear = upper bound, punching shear = lower bound): the table of
        // docs/verification.md §8, computed with python3 from Jewell et al.'s (1984) bounds as
        // Jewell (1996) and Palmeira (2009) quote them, exp(π·tan φ′)·tan²(π/4 + φ′/2) and
        // exp((π/2 + φ′)·tan φ′)·tan(π/4 + φ′/2), not from this module. They are written to 6
        // significant figures, so they are good to 5e-6 relative: hence 1e-5.
        let published: [(f64, f64, f64); 5] = [
            (20.0, 6.39939, 2.87241),
            (25.0, 10.6621, 4.00208),
            (30.0, 18.4011, 5.80376),
            (35.0, 33.2961, 8.85031),
            (40.0, 64.1952, 14.3934),
        ];
        for (phi, upper, lower) in published {
            let t = phi.to_radians().tan();
            let general = general_shear_ratio(t);
            assert!(((general - upper) / upper).abs() < 1e-5, "general shear at {phi}°: {general} against {upper}");
            let punching = punching_shear_ratio(t);
            assert!(((punching - lower) / lower).abs() < 1e-5, "punching at {phi}°: {punching} against {lower}");
            assert!(punching < general);
        }
    }

    #[test]
    fn mobilised_linearly_then_full_and_unloads_with_the_same_slope() {
        let b = Bearing::new(0.1, 0.005, 1.0, 10.0, 0.01);
        // coefficient 0.005·10/(2·0.1) = 0.25: under σn′ = 40 the full bearing is 10
        let r = b.response(0.0, 0.005, 40.0);
        assert!((r.tau - 5.0).abs() < 1e-12 && !r.full);
        let r = b.response(0.0, 0.03, 40.0);
        assert!((r.tau - 10.0).abs() < 1e-12 && r.full && (r.plastic_slip - 0.02).abs() < 1e-15);
        let back = b.response(r.plastic_slip, 0.025, 40.0);
        assert!((back.tau - 5.0).abs() < 1e-12, "{}", back.tau);
        let reversed = b.response(r.plastic_slip, 0.0, 40.0);
        assert!((reversed.tau + 10.0).abs() < 1e-12 && reversed.full);
        assert_eq!(b.response(0.0, 0.03, -5.0).tau, 0.0);
    }
}
