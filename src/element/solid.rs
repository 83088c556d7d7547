//! Isoparametric soil elements, plane strain or axisymmetric: tri3, tri6, quad4, quad8 (Gmsh node
//! order).
//!
//! Stiffness K_e = ∫ Bᵀ D B dA per metre width (plane strain) or ∫ Bᵀ D B 2πr dA with the hoop
//! strain εθ = u_r/r as a fourth row of B (axisymmetric; Zienkiewicz & Taylor vol. 1 §6.2),
//! integrated with a Gauss rule that is exact for undistorted plane elements (1 point for tri3, 3
//! for tri6, 2×2 for quad4, 3×3 for quad8). Axisymmetric Gauss points lie inside the element, so
//! 1/r is finite even for an element that touches the axis.

use super::geometry::Geometry;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The soil element types (the model file's `kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum SolidKind {
    Tri3,
    Tri6,
    Quad4,
    Quad8,
}

/// Plane-strain linear elasticity: σ = D ε with ε = (εxx, εyy, γxy).
#[derive(Debug, Clone, Copy)]
pub struct PlaneStrain {
    pub youngs_modulus: f64,
    pub poissons_ratio: f64,
}

impl PlaneStrain {
    pub fn d_matrix(&self) -> Matrix3<f64> {
        let (e, nu) = (self.youngs_modulus, self.poissons_ratio);
        let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        Matrix3::new(f * (1.0 - nu), f * nu, 0.0, f * nu, f * (1.0 - nu), 0.0, 0.0, 0.0, f * (1.0 - 2.0 * nu) / 2.0)
    }

    /// The elasticity of (εxx, εyy, γxy, εzz) with εzz free: the hoop strain εθ of an axisymmetric
    /// body (x = r, y = z, zz = θθ).
    pub fn d_matrix_with_hoop(&self) -> Matrix4<f64> {
        let (e, nu) = (self.youngs_modulus, self.poissons_ratio);
        let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let (a, b, g) = (f * (1.0 - nu), f * nu, f * (1.0 - 2.0 * nu) / 2.0);
        Matrix4::new(a, b, 0.0, b, b, a, 0.0, b, 0.0, 0.0, g, 0.0, b, b, 0.0, a)
    }

    /// Out-of-plane stress σzz = ν(σxx + σyy).
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> f64 {
        self.poissons_ratio * (sxx + syy)
    }
}

/// A Jacobian determinant that is zero or negative: the element is degenerate or its nodes run
/// clockwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BadJacobian {
    pub det: f64,
}

/// Shape functions and their natural derivatives at (ξ, η).
pub fn shape(kind: SolidKind, xi: f64, eta: f64) -> (Vec<f64>, Vec<[f64; 2]>) {
    let (mut n, mut d) = (Vec::with_capacity(8), Vec::with_capacity(8));
    shape_into(kind, xi, eta, &mut n, &mut d);
    (n, d)
}

