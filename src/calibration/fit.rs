//! Nonlinear least squares (Levenberg–Marquardt, the `levenberg-marquardt` crate's port of MINPACK)
//! and what the fit's Jacobian says about it: standard errors and 95 % intervals from
//! s²·(JᵀJ)⁻¹ with Student's t on m − p degrees of freedom, the correlation matrix, and whether the
//! data identify every parameter at all.
//!
//! The parameters are fitted as θ = value / scale (scales from the starting values) so that one step
//! length suits them all; the Jacobian is taken by central differences in θ.
//!
//! Each parameter has a closed range (the values its law accepts): the residuals are only ever
//! evaluated with every parameter in its range, a trial beyond it at the nearest bound, and a
//! difference at a bound is taken one-sided, into the range. A parameter that ends at a bound (the
//! data would take it further) is held there: it has no standard error, and the statistics are those
//! of the others.

use super::error::CalibrationError;
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use lm_nalgebra::{storage::Owned, DMatrix as LmMatrix, DVector as LmVector, Dyn};
use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::cell::RefCell;

/// The residuals (model − measured) at parameter values, or why they cannot be computed.
pub type Residuals<'a> = dyn Fn(&[f64]) -> Result<Vec<f64>, CalibrationError> + 'a;

/// Below this ratio of the smallest to the largest singular value of the column-normalised Jacobian
/// the fitted parameters are not told apart by the data.
pub const IDENTIFIABLE: f64 = 1e-6;

/// The least-squares fit of the free parameters.
#[derive(Debug, Clone)]
pub struct LeastSquares {
    /// Every free parameter's value, in its range.
    pub values: Vec<f64>,
    /// Whether the parameter ended at a bound of its range (then without a standard error).
    pub at_bound: Vec<bool>,
    /// `None` for a parameter at a bound.
    pub standard_errors: Vec<Option<f64>>,
    /// 95 % confidence intervals; `None` for a parameter at a bound.
    pub intervals: Vec<Option<(f64, f64)>>,
    /// Correlation between the parameters not at a bound, in their order.
    pub correlation: Vec<Vec<f64>>,
    /// Root mean square of the residuals (as the residual function gives them: weighted).
    pub rms: f64,
    pub points: usize,
    pub degrees_of_freedom: usize,
    /// The 97.5 % quantile of Student's t the intervals use.
    pub t_quantile: f64,
    pub evaluations: usize,
}

struct Problem<'a> {
    residuals: &'a Residuals<'a>,
    scale: Vec<f64>,
    /// Each parameter's range in θ.
    range: Vec<(f64, f64)>,
    theta: LmVector<f64>,
    step: f64,
    failure: RefCell<Option<CalibrationError>>,
    evaluations: RefCell<usize>,
}

impl Problem<'_> {
    /// θ held in its range (`max`/`min`, not `clamp`: a NaN goes to the lower bound, never panics;
    /// `+ 0.0` makes a −0 at a bound of 0 a 0).
    fn held(&self, theta: &[f64]) -> Vec<f64> {
        theta.iter().zip(&self.range).map(|(t, &(lo, hi))| t.max(lo).min(hi) + 0.0).collect()
    }

    /// The parameters' values of θ, each in its range.
    fn values(&self, theta: &[f64]) -> Vec<f64> {
        self.held(theta).iter().zip(&self.scale).map(|(t, s)| t * s).collect()
    }

    fn evaluate(&self, theta: &[f64]) -> Option<Vec<f64>> {
        *self.evaluations.borrow_mut() += 1;
        match (self.residuals)(&self.values(theta)) {
            Ok(r) if r.iter().all(|v| v.is_finite()) => Some(r),
            Ok(_) => None,
            Err(e) => {
                self.failure.borrow_mut().get_or_insert(e);
                None
            }
        }
    }

    /// ∂r/∂θ by central differences; one-sided, into the range, for a parameter in its range
    /// within a step of a bound. (Beyond its range, where the residuals are those at the bound, the
    /// difference is that of the residuals as evaluated: zero once both sides are beyond.)
    fn jacobian_at(&self, theta: &[f64]) -> Option<DMatrix<f64>> {
        let mut columns = Vec::with_capacity(theta.len());
        let mut rows = None;
        for k in 0..theta.len() {
            let h = self.step * theta[k].abs().max(1.0);
            let (lo, hi) = self.range[k];
            let (mut up, mut down) = (theta[k] + h, theta[k] - h);
            if (lo..=hi).contains(&theta[k]) {
                up = up.min(hi).max(theta[k]);
                down = down.max(lo).min(theta[k]);
            }
            let column = if up > down {
                let mut plus = theta.to_vec();
                plus[k] = up;
                let mut minus = theta.to_vec();
                minus[k] = down;
                let (rp, rm) = (self.evaluate(&plus)?, self.evaluate(&minus)?);
                DVector::from_iterator(rp.len(), rp.iter().zip(&rm).map(|(p, m)| (p - m) / (up - down)))
            } else {
                // a range narrower than the step's round-off: the parameter cannot move
                let m = match rows {
                    Some(m) => m,
                    None => self.evaluate(theta)?.len(),
                };
                DVector::zeros(m)
            };
            rows = Some(column.len());
            columns.push(column);
        }
        Some(DMatrix::from_columns(&columns))
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &LmVector<f64>) {
        self.theta.copy_from(x);
    }

    fn params(&self) -> LmVector<f64> {
        self.theta.clone()
    }

    fn residuals(&self) -> Option<LmVector<f64>> {
        self.evaluate(self.theta.as_slice()).map(LmVector::from_vec)
    }

    fn jacobian(&self) -> Option<LmMatrix<f64>> {
        let j = self.jacobian_at(self.theta.as_slice())?;
        Some(LmMatrix::from_column_slice(j.nrows(), j.ncols(), j.as_slice()))
    }
}

