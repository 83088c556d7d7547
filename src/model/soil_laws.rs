//! The soil laws a model's materials make: each soil element's law (Mohr–Coulomb, Duncan–Chang or
//! hardening soil, with the defaults of the parameters not given) and the elasticity of its
//! matrices.

use super::file::{self, SoilMaterial};
use super::Model;

impl Model {
    /// The law of a soil element that keeps its stresses (Mohr–Coulomb, Duncan–Chang or hardening
    /// soil), or `None` when its soil is linear elastic.
    pub fn soil_law(&self, solid: usize) -> Option<crate::element::soil_law::SoilLaw> {
        self.law_of(self.soil(solid))
    }

    /// The soil of this element keeps its stresses (Mohr–Coulomb, Duncan–Chang or hardening soil):
    /// its stress is read as committed, not from its strain.
    pub fn keeps_stresses(&self, solid: usize) -> bool {
        self.soil(solid).model != file::SoilModel::LinearElastic
    }

    /// The law of a soil material, as [`soil_law`](Self::soil_law).
    pub(super) fn law_of(&self, m: &SoilMaterial) -> Option<crate::element::soil_law::SoilLaw> {
        use crate::element::soil_law::SoilLaw;
        let phi = m.friction_angle.to_radians();
        match m.model {
            file::SoilModel::LinearElastic => None,
            file::SoilModel::MohrCoulomb => {
                let apex = if phi > 0.0 { m.cohesion / phi.tan() } else { f64::INFINITY };
                Some(SoilLaw::MohrCoulomb(crate::element::mohr_coulomb::MohrCoulomb {
                    cohesion: m.cohesion,
                    friction_angle: phi,
                    dilatancy_angle: m.dilatancy_angle.to_radians(),
                    tensile_strength: m.tensile_strength.unwrap_or(apex).min(apex),
                }))
            }
            file::SoilModel::DuncanChang => {
                let h = m.hyperbolic.as_ref().expect("a Duncan–Chang soil's parameters were checked");
                Some(SoilLaw::DuncanChang(crate::element::duncan_chang::DuncanChang {
                    modulus_number: h.modulus_number,
                    modulus_exponent: h.n,
                    failure_ratio: h.failure_ratio,
                    bulk_modulus_number: h.bulk_modulus_number,
                    bulk_modulus_exponent: h.m,
                    unloading_modulus_number: h.unloading_modulus_number,
                    cohesion: m.cohesion,
                    friction_angle: phi,
                    friction_angle_drop: h.delta_phi.to_radians(),
                    dilatancy_angle: m.dilatancy_angle.to_radians(),
                    atmospheric_pressure: h.pa.unwrap_or_else(|| Model::atmospheric_pressure(&self.units)),
                }))
            }
            file::SoilModel::HardeningSoil => Some(SoilLaw::HardeningSoil(
                Model::hardening_soil(m, &self.units)
                    .and_then(Result::ok)
                    .expect("a hardening soil's parameters were checked"),
            )),
        }
    }

    /// A hardening soil's law from its material, with the defaults of the parameters not given;
    /// `None` without its `hardening` table.
    ///
    /// # Errors
    /// [`CapMisfit`](crate::element::hardening_soil::CapMisfit) when no cap gives its Eoedref and
    /// K0nc.
    pub fn hardening_soil(
        m: &SoilMaterial,
        units: &file::Units,
    ) -> Option<Result<crate::element::hardening_soil::HardeningSoil, crate::element::hardening_soil::CapMisfit>> {
        use crate::element::hardening_soil::{HardeningParameters, HardeningSoil};
        let h = m.hardening.as_ref()?;
        let phi = m.friction_angle.to_radians();
        Some(HardeningSoil::new(HardeningParameters {
            secant_modulus: h.secant_modulus,
            oedometer_modulus: h.oedometer_modulus.unwrap_or(h.secant_modulus),
            unloading_modulus: h.unloading_modulus.unwrap_or(3.0 * h.secant_modulus),
            unloading_poissons_ratio: h.nu_ur.unwrap_or(0.2),
            power: h.m,
            reference_pressure: h.p_ref.unwrap_or_else(|| Model::atmospheric_pressure(units) * 100.0 / 101.325),
            failure_ratio: h.failure_ratio.unwrap_or(0.9),
            k0_nc: m.k0(),
            cohesion: m.cohesion,
            friction_angle: phi,
            dilatancy_angle: m.dilatancy_angle.to_radians(),
        }))
    }

    /// The elasticity of a soil element's matrices: E and ν as given, a Duncan–Chang soil's unloading
    /// moduli at σ3 = pa, or a hardening soil's Eur and νur at σ3 = pref (their stiffness follows
    /// their stresses; this is its reference).
    pub fn elasticity(&self, solid: usize) -> crate::element::solid::PlaneStrain {
        match self.soil_law(solid) {
            Some(crate::element::soil_law::SoilLaw::DuncanChang(law)) => law.reference_elasticity(),
            Some(crate::element::soil_law::SoilLaw::HardeningSoil(law)) => law.reference_elasticity(),
            _ => {
                let m = self.soil(solid);
                crate::element::solid::PlaneStrain {
                    youngs_modulus: m.youngs_modulus.expect("E was checked"),
                    poissons_ratio: m.poissons_ratio.expect("ν was checked"),
                }
            }
        }
    }
}