/// [`shape`] into `n` and `d` (cleared first), which keep their room for the next point.
fn shape_into(kind: SolidKind, xi: f64, eta: f64, n: &mut Vec<f64>, d: &mut Vec<[f64; 2]>) {
    n.clear();
    d.clear();
    match kind {
        SolidKind::Tri3 => {
            n.extend([1.0 - xi - eta, xi, eta]);
            d.extend([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
        }
        SolidKind::Tri6 => {
            let (l1, l2, l3) = (1.0 - xi - eta, xi, eta);
            n.extend([
                l1 * (2.0 * l1 - 1.0),
                l2 * (2.0 * l2 - 1.0),
                l3 * (2.0 * l3 - 1.0),
                4.0 * l1 * l2,
                4.0 * l2 * l3,
                4.0 * l3 * l1,
            ]);
            // dL1 = (-1,-1), dL2 = (1,0), dL3 = (0,1)
            d.extend([
                [-(4.0 * l1 - 1.0), -(4.0 * l1 - 1.0)],
                [4.0 * l2 - 1.0, 0.0],
                [0.0, 4.0 * l3 - 1.0],
                [4.0 * (l1 - l2), -4.0 * l2],
                [4.0 * l3, 4.0 * l2],
                [-4.0 * l3, 4.0 * (l1 - l3)],
            ]);
        }
        SolidKind::Quad4 => {
            const C: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
            for [a, b] in C {
                n.push(0.25 * (1.0 + a * xi) * (1.0 + b * eta));
                d.push([0.25 * a * (1.0 + b * eta), 0.25 * b * (1.0 + a * xi)]);
            }
        }
        SolidKind::Quad8 => {
            const C: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
            const M: [[f64; 2]; 4] = [[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]];
            for [a, b] in C {
                let (p, q) = (1.0 + a * xi, 1.0 + b * eta);
                let s = a * xi + b * eta - 1.0;
                n.push(0.25 * p * q * s);
                d.push([0.25 * a * q * (s + p), 0.25 * b * p * (s + q)]);
            }
            for [a, b] in M {
                if a == 0.0 {
                    n.push(0.5 * (1.0 - xi * xi) * (1.0 + b * eta));
                    d.push([-xi * (1.0 + b * eta), 0.5 * b * (1.0 - xi * xi)]);
                } else {
                    n.push(0.5 * (1.0 + a * xi) * (1.0 - eta * eta));
                    d.push([0.5 * a * (1.0 - eta * eta), -eta * (1.0 + a * xi)]);
                }
            }
        }
    }
}

/// The Gauss rule of an element: full (exact for undistorted elements) or, for quad8, reduced to
/// 2×2 points (Zienkiewicz & Taylor vol. 1 §10.4: the usual rule for nearly incompressible plastic
/// flow; its single spurious mode does not propagate through a mesh).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Integration {
    #[default]
    Full,
    Reduced,
}

/// Gauss points `(ξ, η, weight)` in the element's natural domain.
pub fn gauss_points(kind: SolidKind, rule: Integration) -> Vec<(f64, f64, f64)> {
    let kind = if kind == SolidKind::Quad8 && rule == Integration::Reduced { SolidKind::Quad4 } else { kind };
    match kind {
        SolidKind::Tri3 => vec![(1.0 / 3.0, 1.0 / 3.0, 0.5)],
        SolidKind::Tri6 => {
            let (a, b, w) = (1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0);
            vec![(a, a, w), (b, a, w), (a, b, w)]
        }
        SolidKind::Quad4 => {
            let g = 1.0 / 3f64.sqrt();
            let mut p = Vec::new();
            for eta in [-g, g] {
                for xi in [-g, g] {
                    p.push((xi, eta, 1.0));
                }
            }
            p
        }
        SolidKind::Quad8 => {
            let g = (0.6f64).sqrt();
            let pts = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
            let mut p = Vec::new();
            for (eta, we) in pts {
                for (xi, wx) in pts {
                    p.push((xi, eta, wx * we));
                }
            }
            p
        }
    }
}

/// One integration point mapped to the element: position, weight × det J (× 2πr in axisymmetry),
/// N and ∂N/∂x.
pub struct MappedPoint {
    pub x: [f64; 2],
    pub weight: f64,
    pub n: Vec<f64>,
    pub dn_dx: Vec<[f64; 2]>,
    /// 1/r in an axisymmetric element (the hoop strain is Σ N_i·u_ri/r); `None` in plane strain.
    pub inverse_radius: Option<f64>,
}

/// Map every Gauss point of the element with the given nodal coordinates.
///
/// # Errors
/// [`BadJacobian`] when det J ≤ 0 at any Gauss point (or at the corners, for quadrilaterals, where a
/// bow-tie first shows), or, in axisymmetry, when a Gauss point is not at r > 0 (an element on the
/// wrong side of the axis).
pub fn mapped_points(
    kind: SolidKind,
    coords: &[[f64; 2]],
    rule: Integration,
    geometry: Geometry,
) -> Result<Vec<MappedPoint>, BadJacobian> {
    map_points(kind, coords, rule, geometry, true)
}

/// [`mapped_points`] of an element whose corners were checked when the model was read (the
/// Gauss points' Jacobians are still checked): a step's results map every element again.
///
/// # Errors
/// As [`mapped_points`], but for the corners.
pub fn mapped_points_of_checked(
    kind: SolidKind,
    coords: &[[f64; 2]],
    rule: Integration,
    geometry: Geometry,
) -> Result<Vec<MappedPoint>, BadJacobian> {
    map_points(kind, coords, rule, geometry, false)
}

fn map_points(
    kind: SolidKind,
    coords: &[[f64; 2]],
    rule: Integration,
    geometry: Geometry,
    check_corners: bool,
) -> Result<Vec<MappedPoint>, BadJacobian> {
    let mut points = Vec::new();
    map_points_into(kind, coords, rule, geometry, check_corners, &mut points)?;
    Ok(points)
}

/// [`mapped_points_of_checked`] into `points`, whose shape-function buffers are reused: a step's
/// results map every element again, and without the reuse each element took a dozen allocations.
///
/// # Errors
/// As [`mapped_points_of_checked`]; `points` then holds no meaningful values.
pub fn mapped_points_of_checked_into(
    kind: SolidKind,
    coords: &[[f64; 2]],
    rule: Integration,
    geometry: Geometry,
    points: &mut Vec<MappedPoint>,
) -> Result<(), BadJacobian> {
    map_points_into(kind, coords, rule, geometry, false, points)
}

fn map_points_into(
    kind: SolidKind,
    coords: &[[f64; 2]],
    rule: Integration,
    geometry: Geometry,
    check_corners: bool,
    points: &mut Vec<MappedPoint>,
) -> Result<(), BadJacobian> {
    let size = coords.iter().fold(0.0f64, |m, c| m.max(c[0].abs()).max(c[1].abs())).max(1e-300);
    let corners: &[(f64, f64)] = match kind {
        SolidKind::Quad4 | SolidKind::Quad8 if check_corners => &[(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)],
        _ => &[],
    };
    // (buffers for the corners' shape functions, allocated only when there are corners to check)
    let (mut corner_n, mut corner_dn) = (Vec::new(), Vec::new());
    for &(xi, eta) in corners {
        shape_into(kind, xi, eta, &mut corner_n, &mut corner_dn);
        let j = jacobian(&corner_dn, coords);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if !(det > 1e-12 * size * size) {
            return Err(BadJacobian { det });
        }
    }
    let rule_points = gauss_points(kind, rule);
    points.truncate(rule_points.len());
    while points.len() < rule_points.len() {
        let (n, dn_dx) = (Vec::with_capacity(8), Vec::with_capacity(8));
        points.push(MappedPoint { x: [0.0; 2], weight: 0.0, n, dn_dx, inverse_radius: None });
    }
    for (p, (xi, eta, w)) in points.iter_mut().zip(rule_points) {
        shape_into(kind, xi, eta, &mut p.n, &mut p.dn_dx);
        let j = jacobian(&p.dn_dx, coords);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if !(det > 1e-12 * size * size) {
            return Err(BadJacobian { det });
        }
        // inverse of J = [[dx/dξ, dy/dξ], [dx/dη, dy/dη]]
        let inv = [[j[1][1] / det, -j[0][1] / det], [-j[1][0] / det, j[0][0] / det]];
        // ∂N/∂x in place of ∂N/∂ξ
        for d in p.dn_dx.iter_mut() {
            *d = [inv[0][0] * d[0] + inv[0][1] * d[1], inv[1][0] * d[0] + inv[1][1] * d[1]];
        }
        let mut x = [0.0; 2];
        for (ni, c) in p.n.iter().zip(coords) {
            x[0] += ni * c[0];
            x[1] += ni * c[1];
        }
        let (weight, inverse_radius) = match geometry {
            Geometry::PlaneStrain => (w * det, None),
            Geometry::Axisymmetric => {
                if !(x[0] > 1e-12 * size) {
                    return Err(BadJacobian { det: x[0] });
                }
                (w * det * geometry.circumference(x), Some(1.0 / x[0]))
            }
        };
        (p.x, p.weight, p.inverse_radius) = (x, weight, inverse_radius);
    }
    Ok(())
}

fn jacobian(dn: &[[f64; 2]], coords: &[[f64; 2]]) -> [[f64; 2]; 2] {
    let mut j = [[0.0; 2]; 2];
    for (d, c) in dn.iter().zip(coords) {
        j[0][0] += d[0] * c[0];
        j[0][1] += d[0] * c[1];
        j[1][0] += d[1] * c[0];
        j[1][1] += d[1] * c[1];
    }
    j
}

/// Strain-displacement matrix B (3 × 2n) at one point.
pub fn b_matrix(dn_dx: &[[f64; 2]]) -> DMatrix<f64> {
    let n = dn_dx.len();
    let mut b = DMatrix::zeros(3, 2 * n);
    for (i, d) in dn_dx.iter().enumerate() {
        b[(0, 2 * i)] = d[0];
        b[(1, 2 * i + 1)] = d[1];
        b[(2, 2 * i)] = d[1];
        b[(2, 2 * i + 1)] = d[0];
    }
    b
}

/// Strain-displacement matrix with the hoop row (4 × 2n: εxx, εyy, γxy, εθ) at an axisymmetric
/// point; plane strain's 3 rows at a plane one.
pub fn b_matrix_of(p: &MappedPoint) -> DMatrix<f64> {
    let Some(inverse_radius) = p.inverse_radius else { return b_matrix(&p.dn_dx) };
    let n = p.dn_dx.len();
    let mut b = DMatrix::zeros(4, 2 * n);
    for (i, d) in p.dn_dx.iter().enumerate() {
        b[(0, 2 * i)] = d[0];
        b[(1, 2 * i + 1)] = d[1];
        b[(2, 2 * i)] = d[1];
        b[(2, 2 * i + 1)] = d[0];
        b[(3, 2 * i)] = p.n[i] * inverse_radius;
    }
    b
}

/// The point's stiffness Bᵀ·D·B·w, with D the 4 × 4 tangent of (εxx, εyy, γxy, εzz): its upper
/// 3 × 3 block in plane strain (εzz = 0), all of it in axisymmetry (εzz = εθ).
pub fn point_stiffness(p: &MappedPoint, d: &Matrix4<f64>) -> DMatrix<f64> {
    let b = b_matrix_of(p);
    let rows = b.nrows();
    let d = DMatrix::from_fn(rows, rows, |i, j| d[(i, j)]);
    b.transpose() * (d * &b) * p.weight
}

/// Element stiffness matrix (2n × 2n, DOF order ux1, uy1, ux2, …).
///
/// # Errors
/// [`BadJacobian`] for a degenerate or clockwise element.
pub fn stiffness(
    kind: SolidKind,
    coords: &[[f64; 2]],
    material: &PlaneStrain,
    rule: Integration,
    geometry: Geometry,
) -> Result<DMatrix<f64>, BadJacobian> {
    let mut k = DMatrix::zeros(2 * coords.len(), 2 * coords.len());
    if geometry.is_axisymmetric() {
        let d = material.d_matrix_with_hoop();
        for p in mapped_points(kind, coords, rule, geometry)? {
            k += point_stiffness(&p, &d);
        }
        return Ok(k);
    }
    let d = material.d_matrix();
    let d = DMatrix::from_fn(3, 3, |i, j| d[(i, j)]);
    for p in mapped_points(kind, coords, rule, geometry)? {
        let b = b_matrix(&p.dn_dx);
        k += b.transpose() * &d * &b * p.weight;
    }
    Ok(k)
}

/// Consistent nodal forces of a uniform body force `b` [force/length³] per metre width.
///
/// # Errors
/// [`BadJacobian`] for a degenerate or clockwise element.
pub fn body_force(
    kind: SolidKind,
    coords: &[[f64; 2]],
    b: [f64; 2],
    rule: Integration,
    geometry: Geometry,
) -> Result<DVector<f64>, BadJacobian> {
    let mut f = DVector::zeros(2 * coords.len());
    for p in mapped_points(kind, coords, rule, geometry)? {
        for (i, ni) in p.n.iter().enumerate() {
            f[2 * i] += ni * b[0] * p.weight;
            f[2 * i + 1] += ni * b[1] * p.weight;
        }
    }
    Ok(f)
}

/// Stress at one Gauss point: position and (σxx, σyy, τxy, σzz). Tension positive.
#[derive(Debug, Clone, Copy)]
pub struct GaussStress {
    pub x: [f64; 2],
    /// σxx, σyy, τxy, σzz; tension positive.
    pub stress: [f64; 4],
    /// εxx, εyy, γxy (engineering shear strain); εzz = 0 in plane strain.
    pub strain: [f64; 3],
}

/// Stresses at the Gauss points for element displacements `u_e`.
///
/// # Errors
/// [`BadJacobian`] for a degenerate or clockwise element.
pub fn stresses(
    kind: SolidKind,
    coords: &[[f64; 2]],
    material: &PlaneStrain,
    u_e: &[f64],
    rule: Integration,
) -> Result<Vec<GaussStress>, BadJacobian> {
    let d = material.d_matrix();
    let u = DVector::from_column_slice(u_e);
    let mut out = Vec::new();
    for p in mapped_points(kind, coords, rule, Geometry::PlaneStrain)? {
        let eps = b_matrix(&p.dn_dx) * &u;
        let s = d * nalgebra::Vector3::new(eps[0], eps[1], eps[2]);
        out.push(GaussStress {
            x: p.x,
            stress: [s[0], s[1], s[2], material.sigma_zz(s[0], s[1])],
            strain: [eps[0], eps[1], eps[2]],
        });
    }
    Ok(out)
}

/// 1-D shape functions on an element side with nodes `[a, b]` or `[a, b, mid]`, at s ∈ [−1, 1].
pub fn side_shape(node_count: usize, s: f64) -> (Vec<f64>, Vec<f64>) {
    if node_count == 2 {
        (vec![0.5 * (1.0 - s), 0.5 * (1.0 + s)], vec![-0.5, 0.5])
    } else {
        (vec![0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s], vec![s - 0.5, s + 0.5, -2.0 * s])
    }
}

/// Consistent nodal forces of a uniform traction on one element side. `pressure` acts against the
/// outward normal; `shear` acts along a → b. `outward_sign` is +1 when the outward normal is the
/// right-hand normal of a → b (the element lies to the left), −1 otherwise. In axisymmetry the
/// side is a surface of revolution and the forces are its totals (∫ N·t·2πr ds).
pub fn side_traction(
    coords: &[[f64; 2]],
    pressure: f64,
    shear: f64,
    outward_sign: f64,
    geometry: Geometry,
) -> Vec<f64> {
    let g = (0.6f64).sqrt();
    let rule = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
    let mut f = vec![0.0; 2 * coords.len()];
    for (s, w) in rule {
        let (n, dn) = side_shape(coords.len(), s);
        let mut dx = [0.0; 2];
        for (d, c) in dn.iter().zip(coords) {
            dx[0] += d * c[0];
            dx[1] += d * c[1];
        }
        // dx = tangent × ds/dŝ; its right-hand normal (dy, −dx) has the same length.
        let t = [dx[0], dx[1]];
        let outward = [outward_sign * dx[1], -outward_sign * dx[0]];
        let traction = [-pressure * outward[0] + shear * t[0], -pressure * outward[1] + shear * t[1]];
        let w = match geometry {
            Geometry::PlaneStrain => w,
            Geometry::Axisymmetric => {
                let r: f64 = n.iter().zip(coords).map(|(ni, c)| ni * c[0]).sum();
                w * geometry.circumference([r, 0.0])
            }
        };
        for (i, ni) in n.iter().enumerate() {
            f[2 * i] += ni * traction[0] * w;
            f[2 * i + 1] += ni * traction[1] * w;
        }
    }
    f
}

#[cfg(test)]
mod tests {
    //! Rigid-body modes and the constant-strain patch test (Zienkiewicz & Taylor, The Finite Element
    //! Method, vol. 1, ch. 9) for every solid type.
    use super::*;

    const MATERIAL: PlaneStrain = PlaneStrain { youngs_modulus: 2.0e4, poissons_ratio: 0.3 };

    /// A distorted 2 × 2 patch (quadrilaterals) or its 8 triangles, with one interior node at (0.9, 1.1)
    /// in a 2 × 2 square.
    ///
    /// ```text
    ///  6 --- 7 --- 8
    ///  |     |     |
    ///  3 --- 4 --- 5      4 is the interior node, moved off-centre
    ///  |     |     |
    ///  0 --- 1 --- 2
    /// ```
    fn patch(kind: SolidKind) -> (Vec<[f64; 2]>, Vec<Vec<usize>>, Vec<usize>) {
        let mut x: Vec<[f64; 2]> = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64]).collect();
        x[4] = [0.9, 1.1];
        let quads = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        let mut cells: Vec<Vec<usize>> = match kind {
            SolidKind::Quad4 | SolidKind::Quad8 => quads.iter().map(|q| q.to_vec()).collect(),
            SolidKind::Tri3 | SolidKind::Tri6 => {
                quads.iter().flat_map(|q| [vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]]).collect()
            }
        };
        if kind.is_quadratic() {
            let mut mids = std::collections::HashMap::new();
            for cell in cells.iter_mut() {
                let corners = cell.clone();
                for k in 0..corners.len() {
                    let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
                    let m = *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                        x.push([0.5 * (x[a][0] + x[b][0]), 0.5 * (x[a][1] + x[b][1])]);
                        x.len() - 1
                    });
                    cell.push(m);
                }
            }
        }
        // Interior nodes: only node 4 and the mid-side nodes not on the square's boundary.
        let interior = (0..x.len())
            .filter(|&i| {
                let p = x[i];
                p[0] > 1e-9 && p[0] < 2.0 - 1e-9 && p[1] > 1e-9 && p[1] < 2.0 - 1e-9
            })
            .collect();
        (x, cells, interior)
    }

    fn assemble(kind: SolidKind, x: &[[f64; 2]], cells: &[Vec<usize>]) -> DMatrix<f64> {
        let n = 2 * x.len();
        let mut k = DMatrix::zeros(n, n);
        for c in cells {
            let coords: Vec<_> = c.iter().map(|&i| x[i]).collect();
            let ke = stiffness(kind, &coords, &MATERIAL, Integration::Full, Geometry::PlaneStrain)
                .expect("patch elements are valid");
            for (a, &ia) in c.iter().enumerate() {
                for (b, &ib) in c.iter().enumerate() {
                    for p in 0..2 {
                        for q in 0..2 {
                            k[(2 * ia + p, 2 * ib + q)] += ke[(2 * a + p, 2 * b + q)];
                        }
                    }
                }
            }
        }
        k
    }

    fn linear_field(p: [f64; 2]) -> [f64; 2] {
        // εxx = 1e-3, εyy = −2e-3, γxy = 1.5e-3 plus a rigid part
        [0.1 + 1e-3 * p[0] + 0.5e-3 * p[1], -0.2 + 1.0e-3 * p[0] - 2e-3 * p[1]]
    }

    fn rigid_body_modes_give_no_force(kind: SolidKind) {
        let (x, cells, _) = patch(kind);
        let k = assemble(kind, &x, &cells);
        type Mode = fn([f64; 2]) -> [f64; 2];
        let modes: [Mode; 3] = [|_| [1.0, 0.0], |_| [0.0, 1.0], |p| [-p[1], p[0]]];
        for mode in modes {
            let u = DVector::from_iterator(2 * x.len(), x.iter().flat_map(|&p| mode(p)));
            let f = &k * u;
            assert!(f.amax() < 1e-9 * k.amax(), "{kind:?}: rigid mode gives force {}", f.amax());
        }
        // and exactly three zero-energy modes
        let eig = nalgebra::SymmetricEigen::new(k.clone());
        let zeros = eig.eigenvalues.iter().filter(|&&l| l.abs() < 1e-9 * k.amax()).count();
        assert_eq!(zeros, 3, "{kind:?}: expected 3 rigid-body modes");
    }

    fn constant_strain_patch(kind: SolidKind) {
        let (x, cells, interior) = patch(kind);
        let k = assemble(kind, &x, &cells);
        let n = 2 * x.len();
        let free: Vec<usize> = interior.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
        let fixed: Vec<usize> = (0..n).filter(|d| !free.contains(d)).collect();
        let mut u = DVector::zeros(n);
        for (i, p) in x.iter().enumerate() {
            let v = linear_field(*p);
            u[2 * i] = v[0];
            u[2 * i + 1] = v[1];
        }
        // Solve K_ff u_f = −K_fc u_c for the interior; it must reproduce the linear field.
        let kff = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
        let mut rhs = DVector::zeros(free.len());
        for (i, &fi) in free.iter().enumerate() {
            for &c in &fixed {
                rhs[i] -= k[(fi, c)] * u[c];
            }
        }
        let uf = kff.lu().solve(&rhs).expect("interior stiffness is regular");
        for (i, &fi) in free.iter().enumerate() {
            assert!((uf[i] - u[fi]).abs() < 1e-12, "{kind:?}: interior DOF {fi} off the linear field");
        }
        let d = MATERIAL.d_matrix();
        let exact = d * nalgebra::Vector3::new(1e-3, -2e-3, 1.5e-3);
        for c in &cells {
            let coords: Vec<_> = c.iter().map(|&i| x[i]).collect();
            let ue: Vec<f64> = c.iter().flat_map(|&i| [u[2 * i], u[2 * i + 1]]).collect();
            for gs in stresses(kind, &coords, &MATERIAL, &ue, Integration::Full).unwrap() {
                for k in 0..3 {
                    assert!((gs.stress[k] - exact[k]).abs() < 1e-9 * exact.amax(), "{kind:?}: stress {k}");
                }
            }
        }
    }

    #[test]
    fn tri3_rigid_body_modes() {
        rigid_body_modes_give_no_force(SolidKind::Tri3);
    }
    #[test]
    fn tri6_rigid_body_modes() {
        rigid_body_modes_give_no_force(SolidKind::Tri6);
    }
    #[test]
    fn quad4_rigid_body_modes() {
        rigid_body_modes_give_no_force(SolidKind::Quad4);
    }
    #[test]
    fn quad8_rigid_body_modes() {
        rigid_body_modes_give_no_force(SolidKind::Quad8);
    }
    #[test]
    fn tri3_constant_strain_patch() {
        constant_strain_patch(SolidKind::Tri3);
    }
    #[test]
    fn tri6_constant_strain_patch() {
        constant_strain_patch(SolidKind::Tri6);
    }
    #[test]
    fn quad4_constant_strain_patch() {
        constant_strain_patch(SolidKind::Quad4);
    }
    #[test]
    fn quad8_constant_strain_patch() {
        constant_strain_patch(SolidKind::Quad8);
    }

    #[test]
    fn clockwise_element_is_rejected() {
        let coords = [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
        assert!(stiffness(SolidKind::Tri3, &coords, &MATERIAL, Integration::Full, Geometry::PlaneStrain).is_err());
    }

    #[test]
    fn uniform_pressure_on_a_side_sums_to_pressure_times_length() {
        // side from (0,0) to (2,0), element above (to the left): outward normal is −y, so a
        // pressure of 3 pushes +y with total 6.
        let f = side_traction(&[[0.0, 0.0], [2.0, 0.0]], 3.0, 0.0, 1.0, Geometry::PlaneStrain);
        assert!((f[1] + f[3] - 6.0).abs() < 1e-12 && (f[0] + f[2]).abs() < 1e-12);
        let f = side_traction(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0]], 3.0, 0.0, 1.0, Geometry::PlaneStrain);
        assert!((f[1] - 1.0).abs() < 1e-12 && (f[3] - 1.0).abs() < 1e-12 && (f[5] - 4.0).abs() < 1e-12);
    }

    /// Mapping into a buffer another element left (of another kind, rule or geometry) gives the
    /// points a fresh mapping gives, to the last bit.
    #[test]
    fn points_mapped_into_a_reused_buffer_are_those_mapped_afresh() {
        let mut reused = Vec::new();
        let cases = [
            (SolidKind::Quad8, Integration::Full, Geometry::PlaneStrain),
            (SolidKind::Tri3, Integration::Full, Geometry::PlaneStrain),
            (SolidKind::Quad4, Integration::Full, Geometry::Axisymmetric),
            (SolidKind::Quad8, Integration::Reduced, Geometry::PlaneStrain),
            (SolidKind::Tri6, Integration::Full, Geometry::Axisymmetric),
            (SolidKind::Quad4, Integration::Full, Geometry::PlaneStrain),
        ];
        for (kind, rule, geometry) in cases {
            let (x, elements, _) = patch(kind);
            // (shifted off the axis, for the axisymmetric cases)
            let coords: Vec<[f64; 2]> = elements[1].iter().map(|&n| [x[n][0] + 0.5, x[n][1]]).collect();
            let fresh = mapped_points_of_checked(kind, &coords, rule, geometry).unwrap();
            mapped_points_of_checked_into(kind, &coords, rule, geometry, &mut reused).unwrap();
            assert_eq!(reused.len(), fresh.len(), "{kind:?} {rule:?}");
            for (a, b) in reused.iter().zip(&fresh) {
                assert_eq!(a.x.map(f64::to_bits), b.x.map(f64::to_bits));
                assert_eq!(a.weight.to_bits(), b.weight.to_bits());
                assert_eq!(a.n, b.n);
                assert_eq!(a.dn_dx, b.dn_dx);
                assert_eq!(a.inverse_radius, b.inverse_radius);
            }
        }
    }
}
