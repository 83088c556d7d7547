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
    /// `false` for a parameter held under `[fixed]`, or one the fit left at a bound of its range.
    pub fitted: bool,
    /// The fit left the parameter at a bound of the range its law accepts (the data would take it
    /// further): held there, without a standard error.
    pub at_bound: bool,
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
    /// The fitted model over each curve's range, for plotting: [`smooth_grid`]'s points, a bounded
    /// number over all the curves.
    pub smooth: Vec<Vec<(f64, f64)>>,
    /// What the user should know about the result (a strong correlation, a parameter left at a
    /// bound of its range).
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
    // every parameter's starting value: fixed, given (both in the law's range, spec::check), or
    // estimated; an estimate outside the range (no positive initial slope in curves that fall from
    // their first point) starts at a value inside it
    let all = law.parameters();
    let stress_scale = curves.iter().flat_map(|c| c.y.iter()).fold(0.0f64, |a, y| a.max(y.abs())).max(1e-9);
    let start: Vec<f64> = all
        .iter()
        .map(|p| {
            let given = spec.fixed.iter().chain(&spec.initial).find(|(q, _)| q == p).map(|(_, v)| *v);
            given.unwrap_or_else(|| {
                let v = estimated.iter().find(|(q, _)| q == p).map_or(1.0, |(_, v)| *v);
                match p {
                    _ if p.check(v).is_ok() => v,
                    Parameter::ShearStiffness => stress_scale / largest_x.max(1e-6),
                    Parameter::SofteningSlip => largest_x.max(1e-6),
                    Parameter::Cohesion | Parameter::ResidualCohesion => 0.0,
                    Parameter::FrictionAngle | Parameter::ResidualFrictionAngle => {
                        v.max(0.0).min(parameters::MAX_FITTED_ANGLE)
                    }
                }
            })
        })
        .collect();
    let free: Vec<usize> = (0..all.len()).filter(|&k| !spec.fixed.iter().any(|(p, _)| *p == all[k])).collect();
    let names: Vec<String> = free.iter().map(|&k| all[k].key().to_string()).collect();
    // each free parameter's range: what its law accepts (parameters::Parameter::trial_range), and a
    // peak strength not below a residual held under [fixed] nor a residual above a peak held there
    let held = |p: Parameter| spec.fixed.iter().find(|(q, _)| *q == p).map(|(_, v)| *v);
    let bounds: Vec<(f64, f64)> = free
        .iter()
        .map(|&k| {
            let (mut lo, mut hi) = all[k].trial_range(start[k]);
            match all[k] {
                Parameter::Cohesion => lo = lo.max(held(Parameter::ResidualCohesion).unwrap_or(lo)),
                Parameter::FrictionAngle => lo = lo.max(held(Parameter::ResidualFrictionAngle).unwrap_or(lo)),
                Parameter::ResidualCohesion => hi = hi.min(held(Parameter::Cohesion).unwrap_or(hi)),
                Parameter::ResidualFrictionAngle => hi = hi.min(held(Parameter::FrictionAngle).unwrap_or(hi)),
                _ => {}
            }
            (lo, hi.max(lo))
        })
        .collect();
    // scales: the starting value, or the data's size for a parameter that starts at zero
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
    let fit =
        fit::least_squares(&residuals, &names, &free_start, &scale, &bounds, model.step()).map_err(|e| match e {
            CalibrationError::Unidentifiable { parameters, reason } => {
                unidentifiable_hint(parameters, reason, &curves, spec.test)
            }
            other => other,
        })?;
    // the values the law was evaluated with (the residual strength not above the peak)
    let values = law.admissible(&with_free(&fit.values));
    let parameters: Vec<FittedParameter> = all
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let f = free.iter().position(|&j| j == k);
            let at_bound = f.is_some_and(|i| fit.at_bound[i]);
            FittedParameter {
                name: p.key(),
                unit: p.unit(),
                value: values[k],
                fitted: f.is_some() && !at_bound,
                at_bound,
                standard_error: f.and_then(|i| fit.standard_errors[i]),
                interval: f.and_then(|i| fit.intervals[i]),
            }
        })
        .collect();
    let mut modelled = Vec::new();
    let mut smooth = Vec::new();
    for c in &curves {
        modelled.push(model.curve(law, &values, c.condition, &c.x)?);
        let end = c.x.iter().copied().fold(0.0f64, f64::max);
        let grid = smooth_grid(end, curves.len());
        let y = model.curve(law, &values, c.condition, &grid)?;
        smooth.push(grid.into_iter().zip(y).collect());
    }
    let estimated_names: Vec<String> =
        names.iter().zip(&fit.at_bound).filter(|(_, b)| !**b).map(|(n, _)| n.clone()).collect();
    let warnings = warnings(&parameters, &estimated_names, &fit, &bounds, &free);
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

/// The most points of the fitted curves over all the curves together (as long as each gets
/// [`MIN_SMOOTH_INTERVALS`]).
pub const SMOOTH_BUDGET: usize = 20_000;
/// Intervals of a curve's fitted line when there are few curves.
pub const SMOOTH_INTERVALS: usize = 200;
/// The fewest intervals of a curve's fitted line.
pub const MIN_SMOOTH_INTERVALS: usize = 2;

