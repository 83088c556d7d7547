//! Element formulations: plane-strain and axisymmetric soil solids and reinforcement bars.

pub mod bar;
pub mod dashpot;
pub mod duncan_chang;
pub mod geometry;
pub mod hardening_soil;
pub mod mass;
pub mod mohr_coulomb;
pub mod soil_law;
pub mod soil_state;
pub mod solid;
pub mod substeps;
pub mod yield_mechanisms;

/// The radial strain that holds σr of a triaxial point: the root of `residual` (σr less its
/// target, rising with the radial strain) in [−`bound`, `bound`], by regula falsi (Illinois), to
/// `tolerance` of `scale`. Shared by the tests of the soil laws at one point.
#[cfg(test)]
pub(crate) fn radial_strain_holding(residual: impl Fn(f64) -> f64, bound: f64, tolerance: f64, scale: f64) -> f64 {
    let (mut a, mut b) = (-bound, bound);
    let (mut ra, mut rb) = (residual(a), residual(b));
    assert!(ra < 0.0 && rb > 0.0, "the radial strain is not bracketed: {ra} {rb}");
    let mut er = 0.0;
    for _ in 0..200 {
        er = (a * rb - b * ra) / (rb - ra);
        let r = residual(er);
        if r.abs() < tolerance * scale {
            break;
        }
        if r > 0.0 {
            (b, rb) = (er, r);
            ra *= 0.5;
        } else {
            (a, ra) = (er, r);
            rb *= 0.5;
        }
    }
    er
}
