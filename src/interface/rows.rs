//! The rows an interface contributes for the current association: one constraint row per
//! multiplier (normal rows, and the tangential rows of `tie` points), one tangential spring per
//! point of a sliding law, their gaps, and the force Cᵀλ the multipliers put on the nodes.

use super::{Interface, MultiplierRef, NormalState, Row};
use crate::mesh::Mesh;

/// A row as (global DOF, coefficient) pairs.
pub fn row_dofs(row: &Row) -> Vec<(usize, f64)> {
    row.iter().flat_map(|&(n, c)| [(2 * n, c[0]), (2 * n + 1, c[1])]).collect()
}

/// A tangential spring: one slave point of one face of an interface with a shear stiffness.
#[derive(Debug, Clone)]
pub struct Spring {
    /// Slip s = row · u.
    pub row: Vec<(usize, f64)>,
    /// The point's tributary length times the faces it stands for (2 embedded): its stiffness is
    /// Ks times this, its force τ times this.
    pub tributary: f64,
    pub interface: usize,
    pub face: usize,
    pub point: usize,
    /// The multiplier of the point's normal row.
    pub normal_multiplier: usize,
    /// The slave node and its reference position (for the pore pressure there).
    pub slave: usize,
    pub position: [f64; 2],
}

/// The rows of the multipliers and the springs, for the current association.
pub struct InterfaceRows {
    /// One per multiplier, in `DofMap::multipliers` order.
    pub constraint_rows: Vec<Vec<(usize, f64)>>,
    /// Reference gap of each multiplier's row (zero for tangential rows).
    pub gap0: Vec<f64>,
    /// The full normal row of a held point (its constraint row acts on the slave alone, but its gap
    /// is still measured to the master face).
    held_rows: Vec<Option<Vec<(usize, f64)>>>,
    pub springs: Vec<Spring>,
}

impl InterfaceRows {
    pub fn new(mesh: &Mesh, interfaces: &[Interface], multipliers: &[MultiplierRef]) -> Self {
        let mut constraint_rows = Vec::with_capacity(multipliers.len());
        let mut gap0 = Vec::with_capacity(multipliers.len());
        let mut held_rows = Vec::with_capacity(multipliers.len());
        let mut normal_multiplier = std::collections::HashMap::new();
        for (k, m) in multipliers.iter().enumerate() {
            let face = &interfaces[m.interface].faces[m.face];
            let point = &face.points[m.point];
            let mut row = if m.tangential {
                gap0.push(0.0);
                face.tangential_row(point)
            } else {
                normal_multiplier.insert((m.interface, m.face, m.point), k);
                gap0.push(point.gap0);
                face.normal_row(mesh, point)
            };
            if !m.tangential && matches!(point.normal_state, NormalState::Held { .. }) {
                held_rows.push(Some(row_dofs(&row)));
                // holds the slave node alone: the master entries stay in the pattern as zeros
                for entry in row.iter_mut().skip(1) {
                    entry.1 = [0.0, 0.0];
                }
            } else {
                held_rows.push(None);
            }
            constraint_rows.push(row_dofs(&row));
        }
        let mut springs = Vec::new();
        for (i, interface) in interfaces.iter().enumerate() {
            if !interface.is_tie() {
                for (f, face) in interface.faces.iter().enumerate() {
                    for (p, point) in face.points.iter().enumerate() {
                        springs.push(Spring {
                            row: row_dofs(&face.tangential_row(point)),
                            tributary: point.tributary * face.sides(),
                            interface: i,
                            face: f,
                            point: p,
                            normal_multiplier: normal_multiplier[&(i, f, p)],
                            slave: point.slave,
                            position: mesh.position(point.slave),
                        });
                    }
                }
            }
        }
        InterfaceRows { constraint_rows, gap0, held_rows, springs }
    }

    /// Hold each spring's normal row open by its face's dilation (one value per spring, in
    /// `springs` order): the row's gap is then measured from −opening.
    pub fn dilate(&mut self, openings: impl Iterator<Item = f64>) {
        for (spring, opening) in self.springs.iter().zip(openings) {
            if opening != 0.0 {
                self.gap0[spring.normal_multiplier] += opening;
            }
        }
    }

    /// Current gap of every row: g = gap0 + row · u.
    pub fn gaps(&self, u: &[f64]) -> Vec<f64> {
        self.constraint_rows
            .iter()
            .zip(&self.held_rows)
            .zip(&self.gap0)
            .map(|((row, held), g0)| g0 + held.as_ref().unwrap_or(row).iter().map(|&(d, c)| c * u[d]).sum::<f64>())
            .collect()
    }
}

/// Whether multiplier `m` currently holds its row (true) or sits on a unit diagonal (false).
pub fn multiplier_is_active(interfaces: &[Interface], m: MultiplierRef) -> bool {
    let p = &interfaces[m.interface].faces[m.face].points[m.point];
    if m.tangential {
        // a tie's tangential row holds while its normal row does
        matches!(p.tangential_state, NormalState::Active) && matches!(p.normal_state, NormalState::Active)
    } else {
        matches!(p.normal_state, NormalState::Active | NormalState::Held { .. })
    }
}

/// Cᵀλ over all displacement DOFs.
pub fn constraint_force(rows: &InterfaceRows, lambda: &[f64], dof_count: usize) -> Vec<f64> {
    let mut f = vec![0.0; dof_count];
    for (row, l) in rows.constraint_rows.iter().zip(lambda) {
        for &(d, c) in row {
            f[d] += c * l;
        }
    }
    f
}
