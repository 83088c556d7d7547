//! A dense LU factorisation kept across small changes of its matrix.
//!
//! The matrix is M = F + C: F dense and fixed (the soil's Schur complement, held by the caller and
//! passed in), C sparse and changing (the interface's springs and rows, [`SparseColumns`]). Only the
//! factors are held dense here: which columns changed is found on C alone, and products with M are
//! F·x + C·x, so no second or third m × m array sits beside the factors and the caller's F. The
//! factors leave out the unknowns that stand alone on their diagonal (a released multiplier, a
//! point of a slit still covered by the reinforcement: a tenth of the kept unknowns of a pull-out
//! box, whose LU is then 30 % cheaper).
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
use faer::{get_global_parallelism, Mat, MatMut, MatRef};

/// The largest share of the columns a low-rank update may change before a new factorisation.
pub const MAX_UPDATE_SHARE: f64 = 0.08;
/// The relative residual an iterative solve reaches (a direct solve's is 1e-15 to 1e-13 here).
pub const ITERATIVE_TOLERANCE: f64 = 1e-13;
/// The BiCGSTAB iterations one solve may take before the matrix is factorised instead.
pub const MAX_ITERATIONS: usize = 6;
/// BiCGSTAB iterations that cost about one factorisation: each iteration is two solves with M₀'s
/// factors and two products with the matrix (four memory-bound passes over an m × m array), a
/// factorisation 2m³/3 flops. Measured on the 10⁵-unknown pull-out (docs/performance.md, 2280 kept
/// unknowns, 2024 factorised): about 10 ms an iteration against 76 ms a factorisation with what
/// goes with it, found from the dense phase's times of two Newton runs at two budgets.
pub const ITERATIONS_PER_FACTORISATION: usize = 8;

/// The sparse part C of a matrix F + C, by columns: entries of one position summed, rows in
/// increasing order within a column.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseColumns {
    col_ptr: Vec<usize>,
    rows: Vec<usize>,
    values: Vec<f64>,
}

impl SparseColumns {
    /// C of order `m` from its entries (row, column, value) in any order, repeated positions
    /// added.
    pub fn from_entries(m: usize, entries: impl Iterator<Item = (usize, usize, f64)>) -> SparseColumns {
        let mut list: Vec<(usize, usize, f64)> = entries.collect();
        list.sort_unstable_by_key(|&(i, j, _)| (j, i));
        let mut col_ptr = vec![0; m + 1];
        let mut rows = Vec::with_capacity(list.len());
        let mut values = Vec::with_capacity(list.len());
        let mut last = None;
        for (i, j, v) in list {
            if last == Some((i, j)) {
                *values.last_mut().expect("the entry before") += v;
            } else {
                rows.push(i);
                values.push(v);
                col_ptr[j + 1] += 1;
                last = Some((i, j));
            }
        }
        for j in 0..m {
            col_ptr[j + 1] += col_ptr[j];
        }
        SparseColumns { col_ptr, rows, values }
    }

    fn order(&self) -> usize {
        self.col_ptr.len().saturating_sub(1)
    }

    /// Column j: its rows and values.
    fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.rows[range.clone()], &self.values[range])
    }

    /// Whether column j holds the same entries, bit for bit, in `other`.
    fn same_column(&self, other: &SparseColumns, j: usize) -> bool {
        let (a, b) = (self.column(j), other.column(j));
        a.0 == b.0 && a.1.iter().zip(b.1).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// Add C to the dense `m`.
    fn add_to(&self, mut m: MatMut<'_, f64>) {
        for j in 0..self.order() {
            let (rows, values) = self.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                m[(i, j)] += v;
            }
        }
    }

    /// C·x.
    pub fn times(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let mut out = Mat::zeros(self.order(), x.ncols());
        self.add_times(x, out.as_mut());
        out
    }

    /// out += C·x.
    fn add_times(&self, x: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
        for j in 0..self.order() {
            let (rows, values) = self.column(j);
            for c in 0..x.ncols() {
                let xj = x[(j, c)];
                if xj != 0.0 {
                    for (&i, &v) in rows.iter().zip(values) {
                        out[(i, c)] += v * xj;
                    }
                }
            }
        }
    }
}

/// The matrix F + C as an operator: F·x + C·x.
#[derive(Debug, Clone, Copy)]
pub struct KeptMatrix<'a> {
    pub fixed: MatRef<'a, f64>,
    pub change: &'a SparseColumns,
}

