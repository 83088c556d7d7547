//! The law of a soil element that keeps its stress at its Gauss points: Mohr–Coulomb, or
//! Duncan–Chang. (A linear-elastic element keeps a reference state instead, and has none.)

use super::duncan_chang::DuncanChang;
use super::mohr_coulomb::{self, MohrCoulomb, StressUpdate};
use super::soil_state::PointState;
use super::solid::PlaneStrain;

/// A soil law with a stress state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SoilLaw {
    MohrCoulomb(MohrCoulomb),
    DuncanChang(DuncanChang),
}

impl SoilLaw {
    /// The point's stress after the strain increment `d_strain` (εxx, εyy, γxy, εzz) from its
    /// committed state, with the tangent; its state to keep; and its tangent without the plastic
    /// part (a Mohr–Coulomb soil's elasticity, a Duncan–Chang soil's moduli at the new stress).
    /// `elastic` is a Mohr–Coulomb soil's elasticity (a Duncan–Chang soil's follows its
    /// stresses).
    pub fn update(
        &self,
        elastic: &PlaneStrain,
        committed: &PointState,
        d_strain: [f64; 4],
    ) -> (StressUpdate, PointState, PlaneStrain) {
        let (update, largest_stress_state, elasticity) = match self {
            SoilLaw::MohrCoulomb(law) => (
                mohr_coulomb::update_with_hoop(law, elastic, committed.stress, d_strain),
                committed.largest_stress_state,
                *elastic,
            ),
            SoilLaw::DuncanChang(law) => {
                let u = law.update(committed.stress, committed.largest_stress_state, d_strain);
                (u.update, u.stress_state_max, u.elasticity)
            }
        };
        let state = PointState {
            stress: update.stress,
            plastic_strain: committed.plastic_strain + update.plastic_strain,
            yield_state: update.state,
            largest_stress_state,
        };
        (update, state, elasticity)
    }

    /// Whether the stiffness follows the stresses even where the soil does not yield.
    pub fn is_nonlinear_elastic(&self) -> bool {
        matches!(self, SoilLaw::DuncanChang(_))
    }

    /// The law with c/F and tan φ/F (strength reduction).
    pub fn reduced(&self, factor: f64) -> SoilLaw {
        match self {
            SoilLaw::MohrCoulomb(law) => SoilLaw::MohrCoulomb(law.reduced(factor)),
            SoilLaw::DuncanChang(law) => SoilLaw::DuncanChang(law.reduced(factor)),
        }
    }

    /// Whether its plastic flow is non-associated (ψ ≠ φ): an unsymmetric consistent tangent.
    pub fn non_associated(&self) -> bool {
        match self {
            SoilLaw::MohrCoulomb(law) => law.dilatancy_angle != law.friction_angle,
            SoilLaw::DuncanChang(law) => law.dilatancy_angle != law.friction_angle || law.friction_angle_drop != 0.0,
        }
    }
}
