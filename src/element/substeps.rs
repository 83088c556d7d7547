//! What the two substepped soil laws (Duncan–Chang, hardening soil) share: an integration over a
//! number of equal substeps that is not rounded, so that the update is a continuous function of
//! the strain, and the update's derivative by forward differences.

use nalgebra::Matrix4;

/// The strain step of a difference tangent, as a fraction of the increment's largest component.
const DIFFERENCE_STEP: f64 = 1e-6;
/// The increment below which the difference step stops shrinking.
const SMALLEST_INCREMENT: f64 = 1e-8;

/// The integration in `count` (≥ 1, not a whole number) substeps: ⌊count⌋ substeps blended with
/// ⌊count⌋ + 1 by the fraction, `blend(fewer, more, share)`. A whole number of substeps, or an
/// error-controlled partition, jumps as the strain changes, which Newton's method cannot follow.
pub fn blended<T>(count: f64, integrate_in: impl Fn(usize) -> T, blend: impl Fn(&T, &T, f64) -> T) -> T {
    let fewer = count.max(1.0).floor();
    let share = count.max(1.0) - fewer;
    let coarse = integrate_in(fewer as usize);
    if share == 0.0 {
        return coarse;
    }
    let fine = integrate_in(fewer as usize + 1);
    blend(&coarse, &fine, share)
}

/// The derivative of an update by its strain (εxx, εyy, γxy, εzz), by forward differences (after
/// Pérez-Foguet, Rodríguez-Ferran & Huerta 2000, "Numerical differentiation for local and global
/// tangent operators in computational plasticity", CMAME 189, 277–296): each component of
/// `d_strain` perturbed by [`DIFFERENCE_STEP`] of the increment's largest; `stress` is the update
/// of `d_strain` itself, `integrate` the stress of a perturbed increment.
pub fn difference_tangent(
    d_strain: [f64; 4],
    stress: &[f64; 4],
    integrate: impl Fn([f64; 4]) -> [f64; 4],
) -> Matrix4<f64> {
    let size = d_strain.iter().fold(SMALLEST_INCREMENT, |m, x| m.max(x.abs()));
    let h = DIFFERENCE_STEP * size;
    let mut t = Matrix4::zeros();
    for j in 0..4 {
        let mut e = d_strain;
        e[j] += h;
        let other = integrate(e);
        for i in 0..4 {
            t[(i, j)] = (other[i] - stress[i]) / h;
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: a linear map's forward difference is the map; a blend at a whole count is that
    /// count's integration, and halfway is the mean of its neighbours.
    #[test]
    fn a_linear_update_differentiates_to_its_matrix_and_counts_blend_linearly() {
        let a = Matrix4::new(2.0, 1.0, 0.0, 0.5, 1.0, 3.0, 0.2, 0.0, 0.0, 0.3, 1.0, 0.0, 0.5, 0.0, 0.0, 4.0);
        let apply = |e: [f64; 4]| -> [f64; 4] { (a * nalgebra::Vector4::from(e)).into() };
        let e = [1e-3, -2e-3, 5e-4, 0.0];
        let t = difference_tangent(e, &apply(e), apply);
        assert!((t - a).amax() < 1e-6 * a.amax(), "{t}");
        let count = |n: usize| n as f64;
        assert_eq!(blended(3.0, count, |x, y, s| x + s * (y - x)), 3.0);
        assert!((blended(3.5, count, |x, y, s| x + s * (y - x)) - 3.5).abs() < 1e-15);
        assert_eq!(blended(0.2, count, |x, y, s| x + s * (y - x)), 1.0);
    }
}
