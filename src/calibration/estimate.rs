//! Starting values read off the curves the way an engineer would by hand: the initial slope, the
//! peak and the end of each curve, with c and tan φ from a straight line through the peaks (and the
//! residuals) against the normal stress.

use super::curves::Curve;
use super::parameters::{LawFamily, Parameter};
use super::pullout_closed_form::Reinforcement;

/// A straight line y = a + b·x through the points by least squares (b = y/x through the origin for
/// a single point).
fn line(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    if points.len() < 2 {
        let (x, y) = points.first().copied().unwrap_or((1.0, 0.0));
        return (0.0, if x > 0.0 { y / x } else { 0.0 });
    }
    let (xm, ym) = (points.iter().map(|p| p.0).sum::<f64>() / n, points.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = points.iter().map(|p| (p.0 - xm).powi(2)).sum();
    if sxx == 0.0 {
        return (0.0, if xm > 0.0 { ym / xm } else { 0.0 });
    }
    let b = points.iter().map(|p| (p.0 - xm) * (p.1 - ym)).sum::<f64>() / sxx;
    (ym - b * xm, b)
}

/// c ≥ 0 and φ from a line through (σn, τ); when the line's intercept is negative, through the
/// origin.
fn strength(points: &[(f64, f64)]) -> (f64, f64) {
    let (mut c, mut tan) = line(points);
    if c < 0.0 || tan <= 0.0 {
        let (sx, sxy) = points.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0 * p.0, a.1 + p.0 * p.1));
        c = 0.0;
        tan = if sx > 0.0 { sxy / sx } else { 0.5 };
    }
    (c.max(0.0), tan.max(1e-3).atan().to_degrees())
}

fn peak_index(c: &Curve) -> usize {
    c.y.iter().enumerate().fold((0, f64::MIN), |a, (i, &y)| if y > a.1 { (i, y) } else { a }).0
}

/// The slope through the origin of the points up to half the curve's peak.
fn initial_slope(c: &Curve) -> f64 {
    let half = 0.5 * c.y[peak_index(c)];
    let (sxy, sxx) =
        c.x.iter()
            .zip(&c.y)
            .take_while(|(_, &y)| y <= half)
            .filter(|(x, _)| **x > 0.0)
            .fold((0.0, 0.0), |a, (x, y)| (a.0 + x * y, a.1 + x * x));
    if sxx > 0.0 {
        sxy / sxx
    } else {
        // the first point with a slip is already past half the peak
        c.x.iter().zip(&c.y).find(|(x, _)| **x > 0.0).map_or(1.0, |(x, y)| y / x)
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(1.0)
}

/// Starting values of every parameter of `law` from direct-shear curves.
pub fn direct_shear(law: LawFamily, curves: &[Curve]) -> Vec<(Parameter, f64)> {
    let ks = median(curves.iter().map(initial_slope).collect());
    let peaks: Vec<(f64, f64)> = curves.iter().map(|c| (c.condition, c.y[peak_index(c)])).collect();
    let (c, phi) = strength(&peaks);
    let mut values = vec![(Parameter::ShearStiffness, ks), (Parameter::Cohesion, c), (Parameter::FrictionAngle, phi)];
    if law == LawFamily::Hyperbolic {
        // the measured peak is below the asymptote: start a tenth above it
        values[1].1 *= 1.1;
        values[2].1 = (phi.to_radians().tan() * 1.1).atan().to_degrees();
        // the half-peak secant of a hyperbola is half its initial slope
        values[0].1 *= 2.0;
    }
    if law == LawFamily::Softening {
        // the residual: the mean of each curve's last tenth
        let ends: Vec<(f64, f64)> = curves
            .iter()
            .map(|c| {
                let n = (c.y.len() / 10).max(1);
                (c.condition, c.y[c.y.len() - n..].iter().sum::<f64>() / n as f64)
            })
            .collect();
        let (cr, phir) = strength(&ends);
        // the plastic slip from the peak to where the curve is nine tenths of the way down
        let slips: Vec<f64> = curves
            .iter()
            .zip(&ends)
            .map(|(c, &(_, end))| {
                let i = peak_index(c);
                let target = c.y[i] - 0.9 * (c.y[i] - end);
                let j = (i..c.y.len()).find(|&j| c.y[j] <= target).unwrap_or(c.y.len() - 1);
                (c.x[j] - c.x[i]).max(1e-4)
            })
            .collect();
        values.push((Parameter::ResidualCohesion, cr.min(c)));
        values.push((Parameter::ResidualFrictionAngle, phir.min(phi)));
        values.push((Parameter::SofteningSlip, median(slips)));
    }
    values
}

/// Starting values of every parameter of `law` from pull-out curves: τ = P_max/(n_f·L) against
/// the surcharge for c and φ, and Ks from the head stiffness EA·α·tanh(αL) of the first points.
pub fn pull_out(law: LawFamily, curves: &[Curve], r: &Reinforcement) -> Vec<(Parameter, f64)> {
    let peaks: Vec<(f64, f64)> =
        curves.iter().map(|c| (c.condition, c.y[peak_index(c)] / (r.faces * r.length))).collect();
    let (c, phi) = strength(&peaks);
    let head_stiffness = median(curves.iter().map(initial_slope).collect());
    // K(Ks) = EA·α·tanh(αL), α = √(n_f·Ks/EA), grows with Ks: bisect on log Ks
    let k_of = |ks: f64| {
        let alpha = (r.faces * ks / r.axial_stiffness).sqrt();
        r.axial_stiffness * alpha * (alpha * r.length).tanh()
    };
    let (mut lo, mut hi) = (1e-6f64.ln(), 1e12f64.ln());
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if k_of(mid.exp()) < head_stiffness {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let ks = (0.5 * (lo + hi)).exp();
    let mut values = vec![(Parameter::ShearStiffness, ks), (Parameter::Cohesion, c), (Parameter::FrictionAngle, phi)];
    if law == LawFamily::Softening {
        values.push((Parameter::ResidualCohesion, 0.8 * c));
        values.push((Parameter::ResidualFrictionAngle, 0.8 * phi));
        let span = curves.iter().map(|c| c.x.iter().copied().fold(0.0, f64::max)).fold(0.0, f64::max);
        values.push((Parameter::SofteningSlip, 0.3 * span));
    }
    values
}
