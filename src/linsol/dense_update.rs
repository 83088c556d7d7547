//! A dense LU factorisation kept across small changes of its matrix.
//!
//! The condensed interface system changes a few columns at a time (a spring starts to slide, a row
//! is released): refactorising it costs O(m³), while the change M = M₀ + D·E_Jᵀ, nonzero in the
//! columns J only, is taken by the Sherman–Morrison–Woodbury identity at O(m²·|J|):
//!
//! ```text
//! M⁻¹ b = y − W (I + W_J)⁻¹ y_J,   y = M₀⁻¹ b,   W = M₀⁻¹ D
//! ```
//!
//! (W_J: the rows J of W). Once the changed columns exceed [`MAX_UPDATE_SHARE`] of the matrix, the
//! matrix is factorised afresh and becomes the new M₀.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::perm::PermRef;
use faer::{get_global_parallelism, Mat};

/// The largest share of the columns a low-rank update may change before a new factorisation.
pub const MAX_UPDATE_SHARE: f64 = 0.08;

/// The update of the base factorisation by the changed columns J.
struct LowRank {
    columns: Vec<usize>,
    /// W = M₀⁻¹ D, m × |J|.
    w: Mat<f64>,
    /// LU of I + W_J.
    capacitance: PartialPivLu<f64>,
}

/// An LU factorisation with partial pivoting held packed in one m × m array (L below the
/// diagonal, its unit diagonal implied, U on and above it), as LAPACK's getrf leaves it: faer's
/// `PartialPivLu` keeps L and U apart, two arrays and a third while it splits them.
struct PackedLu {
    factors: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
}

impl PackedLu {
    /// The factors of `matrix`.
    fn of(matrix: &Mat<f64>) -> PackedLu {
        let m = matrix.nrows();
        let mut lu = PackedLu { factors: Mat::zeros(m, m), forward: vec![0; m], inverse: vec![0; m] };
        lu.refactorize(matrix);
        lu
    }

    /// The factors of `matrix` (of the same size) in place of the last ones.
    fn refactorize(&mut self, matrix: &Mat<f64>) {
        let m = matrix.nrows();
        self.factors.copy_from(matrix);
        let par = get_global_parallelism();
        let mut scratch = MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(m, m, par, Default::default()));
        factor::lu_in_place(
            self.factors.as_mut(),
            &mut self.forward,
            &mut self.inverse,
            par,
            MemStack::new(&mut scratch),
            Default::default(),
        );
    }

    /// M⁻¹ b.
    fn solve(&self, b: &Mat<f64>) -> Mat<f64> {
        let m = self.factors.nrows();
        let mut x = b.clone();
        let par = get_global_parallelism();
        let mut scratch = MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(m, x.ncols(), par));
        let permutation = PermRef::new_checked(&self.forward, &self.inverse, m);
        // the packed array serves as both triangles: the unit-lower solve reads below the
        // diagonal only, the upper solve on and above it
        solve::solve_in_place(
            self.factors.as_ref(),
            self.factors.as_ref(),
            permutation,
            x.as_mut(),
            par,
            MemStack::new(&mut scratch),
        );
        x
    }
}

pub struct UpdatedLu {
    /// M₀, the matrix factorised.
    base: Mat<f64>,
    lu: PackedLu,
    /// The matrix now represented and its update, when it is not M₀.
    update: Option<(Mat<f64>, LowRank)>,
}

impl UpdatedLu {
    /// Factorise `matrix`.
    pub fn new(matrix: Mat<f64>) -> UpdatedLu {
        let lu = PackedLu::of(&matrix);
        UpdatedLu { base: matrix, lu, update: None }
    }

    /// The matrix now represented.
    pub fn matrix(&self) -> &Mat<f64> {
        self.update.as_ref().map_or(&self.base, |(m, _)| m)
    }

    /// Represent `matrix` instead: by a low-rank update of the base factorisation where few columns
    /// differ from it, by a new factorisation otherwise. Returns `true` when it factorised.
    pub fn set(&mut self, matrix: Mat<f64>) -> bool {
        let m = matrix.nrows();
        let columns: Vec<usize> =
            (0..m).filter(|&j| (0..m).any(|i| matrix[(i, j)].to_bits() != self.base[(i, j)].to_bits())).collect();
        if columns.len() as f64 > MAX_UPDATE_SHARE * m as f64 {
            // the old matrix and update go first, and the new factors take the old ones' array
            self.update = None;
            self.base = matrix;
            self.lu.refactorize(&self.base);
            return true;
        }
        self.update = if columns.is_empty() {
            None
        } else {
            let d = Mat::from_fn(m, columns.len(), |i, k| matrix[(i, columns[k])] - self.base[(i, columns[k])]);
            let w = self.lu.solve(&d);
            let r = columns.len();
            let cap = Mat::from_fn(r, r, |a, b| w[(columns[a], b)] + if a == b { 1.0 } else { 0.0 });
            Some((matrix, LowRank { capacitance: cap.partial_piv_lu(), columns, w }))
        };
        false
    }

    /// M⁻¹ b for the matrix now represented.
    pub fn solve(&self, b: &Mat<f64>) -> Mat<f64> {
        let y = self.lu.solve(b);
        let Some((_, u)) = &self.update else { return y };
        let y_j = Mat::from_fn(u.columns.len(), b.ncols(), |a, c| y[(u.columns[a], c)]);
        let z = u.capacitance.solve(&y_j);
        &y - &u.w * &z
    }
}

#[cfg(test)]
mod tests {
    //! The updated factorisation solves the changed matrix as a new factorisation does.
    use super::*;

    fn matrix(m: usize, shift: f64) -> Mat<f64> {
        Mat::from_fn(m, m, |i, j| {
            if i == j {
                4.0 + shift * (i % 3) as f64
            } else {
                1.0 / (1.0 + (i as f64 - j as f64).abs())
            }
        })
    }

    #[test]
    fn a_few_changed_columns_are_an_update_and_solve_exactly() {
        let m = 60;
        let mut lu = UpdatedLu::new(matrix(m, 0.0));
        let mut changed = matrix(m, 0.0);
        for &j in &[3usize, 17, 40] {
            for i in 0..m {
                changed[(i, j)] += 0.3 * ((i + j) as f64).sin();
            }
        }
        assert!(!lu.set(changed.clone()), "three of sixty columns: an update");
        let b = Mat::from_fn(m, 1, |i, _| (i as f64 * 0.7).cos());
        let x = lu.solve(&b);
        let r = &b - &changed * &x;
        assert!(r.norm_l2() < 1e-12 * b.norm_l2(), "residual {}", r.norm_l2());
    }

    #[test]
    fn many_changed_columns_are_a_new_factorisation() {
        let m = 40;
        let mut lu = UpdatedLu::new(matrix(m, 0.0));
        assert!(lu.set(matrix(m, 1.0)), "every third diagonal changed: a factorisation");
        let b = Mat::from_fn(m, 1, |i, _| i as f64);
        let x = lu.solve(&b);
        let r = &b - &matrix(m, 1.0) * &x;
        assert!(r.norm_l2() < 1e-12 * b.norm_l2());
    }
}