/// The displacements from 0 to `end` at which a curve's fitted model is drawn, one of `curves`:
/// [`SMOOTH_INTERVALS`] intervals for a few curves, fewer for many, so that the report's fitted
/// curves grow with the curves given, not with their points × a fixed count: at most
/// max([`SMOOTH_BUDGET`], ([`MIN_SMOOTH_INTERVALS`] + 1) × `curves`) points in all.
pub fn smooth_grid(end: f64, curves: usize) -> Vec<f64> {
    let intervals = (SMOOTH_BUDGET / curves.max(1)).saturating_sub(1).clamp(MIN_SMOOTH_INTERVALS, SMOOTH_INTERVALS);
    (0..=intervals).map(|i| end * i as f64 / intervals as f64).collect()
}

/// What the user should know: a parameter left at a bound of its range, a strong correlation.
/// `names` are the fitted parameters not at a bound (the correlation's), `bounds` the ranges of
/// the free parameters `free` (indices into the law's parameters).
fn warnings(
    parameters: &[FittedParameter],
    names: &[String],
    fit: &LeastSquares,
    bounds: &[(f64, f64)],
    free: &[usize],
) -> Vec<String> {
    let mut w = Vec::new();
    for (i, &k) in free.iter().enumerate() {
        let p = &parameters[k];
        if !p.at_bound {
            continue;
        }
        let (lo, hi) = bounds[i];
        let v = fit.values[i];
        let side = if (v - lo).abs() <= (v - hi).abs() { "least" } else { "most" };
        w.push(format!(
            "{} ends at {} {}, the {side} the fit tries (the law's range, or a residual or peak held under \
             [fixed]): the data would take it further, so it has no standard error and the others' are those \
             with it held there; hold it under [fixed] to fit without it, or check the curves",
            p.name,
            report::significant(p.value, 5),
            p.unit
        ));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fitted_curves_have_a_bounded_number_of_points_in_all() {
        // a few curves: 201 points from 0 to the end, as a plot wants them
        let grid = smooth_grid(0.02, 3);
        assert_eq!(grid.len(), 201);
        assert_eq!((grid[0], grid[200]), (0.0, 0.02));
        assert!((grid[100] - 0.01).abs() < 1e-15);
        // many: at most 20 000 points over all of them, but never fewer than 3 a curve
        for curves in [1, 3, 99, 100, 101, 1000, 7000, 20_000, 333_333] {
            let points = smooth_grid(0.02, curves).len();
            assert!(points <= 201, "{curves} curves: {points} points each");
            assert!(points >= 3, "{curves} curves: {points} points each");
            assert!(points * curves <= 20_000.max(3 * curves), "{curves} curves: {} points in all", points * curves);
        }
        assert_eq!(smooth_grid(0.02, 1000).len(), 20);
        assert_eq!(smooth_grid(0.02, 20_000), vec![0.0, 0.01, 0.02]);
    }

    /// Coulomb curves whose peaks lie on τ = 0.6·σn − 2 kPa (σn = 25, 50, 100 kPa: 13, 28, 58 kPa;
    /// Ks = 10 000 kPa/m, slips to 10 mm): the data would take the cohesion to −2 kPa, which no
    /// model accepts. It is held at 0, reported so, without a standard error, with a warning; φ is
    /// fitted with c = 0, so tan φ lies between the peaks' smallest and largest τ/σn (0.52 … 0.58).
    #[test]
    fn a_cohesion_the_data_would_take_below_zero_is_held_at_zero() {
        let curves: Vec<Curve> = [25.0, 50.0, 100.0]
            .iter()
            .map(|&sigma| {
                let x: Vec<f64> = (0..=20).map(|i| 0.0005 * i as f64).collect();
                let y = x.iter().map(|&d| (1e4 * d).min(0.6 * sigma - 2.0)).collect();
                Curve { condition: sigma, x, y }
            })
            .collect();
        let spec = CalibrationSpec {
            path: "fit.toml".into(),
            title: "below zero".into(),
            test: TestKind::DirectShear,
            data: "ds.csv".into(),
            law: LawFamily::Coulomb,
            initial: Vec::new(),
            fixed: Vec::new(),
            pull_out: None,
        };
        let c = calibrate_curves(&spec, curves).unwrap_or_else(|e| panic!("{e}"));
        let cohesion = &c.parameters[1];
        assert_eq!(cohesion.name, "cohesion");
        assert_eq!(cohesion.value, 0.0);
        assert!(cohesion.at_bound && !cohesion.fitted && cohesion.standard_error.is_none(), "{cohesion:?}");
        let phi = &c.parameters[2];
        assert!(phi.fitted && phi.standard_error.is_some(), "{phi:?}");
        let tan = phi.value.to_radians().tan();
        assert!((0.52..=0.58).contains(&tan), "tan φ = {tan}");
        assert!(c.warnings.iter().any(|w| w.starts_with("cohesion ends at 0")), "{:?}", c.warnings);
        // the correlation is that of the parameters fitted: Ks and φ
        assert_eq!(c.correlation.len(), 2);
        // the law written is the one reported, which a model accepts
        match c.law() {
            crate::model::file::ShearLawSpec::Coulomb { cohesion, friction_angle, .. } => {
                assert_eq!((cohesion, friction_angle), (0.0, phi.value));
            }
            other => panic!("{other:?}"),
        }
    }
}