/// Fit `names` (the free parameters) from `start`, each held in its closed range `bounds` (lower,
/// upper; infinite for none), with `scale` (positive) the size of each, and `step` the relative step
/// of the central differences (1e-6 for closed forms; larger for a finite-element model, whose
/// equilibrium is converged to a tolerance). `residuals` is only ever called with every value in
/// its range.
///
/// # Errors
/// [`CalibrationError::Unidentifiable`] when the data cannot tell the parameters apart (or one has
/// no effect), [`CalibrationError::NotConverged`] when the iteration fails, and any error of the
/// residuals themselves.
pub fn least_squares(
    residuals: &Residuals,
    names: &[String],
    start: &[f64],
    scale: &[f64],
    bounds: &[(f64, f64)],
    step: f64,
) -> Result<LeastSquares, CalibrationError> {
    let range: Vec<(f64, f64)> = bounds.iter().zip(scale).map(|(&(lo, hi), s)| (lo / s, hi / s)).collect();
    let problem = Problem {
        residuals,
        scale: scale.to_vec(),
        theta: LmVector::from_iterator(
            start.len(),
            start.iter().zip(scale).zip(&range).map(|((v, s), &(lo, hi))| (v / s).max(lo).min(hi)),
        ),
        range,
        step,
        failure: RefCell::new(None),
        evaluations: RefCell::new(0),
    };
    let (problem, report) = LevenbergMarquardt::new().with_patience(200).minimize(problem);
    let evaluations = *problem.evaluations.borrow();
    if let Some(e) = problem.failure.borrow_mut().take() {
        return Err(e);
    }
    // where the iteration ended, held in the ranges: a parameter there at a bound stays at it
    let ended: Vec<f64> = problem.theta.iter().copied().collect();
    let theta = problem.held(&ended);
    let at_bound: Vec<bool> = theta.iter().zip(&problem.range).map(|(&t, &(lo, hi))| t <= lo || t >= hi).collect();
    let r = problem.evaluate(&theta).ok_or_else(|| CalibrationError::NotConverged {
        evaluations,
        reason: "the model gives no finite curve at the last parameters".into(),
    })?;
    let j = problem.jacobian_at(&theta).ok_or_else(|| CalibrationError::NotConverged {
        evaluations,
        reason: "the model gives no finite curve next to the last parameters".into(),
    })?;
    // every free parameter, those at a bound too (their one-sided effect): c at 0 and φ at one
    // normal stress are still told apart only together
    identifiable(&j, names)?;
    if !report.termination.was_successful() {
        return Err(CalibrationError::NotConverged { evaluations, reason: format!("{:?}", report.termination) });
    }
    // the statistics of the parameters not at a bound
    let estimated: Vec<usize> = (0..theta.len()).filter(|&k| !at_bound[k]).collect();
    let (m, p) = (r.len(), estimated.len());
    if m <= p {
        return Err(CalibrationError::Unidentifiable {
            parameters: estimated.iter().map(|&k| names[k].clone()).collect(),
            reason: format!("{m} measured points for {p} parameters"),
        });
    }
    let sse: f64 = r.iter().map(|v| v * v).sum();
    let dof = m - p;
    let s2 = sse / dof as f64;
    let je = DMatrix::from_fn(m, p, |row, c| j[(row, estimated[c])]);
    let jtj = je.transpose() * &je;
    let inverse = if p == 0 {
        DMatrix::zeros(0, 0)
    } else {
        jtj.try_inverse().ok_or_else(|| CalibrationError::Unidentifiable {
            parameters: estimated.iter().map(|&k| names[k].clone()).collect(),
            reason: "JᵀJ is singular".into(),
        })?
    };
    let values = problem.values(&theta);
    let se_scale: Vec<f64> = estimated.iter().map(|&k| scale[k]).collect();
    let cov = DMatrix::from_fn(p, p, |a, b| s2 * inverse[(a, b)] * se_scale[a] * se_scale[b]);
    let errors: Vec<f64> = (0..p).map(|a| cov[(a, a)].max(0.0).sqrt()).collect();
    let t_quantile = StudentsT::new(0.0, 1.0, dof as f64).map(|t| t.inverse_cdf(0.975)).unwrap_or(1.959964);
    let mut standard_errors = vec![None; theta.len()];
    let mut intervals = vec![None; theta.len()];
    for (a, &k) in estimated.iter().enumerate() {
        standard_errors[k] = Some(errors[a]);
        intervals[k] = Some((values[k] - t_quantile * errors[a], values[k] + t_quantile * errors[a]));
    }
    let correlation = (0..p).map(|a| (0..p).map(|b| cov[(a, b)] / (errors[a] * errors[b])).collect()).collect();
    Ok(LeastSquares {
        values,
        at_bound,
        standard_errors,
        intervals,
        correlation,
        rms: (sse / m as f64).sqrt(),
        points: m,
        degrees_of_freedom: dof,
        t_quantile,
        evaluations,
    })
}

