//! A checked dynamic stage: its time integration, damping, base motion and the boundaries that let
//! waves out (docs/dynamics.md).

use super::ground_motion::GroundMotion;
use super::side::LoadedSide;
use crate::dofs::Direction;

/// A checked dynamic stage.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicPlan {
    /// Δt [s].
    pub time_step: f64,
    /// [s]
    pub duration: f64,
    /// HHT-α's α, in [−1/3, 0].
    pub alpha: f64,
    /// Rayleigh's a0 [1/s] and a1 [s]: C = a0·M + a1·K.
    pub rayleigh: [f64; 2],
    pub lumping: crate::element::mass::Lumping,
    /// The base acceleration in each direction given [length/s²].
    pub base_motion: Vec<(Direction, GroundMotion)>,
    /// g [length/s²]: a soil's density is its unit weight over it.
    pub gravity: f64,
    /// The node sets whose motion the results record.
    pub record: Vec<String>,
    /// The soil's sides with Lysmer–Kuhlemeyer dashpots: the absorbing ones and a compliant
    /// base's.
    pub absorbing: Vec<AbsorbingSide>,
    /// The base is compliant: the motion enters as forces through its dashpots and the
    /// displacements are absolute; otherwise the base is rigid, the supports, and the motion
    /// enters as the inertia force −M·ι·a_g.
    pub compliant_base: bool,
}

/// A side of the soil whose nodes are freed and given dashpots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbsorbingSide {
    pub side: LoadedSide,
    /// The medium beyond it when given (a compliant base's half-space), else the soil's own.
    pub half_space: Option<HalfSpace>,
    /// A compliant base's side: the base motion enters through it.
    pub input: bool,
    /// Whether its dashpots act in (and its supports are freed in) x and y.
    pub directions: [bool; 2],
}

/// An elastic medium's impedances per unit area: ρ·Vp and ρ·Vs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpace {
    /// ρ·Vp [force·s/length³].
    pub normal: f64,
    /// ρ·Vs [force·s/length³].
    pub tangential: f64,
}

impl HalfSpace {
    /// The impedances of an elastic medium of density `density` [mass/length³], Young's modulus
    /// `e` and Poisson's ratio `nu`, in plane strain (Vp of the constrained modulus).
    pub fn elastic(density: f64, e: f64, nu: f64) -> HalfSpace {
        let shear = e / (2.0 * (1.0 + nu));
        let constrained = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
        HalfSpace { normal: (density * constrained).sqrt(), tangential: (density * shear).sqrt() }
    }
}
