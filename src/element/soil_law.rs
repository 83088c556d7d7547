//! The law of a soil element that keeps its stress at its Gauss points: Mohr–Coulomb,
//! Duncan–Chang or hardening soil. (A linear-elastic element keeps a reference state instead, and
//! has none.)

use super::duncan_chang::DuncanChang;
use super::hardening_soil::HardeningSoil;
use super::mohr_coulomb::{self, MohrCoulomb, StressUpdate};
use super::soil_state::PointState;
use super::solid::PlaneStrain;

/// A soil law with a stress state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SoilLaw {
    MohrCoulomb(MohrCoulomb),
    DuncanChang(DuncanChang),
    HardeningSoil(HardeningSoil),
}

impl SoilLaw {
    /// The point's stress after the strain increment `d_strain` (εxx, εyy, γxy, εzz) from its
    /// committed state, with the tangent; its state to keep; and its tangent without the plastic
    /// part (a Mohr–Coulomb soil's elasticity, a Duncan–Chang soil's moduli or a hardening soil's
    /// Eur at the new stress). `elastic` is a Mohr–Coulomb soil's elasticity (the others' follows
    /// their stresses).
    pub fn update(
        &self,
        elastic: &PlaneStrain,
        committed: &PointState,
        d_strain: [f64; 4],
    ) -> (StressUpdate, PointState, PlaneStrain) {
        let mut state = *committed;
        let (update, elasticity) = match self {
            SoilLaw::MohrCoulomb(law) => {
                (mohr_coulomb::update_with_hoop(law, elastic, committed.stress, d_strain), *elastic)
            }
            SoilLaw::DuncanChang(law) => {
                let u = law.update(committed.stress, committed.largest_stress_state, d_strain);
                state.largest_stress_state = u.stress_state_max;
                (u.update, u.elasticity)
            }
            SoilLaw::HardeningSoil(law) => {
                let u = law.update(committed.stress, committed.shear_hardening, committed.preconsolidation, d_strain);
                state.shear_hardening = u.shear_hardening;
                state.preconsolidation = u.preconsolidation;
                (u.update, u.elasticity)
            }
        };
        state.stress = update.stress;
        state.plastic_strain = committed.plastic_strain + update.plastic_strain;
        state.yield_state = update.state;
        (update, state, elasticity)
    }

    /// Whether the stiffness follows the stresses even where the soil does not yield.
    pub fn is_nonlinear_elastic(&self) -> bool {
        matches!(self, SoilLaw::DuncanChang(_) | SoilLaw::HardeningSoil(_))
    }

    /// The law with c/F and tan φ/F (strength reduction).
    pub fn reduced(&self, factor: f64) -> SoilLaw {
        match self {
            SoilLaw::MohrCoulomb(law) => SoilLaw::MohrCoulomb(law.reduced(factor)),
            SoilLaw::DuncanChang(law) => SoilLaw::DuncanChang(law.reduced(factor)),
            SoilLaw::HardeningSoil(law) => SoilLaw::HardeningSoil(law.reduced(factor)),
        }
    }

    /// Whether its plastic flow is non-associated (ψ ≠ φ): an unsymmetric consistent tangent.
    pub fn non_associated(&self) -> bool {
        match self {
            SoilLaw::MohrCoulomb(law) => law.dilatancy_angle != law.friction_angle,
            SoilLaw::DuncanChang(law) => law.dilatancy_angle != law.friction_angle || law.friction_angle_drop != 0.0,
            // the shear hardening's flow (ψm) is never its gradient's
            SoilLaw::HardeningSoil(_) => true,
        }
    }
}
