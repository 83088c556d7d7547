//! The mass matrix of a soil element: consistent, M_e = ∫ ρ NᵀN dV, or lumped by HRZ's diagonal
//! scaling (Hinton, Rock & Zienkiewicz 1976; Zienkiewicz & Taylor vol. 1 §16.2.4: the diagonal of
//! the consistent matrix scaled to the element's mass, which keeps every nodal mass positive on
//! the six-node triangle, where lumping by row sums gives its corners none).
//!
//! dV is dA per metre width in plane strain and 2πr dA in axisymmetry, as for the stiffness. The
//! integrand NᵀN·ρ·det J (·r) is a polynomial of degree up to 5 on an undistorted element, so the
//! rules here are exact for it: Dunavant's seven-point rule (degree 5) on triangles, 3 × 3 Gauss on
//! quadrilaterals; ρ is taken at each point.

use super::geometry::Geometry;
use super::solid::{shape, SolidKind};
use nalgebra::DMatrix;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// How an element's mass is spread over its nodes (the model file's `mass`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Lumping {
    /// Nodal masses only: the diagonal of the consistent matrix scaled to the element's mass.
    #[default]
    Lumped,
    /// M_e = ∫ ρ NᵀN dV.
    Consistent,
}

/// A bar's mass matrix (4 × 4, DOF order ux1, uy1, ux2, uy2) for its total mass `mass`: half at
/// each node (lumped), or ∫ m̄·NᵀN ds, `mass`/6·[2 1; 1 2] in each direction (consistent).
pub fn bar_mass(mass: f64, lumping: Lumping) -> DMatrix<f64> {
    DMatrix::from_fn(4, 4, |a, c| match lumping {
        Lumping::Lumped => {
            if a == c {
                mass / 2.0
            } else {
                0.0
            }
        }
        Lumping::Consistent if a == c => mass / 3.0,
        Lumping::Consistent if a % 2 == c % 2 => mass / 6.0,
        Lumping::Consistent => 0.0,
    })
}

