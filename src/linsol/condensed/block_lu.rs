//! The factorisation of the kept system M = S + C with its sparse unknowns eliminated first.
//!
//! S, the soil's Schur complement, is dense among the soil's interface unknowns only: a bar's
//! unknowns meet S in the few entries of its own stiffness, a multiplier in none. C couples each of
//! them to a few others. Ordered so, the coupled unknowns split into R, whose rows and columns of M
//! are sparse, and D, the rest:
//!
//! ```text
//! M = [A_RR  A_RD]     T = A_DD − A_DR A_RR⁻¹ A_RD   (dense, of D only)
//!     [A_DR  A_DD]
//! ```
//!
//! A_RR is factorised by a sparse LU (faer's, partial pivoting) and only T by a dense one. A bar
//! node's transverse unknown pairs with the row of one face on it (a 2 × 2 pivot the sparse LU
//! finds); the other face's row on the same node has the same coefficients on the bar and would
//! make A_RR singular, so a multiplier whose column in R is parallel to one already in R joins D,
//! as does an unknown with nothing in R. On the pull-out box of 10⁵ unknowns the coupled 2024
//! leave a T of about 1270: a quarter of the dense LU's flops.
//!
//! The unknowns that stand alone on their diagonal (a released multiplier, a point of a slit
//! still covered by the reinforcement: x_j = b_j / c_jj) are left out of both.
//!
//! Every block factorisation is checked on one solve (its relative residual on M at most
//! [`BLOCK_CHECK`]); where it fails (A_RR singular or badly conditioned where M is not), the
//! coupled unknowns are factorised densely together instead, as they were before this split.

use super::kept_matrix::KeptMatrix;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::{SparseColMat, Triplet};
use faer::{get_global_parallelism, Mat, MatRef};
use std::collections::HashMap;

/// The relative residual ‖M·x − b‖/‖b‖ a block factorisation must meet on its test solve (a
/// direct dense solve's is 1e-15 to 1e-13 here).
pub const BLOCK_CHECK: f64 = 1e-11;

/// The factors of one kept matrix.
#[derive(Debug)]
pub struct BlockLu {
    /// The unknowns on their own diagonal, and the diagonal.
    decoupled: Vec<(usize, f64)>,
    /// R, increasing, and A_RR's sparse LU (none when R is empty).
    sparse: Vec<usize>,
    sparse_lu: Option<Lu<usize, f64>>,
    /// A_DR as (position in D, position in R, value).
    dense_by_sparse: Vec<(usize, usize, f64)>,
    /// A_RD as (position in R, position in D, value).
    sparse_by_dense: Vec<(usize, usize, f64)>,
    /// D, increasing, and T's LU with partial pivoting, packed in one array (L below the diagonal,
    /// its unit diagonal implied, U on and above it, as LAPACK's getrf leaves it).
    dense: Vec<usize>,
    factors: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
}

impl BlockLu {
    /// The factors of `matrix`.
    pub fn of(matrix: KeptMatrix) -> BlockLu {
        let mut lu = BlockLu {
            decoupled: Vec::new(),
            sparse: Vec::new(),
            sparse_lu: None,
            dense_by_sparse: Vec::new(),
            sparse_by_dense: Vec::new(),
            dense: Vec::new(),
            factors: Mat::zeros(0, 0),
            forward: Vec::new(),
            inverse: Vec::new(),
        };
        lu.refactorize(matrix);
        lu
    }

    /// The factors of `matrix` (of the same order) in place of the last ones.
    pub fn refactorize(&mut self, matrix: KeptMatrix) {
        let m = matrix.order();
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
        self.decoupled.clear();
        let mut coupled = Vec::with_capacity(m);
        for j in 0..m {
            let d = diagonal(j);
            // (a zero diagonal stays with the factors, whose pivoting meets it)
            if matrix.schur.in_schur(j) || coupled_by_change[j] || d == 0.0 {
                coupled.push(j);
            } else {
                self.decoupled.push((j, d));
            }
        }
        let sparse = eliminable(matrix, &coupled);
        if !sparse.is_empty() && self.factorize_blocks(matrix, &coupled, sparse) {
            return;
        }
        self.factorize_blocks(matrix, &coupled, Vec::new());
    }

