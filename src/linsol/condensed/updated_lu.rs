//! A dense LU factorisation kept across small changes of its matrix.
//!
//! The matrix is M = S + C ([`super::kept_matrix`]): S dense and fixed (the soil's Schur
//! complement, held by the caller and passed in), C sparse and changing (the interface's springs
//! and rows). Only the factors are held here ([`BlockLu`]: the bars' unknowns and one face's rows
//! eliminated sparsely, a dense LU of the rest): which columns changed is found on C alone, and
//! products with M are S·x + C·x.
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

use super::block_lu::BlockLu;
use super::kept_matrix::{KeptMatrix, SoilSchur, SparseColumns};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{get_global_parallelism, Mat};
use std::time::Instant;

/// The largest share of the columns a low-rank update may change before a new factorisation.
pub const MAX_UPDATE_SHARE: f64 = 0.08;
/// The relative residual an iterative solve reaches (a direct solve's is 1e-15 to 1e-13 here).
pub const ITERATIVE_TOLERANCE: f64 = 1e-13;
/// The BiCGSTAB iterations one solve may take before the matrix is factorised instead.
pub const MAX_ITERATIONS: usize = 6;
/// BiCGSTAB iterations that cost about one factorisation: each iteration is two solves with M₀'s
/// factors and two products with the matrix, a factorisation 2m³/3 flops. Measured on the
/// 10⁵-unknown pull-out (docs/performance.md, 2280 kept unknowns, 2024 factorised densely): about
/// 10 ms an iteration against 76 ms a factorisation, found from the dense phase's times of two
/// Newton runs at two budgets. Since then both shrank by about the same factor (the dense LU is of
/// 1265 unknowns and S's product of its 1016-unknown block): not measured again.
pub const ITERATIONS_PER_FACTORISATION: usize = 8;

/// The update of the base factorisation by the changed columns J.
struct LowRank {
    columns: Vec<usize>,
    /// W = M₀⁻¹ D, m × |J|.
    w: Mat<f64>,
    /// LU of I + W_J.
    capacitance: PartialPivLu<f64>,
}

pub struct UpdatedLu {
    /// C₀: M₀ = S + C₀ is the matrix factorised.
    base: SparseColumns,
    lu: BlockLu,
    /// The C now represented and its update, when it is not C₀.
    update: Option<(SparseColumns, LowRank)>,
    /// The C now represented when it differs from C₀ in many columns: solved iteratively.
    drifted: Option<SparseColumns>,
    /// BiCGSTAB iterations since the last factorisation.
    iterations_since: usize,
    /// Solves of the matrix now represented, and the mean over the matrices before it.
    solves_of_this: usize,
    solves_per_matrix: f64,
    /// Mean BiCGSTAB iterations of a solve that converged.
    iterations_per_solve: f64,
    /// Factorisations, low-rank updates and BiCGSTAB iterations over this object's life, and the
    /// time in the factorisations and in the iterations.
    pub factorizations: usize,
    pub updates: usize,
    pub iterations: usize,
    pub factorization_seconds: f64,
    pub iteration_seconds: f64,
}

impl UpdatedLu {
    /// Factorise S + `change`.
    pub fn new(schur: &SoilSchur, change: SparseColumns) -> UpdatedLu {
        let t = Instant::now();
        let lu = BlockLu::of(KeptMatrix { schur, change: &change });
        let factorization_seconds = t.elapsed().as_secs_f64();
        UpdatedLu {
            base: change,
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
            factorization_seconds,
            iteration_seconds: 0.0,
        }
    }

    /// The sparse part of the matrix now represented.
    pub fn change(&self) -> &SparseColumns {
        match (&self.drifted, &self.update) {
            (Some(c), _) | (None, Some((c, _))) => c,
            (None, None) => &self.base,
        }
    }

