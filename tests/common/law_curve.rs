//! The interface laws' monotonic curves, written from their definitions in docs/model-format.md
//! (not from geoslip's law code), for tests whose data must come from elsewhere.
#![allow(dead_code)]

use geoslip::model::file::ShearLawSpec;

/// τ at slip `s` ≥ 0 of a monotonic shear under σn = `q`: Coulomb min(Ks·s, c + q·tan φ);
/// softening elastic up to τp = c + q·tan φ, then τp − (τp − τr)·κ/κs in the plastic slip
/// κ = s − τ/Ks down to τr = c_r + q·tan φ_r; hyperbolic Ks·s/(1 + Ks·s/τp).
pub fn monotonic(law: &ShearLawSpec, q: f64, s: f64) -> f64 {
    let strength = |c: f64, phi: f64| c + q * phi.to_radians().tan();
    match *law {
        ShearLawSpec::Coulomb { shear_stiffness: ks, cohesion, friction_angle } => {
            (ks * s).min(strength(cohesion, friction_angle))
        }
        ShearLawSpec::Softening {
            shear_stiffness: ks,
            cohesion,
            friction_angle,
            residual_cohesion,
            residual_friction_angle,
            softening_slip,
        } => {
            let (peak, residual) =
                (strength(cohesion, friction_angle), strength(residual_cohesion, residual_friction_angle));
            if ks * s <= peak {
                return ks * s;
            }
            // s = κ + τ/Ks with τ = τp − (τp − τr)·κ/κs (no snap-back: (τp − τr)/κs < Ks)
            let slope = (peak - residual) / softening_slip;
            assert!(slope < ks, "the curve snaps back");
            let kappa = (s - peak / ks) / (1.0 - slope / ks);
            if kappa < softening_slip {
                peak - slope * kappa
            } else {
                residual
            }
        }
        ShearLawSpec::Hyperbolic { shear_stiffness: ks, cohesion, friction_angle } => {
            ks * s / (1.0 + ks * s / strength(cohesion, friction_angle))
        }
        ref other => panic!("no closed form written for {other:?}"),
    }
}