    /// Factorise with `sparse` as R; whether the factors passed their check (always, with R empty).
    fn factorize_blocks(&mut self, matrix: KeptMatrix, coupled: &[usize], sparse: Vec<usize>) -> bool {
        let m = matrix.order();
        const NONE: usize = usize::MAX;
        let (mut in_sparse, mut in_dense) = (vec![NONE; m], vec![NONE; m]);
        for (p, &j) in sparse.iter().enumerate() {
            in_sparse[j] = p;
        }
        let dense: Vec<usize> = coupled.iter().copied().filter(|&j| in_sparse[j] == NONE).collect();
        for (p, &j) in dense.iter().enumerate() {
            in_dense[j] = p;
        }
        self.sparse = sparse;
        self.sparse_lu = None;
        self.dense_by_sparse.clear();
        self.sparse_by_dense.clear();
        // the old factors go before the new are made
        if self.factors.nrows() != dense.len() {
            self.factors = Mat::zeros(0, 0);
            self.factors = Mat::zeros(dense.len(), dense.len());
            self.forward = vec![0; dense.len()];
            self.inverse = vec![0; dense.len()];
        }
        self.dense = dense;
        // T starts as A_DD
        matrix.write_into(self.factors.as_mut(), &self.dense);
        if !self.sparse.is_empty() {
            let mut within = Vec::new();
            let mut sort = |i: usize, j: usize, v: f64| match (in_sparse[i], in_sparse[j]) {
                (NONE, NONE) => {}
                (r, NONE) if in_dense[j] != NONE => self.sparse_by_dense.push((r, in_dense[j], v)),
                (NONE, s) if in_dense[i] != NONE => self.dense_by_sparse.push((in_dense[i], s, v)),
                (r, s) if r != NONE && s != NONE => within.push(Triplet::new(r, s, v)),
                _ => {}
            };
            for &(i, j, v) in matrix.schur.sparse_entries() {
                sort(i, j, v);
            }
            for j in 0..m {
                let (rows, values) = matrix.change.column(j);
                for (&i, &v) in rows.iter().zip(values) {
                    sort(i, j, v);
                }
            }
            let n = self.sparse.len();
            let Ok(a) = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &within) else { return false };
            let Ok(lu) = a.as_ref().sp_lu() else { return false };
            // W = A_DR A_RR⁻¹ (by A_RRᵀ Wᵀ = A_DRᵀ), then T −= W A_RD: each entry of A_RD takes a
            // whole column of W from a column of T, a contiguous pass
            let d = self.dense.len();
            let mut w_t = Mat::<f64>::zeros(n, d);
            for &(q, r, v) in &self.dense_by_sparse {
                w_t[(r, q)] += v;
            }
            lu.solve_transpose_in_place(w_t.as_mut());
            let w = transposed(&w_t);
            drop(w_t);
            if !w.iter().all(|v| v.is_finite()) {
                return false;
            }
            let mut by_column: Vec<(usize, usize, f64)> =
                self.sparse_by_dense.iter().map(|&(r, q, v)| (q, r, v)).collect();
            by_column.sort_unstable_by_key(|e| (e.0, e.1));
            for &(q, r, v) in &by_column {
                let tq = self.factors.col_as_slice_mut(q);
                let wr = &w[r * d..(r + 1) * d];
                for (t, &x) in tq.iter_mut().zip(wr) {
                    *t -= v * x;
                }
            }
            self.sparse_lu = Some(lu);
        }
        let order = self.dense.len();
        if order > 0 {
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
        if self.sparse.is_empty() {
            return true;
        }
        // one test solve on M: the elimination of R is trusted only where it solves M as a dense
        // factorisation would
        let w = Mat::from_fn(m, 1, |j, _| 1.0 + (j % 7) as f64 / 7.0);
        let b = matrix.times(w.as_ref());
        let x = self.solve(&b);
        let residual = (&b - matrix.times(x.as_ref())).norm_l2() / b.norm_l2();
        residual <= BLOCK_CHECK
    }

