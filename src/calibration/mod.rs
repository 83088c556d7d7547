//! Interface laws fitted to laboratory curves: direct-shear τ–δ at several normal stresses, or
//! pull-out P–δ at several surcharges, by nonlinear least squares.
//!
//! The data path: the calibration file ([`spec`]) and its curves ([`curves`]) → starting values read
//! off the curves ([`estimate`]) → the model of the test ([`direct_shear`]: the law itself;
//! [`pullout_closed_form`]: the progressive-slip solution on a rigid soil; [`pullout_box`]: the
//! finite-element box) → the fit and its statistics ([`fit`]) → what is written ([`report`]).

pub mod curves;
pub mod direct_shear;
pub mod error;
pub mod estimate;
pub mod fit;
pub mod parameters;
pub mod pullout_box;
pub mod pullout_closed_form;
pub mod report;
pub mod spec;

pub use curves::Curve;
pub use error::CalibrationError;
pub use parameters::{LawFamily, Parameter};
pub use spec::{CalibrationSpec, PullOutModel, TestKind};

use fit::LeastSquares;
use pullout_box::TestBox;
use pullout_closed_form::Reinforcement;

/// One parameter of the fitted law.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FittedParameter {
    pub name: &'static str,
    pub unit: &'static str,
    pub value: f64,
    /// `false` for a parameter held under `[fixed]`.
    pub fitted: bool,
    pub standard_error: Option<f64>,
    /// 95 % confidence interval.
    pub interval: Option<(f64, f64)>,
}

/// A finished calibration.
#[derive(Debug, Clone)]
pub struct Calibration {
    pub spec: CalibrationSpec,
    pub curves: Vec<Curve>,
    pub parameters: Vec<FittedParameter>,
    /// Correlation between the fitted parameters, in the order they appear in `parameters`.
    pub correlation: Vec<Vec<f64>>,
    pub fit: LeastSquares,
    /// The fitted model at each measured point, curve by curve.
    pub modelled: Vec<Vec<f64>>,
    /// The fitted model over each curve's range, for plotting.
    pub smooth: Vec<Vec<(f64, f64)>>,
    /// What the user should know about the result (a strong correlation, a negative adhesion).
    pub warnings: Vec<String>,
    /// The reinforcement length of the finite-element box (on its element columns).
    pub box_embedded_length: Option<f64>,
}

impl Calibration {
    /// The fitted law as the model file writes it.
    pub fn law(&self) -> crate::model::file::ShearLawSpec {
        self.spec.law.spec(&self.parameters.iter().map(|p| p.value).collect::<Vec<_>>())
    }
}

/// How a test's curve is computed from the parameters.
enum TestModel {
    DirectShear,
    ClosedForm(Reinforcement),
    Box(TestBox),
}

impl TestModel {
    fn curve(&self, law: LawFamily, values: &[f64], condition: f64, x: &[f64]) -> Result<Vec<f64>, CalibrationError> {
        match self {
            TestModel::DirectShear => Ok(direct_shear::curve(&law.law(values), condition, x)),
            TestModel::ClosedForm(r) => {
                let l = law.law(values);
                let ks = l.shear_stiffness().unwrap_or(0.0);
                let tau_max = l.peak_strength(condition);
                Ok(x.iter().map(|&u| pullout_closed_form::force(r, ks, tau_max, u)).collect())
            }
            TestModel::Box(b) => b.curve(law.spec(values), condition, x),
        }
    }

    /// The central-difference step: a finite-element curve is converged to a tolerance, so its
    /// derivatives need a larger step than a closed form's.
    fn step(&self) -> f64 {
        match self {
            TestModel::Box(_) => 1e-4,
            _ => 1e-6,
        }
    }
}

/// Read the curves of a checked calibration file and fit its law.
///
/// # Errors
/// The curves' [`CalibrationError::Data`], and those of [`calibrate_curves`].
pub fn calibrate(spec: &CalibrationSpec) -> Result<Calibration, CalibrationError> {
    let curves = curves::read(&spec.data, spec.test)?;
    calibrate_curves(spec, curves)
}

