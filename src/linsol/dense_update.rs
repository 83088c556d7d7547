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
//! (W_J: the rows J of W). Once the changed columns exceed [`MAX_UPDATE_SHARE`] of the matrix (under
//! large slip every point's rows move a little in every iteration), M₀'s factors precondition
//! BiCGSTAB (faer's) on the matrix itself, each solve to a relative residual of [`ITERATIVE_TOLERANCE`];
//! the matrix is factorised afresh, and becomes the new M₀, once the iterations since the last
//! factorisation cost about what a factorisation costs ([`ITERATIONS_PER_FACTORISATION`]), when the
//! solves a matrix has had so far predict that iterating on it would (the constant-stiffness
//! scheme solves one matrix many times: it factorises; Newton's solves each matrix once or twice:
//! it iterates), or when a solve does not converge within [`MAX_ITERATIONS`].

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::perm::PermRef;
use faer::{get_global_parallelism, Mat};

/// The largest share of the columns a low-rank update may change before a new factorisation.
pub const MAX_UPDATE_SHARE: f64 = 0.08;
/// The relative residual an iterative solve reaches (a direct solve's is 1e-15 to 1e-13 here).
pub const ITERATIVE_TOLERANCE: f64 = 1e-13;
/// The BiCGSTAB iterations one solve may take before the matrix is factorised instead.
pub const MAX_ITERATIONS: usize = 6;
/// BiCGSTAB iterations that cost about one factorisation: each iteration is two solves with M₀'s
/// factors and two products with the matrix (four memory-bound passes over an m × m array), a
/// factorisation 2m³/3 flops (0.3–0.4 s at m = 2280 on the project's 2-core machine); chosen on the
/// 10⁵-unknown pull-out benchmark (docs/performance.md).
pub const ITERATIONS_PER_FACTORISATION: usize = 10;

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
#[derive(Debug)]
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

impl faer::matrix_free::LinOp<f64> for PackedLu {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: faer::Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.factors.nrows()
    }
    fn ncols(&self) -> usize {
        self.factors.ncols()
    }
    fn apply(&self, mut out: faer::MatMut<'_, f64>, rhs: faer::MatRef<'_, f64>, _: faer::Par, _: &mut MemStack) {
        out.copy_from(self.solve(&rhs.to_owned()));
    }
    fn conj_apply(&self, out: faer::MatMut<'_, f64>, rhs: faer::MatRef<'_, f64>, par: faer::Par, stack: &mut MemStack) {
        // real: the conjugate is the operator itself
        self.apply(out, rhs, par, stack)
    }
}

impl faer::matrix_free::Precond<f64> for PackedLu {}

pub struct UpdatedLu {
    /// M₀, the matrix factorised.
    base: Mat<f64>,
    lu: PackedLu,
    /// The matrix now represented and its update, when it is not M₀.
    update: Option<(Mat<f64>, LowRank)>,
    /// The matrix now represented when it differs from M₀ in many columns: solved iteratively.
    drifted: Option<Mat<f64>>,
    /// BiCGSTAB iterations since the last factorisation.
    iterations_since: usize,
    /// Solves of the matrix now represented, and the mean over the matrices before it.
    solves_of_this: usize,
    solves_per_matrix: f64,
    /// Mean BiCGSTAB iterations of a solve that converged.
    iterations_per_solve: f64,
    /// Factorisations, low-rank updates and BiCGSTAB iterations over this object's life.
    pub factorizations: usize,
    pub updates: usize,
    pub iterations: usize,
}

impl UpdatedLu {
    /// Factorise `matrix`.
    pub fn new(matrix: Mat<f64>) -> UpdatedLu {
        let lu = PackedLu::of(&matrix);
        UpdatedLu {
            base: matrix,
            lu,
            update: None,
            drifted: None,
            iterations_since: 0,
            solves_of_this: 0,
            solves_per_matrix: 1.0,
            iterations_per_solve: 2.0,
            factorizations: 1,
            updates: 0,
            iterations: 0,
        }
    }

    /// The matrix now represented.
    pub fn matrix(&self) -> &Mat<f64> {
        match (&self.drifted, &self.update) {
            (Some(m), _) | (None, Some((m, _))) => m,
            (None, None) => &self.base,
        }
    }