    /// The order of the dense factors (D).
    #[cfg(test)]
    pub fn dense_order(&self) -> usize {
        self.dense.len()
    }

    /// M⁻¹ b.
    pub fn solve(&self, b: &Mat<f64>) -> Mat<f64> {
        let columns = b.ncols();
        let mut x = b.clone();
        for &(j, d) in &self.decoupled {
            for c in 0..columns {
                x[(j, c)] /= d;
            }
        }
        let gather = |among: &[usize]| Mat::from_fn(among.len(), columns, |k, c| b[(among[k], c)]);
        // y_R = A_RR⁻¹ b_R, then the right-hand side of T: b_D − A_DR y_R
        let mut y = gather(&self.dense);
        if let Some(lu) = &self.sparse_lu {
            let mut y_r = gather(&self.sparse);
            lu.solve_in_place(y_r.as_mut());
            for &(d, r, v) in &self.dense_by_sparse {
                for c in 0..columns {
                    y[(d, c)] -= v * y_r[(r, c)];
                }
            }
        }
        let order = self.dense.len();
        if order > 0 {
            let par = get_global_parallelism();
            let mut scratch = MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(order, columns, par));
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
        }
        for (k, &j) in self.dense.iter().enumerate() {
            for c in 0..columns {
                x[(j, c)] = y[(k, c)];
            }
        }
        // x_R = A_RR⁻¹ (b_R − A_RD x_D)
        if let Some(lu) = &self.sparse_lu {
            let mut x_r = gather(&self.sparse);
            for &(r, d, v) in &self.sparse_by_dense {
                for c in 0..columns {
                    x_r[(r, c)] -= v * y[(d, c)];
                }
            }
            lu.solve_in_place(x_r.as_mut());
            for (k, &j) in self.sparse.iter().enumerate() {
                for c in 0..columns {
                    x[(j, c)] = x_r[(k, c)];
                }
            }
        }
        x
    }
}

impl faer::matrix_free::LinOp<f64> for BlockLu {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: faer::Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.decoupled.len() + self.sparse.len() + self.dense.len()
    }
    fn ncols(&self) -> usize {
        self.nrows()
    }
    fn apply(&self, mut out: faer::MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: faer::Par, _: &mut MemStack) {
        out.copy_from(self.solve(&rhs.to_owned()));
    }
    fn conj_apply(&self, out: faer::MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: faer::Par, stack: &mut MemStack) {
        // real: the conjugate is the operator itself
        self.apply(out, rhs, par, stack)
    }
}

impl faer::matrix_free::Precond<f64> for BlockLu {}

/// The transpose of `a` (column-major) as a column-major array: column r of the result is row r of
/// `a`. By blocks, so that both sides stay in the cache.
fn transposed(a: &Mat<f64>) -> Vec<f64> {
    const BLOCK: usize = 32;
    let (rows, columns) = (a.nrows(), a.ncols());
    let mut out = vec![0.0; rows * columns];
    for c0 in (0..columns).step_by(BLOCK) {
        for r0 in (0..rows).step_by(BLOCK) {
            for c in c0..(c0 + BLOCK).min(columns) {
                let column = a.col_as_slice(c);
                for r in r0..(r0 + BLOCK).min(rows) {
                    out[r * columns + c] = column[r];
                }
            }
        }
    }
    out
}

