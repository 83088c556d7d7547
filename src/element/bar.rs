//! Two-node reinforcement bar: axial stiffness EA per metre width, no bending, no transverse
//! stiffness (a bar node's transverse DOF is held only by the interface constraints); its law
//! (linear elastic, optionally tension-only, optionally rupturing at T_ult) and the state of every
//! bar through a run (ruptured, not yet placed, the stretch it was placed with).

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

/// A reinforcement material as a bar sees it (per metre width).
#[derive(Debug, Clone, Copy)]
pub struct BarMaterial {
    pub axial_stiffness: f64,
    pub tension_only: bool,
    /// T_ult: the bar ruptures when its tension passes it.
    pub rupture_strength: Option<f64>,
}

/// A bar's axial law: linear elastic, optionally tension-only, optionally rupturing at T_ult.
#[derive(Debug, Clone)]
pub struct BarLaw {
    pub id: u64,
    pub block: usize,
    pub axis: [f64; 2],
    pub length: f64,
    pub axial_stiffness: f64,
    pub tension_only: bool,
    pub rupture_strength: Option<f64>,
}

/// The state of every bar (in mesh order): ruptured, not yet placed, and the stretch it had when it
/// was placed (its force counts from there).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct BarStates {
    pub ruptured: Vec<bool>,
    pub absent: Vec<bool>,
    pub placed_stretch: Vec<f64>,
}

impl BarStates {
    pub fn new(count: usize) -> BarStates {
        BarStates { ruptured: vec![false; count], absent: vec![false; count], placed_stretch: vec![0.0; count] }
    }

    /// A bar that carries nothing: ruptured or not placed.
    pub fn idle(&self, i: usize) -> bool {
        self.ruptured.get(i).copied().unwrap_or(false) || self.absent.get(i).copied().unwrap_or(false)
    }

    pub fn stretch0(&self, i: usize) -> f64 {
        self.placed_stretch.get(i).copied().unwrap_or(0.0)
    }
}

impl BarLaw {
    /// Stretch e·(u_b − u_a) along the bar's axis.
    pub fn stretch(&self, u: &[f64], dofs: &[usize]) -> f64 {
        self.axis[0] * (u[dofs[2]] - u[dofs[0]]) + self.axis[1] * (u[dofs[3]] - u[dofs[1]])
    }

    /// Elastic axial force T = EA/L·(e·(u_b − u_a) − stretch at placement) (tension positive).
    pub fn elastic_force(&self, u: &[f64], dofs: &[usize], stretch0: f64) -> f64 {
        self.axial_stiffness / self.length * (self.stretch(u, dofs) - stretch0)
    }

    /// The force the bar carries: zero once ruptured or before it is placed, and never compressive
    /// when tension-only.
    pub fn force(&self, u: &[f64], dofs: &[usize], bars: &BarStates, i: usize) -> f64 {
        let t = self.elastic_force(u, dofs, bars.stretch0(i));
        if bars.idle(i) || (self.tension_only && t < 0.0) {
            0.0
        } else {
            t
        }
    }

    /// Whether the bar carries no stiffness in the current state.
    pub fn slack(&self, u: &[f64], dofs: &[usize], bars: &BarStates, i: usize) -> bool {
        bars.idle(i) || (self.tension_only && self.elastic_force(u, dofs, bars.stretch0(i)) < 0.0)
    }
}

impl BarStates {
    /// Bars whose tension passed their rupture strength break: they carry nothing from then on.
    /// `laws` are the bars' laws and `dofs(block)` each bar's DOFs. Returns a line per bar that
    /// ruptured.
    pub fn rupture<'a>(&mut self, laws: &[BarLaw], dofs: impl Fn(usize) -> &'a [usize], u: &[f64]) -> Vec<String> {
        let mut changes = Vec::new();
        for (i, bar) in laws.iter().enumerate() {
            let Some(t_ult) = bar.rupture_strength else { continue };
            if self.idle(i) {
                continue;
            }
            let t = bar.elastic_force(u, dofs(bar.block), self.stretch0(i));
            if t > t_ult {
                self.ruptured[i] = true;
                changes.push(format!("bar {} ruptured: T = {t:.4} > T_ult = {t_ult}", bar.id));
            }
        }
        changes
    }
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
