//! A direct-shear curve from a law: a uniform slip under a uniform σn (docs/verification.md §4, the
//! block on a rigid base with the displacement applied to every node), so τ(δ) is the law itself,
//! evaluated along the measured slips in order with its history carried from point to point.
//!
//! The measured δ is the box's relative displacement: the Ks fitted includes the compliance of the
//! soil in the box, as the curve a user reads by hand would.

use crate::interface::law::{ShearLaw, ShearState};

/// τ at each slip of `slips` (in the order given), under `sigma_n`.
pub fn curve(law: &ShearLaw, sigma_n: f64, slips: &[f64]) -> Vec<f64> {
    let mut state = ShearState::default();
    slips
        .iter()
        .map(|&s| {
            let r = law.response(&state, s, sigma_n);
            state = r.state;
            r.tau
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coulomb_curve_is_elastic_to_the_peak_then_flat() {
        let law = ShearLaw::Coulomb { shear_stiffness: 1000.0, cohesion: 0.0, tan_friction: 0.5 };
        // σn = 40: τp = 20 at δ = 0.02
        let tau = curve(&law, 40.0, &[0.0, 0.01, 0.02, 0.05]);
        assert_eq!(tau, vec![0.0, 10.0, 20.0, 20.0]);
    }
}
