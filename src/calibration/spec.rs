//! The calibration file (TOML, or a dict from Python): which test, which curves, which law, and for a
//! pull-out test the reinforcement (and for the finite-element model, the box). Lengths in m, forces
//! in kN, stresses in kPa.

use super::error::CalibrationError;
use super::parameters::{LawFamily, Parameter};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The laboratory test the curves come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TestKind {
    /// τ against slip at several normal stresses: the law itself is the model (a uniform slip under
    /// a uniform σn, docs/verification.md §4).
    DirectShear,
    /// Pull-out force per metre width against the head's displacement at several surcharges.
    PullOut,
}

impl TestKind {
    pub fn name(self) -> &'static str {
        match self {
            TestKind::DirectShear => "direct-shear",
            TestKind::PullOut => "pull-out",
        }
    }
}

/// How a pull-out curve is computed from the law's parameters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PullOutModel {
    /// The progressive-slip solution on a rigid soil at σn = the surcharge, with the embedded
    /// length shortened as the reinforcement leaves the soil (docs/verification.md §1–2): Coulomb only.
    #[default]
    ClosedForm,
    /// The pull-out box itself, run by geoslip for every trial of the parameters: any law, the
    /// soil's stiffness and the σn the multipliers give.
    FiniteElement,
}

/// The soil and the box of a pull-out test for the finite-element model.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PullOutBoxSpec {
    /// Inside length of the box [m] (front face to back wall).
    pub length: f64,
    /// Height of soil [m]; the reinforcement lies at mid-height.
    pub height: f64,
    pub youngs_modulus: f64,
    pub poissons_ratio: f64,
    #[serde(default)]
    pub unit_weight: f64,
    /// Elements along the box (default 40).
    #[serde(default)]
    pub elements: Option<usize>,
    /// Pull steps up to the largest measured displacement (default 40).
    #[serde(default)]
    pub steps: Option<usize>,
}

/// The reinforcement of a pull-out test.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PullOutSpec {
    /// Length in the soil at the start [m].
    pub embedded_length: f64,
    /// EA per metre width [kN/m].
    pub axial_stiffness: f64,
    /// Faces in contact with soil (2: soil above and below).
    #[serde(default = "two")]
    pub faces: u32,
    #[serde(default)]
    pub model: PullOutModel,
    /// For `model = "finite-element"`.
    #[serde(default, rename = "box")]
    pub box_: Option<PullOutBoxSpec>,
}

fn two() -> u32 {
    2
}

/// A calibration file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationFile {
    #[serde(default)]
    pub title: Option<String>,
    pub test: TestKind,
    /// The measured curves (CSV with units in the header), relative to this file.
    pub data: PathBuf,
    /// The law to fit: `coulomb`, `softening` (peak, then softening to a residual), `hyperbolic`.
    pub law: String,
    /// Starting values of parameters (otherwise estimated from the curves).
    #[serde(default)]
    pub initial: BTreeMap<String, f64>,
    /// Parameters held at these values, not fitted.
    #[serde(default)]
    pub fixed: BTreeMap<String, f64>,
    #[serde(default)]
    pub pull_out: Option<PullOutSpec>,
}

/// A checked calibration file.
#[derive(Debug, Clone)]
pub struct CalibrationSpec {
    pub path: PathBuf,
    pub title: String,
    pub test: TestKind,
    pub data: PathBuf,
    pub law: LawFamily,
    pub initial: Vec<(Parameter, f64)>,
    pub fixed: Vec<(Parameter, f64)>,
    pub pull_out: Option<PullOutSpec>,
}

/// Read and check a calibration file.
///
/// # Errors
/// [`CalibrationError::Read`], or [`CalibrationError::Spec`] naming the field.
pub fn load(path: &Path) -> Result<CalibrationSpec, CalibrationError> {
    let read = |source| CalibrationError::Read { path: path.into(), source };
    let bytes = crate::input_file::read(path, crate::input_file::SizeLimit::of_memory(None)).map_err(read)?;
    let text =
        String::from_utf8(bytes).map_err(|e| read(std::io::Error::new(std::io::ErrorKind::InvalidData, e).into()))?;
    let de = toml::Deserializer::parse(&text).map_err(|e| CalibrationError::Spec {
        path: path.into(),
        field: "(file)".into(),
        message: e.to_string(),
    })?;
    let file: CalibrationFile = serde_path_to_error::deserialize(de).map_err(|e| CalibrationError::Spec {
        path: path.into(),
        field: e.path().to_string(),
        message: e.inner().to_string(),
    })?;
    check(path, file)
}

