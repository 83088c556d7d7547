//! Lysmer & Kuhlemeyer's viscous boundary (J. Eng. Mech. Div. ASCE 95(EM4), 1969): on a side of
//! the soil, dashpots that apply the tractions t_n = −ρ·Vp·v_n and t_s = −ρ·Vs·v_s, the tractions a
//! plane P or S wave meeting the side at normal incidence carries on beyond it, so that such a wave
//! passes out without reflection (at other incidences a part comes back: their Fig. 3).
//!
//! The side's damping matrix ∫ Nᵀ·(ρVp·n nᵀ + ρVs·s sᵀ)·N ds is lumped by rows onto its nodes:
//! each node's 2 × 2 block is ∫ Nᵢ·(ρVp·n nᵀ + ρVs·s sᵀ) ds, positive for two- and three-node
//! sides alike (∫Nᵢ ds = L/2; or L/6, L/6, 2L/3). In axisymmetry the side is a surface of
//! revolution (∫ … 2πr ds).

use super::geometry::Geometry;
use super::solid::side_shape;

/// Each node's 2 × 2 dashpot block of a side through `coords` (`[a, b]` or `[a, b, mid]`), with
/// the impedances ρ·Vp (`normal`) and ρ·Vs (`tangential`) per unit area.
pub fn side_dashpots(coords: &[[f64; 2]], normal: f64, tangential: f64, geometry: Geometry) -> Vec<[[f64; 2]; 2]> {
    let g = (0.6f64).sqrt();
    let rule = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
    let mut blocks = vec![[[0.0; 2]; 2]; coords.len()];
    for (s, w) in rule {
        let (n, dn) = side_shape(coords.len(), s);
        let mut dx = [0.0; 2];
        let mut x = [0.0; 2];
        for ((d, ni), c) in dn.iter().zip(&n).zip(coords) {
            dx[0] += d * c[0];
            dx[1] += d * c[1];
            x[0] += ni * c[0];
            x[1] += ni * c[1];
        }
        let ds = dx[0].hypot(dx[1]);
        if ds == 0.0 {
            continue;
        }
        let t = [dx[0] / ds, dx[1] / ds];
        let nn = [t[1], -t[0]];
        let weight = w * ds * geometry.circumference(x);
        for (block, ni) in blocks.iter_mut().zip(&n) {
            for (i, row) in block.iter_mut().enumerate() {
                for (j, entry) in row.iter_mut().enumerate() {
                    *entry += ni * weight * (normal * nn[i] * nn[j] + tangential * t[i] * t[j]);
                }
            }
        }
    }
    blocks
}

#[cfg(test)]
mod tests {
    //! The lumped dashpots of a straight side: the impedance times the side's length (or area of
    //! revolution) shared as ∫Nᵢ ds, along the side's normal and tangent.
    use super::*;

    #[test]
    fn a_horizontal_side_shares_its_length() {
        let blocks = side_dashpots(&[[0.0, 0.0], [2.0, 0.0]], 3.0, 1.0, Geometry::PlaneStrain);
        for b in &blocks {
            assert!((b[0][0] - 1.0).abs() < 1e-14 && (b[1][1] - 3.0).abs() < 1e-14 && b[0][1].abs() < 1e-14);
        }
        let blocks = side_dashpots(&[[0.0, 0.0], [0.0, 6.0], [0.0, 3.0]], 3.0, 1.0, Geometry::PlaneStrain);
        let shares = [1.0, 1.0, 4.0];
        for (b, share) in blocks.iter().zip(shares) {
            assert!((b[0][0] - 3.0 * share).abs() < 1e-13 && (b[1][1] - share).abs() < 1e-13, "{b:?}");
        }
    }

    #[test]
    fn an_inclined_side_acts_along_its_normal_and_tangent() {
        // a side at 45°: n nᵀ and s sᵀ are [[½, ∓½], [∓½, ½]]
        let blocks = side_dashpots(&[[0.0, 0.0], [1.0, 1.0]], 3.0, 1.0, Geometry::PlaneStrain);
        let half_length = 0.5 * 2f64.sqrt();
        for b in &blocks {
            assert!((b[0][0] - 2.0 * half_length).abs() < 1e-14);
            assert!((b[0][1] + half_length).abs() < 1e-14, "{b:?}");
        }
    }

    #[test]
    fn an_axisymmetric_side_is_a_surface_of_revolution() {
        // the base of a cylinder of radius 2: area 4π, shared as ∫Nᵢ·2πr dr = 2π·(2/3, 4/3)
        let blocks = side_dashpots(&[[0.0, 0.0], [2.0, 0.0]], 1.0, 1.0, Geometry::Axisymmetric);
        let two_pi = 2.0 * std::f64::consts::PI;
        assert!((blocks[0][1][1] - two_pi * 2.0 / 3.0).abs() < 1e-12);
        assert!((blocks[1][1][1] - two_pi * 4.0 / 3.0).abs() < 1e-12);
    }
}