    /// Represent S + `change` instead: by a low-rank update of the base factorisation where few
    /// columns differ from it, iteratively with the base factorisation as preconditioner otherwise
    /// (until that costs about a factorisation).
    pub fn set(&mut self, schur: &SoilSchur, change: SparseColumns) {
        let m = schur.order();
        let columns: Vec<usize> = (0..m).filter(|&j| !change.same_column(&self.base, j)).collect();
        self.drifted = None;
        // the mean solves a matrix gets (the last matrices weigh most)
        self.solves_per_matrix = 0.5 * (self.solves_per_matrix + self.solves_of_this as f64);
        self.solves_of_this = 0;
        if columns.len() as f64 > MAX_UPDATE_SHARE * m as f64 {
            self.update = None;
            let predicted = self.solves_per_matrix * self.iterations_per_solve;
            let budget = ITERATIONS_PER_FACTORISATION as f64;
            if self.iterations_since as f64 >= budget || predicted >= budget {
                self.refactorize(schur, change);
            } else {
                self.drifted = Some(change);
            }
            return;
        }
        self.update = if columns.is_empty() {
            None
        } else {
            self.updates += 1;
            // D = C − C₀ on the changed columns (S is the same in both)
            let mut d = Mat::zeros(m, columns.len());
            for (k, &j) in columns.iter().enumerate() {
                let (rows, values) = change.column(j);
                for (&i, &v) in rows.iter().zip(values) {
                    d[(i, k)] += v;
                }
                let (rows, values) = self.base.column(j);
                for (&i, &v) in rows.iter().zip(values) {
                    d[(i, k)] -= v;
                }
            }
            let w = self.lu.solve(&d);
            let r = columns.len();
            let cap = Mat::from_fn(r, r, |a, b| w[(columns[a], b)] + if a == b { 1.0 } else { 0.0 });
            Some((change, LowRank { capacitance: cap.partial_piv_lu(), columns, w }))
        };
    }

    /// Factorise S + `change` as the new M₀, in the old factors' array.
    fn refactorize(&mut self, schur: &SoilSchur, change: SparseColumns) {
        self.update = None;
        self.drifted = None;
        let t = Instant::now();
        self.lu.refactorize(KeptMatrix { schur, change: &change });
        self.factorization_seconds += t.elapsed().as_secs_f64();
        self.base = change;
        self.iterations_since = 0;
        self.factorizations += 1;
    }