/// The element's mass matrix (2n × 2n, DOF order ux1, uy1, ux2, …) for the density `density` at a
/// point [mass/length³], of an element the model's validation accepted. The integral is taken
/// with det J as it is at each point: its rule's points are not those the validation checked (a
/// curved quadratic element may have det J ≤ 0 at one of them), and the integral is the element's
/// mass all the same.
pub fn mass(
    kind: SolidKind,
    coords: &[[f64; 2]],
    density: impl Fn([f64; 2]) -> f64,
    geometry: Geometry,
    lumping: Lumping,
) -> DMatrix<f64> {
    let n = coords.len();
    // the scalar matrix ∫ ρ N_i N_j dV, the same for x and y
    let mut scalar = DMatrix::<f64>::zeros(n, n);
    for (xi, eta, w) in mass_rule(kind) {
        let (shape_values, derivatives) = shape(kind, xi, eta);
        let mut j = [[0.0; 2]; 2];
        let mut x = [0.0; 2];
        for ((d, c), v) in derivatives.iter().zip(coords).zip(&shape_values) {
            for a in 0..2 {
                j[a][0] += d[a] * c[0];
                j[a][1] += d[a] * c[1];
                x[a] += v * c[a];
            }
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let weight = w * det * geometry.circumference(x) * density(x);
        for a in 0..n {
            for b in 0..n {
                scalar[(a, b)] += shape_values[a] * shape_values[b] * weight;
            }
        }
    }
    if lumping == Lumping::Lumped {
        let total = scalar.sum();
        let diagonal = scalar.diagonal().sum();
        let factor = if diagonal > 0.0 { total / diagonal } else { 0.0 };
        scalar = DMatrix::from_diagonal(&(scalar.diagonal() * factor));
    }
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    for a in 0..n {
        for b in 0..n {
            m[(2 * a, 2 * b)] = scalar[(a, b)];
            m[(2 * a + 1, 2 * b + 1)] = scalar[(a, b)];
        }
    }
    m
}

/// Points (ξ, η, weight) exact for polynomials of degree 5 on the element's natural domain.
fn mass_rule(kind: SolidKind) -> Vec<(f64, f64, f64)> {
    match kind {
        SolidKind::Tri3 | SolidKind::Tri6 => {
            // Dunavant (1985), degree 5: the centroid and two orbits of three points; weights sum
            // to 1, times the reference triangle's area 1/2
            let (a1, b1, w1) = (0.059_715_871_789_770, 0.470_142_064_105_115, 0.132_394_152_788_506);
            let (a2, b2, w2) = (0.797_426_985_353_087, 0.101_286_507_323_456, 0.125_939_180_544_827);
            let mut points = vec![(1.0 / 3.0, 1.0 / 3.0, 0.225 * 0.5)];
            for (a, b, w) in [(a1, b1, w1), (a2, b2, w2)] {
                points.extend([(b, b, w * 0.5), (a, b, w * 0.5), (b, a, w * 0.5)]);
            }
            points
        }
        SolidKind::Quad4 | SolidKind::Quad8 => {
            let g = 0.6f64.sqrt();
            let line = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
            line.iter().flat_map(|&(eta, we)| line.iter().map(move |&(xi, wx)| (xi, eta, wx * we))).collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RHO: f64 = 2.0;

    fn element(kind: SolidKind) -> Vec<[f64; 2]> {
        // a parallelogram or triangle away from the axis, corners counter-clockwise
        let (a, b, c, d) = ([1.0, 0.5], [3.0, 0.7], [3.4, 2.2], [1.4, 2.0]);
        let mid = |p: [f64; 2], q: [f64; 2]| [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
        match kind {
            SolidKind::Tri3 => vec![a, b, c],
            SolidKind::Tri6 => vec![a, b, c, mid(a, b), mid(b, c), mid(c, a)],
            SolidKind::Quad4 => vec![a, b, c, d],
            SolidKind::Quad8 => vec![a, b, c, d, mid(a, b), mid(b, c), mid(c, d), mid(d, a)],
        }
    }

    /// The area and the first moment ∫x dA of the element's corner polygon (shoelace formulas).
    fn area_and_moment(corners: &[[f64; 2]]) -> (f64, f64) {
        let (mut area, mut moment) = (0.0, 0.0);
        for (i, p) in corners.iter().enumerate() {
            let q = corners[(i + 1) % corners.len()];
            let cross = p[0] * q[1] - q[0] * p[1];
            area += cross / 2.0;
            moment += (p[0] + q[0]) * cross / 6.0;
        }
        (area, moment)
    }

    /// Each direction's masses add up to ρ·A (plane strain) or ρ·2π∫r dA (Pappus), consistent
    /// and lumped, and every lumped nodal mass is positive.
    #[test]
    fn masses_add_up_to_the_element_mass_and_lumped_ones_are_positive() {
        for kind in [SolidKind::Tri3, SolidKind::Tri6, SolidKind::Quad4, SolidKind::Quad8] {
            let coords = element(kind);
            let corners = &coords[..if matches!(kind, SolidKind::Tri3 | SolidKind::Tri6) { 3 } else { 4 }];
            let (area, moment) = area_and_moment(corners);
            for (geometry, expected) in [
                (Geometry::PlaneStrain, RHO * area),
                (Geometry::Axisymmetric, RHO * 2.0 * std::f64::consts::PI * moment),
            ] {
                for lumping in [Lumping::Consistent, Lumping::Lumped] {
                    let m = mass(kind, &coords, |_| RHO, geometry, lumping);
                    let x_total: f64 = (0..coords.len())
                        .flat_map(|a| (0..coords.len()).map(move |b| (a, b)))
                        .map(|(a, b)| m[(2 * a, 2 * b)])
                        .sum();
                    assert!((x_total - expected).abs() < 1e-12 * expected, "{kind:?} {geometry:?} {lumping:?}");
                    if lumping == Lumping::Lumped {
                        assert!((0..2 * coords.len()).all(|i| m[(i, i)] > 0.0), "{kind:?}: {m}");
                    }
                }
            }
        }
    }

    /// The consistent mass of a rectangle's four-node element is ρA/36·[4 2 1 2; …] (Cook et al.,
    /// Concepts and Applications of FEA, 4th ed., §11.3): corners 4ρA/36, neighbours 2, opposite 1.
    #[test]
    fn quad4_consistent_mass_is_the_textbook_matrix() {
        let coords = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        let m = mass(SolidKind::Quad4, &coords, |_| RHO, Geometry::PlaneStrain, Lumping::Consistent);
        let unit = RHO * 2.0 / 36.0;
        let pattern = [[4.0, 2.0, 1.0, 2.0], [2.0, 4.0, 2.0, 1.0], [1.0, 2.0, 4.0, 2.0], [2.0, 1.0, 2.0, 4.0]];
        for a in 0..4 {
            for b in 0..4 {
                assert!((m[(2 * a, 2 * b)] - pattern[a][b] * unit).abs() < 1e-13, "{a} {b}");
                assert_eq!(m[(2 * a, 2 * b + 1)], 0.0);
            }
        }
    }

    /// The six-node triangle's HRZ masses: 3/57 of the element's mass at each corner and 16/57 at
    /// each mid-side node (Zienkiewicz & Taylor vol. 1 §16.2.4 give these fractions).
    #[test]
    fn tri6_lumped_masses_are_hrz_fractions() {
        let coords = element(SolidKind::Tri6);
        let (area, _) = area_and_moment(&coords[..3]);
        let m = mass(SolidKind::Tri6, &coords, |_| RHO, Geometry::PlaneStrain, Lumping::Lumped);
        for a in 0..6 {
            let fraction = if a < 3 { 3.0 / 57.0 } else { 16.0 / 57.0 };
            assert!((m[(2 * a, 2 * a)] - fraction * RHO * area).abs() < 1e-12, "node {a}");
        }
    }
}
