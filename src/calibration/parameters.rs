//! The laws a calibration fits and their parameters, in the model file's names and units.

use crate::interface::law::ShearLaw;
use crate::model::file::ShearLawSpec;

/// A shear law to fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LawFamily {
    /// Elastic–perfectly plastic: Ks, c, φ.
    Coulomb,
    /// Peak, then linear softening to a residual over a plastic slip: Ks, c, φ, c_r, φ_r, the
    /// softening slip. (The `peak-residual` law's sudden drop is not fitted: the curves fix its peak
    /// only between two measured points.)
    Softening,
    /// Hyperbolic: initial slope Ks and asymptote c + σn·tan φ.
    Hyperbolic,
}

/// One parameter of a law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Parameter {
    ShearStiffness,
    Cohesion,
    FrictionAngle,
    ResidualCohesion,
    ResidualFrictionAngle,
    SofteningSlip,
}

impl Parameter {
    /// The model file's name of the parameter.
    pub fn key(self) -> &'static str {
        match self {
            Parameter::ShearStiffness => "shear_stiffness",
            Parameter::Cohesion => "cohesion",
            Parameter::FrictionAngle => "friction_angle",
            Parameter::ResidualCohesion => "residual_cohesion",
            Parameter::ResidualFrictionAngle => "residual_friction_angle",
            Parameter::SofteningSlip => "softening_slip",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Parameter::ShearStiffness => "kPa/m",
            Parameter::Cohesion | Parameter::ResidualCohesion => "kPa",
            Parameter::FrictionAngle | Parameter::ResidualFrictionAngle => "°",
            Parameter::SofteningSlip => "m",
        }
    }

    /// The range the law accepts: a trial outside it is evaluated at the nearest bound.
    fn bounded(self, v: f64) -> f64 {
        match self {
            Parameter::ShearStiffness | Parameter::SofteningSlip => v.max(1e-12),
            // a negative adhesion is evaluated as given (and reported): clamping it would hide it
            Parameter::Cohesion | Parameter::ResidualCohesion => v,
            Parameter::FrictionAngle | Parameter::ResidualFrictionAngle => v.clamp(0.0, 89.0),
        }
    }
}

impl LawFamily {
    pub fn name(self) -> &'static str {
        match self {
            LawFamily::Coulomb => "coulomb",
            LawFamily::Softening => "softening",
            LawFamily::Hyperbolic => "hyperbolic",
        }
    }

    /// The law's parameters in the order of a parameter vector.
    pub fn parameters(self) -> &'static [Parameter] {
        use Parameter::*;
        match self {
            LawFamily::Coulomb | LawFamily::Hyperbolic => &[ShearStiffness, Cohesion, FrictionAngle],
            LawFamily::Softening => {
                &[ShearStiffness, Cohesion, FrictionAngle, ResidualCohesion, ResidualFrictionAngle, SofteningSlip]
            }
        }
    }

    /// The law with the parameter values `v` (in the order of [`Self::parameters`]), each held in
    /// the range the law accepts.
    pub fn law(self, v: &[f64]) -> ShearLaw {
        let p = self.parameters();
        let c: Vec<f64> = p.iter().zip(v).map(|(p, &v)| p.bounded(v)).collect();
        let tan = |deg: f64| deg.to_radians().tan();
        match self {
            LawFamily::Coulomb => ShearLaw::Coulomb { shear_stiffness: c[0], cohesion: c[1], tan_friction: tan(c[2]) },
            LawFamily::Hyperbolic => {
                ShearLaw::Hyperbolic { shear_stiffness: c[0], cohesion: c[1], tan_friction: tan(c[2]) }
            }
            LawFamily::Softening => ShearLaw::Softening {
                shear_stiffness: c[0],
                cohesion: c[1],
                tan_friction: tan(c[2]),
                // the residual never above the peak (the law's own requirement)
                residual_cohesion: c[3].min(c[1]),
                residual_tan_friction: tan(c[4].min(c[2])),
                softening_slip: c[5],
            },
        }
    }

    /// The model file's law with the values `v`.
    pub fn spec(self, v: &[f64]) -> ShearLawSpec {
        match self {
            LawFamily::Coulomb => ShearLawSpec::Coulomb { shear_stiffness: v[0], cohesion: v[1], friction_angle: v[2] },
            LawFamily::Hyperbolic => {
                ShearLawSpec::Hyperbolic { shear_stiffness: v[0], cohesion: v[1], friction_angle: v[2] }
            }
            LawFamily::Softening => ShearLawSpec::Softening {
                shear_stiffness: v[0],
                cohesion: v[1],
                friction_angle: v[2],
                residual_cohesion: v[3],
                residual_friction_angle: v[4],
                softening_slip: v[5],
            },
        }
    }
}