/// Fit the law of `spec` to `curves`.
///
/// # Errors
/// [`CalibrationError::Unidentifiable`] when the curves cannot identify the free parameters (one
/// normal stress for c and φ, no point past the peak for the residual), and
/// [`CalibrationError::NotConverged`] or [`CalibrationError::Model`] when the fit fails.
pub fn calibrate_curves(spec: &CalibrationSpec, curves: Vec<Curve>) -> Result<Calibration, CalibrationError> {
    if spec.test == TestKind::PullOut {
        monotonic_pull(spec, &curves)?;
    }
    let law = spec.law;
    let largest_x = curves.iter().flat_map(|c| c.x.iter()).fold(0.0f64, |a, x| a.max(x.abs()));
    let (model, estimated) = match (spec.test, &spec.pull_out) {
        (TestKind::PullOut, Some(p)) => {
            let r =
                Reinforcement { length: p.embedded_length, axial_stiffness: p.axial_stiffness, faces: p.faces.into() };
            let estimated = estimate::pull_out(law, &curves, &r);
            match (&p.model, &p.box_) {
                (PullOutModel::FiniteElement, Some(b)) => (TestModel::Box(TestBox::new(p, b, largest_x)), estimated),
                _ => (TestModel::ClosedForm(r), estimated),
            }
        }
        _ => (TestModel::DirectShear, estimate::direct_shear(law, &curves)),
    };
    // every parameter's starting value: fixed, given, or estimated
    let all = law.parameters();
    let start: Vec<f64> = all
        .iter()
        .map(|p| {
            let given = spec.fixed.iter().chain(&spec.initial).find(|(q, _)| q == p).map(|(_, v)| *v);
            given.unwrap_or_else(|| estimated.iter().find(|(q, _)| q == p).map_or(1.0, |(_, v)| *v))
        })
        .collect();
    let free: Vec<usize> = (0..all.len()).filter(|&k| !spec.fixed.iter().any(|(p, _)| *p == all[k])).collect();
    let names: Vec<String> = free.iter().map(|&k| all[k].key().to_string()).collect();
    // scales: the starting value, or the data's size for a parameter that starts at zero
    let stress_scale = curves.iter().flat_map(|c| c.y.iter()).fold(0.0f64, |a, y| a.max(y.abs())).max(1e-9);
    let scale: Vec<f64> = free
        .iter()
        .map(|&k| {
            if start[k].abs() > 0.0 {
                start[k].abs()
            } else {
                match all[k] {
                    Parameter::Cohesion | Parameter::ResidualCohesion => 0.1 * stress_scale,
                    Parameter::SofteningSlip => largest_x.max(1e-6),
                    _ => 1.0,
                }
            }
        })
        .collect();
    let with_free = |free_values: &[f64]| {
        let mut v = start.clone();
        for (&k, &x) in free.iter().zip(free_values) {
            v[k] = x;
        }
        v
    };
    // each curve's residuals over its largest measured value: every curve counts alike, and a
    // scatter proportional to the curve's size (a load cell's error as a fraction of its range) is
    // weighted as it should be
    let weights: Vec<f64> =
        curves.iter().map(|c| 1.0 / c.y.iter().fold(0.0f64, |a, y| a.max(y.abs())).max(1e-12)).collect();
    let residuals = |free_values: &[f64]| -> Result<Vec<f64>, CalibrationError> {
        let v = with_free(free_values);
        let mut r = Vec::new();
        for (c, w) in curves.iter().zip(&weights) {
            let m = model.curve(law, &v, c.condition, &c.x)?;
            r.extend(m.iter().zip(&c.y).map(|(m, y)| w * (m - y)));
        }
        Ok(r)
    };
    let free_start: Vec<f64> = free.iter().map(|&k| start[k]).collect();
    let fit = fit::least_squares(&residuals, &names, &free_start, &scale, model.step()).map_err(|e| match e {
        CalibrationError::Unidentifiable { parameters, reason } => {
            unidentifiable_hint(parameters, reason, &curves, spec.test)
        }
        other => other,
    })?;
    let values = with_free(&fit.values);
    let parameters: Vec<FittedParameter> = all
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let f = free.iter().position(|&j| j == k);
            FittedParameter {
                name: p.key(),
                unit: p.unit(),
                value: values[k],
                fitted: f.is_some(),
                standard_error: f.map(|i| fit.standard_errors[i]),
                interval: f.map(|i| fit.intervals[i]),
            }
        })
        .collect();
    let mut modelled = Vec::new();
    let mut smooth = Vec::new();
    for c in &curves {
        modelled.push(model.curve(law, &values, c.condition, &c.x)?);
        let end = c.x.iter().copied().fold(0.0f64, f64::max);
        let grid: Vec<f64> = (0..=200).map(|i| end * i as f64 / 200.0).collect();
        let y = model.curve(law, &values, c.condition, &grid)?;
        smooth.push(grid.into_iter().zip(y).collect());
    }
    let warnings = warnings(&parameters, &names, &fit);
    Ok(Calibration {
        spec: spec.clone(),
        curves,
        parameters,
        correlation: fit.correlation.clone(),
        fit,
        modelled,
        smooth,
        warnings,
        box_embedded_length: match &model {
            TestModel::Box(b) => Some(b.embedded_length),
            _ => None,
        },
    })
}