impl KeptMatrix<'_> {
    /// (F + C)·x.
    pub fn times(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let mut out = self.fixed * x;
        self.change.add_times(x, out.as_mut());
        out
    }

    /// F + C on the unknowns `among` (increasing), as a dense matrix into `out` (of their number).
    fn write_into(&self, mut out: MatMut<'_, f64>, among: &[usize]) {
        if among.len() == self.fixed.nrows() {
            out.copy_from(self.fixed);
            self.change.add_to(out);
            return;
        }
        // by blocks, so that both F (by rows or by columns) and `out` are read and written in
        // runs that stay in the cache
        const BLOCK: usize = 64;
        let k = among.len();
        for q0 in (0..k).step_by(BLOCK) {
            for p0 in (0..k).step_by(BLOCK) {
                for q in q0..(q0 + BLOCK).min(k) {
                    for p in p0..(p0 + BLOCK).min(k) {
                        out[(p, q)] = self.fixed[(among[p], among[q])];
                    }
                }
            }
        }
        let mut position = vec![usize::MAX; self.fixed.nrows()];
        for (p, &i) in among.iter().enumerate() {
            position[i] = p;
        }
        for &j in among {
            let (rows, values) = self.change.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                if position[i] != usize::MAX {
                    out[(position[i], position[j])] += v;
                }
            }
        }
    }
}

impl faer::matrix_free::LinOp<f64> for KeptMatrix<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: faer::Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.fixed.nrows()
    }
    fn ncols(&self) -> usize {
        self.fixed.ncols()
    }
    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: faer::Par, _: &mut MemStack) {
        out.copy_from(self.times(rhs));
    }
    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: faer::Par, stack: &mut MemStack) {
        // real: the conjugate is the operator itself
        self.apply(out, rhs, par, stack)
    }
}

/// The update of the base factorisation by the changed columns J.
struct LowRank {
    columns: Vec<usize>,
    /// W = M₀⁻¹ D, m × |J|.
    w: Mat<f64>,
    /// LU of I + W_J.
    capacitance: PartialPivLu<f64>,
}

/// An LU factorisation with partial pivoting held packed in one array (L below the diagonal, its
/// unit diagonal implied, U on and above it), as LAPACK's getrf leaves it: faer's `PartialPivLu`
/// keeps L and U apart, two arrays and a third while it splits them.
///
/// Only the coupled unknowns are factorised: an unknown whose row and column of F are zero and
/// whose row and column of C hold nothing off the diagonal (a multiplier on its unit diagonal: a
/// released row, a point of a slit still covered by the reinforcement) is solved on its own,
/// x_j = b_j / c_jj, and its row and column are left out of the dense factors.
#[derive(Debug)]
struct PackedLu {
    /// The factors of the coupled unknowns' matrix.
    factors: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
    /// The coupled unknowns (in increasing order), the order of the factors.
    coupled: Vec<usize>,
    /// The decoupled unknowns and their diagonals.
    decoupled: Vec<(usize, f64)>,
}

impl PackedLu {
    /// The factors of `matrix`; `in_fixed[j]`: whether F has anything in row or column j.
    fn of(matrix: KeptMatrix, in_fixed: &[bool]) -> PackedLu {
        let mut lu = PackedLu {
            factors: Mat::zeros(0, 0),
            forward: Vec::new(),
            inverse: Vec::new(),
            coupled: Vec::new(),
            decoupled: Vec::new(),
        };
        lu.refactorize(matrix, in_fixed);
        lu
    }

