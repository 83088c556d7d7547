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
    /// their stresses). `consistent`: whether the caller uses a plastic point's tangent (a
    /// hardening soil or a Duncan–Chang soil differentiates its update for it, at four more
    /// integrations; without, it gives its elasticity or the last substep's return).
    pub fn update(
        &self,
        elastic: &PlaneStrain,
        committed: &PointState,
        d_strain: [f64; 4],
        consistent: bool,
    ) -> (StressUpdate, PointState, PlaneStrain) {
        let mut state = *committed;
        let (update, elasticity) = match self {
            SoilLaw::MohrCoulomb(law) => {
                (mohr_coulomb::update_with_hoop(law, elastic, committed.stress, d_strain), *elastic)
            }
            SoilLaw::DuncanChang(law) => {
                let u = law.update(committed.stress, committed.largest_stress_state, d_strain, consistent);
                state.largest_stress_state = u.stress_state_max;
                (u.update, u.elasticity)
            }
            SoilLaw::HardeningSoil(law) => {
                let u = law.update(
                    committed.stress,
                    committed.shear_hardening,
                    committed.preconsolidation,
                    d_strain,
                    consistent,
                );
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

    /// The elasticity an increment's first iteration predicts with: the point's at its committed
    /// state (a Mohr–Coulomb soil's `elastic`, a hardening soil's Eur at its stress), or `None`
    /// for the moduli at the updated stress. A Duncan–Chang soil takes the latter: its moduli at
    /// the committed state, at its largest stress state where the loading criterion blends towards
    /// Eur, predicted worse on the triaxial test of verification §11 (69 cutbacks against 21 on
    /// tri6).
    pub fn predictor_elasticity(&self, elastic: &PlaneStrain, committed: &PointState) -> Option<PlaneStrain> {
        match self {
            SoilLaw::MohrCoulomb(_) => Some(*elastic),
            SoilLaw::DuncanChang(_) => None,
            SoilLaw::HardeningSoil(law) => Some(law.elasticity(&committed.stress)),
        }
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
            // a plastic point's tangent is its update's derivative, unsymmetric where the moduli
            // change along it
            SoilLaw::DuncanChang(_) => true,
            // the shear hardening's flow (ψm) is never its gradient's
            SoilLaw::HardeningSoil(_) => true,
        }
    }
}
