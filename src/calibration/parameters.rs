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

    /// The model's check of the parameter's value, as a model file's interface law is checked
    /// (`shear_law` in src/model/validate/materials.rs, which checks a whole model and is not
    /// reachable from here): a positive stiffness and softening slip, an adhesion of zero or more,
    /// an angle in [0, 90)°. The message completes "<field>: ".
    ///
    /// # Errors
    /// The value and the range it is outside.
    pub fn check(self, v: f64) -> Result<(), String> {
        match self {
            Parameter::ShearStiffness | Parameter::SofteningSlip if !(v.is_finite() && v > 0.0) => {
                Err(format!("must be a positive number, found {v}"))
            }
            Parameter::Cohesion | Parameter::ResidualCohesion if !(v.is_finite() && v >= 0.0) => {
                Err(format!("must be zero or positive, found {v}"))
            }
            Parameter::FrictionAngle | Parameter::ResidualFrictionAngle
                if !(v.is_finite() && (0.0..90.0).contains(&v)) =>
            {
                Err(format!("must be an angle in degrees within [0, 90), found {v}"))
            }
            _ => Ok(()),
        }
    }

    /// The closed range a fit holds the parameter's trials in, inside [`Self::check`]'s: a
    /// stiffness or a softening slip down to a millionth of its starting value `start` (which
    /// [`Self::check`] accepts), an adhesion down to 0, an angle from 0 to [`MAX_FITTED_ANGLE`].
    pub fn trial_range(self, start: f64) -> (f64, f64) {
        match self {
            Parameter::ShearStiffness | Parameter::SofteningSlip => (1e-6 * start, f64::INFINITY),
            Parameter::Cohesion | Parameter::ResidualCohesion => (0.0, f64::INFINITY),
            Parameter::FrictionAngle | Parameter::ResidualFrictionAngle => (0.0, MAX_FITTED_ANGLE),
        }
    }

    /// `v` in the range [`Self::check`] accepts, at its nearest value there (a value it accepts is
    /// kept as it is): what a law is built with, whatever it is given.
    fn bounded(self, v: f64) -> f64 {
        if self.check(v).is_ok() {
            return v;
        }
        // `max`/`min`, not `clamp`: a NaN goes to the bound
        match self {
            Parameter::ShearStiffness | Parameter::SofteningSlip => v.max(f64::MIN_POSITIVE).min(f64::MAX),
            Parameter::Cohesion | Parameter::ResidualCohesion => v.max(0.0).min(f64::MAX),
            Parameter::FrictionAngle | Parameter::ResidualFrictionAngle => v.max(0.0).min(MAX_FITTED_ANGLE),
        }
    }
}