    /// M⁻¹ b for the matrix now represented (S the same as in [`UpdatedLu::set`]).
    pub fn solve(&mut self, schur: &SoilSchur, b: &Mat<f64>) -> Mat<f64> {
        self.solves_of_this += 1;
        if self.iterations_since >= ITERATIONS_PER_FACTORISATION {
            if let Some(change) = self.drifted.take() {
                self.refactorize(schur, change);
            }
        }
        if let Some(change) = self.drifted.take() {
            let t = Instant::now();
            let (x, iterations) = iterate(&self.lu, KeptMatrix { schur, change: &change }, b);
            self.iteration_seconds += t.elapsed().as_secs_f64();
            self.iterations += iterations;
            self.iterations_since += iterations;
            match x {
                Some(x) => {
                    self.iterations_per_solve = 0.5 * (self.iterations_per_solve + iterations as f64);
                    self.drifted = Some(change);
                    return x;
                }
                None => self.refactorize(schur, change),
            }
        }
        self.solve_exactly(b)
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

/// BiCGSTAB on `matrix` preconditioned by `lu` (M₀'s factors): the solution, checked against its
/// true residual ‖b − M·x‖, and the iterations; no solution when it does not reach the tolerance
/// within [`MAX_ITERATIONS`].
fn iterate(lu: &BlockLu, matrix: KeptMatrix, b: &Mat<f64>) -> (Option<Mat<f64>>, usize) {
    use faer::matrix_free::bicgstab::{bicgstab, bicgstab_scratch, BicgParams};
    use faer::matrix_free::{IdentityPrecond, InitialGuessStatus};
    let m = matrix.order();
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
    let mut scratch = MemBuffer::new(bicgstab_scratch(identity, lu, matrix, b.ncols(), par));
    let info = bicgstab(x.as_mut(), identity, lu, matrix, b.as_ref(), params, |_| {}, par, MemStack::new(&mut scratch));
    let iterations = match info {
        Ok(info) => info.iter_count,
        Err(_) => MAX_ITERATIONS,
    };
    // the recursive residual can drift from the true one: checked
    let residual = (b - matrix.times(x.as_ref())).norm_l2();
    let converged = info.is_ok() && residual <= 10.0 * ITERATIVE_TOLERANCE * b.norm_l2();
    (converged.then_some(x), iterations)
}

#[cfg(test)]
mod tests {
    //! The updated factorisation solves the changed matrix as a new factorisation does.
    use super::*;

    /// The soil's Schur complement S.
    fn soil_schur(m: usize) -> Mat<f64> {
        Mat::from_fn(m, m, |i, j| if i == j { 4.0 } else { 1.0 / (1.0 + (i as f64 - j as f64).abs()) })
    }

    /// A change with the given entries, and S + C as a dense matrix to check against.
    fn change(m: usize, entries: &[(usize, usize, f64)]) -> (SparseColumns, Mat<f64>) {
        let c = SparseColumns::from_entries(m, entries.iter().copied());
        let mut whole = soil_schur(m);
        for &(i, j, v) in entries {
            whole[(i, j)] += v;
        }
        (c, whole)
    }

    fn residual(whole: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
        (b - whole * x).norm_l2() / b.norm_l2()
    }

    #[test]
    fn a_few_changed_columns_are_an_update_and_solve_exactly() {
        let m = 60;
        let f = soil_schur(m);
        let (c0, _) = change(m, &[(5, 5, 1.0), (7, 2, 0.25)]);
        let f = SoilSchur::from_dense(f.as_ref());
        let mut lu = UpdatedLu::new(&f, c0);
        let mut entries = vec![(5, 5, 1.0), (7, 2, 0.25)];
        for &j in &[3usize, 17, 40] {
            for i in 0..m {
                entries.push((i, j, 0.3 * ((i + j) as f64).sin()));
            }
        }
        let (c, whole) = change(m, &entries);
        lu.set(&f, c);
        assert_eq!((lu.factorizations, lu.updates), (1, 1), "three of sixty columns: an update");
        let b = Mat::from_fn(m, 1, |i, _| (i as f64 * 0.7).cos());
        let x = lu.solve(&f, &b);
        assert!(residual(&whole, &x, &b) < 1e-12, "residual {}", residual(&whole, &x, &b));
    }

    #[test]
    fn unknowns_on_their_own_diagonal_are_left_out_of_the_factors() {
        // S zero in the rows and columns of the last 10 unknowns (multipliers), C their unit
        // diagonals and, for two of them (50 and 55), a row and column coupling them to the rest
        let (m, free) = (60, 50);
        let mut f = soil_schur(m);
        for i in 0..m {
            for j in 0..m {
                if i >= free || j >= free {
                    f[(i, j)] = 0.0;
                }
            }
        }
        let mut entries: Vec<(usize, usize, f64)> = (free..m).map(|j| (j, j, 1.0 + j as f64 * 0.1)).collect();
        for (i, j, v) in [(50, 3, 1.0), (3, 50, 1.0), (55, 7, -0.5), (7, 55, -0.5)] {
            entries.push((i, j, v));
        }
        // a released row keeps its master entries as zeros: still on its own
        entries.push((57, 9, 0.0));
        entries.push((9, 57, 0.0));
        let c = SparseColumns::from_entries(m, entries.iter().copied());
        let mut whole = f.clone();
        for &(i, j, v) in &entries {
            whole[(i, j)] += v;
        }
        let whole_f = f;
        let f = SoilSchur::from_dense(whole_f.as_ref());
        let lu = UpdatedLu::new(&f, c);
        // the eight multipliers on their own diagonal are left out; the two coupled ones (their
        // diagonals nonzero) are eliminated before the dense factors, which are S's block alone
        assert_eq!(lu.lu.dense_order(), free);
        let b = Mat::from_fn(m, 2, |i, c| (i as f64 * 0.3 + c as f64).cos());
        let mut this = lu;
        let x = this.solve(&f, &b);
        assert!(residual(&whole, &x, &b) < 1e-13, "residual {}", residual(&whole, &x, &b));
        // the released row closes again (its entries nonzero): an update of the factors, whose
        // base solves the left-out unknowns on their diagonal
        for e in entries.iter_mut().filter(|e| e.0 == 57 || e.1 == 57) {
            if e.0 != e.1 {
                e.2 = 0.7;
            }
        }
        let c = SparseColumns::from_entries(m, entries.iter().copied());
        let mut whole = whole_f.clone();
        for &(i, j, v) in &entries {
            whole[(i, j)] += v;
        }
        this.set(&f, c);
        assert_eq!((this.factorizations, this.updates), (1, 1), "two changed columns: an update");
        let x = this.solve(&f, &b);
        assert!(residual(&whole, &x, &b) < 1e-12, "after the update: residual {}", residual(&whole, &x, &b));
    }

    #[test]
    fn a_matrix_that_moved_a_little_everywhere_is_solved_iteratively_to_the_tolerance() {
        let m = 80;
        let whole_f = soil_schur(m);
        let f = SoilSchur::from_dense(whole_f.as_ref());
        let mut lu = UpdatedLu::new(&f, SparseColumns::from_entries(m, std::iter::empty()));
        // every entry 0.1 % off: every column changed
        let entries: Vec<(usize, usize, f64)> = (0..m)
            .flat_map(|j| (0..m).map(move |i| (i, j)))
            .map(|(i, j)| (i, j, whole_f[(i, j)] * 1e-3 * ((i * 7 + j * 3) as f64).sin()))
            .collect();
        let (c, whole) = change(m, &entries);
        lu.set(&f, c);
        let b = Mat::from_fn(m, 1, |i, _| 1.0 + i as f64);
        let x = lu.solve(&f, &b);
        assert!(residual(&whole, &x, &b) <= 10.0 * ITERATIVE_TOLERANCE, "residual {}", residual(&whole, &x, &b));
        assert_eq!(lu.factorizations, 1, "no new factorisation");
        assert!(lu.iterations >= 1 && lu.iterations <= MAX_ITERATIONS, "{} iterations", lu.iterations);
    }

    #[test]
    fn a_matrix_far_from_the_factorised_one_is_factorised_afresh() {
        let m = 40;
        let f = soil_schur(m);
        let far = |shift: f64| change(m, &(0..m).map(|i| (i, i, shift * (1 + i % 3) as f64)).collect::<Vec<_>>());
        let f = SoilSchur::from_dense(f.as_ref());
        let mut lu = UpdatedLu::new(&f, SparseColumns::from_entries(m, std::iter::empty()));
        let b = Mat::from_fn(m, 1, |i, _| i as f64);
        let (c, whole) = far(1.0);
        lu.set(&f, c);
        let x = lu.solve(&f, &b);
        assert!(residual(&whole, &x, &b) < 1e-12);
        // BiCGSTAB may or may not have reached the tolerance; either way the answer is exact enough,
        // and iterations that cost a factorisation bring one on the next change
        let before = lu.factorizations;
        for k in 0..ITERATIONS_PER_FACTORISATION {
            let (c, whole) = far(1.0 + 0.5 * (k + 1) as f64);
            lu.set(&f, c);
            let x = lu.solve(&f, &b);
            let r = residual(&whole, &x, &b);
            assert!(r <= 10.0 * ITERATIVE_TOLERANCE, "change {k}: residual {r}");
        }
        assert!(lu.factorizations > before, "a new factorisation once the iterations cost one");
    }
}
