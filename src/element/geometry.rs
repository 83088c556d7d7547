//! What the 2-D mesh stands for: a slice of unit width of a long body (plane strain) or a
//! meridian plane of a body of revolution about the y axis (axisymmetric, x = r ≥ 0, y = z).
//!
//! Axisymmetric quantities are totals over the whole circumference: an element's volume is
//! ∫2πr dA, a line's area ∫2πr ds, so that nodal forces, reactions, interface forces and a
//! reinforcement's pull are in kN (not per radian, not per metre). Zienkiewicz & Taylor, The Finite
//! Element Method, vol. 1, §6.2 (6th ed.): the hoop strain εθ = u_r/r is the fourth strain.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Plane strain (per metre width) or axisymmetric (about the y axis, totals over 2π).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Geometry {
    #[default]
    PlaneStrain,
    Axisymmetric,
}

impl Geometry {
    /// The measure per unit of 2-D length or area at a point: 1 (per metre width) in plane strain,
    /// the circumference 2πr in axisymmetry.
    pub fn circumference(self, x: [f64; 2]) -> f64 {
        match self {
            Geometry::PlaneStrain => 1.0,
            Geometry::Axisymmetric => 2.0 * std::f64::consts::PI * x[0],
        }
    }

    pub fn is_axisymmetric(self) -> bool {
        self == Geometry::Axisymmetric
    }

    pub fn name(self) -> &'static str {
        match self {
            Geometry::PlaneStrain => "plane strain",
            Geometry::Axisymmetric => "axisymmetric",
        }
    }

    /// The unit of a force in the outputs, for a model whose force unit is `force` and length unit
    /// `length`: per metre width in plane strain, a total in axisymmetry.
    pub fn force_unit(self, force: &str, length: &str) -> String {
        match self {
            Geometry::PlaneStrain => format!("{force}/{length}"),
            Geometry::Axisymmetric => force.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_weighs_one_and_axisymmetry_the_circumference() {
        assert_eq!(Geometry::PlaneStrain.circumference([3.0, 1.0]), 1.0);
        let c = Geometry::Axisymmetric.circumference([0.5, 7.0]);
        assert!((c - std::f64::consts::PI).abs() < 1e-15);
    }
}