/// The largest friction angle a fit tries [°] (tan φ = 57): the law accepts up to, not including, 90°.
pub const MAX_FITTED_ANGLE: f64 = 89.0;

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

    /// The values `v` (in the order of [`Self::parameters`]) as the law takes them: each in the
    /// range the model accepts, and the residual strength not above the peak (the law's own
    /// requirement).
    pub fn admissible(self, v: &[f64]) -> Vec<f64> {
        let mut c: Vec<f64> = self.parameters().iter().zip(v).map(|(p, &v)| p.bounded(v)).collect();
        if self == LawFamily::Softening {
            c[3] = c[3].min(c[1]);
            c[4] = c[4].min(c[2]);
        }
        c
    }

    /// The law with the parameter values `v` (in the order of [`Self::parameters`]), as
    /// [`Self::admissible`] holds them.
    pub fn law(self, v: &[f64]) -> ShearLaw {
        let c = self.admissible(v);
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
                residual_cohesion: c[3],
                residual_tan_friction: tan(c[4]),
                softening_slip: c[5],
            },
        }
    }

    /// The model file's law with the values `v`, as [`Self::admissible`] holds them: a law the
    /// model accepts.
    pub fn spec(self, v: &[f64]) -> ShearLawSpec {
        let v = self.admissible(v);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::meshgen::PullOutBox;
    use crate::model::Model;
    use std::path::Path;

    /// Every problem a model (the default pull-out box with `law` on its interface) has.
    fn model_problems(law: ShearLawSpec) -> Vec<crate::Problem> {
        let file = PullOutBox { law, steps: 1, ..PullOutBox::default() }.model();
        Model::from_file(Path::new("box"), &file).err().map(|e| e.problems).unwrap_or_default()
    }

    /// The parameters of the law that a model refuses, by name.
    fn refused_by_a_model(law: ShearLawSpec) -> Vec<String> {
        let problems = model_problems(law);
        problems.iter().filter_map(|p| p.field.rsplit_once(".law.").map(|(_, name)| name.to_string())).collect()
    }

    #[test]
    fn a_value_is_refused_here_exactly_when_a_model_refuses_it() {
        // peak values that leave room for any residual, residual values below any peak tried
        let typical = [1000.0, 50.0, 60.0, 0.0, 0.0, 0.01];
        let probes =
            [-1.0, -1e-300, -0.0, 0.0, 1e-300, 1e-3, 1.0, 45.0, 89.999, 90.0, 95.0, 1e300, f64::INFINITY, f64::NAN];
        for law in [LawFamily::Coulomb, LawFamily::Hyperbolic, LawFamily::Softening] {
            let parameters = law.parameters();
            for (k, p) in parameters.iter().enumerate() {
                for v in probes {
                    // a residual under the peak's typical value, so that only the range is tried
                    if matches!(p, Parameter::ResidualCohesion | Parameter::ResidualFrictionAngle) && v > 45.0 {
                        continue;
                    }
                    let mut values = typical[..parameters.len()].to_vec();
                    values[k] = v;
                    let spec = match law {
                        LawFamily::Coulomb => ShearLawSpec::Coulomb {
                            shear_stiffness: values[0],
                            cohesion: values[1],
                            friction_angle: values[2],
                        },
                        LawFamily::Hyperbolic => ShearLawSpec::Hyperbolic {
                            shear_stiffness: values[0],
                            cohesion: values[1],
                            friction_angle: values[2],
                        },
                        LawFamily::Softening => ShearLawSpec::Softening {
                            shear_stiffness: values[0],
                            cohesion: values[1],
                            friction_angle: values[2],
                            residual_cohesion: values[3],
                            residual_friction_angle: values[4],
                            softening_slip: values[5],
                        },
                    };
                    let fields = refused_by_a_model(spec);
                    let model_refuses = fields.iter().any(|f| f == p.key());
                    assert_eq!(
                        p.check(v).is_err(),
                        model_refuses,
                        "{} law, {} = {v}: here {:?}, the model's problems {fields:?}",
                        law.name(),
                        p.key(),
                        p.check(v)
                    );
                }
            }
        }
        assert_eq!(
            Parameter::FrictionAngle.check(95.0),
            Err("must be an angle in degrees within [0, 90), found 95".to_string())
        );
    }

    #[test]
    fn every_trial_gives_a_law_that_a_model_accepts() {
        // what an iteration may ask for: a negative stiffness, cohesion or slip, an angle of 90° or
        // more, a residual above the peak, a NaN
        let trials: [[f64; 6]; 4] = [
            [-5.0, -1e-4, 95.0, 20.0, 40.0, -0.01],
            [0.0, -0.0, 90.0, -1.0, 95.0, 0.0],
            [f64::NAN, f64::NAN, f64::NAN, f64::NAN, f64::NAN, f64::NAN],
            [2e4, 5.0, 30.0, 8.0, 35.0, 0.01],
        ];
        for law in [LawFamily::Coulomb, LawFamily::Hyperbolic, LawFamily::Softening] {
            for t in trials {
                let v = &t[..law.parameters().len()];
                let problems = model_problems(law.spec(v));
                assert!(problems.is_empty(), "{} law at {v:?}: {problems:?}", law.name());
                for (p, a) in law.parameters().iter().zip(law.admissible(v)) {
                    assert!(p.check(a).is_ok(), "{} = {a}", p.key());
                }
            }
        }
        // values in the range are kept as they are; a residual above the peak is the peak
        let kept = LawFamily::Softening.admissible(&[2e4, 5.0, 30.0, 4.0, 25.0, 0.01]);
        assert_eq!(kept, vec![2e4, 5.0, 30.0, 4.0, 25.0, 0.01]);
        let capped = LawFamily::Softening.admissible(&[2e4, 5.0, 30.0, 8.0, 35.0, 0.01]);
        assert_eq!((capped[3], capped[4]), (5.0, 30.0));
    }
}
