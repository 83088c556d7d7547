//! Two-node reinforcement bar: axial stiffness EA per metre width, no bending, no transverse
//! stiffness (a bar node's transverse DOF is held only by the interface constraints).

use nalgebra::Matrix4;

/// Unit axis and reference length of a bar from `a` to `b`.
pub fn axis(a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let length = (d[0] * d[0] + d[1] * d[1]).sqrt();
    ([d[0] / length, d[1] / length], length)
}

/// Bar stiffness (4 × 4, DOF order ux_a, uy_a, ux_b, uy_b).
pub fn stiffness(a: [f64; 2], b: [f64; 2], axial_stiffness: f64) -> Matrix4<f64> {
    let (e, length) = axis(a, b);
    let k = axial_stiffness / length;
    let m = [e[0] * e[0], e[0] * e[1], e[1] * e[1]];
    let block = [[m[0], m[1]], [m[1], m[2]]];
    Matrix4::from_fn(|i, j| {
        let sign = if (i < 2) == (j < 2) { 1.0 } else { -1.0 };
        sign * k * block[i % 2][j % 2]
    })
}

/// Axial force T (tension positive) for nodal displacements `[ux_a, uy_a, ux_b, uy_b]`.
pub fn axial_force(a: [f64; 2], b: [f64; 2], axial_stiffness: f64, u: [f64; 4]) -> f64 {
    let (e, length) = axis(a, b);
    axial_stiffness / length * (e[0] * (u[2] - u[0]) + e[1] * (u[3] - u[1]))
}

#[cfg(test)]
mod tests {
    //! Rigid-body modes and the constant-strain test of a two-node bar (any structural analysis text,
    //! e.g. Cook et al., Concepts and Applications of FEA, §2.4).
    use super::*;
    use nalgebra::Vector4;

    const A: [f64; 2] = [1.0, 2.0];
    const B: [f64; 2] = [4.0, 6.0]; // length 5, axis (0.6, 0.8)

    #[test]
    fn bar_rigid_body_modes_give_no_force() {
        let k = stiffness(A, B, 1000.0);
        let rotation = Vector4::new(-A[1], A[0], -B[1], B[0]);
        for u in [Vector4::new(1.0, 0.0, 1.0, 0.0), Vector4::new(0.0, 1.0, 0.0, 1.0), rotation] {
            assert!((k * u).amax() < 1e-12 * k.amax());
        }
        // a small rotation about A gives no axial force either
        assert!(axial_force(A, B, 1000.0, [0.0, 0.0, -0.8e-6 * 5.0, 0.6e-6 * 5.0]).abs() < 1e-12);
    }

    #[test]
    fn bar_constant_strain() {
        // uniform strain ε along the axis: T = EA ε, and K u gives ±T along the axis
        let eps = 2e-3;
        let u = [0.0, 0.0, eps * 3.0, eps * 4.0];
        let t = axial_force(A, B, 1000.0, u);
        assert!((t - 2.0).abs() < 1e-12);
        let f = stiffness(A, B, 1000.0) * Vector4::from(u);
        assert!((f[2] - 2.0 * 0.6).abs() < 1e-12 && (f[3] - 2.0 * 0.8).abs() < 1e-12);
        assert!((f[0] + f[2]).abs() < 1e-12 && (f[1] + f[3]).abs() < 1e-12);
    }
}