    /// The factors of `matrix` (of the same order) in place of the last ones: the coupled part of
    /// the matrix is written into the factors' array (a new one, the old let go first, when the
    /// number of coupled unknowns changed) and factorised there.
    fn refactorize(&mut self, matrix: KeptMatrix, in_fixed: &[bool]) {
        let m = matrix.fixed.nrows();
        let mut coupled_by_change = vec![false; m];
        for j in 0..m {
            let (rows, values) = matrix.change.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                if i != j && v != 0.0 {
                    coupled_by_change[i] = true;
                    coupled_by_change[j] = true;
                }
            }
        }
        let diagonal = |j: usize| {
            let (rows, values) = matrix.change.column(j);
            rows.iter().zip(values).filter(|(&i, _)| i == j).map(|(_, &v)| v).sum::<f64>()
        };
        self.coupled.clear();
        self.decoupled.clear();
        for j in 0..m {
            let d = diagonal(j);
            // (a zero diagonal stays with the factors, whose pivoting meets it)
            if in_fixed[j] || coupled_by_change[j] || d == 0.0 {
                self.coupled.push(j);
            } else {
                self.decoupled.push((j, d));
            }
        }
        let order = self.coupled.len();
        if self.factors.nrows() != order {
            self.factors = Mat::zeros(0, 0);
            self.factors = Mat::zeros(order, order);
            self.forward = vec![0; order];
            self.inverse = vec![0; order];
        }
        matrix.write_into(self.factors.as_mut(), &self.coupled);
        if order == 0 {
            return;
        }
        let par = get_global_parallelism();
        let mut scratch =
            MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(order, order, par, Default::default()));
        factor::lu_in_place(
            self.factors.as_mut(),
            &mut self.forward,
            &mut self.inverse,
            par,
            MemStack::new(&mut scratch),
            Default::default(),
        );
    }

    /// The order of the dense factors (the coupled unknowns).
    #[cfg(test)]
    fn factored_order(&self) -> usize {
        self.coupled.len()
    }

    /// M⁻¹ b.
    fn solve(&self, b: &Mat<f64>) -> Mat<f64> {
        let order = self.coupled.len();
        let mut x = b.clone();
        for &(j, d) in &self.decoupled {
            for c in 0..x.ncols() {
                x[(j, c)] /= d;
            }
        }
        if order == 0 {
            return x;
        }
        let mut y = Mat::from_fn(order, b.ncols(), |k, c| b[(self.coupled[k], c)]);
        let par = get_global_parallelism();
        let mut scratch = MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(order, y.ncols(), par));
        let permutation = PermRef::new_checked(&self.forward, &self.inverse, order);
        // the packed array serves as both triangles: the unit-lower solve reads below the
        // diagonal only, the upper solve on and above it
        solve::solve_in_place(
            self.factors.as_ref(),
            self.factors.as_ref(),
            permutation,
            y.as_mut(),
            par,
            MemStack::new(&mut scratch),
        );
        for (k, &j) in self.coupled.iter().enumerate() {
            for c in 0..x.ncols() {
                x[(j, c)] = y[(k, c)];
            }
        }
        x
    }
}

impl faer::matrix_free::LinOp<f64> for PackedLu {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: faer::Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.coupled.len() + self.decoupled.len()
    }
    fn ncols(&self) -> usize {
        self.coupled.len() + self.decoupled.len()
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
    /// Whether F has anything in row or column j (F is the same over this object's life).
    in_fixed: Vec<bool>,
    /// C₀: M₀ = F + C₀ is the matrix factorised.
    base: SparseColumns,
    lu: PackedLu,
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
    /// Factorisations, low-rank updates and BiCGSTAB iterations over this object's life.
    pub factorizations: usize,
    pub updates: usize,
    pub iterations: usize,
}

impl UpdatedLu {
    /// Factorise F + `change`.
    pub fn new(fixed: MatRef<'_, f64>, change: SparseColumns) -> UpdatedLu {
        let in_fixed = in_fixed(fixed);
        let lu = PackedLu::of(KeptMatrix { fixed, change: &change }, &in_fixed);
        UpdatedLu {
            in_fixed,
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
        }
    }

    /// The sparse part of the matrix now represented.
    pub fn change(&self) -> &SparseColumns {
        match (&self.drifted, &self.update) {
            (Some(c), _) | (None, Some((c, _))) => c,
            (None, None) => &self.base,
        }
    }