/// Both pull-out models pull the head one way (the closed form's progressive slip, the box's pull
/// stage): a curve whose displacement goes back would be fitted as if it had not.
fn monotonic_pull(spec: &CalibrationSpec, curves: &[Curve]) -> Result<(), CalibrationError> {
    // metres in millimetres, rid of the round-off of the unit conversion
    let mm = |x: f64| (x.abs() * 1e12).round() / 1e9;
    for c in curves {
        if let Some(k) = (1..c.x.len()).find(|&k| c.x[k].abs() < c.x[k - 1].abs()) {
            return Err(CalibrationError::Data {
                path: spec.data.clone(),
                line: None,
                column: Some("displacement".into()),
                message: format!(
                    "the curve at {} kPa goes back from {} to {} mm (its points {} and {}): a pull-out calibration \
                     needs a monotonic pull, points in the order of the test",
                    c.condition,
                    mm(c.x[k - 1]),
                    mm(c.x[k]),
                    k,
                    k + 1
                ),
            });
        }
    }
    Ok(())
}

/// Say why, in the test's terms, when the reason is one the curves' conditions explain.
fn unidentifiable_hint(parameters: Vec<String>, reason: String, curves: &[Curve], test: TestKind) -> CalibrationError {
    let strength = |p: &String| p.contains("cohesion") || p.contains("friction_angle");
    let reason = if curves.len() == 1 && parameters.iter().any(strength) {
        let what = match test {
            TestKind::DirectShear => "normal stress",
            TestKind::PullOut => "surcharge",
        };
        format!(
            "every curve is at one {what} ({} kPa), where c and tan φ act only as c + σn·tan φ; {reason}",
            curves[0].condition
        )
    } else {
        reason
    };
    CalibrationError::Unidentifiable { parameters, reason }
}

fn warnings(parameters: &[FittedParameter], names: &[String], fit: &LeastSquares) -> Vec<String> {
    let mut w = Vec::new();
    for p in parameters.iter().filter(|p| p.fitted) {
        if p.name.contains("cohesion") && p.value < 0.0 {
            w.push(format!(
                "{} is fitted negative ({:.4} kPa), which a model refuses: hold it at 0 under [fixed]",
                p.name, p.value
            ));
        }
    }
    for a in 0..names.len() {
        for b in a + 1..names.len() {
            let rho = fit.correlation[a][b];
            if rho.abs() > 0.95 {
                w.push(format!(
                    "{} and {} are strongly correlated (ρ = {rho:.3}): the data fix a combination of them better \
                     than either",
                    names[a], names[b]
                ));
            }
        }
    }
    w
}
