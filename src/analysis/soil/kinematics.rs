//! A Gauss point's strain from its element's displacements, and its stress's work back onto the
//! element's nodes (Bᵀσ): plane strain or axisymmetric.

use crate::element::solid::MappedPoint;

/// Strain (εxx, εyy, γxy, εzz) at a mapped point for element displacements `u_e`: εzz is zero in
/// plane strain and the hoop strain Σ N_i·u_xi/r in axisymmetry.
pub(super) fn strain(p: &MappedPoint, u_e: &[f64]) -> [f64; 4] {
    let mut e = [0.0; 4];
    for (i, d) in p.dn_dx.iter().enumerate() {
        let (ux, uy) = (u_e[2 * i], u_e[2 * i + 1]);
        e[0] += d[0] * ux;
        e[1] += d[1] * uy;
        e[2] += d[1] * ux + d[0] * uy;
    }
    if let Some(inverse_radius) = p.inverse_radius {
        e[3] = p.n.iter().enumerate().map(|(i, n)| n * u_e[2 * i]).sum::<f64>() * inverse_radius;
    }
    e
}

/// Add Bᵀ·(σxx, σyy, τxy, σzz)·w to an element force vector (σzz, the hoop stress, only in
/// axisymmetry: in plane strain εzz = 0 does no work).
pub(super) fn add_bt_sigma(p: &MappedPoint, s: [f64; 4], f: &mut [f64]) {
    for (i, d) in p.dn_dx.iter().enumerate() {
        f[2 * i] += (d[0] * s[0] + d[1] * s[2]) * p.weight;
        f[2 * i + 1] += (d[1] * s[1] + d[0] * s[2]) * p.weight;
    }
    if let Some(inverse_radius) = p.inverse_radius {
        for (i, n) in p.n.iter().enumerate() {
            f[2 * i] += n * inverse_radius * s[3] * p.weight;
        }
    }
}