/// R: the coupled unknowns whose rows and columns of S are sparse, less those that would make A_RR
/// singular: an unknown with a zero diagonal whose column in R is parallel to that of one taken
/// before it (the second face's row on a bar node), and an unknown with nothing in R.
fn eliminable(matrix: KeptMatrix, coupled: &[usize]) -> Vec<usize> {
    let m = matrix.order();
    let candidate: Vec<bool> = {
        let mut c = vec![false; m];
        for &j in coupled.iter().filter(|&&j| matrix.schur.is_sparse(j)) {
            c[j] = true;
        }
        c
    };
    // the candidates' columns among the candidates, S's part and C's
    let mut columns: HashMap<usize, Vec<(usize, f64)>> = HashMap::new();
    for &(i, j, v) in matrix.schur.sparse_entries() {
        if candidate[i] && candidate[j] {
            columns.entry(j).or_default().push((i, v));
        }
    }
    for j in (0..m).filter(|&j| candidate[j]) {
        let (rows, values) = matrix.change.column(j);
        for (&i, &v) in rows.iter().zip(values) {
            if candidate[i] {
                columns.entry(j).or_default().push((i, v));
            }
        }
    }
    let mut taken = Vec::new();
    // a taken zero-diagonal column's rows (off its diagonal) → its values, scaled by its first
    let mut seen: HashMap<Vec<usize>, Vec<Vec<f64>>> = HashMap::new();
    for j in (0..m).filter(|&j| candidate[j]) {
        let Some(mut column) = columns.remove(&j) else { continue };
        column.sort_unstable_by_key(|e| e.0);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(column.len());
        for (i, v) in column {
            match merged.last_mut() {
                Some(last) if last.0 == i => last.1 += v,
                _ => merged.push((i, v)),
            }
        }
        merged.retain(|e| e.1 != 0.0);
        if merged.is_empty() {
            continue;
        }
        if merged.iter().all(|e| e.0 != j) {
            let rows: Vec<usize> = merged.iter().map(|e| e.0).collect();
            let scaled: Vec<f64> = merged.iter().map(|e| e.1 / merged[0].1).collect();
            let before = seen.entry(rows).or_default();
            let parallel = before
                .iter()
                .any(|other| other.iter().zip(&scaled).all(|(a, b)| (a - b).abs() <= 1e-12 * a.abs().max(b.abs())));
            if parallel {
                continue;
            }
            before.push(scaled);
        }
        taken.push(j);
    }
    taken
}

#[cfg(test)]
mod tests {
    //! The block factorisation of a kept system shaped as an interface's: a dense soil part, a bar
    //! chain, two faces' rows on each bar node.
    use super::super::kept_matrix::{SoilSchur, SparseColumns};
    use super::*;

    /// S: a dense symmetric soil block on the first `soil` unknowns, then a bar of `nodes` nodes at
    /// `angle` to the x axis (two unknowns each, x and y: a chain stiffness along the bar, none
    /// across it), then the two faces' multipliers (one per node and face). C: each multiplier's row
    /// on its bar node's displacement across the bar and on a soil unknown, and a spring between
    /// each node's displacement along the bar and a soil unknown.
    fn interface(soil: usize, nodes: usize, angle: f64) -> (Mat<f64>, Vec<(usize, usize, f64)>) {
        let m = soil + 4 * nodes;
        let (c, s) = (angle.cos(), angle.sin());
        let along = [c, s];
        let across = [-s, c];
        let mut f = Mat::zeros(m, m);
        for i in 0..soil {
            for j in 0..soil {
                f[(i, j)] = if i == j { 10.0 } else { 1.0 / (1.0 + (i as f64 - j as f64).abs()) };
            }
        }
        let node = |n: usize| soil + 2 * n;
        for n in 0..nodes.saturating_sub(1) {
            for (a, b, sign) in [(n, n, 1.0), (n + 1, n + 1, 1.0), (n, n + 1, -1.0), (n + 1, n, -1.0)] {
                for p in 0..2 {
                    for q in 0..2 {
                        f[(node(a) + p, node(b) + q)] += sign * 5.0 * along[p] * along[q];
                    }
                }
            }
        }
        let mut entries = Vec::new();
        for n in 0..nodes {
            for face in 0..2 {
                let row = soil + 2 * nodes + 2 * n + face;
                let sign = if face == 0 { 1.0 } else { -1.0 };
                let soil_node = (2 * n + face) % soil;
                for p in 0..2 {
                    entries.push((row, node(n) + p, -sign * across[p]));
                    entries.push((node(n) + p, row, -sign * across[p]));
                }
                entries.push((row, soil_node, sign));
                entries.push((soil_node, row, sign));
            }
            let spring = (2 * n + 1) % soil;
            for p in 0..2 {
                for q in 0..2 {
                    entries.push((node(n) + p, node(n) + q, 2.0 * along[p] * along[q]));
                }
                entries.push((node(n) + p, spring, -2.0 * along[p]));
                entries.push((spring, node(n) + p, -2.0 * along[p]));
            }
            entries.push((spring, spring, 2.0));
        }
        (f, entries)
    }