/// Refuse a Jacobian whose columns (normalised) are nearly dependent, naming the parameters of the
/// dependent combination, or a column that is zero.
fn identifiable(j: &DMatrix<f64>, names: &[String]) -> Result<(), CalibrationError> {
    let norms: Vec<f64> = j.column_iter().map(|c| c.norm()).collect();
    let largest_norm = norms.iter().copied().fold(0.0, f64::max);
    let active: Vec<usize> = (0..names.len()).filter(|&k| norms[k] > 1e-12 * largest_norm).collect();
    let idle: Vec<String> = (0..names.len()).filter(|k| !active.contains(k)).map(|k| names[k].clone()).collect();
    // among the parameters that do act: every one of a combination that leaves the curves (nearly)
    // unchanged
    let mut together: Vec<String> = Vec::new();
    let mut worst = f64::MAX;
    if !active.is_empty() {
        let normalised = DMatrix::from_fn(j.nrows(), active.len(), |r, c| j[(r, active[c])] / norms[active[c]]);
        let svd = normalised.svd(false, true);
        let largest = svd.singular_values.max();
        let v_t = svd.v_t.expect("asked for");
        for (k, &s) in svd.singular_values.iter().enumerate() {
            if s < IDENTIFIABLE * largest {
                worst = worst.min(s / largest);
                for (&a, v) in active.iter().zip(v_t.row(k).iter()) {
                    if v.abs() >= 0.2 && !together.contains(&names[a]) {
                        together.push(names[a].clone());
                    }
                }
            }
        }
    }
    if idle.is_empty() && together.is_empty() {
        return Ok(());
    }
    let mut reasons = Vec::new();
    if !together.is_empty() {
        together.sort_by_key(|n| names.iter().position(|m| m == n));
        reasons.push(format!(
            "{} change the modelled curves only together (a combination of them changes them by {worst:.0e} of \
             the largest effect of one)",
            together.join(", ")
        ));
    }
    if !idle.is_empty() {
        reasons.push(format!("the modelled curves do not change with {} over the measured range", idle.join(", ")));
    }
    let mut parameters: Vec<String> = together.into_iter().chain(idle).collect();
    parameters.sort_by_key(|n| names.iter().position(|m| m == n));
    Err(CalibrationError::Unidentifiable { parameters, reason: reasons.join("; and ") })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_line_is_fitted_with_the_textbook_standard_errors() {
        // y = a + b·x over x = 0..9 with residuals ±0.1 alternating: b's standard error is
        // s/√Σ(x − x̄)², s² = Σr²/(n − 2)
        let x: Vec<f64> = (0..10).map(f64::from).collect();
        let y: Vec<f64> =
            x.iter().enumerate().map(|(i, x)| 2.0 + 0.5 * x + if i % 2 == 0 { 0.1 } else { -0.1 }).collect();
        let residuals = |p: &[f64]| Ok(x.iter().zip(&y).map(|(x, y)| p[0] + p[1] * x - y).collect());
        let free = [(f64::NEG_INFINITY, f64::INFINITY); 2];
        let fit = least_squares(&residuals, &["a".into(), "b".into()], &[1.0, 1.0], &[1.0, 1.0], &free, 1e-6).unwrap();
        // least squares on the data directly
        let n = 10.0;
        let (xm, ym) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
        let sxx: f64 = x.iter().map(|x| (x - xm).powi(2)).sum();
        let b = x.iter().zip(&y).map(|(x, y)| (x - xm) * (y - ym)).sum::<f64>() / sxx;
        let a = ym - b * xm;
        let s2: f64 = x.iter().zip(&y).map(|(x, y)| (a + b * x - y).powi(2)).sum::<f64>() / (n - 2.0);
        assert!((fit.values[0] - a).abs() < 1e-8 && (fit.values[1] - b).abs() < 1e-8, "{fit:?}");
        assert!((fit.standard_errors[1].unwrap() - (s2 / sxx).sqrt()).abs() < 1e-6 * (s2 / sxx).sqrt());
        assert_eq!(fit.at_bound, vec![false, false]);
        // t(0.975, 8) = 2.306004
        assert!((fit.t_quantile - 2.306004).abs() < 1e-5);
    }

    #[test]
    fn two_parameters_that_act_only_together_are_named() {
        let x: Vec<f64> = (0..10).map(f64::from).collect();
        let residuals = |p: &[f64]| Ok(x.iter().map(|x| (p[0] + p[1]) * x - 3.0 * x).collect());
        let free = [(f64::NEG_INFINITY, f64::INFINITY); 2];
        let e =
            least_squares(&residuals, &["c".into(), "d".into()], &[1.0, 1.0], &[1.0, 1.0], &free, 1e-6).unwrap_err();
        match e {
            CalibrationError::Unidentifiable { parameters, .. } => assert_eq!(parameters, vec!["c", "d"]),
            other => panic!("{other}"),
        }
    }

    /// y = a + b·x with a ≥ 0 on data of the line −1 + 0.5·x (x = 1..10, residuals ±0.1): the
    /// residuals never see a < 0, a ends at 0 without a standard error, and b is then the slope of
    /// the least-squares line through the origin, Σxy/Σx², with its textbook standard error
    /// s/√Σx², s² = Σr²/(n − 1).
    #[test]
    fn a_parameter_that_the_data_would_take_below_its_range_is_held_at_the_bound() {
        let x: Vec<f64> = (1..=10).map(f64::from).collect();
        let y: Vec<f64> =
            x.iter().enumerate().map(|(i, x)| -1.0 + 0.5 * x + if i % 2 == 0 { 0.1 } else { -0.1 }).collect();
        let lowest = std::cell::Cell::new(f64::MAX);
        let residuals = |p: &[f64]| {
            lowest.set(lowest.get().min(p[0]));
            Ok(x.iter().zip(&y).map(|(x, y)| p[0] + p[1] * x - y).collect())
        };
        let bounds = [(0.0, f64::INFINITY), (f64::NEG_INFINITY, f64::INFINITY)];
        let fit = least_squares(&residuals, &["a".into(), "b".into()], &[1.0, 1.0], &[1.0, 1.0], &bounds, 1e-6)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(lowest.get(), 0.0, "the residuals were asked for a = {}", lowest.get());
        assert_eq!(fit.values[0], 0.0);
        assert_eq!(fit.at_bound, vec![true, false]);
        assert!(fit.standard_errors[0].is_none() && fit.intervals[0].is_none());
        let sxx: f64 = x.iter().map(|x| x * x).sum();
        let b = x.iter().zip(&y).map(|(x, y)| x * y).sum::<f64>() / sxx;
        let s2: f64 = x.iter().zip(&y).map(|(x, y)| (b * x - y).powi(2)).sum::<f64>() / 9.0;
        assert!((fit.values[1] - b).abs() < 1e-8, "{} against {b}", fit.values[1]);
        let se = fit.standard_errors[1].unwrap();
        assert!((se - (s2 / sxx).sqrt()).abs() < 1e-6 * (s2 / sxx).sqrt(), "{se}");
        assert_eq!(fit.degrees_of_freedom, 9);
        assert_eq!(fit.correlation.len(), 1);
    }
}