/// Check a calibration file read by other means (from Python, as JSON): `path` names it in messages,
/// and `data` is relative to its folder.
///
/// # Errors
/// [`CalibrationError::Spec`] naming the field.
pub fn check(path: &Path, file: CalibrationFile) -> Result<CalibrationSpec, CalibrationError> {
    let spec_error = |field: String, message: String| CalibrationError::Spec { path: path.into(), field, message };
    let law =
        match file.law.as_str() {
            "coulomb" => LawFamily::Coulomb,
            "softening" => LawFamily::Softening,
            "hyperbolic" => LawFamily::Hyperbolic,
            "peak-residual" => return Err(spec_error(
                "law".into(),
                "the peak-residual law drops at once from the peak to the residual, so measured curves fix its peak \
                 only between two of their points: fit \"softening\" (the same law with a measured softening slip)"
                    .into(),
            )),
            other => {
                return Err(spec_error(
                    "law".into(),
                    format!("\"{other}\": one of coulomb, softening, hyperbolic (the laws a calibration fits)"),
                ))
            }
        };
    let parameters = law.parameters();
    let named = |table: &str, map: &BTreeMap<String, f64>| -> Result<Vec<(Parameter, f64)>, CalibrationError> {
        map.iter()
            .map(|(key, &value)| {
                let p = parameters.iter().copied().find(|p| p.key() == key).ok_or_else(|| {
                    spec_error(
                        format!("{table}.{key}"),
                        format!(
                            "not a parameter of the {} law: {}",
                            law.name(),
                            parameters.iter().map(|p| p.key()).collect::<Vec<_>>().join(", ")
                        ),
                    )
                })?;
                if !value.is_finite() {
                    return Err(spec_error(format!("{table}.{key}"), "not a finite number".into()));
                }
                // the range a model's interface law accepts: a fit with a value outside it would
                // write a law no model takes
                p.check(value).map_err(|message| spec_error(format!("{table}.{key}"), message))?;
                Ok((p, value))
            })
            .collect()
    };
    let initial = named("initial", &file.initial)?;
    let fixed = named("fixed", &file.fixed)?;
    // the residual strength not above the peak, as a model checks a softening law: among the values
    // given (a parameter under both tables at its [fixed] one, as the fit takes it)
    let given = |p: Parameter| {
        let tables = fixed.iter().map(|f| ("fixed", f)).chain(initial.iter().map(|i| ("initial", i)));
        tables.filter(|(_, (q, _))| *q == p).map(|(table, &(_, v))| (table, v)).next()
    };
    for (peak, residual) in [
        (Parameter::Cohesion, Parameter::ResidualCohesion),
        (Parameter::FrictionAngle, Parameter::ResidualFrictionAngle),
    ] {
        if let (Some((peak_table, peak_value)), Some((table, value))) = (given(peak), given(residual)) {
            if value > peak_value {
                return Err(spec_error(
                    format!("{table}.{}", residual.key()),
                    format!(
                        "{value} is above the peak's {peak_value} ({peak_table}.{}): the residual strength must not \
                         exceed the peak",
                        peak.key()
                    ),
                ));
            }
        }
    }
    if fixed.len() == parameters.len() {
        return Err(spec_error("fixed".into(), "every parameter is fixed: nothing is left to fit".into()));
    }
    match (file.test, &file.pull_out) {
        (TestKind::PullOut, None) => {
            return Err(spec_error(
                "pull_out".into(),
                "a pull-out test needs [pull_out] with embedded_length and axial_stiffness".into(),
            ))
        }
        (TestKind::DirectShear, Some(_)) => {
            return Err(spec_error("pull_out".into(), "given for a direct-shear test".into()));
        }
        _ => {}
    }
    if let Some(p) = &file.pull_out {
        let positive =
            [("pull_out.embedded_length", p.embedded_length), ("pull_out.axial_stiffness", p.axial_stiffness)];
        for (field, v) in positive {
            if !(v > 0.0 && v.is_finite()) {
                return Err(spec_error(field.into(), format!("{v} is not a positive number")));
            }
        }
        if !(1..=2).contains(&p.faces) {
            return Err(spec_error("pull_out.faces".into(), format!("{}: one or two faces", p.faces)));
        }
        match p.model {
            PullOutModel::ClosedForm if law != LawFamily::Coulomb => {
                return Err(spec_error(
                    "pull_out.model".into(),
                    format!(
                    "the closed form holds for the coulomb law only; fit the {} law with model = \"finite-element\"",
                    law.name()
                ),
                ))
            }
            PullOutModel::FiniteElement => {
                let Some(b) = &p.box_ else {
                    return Err(spec_error(
                        "pull_out.box".into(),
                        "the finite-element model needs the box: length, height, youngs_modulus, poissons_ratio".into(),
                    ));
                };
                for (field, v) in [("length", b.length), ("height", b.height), ("youngs_modulus", b.youngs_modulus)] {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(spec_error(
                            format!("pull_out.box.{field}"),
                            format!("{v} is not a positive number"),
                        ));
                    }
                }
                if !(b.poissons_ratio >= 0.0 && b.poissons_ratio < 0.5) {
                    return Err(spec_error(
                        "pull_out.box.poissons_ratio".into(),
                        format!("{} is not in [0, 0.5)", b.poissons_ratio),
                    ));
                }
                if b.length < p.embedded_length {
                    return Err(spec_error(
                        "pull_out.box.length".into(),
                        format!("{} m is shorter than the embedded length {} m", b.length, p.embedded_length),
                    ));
                }
                for (field, n, max) in [("elements", b.elements, 400), ("steps", b.steps, 1000)] {
                    if let Some(n) = n {
                        if n == 0 || n > max {
                            return Err(spec_error(format!("pull_out.box.{field}"), format!("{n}: from 1 to {max}")));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    let title = file.title.clone().unwrap_or_else(|| {
        path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "calibration".into())
    });
    let data = path.parent().unwrap_or(Path::new(".")).join(&file.data);
    Ok(CalibrationSpec {
        path: path.into(),
        title,
        test: file.test,
        data,
        law,
        initial,
        fixed,
        pull_out: file.pull_out,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The calibration file of a direct-shear test of the `law` with the tables `extra` (TOML).
    fn checked(law: &str, extra: &str) -> Result<CalibrationSpec, CalibrationError> {
        let text = format!("test = \"direct-shear\"\ndata = \"ds.csv\"\nlaw = \"{law}\"\n{extra}");
        let file: CalibrationFile = toml::from_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        check(Path::new("fit.toml"), file)
    }

    /// The field and the message of a refusal.
    fn refusal(law: &str, extra: &str) -> (String, String) {
        match checked(law, extra) {
            Err(CalibrationError::Spec { field, message, .. }) => (field, message),
            Err(other) => panic!("{extra}: {other}"),
            Ok(_) => panic!("{extra}: accepted"),
        }
    }

    #[test]
    fn a_fixed_or_initial_value_that_a_model_refuses_is_refused_naming_its_field() {
        let cases = [
            ("coulomb", "[fixed]\nshear_stiffness = -5000.0\n", "fixed.shear_stiffness", "must be a positive number"),
            ("coulomb", "[fixed]\nshear_stiffness = 0.0\n", "fixed.shear_stiffness", "must be a positive number"),
            ("coulomb", "[fixed]\nfriction_angle = 95.0\n", "fixed.friction_angle", "within [0, 90)"),
            ("coulomb", "[fixed]\nfriction_angle = 90.0\n", "fixed.friction_angle", "within [0, 90)"),
            ("hyperbolic", "[fixed]\ncohesion = -2.0\n", "fixed.cohesion", "must be zero or positive"),
            ("coulomb", "[fixed]\ncohesion = nan\n", "fixed.cohesion", "not a finite number"),
            ("coulomb", "[initial]\nfriction_angle = -3.0\n", "initial.friction_angle", "within [0, 90)"),
            ("softening", "[fixed]\nsoftening_slip = 0.0\n", "fixed.softening_slip", "must be a positive number"),
            ("softening", "[initial]\nresidual_cohesion = -1.0\n", "initial.residual_cohesion", "zero or positive"),
            // the residual above the peak, among the values given in either table
            (
                "softening",
                "[fixed]\ncohesion = 5.0\nresidual_cohesion = 8.0\n",
                "fixed.residual_cohesion",
                "above the peak's 5 (fixed.cohesion)",
            ),
            (
                "softening",
                "[initial]\nresidual_friction_angle = 31.0\n[fixed]\nfriction_angle = 30.0\n",
                "initial.residual_friction_angle",
                "above the peak's 30 (fixed.friction_angle)",
            ),
        ];
        for (law, extra, field, words) in cases {
            let (f, message) = refusal(law, extra);
            assert_eq!(f, field, "{extra}: {message}");
            assert!(message.contains(words), "{extra}: {message}");
        }
        // the whole message names the file and the field
        let e = checked("coulomb", "[fixed]\nshear_stiffness = -5000.0\n").unwrap_err();
        assert_eq!(e.to_string(), "fit.toml: fixed.shear_stiffness: must be a positive number, found -5000");
    }

    #[test]
    fn values_at_the_edges_of_the_range_are_accepted() {
        let spec = checked(
            "softening",
            "[fixed]\ncohesion = 0.0\nresidual_cohesion = 0.0\nfriction_angle = 89.9\n\
             [initial]\nresidual_friction_angle = 89.9\nshear_stiffness = 1e-9\nsoftening_slip = 1e-9\n",
        )
        .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(spec.fixed.len(), 3);
        assert_eq!(spec.initial.len(), 3);
    }
}