    /// Represent F + `change` instead: by a low-rank update of the base factorisation where few
    /// columns differ from it, iteratively with the base factorisation as preconditioner otherwise
    /// (until that costs about a factorisation).
    pub fn set(&mut self, fixed: MatRef<'_, f64>, change: SparseColumns) {
        let m = fixed.nrows();
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
                self.refactorize(fixed, change);
            } else {
                self.drifted = Some(change);
            }
            return;
        }
        self.update = if columns.is_empty() {
            None
        } else {
            self.updates += 1;
            // D = C − C₀ on the changed columns (F is the same in both)
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

    /// Factorise F + `change` as the new M₀, in the old factors' array.
    fn refactorize(&mut self, fixed: MatRef<'_, f64>, change: SparseColumns) {
        self.update = None;
        self.drifted = None;
        self.lu.refactorize(KeptMatrix { fixed, change: &change }, &self.in_fixed);
        self.base = change;
        self.iterations_since = 0;
        self.factorizations += 1;
    }

    /// M⁻¹ b for the matrix now represented (F the same as in [`UpdatedLu::set`]).
    pub fn solve(&mut self, fixed: MatRef<'_, f64>, b: &Mat<f64>) -> Mat<f64> {
        self.solves_of_this += 1;
        if self.iterations_since >= ITERATIONS_PER_FACTORISATION {
            if let Some(change) = self.drifted.take() {
                self.refactorize(fixed, change);
            }
        }
        if let Some(change) = &self.drifted {
            let (x, iterations) = iterate(&self.lu, KeptMatrix { fixed, change }, b);
            self.iterations += iterations;
            self.iterations_since += iterations;
            match x {
                Some(x) => {
                    self.iterations_per_solve = 0.5 * (self.iterations_per_solve + iterations as f64);
                    return x;
                }
                None => {
                    let change = self.drifted.take().expect("checked above");
                    self.refactorize(fixed, change);
                }
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

/// Whether F has anything in row or column j, for each j.
fn in_fixed(fixed: MatRef<'_, f64>) -> Vec<bool> {
    let m = fixed.nrows();
    let mut any = vec![false; m];
    // (in the order F is stored)
    let by_rows = fixed.col_stride().unsigned_abs() <= fixed.row_stride().unsigned_abs();
    for a in 0..m {
        for b in 0..m {
            let (i, j) = if by_rows { (a, b) } else { (b, a) };
            if fixed[(i, j)] != 0.0 {
                any[i] = true;
                any[j] = true;
            }
        }
    }
    any
}

/// BiCGSTAB on `matrix` preconditioned by `lu` (M₀'s factors): the solution, checked against its
/// true residual ‖b − M·x‖, and the iterations; no solution when it does not reach the tolerance
/// within [`MAX_ITERATIONS`].
fn iterate(lu: &PackedLu, matrix: KeptMatrix, b: &Mat<f64>) -> (Option<Mat<f64>>, usize) {
    use faer::matrix_free::bicgstab::{bicgstab, bicgstab_scratch, BicgParams};
    use faer::matrix_free::{IdentityPrecond, InitialGuessStatus};
    let m = matrix.fixed.nrows();
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

    /// The fixed part F.
    fn fixed(m: usize) -> Mat<f64> {
        Mat::from_fn(m, m, |i, j| if i == j { 4.0 } else { 1.0 / (1.0 + (i as f64 - j as f64).abs()) })
    }

    /// A change with the given entries, and F + C as a dense matrix to check against.
    fn change(m: usize, entries: &[(usize, usize, f64)]) -> (SparseColumns, Mat<f64>) {
        let c = SparseColumns::from_entries(m, entries.iter().copied());
        let mut whole = fixed(m);
        for &(i, j, v) in entries {
            whole[(i, j)] += v;
        }
        (c, whole)
    }

    fn residual(whole: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
        (b - whole * x).norm_l2() / b.norm_l2()
    }

    #[test]
    fn repeated_entries_are_summed_and_columns_compared_bit_for_bit() {
        let c = SparseColumns::from_entries(3, [(2, 1, 1.0), (0, 1, 2.0), (2, 1, 0.5)].into_iter());
        assert_eq!(c.column(1), (&[0usize, 2][..], &[2.0, 1.5][..]));
        assert_eq!(c.column(0).0.len() + c.column(2).0.len(), 0);
        let d = SparseColumns::from_entries(3, [(0, 1, 2.0), (2, 1, 1.5 + 1e-16)].into_iter());
        assert!(c.same_column(&d, 0) && c.same_column(&d, 2));
        assert_eq!(c.same_column(&d, 1), (1.5f64 + 1e-16).to_bits() == 1.5f64.to_bits());
        let e = SparseColumns::from_entries(3, [(0, 1, 2.0), (1, 1, 1.5)].into_iter());
        assert!(!c.same_column(&e, 1), "the same values in other rows");
    }

    #[test]
    fn a_few_changed_columns_are_an_update_and_solve_exactly() {
        let m = 60;
        let f = fixed(m);
        let (c0, _) = change(m, &[(5, 5, 1.0), (7, 2, 0.25)]);
        let mut lu = UpdatedLu::new(f.as_ref(), c0);
        let mut entries = vec![(5, 5, 1.0), (7, 2, 0.25)];
        for &j in &[3usize, 17, 40] {
            for i in 0..m {
                entries.push((i, j, 0.3 * ((i + j) as f64).sin()));
            }
        }
        let (c, whole) = change(m, &entries);
        lu.set(f.as_ref(), c);
        assert_eq!((lu.factorizations, lu.updates), (1, 1), "three of sixty columns: an update");
        let b = Mat::from_fn(m, 1, |i, _| (i as f64 * 0.7).cos());
        let x = lu.solve(f.as_ref(), &b);
        assert!(residual(&whole, &x, &b) < 1e-12, "residual {}", residual(&whole, &x, &b));
    }

    #[test]
    fn unknowns_on_their_own_diagonal_are_left_out_of_the_factors() {
        // F zero in the rows and columns of the last 10 unknowns (multipliers), C their unit
        // diagonals and, for two of them (50 and 55), a row and column coupling them to the rest
        let (m, free) = (60, 50);
        let mut f = fixed(m);
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
        let lu = UpdatedLu::new(f.as_ref(), c);
        assert_eq!(lu.lu.factored_order(), free + 2, "the eight multipliers on their own diagonal left out");
        let b = Mat::from_fn(m, 2, |i, c| (i as f64 * 0.3 + c as f64).cos());
        let mut this = lu;
        let x = this.solve(f.as_ref(), &b);
        assert!(residual(&whole, &x, &b) < 1e-13, "residual {}", residual(&whole, &x, &b));
        // the released row closes again (its entries nonzero): an update of the factors, whose
        // base solves the left-out unknowns on their diagonal
        for e in entries.iter_mut().filter(|e| e.0 == 57 || e.1 == 57) {
            if e.0 != e.1 {
                e.2 = 0.7;
            }
        }
        let c = SparseColumns::from_entries(m, entries.iter().copied());
        let mut whole = f.clone();
        for &(i, j, v) in &entries {
            whole[(i, j)] += v;
        }
        this.set(f.as_ref(), c);
        assert_eq!((this.factorizations, this.updates), (1, 1), "two changed columns: an update");
        let x = this.solve(f.as_ref(), &b);
        assert!(residual(&whole, &x, &b) < 1e-12, "after the update: residual {}", residual(&whole, &x, &b));
    }

    #[test]
    fn a_matrix_that_moved_a_little_everywhere_is_solved_iteratively_to_the_tolerance() {
        let m = 80;
        let f = fixed(m);
        let mut lu = UpdatedLu::new(f.as_ref(), SparseColumns::from_entries(m, std::iter::empty()));
        // every entry 0.1 % off: every column changed
        let entries: Vec<(usize, usize, f64)> = (0..m)
            .flat_map(|j| (0..m).map(move |i| (i, j)))
            .map(|(i, j)| (i, j, f[(i, j)] * 1e-3 * ((i * 7 + j * 3) as f64).sin()))
            .collect();
        let (c, whole) = change(m, &entries);
        lu.set(f.as_ref(), c);
        let b = Mat::from_fn(m, 1, |i, _| 1.0 + i as f64);
        let x = lu.solve(f.as_ref(), &b);
        assert!(residual(&whole, &x, &b) <= 10.0 * ITERATIVE_TOLERANCE, "residual {}", residual(&whole, &x, &b));
        assert_eq!(lu.factorizations, 1, "no new factorisation");
        assert!(lu.iterations >= 1 && lu.iterations <= MAX_ITERATIONS, "{} iterations", lu.iterations);
    }

    #[test]
    fn a_matrix_far_from_the_factorised_one_is_factorised_afresh() {
        let m = 40;
        let f = fixed(m);
        let far = |shift: f64| change(m, &(0..m).map(|i| (i, i, shift * (1 + i % 3) as f64)).collect::<Vec<_>>());
        let mut lu = UpdatedLu::new(f.as_ref(), SparseColumns::from_entries(m, std::iter::empty()));
        let b = Mat::from_fn(m, 1, |i, _| i as f64);
        let (c, whole) = far(1.0);
        lu.set(f.as_ref(), c);
        let x = lu.solve(f.as_ref(), &b);
        assert!(residual(&whole, &x, &b) < 1e-12);
        // BiCGSTAB may or may not have reached the tolerance; either way the answer is exact enough,
        // and iterations that cost a factorisation bring one on the next change
        let before = lu.factorizations;
        for k in 0..ITERATIONS_PER_FACTORISATION {
            let (c, whole) = far(1.0 + 0.5 * (k + 1) as f64);
            lu.set(f.as_ref(), c);
            let x = lu.solve(f.as_ref(), &b);
            let r = residual(&whole, &x, &b);
            assert!(r <= 10.0 * ITERATIVE_TOLERANCE, "change {k}: residual {r}");
        }
        assert!(lu.factorizations > before, "a new factorisation once the iterations cost one");
    }
}