    /// Represent `matrix` instead: by a low-rank update of the base factorisation where few columns
    /// differ from it, iteratively with the base factorisation as preconditioner otherwise (until
    /// that costs about a factorisation).
    pub fn set(&mut self, matrix: Mat<f64>) {
        let m = matrix.nrows();
        let columns: Vec<usize> =
            (0..m).filter(|&j| (0..m).any(|i| matrix[(i, j)].to_bits() != self.base[(i, j)].to_bits())).collect();
        self.drifted = None;
        // the mean solves a matrix gets (the last matrices weigh most)
        self.solves_per_matrix = 0.5 * (self.solves_per_matrix + self.solves_of_this as f64);
        self.solves_of_this = 0;
        if columns.len() as f64 > MAX_UPDATE_SHARE * m as f64 {
            self.update = None;
            let predicted = self.solves_per_matrix * self.iterations_per_solve;
            let budget = ITERATIONS_PER_FACTORISATION as f64;
            if self.iterations_since as f64 >= budget || predicted >= budget {
                self.refactorize(matrix);
            } else {
                self.drifted = Some(matrix);
            }
            return;
        }
        self.update = if columns.is_empty() {
            None
        } else {
            self.updates += 1;
            let d = Mat::from_fn(m, columns.len(), |i, k| matrix[(i, columns[k])] - self.base[(i, columns[k])]);
            let w = self.lu.solve(&d);
            let r = columns.len();
            let cap = Mat::from_fn(r, r, |a, b| w[(columns[a], b)] + if a == b { 1.0 } else { 0.0 });
            Some((matrix, LowRank { capacitance: cap.partial_piv_lu(), columns, w }))
        };
    }

    /// Factorise `matrix` as the new M₀: the old matrix and update go first, and the new factors
    /// take the old ones' array.
    fn refactorize(&mut self, matrix: Mat<f64>) {
        self.update = None;
        self.drifted = None;
        self.base = matrix;
        self.lu.refactorize(&self.base);
        self.iterations_since = 0;
        self.factorizations += 1;
    }

    /// M⁻¹ b for the matrix now represented, and ‖b − M·x‖ when the solve computed it (an
    /// iterative solve checks it; a direct one does not).
    pub fn solve(&mut self, b: &Mat<f64>) -> (Mat<f64>, Option<f64>) {
        self.solves_of_this += 1;
        if self.iterations_since >= ITERATIONS_PER_FACTORISATION {
            if let Some(matrix) = self.drifted.take() {
                self.refactorize(matrix);
            }
        }
        if let Some(matrix) = &self.drifted {
            let (x, iterations) = iterate(&self.lu, matrix, b);
            self.iterations += iterations;
            self.iterations_since += iterations;
            match x {
                Some((x, residual)) => {
                    self.iterations_per_solve = 0.5 * (self.iterations_per_solve + iterations as f64);
                    return (x, Some(residual));
                }
                None => {
                    let matrix = self.drifted.take().expect("checked above");
                    self.refactorize(matrix);
                }
            }
        }
        (self.solve_exactly(b), None)
    }

    /// M⁻¹ b with the factors: exactly for M₀ and its low-rank update.
    fn solve_exactly(&self, b: &Mat<f64>) -> Mat<f64> {
        let y = self.lu.solve(b);
        let Some((_, u)) = &self.update else { return y };
        let y_j = Mat::from_fn(u.columns.len(), b.ncols(), |a, c| y[(u.columns[a], c)]);
        let z = u.capacitance.solve(&y_j);
        &y - &u.w * &z
    }
}

