//! Iterative refinement of a direct solve, shared by the full system and the condensed one: when
//! pivoting (on a saddle point, or a dense interface system) left more than 1e-10 in the relative
//! residual, at most two corrections, each kept only if it lowers the residual. The outer
//! (equilibrium) iteration corrects anything smaller.

use super::norm2;

/// Relative residuals above this are refined.
const REFINE_ABOVE: f64 = 1e-10;
/// A solution is accepted when its relative residual is below this.
const ACCEPT_BELOW: f64 = 1e-6;

/// A factorised system that can give its residual and solve for a correction.
pub(crate) trait Refinable {
    type Error;
    /// b − A·x.
    fn residual(&self, x: &[f64], rhs: &[f64]) -> Vec<f64>;
    /// A⁻¹·r with the factorisation at hand (counted as a solve by the implementor).
    fn correct(&mut self, r: &[f64]) -> Result<Vec<f64>, Self::Error>;
}

/// ‖r‖ / ‖b‖ (‖r‖ when b = 0).
fn relative(r: &[f64], rhs: &[f64]) -> f64 {
    let (r, b) = (norm2(r), norm2(rhs));
    if b > 0.0 {
        r / b
    } else {
        r
    }
}

/// `x` (A's first solution for `rhs`) refined: the solution and its relative residual.
pub(crate) fn refine<R: Refinable>(system: &mut R, mut x: Vec<f64>, rhs: &[f64]) -> Result<(Vec<f64>, f64), R::Error> {
    let mut r = system.residual(&x, rhs);
    let mut residual = relative(&r, rhs);
    for _ in 0..2 {
        if !(residual > REFINE_ABOVE) || !x.iter().all(|v| v.is_finite()) {
            break;
        }
        let dx = system.correct(&r)?;
        let refined: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
        let refined_r = system.residual(&refined, rhs);
        let refined_residual = relative(&refined_r, rhs);
        if refined_residual < residual {
            x = refined;
            r = refined_r;
            residual = refined_residual;
        } else {
            break;
        }
    }
    Ok((x, residual))
}

/// Whether a refined solution is accepted: finite, and its relative residual below 1e-6.
pub(crate) fn accepted(x: &[f64], residual: f64) -> bool {
    x.iter().all(|v| v.is_finite()) && residual < ACCEPT_BELOW
}