    fn residual(f: &Mat<f64>, c: &[(usize, usize, f64)], x: &Mat<f64>, b: &Mat<f64>) -> f64 {
        let mut whole = f.clone();
        for &(i, j, v) in c {
            whole[(i, j)] += v;
        }
        (b - &whole * x).norm_l2() / b.norm_l2()
    }

    #[test]
    fn the_bar_and_one_face_are_eliminated_sparsely_and_the_solve_is_exact() {
        for angle in [0.0, 0.3, -1.2] {
            the_bar_and_one_face_are_eliminated_sparsely(angle);
        }
    }

    fn the_bar_and_one_face_are_eliminated_sparsely(angle: f64) {
        let (soil, nodes) = (24, 10);
        let (f, c) = interface(soil, nodes, angle);
        let change = SparseColumns::from_entries(f.nrows(), c.iter().copied());
        let schur = SoilSchur::from_dense(f.as_ref());
        let lu = BlockLu::of(KeptMatrix { schur: &schur, change: &change });
        // the bar's two unknowns and the first face's row a node are eliminated sparsely; the
        // second face's row (parallel on the bar) stays with the soil in T
        assert_eq!(lu.sparse.len(), 3 * nodes, "at {angle} rad, R: {:?}", lu.sparse);
        assert_eq!(lu.dense_order(), soil + nodes);
        let b = Mat::from_fn(f.nrows(), 2, |i, c| ((i + 3 * c) as f64 * 0.37).sin());
        let x = lu.solve(&b);
        let r = residual(&f, &c, &x, &b);
        assert!(r < 1e-13, "at {angle} rad: relative residual {r}");
    }

    #[test]
    fn a_singular_sparse_block_falls_back_to_one_dense_factorisation() {
        // two unknowns outside S whose block of C is [1 1; 1 1] (singular, both diagonals nonzero:
        // nothing picks them out before the factorisation), the first tied to the soil: M is
        // regular, A_RR is not
        let soil = 20;
        let (f, _) = interface(soil, 0, 0.0);
        let mut f2 = Mat::zeros(soil + 2, soil + 2);
        f2.as_mut().submatrix_mut(0, 0, soil, soil).copy_from(f.as_ref());
        let (a, b) = (soil, soil + 1);
        let c = vec![(a, a, 1.0), (a, b, 1.0), (b, a, 1.0), (b, b, 1.0), (a, 0, 1.0), (0, a, 1.0)];
        let change = SparseColumns::from_entries(f2.nrows(), c.iter().copied());
        let schur = SoilSchur::from_dense(f2.as_ref());
        let lu = BlockLu::of(KeptMatrix { schur: &schur, change: &change });
        assert_eq!((lu.sparse.len(), lu.dense_order()), (0, soil + 2), "one dense factorisation of all");
        let rhs = Mat::from_fn(f2.nrows(), 1, |i, _| 1.0 + i as f64);
        let x = lu.solve(&rhs);
        let r = residual(&f2, &c, &x, &rhs);
        assert!(r < 1e-13, "relative residual {r}");
    }
}