/// BiCGSTAB on `matrix` preconditioned by `lu` (M₀'s factors): the solution with its true
/// residual norm ‖b − M·x‖, and the iterations; no solution when it does not reach the tolerance
/// within [`MAX_ITERATIONS`].
fn iterate(lu: &PackedLu, matrix: &Mat<f64>, b: &Mat<f64>) -> (Option<(Mat<f64>, f64)>, usize) {
    use faer::matrix_free::bicgstab::{bicgstab, bicgstab_scratch, BicgParams};
    use faer::matrix_free::{IdentityPrecond, InitialGuessStatus};
    let m = matrix.nrows();
    let par = get_global_parallelism();
    let identity = IdentityPrecond { dim: m };
    // (faer 0.24's `InitialGuessStatus::Zero` path gives NaN: the zero guess is passed as a
    // guess instead)
    let params = BicgParams {
        initial_guess: InitialGuessStatus::MaybeNonZero,
        rel_tolerance: ITERATIVE_TOLERANCE,
        max_iters: MAX_ITERATIONS,
        ..Default::default()
    };
    let mut x = Mat::<f64>::zeros(m, b.ncols());
    let mut scratch = MemBuffer::new(bicgstab_scratch(identity, lu, matrix.as_ref(), b.ncols(), par));
    let info = bicgstab(
        x.as_mut(),
        identity,
        lu,
        matrix.as_ref(),
        b.as_ref(),
        params,
        |_| {},
        par,
        MemStack::new(&mut scratch),
    );
    let iterations = match info {
        Ok(info) => info.iter_count,
        Err(_) => MAX_ITERATIONS,
    };
    // the recursive residual can drift from the true one: checked
    let residual = (b - matrix * &x).norm_l2();
    let converged = info.is_ok() && residual <= 10.0 * ITERATIVE_TOLERANCE * b.norm_l2();
    (converged.then_some((x, residual)), iterations)
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
        lu.set(changed.clone());
        assert_eq!((lu.factorizations, lu.updates), (1, 1), "three of sixty columns: an update");
        let b = Mat::from_fn(m, 1, |i, _| (i as f64 * 0.7).cos());
        let (x, _) = lu.solve(&b);
        let r = &b - &changed * &x;
        assert!(r.norm_l2() < 1e-12 * b.norm_l2(), "residual {}", r.norm_l2());
    }

    #[test]
    fn a_matrix_that_moved_a_little_everywhere_is_solved_iteratively_to_the_tolerance() {
        let m = 80;
        let mut lu = UpdatedLu::new(matrix(m, 0.0));
        // every entry 0.1 % off: every column changed
        let moved = Mat::from_fn(m, m, |i, j| matrix(m, 0.0)[(i, j)] * (1.0 + 1e-3 * ((i * 7 + j * 3) as f64).sin()));
        lu.set(moved.clone());
        let b = Mat::from_fn(m, 1, |i, _| 1.0 + i as f64);
        let (x, _) = lu.solve(&b);
        let r = &b - &moved * &x;
        assert!(r.norm_l2() <= 10.0 * ITERATIVE_TOLERANCE * b.norm_l2(), "residual {}", r.norm_l2());
        assert_eq!(lu.factorizations, 1, "no new factorisation");
        assert!(lu.iterations >= 1 && lu.iterations <= MAX_ITERATIONS, "{} iterations", lu.iterations);
    }

    #[test]
    fn a_matrix_far_from_the_factorised_one_is_factorised_afresh() {
        let m = 40;
        let mut lu = UpdatedLu::new(matrix(m, 0.0));
        lu.set(matrix(m, 1.0));
        let b = Mat::from_fn(m, 1, |i, _| i as f64);
        let (x, _) = lu.solve(&b);
        let r = &b - &matrix(m, 1.0) * &x;
        assert!(r.norm_l2() < 1e-12 * b.norm_l2());
        // BiCGSTAB may or may not have reached the tolerance; either way the answer is exact enough,
        // and iterations that cost a factorisation bring one on the next change
        let before = lu.factorizations;
        for k in 0..ITERATIONS_PER_FACTORISATION {
            lu.set(matrix(m, 1.0 + 0.5 * (k + 1) as f64));
            let (x, _) = lu.solve(&b);
            let r = &b - &matrix(m, 1.0 + 0.5 * (k + 1) as f64) * &x;
            assert!(r.norm_l2() <= 10.0 * ITERATIVE_TOLERANCE * b.norm_l2(), "change {k}: residual {}", r.norm_l2());
        }
        assert!(lu.factorizations > before, "a new factorisation once the iterations cost one");
    }
}
